// Bead models: the generalised Rotne-Prager-Yamakawa mobility, the Cholesky solve of the 3N x 3N
// system, the tensor's invariances, the diffusion tensor, and bad input.

#include "ResistanceTensor.h"
#include "ResistanceTestHelpers.h"
#include "internal/BeadHydrodynamics.h"
#include "internal/RotnePragerYamakawa.h"
#include "beadkernel/BeadResistanceKernel.h"
#include "beadkernel/ParallelCholesky.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ThreadPool.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <gtest/gtest.h>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>
#if defined(__unix__) || defined(__APPLE__)
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#endif

using namespace RigidLangevinPlugin;
using namespace ResistanceTestHelpers;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

Vector3d toEigen(const Vec3& v) {
    return Vector3d(v[0], v[1], v[2]);
}

Matrix3d skew(const Vector3d& r) {
    Matrix3d s;
    s << 0, -r[2], r[1],
         r[2], 0, -r[0],
         -r[1], r[0], 0;
    return s;
}

Matrix3d block(const Vector3d& d, double ai, double aj) {
    double values[9];
    RotnePragerYamakawa::mobilityBlock(d[0], d[1], d[2], ai, aj, values);
    return Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor> >(values);
}

/**
 * The source's procedure, written independently of the library: the Rotne-Prager tensor of
 * non-overlapping beads (PHYSICS.md's corrected form), the matrix B inverted explicitly, and the
 * blocks of C = B^-1 summed about the origin. The force-from-angular-velocity block is summed on
 * its own (-sum C_ij U_j) rather than taken as the transpose of the torque-from-velocity block.
 */
Matrix6 bruteForce(const vector<Vec3>& positions, const vector<double>& radii, const Vec3& origin) {
    const int n = positions.size();
    MatrixXd b(3*n, 3*n);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            if (i == j) {
                b.block<3, 3>(3*i, 3*i) = Matrix3d::Identity()/(6*M_PI*radii[i]);
                continue;
            }
            Vector3d r = toEigen(positions[j]-positions[i]);
            double distance = r.norm();
            EXPECT_GT(distance, radii[i]+radii[j]) << "bruteForce() is for non-overlapping beads";
            Matrix3d rr = r*r.transpose()/(distance*distance);
            double sigma2 = (radii[i]*radii[i]+radii[j]*radii[j])/(distance*distance);
            b.block<3, 3>(3*i, 3*j) = ((Matrix3d::Identity()+rr)+sigma2*(Matrix3d::Identity()/3-rr))/(8*M_PI*distance);
        }
    MatrixXd c = b.inverse();
    Matrix6 xi = Matrix6::Zero();
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            Matrix3d cij = c.block<3, 3>(3*i, 3*j);
            Matrix3d ui = skew(toEigen(positions[i]-origin)), uj = skew(toEigen(positions[j]-origin));
            xi.block<3, 3>(0, 0) += cij;
            xi.block<3, 3>(3, 0) += ui*cij;
            xi.block<3, 3>(0, 3) -= cij*uj;
            xi.block<3, 3>(3, 3) -= ui*cij*uj;
        }
    return xi;
}

Matrix3d coupling(const Matrix6& xi) {
    return xi.block<3, 3>(3, 0);
}

/** The antisymmetric part of a coupling block relative to the whole block. */
double asymmetry(const Matrix3d& m) {
    return (m-m.transpose()).norm()/m.norm();
}

/** A chiral 12-bead model (no symmetry that would make the coupling vanish). */
void chiralModel(vector<Vec3>& positions, vector<double>& radii) {
    std::mt19937 random(2024);
    randomBeads(12, 2.0, 0.05, random, positions, radii);
}

} // namespace

