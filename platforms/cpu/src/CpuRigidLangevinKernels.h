#ifndef CPU_RIGID_LANGEVIN_KERNELS_H_
#define CPU_RIGID_LANGEVIN_KERNELS_H_

#include "CpuBodyStates.h"
#include "CpuPlatform.h"
#include "ReferencePlatform.h"
#include "ZigguratGaussianRandom.h"
#include "internal/RigidLangevinStepKernelBase.h"
#include <functional>
#include <memory>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The CPU platform's implementation of RigidLangevinIntegrator: the Reference kernel's equations
 * of motion (BodyDynamics.h, double precision), threaded with the CPU platform's ThreadPool.
 *
 * The bodies are split into a fixed set of contiguous chunks, each with its own stream of normal
 * random numbers (ZigguratGaussianRandom: the kernel draws up to 24 per body and step); threads take
 * whole chunks. The partition depends only on the number of bodies, so a
 * trajectory is determined by the random number seed (and the forces), whatever the number of
 * threads.
 */
class CpuIntegrateRigidLangevinStepKernel : public RigidLangevinStepKernelBase {
public:
    CpuIntegrateRigidLangevinStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data,
                                        OpenMM::CpuPlatform::PlatformData& cpuData);
    void initialize(const OpenMM::System& system, const RigidLangevinIntegrator& integrator);
    /** The most chunks (and random streams) the bodies are split into. */
    static const int MaxChunks = 64;
    /** Below this many bodies the chunks are run on the calling thread. */
    static const int MinBodiesForThreads = 200;
protected:
    void initializeBodies(OpenMM::ContextImpl& context, const RigidBodyModel& model);
    void uploadBodyStates(OpenMM::ContextImpl& context, const std::vector<BodyState>& states);
    void downloadBodyStates(OpenMM::ContextImpl& context, std::vector<BodyState>& states);
    void uploadCoefficients(OpenMM::ContextImpl& context, const std::vector<TypeStepCoefficients>& coefficients);
    void takeStep(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator, bool removeMotion);
    void computeBodyKineticEnergies(OpenMM::ContextImpl& context, double timeShift, double& translational, double& rotational, OpenMM::Vec3& momentum);
    void createRandomCheckpoint(std::ostream& stream);
    void loadRandomCheckpoint(std::istream& stream);
private:
    /** Run task(chunk, firstBody, endBody) for every chunk, spread over the threads, and wait. */
    void forEachChunk(const std::function<void (int, int, int)>& task);
    /** Total force (lab frame) and torque (body frame) on a body, from the platform's forces. */
    void computeBodyForce(int body, const BodyState& s, OpenMM::Vec3& force, OpenMM::Vec3& torque) const;
    /** Write the positions and velocities of a body's particles. */
    void placeParticles(int body, const BodyState& s);
    /** The total momentum of all bodies, summed chunk by chunk in a fixed order. */
    OpenMM::Vec3 computeMomentum();
    /**
     * One chunk's random numbers, alone in its cache lines: the generators' state changes with
     * every number, and threads drawing from neighbouring ones would otherwise share lines.
     */
    struct alignas(64) RandomStream {
        explicit RandomStream(uint32_t seed) : random(seed) {
        }
        ZigguratGaussianRandom random;
    };
    OpenMM::ReferencePlatform::PlatformData& data;
    OpenMM::ThreadPool& threads;
    CpuBodyStates bodies;
    std::vector<int> chunkStart;
    std::vector<std::unique_ptr<RandomStream> > random;  // one per chunk
};

} // namespace RigidLangevinPlugin

#endif /*CPU_RIGID_LANGEVIN_KERNELS_H_*/
