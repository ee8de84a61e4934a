#include "internal/BeadHydrodynamics.h"
#include "beadkernel/BeadResistanceKernel.h"
#include "internal/MessageFormat.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <numeric>
#include <thread>
#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::ResistanceMath;
using namespace RigidLangevinPlugin::MessageFormat;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::string;
using std::vector;

namespace {

/** Relative distance (and radius difference) below which two beads count as the same sphere. */
const double COINCIDENCE_TOLERANCE = 1e-10;

/** Physical memory in bytes, or 0 where the system does not say. */
double physicalMemory() {
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGESIZE)
    long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
    if (pages > 0 && pageSize > 0)
        return (double) pages*pageSize;
#endif
    return 0;
}

BeadResistanceKernel chooseKernel(BeadHydrodynamics::Kernel kernel) {
    if (kernel == BeadHydrodynamics::GenericKernel)
        return rigidLangevinBeadResistanceGeneric;
    bool avx2 = BeadHydrodynamics::isAVX2KernelAvailable();
    if (kernel == BeadHydrodynamics::AVX2Kernel && !avx2)
        throw OpenMMException("BeadHydrodynamics: the AVX2 kernel was asked for, but this build or this CPU does not have it");
#ifdef RIGIDLANGEVIN_HAVE_AVX2_KERNEL
    if (avx2)
        return rigidLangevinBeadResistanceAVX2;
#endif
    return rigidLangevinBeadResistanceGeneric;
}

} // namespace

bool BeadHydrodynamics::choleskyInPlace(int n, double* lower, int numThreads) {
    CholeskyKernel kernel = rigidLangevinCholeskyGeneric;
#ifdef RIGIDLANGEVIN_HAVE_AVX2_KERNEL
    if (isAVX2KernelAvailable())
        kernel = rigidLangevinCholeskyAVX2;
#endif
    const int result = kernel(n, lower, numThreads);
    if (result == BEAD_KERNEL_OUT_OF_MEMORY)
        throw OpenMMException("BeadHydrodynamics::choleskyInPlace: the factorisation of a "+std::to_string(n)+" x "+std::to_string(n)+
                              " matrix ran out of memory");
    return result == BEAD_KERNEL_CHOLESKY;
}

int BeadHydrodynamics::getNumThreads() {
    const char* setting = std::getenv("OPENMM_CPU_THREADS");
    if (setting != nullptr) {
        int threads = std::atoi(setting);
        if (threads > 0)
            return threads;
    }
    return std::max(1u, std::thread::hardware_concurrency());
}

bool BeadHydrodynamics::isAVX2KernelAvailable() {
#ifdef RIGIDLANGEVIN_HAVE_AVX2_KERNEL
    // GCC's and Clang's checks also ask the operating system whether it saves the AVX registers.
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return false;
#endif
}

void BeadHydrodynamics::validate(const string& caller, const vector<Vec3>& positions, const vector<double>& radii, const BeadNames& names) {
    auto name = [&](int i) { return (names ? names(i) : "bead "+std::to_string(i)); };
    if (positions.empty())
        throw OpenMMException(caller+": the bead model is empty; give at least one bead (a position and a radius)");
    if (positions.size() != radii.size())
        throw OpenMMException(caller+": got "+std::to_string(positions.size())+" bead positions but "+std::to_string(radii.size())+" radii; give one radius per bead");
    const int numBeads = positions.size();
    vector<double> keys(numBeads);
    for (int i = 0; i < numBeads; i++) {
        if (!std::isfinite(positions[i][0]) || !std::isfinite(positions[i][1]) || !std::isfinite(positions[i][2]))
            throw OpenMMException(caller+": "+name(i)+" has position "+describe(positions[i])+"; every coordinate must be a finite number (nm)");
        if (!(radii[i] > 0) || !std::isfinite(radii[i]))
            throw OpenMMException(caller+": "+name(i)+" has radius "+str(radii[i])+"; every radius must be positive and finite (nm)");
        keys[i] = positions[i][0];
    }
    std::pair<int, int> same = findCoincident(keys, 0, [&](int i, int j) { return positions[i]-positions[j]; }, radii);
    if (same.first >= 0) {
        int i = same.first, j = same.second;
        throw OpenMMException(caller+": "+(names ? names(i)+" and "+names(j) : "beads "+std::to_string(i)+" and "+std::to_string(j))+" are coincident (both at "+
                describe(positions[i])+" with radius "+str(radii[i])+"); the same sphere cannot be there twice (its mobility would be "
                "singular), so remove one of them");
    }
}

