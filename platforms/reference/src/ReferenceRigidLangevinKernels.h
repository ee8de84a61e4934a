#ifndef REFERENCE_RIGID_LANGEVIN_KERNELS_H_
#define REFERENCE_RIGID_LANGEVIN_KERNELS_H_

#include "RigidLangevinKernels.h"
#include "internal/GaussianRandom.h"
#include "internal/StepCoefficients.h"
#include "ReferencePlatform.h"
#include <memory>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The Reference implementation of RigidLangevinIntegrator: double precision, one body after another,
 * the definition of correct for every other platform.
 */
class ReferenceIntegrateRigidLangevinStepKernel : public IntegrateRigidLangevinStepKernel {
public:
    ReferenceIntegrateRigidLangevinStepKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data) :
            IntegrateRigidLangevinStepKernel(name, platform), data(data), particlesChanged(true), ignoreStateChanges(false), positionsSet(false), removerFrequency(0) {
    }
    void initialize(const OpenMM::System& system, const RigidLangevinIntegrator& integrator);
    void execute(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator);
    void computeKineticEnergies(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator,
                                double& translational, double& rotational, double& centerOfMass);
    bool kineticEnergyRequiresForce(const RigidLangevinIntegrator& integrator) const;
    void stateChanged(OpenMM::ContextImpl& context, OpenMM::State::DataType changed);
    const RigidBodyModel& getModel(OpenMM::ContextImpl& context);
    void getBodyStates(OpenMM::ContextImpl& context, std::vector<BodyState>& states);
    void setBodyStates(OpenMM::ContextImpl& context, const std::vector<BodyState>& states);
    void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream);
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream);
private:
    /** Fit the bodies to the particles if they were set from outside since the last step. */
    void updateBodies(OpenMM::ContextImpl& context);
    /** Recompute the step coefficients if a parameter of the integrator changed. */
    void updateCoefficients(const RigidLangevinIntegrator& integrator);
    /** Total force (lab frame) and torque (body frame) on each body. */
    void computeBodyForces(std::vector<OpenMM::Vec3>& forces, std::vector<OpenMM::Vec3>& torques) const;
    void writeParticles(OpenMM::ContextImpl& context);
    OpenMM::ReferencePlatform::PlatformData& data;
    std::unique_ptr<RigidBodyModel> model;
    std::unique_ptr<GaussianRandom> random;
    std::vector<BodyState> states;
    std::vector<TypeStepCoefficients> coefficients;
    double coefficientParameters[4];
    bool particlesChanged, ignoreStateChanges, positionsSet;
    int removerFrequency;
};

} // namespace RigidLangevinPlugin

#endif /*REFERENCE_RIGID_LANGEVIN_KERNELS_H_*/
