#ifndef CPU_RIGID_LANGEVIN_KERNELS_H_
#define CPU_RIGID_LANGEVIN_KERNELS_H_

#include "CpuPlatform.h"
#include "HostRigidLangevinStepKernel.h"
#include "HostStickyDipoleForceKernel.h"
#include "ZigguratGaussianRandom.h"

namespace RigidLangevinPlugin {

// The host step is compiled in CpuRigidLangevinKernels.cpp alone; the factory, which only creates
// the kernel, would otherwise compile all of it again.
extern template class HostRigidLangevinStepKernel<ZigguratGaussianRandom>;

/**
 * The CPU platform's implementation of RigidLangevinIntegrator: the host step shared with the
 * Reference platform (HostRigidLangevinStepKernel, double precision), threaded with the CPU
 * platform's ThreadPool.
 *
 * The bodies are split into a fixed set of contiguous chunks, each with its own stream of normal
 * random numbers (ZigguratGaussianRandom: the kernel draws up to 24 per body and step); threads take
 * whole chunks. The partition depends only on the number of bodies, so a
 * trajectory is determined by the random number seed (and the forces), whatever the number of
 * threads.
 */
class CpuIntegrateRigidLangevinStepKernel : public HostRigidLangevinStepKernel<ZigguratGaussianRandom> {
public:
    CpuIntegrateRigidLangevinStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data,
                                        OpenMM::CpuPlatform::PlatformData& cpuData) :
            HostRigidLangevinStepKernel<ZigguratGaussianRandom>(name, platform, data), threads(cpuData.threads) {
    }
    void initialize(const OpenMM::System& system, const RigidBodyIntegrator& integrator);
    /** The most chunks (and random streams) the bodies are split into. */
    static const int MaxChunks = 64;
    /** Below this many bodies the chunks are run on the calling thread. */
    static const int MinBodiesForThreads = 200;
    /**
     * From this many blobs the coupled friction step (hydrodynamic interactions in an unbounded
     * solvent) is matrix-free (Krylov), below it dense (measured: benchmarks/platforms/
     * hydrodynamic_interactions.py); RigidLangevinStepKernelBase::chooseCoupledSolve.
     */
    static const int KrylovMinBlobs = 100;
protected:
    int getDefaultKrylovMinBlobs() const {
        return KrylovMinBlobs;
    }
    void parallelFor(int count, const std::function<void (int, int)>& task);
    void forEachChunk(const std::function<void (int, int, int)>& task);
    void createRandomCheckpoint(std::ostream& stream);
    void loadRandomCheckpoint(std::istream& stream);
private:
    OpenMM::ThreadPool& threads;
    int numBodies = 0;
};

/**
 * StickyDipoleForce on the CPU platform: the host kernel (HostCalcStickyDipoleForceKernel, double
 * precision), its pairs shared among the platform's threads and evaluated four at a time
 * (CpuStickyDipolePairs.h). The sums depend on the number of threads, as those of OpenMM's own CPU
 * forces do.
 */
class CpuCalcStickyDipoleForceKernel : public HostCalcStickyDipoleForceKernel {
public:
    CpuCalcStickyDipoleForceKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data,
                                   OpenMM::CpuPlatform::PlatformData& cpuData) :
            HostCalcStickyDipoleForceKernel(name, platform, data), threads(cpuData.threads), sharedParameters(false) {
    }
    void initialize(const OpenMM::System& system, const StickyDipoleForce& force);
protected:
    double computePairs(long long begin, long long end, const std::vector<OpenMM::Vec3>& sitePositions, const std::vector<SiteFrame>& frames,
                        const OpenMM::Vec3* box, std::vector<OpenMM::Vec3>& siteForces, std::vector<OpenMM::Vec3>& torques);
    int getNumThreads() {
        return threads.getNumThreads();
    }
    void runThreads(const std::function<void (int)>& task) {
        threads.execute([&] (OpenMM::ThreadPool& /*pool*/, int thread) {task(thread);});
        threads.waitForThreads();
    }
private:
    OpenMM::ThreadPool& threads;
    bool sharedParameters;  // whether all sites have the same parameters
};

} // namespace RigidLangevinPlugin

#endif /*CPU_RIGID_LANGEVIN_KERNELS_H_*/
