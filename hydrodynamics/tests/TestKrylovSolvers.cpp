// The Krylov methods against the dense answer: conjugate gradients (plain and preconditioned) and
// Lanczos A^1/2 w on the RPY mobility of random overlapping blobs, whose matrix-free product is the
// dense matrix's; failure to converge is reported, not hidden.

#include "internal/CoupledResistanceMath.h"
#include "internal/KrylovSolvers.h"
#include "openmm/Vec3.h"
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>
#include <random>

using namespace RigidLangevinPlugin;
using OpenMM::Vec3;
using std::vector;

namespace {

/** 60 blobs of unequal radii in a 2 nm cube (many overlapping) and their dense mobility. */
struct Blobs {
    vector<Vec3> positions;
    vector<double> radii;
    Eigen::MatrixXd mobility;
    Blobs() {
        std::mt19937 random(3);
        std::uniform_real_distribution<double> uniform(0, 1);
        for (int i = 0; i < 60; i++) {
            positions.push_back(Vec3(2*uniform(random), 2*uniform(random), 2*uniform(random)));
            radii.push_back(0.1+0.15*uniform(random));
        }
        // The dense M, column by column from the matrix-free product (checked against the formula below).
        const int n = 3*positions.size();
        mobility.resize(n, n);
        for (int j = 0; j < n; j++) {
            Eigen::VectorXd e = Eigen::VectorXd::Unit(n, j), column;
            CoupledResistanceMath::mobilityProduct(positions, radii, e, column);
            mobility.col(j) = column;
        }
    }
    KrylovSolvers::Operator product() const {
        return [this] (const Eigen::VectorXd& in, Eigen::VectorXd& out) { CoupledResistanceMath::mobilityProduct(positions, radii, in, out); };
    }
};

} // namespace

TEST(KrylovSolvers, MobilityProductIsTheDenseMatrix) {
    // The product's matrix is the one the dense resistance factorises: with one blob per body and
    // no rotation, R's translational blocks are M^-1.
    Blobs blobs;
    const int n = blobs.positions.size();
    vector<int> owner(n);
    for (int i = 0; i < n; i++)
        owner[i] = i;
    Eigen::MatrixXd r = CoupledResistanceMath::resistance("test", blobs.positions, blobs.radii, owner, blobs.positions);
    Eigen::MatrixXd inverse = blobs.mobility.inverse();
    double worst = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            worst = std::max(worst, (r.block<3, 3>(6*i, 6*j)-inverse.block<3, 3>(3*i, 3*j)).cwiseAbs().maxCoeff());
    EXPECT_LT(worst, 1e-9*inverse.cwiseAbs().maxCoeff());
    EXPECT_LT((blobs.mobility-blobs.mobility.transpose()).cwiseAbs().maxCoeff(), 1e-15*blobs.mobility.cwiseAbs().maxCoeff());
}

TEST(KrylovSolvers, ConjugateGradientSolvesToItsTolerance) {
    Blobs blobs;
    const int n = blobs.mobility.rows();
    std::mt19937 random(5);
    std::normal_distribution<double> normal;
    Eigen::VectorXd b(n);
    for (int i = 0; i < n; i++)
        b[i] = normal(random);
    Eigen::VectorXd exact = blobs.mobility.llt().solve(b);
    // Jacobi (each blob's self block) against none: both converge; the answer is the dense one to
    // the tolerance times the condition number's share.
    KrylovSolvers::Operator none = [] (const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = in; };
    KrylovSolvers::Operator jacobi = [&] (const Eigen::VectorXd& in, Eigen::VectorXd& out) {
        out.resize(in.size());
        for (int i = 0; i < n; i++)
            out[i] = in[i]*6*M_PI*blobs.radii[i/3];
    };
    for (const KrylovSolvers::Operator* preconditioner : {&none, &jacobi}) {
        Eigen::VectorXd x;
        double residual;
        int iterations = KrylovSolvers::conjugateGradient(blobs.product(), *preconditioner, b, x, 1e-12, 1000, residual);
        EXPECT_GT(iterations, 0);
        EXPECT_LE(residual, 1e-12);
        EXPECT_LT((x-exact).norm(), 1e-9*exact.norm());
        // Started from the answer, it stops at once.
        EXPECT_EQ(KrylovSolvers::conjugateGradient(blobs.product(), *preconditioner, b, x, 1e-9, 1000, residual), 0);
    }
    // Too few iterations: reported, with the residual reached.
    Eigen::VectorXd x;
    double residual;
    EXPECT_EQ(KrylovSolvers::conjugateGradient(blobs.product(), none, b, x, 1e-12, 3, residual), -1);
    EXPECT_GT(residual, 1e-12);
}

TEST(KrylovSolvers, LanczosSquareRootIsTheMatrixSquareRoot) {
    Blobs blobs;
    const int n = blobs.mobility.rows();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(blobs.mobility);
    Eigen::MatrixXd root = eigen.eigenvectors()*eigen.eigenvalues().cwiseSqrt().asDiagonal()*eigen.eigenvectors().transpose();
    std::mt19937 random(8);
    std::normal_distribution<double> normal;
    Eigen::VectorXd w(n);
    for (int i = 0; i < n; i++)
        w[i] = normal(random);
    Eigen::VectorXd exact = root*w, result;
    double change;
    int iterations = KrylovSolvers::lanczosSquareRoot(blobs.product(), w, result, 1e-10, 200, change);
    EXPECT_GT(iterations, 2);
    EXPECT_LT(iterations, n);  // far fewer than the matrix's size
    EXPECT_LT((result-exact).norm(), 1e-8*exact.norm());
    EXPECT_EQ(KrylovSolvers::lanczosSquareRoot(blobs.product(), w, result, 1e-10, 3, change), -1);
    EXPECT_GT(change, 1e-10);
}
