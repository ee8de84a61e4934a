// The positively split Ewald product against the dense Ewald sum (PeriodicRotnePragerYamakawa, the
// oracle) at the stated tolerance, across splittings, cubic and triclinic boxes, equal and unequal
// and overlapping blobs; Hasimoto's lone blob; both parts symmetric positive semidefinite; the
// noise's covariance against the dense M eigenmode by eigenmode; the same answers on any number of
// threads; bad input.

#include "internal/PeriodicRotnePragerYamakawa.h"
#include "internal/PositivelySplitEwald.h"
#include "PeriodicTestHelpers.h"
#include "openmm/OpenMMException.h"
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

/** A cube of side l, or a triclinic box (OpenMM's reduced form) of about the same volume. */
void makeBox(bool triclinic, double l, Vec3 box[3]) {
    box[0] = Vec3(l, 0, 0);
    box[1] = (triclinic ? Vec3(0.3*l, 0.95*l, 0) : Vec3(0, l, 0));
    box[2] = (triclinic ? Vec3(-0.25*l, 0.35*l, 1.1*l) : Vec3(0, 0, l));
}

/** n blobs placed at random (overlaps included), radii drawn from choices, the first pair overlapping. */
void randomBlobs(int n, const vector<double>& choices, const Vec3 box[3], int seed, vector<Vec3>& positions, vector<double>& radii) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(0, 1);
    positions.clear();
    radii.clear();
    for (int i = 0; i < n; i++) {
        positions.push_back(box[0]*uniform(random)+box[1]*uniform(random)+box[2]*uniform(random)+box[0]*(i%3-1));
        radii.push_back(choices[i%choices.size()]);
    }
    positions[1] = positions[0]+Vec3(0.3, -0.2, 0.1)*radii[0];
}

/** A box of side about l and n blobs in it (randomBlobs). */
struct Scene {
    Scene(int n, const vector<double>& choices, bool triclinic, double l, int seed) {
        makeBox(triclinic, l, box);
        randomBlobs(n, choices, box, seed, positions, radii);
    }
    Vec3 box[3];
    vector<Vec3> positions;
    vector<double> radii;
};

Eigen::VectorXd randomForces(int n, int seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> normal;
    Eigen::VectorXd f(3*n);
    for (int i = 0; i < 3*n; i++)
        f[i] = normal(random);
    return f;
}

/** The worst |M_pse f - M f|/|M f| over three random force vectors. */
double worstRelativeError(PositivelySplitEwald& pse, const Eigen::MatrixXd& dense) {
    double worst = 0;
    for (int seed = 1; seed <= 3; seed++) {
        Eigen::VectorXd f = randomForces(dense.rows()/3, seed), product;
        pse.multiply(f, product);
        Eigen::VectorXd exact = dense*f;
        worst = std::max(worst, (product-exact).norm()/exact.norm());
    }
    return worst;
}

/** The operator as a dense matrix, column by column. */
Eigen::MatrixXd formMatrix(const std::function<void (const Eigen::VectorXd&, Eigen::VectorXd&)>& multiply, int size) {
    Eigen::MatrixXd m(size, size);
    for (int k = 0; k < size; k++) {
        Eigen::VectorXd unit = Eigen::VectorXd::Unit(size, k), column;
        multiply(unit, column);
        m.col(k) = column;
    }
    return m;
}

} // namespace

TEST(PositivelySplitEwald, AgreesWithTheDenseEwaldAtTheTolerance) {
    // 60 blobs at about 10% volume fraction (overlaps included) in a cube and a triclinic box, of
    // one, two and three radii: the relative error of M f below epsilon (criterion: |M_pse f -
    // M f|/|M f| < epsilon for three random f), at the splitting chosen and at 1.5 times it (more
    // of the sum in wave space); 1e-4 is the tightest with the real-space pairs in single precision
    // (PseParameterChoice::singlePrecisionPairs). The worst error over epsilon is printed.
    double worst = 0;
    for (bool triclinic : {false, true})
        for (const vector<double>& choices : vector<vector<double> >{{0.3}, {0.3, 0.18}, {0.25, 0.4, 0.2}}) {
            Scene scene(60, choices, triclinic, 4.2, 7+choices.size());
            Eigen::MatrixXd dense = PeriodicRotnePragerYamakawa(scene.box).mobility(scene.positions, scene.radii);
            for (double tolerance : {1e-3, 1e-4, 1e-6, 1e-9}) {
                PositivelySplitEwald chosen(tolerance);
                chosen.setBlobs(scene.positions, scene.radii, scene.box);
                PositivelySplitEwald more(tolerance, 1.5*chosen.getSplitting());
                more.setBlobs(scene.positions, scene.radii, scene.box);
                for (PositivelySplitEwald* pse : {&chosen, &more}) {
                    double error = worstRelativeError(*pse, dense);
                    EXPECT_LT(error, tolerance) << "triclinic " << triclinic << ", " << choices.size() << " radii, epsilon " << tolerance << ", xi "
                                                << pse->getSplitting();
                    worst = std::max(worst, error/tolerance);
                }
            }
        }
    std::cout << "largest error: " << worst << " epsilon" << std::endl;
}

