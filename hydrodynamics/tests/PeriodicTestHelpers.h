#ifndef RIGID_LANGEVIN_PERIODIC_TEST_HELPERS_H_
#define RIGID_LANGEVIN_PERIODIC_TEST_HELPERS_H_

// Helpers shared by the tests of the periodic mobilities (TestPeriodicRotnePragerYamakawa.cpp,
// TestPositivelySplitEwald.cpp).

#include "internal/KrylovSolvers.h"
#include <functional>
#include <thread>
#include <vector>

namespace PeriodicTestHelpers {

/** Hasimoto's (1959) constant of the simple cubic lattice, to ten digits (Beenakker 1986 gives 2.837297). */
const double Hasimoto = 2.8372974795;

/** A ParallelFor on numThreads threads of its own, each given one contiguous range (as the CPU platform). */
inline RigidLangevinPlugin::KrylovSolvers::ParallelFor threads(int numThreads) {
    return [numThreads] (int count, const std::function<void (int, int)>& task) {
        std::vector<std::thread> workers;
        for (int t = 0; t < numThreads; t++)
            workers.emplace_back(task, (int) ((long long) count*t/numThreads), (int) ((long long) count*(t+1)/numThreads));
        for (std::thread& worker : workers)
            worker.join();
    };
}

} // namespace PeriodicTestHelpers

#endif /*RIGID_LANGEVIN_PERIODIC_TEST_HELPERS_H_*/
