#ifndef REFERENCE_RIGID_LANGEVIN_KERNELS_H_
#define REFERENCE_RIGID_LANGEVIN_KERNELS_H_

#include "HostRigidLangevinStepKernel.h"
#include "HostStickyDipoleForceKernel.h"
#include "internal/GaussianRandom.h"

namespace RigidLangevinPlugin {

// The host step is compiled in ReferenceRigidLangevinKernels.cpp alone; the factory, which only
// creates the kernel, would otherwise compile all of it again.
extern template class HostRigidLangevinStepKernel<GaussianRandom>;

/**
 * The Reference implementation of RigidLangevinIntegrator: the host step (HostRigidLangevinStepKernel)
 * in double precision, all bodies as one chunk on the calling thread, with OpenMM's SFMT generator
 * through the polar Box-Muller method: the definition of correct for every other platform.
 */
class ReferenceIntegrateRigidLangevinStepKernel : public HostRigidLangevinStepKernel<GaussianRandom> {
public:
    ReferenceIntegrateRigidLangevinStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data) :
            HostRigidLangevinStepKernel<GaussianRandom>(name, platform, data) {
    }
    void initialize(const OpenMM::System& system, const RigidBodyIntegrator& integrator);
protected:
    void createRandomCheckpoint(std::ostream& stream);
    void loadRandomCheckpoint(std::istream& stream);
};

/** StickyDipoleForce on the host (HostCalcStickyDipoleForceKernel), on the calling thread. */
class ReferenceCalcStickyDipoleForceKernel : public HostCalcStickyDipoleForceKernel {
public:
    ReferenceCalcStickyDipoleForceKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data) :
            HostCalcStickyDipoleForceKernel(name, platform, data) {
    }
};

} // namespace RigidLangevinPlugin

#endif /*REFERENCE_RIGID_LANGEVIN_KERNELS_H_*/
