#include "RigidBrownianIntegrator.h"
#include "RigidLangevinKernels.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include <cmath>
#include <string>

using namespace RigidLangevinPlugin;
using namespace OpenMM;

RigidBrownianIntegrator::RigidBrownianIntegrator(double temperature, double viscosity, double stepSize) :
        RigidBodyIntegrator(temperature, viscosity, stepSize) {
}

void RigidBrownianIntegrator::step(int steps) {
    if (context == NULL)
        throw OpenMMException("This Integrator is not bound to a context!");
    if (!(getStepSize() > 0) || !std::isfinite(getStepSize()))
        throw OpenMMException("RigidBrownianIntegrator: the step size must be positive and finite, got "+std::to_string(getStepSize())+" ps");
    if (!(getViscosity() > 0))
        throw OpenMMException("RigidBrownianIntegrator: the viscosity is zero, but overdamped bodies move at their mobility, the inverse of their "
                "friction: set a positive viscosity (or use RigidLangevinIntegrator for dynamics without a solvent)");
    IntegrateRigidLangevinStepKernel& k = kernel.getAs<IntegrateRigidLangevinStepKernel>();
    for (int i = 0; i < steps; i++) {
        context->updateContextState();
        context->calcForcesAndEnergy(true, false, getIntegrationForceGroups());
        k.execute(*context, *this);
    }
}

double RigidBrownianIntegrator::computeKineticEnergy() {
    // Overdamped bodies carry no thermal velocities: the velocities reported are displacements
    // over the step, whose square is no kinetic energy.
    return 0.0;
}

bool RigidBrownianIntegrator::kineticEnergyRequiresForce() const {
    return false;
}