TEST(RotnePragerYamakawa, MatchesThePublishedForms) {
    // PHYSICS.md section 2, typed in: the corrected non-overlapping form and the equal-radius
    // overlapping form. Same formulas, different arithmetic: 1e-14.
    const double a = 0.3;
    Vector3d direction = Vector3d(1, -2, 0.5).normalized();
    Matrix3d rr = direction*direction.transpose(), identity = Matrix3d::Identity();
    for (double r : {0.1, 0.35, 0.59, 0.61, 1.5, 10.0}) {
        Matrix3d expected;
        if (r >= 2*a)
            expected = ((identity+rr)+(2*a*a/(r*r))*(identity/3-rr))/(8*M_PI*r);
        else
            expected = ((1-9*r/(32*a))*identity+(3*r/(32*a))*rr)/(6*M_PI*a);
        EXPECT_LT((block(r*direction, a, a)-expected).norm(), 1e-14*expected.norm()) << "r = " << r;
    }
    // Unequal radii (Zuk et al.), one overlapping and one nested distance.
    const double ai = 0.2, aj = 0.5;
    for (double r : {0.4, 0.65}) {
        double d2 = (ai-aj)*(ai-aj);
        Matrix3d expected = ((16*r*r*r*(ai+aj)-std::pow(d2+3*r*r, 2))/(32*r*r*r)*identity+3*std::pow(d2-r*r, 2)/(32*r*r*r)*rr)/(6*M_PI*ai*aj);
        EXPECT_LT((block(r*direction, ai, aj)-expected).norm(), 1e-14*expected.norm()) << "r = " << r;
    }
    Matrix3d nested = block(0.2*direction, ai, aj);
    EXPECT_LT((nested-identity/(6*M_PI*aj)).norm(), 1e-15);
    EXPECT_LT((block(Vector3d::Zero(), ai, aj)-identity/(6*M_PI*aj)).norm(), 1e-15);
}

TEST(RotnePragerYamakawa, ContinuousSymmetricAndPositiveDefinite) {
    const double ai = 0.2, aj = 0.5;
    Vector3d direction = Vector3d(0.3, 0.4, -1).normalized();
    // Continuous where the forms change (r = ai+aj and r = |ai-aj|): the blocks are smooth in r on
    // either side, so a step of 1e-9 changes them by O(1e-9) relative.
    for (double boundary : {ai+aj, aj-ai}) {
        Matrix3d below = block((boundary-1e-9)*direction, ai, aj), above = block((boundary+1e-9)*direction, ai, aj);
        EXPECT_LT((below-above).norm(), 1e-8*above.norm()) << "at r = " << boundary;
    }
    // Swapping the beads (and the direction) leaves the block unchanged; blocks are symmetric.
    Matrix3d forward = block(0.45*direction, ai, aj);
    EXPECT_LT((forward-block(-0.45*direction, aj, ai)).norm(), 1e-15);
    EXPECT_LT((forward-forward.transpose()).norm(), 1e-15);
    // The two-bead mobility is positive definite at every distance, overlap included.
    for (double r = 0.0; r < 1.5; r += 0.01) {
        MatrixXd b(6, 6);
        b << Matrix3d::Identity()/(6*M_PI*ai), block(r*direction, ai, aj),
             block(r*direction, ai, aj), Matrix3d::Identity()/(6*M_PI*aj);
        EXPECT_GT(Eigen::SelfAdjointEigenSolver<MatrixXd>(b).eigenvalues().minCoeff(), 0) << "r = " << r;
    }
}

TEST(ParallelCholesky, MatchesEigensLLT) {
    // Small blocks so that every part of the driver runs, sizes that are and are not multiples of
    // them, on the calling thread and on a pool of three. Same arithmetic up to summation order:
    // 1e-13 relative (the matrix is well conditioned).
    std::mt19937 random(3);
    OpenMM::ThreadPool threads(3);
    for (int n : {1, 64, 301})
      for (OpenMM::ThreadPool* pool : {(OpenMM::ThreadPool*) nullptr, &threads}) {
        MatrixXd g = MatrixXd::NullaryExpr(n, n, [&]() { return std::normal_distribution<double>()(random); });
        MatrixXd spd = g*g.transpose()+n*MatrixXd::Identity(n, n);
        MatrixXd factor = spd;
        factor.triangularView<Eigen::StrictlyUpper>().setConstant(std::nan(""));  // must not be read
        ASSERT_TRUE(parallelCholeskyInPlace(factor, pool, 16, 32));
        MatrixXd expected = Eigen::LLT<MatrixXd>(spd).matrixL();
        MatrixXd lower = factor.triangularView<Eigen::Lower>();
        EXPECT_LT((lower-expected).norm(), 1e-13*expected.norm()) << "n = " << n;
        int written = 0;
        for (int j = 0; j < n; j++)
            for (int i = 0; i < j; i++)
                written += !std::isnan(factor(i, j));
        EXPECT_EQ(0, written) << "elements of the strict upper triangle were written";
    }
    // An indefinite matrix is reported, whichever block holds the negative pivot.
    MatrixXd indefinite = MatrixXd::Identity(100, 100);
    indefinite(70, 70) = -1;
    EXPECT_FALSE(parallelCholeskyInPlace(indefinite, &threads, 16, 32));
}

