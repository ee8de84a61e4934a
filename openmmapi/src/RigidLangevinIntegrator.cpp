#include "RigidLangevinIntegrator.h"
#include "RigidLangevinKernels.h"
#include "ResistanceTensor.h"
#include "internal/GaussianRandom.h"
#include "internal/StepCoefficients.h"
#include "openmm/CMMotionRemover.h"
#include "openmm/Context.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include "openmm/serialization/SerializationNode.h"
#include <cmath>
#include <string>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::string;
using std::vector;

RigidLangevinIntegrator::RigidLangevinIntegrator(double temperature, double viscosity, double stepSize) :
        RigidBodyIntegrator(temperature, viscosity, stepSize), scheme(ExactFlow) {
}

void RigidLangevinIntegrator::setScheme(Scheme s) {
    if (s != ExactFlow && s != BAOAB && s != Original)
        throw OpenMMException("RigidLangevinIntegrator: unknown scheme "+std::to_string((int) s)+"; use ExactFlow (0), BAOAB (1) or Original (2)");
    scheme = s;
}

void RigidLangevinIntegrator::step(int steps) {
    if (context == NULL)
        throw OpenMMException("This Integrator is not bound to a context!");
    if (!(getStepSize() > 0) || !std::isfinite(getStepSize()))
        throw OpenMMException("RigidLangevinIntegrator: the step size must be positive and finite, got "+std::to_string(getStepSize())+" ps");
    IntegrateRigidLangevinStepKernel& k = kernel.getAs<IntegrateRigidLangevinStepKernel>();
    for (int i = 0; i < steps; i++) {
        context->updateContextState();
        context->calcForcesAndEnergy(true, false, getIntegrationForceGroups());
        k.execute(*context, *this);
    }
}

double RigidLangevinIntegrator::getVelocityTimeOffset() const {
    static_assert((int) SplittingScheme::ExactFlow == ExactFlow && (int) SplittingScheme::BAOAB == BAOAB && (int) SplittingScheme::Original == Original,
                  "the model's splitting schemes carry the values of RigidLangevinIntegrator::Scheme");
    return velocityTimeOffset(static_cast<SplittingScheme>(getScheme()), getViscosity(), getStepSize());
}

bool RigidLangevinIntegrator::kineticEnergyRequiresForce() const {
    if (context == NULL)
        return true;
    return kernel.getAs<IntegrateRigidLangevinStepKernel>().kineticEnergyRequiresForce(*this);
}

double RigidLangevinIntegrator::computeKineticEnergy() {
    double translational, rotational, centerOfMass;
    kernel.getAs<IntegrateRigidLangevinStepKernel>().computeKineticEnergies(*context, *this, translational, rotational, centerOfMass);
    return translational+rotational;
}

/** components: 1 translational, 2 rotational, 3 both. */
double RigidLangevinIntegrator::computeTemperature(int components) {
    if (context == NULL)
        throw OpenMMException("This Integrator is not bound to a context!");
    IntegrateRigidLangevinStepKernel& k = kernel.getAs<IntegrateRigidLangevinStepKernel>();
    if (k.kineticEnergyRequiresForce(*this))
        context->calcForcesAndEnergy(true, false, getIntegrationForceGroups());
    const RigidBodyModel& model = k.getModel(*context);
    double translational, rotational, centerOfMass;
    k.computeKineticEnergies(*context, *this, translational, rotational, centerOfMass);
    bool removesMotion = false;
    const System& system = context->getSystem();
    for (int i = 0; i < system.getNumForces(); i++)
        if (dynamic_cast<const CMMotionRemover*>(&system.getForce(i)) != NULL)
            removesMotion = true;
    double energy = 0;
    int dof = 0;
    if (components & 1) {
        energy += translational;
        dof += model.getNumTranslationalDegreesOfFreedom();
        if (removesMotion) {
            energy -= centerOfMass;
            dof -= 3;
        }
    }
    if (components & 2) {
        energy += rotational;
        dof += model.getNumRotationalDegreesOfFreedom();
    }
    return (dof > 0 ? 2*energy/(dof*BOLTZ) : 0.0);
}

double RigidLangevinIntegrator::computeSystemTemperature() {
    return computeTemperature(3);
}

double RigidLangevinIntegrator::computeTranslationalTemperature() {
    return computeTemperature(1);
}

double RigidLangevinIntegrator::computeRotationalTemperature() {
    return computeTemperature(2);
}

vector<Vec3> RigidLangevinIntegrator::getVelocitiesForTemperature(const System& system, double temp, int randomSeed) const {
    // Maxwell-Boltzmann in the bodies' own degrees of freedom: every particle then moves rigidly.
    IntegrateRigidLangevinStepKernel& k = kernel.getAs<IntegrateRigidLangevinStepKernel>();
    const RigidBodyModel& model = k.getModel(*context);
    vector<BodyState> states;
    k.getBodyStates(*context, states);
    GaussianRandom random(randomSeed);
    double kT = BOLTZ*temp;
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        BodyState& s = states[b];
        double scale = std::sqrt(kT/type.mass);
        for (int k = 0; k < 3; k++)
            s.velocity[k] = scale*random.next();
        for (int k = 0; k < 3; k++)
            s.angularMomentum[k] = (type.rotates(k) ? std::sqrt(kT*type.inertia[k])*random.next() : 0.0);
    }
    vector<Vec3> positions(system.getNumParticles()), velocities(system.getNumParticles());
    model.placeParticles(states, positions, velocities);
    return velocities;
}

