#ifndef REFERENCE_RIGID_LANGEVIN_KERNELS_H_
#define REFERENCE_RIGID_LANGEVIN_KERNELS_H_

#include "HostRigidLangevinStepKernel.h"
#include "RigidLangevinKernels.h"
#include "StickyDipoleForce.h"
#include "internal/GaussianRandom.h"
#include <set>
#include <vector>

namespace RigidLangevinPlugin {

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
    void initialize(const OpenMM::System& system, const RigidLangevinIntegrator& integrator);
protected:
    void createRandomCheckpoint(std::ostream& stream);
    void loadRandomCheckpoint(std::istream& stream);
};

/**
 * StickyDipoleForce in double precision (StickyDipoleInteraction.h), pairs from OpenMM's voxel
 * neighbour list with a cutoff, all pairs without one.
 */
class ReferenceCalcStickyDipoleForceKernel : public CalcStickyDipoleForceKernel {
public:
    ReferenceCalcStickyDipoleForceKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data) :
            CalcStickyDipoleForceKernel(name, platform), data(data) {
    }
    void initialize(const OpenMM::System& system, const StickyDipoleForce& force);
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy);
private:
    OpenMM::ReferencePlatform::PlatformData& data;
    std::vector<int> particles, references1, references2;
    std::vector<StickyDipoleForce::SiteParameters> parameters;
    std::vector<std::set<int> > exclusions;
    StickyDipoleForce::NonbondedMethod method;
    double cutoff, switchingDistance, kappa;
    bool useSwitching;
};

} // namespace RigidLangevinPlugin

#endif /*REFERENCE_RIGID_LANGEVIN_KERNELS_H_*/
