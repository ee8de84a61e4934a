// The bead-model kernel. Built once per instruction set; RIGIDLANGEVIN_BEAD_KERNEL_ENTRY names the
// entry point of each build (see BeadResistanceKernel.h). Keep this file free of code shared with
// the rest of the library other than Eigen-free inline headers.
#include "BeadResistanceKernel.h"
#include "ParallelCholesky.h"
#include "ParallelFor.h"
#include "internal/RotnePragerYamakawa.h"
#include "openmm/internal/ThreadPool.h"
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <memory>
#include <new>

#ifndef RIGIDLANGEVIN_BEAD_KERNEL_ENTRY
#error "RIGIDLANGEVIN_BEAD_KERNEL_ENTRY must name the entry point of this build of the kernel"
#endif
#ifndef RIGIDLANGEVIN_CHOLESKY_ENTRY
#error "RIGIDLANGEVIN_CHOLESKY_ENTRY must name the Cholesky entry point of this build of the kernel"
#endif

// The AVX2 build hides every symbol (-fvisibility=hidden) but this one.
#if defined(__GNUC__)
#define BEAD_KERNEL_EXPORT __attribute__((visibility("default")))
#else
#define BEAD_KERNEL_EXPORT
#endif

using Eigen::Index;
using Eigen::MatrixXd;

namespace {

/**
 * The lower triangle of the 3N x 3N mobility matrix B (per unit viscosity): bead velocities are
 * B times bead forces. Self blocks are I/(6 pi a_i), the others the generalised RPY tensor.
 */
void assembleMobility(int numBeads, const double* positions, const double* radii, MatrixXd& b, OpenMM::ThreadPool* pool) {
    // Columns of 16 beads per task; the first columns hold the most blocks.
    const int chunk = 16;
    RigidLangevinPlugin::parallelFor(pool, (numBeads+chunk-1)/chunk, [&](Index task) {
        for (int j = task*chunk; j < std::min<int>(numBeads, (task+1)*chunk); j++) {
            const double* pj = positions+3*j;
            b.block<3, 3>(3*j, 3*j) = RigidLangevinPlugin::RotnePragerYamakawa::selfMobility(radii[j])*Eigen::Matrix3d::Identity();
            for (int i = j+1; i < numBeads; i++) {
                const double* pi = positions+3*i;
                double block[9];
                RigidLangevinPlugin::RotnePragerYamakawa::mobilityBlock(pj[0]-pi[0], pj[1]-pi[1], pj[2]-pi[2], radii[i], radii[j], block);
                for (int l = 0; l < 3; l++)
                    for (int k = 0; k < 3; k++)
                        b(3*i+k, 3*j+l) = block[3*k+l];
            }
        }
    });
}

/**
 * The 3N x 6 matrix P of rigid motions: bead i of a body moving with velocity v and angular
 * velocity w about the origin moves with v + w x d_i = v - skew(d_i) w, d_i its offset from the
 * origin, so its rows are [I, -skew(d_i)]. The total force and the torque about the origin of bead
 * forces f are P^T f, so Xi = P^T B^-1 P.
 */
MatrixXd rigidMotions(int numBeads, const double* positions, const double* origin) {
    MatrixXd p = MatrixXd::Zero(3*numBeads, 6);
    for (int i = 0; i < numBeads; i++) {
        const double dx = positions[3*i]-origin[0], dy = positions[3*i+1]-origin[1], dz = positions[3*i+2]-origin[2];
        p.block<3, 3>(3*i, 0).setIdentity();
        p.block<3, 3>(3*i, 3) << 0, dz, -dy,
                                 -dz, 0, dx,
                                 dy, -dx, 0;
    }
    return p;
}

void store(const Eigen::Matrix<double, 6, 6>& xi, double* resistance) {
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++)
            resistance[6*i+j] = xi(i, j);
}

} // namespace

extern "C" BEAD_KERNEL_EXPORT int RIGIDLANGEVIN_BEAD_KERNEL_ENTRY(int numBeads, const double* positions, const double* radii,
                                                                  const double* origin, int numThreads, double* resistance) {
    try {
        const Index n = 3*(Index) numBeads;
        // Threads pay off from a few hundred beads on; below that, start none.
        std::unique_ptr<OpenMM::ThreadPool> pool;
        if (numThreads > 1 && numBeads >= 200)
            pool.reset(new OpenMM::ThreadPool(numThreads));
        MatrixXd b(n, n);
        MatrixXd p = rigidMotions(numBeads, positions, origin);
        assembleMobility(numBeads, positions, radii, b, pool.get());
        // Xi = P^T B^-1 P = (L^-1 P)^T (L^-1 P): one triangular solve with six right-hand sides,
        // and the result is symmetric positive semidefinite by construction.
        if (RigidLangevinPlugin::parallelCholeskyInPlace(b, pool.get())) {
            b.triangularView<Eigen::Lower>().solveInPlace(p);
            Eigen::Matrix<double, 6, 6> xi = p.transpose()*p;
            store(xi, resistance);
            return BEAD_KERNEL_CHOLESKY;
        }
        // Rounding made B indefinite (nearly coincident beads): factor it again, with pivoting.
        assembleMobility(numBeads, positions, radii, b, pool.get());
        Eigen::LDLT<Eigen::Ref<MatrixXd>, Eigen::Lower> ldlt(b);
        if (ldlt.info() != Eigen::Success)
            return BEAD_KERNEL_FAILED;
        Eigen::Matrix<double, 6, 6> xi = p.transpose()*ldlt.solve(p);
        store(0.5*(xi+xi.transpose()), resistance);
        return BEAD_KERNEL_LDLT;
    }
    catch (const std::bad_alloc&) {
        return BEAD_KERNEL_OUT_OF_MEMORY;
    }
}

extern "C" BEAD_KERNEL_EXPORT int RIGIDLANGEVIN_CHOLESKY_ENTRY(int n, double* lower, int numThreads) {
    try {
        std::unique_ptr<OpenMM::ThreadPool> pool;
        if (numThreads > 1)
            pool.reset(new OpenMM::ThreadPool(numThreads));
        Eigen::Map<MatrixXd> a(lower, n, n);
        return (RigidLangevinPlugin::parallelCholeskyInPlace(a, pool.get()) ? BEAD_KERNEL_CHOLESKY : BEAD_KERNEL_FAILED);
    }
    catch (const std::bad_alloc&) {
        return BEAD_KERNEL_OUT_OF_MEMORY;
    }
}
