#ifndef RIGID_LANGEVIN_KRYLOV_SOLVERS_H_
#define RIGID_LANGEVIN_KRYLOV_SOLVERS_H_

#include "internal/windowsExportHydrodynamics.h"
#include <Eigen/Core>
#include <functional>

namespace RigidLangevinPlugin {

/**
 * Krylov methods for symmetric positive definite operators given only as products, for the
 * coupled friction of many bodies (HydrodynamicInteractions): preconditioned conjugate gradients
 * for A x = b, and Lanczos for A^1/2 w (the noise; Ando, Chow, Saad & Skolnick, J. Chem. Phys.
 * 137, 064106 (2012)). Both stop at a relative tolerance and report failure instead of returning
 * an unconverged answer; the caller names what did not converge.
 */
namespace KrylovSolvers {

/** out = A in (out is resized by the caller to the size of in). */
typedef std::function<void (const Eigen::VectorXd& in, Eigen::VectorXd& out)> Operator;

/** Run task(begin, end) over [0, count) split into ranges, possibly at once on several threads. */
typedef std::function<void (int count, const std::function<void (int begin, int end)>& task)> ParallelFor;

/** ParallelFor on the calling thread. */
OPENMM_EXPORT_HYDRODYNAMICS void sequentially(int count, const std::function<void (int begin, int end)>& task);

/**
 * Solve A x = b by conjugate gradients preconditioned by P (an approximation of A^-1, symmetric
 * positive definite), starting from x as given (resized to zero if its size differs), until
 * |b - A x| <= tolerance |b|.
 *
 * @return the number of iterations taken, or -1 if maxIterations were not enough (x then holds the
 *         last iterate, and residual its relative residual)
 */
OPENMM_EXPORT_HYDRODYNAMICS int conjugateGradient(const Operator& a, const Operator& preconditioner, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                                  double tolerance, int maxIterations, double& residual);

/**
 * result = A^1/2 w by the Lanczos process: with V the orthonormal Krylov basis of A from w and T
 * the tridiagonal V^T A V, result = |w| V T^1/2 e_1, stopped when two successive estimates (formed
 * every third iteration) differ by at most tolerance |result|. The basis is reorthogonalised fully (the number of iterations is
 * small and A's products dominate).
 *
 * @return the number of iterations (products with A) taken, or -1 if maxIterations were not enough
 */
OPENMM_EXPORT_HYDRODYNAMICS int lanczosSquareRoot(const Operator& a, const Eigen::VectorXd& w, Eigen::VectorXd& result, double tolerance, int maxIterations,
                                                  double& change);

} // namespace KrylovSolvers
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_KRYLOV_SOLVERS_H_*/
