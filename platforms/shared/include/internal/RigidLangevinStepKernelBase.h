#ifndef RIGID_LANGEVIN_STEP_KERNEL_BASE_H_
#define RIGID_LANGEVIN_STEP_KERNEL_BASE_H_

#include "RigidLangevinKernels.h"
#include "internal/HydrodynamicInteractions.h"
#include "internal/RigidBodyModel.h"
#include "internal/StepCoefficients.h"
#include "internal/windowsExportRigidLangevin.h"
#include <memory>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * What every platform's step kernel shares: the body model, fitting bodies to particles the user
 * set, recomputing step coefficients when a parameter changes, when a CMMotionRemover acts, which
 * kinetic energy is reported, and checkpoints. A platform supplies where body states and
 * coefficients live, the step itself, kinetic energies and its random numbers' state.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN RigidLangevinStepKernelBase : public IntegrateRigidLangevinStepKernel {
public:
    RigidLangevinStepKernelBase(std::string name, const OpenMM::Platform& platform);
    void initialize(const OpenMM::System& system, const RigidLangevinIntegrator& integrator);
    void execute(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator);
    void computeKineticEnergies(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator,
                                double& translational, double& rotational, double& centerOfMass);
    bool kineticEnergyRequiresForce(const RigidLangevinIntegrator& integrator) const;
    void stateChanged(OpenMM::ContextImpl& context, OpenMM::State::DataType changed);
    const RigidBodyModel& getModel(OpenMM::ContextImpl& context);
    void getBodyStates(OpenMM::ContextImpl& context, std::vector<BodyState>& states);
    void setBodyTypesAndStates(OpenMM::ContextImpl& context, const OpenMM::SerializationNode& types, const std::vector<BodyState>& states);
    void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream);
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream);
protected:
    /** Called when the model is built, or its types restored from a checkpoint: set up per-body and per-type storage. */
    virtual void initializeBodies(OpenMM::ContextImpl& context, const RigidBodyModel& model) = 0;
    /** Store body states and place every body's particles (positions, velocities) from them. */
    virtual void uploadBodyStates(OpenMM::ContextImpl& context, const std::vector<BodyState>& states) = 0;
    /** Read the current body states. */
    virtual void downloadBodyStates(OpenMM::ContextImpl& context, std::vector<BodyState>& states) = 0;
    /** Store the step coefficients of every body type. */
    virtual void uploadCoefficients(OpenMM::ContextImpl& context, const std::vector<TypeStepCoefficients>& coefficients) = 0;
    /**
     * Take one step of every body with the forces in the context, place the particles and advance
     * the context's time and step count. If removeMotion, first subtract the velocity of the centre
     * of mass from every body (a CMMotionRemover acted on the particles before this step).
     */
    virtual void takeStep(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator, bool removeMotion) = 0;
    /**
     * Sum 1/2 m V^2, 1/2 sum_k j_k^2/I_k and the total momentum over all bodies, with each body's
     * velocities first kicked forward by timeShift (force and torque from the context's forces).
     */
    virtual void computeBodyKineticEnergies(OpenMM::ContextImpl& context, double timeShift, double& translational,
                                            double& rotational, OpenMM::Vec3& momentum) = 0;
    /** Write and read the state of the random number generator. */
    virtual void createRandomCheckpoint(std::ostream& stream) = 0;
    virtual void loadRandomCheckpoint(std::istream& stream) = 0;
    /**
     * Whether this platform couples bodies through the solvent (RigidLangevinIntegrator::
     * setHydrodynamicInteractions()); a Context with interactions on a platform without them is refused.
     */
    virtual bool supportsHydrodynamicInteractions() const {
        return false;
    }
    /** Fit the bodies to the particles if those were set from outside since the last step. */
    void updateBodies(OpenMM::ContextImpl& context);
    std::unique_ptr<RigidBodyModel> model;
    std::vector<TypeStepCoefficients> coefficients;
    /** The bodies' coupling through the solvent, once their types exist; null without hydrodynamic interactions. */
    std::unique_ptr<HydrodynamicInteractions> interactions;
    int removerFrequency, removerIndex;
private:
    void updateCoefficients(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator);
    /** Refuse a CMMotionRemover at a nonzero viscosity (with an OpenMMException that says why and how to leave it out). */
    void checkMotionRemover(double viscosity) const;
    /** Refuse hydrodynamic interactions with a scheme other than BAOAB while there is friction. */
    void checkInteractionScheme(const RigidLangevinIntegrator& integrator) const;
    /** Build the bodies' coupling from the model's types, if interactions are on. */
    void initializeInteractions();
    /** Set up the kernel's storage for types just restored into the model, then place the bodies from states. */
    void installRestoredBodies(OpenMM::ContextImpl& context, const std::vector<BodyState>& states);
    double coefficientParameters[4];
    bool bodiesInitialized, particlesChanged, ignoreStateChanges, positionsSet, interactionsEnabled;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_STEP_KERNEL_BASE_H_*/
