// Timing helpers the hydrodynamics benchmarks share (benchmarks/README.md's conventions): blocks of
// calls timed in alternating pairs against a peer, the ratio's standard error over the pairs, wall
// and CPU seconds, peak memory, and a ParallelFor on OpenMM's ThreadPool as the CPU platform shares
// rows. Header-only: each benchmark is one translation unit.
#ifndef RIGID_LANGEVIN_BENCHMARK_TIMING_H_
#define RIGID_LANGEVIN_BENCHMARK_TIMING_H_

#include "internal/KrylovSolvers.h"
#include "openmm/internal/ThreadPool.h"
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <sys/resource.h>
#include <thread>
#include <vector>

namespace BenchmarkTiming {

namespace KrylovSolvers = RigidLangevinPlugin::KrylovSolvers;
using std::string;
using std::vector;

/** OPENMM_CPU_THREADS, or every core. */
inline int numThreads() {
    const char* setting = std::getenv("OPENMM_CPU_THREADS");
    if (setting != nullptr && std::atoi(setting) > 0)
        return std::atoi(setting);
    return std::max(1u, std::thread::hardware_concurrency());
}

/** A ParallelFor on pool's threads, each taking one contiguous range (as the CPU platform does). */
inline KrylovSolvers::ParallelFor poolParallel(OpenMM::ThreadPool& pool) {
    return [&pool] (int count, const std::function<void (int, int)>& task) {
        const int n = pool.getNumThreads();
        if (n == 1 || count < 2*n) {
            task(0, count);
            return;
        }
        pool.execute([&] (OpenMM::ThreadPool&, int t) { task((int) ((long long) count*t/n), (int) ((long long) count*(t+1)/n)); });
        pool.waitForThreads();
    };
}

inline double seconds(const std::function<void ()>& work) {
    auto start = std::chrono::steady_clock::now();
    work();
    return std::chrono::duration<double>(std::chrono::steady_clock::now()-start).count();
}

/** The process's CPU time (all threads), in seconds. */
inline double cpuSeconds() {
    timespec now;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return now.tv_sec+1e-9*now.tv_nsec;
}

/** Calls of work per block: enough to fill blockSeconds (at least one). */
inline int callsPerBlock(const std::function<void ()>& work, double blockSeconds) {
    const double once = seconds(work);
    return std::max(1, (int) std::ceil(blockSeconds/std::max(once, 1e-9)));
}

/** Wall-clock seconds per call over a block of calls; cpu, if given, gains the block's CPU seconds
 *  per call (all threads). */
inline double blockSecondsPerCall(const std::function<void ()>& work, int calls, vector<double>* cpu = nullptr) {
    const double cpuStart = cpuSeconds();
    const double wall = seconds([&] () {
        for (int k = 0; k < calls; k++)
            work();
    })/calls;
    if (cpu != nullptr)
        cpu->push_back((cpuSeconds()-cpuStart)/calls);
    return wall;
}

inline void meanAndError(const vector<double>& values, double& mean, double& error) {
    mean = 0;
    for (double v : values)
        mean += v/values.size();
    double variance = 0;
    for (double v : values)
        variance += (v-mean)*(v-mean)/std::max<size_t>(1, values.size()-1);
    error = std::sqrt(variance/values.size());
}

/** meanAndError of seconds, in milliseconds. */
inline void meanAndErrorMs(const vector<double>& values, double& mean, double& error) {
    meanAndError(values, mean, error);
    mean *= 1e3;
    error *= 1e3;
}

/** Times per call of a and b in alternating pairs of blocks (b first in every other pair); cpuA and
 *  cpuB, if given, gain each block's CPU seconds per call. */
inline void alternatingPairs(const std::function<void ()>& a, const std::function<void ()>& b, int pairs, double blockSeconds, vector<double>& timesA,
                      vector<double>& timesB, vector<double>* cpuA = nullptr, vector<double>* cpuB = nullptr) {
    const int callsA = callsPerBlock(a, blockSeconds), callsB = callsPerBlock(b, blockSeconds);
    for (int p = 0; p < pairs; p++) {
        if (p%2 == 0) {
            timesA.push_back(blockSecondsPerCall(a, callsA, cpuA));
            timesB.push_back(blockSecondsPerCall(b, callsB, cpuB));
        }
        else {
            timesB.push_back(blockSecondsPerCall(b, callsB, cpuB));
            timesA.push_back(blockSecondsPerCall(a, callsA, cpuA));
        }
    }
}

/** Mean and standard error of timesB[i]/timesA[i] over the pairs. */
inline void pairRatio(const vector<double>& timesA, const vector<double>& timesB, double& ratio, double& error) {
    vector<double> ratios;
    for (size_t i = 0; i < timesA.size(); i++)
        ratios.push_back(timesB[i]/timesA[i]);
    meanAndError(ratios, ratio, error);
}

inline double peakMiB() {
    struct rusage usage;
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss/1024.0;  // Linux reports KiB
}

/** "1,2,3" as numbers. */
template <class T>
vector<T> parseList(const string& text) {
    vector<T> values;
    std::stringstream stream(text);
    string item;
    while (std::getline(stream, item, ','))
        values.push_back((T) std::stod(item));
    return values;
}

/**
 * Read "--name value" pairs from argv[2] on, handing each value to its option's reader; an option
 * not among them is reported on standard error and returns false.
 */
inline bool readOptions(int argc, char** argv, const std::map<string, std::function<void (const char* value)>>& readers) {
    for (int i = 2; i+1 < argc; i += 2) {
        auto reader = readers.find(argv[i]);
        if (reader == readers.end()) {
            std::cerr << "unknown option " << argv[i] << std::endl;
            return false;
        }
        reader->second(argv[i+1]);
    }
    return true;
}

} // namespace BenchmarkTiming

#endif /*RIGID_LANGEVIN_BENCHMARK_TIMING_H_*/