TEST(ResistanceTensor, BeadsAgainstBruteForceInverse) {
    // 12 random non-overlapping beads (one Cholesky block) and 150 (several blocks of the
    // parallel factorisation). B is well conditioned here (condition number ~10-100), so the two
    // routes agree to ~1e-13; 1e-10 relative to the largest element.
    std::mt19937 random(7);
    for (int numBeads : {12, 150}) {
        vector<Vec3> positions;
        vector<double> radii;
        randomBeads(numBeads, 1.2*std::cbrt((double) numBeads), 0.01, random, positions, radii);
        ResistanceTensor t = ResistanceTensor::beads(positions, radii);
        for (Vec3 origin : {t.getOrigin(), positions[0], Vec3(1, -2, 3)})
            EXPECT_LT(relativeDifference(toMatrix6(t.getMatrix(origin)), bruteForce(positions, radii, origin)), 1e-10) << numBeads << " beads";
    }
}

TEST(ResistanceTensor, SingleBeadIsStokesSphere) {
    // One bead: Xtt = 6 pi a exactly; a point force has no rotational friction, and the volume
    // correction 6 V = 6 (4/3) pi a^3 = 8 pi a^3 restores Stokes rotation exactly.
    const double a = 0.37;
    Vec3 p(1, 2, 3);
    Matrix6 plain = toMatrix6(ResistanceTensor::beads({p}, {a}).getMatrix(p));
    Matrix6 expected = toMatrix6(ResistanceTensor::sphere(a, p).getMatrix(p));
    EXPECT_LT(((plain.block<3, 3>(0, 0)-expected.block<3, 3>(0, 0)).norm()), (1e-14*expected(0, 0)));
    EXPECT_LT((plain.block<3, 3>(3, 3).norm()+plain.block<3, 3>(3, 0).norm()), (1e-14*expected(0, 0)));
    Matrix6 corrected = toMatrix6(ResistanceTensor::beads({p}, {a}, ResistanceTensor::beadVolume({a})).getMatrix(p));
    EXPECT_LT(relativeDifference(corrected, expected), 1e-14);
}