TEST(PositivelySplitEwald, LoneBlobIsHasimotos) {
    // One blob of radius a in a cube of side L moves with (1 - 2.837297 a/L + 4 pi/3 (a/L)^3)/(6 pi a)
    // (Hasimoto 1959; exact for an RPY blob), to epsilon.
    const double a = 0.3;
    for (double ratio : {0.02, 0.1})
        for (double tolerance : {1e-4, 1e-8}) {
            const double l = a/ratio;
            Vec3 box[3];
            makeBox(false, l, box);
            PositivelySplitEwald pse(tolerance);
            pse.setBlobs({Vec3(0.1, 3.2, -0.7)}, {a}, box);
            Eigen::VectorXd f(3), u;
            f << 0.3, -1.1, 0.5;
            pse.multiply(f, u);
            const double mobility = (1-Hasimoto*ratio+4*M_PI/3*ratio*ratio*ratio)/(6*M_PI*a);
            EXPECT_LT((u-mobility*f).norm(), tolerance*mobility*f.norm()) << "a/L " << ratio << ", epsilon " << tolerance;
        }
}

TEST(PositivelySplitEwald, BothPartsAreSymmetricPositiveSemidefinite) {
    // The wave-space part exactly (interpolation is spreading's transpose, each mode's factor
    // positive): symmetric and no eigenvalue below -1e-14 of the largest; the real-space part up to
    // its cutoff's error epsilon; and together the dense M to epsilon.
    Scene scene(20, {0.3, 0.2}, true, 3.5, 5);
    const double tolerance = 1e-6;
    PositivelySplitEwald pse(tolerance);
    pse.setBlobs(scene.positions, scene.radii, scene.box);
    Eigen::MatrixXd wave = formMatrix([&] (const Eigen::VectorXd& f, Eigen::VectorXd& u) { pse.multiplyWaveSpace(f, u); }, 60);
    Eigen::MatrixXd real = formMatrix([&] (const Eigen::VectorXd& f, Eigen::VectorXd& u) { pse.multiplyRealSpace(f, u); }, 60);
    const double scale = (wave+real).cwiseAbs().maxCoeff();
    EXPECT_LT((wave-wave.transpose()).cwiseAbs().maxCoeff(), 1e-14*scale);
    EXPECT_LT((real-real.transpose()).cwiseAbs().maxCoeff(), 1e-14*scale);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(wave).eigenvalues()[0], -1e-14*scale);
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(real).eigenvalues()[0], -tolerance*scale);
    Eigen::MatrixXd dense = PeriodicRotnePragerYamakawa(scene.box).mobility(scene.positions, scene.radii);
    EXPECT_LT((wave+real-dense).norm(), tolerance*dense.norm());
}

TEST(PositivelySplitEwald, NoiseCovarianceIsTheMobilityModeByMode) {
    // 2000 samples for 6 blobs of two radii (two overlapping) in a triclinic box, whitened by the
    // dense M's eigenmodes: y_k = (v_k . u)/sqrt(lambda_k) must have unit variance and no
    // correlations. The variance averaged over the 18 modes has standard error sqrt(2/36000) =
    // 0.0075: the 4 SE tolerance (0.030) fails a 5% error in the noise's variance (6.7 SE); each
    // mode alone is held to 5 SE (0.16); the off-diagonal covariances, n C_kl^2 summed, to 5 SD of
    // their chi^2. At epsilon 1e-3 the PSE's M is the dense one to 1e-4, far below these errors.
    Scene scene(6, {0.3, 0.2}, true, 5.0, 3);
    PositivelySplitEwald pse(1e-3);
    pse.setBlobs(scene.positions, scene.radii, scene.box);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(PeriodicRotnePragerYamakawa(scene.box).mobility(scene.positions, scene.radii));
    Eigen::MatrixXd whiten = eigen.eigenvalues().cwiseSqrt().cwiseInverse().asDiagonal()*eigen.eigenvectors().transpose();
    std::mt19937_64 random(2024);
    std::normal_distribution<double> gaussian;
    long long draws = 0;
    std::function<double()> normal = [&] () { draws++; return gaussian(random); };
    const int numSamples = 2000, d = 18;
    Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(d, d);
    for (int s = 0; s < numSamples; s++) {
        Eigen::VectorXd u;
        draws = 0;
        ASSERT_EQ(pse.sampleNoise(normal, u, 1e-10, 50).outcome, KrylovSolvers::Converged);
        ASSERT_EQ(draws, pse.getNumNoiseNormals());
        Eigen::VectorXd y = whiten*u;
        covariance += y*y.transpose()/numSamples;
    }
    const double variance = covariance.diagonal().mean();
    EXPECT_NEAR(variance, 1.0, 4*std::sqrt(2.0/(numSamples*d)));
    double offDiagonal = 0;
    for (int k = 0; k < d; k++) {
        EXPECT_NEAR(covariance(k, k), 1.0, 5*std::sqrt(2.0/numSamples)) << "mode " << k;
        for (int l = 0; l < k; l++)
            offDiagonal += numSamples*covariance(k, l)*covariance(k, l);
    }
    const double dof = d*(d-1)/2;
    EXPECT_LT(offDiagonal, dof+5*std::sqrt(2*dof));
    std::cout << "variance over the modes " << variance << " (SE " << std::sqrt(2.0/(numSamples*d)) << "), off-diagonal chi^2 " << offDiagonal
              << " for " << dof << " degrees of freedom" << std::endl;
}

