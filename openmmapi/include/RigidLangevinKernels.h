#ifndef RIGID_LANGEVIN_KERNELS_H_
#define RIGID_LANGEVIN_KERNELS_H_

#include "RigidBrownianIntegrator.h"
#include "RigidLangevinIntegrator.h"
#include "StickyDipoleForce.h"
#include "internal/RigidBodyModel.h"
#include "openmm/KernelImpl.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include <iosfwd>
#include <string>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * This kernel is invoked by the rigid-body integrators (RigidLangevinIntegrator,
 * RigidBrownianIntegrator) to take one time step, and to report and change the state of the rigid
 * bodies they move. The body model and every matrix a step needs come
 * precomputed from the API layer (RigidBodyModel, computeStepCoefficients()); a kernel applies
 * them to its platform's data.
 */
class IntegrateRigidLangevinStepKernel : public OpenMM::KernelImpl {
public:
    static std::string Name() {
        return "IntegrateRigidLangevinStep";
    }
    IntegrateRigidLangevinStepKernel(std::string name, const OpenMM::Platform& platform) : OpenMM::KernelImpl(name, platform) {
    }
    /**
     * Initialize the kernel.
     *
     * @param system      the System this kernel will be applied to
     * @param integrator  the integrator this kernel will be used for
     */
    virtual void initialize(const OpenMM::System& system, const RigidBodyIntegrator& integrator) = 0;
    /**
     * Take one time step of the integrator's dynamics (Langevin or overdamped). The forces in the
     * context are those at the current positions.
     */
    virtual void execute(OpenMM::ContextImpl& context, const RigidBodyIntegrator& integrator) = 0;
    /**
     * Compute the kinetic energy of the bodies' translation and rotation, and that of the motion of
     * the centre of mass of the whole system (kJ/mol).
     */
    virtual void computeKineticEnergies(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator,
                                        double& translational, double& rotational, double& centerOfMass) = 0;
    /** Whether computeKineticEnergies() uses the forces. */
    virtual bool kineticEnergyRequiresForce(const RigidLangevinIntegrator& integrator) const = 0;
    /** Tell the kernel that the positions or velocities of the particles were set from outside. */
    virtual void stateChanged(OpenMM::ContextImpl& context, OpenMM::State::DataType changed) = 0;
    /** The body model, built from the current positions if it was not built yet. */
    virtual const RigidBodyModel& getModel(OpenMM::ContextImpl& context) = 0;
    /**
     * The iterations the last step's Krylov solves of the coupled friction (hydrodynamic
     * interactions) took: the noise's Lanczos square root, the noise's and the friction's conjugate
     * gradients; all zero after a dense step or without interactions.
     */
    virtual void getKrylovIterations(int& noise, int& noiseSolve, int& friction) const = 0;
    /** Get the state of every body (user bodies first, then free particles). */
    virtual void getBodyStates(OpenMM::ContextImpl& context, std::vector<BodyState>& states) = 0;
    /**
     * Get the state of every body with its synchronous velocities (TypeStepCoefficients::
     * synchronousKick), from the forces at the current positions (computed here).
     */
    virtual void getSynchronousBodyStates(OpenMM::ContextImpl& context, const RigidBodyIntegrator& integrator, std::vector<BodyState>& states) = 0;
    /**
     * Restore the body states of a State, expressed in the frames of the body types it carries
     * (RigidBodyModel::writeTypes()), into this integrator's bodies (RigidBodyModel::restoreStates():
     * the friction stays this integrator's); the particles are placed from them.
     */
    virtual void restoreFromState(OpenMM::ContextImpl& context, const OpenMM::SerializationNode& types, const std::vector<BodyState>& states) = 0;
    /** Write everything needed for a bit-identical continuation. */
    virtual void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream) = 0;
    /** Read a checkpoint written by createCheckpoint(). */
    virtual void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream) = 0;
};

/** Computes StickyDipoleForce's energy and forces. */
class CalcStickyDipoleForceKernel : public OpenMM::KernelImpl {
public:
    static std::string Name() {
        return "CalcStickyDipoleForce";
    }
    CalcStickyDipoleForceKernel(std::string name, const OpenMM::Platform& platform) : OpenMM::KernelImpl(name, platform) {
    }
    /** Copy the force's parameters (StickyDipoleForceImpl has checked them against the System). */
    virtual void initialize(const OpenMM::System& system, const StickyDipoleForce& force) = 0;
    /** Add the forces to the context's, and return the energy (kJ/mol) if asked. */
    virtual double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) = 0;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_KERNELS_H_*/
