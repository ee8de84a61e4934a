// The periodic (Ewald-summed) generalised RPY mobility against exact answers: Hasimoto's lone
// sphere in a cube, the same result whatever the Ewald splitting (which moves almost all of it
// between the two sums), a pair far from its images is the free pair with Hasimoto's 1/L shift,
// periodicity, and positive definiteness with overlapping blobs and blobs overlapping their images;
// the closed-form real-space part against the trapezoid-rule quadrature it replaced; threads.

#include "internal/HasimotoSplit.h"
#include "internal/PeriodicRotnePragerYamakawa.h"
#include "internal/RotnePragerYamakawa.h"
#include "PeriodicTestHelpers.h"
#include "openmm/OpenMMException.h"
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <iostream>
#include <random>

using namespace RigidLangevinPlugin;
using namespace PeriodicTestHelpers;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

const Vec3 Cube[3] = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};

vector<Vec3> scaled(const Vec3 box[3], double l) {
    return {box[0]*l, box[1]*l, box[2]*l};
}

/** Blobs of unequal radii in a triclinic box, some overlapping each other and one its own images. */
void crowdedBlobs(vector<Vec3>& positions, vector<double>& radii, Vec3 box[3]) {
    box[0] = Vec3(2.0, 0, 0);
    box[1] = Vec3(0.5, 1.8, 0);
    box[2] = Vec3(-0.4, 0.3, 1.6);
    std::mt19937 random(11);
    std::uniform_real_distribution<double> uniform(0, 1);
    for (int i = 0; i < 12; i++) {
        positions.push_back(Vec3(2*uniform(random), 2*uniform(random), 2*uniform(random)));
        radii.push_back(0.1+0.25*uniform(random));
    }
    positions[1] = positions[0]+Vec3(0.15, 0.05, 0);   // overlapping
    positions[2] = positions[0]+Vec3(0.02, 0, 0.01);   // nearly inside
    radii[3] = 0.95;                                   // overlaps its images 1.6-2.0 nm away
}

/** The spherical Bessel functions j0 and j2 (series below 1, free of the closed form's cancellation). */
void besselJ0J2(double x, double& j0, double& j2) {
    if (x < 1.0) {
        j0 = 0;
        j2 = 0;
        double term0 = 1, term2 = x*x/15;
        for (int k = 0; k < 12; k++) {
            j0 += term0;
            j2 += term2;
            term0 *= -x*x/(2*(k+1)*(2*k+3));
            term2 *= -x*x/(2*(k+1)*(2*k+7));
        }
        return;
    }
    double s = std::sin(x), c = std::cos(x);
    j0 = s/x;
    j2 = (3/(x*x*x)-1/x)*s-3*c/(x*x);
}

/**
 * The slow reference for the smooth part G = A I + B rr: its Fourier integral
 * (1/2 pi^2) int dk sinc(k a_i) sinc(k a_j) phi(k) (j0 (2/3) - j2/3, j2) by the trapezoid rule, whose
 * step puts the aliases 7/xi beyond the integrand's band limit (the library's method before the
 * closed form).
 */
void quadratureSmoothPart(double r, double ai, double aj, double xi, double& a, double& b) {
    auto sinc = [] (double x) { return (std::abs(x) < 1e-4 ? 1-x*x/6 : std::sin(x)/x); };
    const double dk = 2*M_PI/(ai+aj+r+7.0/xi), cutoff = 2*xi*std::sqrt(41.5);
    a = 0;
    b = 0;
    for (int n = 0; n <= (int) std::ceil(cutoff/dk); n++) {
        double k = n*dk, j0, j2;
        besselJ0J2(k*r, j0, j2);
        double weight = (n == 0 ? 0.5 : 1.0)*dk*sinc(k*ai)*sinc(k*aj)*HasimotoSplit::weight(k*k, xi)/(2*M_PI*M_PI);
        a += weight*(2.0/3.0*j0-j2/3);
        b += weight*j2;
    }
}

} // namespace

