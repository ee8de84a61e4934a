#include "CpuRigidLangevinKernels.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/OSRngSeed.h"
#include <algorithm>
#include <cstdint>
#include <istream>
#include <ostream>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

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

void CpuIntegrateRigidLangevinStepKernel::initialize(const System& system, const RigidLangevinIntegrator& integrator) {
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
        throw OpenMMException("RigidLangevinIntegrator: the checkpoint was not written by the CPU platform for this System "
                              "(it has "+std::to_string(numStreams)+" random number streams, this context "+std::to_string(random.size())+")");
    for (auto& r : random)
        r->random.loadCheckpoint(stream);
}
