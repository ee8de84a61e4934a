// Shell models: tilings of spheres, unions of spheres and spheroids, and the extrapolation of
// their resistance to zero bead size against Stokes, Perrin and the two-sphere values.

#include "ResistanceTensor.h"
#include "ResistanceTestHelpers.h"
#include "internal/PerrinFriction.h"
#include "internal/ShellModel.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>
#include <cmath>
#include <limits>

using namespace RigidLangevinPlugin;
using namespace ResistanceTestHelpers;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

double smallestSeparation(const vector<Vec3>& beads) {
    double smallest = INFINITY;
    for (int i = 0; i < (int) beads.size(); i++)
        for (int j = i+1; j < (int) beads.size(); j++)
            smallest = std::min(smallest, distance(beads[i], beads[j]));
    return smallest;
}

/**
 * Shells are solved at 1000 beads at most in these tests (a third of a second each). Measured
 * errors of the extrapolation at that size: 0.2-0.3% for a sphere, up to 0.3% (ratio 2) and 0.7%
 * (ratio 5, rotation) for prolate ellipsoids, 0.2-0.35% for two touching spheres. The issue asks
 * for 1%, which is what is checked.
 */
const int MAX_BEADS = 1000;
const double TOLERANCE = 0.01;

void expectDiagonalNear(const vector<double>& expected, const Matrix6& xi, const std::string& what) {
    for (int i = 0; i < 6; i++)
        EXPECT_NEAR(1.0, xi(i, i)/expected[i], TOLERANCE) << what << ", diagonal element " << i;
    // The bodies are symmetric about the origin: no coupling and no off-diagonal terms, up to the
    // tiling's own small asymmetries.
    Matrix6 offDiagonal = xi;
    offDiagonal.diagonal().setZero();
    EXPECT_LT(offDiagonal.cwiseAbs().maxCoeff(), 2e-3*xi.diagonal().minCoeff()) << what;
}

} // namespace

TEST(ShellModel, SphereTilingLiesOnTheSurface) {
    const double radius = 0.5, sigma = 0.02;
    Vec3 centre(1, -2, 0.5);
    vector<Vec3> beads = ResistanceTensor::roughShellBeads({centre}, {radius}, sigma);
    for (const Vec3& b : beads)
        EXPECT_NEAR(radius, distance(b, centre), 1e-12);
    // Bead centres about 3 sigma apart: one bead per (3 sigma)^2 of surface, to the 10% that
    // rounding the numbers of rings and of beads per ring leaves.
    EXPECT_NEAR(4*M_PI*radius*radius/(9*sigma*sigma), beads.size(), 0.1*beads.size());
    EXPECT_GT(smallestSeparation(beads), 2*sigma) << "beads of one sphere must not overlap";
    // The centroid of the shell is the centre (rings are symmetric about the equator).
    Vec3 sum;
    for (const Vec3& b : beads)
        sum += b;
    EXPECT_LT(distance(sum/(double) beads.size(), centre), 1e-3*radius);
}

TEST(ShellModel, UnionTilingCoversOnlyTheOuterSurface) {
    // Two overlapping spheres: every bead on one sphere and not inside the other, the seam free of
    // near-duplicates, and the count matching the union's area (each sphere less a cap of height
    // R - d/2).
    const double radius = 0.4, separation = 0.5, sigma = 0.015;
    vector<Vec3> centres = {Vec3(0, 0, 0), Vec3(separation, 0, 0)};
    vector<Vec3> beads = ResistanceTensor::roughShellBeads(centres, {radius, radius}, sigma);
    for (const Vec3& b : beads) {
        double d0 = distance(b, centres[0]), d1 = distance(b, centres[1]);
        EXPECT_TRUE(std::abs(d0-radius) < 1e-12 || std::abs(d1-radius) < 1e-12);
        EXPECT_GE(d0, radius*(1-1e-9));
        EXPECT_GE(d1, radius*(1-1e-9));
    }
    EXPECT_GE(smallestSeparation(beads), 1.5*sigma);
    double area = 2*(4*M_PI*radius*radius-2*M_PI*radius*(radius-separation/2));
    EXPECT_NEAR(area/(9*sigma*sigma), beads.size(), 0.1*beads.size());
    // A sphere inside another leaves no bead.
    vector<Vec3> inner = ResistanceTensor::roughShellBeads({Vec3(0, 0, 0), Vec3(0.1, 0, 0)}, {radius, 0.2}, sigma);
    EXPECT_EQ(ResistanceTensor::roughShellBeads({Vec3(0, 0, 0)}, {radius}, sigma).size(), inner.size());
}

