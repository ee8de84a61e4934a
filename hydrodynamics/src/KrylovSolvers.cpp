#include "internal/KrylovSolvers.h"
#include "internal/MessageFormat.h"
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::KrylovSolvers;
using namespace RigidLangevinPlugin::MessageFormat;
using Eigen::VectorXd;

namespace {

std::string iterations(int count) {
    return std::to_string(count)+(count == 1 ? " iteration" : " iterations");
}

/** Whether r^T P r (rz) is usable; if not, the report says why. */
bool checkPreconditioned(const VectorXd& r, double rz, double& largest, Result& report) {
    if (!std::isfinite(rz)) {
        report.outcome = NotFinite;
        return false;
    }
    double quotient = rz/r.squaredNorm();
    if (!(rz > 0)) {
        report.outcome = PreconditionerNotPositiveDefinite;
        report.curvature = quotient;
        report.largestCurvature = largest;
        return false;
    }
    largest = std::max(largest, quotient);
    return true;
}

} // namespace

void KrylovSolvers::sequentially(int count, const std::function<void (int begin, int end)>& task) {
    task(0, count);
}

std::string KrylovSolvers::explain(const Result& result) {
    const std::string error = " (relative error "+str(result.residual)+", asked for "+str(result.tolerance)+")";
    const std::string after = " after "+iterations(result.iterations);
    const std::string largest = (result.largestCurvature > 0 ? "; the largest seen is "+str(result.largestCurvature) : "");
    switch (result.outcome) {
    case Converged:
        return "converged in "+iterations(result.iterations)+error;
    case NotConverged:
        return "did not converge in "+iterations(result.iterations)+error;
    case NotPositiveDefinite:
        return "found the operator not positive definite"+after+": a Rayleigh quotient of it on its Krylov space is "+str(result.curvature)+
               " (all are positive for a positive definite operator"+largest+")";
    case PreconditionerNotPositiveDefinite:
        return "found the preconditioner P not positive definite"+after+": r^T P r/r^T r is "+str(result.curvature)+" for a residual r"+
               " (positive for a positive definite P"+largest+")";
    case NotFinite:
        return "met a right-hand side or a product that is not finite (NaN or infinite)"+after;
    }
    return "ended in an unknown way";
}

void KrylovSolvers::scaledStart(const Operator& a, const VectorXd& guess, const VectorXd& b, VectorXd& start, VectorXd& startProduct) {
    start = VectorXd::Zero(b.size());
    startProduct = VectorXd::Zero(b.size());
    if (guess.size() != b.size() || guess.size() == 0)
        return;
    VectorXd product;
    a(guess, product);
    const double curvature = guess.dot(product), alpha = guess.dot(b)/curvature;
    if (!(curvature > 0) || !std::isfinite(alpha))
        return;
    start = alpha*guess;
    startProduct = alpha*product;
}

bool KrylovSolvers::settledByRightHandSide(const VectorXd& b, VectorXd& x, Result& report) {
    const double norm = b.norm();
    if (!std::isfinite(norm))
        report.outcome = NotFinite;
    else if (norm == 0)
        x.setZero();
    return !std::isfinite(norm) || norm == 0;
}

Result KrylovSolvers::conjugateGradient(const Operator& a, const Operator& preconditioner, const VectorXd& b, VectorXd& x, double tolerance, int maxIterations,
                                        const VectorXd* startProduct) {
    Result report = {Converged, 0, tolerance, maxIterations, 0, 0, 0};
    const int n = b.size();
    // From zero the start's product is zero: no product is spent on it.
    const bool fromZero = (x.size() != n);
    const bool productGiven = (startProduct != nullptr && startProduct->size() == n && !fromZero);
    if (fromZero)
        x = VectorXd::Zero(n);
    if (settledByRightHandSide(b, x, report))
        return report;
    const double bNorm = b.norm();
    VectorXd r(n), z(n), p(n), ap(n);
    if (productGiven)
        ap = *startProduct;
    else if (fromZero)
        ap.setZero();
    else
        a(x, ap);
    r = b-ap;
    report.residual = r.norm()/bNorm;
    if (!std::isfinite(report.residual)) {
        report.outcome = NotFinite;
        return report;
    }
    if (report.residual <= tolerance)
        return report;
    double largestA = 0, largestP = 0;
    preconditioner(r, z);
    double rz = r.dot(z);
    if (!checkPreconditioned(r, rz, largestP, report))
        return report;
    p = z;
    for (int iteration = 1; iteration <= maxIterations; iteration++) {
        a(p, ap);
        report.iterations = iteration;
        // A positive definite A has p^T A p > 0 for every p: anything else is no rounding error
        // that more iterations would cure.
        const double pap = p.dot(ap);
        if (!std::isfinite(pap)) {
            report.outcome = NotFinite;
            return report;
        }
        if (!(pap > 0)) {
            report.outcome = NotPositiveDefinite;
            report.curvature = pap/p.squaredNorm();
            report.largestCurvature = largestA;
            return report;
        }
        largestA = std::max(largestA, pap/p.squaredNorm());
        double alpha = rz/pap;
        x += alpha*p;
        r -= alpha*ap;
        report.residual = r.norm()/bNorm;
        if (report.residual <= tolerance)
            return report;
        preconditioner(r, z);
        double rzNext = r.dot(z);
        if (!checkPreconditioned(r, rzNext, largestP, report))
            return report;
        p = z+(rzNext/rz)*p;
        rz = rzNext;
    }
    report.outcome = NotConverged;
    return report;
}