TEST(ResistanceTensor, TwoTouchingSpheres) {
    // Two beads of radius a touching (r = 2a), about the contact point, axis x.
    //
    // What the two-bead RPY model gives, exactly: with self mobility 8/(48 pi a) and the RPY
    // tensor at r = 2a equal to 5/(48 pi a) along the axis and 3.5/(48 pi a) across it,
    //   xi_t_par  = 2/(13/(48 pi a))   = (16/13)   6 pi a = 1.2308 6 pi a
    //   xi_t_perp = 2/(11.5/(48 pi a)) = (16/11.5) 6 pi a = 1.3913 6 pi a
    //   xi_r_par  = 0 + 6 V            = 2         8 pi a^3   (V = 2 (4/3) pi a^3)
    //   xi_r_perp = 2 a^2 48 pi a/4.5 + 6 V = (8/3 + 2) 8 pi a^3 = 4.6667 8 pi a^3
    // (checked to 1e-12: exact arithmetic against the solver).
    //
    // Against the published exact values (PHYSICS.md): translation 1.2902 and 1.4492 (the model is
    // 4.6% and 4.0% low), rotation 1.8032 and 3.740, which PHYSICS says the 6 eta V corrected
    // two-bead model overestimates by 11% and 25%: 2/1.8032 = 1.109, 4.6667/3.740 = 1.248. The shell
    // model gets all four to within 1% (TestResistanceTensorShell).
    const double a = 0.25;
    vector<Vec3> positions = {Vec3(-a, 0, 0), Vec3(a, 0, 0)};
    vector<double> radii = {a, a};
    Matrix6 xi = toMatrix6(ResistanceTensor::beads(positions, radii, ResistanceTensor::beadVolume(radii)).getMatrix(Vec3()));
    const double t = 6*M_PI*a, r = 8*M_PI*a*a*a;
    EXPECT_NEAR(16.0/13.0, xi(0, 0)/t, 1e-12);
    EXPECT_NEAR(16.0/11.5, xi(1, 1)/t, 1e-12);
    EXPECT_NEAR(16.0/11.5, xi(2, 2)/t, 1e-12);
    EXPECT_NEAR(2.0, xi(3, 3)/r, 1e-12);
    EXPECT_NEAR(14.0/3.0, xi(4, 4)/r, 1e-12);
    EXPECT_NEAR(14.0/3.0, xi(5, 5)/r, 1e-12);
    EXPECT_LT((xi.block<3, 3>(3, 0).norm()), (1e-12*t));
    // PHYSICS's statements, to the precision it gives them (whole percent: +-0.5%).
    EXPECT_NEAR(1.11, xi(3, 3)/r/1.8032, 0.005);
    EXPECT_NEAR(1.25, xi(4, 4)/r/3.740, 0.005);
    EXPECT_NEAR(1.2902, xi(0, 0)/t, 0.05*1.2902);
    EXPECT_NEAR(1.4492, xi(1, 1)/t, 0.05*1.4492);
}

TEST(ResistanceTensor, NestedAndOverlappingBeads) {
    // A bead inside a larger one moves with it (mobility I/(6 pi a_big) between them), so it adds
    // nothing to the translational friction, wherever it is inside: Xtt = 6 pi a_big exactly.
    const double big = 0.5;
    for (Vec3 inner : {Vec3(0, 0, 0), Vec3(0.1, 0.2, -0.1)}) {
        Matrix6 xi = toMatrix6(ResistanceTensor::beads({Vec3(0, 0, 0), inner}, {big, 0.2}).getMatrix(Vec3()));
        EXPECT_LT(((xi.block<3, 3>(0, 0)-6*M_PI*big*Matrix3d::Identity()).norm()), (1e-12*6*M_PI*big));
    }
    // A chain of overlapping beads of different sizes: symmetric positive definite, and its
    // translational friction lies between that of its largest bead and the free-draining sum.
    vector<Vec3> positions;
    vector<double> radii;
    for (int i = 0; i < 8; i++) {
        positions.push_back(Vec3(0.15*i, 0.05*std::sin(i), 0.0));
        radii.push_back(0.1+0.02*(i%3));
    }
    Matrix6 xi = toMatrix6(ResistanceTensor::beads(positions, radii, ResistanceTensor::beadVolume(radii)).getMatrix());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6>(xi).eigenvalues().minCoeff(), 0);
    double sum = 0;
    for (double r : radii)
        sum += 6*M_PI*r;
    for (int k = 0; k < 3; k++) {
        EXPECT_GT(xi(k, k), 6*M_PI*0.14);
        EXPECT_LT(xi(k, k), sum);
    }
}