TEST(PeriodicRotnePragerYamakawa, ClosedFormSmoothPartIsTheQuadrature) {
    // The closed form (and its Taylor series near r = 0) against the trapezoid rule, for equal,
    // unequal and very unequal blobs, apart, overlapping and one inside the other, from r = 0 to
    // beyond the real-space cutoff, at splittings from xi a = 0.05 to 4: within 1e-12 of a blob's
    // self-mobility. The largest difference found is printed.
    double worst = 0;
    for (double xi : {0.5, 2.0, 5.0, 12.0})
        for (const vector<double>& pair : vector<vector<double> >{{0.3, 0.3}, {0.3, 0.2}, {0.1, 0.35}, {0.33, 0.02}})
            for (double r : {0.0, 1e-9, 1e-4, 0.003, 0.0199, 0.0201, 0.05, 0.1, 0.15, 0.28, 0.31, 0.5, 0.64, 1.0, 2.5, 6.0}) {
                double a, b, expectedA, expectedB;
                HasimotoSplit::smoothPart(r, pair[0], pair[1], xi, a, b);
                quadratureSmoothPart(r, pair[0], pair[1], xi, expectedA, expectedB);
                const double scale = RotnePragerYamakawa::selfMobility(std::max(pair[0], pair[1]));
                EXPECT_NEAR(a, expectedA, 1e-12*scale) << "r " << r << ", radii " << pair[0] << " " << pair[1] << ", xi " << xi;
                EXPECT_NEAR(b, expectedB, 1e-12*scale) << "r " << r << ", radii " << pair[0] << " " << pair[1] << ", xi " << xi;
                worst = std::max(worst, std::max(std::abs(a-expectedA), std::abs(b-expectedB))/scale);
            }
    // Exact special cases: G has no dyadic part at r = 0, and G(0) of small blobs (xi a = 0.009) is
    // the point force's xi/(2 pi^1.5) I times 1 - (10/9)(xi a)^2 + (56/45)(xi a)^4 + O((xi a)^6)
    // (sinc(k a)^2 expanded under the integral).
    double a, b;
    const double xi = 3.0, radius = 0.003, x2 = xi*radius*xi*radius;
    HasimotoSplit::smoothPart(0, radius, radius, xi, a, b);
    EXPECT_NEAR(a, xi/(2*std::pow(M_PI, 1.5))*(1-10.0/9*x2+56.0/45*x2*x2), 1e-10*a);
    EXPECT_EQ(b, 0.0);
    std::cout << "largest difference from the quadrature: " << worst << " of the self-mobility" << std::endl;
}

TEST(PeriodicRotnePragerYamakawa, ThreadsGiveTheSameMatrix) {
    vector<Vec3> positions;
    vector<double> radii;
    Vec3 box[3];
    crowdedBlobs(positions, radii, box);
    for (int i = 0; i < 40; i++) {
        positions.push_back(positions[i%12]+Vec3(0.37*i, -0.11*i, 0.05*i));
        radii.push_back(radii[i%12]);
    }
    PeriodicRotnePragerYamakawa periodic(box);
    Eigen::MatrixXd sequential = periodic.mobility(positions, radii);
    Eigen::MatrixXd parallel = periodic.mobility(positions, radii, threads(3));
    EXPECT_LT((parallel-sequential).cwiseAbs().maxCoeff(), 1e-15*sequential.cwiseAbs().maxCoeff());
}

TEST(PeriodicRotnePragerYamakawa, LoneSphereInACubeIsHasimotos) {
    // One blob of radius a in a cube of side L: (1 - 2.837297 a/L + 4 pi/3 (a/L)^3)/(6 pi a), exactly
    // (the RPY tensor has no higher multipoles), isotropic, whatever the splitting.
    const double a = 0.3;
    for (double ratio : {0.02, 0.1, 0.25, 0.45}) {
        vector<Vec3> box = scaled(Cube, a/ratio);
        for (double splitting : {0.0, 3/box[0][0], 9/box[0][0]}) {
            PeriodicRotnePragerYamakawa periodic(box.data(), splitting);
            Eigen::MatrixXd m = periodic.mobility({Vec3(0.1, 0.2, 0.3)}, {a});
            double expected = (1-Hasimoto*ratio+4*M_PI/3*ratio*ratio*ratio)/(6*M_PI*a);
            for (int k = 0; k < 3; k++)
                for (int l = 0; l < 3; l++)
                    EXPECT_NEAR(m(k, l), (k == l ? expected : 0.0), 1e-10/(6*M_PI*a)) << "a/L " << ratio << ", xi " << splitting;
        }
    }
}