TEST(ShellModel, RoughShellIsTheBeadModelOfItsBeads) {
    vector<Vec3> centres = {Vec3(0, 0, 0), Vec3(0.3, 0.1, 0)};
    vector<double> radii = {0.25, 0.2};
    const double sigma = 0.03;
    vector<Vec3> beads = ResistanceTensor::roughShellBeads(centres, radii, sigma);
    ResistanceTensor shell = ResistanceTensor::roughShell(centres, radii, sigma);
    ResistanceTensor direct = ResistanceTensor::beads(beads, vector<double>(beads.size(), sigma));
    Vec3 point(0.1, 0, 0);
    EXPECT_LT(relativeDifference(toMatrix6(shell.getMatrix(point)), toMatrix6(direct.getMatrix(point))), 1e-12);
    EXPECT_LT(distance(shell.getOrigin(), Vec3(0.15, 0.05, 0)), 1e-15);
}

TEST(ShellModel, ExtrapolationIsExactForLinearData) {
    Matrix6 a = Matrix6::Random(), b = Matrix6::Random();
    vector<double> sigmas = {0.1, 0.13, 0.2, 0.21};
    vector<Matrix6> tensors;
    for (double s : sigmas)
        tensors.push_back(a+s*b);
    EXPECT_LT((ShellModel::extrapolateToZeroBeadSize(sigmas, tensors)-a).cwiseAbs().maxCoeff(), 1e-14);
    // A quadratic term is not removed: the fit is a straight line, as in HYDRO.
    tensors.clear();
    for (double s : sigmas)
        tensors.push_back(a+s*s*b);
    EXPECT_GT((ShellModel::extrapolateToZeroBeadSize(sigmas, tensors)-a).cwiseAbs().maxCoeff(), 1e-3);
    EXPECT_THROW(ShellModel::extrapolateToZeroBeadSize({0.1}, {a}), OpenMMException);
    EXPECT_THROW(ShellModel::extrapolateToZeroBeadSize({0.1, 0.1}, {a, b}), OpenMMException);
    EXPECT_THROW(ShellModel::extrapolateToZeroBeadSize({0.1, 0.2}, {a}), OpenMMException);
}

TEST(ShellModel, SphereExtrapolatesToStokes) {
    const double r = 0.6;
    Vec3 centre(0.2, 0.3, -0.1);
    ResistanceTensor t = ResistanceTensor::shellExtrapolated({centre}, {r}, MAX_BEADS);
    const double tt = 6*M_PI*r, rr = 8*M_PI*r*r*r;
    expectDiagonalNear({tt, tt, tt, rr, rr, rr}, toMatrix6(t.getMatrix(centre)), "sphere");
    // A finite shell overestimates: its beads stick out of the surface.
    Matrix6 finite = toMatrix6(ResistanceTensor::roughShell({centre}, {r}, 0.05).getMatrix(centre));
    EXPECT_GT(finite(0, 0), 1.01*tt);
}

TEST(ShellModel, ProlateEllipsoidsExtrapolateToPerrin) {
    for (double ratio : {2.0, 5.0}) {
        const double a = 0.3*ratio, b = 0.3;
        ShellModel::Tiling tiling = [&](double sigma) { return ShellModel::tileSpheroid(a, b, sigma); };
        // The area of a prolate spheroid, only a first guess for the bead radius.
        double e = std::sqrt(1-b*b/(a*a));
        double area = 2*M_PI*b*b*(1+a/(b*e)*std::asin(e));
        Matrix6 xi = ShellModel::extrapolated("test", tiling, area, Vec3(), MAX_BEADS, 6);
        PerrinFriction::PrincipalFriction f = PerrinFriction::spheroid(a, b);
        expectDiagonalNear({f.translation[0], f.translation[1], f.translation[2], f.rotation[0], f.rotation[1], f.rotation[2]}, xi,
                           "prolate ratio "+std::to_string(ratio));
    }
}

