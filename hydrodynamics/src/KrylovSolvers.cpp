#include "internal/KrylovSolvers.h"
#include <Eigen/Eigenvalues>
#include <cmath>

using namespace RigidLangevinPlugin;
using Eigen::VectorXd;

void KrylovSolvers::sequentially(int count, const std::function<void (int begin, int end)>& task) {
    task(0, count);
}

int KrylovSolvers::conjugateGradient(const Operator& a, const Operator& preconditioner, const VectorXd& b, VectorXd& x, double tolerance, int maxIterations,
                                     double& residual) {
    const int n = b.size();
    if (x.size() != n)
        x = VectorXd::Zero(n);
    const double bNorm = b.norm();
    if (bNorm == 0) {
        x.setZero();
        residual = 0;
        return 0;
    }
    VectorXd r(n), z(n), p(n), ap(n);
    a(x, ap);
    r = b-ap;
    residual = r.norm()/bNorm;
    if (residual <= tolerance)
        return 0;
    preconditioner(r, z);
    p = z;
    double rz = r.dot(z);
    for (int iteration = 1; iteration <= maxIterations; iteration++) {
        a(p, ap);
        double alpha = rz/p.dot(ap);
        x += alpha*p;
        r -= alpha*ap;
        residual = r.norm()/bNorm;
        if (residual <= tolerance)
            return iteration;
        preconditioner(r, z);
        double rzNext = r.dot(z);
        p = z+(rzNext/rz)*p;
        rz = rzNext;
    }
    return -1;
}

int KrylovSolvers::lanczosSquareRoot(const Operator& a, const VectorXd& w, VectorXd& result, double tolerance, int maxIterations, double& change) {
    const int n = w.size();
    const double wNorm = w.norm();
    result = VectorXd::Zero(n);
    change = 0;
    if (wNorm == 0)
        return 0;
    const int maxBasis = std::min(maxIterations, n);
    Eigen::MatrixXd basis(n, maxBasis);
    VectorXd alpha(maxBasis), beta(maxBasis);
    basis.col(0) = w/wNorm;
    VectorXd v(n), previous = VectorXd::Zero(n);
    for (int m = 0; m < maxBasis; m++) {
        a(basis.col(m), v);
        alpha[m] = basis.col(m).dot(v);
        v -= alpha[m]*basis.col(m);
        if (m > 0)
            v -= beta[m-1]*basis.col(m-1);
        // Full reorthogonalisation, twice: the basis stays orthonormal to rounding.
        for (int pass = 0; pass < 2; pass++)
            v -= basis.leftCols(m+1)*(basis.leftCols(m+1).transpose()*v);
        beta[m] = v.norm();
        const bool exhausted = (beta[m] <= 1e-14*std::abs(alpha[m]) || m+1 == n);
        if (!exhausted && m+1 < maxBasis && m%3 != 2) {
            // The estimate is formed every third vector: its eigendecomposition costs more than a
            // product with a small A.
            basis.col(m+1) = v/beta[m];
            continue;
        }
        // The estimate from the first m+1 vectors: |w| V T^1/2 e_1.
        Eigen::MatrixXd t = Eigen::MatrixXd::Zero(m+1, m+1);
        for (int i = 0; i <= m; i++) {
            t(i, i) = alpha[i];
            if (i < m)
                t(i, i+1) = t(i+1, i) = beta[i];
        }
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(t);
        VectorXd root = eigen.eigenvectors()*eigen.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal()*eigen.eigenvectors().row(0).transpose();
        result = wNorm*(basis.leftCols(m+1)*root);
        change = (result-previous).norm()/result.norm();
        // Converged, or the Krylov space is exhausted (then the answer is exact).
        if ((m > 2 && change <= tolerance) || exhausted)
            return m+1;
        previous = result;
        if (m+1 < maxBasis)
            basis.col(m+1) = v/beta[m];
    }
    return -1;
}
