#ifndef RIGID_LANGEVIN_PARALLEL_CHOLESKY_H_
#define RIGID_LANGEVIN_PARALLEL_CHOLESKY_H_

#include "ParallelFor.h"
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>

namespace RigidLangevinPlugin {

/**
 * The right-looking blocked Cholesky factorisation A = L L^T, in place in the lower triangle of a,
 * with its level-3 work spread over the threads of pool (none: the calling thread). Every numerical
 * step is Eigen's: its LLT on the diagonal blocks, its triangular solve on the panels below them,
 * its rank-k update and matrix product on the trailing matrix. The driver exists because Eigen's
 * own blocked LLT runs on one thread whatever it is built with (with OpenMP, Eigen parallelises
 * only plain matrix products, and its LLT uses triangular solves and rank-k updates); here the
 * update of each step, which holds almost all of the n^3/3 flops, is cut into column panels that
 * the threads share. On one thread it runs as fast as Eigen's LLT (about 47 GFlop/s with AVX2 and
 * FMA on one core of the development machine, an AMD EPYC; 86 GFlop/s on its two cores).
 *
 * blockSize is the width of a factorisation step and panelWidth that of a unit of work of the
 * trailing update (wider panels repack the step's columns less often; 512 was the fastest of
 * 256-1024 measured at n = 6000). The strict upper triangle is neither read nor written. Returns
 * false if a diagonal block is not positive definite, leaving a part-factorised.
 */
inline bool parallelCholeskyInPlace(Eigen::Ref<Eigen::MatrixXd> a, OpenMM::ThreadPool* pool, Eigen::Index blockSize = 256, Eigen::Index panelWidth = 512) {
    typedef Eigen::Index Index;
    const Index n = a.rows();
    for (Index k = 0; k < n; k += blockSize) {
        const Index size = std::min(blockSize, n-k);
        const Index rest = n-k-size;
        Eigen::Ref<Eigen::MatrixXd> diagonal = a.block(k, k, size, size);
        Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(diagonal);
        if (llt.info() != Eigen::Success)
            return false;
        if (rest == 0)
            break;
        // The panel below the diagonal block: A21 <- A21 L11^-T, in bands of rows.
        parallelFor(pool, (rest+blockSize-1)/blockSize, [&](Index band) {
            const Index row = band*blockSize;
            auto rows = a.block(k+size+row, k, std::min(blockSize, rest-row), size);
            diagonal.triangularView<Eigen::Lower>().transpose().solveInPlace<Eigen::OnTheRight>(rows);
        });
        // The trailing matrix: A22 <- A22 - A21 A21^T, lower triangle, one column panel per task
        // (the tallest first): a rank-k update of the panel's own diagonal block and a product for
        // the rows below it.
        parallelFor(pool, (rest+panelWidth-1)/panelWidth, [&](Index panel) {
            const Index column = panel*panelWidth;
            const Index width = std::min(panelWidth, rest-column);
            const Index first = k+size+column;
            const Index below = n-first-width;
            a.block(first, first, width, width).selfadjointView<Eigen::Lower>().rankUpdate(a.block(first, k, width, size), -1.0);
            if (below > 0)
                a.block(first+width, first, below, width).noalias() -= a.block(first+width, k, below, size)*a.block(first, k, width, size).transpose();
        });
    }
    return true;
}

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PARALLEL_CHOLESKY_H_*/
