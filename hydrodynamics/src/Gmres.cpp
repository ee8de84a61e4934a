// GMRES with right preconditioning, restarted (KrylovSolvers::gmres): for the rigid bodies'
// saddle-point mobility problem, which is symmetric but indefinite, so that conjugate gradients
// and MINRES with the bodies' own (indefinite) blocks as preconditioner do not apply.

#include "internal/KrylovSolvers.h"
#include <Eigen/Core>
#include <cmath>
#include <vector>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::KrylovSolvers;
using Eigen::VectorXd;

namespace {

/** A Givens rotation (c, s) that zeroes b in (a, b). */
void givens(double a, double b, double& c, double& s) {
    double r = std::hypot(a, b);
    c = (r == 0 ? 1.0 : a/r);
    s = (r == 0 ? 0.0 : b/r);
}

/**
 * One cycle of GMRES from x, whose residual is r (not zero): at most `restart` products, or fewer if
 * the residual estimate reaches target (absolute) or the products reach maxProducts. Returns false
 * if a vector stopped being finite.
 */
bool gmresCycle(const Operator& a, const Operator& preconditioner, const VectorXd& r, VectorXd& x, double target, int restart, int maxProducts,
                int& products) {
    const double beta = r.norm();
    std::vector<VectorXd> v(1, r/beta), z;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(restart+1, restart);
    VectorXd g = VectorXd::Zero(restart+1), cs(restart), sn(restart);
    g[0] = beta;
    int k = 0;
    for (; k < restart && products < maxProducts; k++) {
        VectorXd zk, w;
        preconditioner(v[k], zk);
        a(zk, w);
        products++;
        z.push_back(zk);
        for (int i = 0; i <= k; i++) {  // modified Gram-Schmidt
            h(i, k) = v[i].dot(w);
            w -= h(i, k)*v[i];
        }
        h(k+1, k) = w.norm();
        if (!std::isfinite(h(k+1, k)))
            return false;
        v.push_back(h(k+1, k) > 0 ? VectorXd(w/h(k+1, k)) : w);
        for (int i = 0; i < k; i++) {
            double t = cs[i]*h(i, k)+sn[i]*h(i+1, k);
            h(i+1, k) = -sn[i]*h(i, k)+cs[i]*h(i+1, k);
            h(i, k) = t;
        }
        givens(h(k, k), h(k+1, k), cs[k], sn[k]);
        h(k, k) = cs[k]*h(k, k)+sn[k]*h(k+1, k);
        h(k+1, k) = 0;
        g[k+1] = -sn[k]*g[k];
        g[k] = cs[k]*g[k];
        if (std::abs(g[k+1]) <= target || h(k, k) == 0) {
            k++;
            break;
        }
    }
    // x += Z y with H y = g (upper triangular).
    VectorXd y = h.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
    for (int i = 0; i < k; i++)
        x += y[i]*z[i];
    return x.allFinite();
}

} // namespace

Result KrylovSolvers::gmres(const Operator& a, const Operator& preconditioner, const VectorXd& b, VectorXd& x, double tolerance, int maxIterations,
                            int restart) {
    Result report = {Converged, 0, tolerance, maxIterations, 0, 0, 0};
    if (x.size() != b.size())
        x = VectorXd::Zero(b.size());
    if (settledByRightHandSide(b, x, report))
        return report;
    const double norm = b.norm();
    VectorXd ax;
    while (true) {
        // The true residual at each restart, not the cycle's estimate (from a zero start, b itself:
        // no product).
        if (report.iterations == 0 && x.isZero(0))
            ax = VectorXd::Zero(b.size());
        else
            a(x, ax);
        const VectorXd r = b-ax;
        report.residual = r.norm()/norm;
        if (!std::isfinite(report.residual)) {
            report.outcome = NotFinite;
            return report;
        }
        if (report.residual <= tolerance)
            return report;
        if (report.iterations >= maxIterations) {
            report.outcome = NotConverged;
            return report;
        }
        if (!gmresCycle(a, preconditioner, r, x, tolerance*norm, restart, maxIterations, report.iterations)) {
            report.outcome = NotFinite;
            return report;
        }
    }
}