std::pair<int, int> BeadHydrodynamics::findCoincident(const vector<double>& keys, double period, const std::function<Vec3 (int, int)>& difference,
                                                      const vector<double>& radii) {
    const int n = keys.size();
    const double maxRadius = *std::max_element(radii.begin(), radii.end());
    vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return keys[a] < keys[b]; });
    // Each bead against those after it in key order within the tolerance; with a period the scan
    // runs on past the last key to the first ones again, a period further on.
    const double window = COINCIDENCE_TOLERANCE*maxRadius;
    for (int m = 0; m < n; m++)
        for (int l = m+1; l < (period > 0 ? m+n : n); l++) {
            int other = order[l%n];
            if (keys[other]+(l >= n ? period : 0.0)-keys[order[m]] > window)
                break;
            int i = std::min(order[m], other), j = std::max(order[m], other);
            double tolerance = COINCIDENCE_TOLERANCE*std::max(radii[i], radii[j]);
            Vec3 d = difference(i, j);
            if (std::sqrt(d.dot(d)) <= tolerance && std::abs(radii[i]-radii[j]) <= tolerance)
                return std::make_pair(i, j);
        }
    return std::make_pair(-1, -1);
}

Matrix6 BeadHydrodynamics::resistance(const string& caller, const vector<Vec3>& positions, const vector<double>& radii,
                                      const Vec3& origin, Kernel kernel) {
    validate(caller, positions, radii);
    BeadResistanceKernel solve = chooseKernel(kernel);
    const int numBeads = positions.size();
    double bytes = 8.0*(3.0*numBeads)*(3.0*numBeads);
    double available = physicalMemory();
    if (available > 0 && bytes > available)
        throw OpenMMException(caller+": a model of "+std::to_string(numBeads)+" beads needs "+std::to_string(bytes/(1 << 30))+" GiB for its 3N x 3N mobility matrix, more than this machine's "+
                std::to_string(available/(1 << 30))+" GiB; use fewer beads (for a shell model, larger beads)");
    vector<double> flat(3*numBeads);
    for (int i = 0; i < numBeads; i++)
        for (int k = 0; k < 3; k++)
            flat[3*i+k] = positions[i][k];
    double center[3] = {origin[0], origin[1], origin[2]};
    double values[36];
    int result = solve(numBeads, flat.data(), radii.data(), center, getNumThreads(), values);
    if (result == BEAD_KERNEL_OUT_OF_MEMORY)
        throw OpenMMException(caller+": out of memory: a model of "+std::to_string(numBeads)+" beads needs "+std::to_string(bytes/(1 << 30))+" GiB for its mobility matrix; use fewer beads");
    if (result == BEAD_KERNEL_FAILED)
        throw OpenMMException(caller+": the mobility matrix of the "+std::to_string(numBeads)+"-bead model could not be factorised; look for nearly coincident beads");
    if (result == BEAD_KERNEL_LDLT)
        std::cerr << "RigidLangevin warning: " << caller << ": the mobility matrix of the " << numBeads
                  << "-bead model is not numerically positive definite (nearly coincident beads?); solved it with a pivoted LDL^T factorisation instead" << std::endl;
    Matrix6 xi;
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++)
            xi(i, j) = values[6*i+j];
    return xi;
}
