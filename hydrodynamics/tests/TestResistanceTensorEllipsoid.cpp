// Ellipsoids: Carlson's integrals, Perrin's friction coefficients (triaxial through the integrals,
// spheroids through the closed forms) and the ResistanceTensor factories built on them.

#include "ResistanceTensor.h"
#include "ResistanceTestHelpers.h"
#include "internal/CarlsonIntegrals.h"
#include "internal/PerrinFriction.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>
#include <cmath>
#include <limits>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::CarlsonIntegrals;
using namespace ResistanceTestHelpers;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using PerrinFriction::PrincipalFriction;

namespace {

/** The six coefficients in the order tx, ty, tz, rx, ry, rz. */
std::vector<double> coefficients(const PrincipalFriction& f) {
    return {f.translation[0], f.translation[1], f.translation[2], f.rotation[0], f.rotation[1], f.rotation[2]};
}

/**
 * The source's closed forms, typed in literally (seed/Langevin.tex; PHYSICS.md says they are
 * right): semi-axis a along the symmetry axis, b across it, a != b. Returns tx, ty, tz, rx, ry, rz.
 */
std::vector<double> sourceSpheroid(double a, double b) {
    double s;
    if (a > b)
        s = 2/std::sqrt(a*a-b*b)*std::log((a+std::sqrt(a*a-b*b))/b);
    else
        s = 2/std::sqrt(b*b-a*a)*std::atan(std::sqrt(b*b-a*a)/a);
    double ta = 16*M_PI*(a*a-b*b)/((2*a*a-b*b)*s-2*a);
    double tb = 32*M_PI*(a*a-b*b)/((2*a*a-3*b*b)*s+2*a);
    double ra = (32*M_PI/3)*(a*a-b*b)*b*b/(2*a-b*b*s);
    double rb = (32*M_PI/3)*(a*a*a*a-b*b*b*b)/((2*a*a-b*b)*s-2*a);
    return {ta, tb, tb, ra, rb, rb};
}

void expectRelativelyNear(const std::vector<double>& expected, const std::vector<double>& actual, double tolerance, const std::string& what) {
    ASSERT_EQ(expected.size(), actual.size());
    for (int i = 0; i < (int) expected.size(); i++)
        EXPECT_NEAR(1.0, actual[i]/expected[i], tolerance) << what << ", coefficient " << i << ": expected " << expected[i] << ", got " << actual[i];
}

/** Axial ratios at which the forms are compared: near the sphere, the series' edge |eps| = 0.25, and far from it. */
const double RATIOS[] = {1.001, std::sqrt(4.0/3.0), 2.0, 5.0, 10.0};

} // namespace

TEST(CarlsonIntegrals, PublishedValues) {
    // Carlson (1995), section 3, test values to 14 digits; his algorithm gives them to rounding.
    EXPECT_NEAR(1.3110287771461, carlsonRF(1, 2, 0), 1e-13);
    EXPECT_NEAR(0.58408284167715, carlsonRF(2, 3, 4), 1e-13);
    EXPECT_NEAR(1.7972103521034, carlsonRD(0, 2, 1), 1e-13);
    EXPECT_NEAR(0.16510527294261, carlsonRD(2, 3, 4), 1e-13);
}

TEST(CarlsonIntegrals, ClosedForms) {
    // R_F(x,x,x) = x^-1/2, R_D(x,x,x) = x^-3/2; the complete elliptic integral K(k) = R_F(0, 1-k^2, 1)
    // with K(0) = pi/2; and R_D(0,1,1) = 3 pi/4. All to rounding.
    for (double x : {1e-6, 0.37, 1.0, 42.0, 3e5}) {
        EXPECT_NEAR(1.0, carlsonRF(x, x, x)*std::sqrt(x), 1e-15);
        EXPECT_NEAR(1.0, carlsonRD(x, x, x)*x*std::sqrt(x), 1e-15);
    }
    EXPECT_NEAR(M_PI/2, carlsonRF(0, 1, 1), 1e-15);
    EXPECT_NEAR(3*M_PI/4, carlsonRD(0, 1, 1), 1e-15);
    // Symmetry: R_F in all three arguments, R_D in its first two.
    EXPECT_NEAR(carlsonRF(0.3, 2.0, 7.0), carlsonRF(7.0, 0.3, 2.0), 1e-15);
    EXPECT_NEAR(carlsonRD(0.3, 2.0, 7.0), carlsonRD(2.0, 0.3, 7.0), 1e-15);
    // Homogeneity: R_F(lx,ly,lz) = l^-1/2 R_F(x,y,z), R_D scales as l^-3/2.
    EXPECT_NEAR(carlsonRF(0.3, 2.0, 7.0), 4*carlsonRF(4.8, 32.0, 112.0), 1e-14);
    EXPECT_NEAR(carlsonRD(0.3, 2.0, 7.0), 64*carlsonRD(4.8, 32.0, 112.0), 1e-14);
}