TEST(ShellModel, TwoTouchingSpheresMatchPublishedValues) {
    // PHYSICS.md: 1.2902 and 1.4492 x 6 pi a (exact), 1.8032 x 8 pi a^3 (exact), 3.740 x 8 pi a^3
    // (+-0.2%). Measured here: 0.2-0.35% low.
    const double a = 0.2;
    ResistanceTensor t = ResistanceTensor::shellExtrapolated({Vec3(-a, 0, 0), Vec3(a, 0, 0)}, {a, a}, MAX_BEADS);
    const double tt = 6*M_PI*a, rr = 8*M_PI*a*a*a;
    expectDiagonalNear({1.2902*tt, 1.4492*tt, 1.4492*tt, 1.8032*rr, 3.740*rr, 3.740*rr}, toMatrix6(t.getMatrix(Vec3())), "two touching spheres");
}

TEST(ShellModel, RejectsBadInput) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    vector<Vec3> centres = {Vec3(0, 0, 0), Vec3(0.3, 0, 0)};
    vector<double> radii = {0.2, 0.2};
    for (double bad : {0.0, -0.01, nan}) {
        EXPECT_THROW(ResistanceTensor::roughShell(centres, radii, bad), OpenMMException);
        expectThrowMentioning([&] { ResistanceTensor::roughShellBeads(centres, radii, bad); }, {"bead radius"});
    }
    expectThrowMentioning([&] { ResistanceTensor::roughShellBeads(centres, radii, 1e-7); }, {"larger bead radius"});
    expectThrowMentioning([&] { ResistanceTensor::roughShell({Vec3(0, 0, 0), Vec3(nan, 0, 0)}, radii, 0.02); }, {"roughShell", "sphere (atom) 1"});
    expectThrowMentioning([&] { ResistanceTensor::shellExtrapolated(centres, {0.2, 0.0}); }, {"shellExtrapolated", "sphere (atom) 1", "radius"});
    expectThrowMentioning([&] { ResistanceTensor::shellExtrapolated({}, {}); }, {"no spheres"});
    expectThrowMentioning([&] { ResistanceTensor::shellExtrapolated(centres, {0.2}); }, {"2 sphere centres but 1 radii"});
    expectThrowMentioning([&] { ResistanceTensor::shellExtrapolated(centres, radii, 10); }, {"maxBeads"});
    expectThrowMentioning([&] { ResistanceTensor::shellExtrapolated(centres, radii, 500, 1); }, {"numResolutions"});
}

namespace {

/** (x/a)^2 + (rho/b)^2 of point p in the spheroid at centre with unit axis u. */
double spheroidLevel(const Vec3& p, const Vec3& centre, const Vec3& u, double a, double b) {
    Vec3 d = p-centre;
    double x = d.dot(u), rho2 = d.dot(d)-x*x;
    return x*x/(a*a)+rho2/(b*b);
}

Vec3 unit(const Vec3& v) {
    return v*(1/std::sqrt(v.dot(v)));
}

} // namespace

TEST(ShellModel, SpheroidTilingLiesOnTheTurnedSurface) {
    // A spheroid whose axis is x tiles exactly as the sphere union does when a = b; turned, its
    // beads lie on the turned surface.
    const double r = 0.4, sigma = 0.02;
    Vec3 centre(0.1, -0.2, 0.3);
    vector<Vec3> spheres = ResistanceTensor::roughShellBeads({centre}, {r}, sigma);
    vector<Vec3> spheroids = ResistanceTensor::spheroidRoughShellBeads({centre}, {Vec3(2, 0, 0)}, {r}, {r}, sigma);
    ASSERT_EQ(spheres.size(), spheroids.size());
    for (int i = 0; i < (int) spheres.size(); i++)
        EXPECT_EQ(0.0, distance(spheres[i], spheroids[i]));
    const double a = 0.9, b = 0.3;
    Vec3 axis = unit(Vec3(0.3, -0.5, 0.8));
    vector<Vec3> beads = ResistanceTensor::spheroidRoughShellBeads({centre}, {axis*3.0}, {a}, {b}, sigma);
    EXPECT_EQ(ShellModel::tileSpheroid(a, b, sigma).size(), beads.size());
    for (const Vec3& p : beads)
        ASSERT_NEAR(1.0, spheroidLevel(p, centre, axis, a, b), 1e-12);
}

