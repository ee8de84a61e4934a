#ifndef RIGID_LANGEVIN_KRYLOV_SOLVERS_H_
#define RIGID_LANGEVIN_KRYLOV_SOLVERS_H_

#include "internal/windowsExportHydrodynamics.h"
#include <Eigen/Core>
#include <functional>
#include <string>

namespace RigidLangevinPlugin {

/**
 * Krylov methods for symmetric positive definite operators given only as products, for the
 * coupled friction of many bodies (HydrodynamicInteractions): preconditioned conjugate gradients
 * for A x = b, and Lanczos for A^1/2 w (the noise; Ando, Chow, Saad & Skolnick, J. Chem. Phys.
 * 137, 064106 (2012)). Both stop at a relative tolerance and report failure instead of returning
 * an unconverged answer: not converging, an operator (or preconditioner) that shows it is not
 * positive definite, and a product that is not finite each end the method at once with their own
 * Outcome; the caller names which solve failed (explain() says why).
 */
namespace KrylovSolvers {

/** out = A in (out is resized by the caller to the size of in). */
typedef std::function<void (const Eigen::VectorXd& in, Eigen::VectorXd& out)> Operator;

/** Run task(begin, end) over [0, count) split into ranges, possibly at once on several threads. */
typedef std::function<void (int count, const std::function<void (int begin, int end)>& task)> ParallelFor;

/** ParallelFor on the calling thread. */
OPENMM_EXPORT_HYDRODYNAMICS void sequentially(int count, const std::function<void (int begin, int end)>& task);

/** How a Krylov method ended. */
enum Outcome {
    /** It reached its tolerance: the answer holds. */
    Converged,
    /** maxIterations were not enough (the answer holds the last iterate). */
    NotConverged,
    /**
     * The operator is not positive definite: conjugate gradients met a direction p with
     * p^T A p <= 0, or Lanczos a tridiagonal T (a compression of A, whose eigenvalues lie within
     * A's) with an eigenvalue below -NegativeRitzTolerance times its largest. More iterations
     * cannot help, and any answer would be meaningless.
     */
    NotPositiveDefinite,
    /** Conjugate gradients' preconditioner is not positive definite: r^T P r <= 0 for a residual r. */
    PreconditionerNotPositiveDefinite,
    /** The right-hand side, or a product with the operator or preconditioner, is not finite (NaN or infinite). */
    NotFinite
};

/** What a Krylov method did: its outcome, the products with A it took, and the numbers that tell why. */
struct Result {
    Outcome outcome;
    /** The products with A taken. */
    int iterations;
    /** The tolerance and iteration limit asked for. */
    double tolerance;
    int maxIterations;
    /** Conjugate gradients and GMRES: the relative residual |b - A x|/|b| reached; Lanczos: the
     *  relative change of its estimate over its last three iterations (lanczosSquareRoot()). */
    double residual;
    /** NotPositiveDefinite and PreconditionerNotPositiveDefinite: the Rayleigh quotient that is not
     *  positive (p^T A p/p^T p, r^T P r/r^T r, or T's smallest eigenvalue), and the largest one of
     *  the same operator the method had seen (0 where none). */
    double curvature, largestCurvature;
};

/** T's eigenvalues above -this times its largest are taken as rounding errors of zero. */
const double NegativeRitzTolerance = 1e-10;
/** From this size of A on (300 entries, 100 blobs), the Lanczos estimate is formed after every
 *  product rather than every third: a product then costs more than the estimate's eigendecomposition,
 *  and a solve stops as soon as it may. */
const int EstimateEveryVector = 300;

/** Why a Krylov method ended as it did, in words with its numbers ("did not converge in ..."). */
OPENMM_EXPORT_HYDRODYNAMICS std::string explain(const Result& result);

/**
 * Solve A x = b by conjugate gradients preconditioned by P (an approximation of A^-1, symmetric
 * positive definite), starting from x as given (from zero, without a product, if its size differs), until
 * |b - A x| <= tolerance |b|. Every step checks p^T A p > 0 and r^T P r > 0, which hold for
 * every direction if A and P are symmetric positive definite, and that both are finite.
 * startProduct, if given, is A x for the x given (as scaledStart() returns it): one product fewer.
 */
OPENMM_EXPORT_HYDRODYNAMICS Result conjugateGradient(const Operator& a, const Operator& preconditioner, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                                     double tolerance, int maxIterations, const Eigen::VectorXd* startProduct = nullptr);

/**
 * Whether b settles a solve before any product: |b| not finite (report NotFinite) or b = 0 (x = 0,
 * Converged). Shared by conjugateGradient() and gmres(); report is their opening one.
 */
bool settledByRightHandSide(const Eigen::VectorXd& b, Eigen::VectorXd& x, Result& report);

/**
 * A warm start for conjugate gradients on A x = b from a guess g (the solution of a similar solve,
 * such as the last step's): start = alpha g, alpha = g^T b/(g^T A g), the multiple of g nearest the
 * solution in A's norm, so never farther from it than zero is (alpha = 0 where g^T A g is not
 * positive and finite, or g is empty or of another size). It handles a solution that changed sign or
 * scale. One product with A (none for an unusable g); startProduct = A start, for conjugateGradient().
 */
OPENMM_EXPORT_HYDRODYNAMICS void scaledStart(const Operator& a, const Eigen::VectorXd& guess, const Eigen::VectorXd& b, Eigen::VectorXd& start,
                                             Eigen::VectorXd& startProduct);

/**
 * result = A^1/2 w by the Lanczos process: with V the orthonormal Krylov basis of A from w and T
 * the tridiagonal V^T A V, result = |w| V T^1/2 e_1, stopped from the fourth iteration on when it
 * differs from the estimate of three iterations before by at most tolerance |result|. The estimate
 * is formed every iteration (every third for A smaller than EstimateEveryVector). The basis is reorthogonalised fully
 * (the number of iterations is small and A's products dominate). T's eigenvalues are checked at
 * every estimate (NotPositiveDefinite) and every product for finiteness.
 */
OPENMM_EXPORT_HYDRODYNAMICS Result lanczosSquareRoot(const Operator& a, const Eigen::VectorXd& w, Eigen::VectorXd& result, double tolerance,
                                                     int maxIterations);

/**
 * result = A^power w by the same Lanczos process (|w| V T^power e_1; lanczosSquareRoot() is power
 * 1/2). A negative power needs A positive definite: a Ritz value at or below zero is NotPositiveDefinite.
 * With A = L^-1 M L^-T for a factor L L^T = P of a preconditioner P of M, L^-T (A^-1/2 w) has
 * covariance M^-1 and L (A^1/2 w) covariance M for white noise w: the noise of a Krylov step in
 * the iterations of a preconditioned operator.
 */
OPENMM_EXPORT_HYDRODYNAMICS Result lanczosPower(const Operator& a, const Eigen::VectorXd& w, Eigen::VectorXd& result, double power, double tolerance,
                                                int maxIterations);

/**
 * Solve A x = b by GMRES(restart) with right preconditioning: the Krylov space of A P, P an
 * approximation of A^-1 (any nonsingular operator: A need not be symmetric or definite, as the
 * rigid bodies' saddle-point mobility problem is not), starting from x as given (resized to zero if
 * its size differs), until |b - A x| <= tolerance |b|. The residual is the true one at each
 * restart (one product each, none for a zero start). Outcomes: Converged, NotConverged (after maxIterations products with A), NotFinite.
 */
OPENMM_EXPORT_HYDRODYNAMICS Result gmres(const Operator& a, const Operator& preconditioner, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                         double tolerance, int maxIterations, int restart = 60);

} // namespace KrylovSolvers
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_KRYLOV_SOLVERS_H_*/
