#ifndef REFERENCE_RIGID_LANGEVIN_KERNELS_H_
#define REFERENCE_RIGID_LANGEVIN_KERNELS_H_

#include "internal/GaussianRandom.h"
#include "internal/RigidLangevinStepKernelBase.h"
#include "ReferencePlatform.h"
#include <memory>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The Reference implementation of RigidLangevinIntegrator: double precision, one body after another,
 * the definition of correct for every other platform.
 */
class ReferenceIntegrateRigidLangevinStepKernel : public RigidLangevinStepKernelBase {
public:
    ReferenceIntegrateRigidLangevinStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data) :
            RigidLangevinStepKernelBase(name, platform), data(data) {
    }
    void initialize(const OpenMM::System& system, const RigidLangevinIntegrator& integrator);
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
    /** Total force (lab frame) and torque (body frame) on each body. */
    void computeBodyForces(std::vector<OpenMM::Vec3>& forces, std::vector<OpenMM::Vec3>& torques) const;
    OpenMM::ReferencePlatform::PlatformData& data;
    std::unique_ptr<GaussianRandom> random;
    std::vector<BodyState> states;
};

} // namespace RigidLangevinPlugin

#endif /*REFERENCE_RIGID_LANGEVIN_KERNELS_H_*/