TEST(CarlsonIntegrals, RejectsInvalidArguments) {
    EXPECT_THROW(carlsonRF(-1, 1, 1), OpenMMException);
    EXPECT_THROW(carlsonRF(0, 0, 1), OpenMMException);
    EXPECT_THROW(carlsonRF(std::nan(""), 1, 1), OpenMMException);
    EXPECT_THROW(carlsonRD(1, 1, 0), OpenMMException);
    EXPECT_THROW(carlsonRD(0, 0, 1), OpenMMException);
}

TEST(PerrinFriction, ClosedFormsAgreeWithCarlsonIntegrals) {
    // Both are exact. The duplication algorithm is accurate to ~1e-15; the closed forms are
    // evaluated without cancellation. 1e-10 leaves room for neither and catches any wrong term.
    for (double ratio : RATIOS)
        for (bool prolate : {true, false}) {
            double a = (prolate ? ratio : 1/ratio), b = 1.0;
            std::string what = std::string(prolate ? "prolate" : "oblate")+" ratio "+std::to_string(ratio);
            expectRelativelyNear(coefficients(PerrinFriction::ellipsoid(a, b, b)), coefficients(PerrinFriction::spheroid(a, b)), 1e-10, what);
        }
}

TEST(PerrinFriction, ClosedFormsAreTheSourcesFormulas) {
    // The library rewrites the source's S-forms to remove their 0/0 at the sphere; the literal
    // forms lose about log10(1/|1-b^2/a^2|) digits to cancellation (3 at ratio 1.001), so 1e-10 is
    // still five orders above their rounding error.
    for (double ratio : RATIOS)
        for (bool prolate : {true, false}) {
            double a = (prolate ? ratio : 1/ratio), b = 1.0;
            std::string what = std::string(prolate ? "prolate" : "oblate")+" ratio "+std::to_string(ratio);
            expectRelativelyNear(sourceSpheroid(a, b), coefficients(PerrinFriction::spheroid(a, b)), 1e-10, what+" (closed form)");
            expectRelativelyNear(sourceSpheroid(a, b), coefficients(PerrinFriction::ellipsoid(a, b, b)), 1e-10, what+" (Carlson)");
        }
}

TEST(PerrinFriction, SphereLimit) {
    // Stokes: 6 pi R and 8 pi R^3, exactly at a = b and continuously next to it (no 0/0).
    const double r = 0.7;
    std::vector<double> stokes = {6*M_PI*r, 6*M_PI*r, 6*M_PI*r, 8*M_PI*r*r*r, 8*M_PI*r*r*r, 8*M_PI*r*r*r};
    expectRelativelyNear(stokes, coefficients(PerrinFriction::spheroid(r, r)), 1e-15, "spheroid(r, r)");
    expectRelativelyNear(stokes, coefficients(PerrinFriction::ellipsoid(r, r, r)), 1e-14, "ellipsoid(r, r, r)");
    // Friction is homogeneous of degree 1 (translation) or 3 (rotation) in the semi-axes and grows
    // with each of them, so changing one axis by a relative delta changes no coefficient by more
    // than 3 delta (relative): an evaluation that went 0/0 would be far outside that.
    for (double delta : {1e-12, -1e-12, 1e-7, -1e-7}) {
        expectRelativelyNear(stokes, coefficients(PerrinFriction::spheroid(r*(1+delta), r)), 3*std::abs(delta)+1e-15, "spheroid near the sphere");
        expectRelativelyNear(stokes, coefficients(PerrinFriction::ellipsoid(r, r*(1+delta), r)), 3*std::abs(delta)+1e-14, "ellipsoid near the sphere");
    }
}

TEST(PerrinFriction, TriaxialBetweenAndTowardsItsSpheroidLimits) {
    // Minimum dissipation: a body that contains another has at least its friction for every
    // rigid motion. (3,1,1) is inside (3,2,1), which is inside (3,2,2).
    std::vector<double> inner = coefficients(PerrinFriction::ellipsoid(3, 1, 1));
    std::vector<double> middle = coefficients(PerrinFriction::ellipsoid(3, 2, 1));
    std::vector<double> outer = coefficients(PerrinFriction::ellipsoid(3, 2, 2));
    for (int i = 0; i < 6; i++) {
        EXPECT_LT(inner[i], middle[i]) << "coefficient " << i;
        EXPECT_LT(middle[i], outer[i]) << "coefficient " << i;
    }
    // As c -> b the triaxial result tends to the prolate and the oblate closed forms, at most 3
    // delta away (homogeneity and monotonicity, as in SphereLimit).
    for (double delta : {1e-4, 1e-8}) {
        expectRelativelyNear(coefficients(PerrinFriction::spheroid(3, 1)), coefficients(PerrinFriction::ellipsoid(3, 1, 1+delta)), 3*delta, "towards prolate");
        expectRelativelyNear(coefficients(PerrinFriction::spheroid(0.3, 1)), coefficients(PerrinFriction::ellipsoid(0.3, 1+delta, 1)), 3*delta, "towards oblate");
    }
    // Swapping two semi-axes swaps their coefficients.
    std::vector<double> swapped = coefficients(PerrinFriction::ellipsoid(2, 3, 1));
    expectRelativelyNear({middle[1], middle[0], middle[2], middle[4], middle[3], middle[5]}, swapped, 1e-14, "x and y swapped");
}