TEST(ResistanceTensor, OriginCentreOfResistanceAndRotation) {
    vector<Vec3> positions;
    vector<double> radii;
    chiralModel(positions, radii);
    ResistanceTensor t = ResistanceTensor::beads(positions, radii);
    Matrix6 atOrigin = toMatrix6(t.getMatrix());
    // Xtt does not depend on the origin (to rounding); the other blocks do.
    Matrix6 elsewhere = toMatrix6(t.getMatrix(Vec3(3, -1, 2)));
    EXPECT_LT(((elsewhere.block<3, 3>(0, 0)-atOrigin.block<3, 3>(0, 0)).norm()), (1e-13*atOrigin.block<3, 3>(0, 0).norm()));
    EXPECT_GT(((elsewhere.block<3, 3>(3, 3)-atOrigin.block<3, 3>(3, 3)).norm()), (0.1*atOrigin.block<3, 3>(3, 3).norm()));
    // The coupling block is symmetric at the centre of resistance and not at the centroid.
    Vec3 centre = t.getCenterOfResistance();
    Matrix6 atCentre = toMatrix6(t.getMatrix(centre));
    EXPECT_LT(asymmetry(coupling(atCentre)), 1e-10);
    EXPECT_GT(asymmetry(coupling(atOrigin)), 1e-2);
    // ... where the trace of Xrr is smallest: it grows as tr(Xtt)|d|^2-d.Xtt.d away from it.
    for (Vec3 d : {Vec3(0.01, 0, 0), Vec3(0, -0.01, 0), Vec3(0, 0, 0.01)}) {
        Matrix6 moved = toMatrix6(t.getMatrix(centre+d));
        EXPECT_GT((moved.block<3, 3>(3, 3).trace()), (atCentre.block<3, 3>(3, 3).trace()));
    }
    // Rotating the beads rotates the tensor: R X R^T per block, about the rotated point.
    std::mt19937 random(11);
    Matrix3d rotation = randomRotation(random);
    vector<Vec3> turned;
    for (const Vec3& p : positions) {
        Vector3d q = rotation*toEigen(p);
        turned.push_back(Vec3(q[0], q[1], q[2]));
    }
    ResistanceTensor direct = ResistanceTensor::beads(turned, radii);
    ResistanceTensor rotated = t.rotated(rowMajor(rotation));
    Vec3 point(0.3, 0.1, -0.2);
    EXPECT_LT(relativeDifference(toMatrix6(direct.getMatrix(point)), toMatrix6(rotated.getMatrix(point))), 1e-12);
    // Symmetric to rounding, positive definite.
    EXPECT_LT((atOrigin-atOrigin.transpose()).cwiseAbs().maxCoeff(), 1e-14*atOrigin.cwiseAbs().maxCoeff());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Matrix6>(atOrigin).eigenvalues().minCoeff(), 1e-3*atOrigin.diagonal().minCoeff());
    EXPECT_NO_THROW(t.validate("chiral model"));
}

TEST(ResistanceTensor, DiffusionTensor) {
    vector<Vec3> positions;
    vector<double> radii;
    chiralModel(positions, radii);
    ResistanceTensor t = ResistanceTensor::beads(positions, radii);
    const double temperature = 300, viscosity = 536.0;  // water, amu/(nm ps)
    const double kT = BOLTZ*temperature;
    for (Vec3 origin : {t.getOrigin(), Vec3(1, 2, -1)}) {
        Matrix6 d = toMatrix6(t.getDiffusionTensor(temperature, viscosity, origin));
        Matrix6 xi = toMatrix6(t.getMatrix(origin));
        // D (viscosity Xi) = kT I; Xi's condition number is ~1e3 here, so 1e-12 relative.
        EXPECT_LT((d*viscosity*xi-kT*Matrix6::Identity()).cwiseAbs().maxCoeff(), 1e-12*kT);
    }
    EXPECT_LT(relativeDifference(toMatrix6(t.getDiffusionTensor(temperature, viscosity)), toMatrix6(t.getDiffusionTensor(temperature, viscosity, t.getOrigin()))), 1e-15);
    // The centre of diffusion: there the block giving angular velocity from force is symmetric.
    Vec3 centre = t.getCenterOfDiffusion();
    EXPECT_LT(asymmetry(coupling(toMatrix6(t.getDiffusionTensor(temperature, viscosity, centre)))), 1e-10);
    EXPECT_GT(asymmetry(coupling(toMatrix6(t.getDiffusionTensor(temperature, viscosity)))), 1e-2);
    // A sphere: Stokes-Einstein, kT/(6 pi eta R) and kT/(8 pi eta R^3), centre of diffusion at its centre.
    const double radius = 0.2;
    Vec3 c(1, 1, 1);
    Matrix6 d = toMatrix6(ResistanceTensor::sphere(radius, c).getDiffusionTensor(temperature, viscosity));
    EXPECT_NEAR(kT/(6*M_PI*viscosity*radius), d(0, 0), 1e-15*d(0, 0));
    EXPECT_NEAR(kT/(8*M_PI*viscosity*radius*radius*radius), d(5, 5), 1e-15*d(5, 5));
    Vec3 sphereCentre = ResistanceTensor::sphere(radius, c).getCenterOfDiffusion();
    EXPECT_LT(std::sqrt((sphereCentre-c).dot(sphereCentre-c)), 1e-15);
    // Bad arguments and singular tensors are errors, not NaN.
    expectThrowMentioning([&] { t.getDiffusionTensor(0, viscosity); }, {"temperature"});
    expectThrowMentioning([&] { t.getDiffusionTensor(temperature, -1); }, {"viscosity"});
    expectThrowMentioning([&] { t.getDiffusionTensor(std::nan(""), viscosity); }, {"temperature"});
    ResistanceTensor linear = ResistanceTensor::beads({Vec3(0, 0, 0), Vec3(0.5, 0, 0)}, {0.2, 0.2});
    expectThrowMentioning([&] { linear.getDiffusionTensor(temperature, viscosity); }, {"not positive definite"});
    expectThrowMentioning([&] { linear.getCenterOfDiffusion(); }, {"singular"});
}