TEST(ShellModel, SpheroidUnionTilingCoversOnlyTheOuterSurface) {
    // Two prolate spheroids crossing at 60 degrees: every bead on one surface and outside the other,
    // none closer than half the spacing (1.5 sigma) to another, and fewer beads than the two apart.
    const double a = 1.0, b = 0.3, sigma = 0.02;
    vector<Vec3> centres = {Vec3(0, 0, 0), Vec3(0.5, 0.4, 0)};
    vector<Vec3> axes = {Vec3(1, 0, 0), Vec3(0.5, std::sqrt(3.0)/2, 0)};
    vector<Vec3> beads = ResistanceTensor::spheroidRoughShellBeads(centres, axes, {a, a}, {b, b}, sigma);
    EXPECT_LT(beads.size(), 2*ShellModel::tileSpheroid(a, b, sigma).size());
    for (const Vec3& p : beads) {
        double first = spheroidLevel(p, centres[0], axes[0], a, b), second = spheroidLevel(p, centres[1], axes[1], a, b);
        ASSERT_TRUE(std::abs(first-1) < 1e-12 || std::abs(second-1) < 1e-12);
        ASSERT_GT(first, 1-1e-9);
        ASSERT_GT(second, 1-1e-9);
    }
    EXPECT_GE(smallestSeparation(beads), 1.5*sigma*(1-1e-12));
}

TEST(ShellModel, TurnedSpheroidExtrapolatesToTurnedPerrin) {
    // One prolate spheroid of axial ratio 3 along a general direction, through the union's
    // extrapolation: Perrin's principal friction turned into the lab frame, about its centre.
    const double a = 0.9, b = 0.3;
    Vec3 centre(0.2, 0.1, -0.3), axis = unit(Vec3(1, 2, -2));
    ResistanceTensor t = ResistanceTensor::spheroidShellExtrapolated({centre}, {axis}, {a}, {b}, MAX_BEADS);
    Eigen::Matrix3d frame = ShellModel::spheroidFrame(axis);
    PerrinFriction::PrincipalFriction f = PerrinFriction::spheroid(a, b);
    Matrix6 principal = Matrix6::Zero();
    for (int k = 0; k < 3; k++) {
        principal(k, k) = f.translation[k];
        principal(k+3, k+3) = f.rotation[k];
    }
    Matrix6 turn = Matrix6::Zero();
    turn.block<3, 3>(0, 0) = frame;
    turn.block<3, 3>(3, 3) = frame;
    Matrix6 expected = turn*principal*turn.transpose();
    Matrix6 xi = toMatrix6(t.getMatrix(centre));
    for (int block = 0; block < 2; block++) {
        Eigen::Matrix3d want = expected.block(3*block, 3*block, 3, 3), got = xi.block(3*block, 3*block, 3, 3);
        EXPECT_LT((got-want).cwiseAbs().maxCoeff(), TOLERANCE*want.cwiseAbs().maxCoeff()) << (block == 0 ? "translation" : "rotation");
    }
    // No coupling about the centre of a spheroid.
    Eigen::Matrix3d coupling = xi.block(0, 3, 3, 3);
    EXPECT_LT(coupling.cwiseAbs().maxCoeff(), TOLERANCE*expected(0, 0)*b);
}

TEST(ShellModel, SpheroidUnionRejectsBadInput) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    vector<Vec3> centres = {Vec3(0, 0, 0), Vec3(0.3, 0, 0)}, axes = {Vec3(1, 0, 0), Vec3(0, 1, 0)};
    vector<double> a = {0.5, 0.5}, b = {0.2, 0.2};
    expectThrowMentioning([&] { ResistanceTensor::spheroidRoughShell(centres, {Vec3(1, 0, 0), Vec3()}, a, b, 0.02); },
                          {"spheroidRoughShell", "spheroid 1", "axis"});
    expectThrowMentioning([&] { ResistanceTensor::spheroidRoughShellBeads(centres, axes, a, {0.2, -1.0}, 0.02); }, {"spheroid 1", "semi-axes"});
    expectThrowMentioning([&] { ResistanceTensor::spheroidShellExtrapolated(centres, axes, {0.5}, b); }, {"one axis and two semi-axes"});
    expectThrowMentioning([&] { ResistanceTensor::spheroidShellExtrapolated({Vec3(nan, 0, 0), Vec3()}, axes, a, b); }, {"spheroid 0", "centre"});
    expectThrowMentioning([&] { ResistanceTensor::spheroidRoughShell(centres, axes, a, b, 0.0); }, {"bead radius"});
    expectThrowMentioning([&] { ResistanceTensor::spheroidShellExtrapolated({}, {}, {}, {}); }, {"no spheroids"});
}