TEST(PerrinFriction, OrientationAveragedFrictionRatios) {
    // f/f0 with f = 3/(1/f_a + 2/f_b) (orientation-averaged translational friction) and f0 that of
    // the sphere of equal volume. Perrin's explicit forms, p the axial ratio:
    //   prolate F = sqrt(p^2-1) / (p^(1/3) ln(p + sqrt(p^2-1)))
    //   oblate  F = sqrt(p^2-1) / (p^(2/3) atan(sqrt(p^2-1)))
    // are exact (1e-10). PHYSICS.md section 2 gives them to 3 decimals; its oblate-5 entry, 1.224,
    // is 0.0006 above the exact 1.22344, so those are checked to 1e-3.
    const double prolate[] = {1.044, 1.250, 1.543}, oblate[] = {1.042, 1.224, 1.458};
    const double ratios[] = {2, 5, 10};
    for (int k = 0; k < 3; k++)
        for (bool isProlate : {true, false}) {
            double p = ratios[k];
            double a = (isProlate ? p : 1/p), b = 1;
            PrincipalFriction f = PerrinFriction::spheroid(a, b);
            double average = 3/(1/f.translation[0]+2/f.translation[1]);
            double ratio = average/(6*M_PI*std::cbrt(a*b*b));
            double q = std::sqrt(p*p-1);
            double perrin = (isProlate ? q/(std::cbrt(p)*std::log(p+q)) : q/(std::cbrt(p*p)*std::atan(q)));
            std::string what = std::string(isProlate ? "prolate " : "oblate ")+std::to_string(p);
            EXPECT_NEAR(perrin, ratio, 1e-10) << what;
            EXPECT_NEAR(isProlate ? prolate[k] : oblate[k], ratio, 1e-3) << what;
        }
}

TEST(ResistanceTensor, EllipsoidFactories) {
    Vec3 center(0.3, -1.2, 2.0);
    Matrix6 triaxial = toMatrix6(ResistanceTensor::ellipsoid(0.5, 0.3, 0.2, center).getMatrix(center));
    PrincipalFriction f = PerrinFriction::ellipsoid(0.5, 0.3, 0.2);
    Matrix6 expected = Matrix6::Zero();
    for (int i = 0; i < 3; i++) {
        expected(i, i) = f.translation[i];
        expected(i+3, i+3) = f.rotation[i];
    }
    EXPECT_LT(relativeDifference(triaxial, expected), 1e-15);
    Vec3 origin = ResistanceTensor::ellipsoid(0.5, 0.3, 0.2, center).getOrigin();
    for (int k = 0; k < 3; k++)
        EXPECT_EQ(center[k], origin[k]);
    Matrix6 closed = toMatrix6(ResistanceTensor::spheroid(0.5, 0.2).getMatrix());
    Matrix6 general = toMatrix6(ResistanceTensor::ellipsoid(0.5, 0.2, 0.2).getMatrix());
    EXPECT_LT(relativeDifference(closed, general), 1e-10);
    Matrix6 sphere = toMatrix6(ResistanceTensor::sphere(0.2).getMatrix());
    EXPECT_LT(relativeDifference(toMatrix6(ResistanceTensor::spheroid(0.2, 0.2).getMatrix()), sphere), 1e-15);
}

TEST(ResistanceTensor, EllipsoidRejectsBadSemiAxes) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(ResistanceTensor::ellipsoid(0, 1, 1), OpenMMException);
    expectThrowMentioning([&] { ResistanceTensor::ellipsoid(1, -1, 1); }, {"semi-axis b", "positive"});
    expectThrowMentioning([&] { ResistanceTensor::ellipsoid(1, 1, nan); }, {"semi-axis c"});
    expectThrowMentioning([&] { ResistanceTensor::spheroid(1, 0); }, {"semi-axis b"});
    expectThrowMentioning([&] { ResistanceTensor::spheroid(std::numeric_limits<double>::infinity(), 1); }, {"semi-axis a"});
    expectThrowMentioning([&] { ResistanceTensor::ellipsoid(1, 1, 1, Vec3(nan, 0, 0)); }, {"centre"});
}