TEST(ResistanceTensor, BeadVolumeCorrection) {
    vector<Vec3> positions;
    vector<double> radii;
    chiralModel(positions, radii);
    Matrix6 plain = toMatrix6(ResistanceTensor::beads(positions, radii).getMatrix());
    const double volume = ResistanceTensor::beadVolume(radii);
    Matrix6 corrected = toMatrix6(ResistanceTensor::beads(positions, radii, volume).getMatrix());
    Matrix6 difference = corrected-plain;
    Matrix6 expected = Matrix6::Zero();
    expected.block<3, 3>(3, 3) = 6*volume*Matrix3d::Identity();
    EXPECT_LT((difference-expected).cwiseAbs().maxCoeff(), 1e-13*plain.cwiseAbs().maxCoeff());
    double sum = 0;
    for (double r : radii)
        sum += 4*M_PI/3*r*r*r;
    EXPECT_NEAR(sum, volume, 1e-15*sum);
    expectThrowMentioning([&] { ResistanceTensor::beads(positions, radii, -1); }, {"correction volume"});
}

TEST(ResistanceTensor, KernelsAgree) {
    // The AVX2/FMA and baseline builds of the kernel differ only in rounding (FMA, vector
    // reduction order): 1e-11 relative on a 300-bead cluster of overlapping beads (condition
    // number ~1e4).
    if (!BeadHydrodynamics::isAVX2KernelAvailable()) {
        EXPECT_THROW(BeadHydrodynamics::resistance("test", {Vec3()}, {1.0}, Vec3(), BeadHydrodynamics::AVX2Kernel), OpenMMException);
        GTEST_SKIP() << "no AVX2 kernel on this build or CPU";
    }
    std::mt19937 random(5);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    vector<Vec3> positions;
    vector<double> radii;
    for (int i = 0; i < 300; i++) {
        positions.push_back(Vec3(2*uniform(random), 2*uniform(random), 2*uniform(random)));
        radii.push_back(0.05+0.1*uniform(random));
    }
    Matrix6 generic = BeadHydrodynamics::resistance("test", positions, radii, Vec3(1, 1, 1), BeadHydrodynamics::GenericKernel);
    Matrix6 avx2 = BeadHydrodynamics::resistance("test", positions, radii, Vec3(1, 1, 1), BeadHydrodynamics::AVX2Kernel);
    EXPECT_LT(relativeDifference(avx2, generic), 1e-11);
}