TEST(PositivelySplitEwald, ThreadsGiveTheSameAnswers) {
    // Every stage shares out whole rows, planes or lines: the same numbers on three threads, in a
    // cube (rectangular spreading) and a triclinic box.
    for (bool triclinic : {false, true}) {
        Scene scene(300, {0.3, 0.2}, triclinic, 6.0, 9);
        PositivelySplitEwald sequential(1e-5), parallel(1e-5, 0, threads(3));
        sequential.setBlobs(scene.positions, scene.radii, scene.box);
        parallel.setBlobs(scene.positions, scene.radii, scene.box);
        Eigen::VectorXd f = randomForces(300, 4), u, v;
        sequential.multiply(f, u);
        parallel.multiply(f, v);
        EXPECT_EQ((u-v).cwiseAbs().maxCoeff(), 0.0) << "triclinic " << triclinic;
        std::mt19937_64 first(1), second(1);
        std::normal_distribution<double> gaussian;
        sequential.sampleNoise([&] () { return gaussian(first); }, u, 1e-8, 100);
        parallel.sampleNoise([&] () { return gaussian(second); }, v, 1e-8, 100);
        EXPECT_LT((u-v).cwiseAbs().maxCoeff(), 1e-14*u.cwiseAbs().maxCoeff()) << "triclinic " << triclinic;
    }
}

namespace {

/** Expect work to throw an OpenMMException whose message contains words. */
void expectError(const std::function<void ()>& work, const std::string& words) {
    try {
        work();
        ADD_FAILURE() << "no exception; expected one about \"" << words << "\"";
    }
    catch (const OpenMMException& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

} // namespace

TEST(PositivelySplitEwald, RejectsBadInputNamingTheSetting) {
    Scene scene(50, {0.3}, false, 5.0, 2);
    for (double tolerance : {0.0, -1e-3, 0.2, std::nan("")})
        expectError([&] { PositivelySplitEwald pse(tolerance); }, "out of range");
    expectError([&] { PositivelySplitEwald pse(1e-13); }, "below what double precision reaches");
    for (double splitting : {-1.0, std::nan(""), (double) INFINITY})
        expectError([&] { PositivelySplitEwald pse(1e-3, splitting); }, "splitting xi");
    PositivelySplitEwald pse(1e-6);
    Eigen::VectorXd u;
    expectError([&] { pse.multiply(Eigen::VectorXd::Zero(150), u); }, "setBlobs() before");
    expectError([&] { pse.setBlobs(scene.positions, scene.radii); }, "needs a periodic box");
    // A cutoff that the box cannot hold: the splitting given is too small, or the blobs too large.
    expectError([&] { PositivelySplitEwald(1e-6, 1.0).setBlobs(scene.positions, scene.radii, scene.box); }, "raise xi above");
    expectError([&] { pse.setBlobs({Vec3(), Vec3(1, 1, 1)}, {1.3, 0.3}, scene.box); }, "too small for blobs of radius 1.3");
    vector<double> manyRadii = scene.radii;
    for (int i = 0; i < 5; i++)
        manyRadii[i] = 0.1+0.05*i;
    expectError([&] { pse.setBlobs(scene.positions, manyRadii, scene.box); }, "at most 4");
    vector<double> badRadii = scene.radii;
    badRadii[7] = 0;
    expectError([&] { pse.setBlobs(scene.positions, badRadii, scene.box); }, "radius of blob 7");
    vector<Vec3> badPositions = scene.positions;
    badPositions[3][1] = std::nan("");
    expectError([&] { pse.setBlobs(badPositions, scene.radii, scene.box); }, "position of blob 3");
    // Over the memory budget: a small budget, or a grid of 10^13 points, refused before allocating.
    PositivelySplitEwald small(1e-6);
    small.setMemoryBudget(1e5);
    expectError([&] { small.setBlobs(scene.positions, scene.radii, scene.box); }, "memory budget");
    Vec3 huge[3];
    makeBox(false, 2000.0, huge);
    expectError([&] { PositivelySplitEwald(1e-6, 5.0).setBlobs({Vec3(), Vec3(5, 0, 0)}, {0.3, 0.3}, huge); }, "setMemoryBudget");
    pse.setBlobs(scene.positions, scene.radii, scene.box);
    expectError([&] { pse.multiply(Eigen::VectorXd::Zero(149), u); }, "3 per blob");
}
