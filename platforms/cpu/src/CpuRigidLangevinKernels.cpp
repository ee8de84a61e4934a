#include "CpuRigidLangevinKernels.h"
#include "CpuStickyDipolePairs.h"
#include "internal/StickyDipoleForceImpl.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/OSRngSeed.h"
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <istream>
#include <ostream>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

// The host step's one instantiation for the CPU platform (see CpuRigidLangevinKernels.h).
template class RigidLangevinPlugin::HostRigidLangevinStepKernel<ZigguratGaussianRandom>;

namespace {

/**
 * The seed of one chunk's random stream: a 32-bit mix of the integrator's seed and the chunk
 * index (MurmurHash3's finalizer), so that neighbouring chunks start far apart.
 */
uint32_t chunkSeed(uint32_t seed, int chunk) {
    uint32_t h = seed ^ (0x9e3779b9u*(uint32_t) (chunk+1));
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

} // namespace

void CpuIntegrateRigidLangevinStepKernel::initialize(const System& system, const RigidBodyIntegrator& integrator) {
    RigidLangevinStepKernelBase::initialize(system, integrator);
    numBodies = model->getNumBodies();
    int numChunks = std::max(1, std::min(numBodies, (int) MaxChunks));
    // A seed of 0 means a unique one: pick it once, then derive every chunk's from it.
    uint32_t seed = (integrator.getRandomNumberSeed() == 0 ? (uint32_t) osrngseed() : (uint32_t) integrator.getRandomNumberSeed());
    std::vector<std::unique_ptr<RandomStream> > streams;
    for (int c = 0; c < numChunks; c++)
        streams.emplace_back(new RandomStream(chunkSeed(seed, c)));
    setChunks(numBodies, std::move(streams));
}

void CpuIntegrateRigidLangevinStepKernel::parallelFor(int count, const std::function<void (int, int)>& task) {
    parallelForOn(threads, count, task);
}

void CpuIntegrateRigidLangevinStepKernel::forEachChunk(const std::function<void (int, int, int)>& task) {
    if (numBodies < MinBodiesForThreads || threads.getNumThreads() == 1) {
        // Waking the threads would cost more than the work; the chunks (and so the results) are the same.
        HostRigidLangevinStepKernel<ZigguratGaussianRandom>::forEachChunk(task);
        return;
    }
    int numChunks = getNumChunks();
    threads.execute([&] (ThreadPool& pool, int threadIndex) {
        for (int c = threadIndex; c < numChunks; c += pool.getNumThreads())
            task(c, chunkBegin(c), chunkBegin(c+1));
    });
    threads.waitForThreads();
}

void CpuIntegrateRigidLangevinStepKernel::createRandomCheckpoint(std::ostream& stream) {
    int numStreams = random.size();
    stream.write((char*) &numStreams, sizeof(int));
    for (auto& r : random)
        r->random.createCheckpoint(stream);
}

void CpuIntegrateRigidLangevinStepKernel::loadRandomCheckpoint(std::istream& stream) {
    int numStreams;
    stream.read((char*) &numStreams, sizeof(int));
    if (!stream || numStreams != (int) random.size())
        throw OpenMMException(model->getIntegratorName()+": the checkpoint was not written by the CPU platform for this System "
                              "(it has "+std::to_string(numStreams)+" random number streams, this context "+std::to_string(random.size())+")");
    for (auto& r : random)
        r->random.loadCheckpoint(stream);
}

double CpuCalcStickyDipoleForceKernel::computePairs(long long begin, long long end, const std::vector<Vec3>& sitePositions,
                                                   const std::vector<SiteFrame>& frames, const Vec3* box, std::vector<Vec3>& siteForces,
                                                   std::vector<Vec3>& torques) {
    const int lanes = StickyPairBlock::Lanes;
    double boxValues[9];
    StickyPairSettings settings;
    settings.box = nullptr;
    if (method == StickyDipoleForce::CutoffPeriodic) {
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++)
                boxValues[3*k+c] = box[k][c];
        settings.box = boxValues;
    }
    settings.useCutoff = (method != StickyDipoleForce::NoCutoff);
    settings.useSwitching = (settings.useCutoff && useSwitching);
    settings.cutoff = cutoff;
    settings.switchingDistance = switchingDistance;
    settings.kappa = kappa;
    auto put = [] (double (*target)[lanes], int lane, const Vec3& v) {
        for (int c = 0; c < 3; c++)
            target[c][lane] = v[c];
    };
    auto putParameters = [] (double (*target)[lanes], int lane, const StickyDipoleForce::SiteParameters& p) {
        std::vector<double> values = StickyDipoleForceImpl::parameterValues(p);
        for (int k = 0; k < StickyDipoleForceImpl::NumParameterValues; k++)
            target[k][lane] = values[k];
    };
    StickyPairBlock block;
    StickyPairResults results;
    // Where all sites share their parameters (a neat liquid), every lane has the same: fill them once.
    bool uniform = sharedParameters;
    if (uniform)
        for (int lane = 0; lane < lanes; lane++) {
            putParameters(block.pi, lane, parameters[0]);
            putParameters(block.pj, lane, parameters[0]);
        }
    double energy = 0;
    for (long long first = begin; first < end; first += lanes) {
        int used = (int) std::min<long long>(lanes, end-first);
        for (int lane = 0; lane < lanes; lane++) {
            // An unused lane repeats the block's first pair and is masked out.
            const std::pair<int, int>& pair = pairs[first+(lane < used ? lane : 0)];
            int i = pair.first, j = pair.second;
            put(block.d, lane, sitePositions[j]-sitePositions[i]);
            put(block.xi, lane, frames[i].x);
            put(block.yi, lane, frames[i].y);
            put(block.zi, lane, frames[i].z);
            put(block.xj, lane, frames[j].x);
            put(block.yj, lane, frames[j].y);
            put(block.zj, lane, frames[j].z);
            if (!uniform) {
                putParameters(block.pi, lane, parameters[i]);
                putParameters(block.pj, lane, parameters[j]);
            }
            block.used[lane] = (lane < used ? 1.0 : 0.0);
        }
        computeStickyPairBlock(block, settings, results);
        for (int lane = 0; lane < used; lane++) {
            int i = pairs[first+lane].first, j = pairs[first+lane].second;
            Vec3 force(results.force[0][lane], results.force[1][lane], results.force[2][lane]);
            energy += results.energy[lane];
            siteForces[i] += force;
            siteForces[j] -= force;
            torques[i] += Vec3(results.torqueI[0][lane], results.torqueI[1][lane], results.torqueI[2][lane]);
            torques[j] += Vec3(results.torqueJ[0][lane], results.torqueJ[1][lane], results.torqueJ[2][lane]);
        }
    }
    return energy;
}

void CpuCalcStickyDipoleForceKernel::initialize(const System& system, const StickyDipoleForce& force) {
    HostCalcStickyDipoleForceKernel::initialize(system, force);
    sharedParameters = true;
    for (int i = 1; i < (int) parameters.size() && sharedParameters; i++)
        sharedParameters = (StickyDipoleForceImpl::parameterValues(parameters[i]) == StickyDipoleForceImpl::parameterValues(parameters[0]));
}