TEST(ResistanceTensor, PivotedFallbackForASingularMobility) {
    // The generalised RPY matrix of distinct beads is positive definite, so the fallback is for
    // matrices that rounding has made indefinite. Call the kernel directly with one bead given
    // twice (which validation would reject): B is exactly singular, the Cholesky factorisation
    // fails, and the pivoted LDL^T solves the consistent system; since P lies in the range of B,
    // P^T B^+ P is the tensor of the model without the duplicate (a single Stokes bead: 6 pi a).
    const double a = 0.3;
    double positions[6] = {0.1, 0.2, 0.3, 0.1, 0.2, 0.3};
    double radii[2] = {a, a};
    double origin[3] = {0.1, 0.2, 0.3};
    double values[36];
    EXPECT_EQ(BEAD_KERNEL_LDLT, rigidLangevinBeadResistanceGeneric(2, positions, radii, origin, 1, values));
    for (int k = 0; k < 3; k++)
        EXPECT_NEAR(6*M_PI*a, values[7*k], 1e-10*6*M_PI*a);
}

#if defined(__unix__) || defined(__APPLE__)
TEST(ResistanceTensor, ForkAfterComputingDoesNotHang) {
    // A process that computed a tensor and then forks (Python's multiprocessing) must be able to
    // compute in the child. With GCC's OpenMP runtime the child would wait forever for the
    // parent's worker threads; the kernel's ThreadPool lives only during one computation. Large
    // enough to use threads; the child gets 60 s for what takes well under one.
    std::mt19937 random(17);
    vector<Vec3> positions;
    vector<double> radii;
    randomBeads(300, 8.0, 0.0, random, positions, radii);
    Matrix6 parent = toMatrix6(ResistanceTensor::beads(positions, radii).getMatrix());
    pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        Matrix6 again = toMatrix6(ResistanceTensor::beads(positions, radii).getMatrix());
        _exit(relativeDifference(again, parent) < 1e-12 ? 0 : 1);
    }
    int status = 0;
    bool finished = false;
    for (int i = 0; i < 600 && !finished; i++) {
        finished = (waitpid(child, &status, WNOHANG) == child);
        if (!finished)
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    if (!finished) {
        kill(child, SIGKILL);
        waitpid(child, &status, 0);
    }
    EXPECT_TRUE(finished) << "the forked child hung computing a tensor";
    EXPECT_TRUE(finished && WIFEXITED(status) && WEXITSTATUS(status) == 0);
}
#endif

TEST(ResistanceTensor, BeadsRejectBadInput) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    vector<Vec3> positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    vector<double> radii = {0.2, 0.2, 0.2, 0.2};
    EXPECT_NO_THROW(ResistanceTensor::beads(positions, radii));

    // Coincident beads: same position, same radius.
    vector<Vec3> coincident = positions;
    coincident[3] = coincident[1];
    EXPECT_THROW(ResistanceTensor::beads(coincident, radii), OpenMMException);
    expectThrowMentioning([&] { ResistanceTensor::beads(coincident, radii); }, {"beads 1 and 3", "coincident"});
    // The same position with a different radius is a nested bead, not an error.
    vector<double> nested = radii;
    nested[3] = 0.1;
    EXPECT_NO_THROW(ResistanceTensor::beads(coincident, nested));

    for (double bad : {0.0, -0.2, nan, std::numeric_limits<double>::infinity()}) {
        vector<double> badRadii = radii;
        badRadii[2] = bad;
        EXPECT_THROW(ResistanceTensor::beads(positions, badRadii), OpenMMException);
        expectThrowMentioning([&] { ResistanceTensor::beads(positions, badRadii); }, {"bead 2", "radius"});
    }
    vector<Vec3> badPositions = positions;
    badPositions[1] = Vec3(0, nan, 0);
    EXPECT_THROW(ResistanceTensor::beads(badPositions, radii), OpenMMException);
    expectThrowMentioning([&] { ResistanceTensor::beads(badPositions, radii); }, {"bead 1", "position"});

    EXPECT_THROW(ResistanceTensor::beads({}, {}), OpenMMException);
    expectThrowMentioning([&] { ResistanceTensor::beads({}, {}); }, {"empty"});
    expectThrowMentioning([&] { ResistanceTensor::beads(positions, {0.2, 0.2}); }, {"4 bead positions but 2 radii"});
}