Result KrylovSolvers::lanczosSquareRoot(const Operator& a, const VectorXd& w, VectorXd& result, double tolerance, int maxIterations) {
    return lanczosPower(a, w, result, 0.5, tolerance, maxIterations);
}

Result KrylovSolvers::lanczosPower(const Operator& a, const VectorXd& w, VectorXd& result, double power, double tolerance, int maxIterations) {
    Result report = {Converged, 0, tolerance, maxIterations, 0, 0, 0};
    const int n = w.size();
    const double wNorm = w.norm();
    result = VectorXd::Zero(n);
    if (!std::isfinite(wNorm)) {
        report.outcome = NotFinite;
        return report;
    }
    if (wNorm == 0)
        return report;
    const int maxBasis = std::min(maxIterations, n);
    Eigen::MatrixXd basis(n, maxBasis);
    VectorXd alpha(maxBasis), beta(maxBasis);
    basis.col(0) = w/wNorm;
    VectorXd v(n);
    // The estimates of the last three iterations, the one of iteration m in slot m % 3 (zero before any).
    std::vector<VectorXd> recent(3, VectorXd::Zero(n));
    for (int m = 0; m < maxBasis; m++) {
        a(basis.col(m), v);
        report.iterations = m+1;
        alpha[m] = basis.col(m).dot(v);
        v -= alpha[m]*basis.col(m);
        if (m > 0)
            v -= beta[m-1]*basis.col(m-1);
        // Full reorthogonalisation, twice: the basis stays orthonormal to rounding.
        for (int pass = 0; pass < 2; pass++)
            v -= basis.leftCols(m+1)*(basis.leftCols(m+1).transpose()*v);
        beta[m] = v.norm();
        if (!std::isfinite(alpha[m]) || !std::isfinite(beta[m])) {
            report.outcome = NotFinite;
            return report;
        }
        const bool exhausted = (beta[m] <= 1e-14*std::abs(alpha[m]) || m+1 == n);
        if (!exhausted && m+1 < maxBasis && n < EstimateEveryVector && m%3 != 2) {
            // For a small A the estimate is formed every third vector: its eigendecomposition costs
            // more than a product.
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
        // T's eigenvalues lie within A's: one significantly below zero means A is not positive
        // definite, and its square root would be a fiction. Those within rounding of zero are zero.
        const double smallest = eigen.eigenvalues()[0], largest = eigen.eigenvalues()[m];
        if (!(largest > 0) || smallest < -NegativeRitzTolerance*largest || (power < 0 && !(smallest > 0))) {
            report.outcome = NotPositiveDefinite;
            report.curvature = smallest;
            report.largestCurvature = largest;
            return report;
        }
        const VectorXd values = eigen.eigenvalues().cwiseMax(0);
        const VectorXd powers = (power == 0.5 ? VectorXd(values.cwiseSqrt()) : VectorXd(values.array().pow(power).matrix()));
        VectorXd root = eigen.eigenvectors()*powers.asDiagonal()*eigen.eigenvectors().row(0).transpose();
        result = wNorm*(basis.leftCols(m+1)*root);
        // The change over three iterations: over one, it would stop early (the estimates' error
        // shrinks slowly once their change is small: the boomerang suspensions' Brownian steps erred
        // by 2 to 10 times the tolerance).
        report.residual = (result-recent[m%3]).norm()/result.norm();
        // Converged, or the Krylov space is exhausted (then the answer is exact).
        if ((m > 2 && report.residual <= tolerance) || exhausted)
            return report;
        recent[m%3] = result;
        if (m+1 < maxBasis)
            basis.col(m+1) = v/beta[m];
    }
    report.outcome = NotConverged;
    return report;
}
