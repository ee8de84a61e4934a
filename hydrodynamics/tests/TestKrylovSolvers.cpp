// The Krylov methods against the dense answer: conjugate gradients (plain and preconditioned) and
// Lanczos A^1/2 w on the RPY mobility of random overlapping blobs, whose matrix-free product is the
// dense matrix's; failure to converge, an operator or preconditioner that is not positive definite
// and products that are not finite are reported, each as such, not hidden.

#include "internal/CoupledResistanceMath.h"
#include "internal/KrylovSolvers.h"
#include "openmm/Vec3.h"
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
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
        KrylovSolvers::Result result = KrylovSolvers::conjugateGradient(blobs.product(), *preconditioner, b, x, 1e-12, 1000);
        EXPECT_EQ(result.outcome, KrylovSolvers::Converged);
        EXPECT_GT(result.iterations, 0);
        EXPECT_LE(result.residual, 1e-12);
        EXPECT_LT((x-exact).norm(), 1e-9*exact.norm());
        // Started from the answer, it stops at once.
        result = KrylovSolvers::conjugateGradient(blobs.product(), *preconditioner, b, x, 1e-9, 1000);
        EXPECT_EQ(result.outcome, KrylovSolvers::Converged);
        EXPECT_EQ(result.iterations, 0);
    }
    // Too few iterations: reported, with the residual reached.
    Eigen::VectorXd x;
    KrylovSolvers::Result result = KrylovSolvers::conjugateGradient(blobs.product(), none, b, x, 1e-12, 3);
    EXPECT_EQ(result.outcome, KrylovSolvers::NotConverged);
    EXPECT_EQ(result.iterations, 3);
    EXPECT_GT(result.residual, 1e-12);
    std::string why = KrylovSolvers::explain(result);
    EXPECT_NE(why.find("did not converge in 3 iterations"), std::string::npos) << why;
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
    KrylovSolvers::Result report = KrylovSolvers::lanczosSquareRoot(blobs.product(), w, result, 1e-10, 200);
    EXPECT_EQ(report.outcome, KrylovSolvers::Converged);
    EXPECT_GT(report.iterations, 2);
    EXPECT_LT(report.iterations, n);  // far fewer than the matrix's size
    EXPECT_LT((result-exact).norm(), 1e-8*exact.norm());
    report = KrylovSolvers::lanczosSquareRoot(blobs.product(), w, result, 1e-10, 3);
    EXPECT_EQ(report.outcome, KrylovSolvers::NotConverged);
    EXPECT_EQ(report.iterations, 3);
    EXPECT_GT(report.residual, 1e-10);
}

namespace {

/** Q diag(eigenvalues) Q^T, Q a random rotation, as an operator that counts its products. */
struct SymmetricMatrix {
    Eigen::MatrixXd matrix;
    int products = 0;
    explicit SymmetricMatrix(const Eigen::VectorXd& eigenvalues) {
        std::mt19937 random(12);
        std::normal_distribution<double> normal;
        const int n = eigenvalues.size();
        Eigen::MatrixXd g(n, n);
        for (int i = 0; i < n*n; i++)
            g.data()[i] = normal(random);
        Eigen::HouseholderQR<Eigen::MatrixXd> qr(g);
        Eigen::MatrixXd q = qr.householderQ();
        matrix = q*eigenvalues.asDiagonal()*q.transpose();
        matrix = (0.5*(matrix+matrix.transpose())).eval();
    }
    KrylovSolvers::Operator product() {
        return [this] (const Eigen::VectorXd& in, Eigen::VectorXd& out) { products++; out = matrix*in; };
    }
};

Eigen::VectorXd randomVector(int n, unsigned seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> normal;
    Eigen::VectorXd v(n);
    for (int i = 0; i < n; i++)
        v[i] = normal(random);
    return v;
}

const KrylovSolvers::Operator Identity = [] (const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = in; };

} // namespace

