#ifndef RIGID_LANGEVIN_BEAD_RESISTANCE_KERNEL_H_
#define RIGID_LANGEVIN_BEAD_RESISTANCE_KERNEL_H_

/**
 * The dense kernel that turns a bead model into its resistance tensor. It is compiled twice: for
 * baseline x86-64 into the RigidLangevin library, and with AVX2 and FMA into a small library of
 * its own (RigidLangevinBeadKernelAVX2) that exports nothing but its entry point, so that none of
 * its Eigen or standard-library code can stand in for the baseline copies on a machine without
 * AVX2. BeadHydrodynamics.cpp picks one at run time. The interface is plain C for the same reason.
 */

/** What a kernel call returns. */
enum BeadKernelResult {
    /** Solved with the Cholesky factorisation of the mobility matrix. */
    BEAD_KERNEL_CHOLESKY = 0,
    /** The mobility matrix was not numerically positive definite; solved with a pivoted LDL^T. */
    BEAD_KERNEL_LDLT = 1,
    /** Not even the LDL^T factorisation succeeded; the output is undefined. */
    BEAD_KERNEL_FAILED = 2,
    /** The 3N x 3N mobility matrix did not fit in memory. */
    BEAD_KERNEL_OUT_OF_MEMORY = 3
};

extern "C" {

/**
 * The resistance tensor per unit viscosity of a rigid assembly of beads.
 *
 * numBeads     the number N of beads (> 0)
 * positions    3N coordinates (nm): x, y, z of bead 0, then of bead 1, ...
 * radii        N radii (nm), all positive
 * origin       3 coordinates of the point the tensor refers to
 * numThreads   how many threads to use (1: only the calling thread)
 * resistance   out: 36 values, row-major, in the convention of ResistanceTensor
 *
 * The inputs must have been checked (finite, positive radii, no two beads coincident). Returns a
 * BeadKernelResult.
 */
typedef int (*BeadResistanceKernel)(int numBeads, const double* positions, const double* radii,
                                    const double* origin, int numThreads, double* resistance);

int rigidLangevinBeadResistanceGeneric(int numBeads, const double* positions, const double* radii,
                                       const double* origin, int numThreads, double* resistance);

int rigidLangevinBeadResistanceAVX2(int numBeads, const double* positions, const double* radii,
                                    const double* origin, int numThreads, double* resistance);

/**
 * The Cholesky factorisation A = L L^T in place in the lower triangle of the n x n column-major
 * matrix lower (its strict upper triangle neither read nor written), blocked, its updates shared
 * among numThreads threads (parallelCholeskyInPlace). Returns BEAD_KERNEL_CHOLESKY,
 * BEAD_KERNEL_FAILED where A is not numerically positive definite, or BEAD_KERNEL_OUT_OF_MEMORY.
 */
typedef int (*CholeskyKernel)(int n, double* lower, int numThreads);

int rigidLangevinCholeskyGeneric(int n, double* lower, int numThreads);

int rigidLangevinCholeskyAVX2(int n, double* lower, int numThreads);

}

#endif /*RIGID_LANGEVIN_BEAD_RESISTANCE_KERNEL_H_*/
