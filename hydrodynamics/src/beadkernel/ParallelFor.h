#ifndef RIGID_LANGEVIN_PARALLEL_FOR_H_
#define RIGID_LANGEVIN_PARALLEL_FOR_H_

#include "openmm/internal/ThreadPool.h"
#include <Eigen/Core>
#include <atomic>
#include <exception>

namespace RigidLangevinPlugin {

/**
 * Run task(i) for every i in [0, count) on the threads of pool, or in the calling thread if pool is
 * null. Indices are handed out in increasing order as threads become free (as OpenMM's CPU
 * kernels share work), so put the largest tasks first. An exception thrown by a task is rethrown
 * here once all threads have finished.
 *
 * OpenMM's ThreadPool rather than OpenMP: GCC's OpenMP runtime keeps its threads after a parallel
 * region, and a process that forks after using them (Python's multiprocessing does) hangs in the
 * child's first parallel region. A pool that lives for one computation leaves no threads behind.
 */
template <class Task>
void parallelFor(OpenMM::ThreadPool* pool, Eigen::Index count, const Task& task) {
    if (pool == nullptr) {
        for (Eigen::Index i = 0; i < count; i++)
            task(i);
        return;
    }
    std::atomic<Eigen::Index> next(0);
    std::exception_ptr failure;
    std::atomic<bool> failed(false);
    pool->execute([&](OpenMM::ThreadPool&, int) {
        try {
            for (Eigen::Index i = next++; i < count && !failed; i = next++)
                task(i);
        }
        catch (...) {
            if (!failed.exchange(true))
                failure = std::current_exception();
        }
    });
    pool->waitForThreads();
    if (failure)
        std::rethrow_exception(failure);
}

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PARALLEL_FOR_H_*/