TEST(KrylovSolvers, IndefiniteOperatorsFailLoudly) {
    // Eigenvalues 0.5 ... 5 and one negative (-1, or -1e-3 of the largest, far above rounding):
    // conjugate gradients meet p^T A p < 0 and Lanczos a negative eigenvalue of T, each reported as
    // such, not as convergence (without the checks CG solves this indefinite system happily and
    // Lanczos returns the square root with the negative eigenvalue clipped) and not after
    // maxIterations.
    const int n = 40;
    for (double negative : {-1.0, -5e-3}) {
        SCOPED_TRACE("negative eigenvalue "+std::to_string(negative));
        Eigen::VectorXd eigenvalues = Eigen::VectorXd::LinSpaced(n, 0.5, 5);
        eigenvalues[n/2] = negative;
        SymmetricMatrix a(eigenvalues);
        Eigen::VectorXd b = randomVector(n, 4), x, result;
        KrylovSolvers::Result cg = KrylovSolvers::conjugateGradient(a.product(), Identity, b, x, 1e-12, 1000);
        EXPECT_EQ(cg.outcome, KrylovSolvers::NotPositiveDefinite);
        EXPECT_LE(cg.curvature, 0);
        EXPECT_GT(cg.largestCurvature, 0);
        EXPECT_LE(cg.iterations, n);
        std::string why = KrylovSolvers::explain(cg);
        EXPECT_NE(why.find("not positive definite"), std::string::npos) << why;
        KrylovSolvers::Result lanczos = KrylovSolvers::lanczosSquareRoot(a.product(), b, result, 1e-10, 1000);
        EXPECT_EQ(lanczos.outcome, KrylovSolvers::NotPositiveDefinite);
        EXPECT_LT(lanczos.curvature, -KrylovSolvers::NegativeRitzTolerance*lanczos.largestCurvature);
        EXPECT_GE(lanczos.curvature, negative-1e-9);  // T's eigenvalues lie within A's
        EXPECT_LE(lanczos.iterations, n);
        std::cout << "negative eigenvalue " << negative << ": CG stopped after " << cg.iterations << " iterations (p^T A p/p^T p " << cg.curvature
                  << "), Lanczos after " << lanczos.iterations << " (T's smallest eigenvalue " << lanczos.curvature << ")" << std::endl;
    }
    // Positive semidefinite, rank half: T's eigenvalues at zero are rounding, not indefiniteness,
    // and the square root is still right.
    Eigen::VectorXd eigenvalues = Eigen::VectorXd::LinSpaced(n, 0.5, 5);
    eigenvalues.head(n/2).setZero();
    SymmetricMatrix singular(eigenvalues);
    Eigen::VectorXd w = randomVector(n, 6), result;
    KrylovSolvers::Result report = KrylovSolvers::lanczosSquareRoot(singular.product(), w, result, 1e-10, 1000);
    EXPECT_EQ(report.outcome, KrylovSolvers::Converged);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(singular.matrix);
    Eigen::VectorXd exact = eigen.eigenvectors()*eigen.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal()*eigen.eigenvectors().transpose()*w;
    EXPECT_LT((result-exact).norm(), 1e-8*exact.norm());
}

TEST(KrylovSolvers, LanczosInverseSquareRootIsTheMatrixInverseSquareRoot) {
    // The power -1/2 of a well-conditioned operator (eigenvalues 0.5 to 5) against the dense one; a
    // semidefinite operator has no inverse square root, and is refused rather than clipped.
    const int n = 60;
    SymmetricMatrix a(Eigen::VectorXd::LinSpaced(n, 0.5, 5));
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(a.matrix);
    Eigen::VectorXd w = randomVector(n, 9), result;
    Eigen::VectorXd exact = eigen.eigenvectors()*eigen.eigenvalues().cwiseSqrt().cwiseInverse().asDiagonal()*eigen.eigenvectors().transpose()*w;
    KrylovSolvers::Result report = KrylovSolvers::lanczosPower(a.product(), w, result, -0.5, 1e-10, 200);
    EXPECT_EQ(report.outcome, KrylovSolvers::Converged);
    EXPECT_LT(report.iterations, n);
    EXPECT_LT((result-exact).norm(), 1e-8*exact.norm());
    Eigen::VectorXd eigenvalues = Eigen::VectorXd::LinSpaced(n, 0.5, 5);
    eigenvalues.head(n/2).setZero();
    SymmetricMatrix singular(eigenvalues);
    EXPECT_EQ(KrylovSolvers::lanczosPower(singular.product(), w, result, -0.5, 1e-10, 1000).outcome, KrylovSolvers::NotPositiveDefinite);
}

TEST(KrylovSolvers, IndefinitePreconditionerAndNonFiniteProductsFailAtOnce) {
    const int n = 40;
    SymmetricMatrix a(Eigen::VectorXd::LinSpaced(n, 0.5, 5));
    Eigen::VectorXd b = randomVector(n, 9), x, result;
    // A preconditioner that is not positive definite: r^T P r < 0 before the first iteration.
    KrylovSolvers::Operator negative = [] (const Eigen::VectorXd& in, Eigen::VectorXd& out) { out = -in; };
    KrylovSolvers::Result report = KrylovSolvers::conjugateGradient(a.product(), negative, b, x, 1e-12, 1000);
    EXPECT_EQ(report.outcome, KrylovSolvers::PreconditionerNotPositiveDefinite);
    EXPECT_NEAR(report.curvature, -1, 1e-12);
    EXPECT_EQ(report.iterations, 0);
    // NaN in a product, or in the right-hand side: stopped at the first product, or before any.
    int products = 0;
    KrylovSolvers::Operator broken = [&] (const Eigen::VectorXd& in, Eigen::VectorXd& out) {
        products++;
        out = in;
        out[3] = std::nan("");
    };
    report = KrylovSolvers::conjugateGradient(broken, Identity, b, x, 1e-12, 1000);
    EXPECT_EQ(report.outcome, KrylovSolvers::NotFinite);
    EXPECT_EQ(products, 1);
    report = KrylovSolvers::lanczosSquareRoot(broken, b, result, 1e-10, 1000);
    EXPECT_EQ(report.outcome, KrylovSolvers::NotFinite);
    EXPECT_EQ(products, 2);
    Eigen::VectorXd nan = b;
    nan[0] = std::nan("");
    x.resize(0);
    a.products = 0;
    EXPECT_EQ(KrylovSolvers::conjugateGradient(a.product(), Identity, nan, x, 1e-12, 1000).outcome, KrylovSolvers::NotFinite);
    EXPECT_EQ(KrylovSolvers::lanczosSquareRoot(a.product(), nan, result, 1e-10, 1000).outcome, KrylovSolvers::NotFinite);
    EXPECT_EQ(a.products, 0);
    std::string why = KrylovSolvers::explain(report);
    EXPECT_NE(why.find("not finite"), std::string::npos) << why;
}