TEST(PeriodicRotnePragerYamakawa, IndependentOfTheSplitting) {
    // Overlapping unequal blobs in a triclinic box: the whole mobility the same to 1e-12 of a blob's
    // self-mobility at four splittings, whose real-space parts differ by per cents of it.
    vector<Vec3> positions;
    vector<double> radii;
    Vec3 box[3];
    crowdedBlobs(positions, radii, box);
    double scale = 1/(6*M_PI*0.1);
    Eigen::MatrixXd reference = PeriodicRotnePragerYamakawa(box, 2.0).mobility(positions, radii);
    for (double splitting : {0.0, 4.5, 8.0}) {
        PeriodicRotnePragerYamakawa periodic(box, splitting);
        Eigen::MatrixXd m = periodic.mobility(positions, radii);
        EXPECT_LT((m-reference).cwiseAbs().maxCoeff(), 1e-12*scale) << "xi " << periodic.getSplitting();
        double realPart[9], otherRealPart[9];
        periodic.realSpaceBlock(positions[1]-positions[0], radii[0], radii[1], realPart);
        PeriodicRotnePragerYamakawa(box, 2.0).realSpaceBlock(positions[1]-positions[0], radii[0], radii[1], otherRealPart);
        EXPECT_GT(std::abs(realPart[0]-otherRealPart[0]), 0.02*scale);
    }
    EXPECT_LT((reference-reference.transpose()).cwiseAbs().maxCoeff(), 1e-15*scale);
}

TEST(PeriodicRotnePragerYamakawa, PositiveDefiniteAndPeriodic) {
    // Positive definite for overlapping blobs and a blob overlapping its own images; moving a blob
    // by a box vector changes nothing; moving all of them together changes nothing.
    vector<Vec3> positions;
    vector<double> radii;
    Vec3 box[3];
    crowdedBlobs(positions, radii, box);
    PeriodicRotnePragerYamakawa periodic(box);
    Eigen::MatrixXd m = periodic.mobility(positions, radii);
    Eigen::LLT<Eigen::MatrixXd> cholesky(m);
    EXPECT_EQ(cholesky.info(), Eigen::Success);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(m);
    EXPECT_GT(eigen.eigenvalues()[0], 0);
    vector<Vec3> moved = positions;
    moved[3] += box[0]-box[2]*2;
    EXPECT_LT((periodic.mobility(moved, radii)-m).cwiseAbs().maxCoeff(), 1e-12*m.cwiseAbs().maxCoeff());
    for (Vec3& p : moved)
        p += Vec3(0.37, -1.2, 0.4);
    EXPECT_LT((periodic.mobility(moved, radii)-m).cwiseAbs().maxCoeff(), 1e-12*m.cwiseAbs().maxCoeff());
}

TEST(PeriodicRotnePragerYamakawa, PairFarFromItsImagesIsTheFreePairShifted) {
    // Two blobs 0.6 nm apart in a cube of side L: the periodic pair block is the free RPY block plus
    // the images' uniform backflow -2.837297/(6 pi L) I, up to O(r^2/L^3); as L grows the rest falls
    // as 1/L^3.
    const double a = 0.2, b = 0.15;
    Vec3 d(0.5, 0.3, 0.1);
    double free[9];
    RotnePragerYamakawa::mobilityBlock(d[0], d[1], d[2], a, b, free);
    double previous = 0;
    for (double l : {10.0, 20.0, 40.0}) {
        vector<Vec3> box = scaled(Cube, l);
        Eigen::MatrixXd m = PeriodicRotnePragerYamakawa(box.data()).mobility({Vec3(), d}, {a, b});
        double worst = 0;
        for (int k = 0; k < 3; k++)
            for (int n = 0; n < 3; n++)
                worst = std::max(worst, std::abs(m(k, 3+n)-free[3*k+n]+(k == n ? Hasimoto/(6*M_PI*l) : 0.0)));
        double orderL3 = 1/(6*M_PI*l*l*l);
        EXPECT_LT(worst, 10*orderL3) << "L " << l;
        if (previous > 0) {
            EXPECT_NEAR(worst/previous, 1.0/8, 0.03) << "L " << l;
        }
        previous = worst;
    }
}

TEST(PeriodicRotnePragerYamakawa, RejectsBadBoxes) {
    Vec3 flat[3] = {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
    EXPECT_THROW(PeriodicRotnePragerYamakawa periodic(flat), OpenMMException);
    Vec3 broken[3] = {Vec3(1, 0, 0), Vec3(0, std::nan(""), 0), Vec3(0, 0, 1)};
    EXPECT_THROW(PeriodicRotnePragerYamakawa periodic(broken), OpenMMException);
}
