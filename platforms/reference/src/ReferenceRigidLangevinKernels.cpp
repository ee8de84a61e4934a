#include "ReferenceRigidLangevinKernels.h"
#include "internal/BodyDynamics.h"
#include "ReferenceVirtualSites.h"
#include "openmm/CMMotionRemover.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include <cmath>
#include <istream>
#include <ostream>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

namespace {

const int CheckpointVersion = 1;

/** The shift that turns the stored (mid-step) velocities into on-step ones, see kineticEnergyRequiresForce(). */
double kineticEnergyTimeShift(const RigidLangevinIntegrator& integrator) {
    bool onStep = (integrator.getViscosity() == 0 || integrator.getScheme() == RigidLangevinIntegrator::Original);
    return onStep ? 0.5*integrator.getStepSize() : 0.0;
}

} // namespace

void ReferenceIntegrateRigidLangevinStepKernel::initialize(const System& system, const RigidLangevinIntegrator& integrator) {
    model.reset(new RigidBodyModel(system, integrator));
    random.reset(new GaussianRandom(integrator.getRandomNumberSeed()));
    for (int i = 0; i < system.getNumForces(); i++) {
        const CMMotionRemover* remover = dynamic_cast<const CMMotionRemover*>(&system.getForce(i));
        if (remover != NULL)
            removerFrequency = remover->getFrequency();
    }
}

void ReferenceIntegrateRigidLangevinStepKernel::stateChanged(ContextImpl& context, State::DataType changed) {
    if (changed != State::Positions && changed != State::Velocities)
        return;
    if (changed == State::Positions)
        positionsSet = true;
    if (ignoreStateChanges) {
        // ContextImpl::loadCheckpoint() reports positions, then velocities, as changed after the
        // integrator restored its exact body states; those particles already match them.
        if (changed == State::Velocities)
            ignoreStateChanges = false;
        return;
    }
    particlesChanged = true;
}

void ReferenceIntegrateRigidLangevinStepKernel::updateBodies(ContextImpl& context) {
    if (!particlesChanged)
        return;
    if (!positionsSet)
        throw OpenMMException("RigidLangevinIntegrator: the particle positions have not been set; rigid bodies take their shapes from them");
    bool periodic = context.getSystem().usesPeriodicBoundaryConditions();
    states = model->fitStates(*data.positions, *data.velocities, periodic ? data.periodicBoxVectors : NULL);
    particlesChanged = false;
    writeParticles(context);
}

void ReferenceIntegrateRigidLangevinStepKernel::updateCoefficients(const RigidLangevinIntegrator& integrator) {
    double parameters[4] = {integrator.getTemperature(), integrator.getViscosity(), integrator.getStepSize(), (double) integrator.getScheme()};
    bool changed = coefficients.empty();
    for (int i = 0; i < 4; i++)
        changed |= (parameters[i] != coefficientParameters[i]);
    if (!changed)
        return;
    coefficients = computeStepCoefficients(*model, integrator.getScheme(), parameters[0], parameters[1], parameters[2]);
    if (integrator.getScheme() == RigidLangevinIntegrator::Original)
        checkOriginalSchemeStability(*model, coefficients, parameters[2]);
    for (int i = 0; i < 4; i++)
        coefficientParameters[i] = parameters[i];
}

const RigidBodyModel& ReferenceIntegrateRigidLangevinStepKernel::getModel(ContextImpl& context) {
    updateBodies(context);
    return *model;
}

void ReferenceIntegrateRigidLangevinStepKernel::computeBodyForces(vector<Vec3>& forces, vector<Vec3>& torques) const {
    const vector<Vec3>& f = *data.forces;
    int numBodies = model->getNumBodies();
    forces.assign(numBodies, Vec3());
    torques.assign(numBodies, Vec3());
    for (int b = 0; b < numBodies; b++) {
        const BodyType& type = model->getType(model->getBodyType(b));
        const vector<int>& particles = model->getBodyParticles(b);
        for (int i = 0; i < (int) particles.size(); i++) {
            const Vec3& force = f[particles[i]];
            forces[b] += force;
            if (type.numRotations > 0)
                torques[b] += type.coords[i].cross(BodyDynamics::toBody(states[b].rotation, force));
        }
    }
}

void ReferenceIntegrateRigidLangevinStepKernel::writeParticles(ContextImpl& context) {
    model->placeParticles(states, *data.positions, *data.velocities);
    data.virtualSites->computePositions(context.getSystem(), *data.positions, data.periodicBoxVectors);
}

void ReferenceIntegrateRigidLangevinStepKernel::execute(ContextImpl& context, const RigidLangevinIntegrator& integrator) {
    updateBodies(context);
    updateCoefficients(integrator);
    const double h = integrator.getStepSize();
    int numBodies = model->getNumBodies();

    // A CMMotionRemover acted on the particle velocities before this step; do the same to the bodies.
    if (removerFrequency > 0 && data.stepCount%removerFrequency == 0) {
        Vec3 momentum;
        for (int b = 0; b < numBodies; b++)
            momentum += states[b].velocity*model->getType(model->getBodyType(b)).mass;
        Vec3 velocity = momentum/model->getTotalMass();
        for (int b = 0; b < numBodies; b++)
            states[b].velocity -= velocity;
    }

    vector<Vec3> forces, torques;
    computeBodyForces(forces, torques);
    RigidLangevinIntegrator::Scheme scheme = integrator.getScheme();
    bool frictionless = (integrator.getViscosity() == 0);
    for (int b = 0; b < numBodies; b++) {
        const BodyType& type = model->getType(model->getBodyType(b));
        const TypeStepCoefficients& c = coefficients[model->getBodyType(b)];
        BodyState& s = states[b];
        if (scheme == RigidLangevinIntegrator::Original) {
            BodyDynamics::originalStep(s, type, c, forces[b], torques[b], h, *random);
            continue;
        }
        // The two half kicks of consecutive steps, as one: velocities are kept between flow and kick.
        // Without friction both schemes are plain velocity Verlet with free rotation.
        BodyDynamics::kick(s, type, forces[b], torques[b], h);
        if (scheme == RigidLangevinIntegrator::ExactFlow) {
            if (frictionless)
                BodyDynamics::drift(s, type, h);
            else
                BodyDynamics::exactFlow(s, type, c, h, *random);
        }
        else {
            BodyDynamics::drift(s, type, 0.5*h);
            if (!frictionless)
                BodyDynamics::ornsteinUhlenbeck(s, type, c, *random);
            BodyDynamics::drift(s, type, 0.5*h);
        }
    }
    writeParticles(context);
    data.time += h;
    data.stepCount++;
}

bool ReferenceIntegrateRigidLangevinStepKernel::kineticEnergyRequiresForce(const RigidLangevinIntegrator& integrator) const {
    return kineticEnergyTimeShift(integrator) != 0;
}

void ReferenceIntegrateRigidLangevinStepKernel::computeKineticEnergies(ContextImpl& context, const RigidLangevinIntegrator& integrator,
        double& translational, double& rotational, double& centerOfMass) {
    // With friction the stored velocities, which lie between the flow and the next kick, are the
    // accurate ones (exactly Maxwellian in the stiff limit), as in OpenMM's LangevinMiddleIntegrator.
    // Velocity Verlet (no friction) and the Original scheme report on-step velocities, half a kick on.
    updateBodies(context);
    double shift = kineticEnergyTimeShift(integrator);
    vector<Vec3> forces, torques;
    if (shift != 0)
        computeBodyForces(forces, torques);
    translational = rotational = 0;
    Vec3 momentum;
    for (int b = 0; b < model->getNumBodies(); b++) {
        const BodyType& type = model->getType(model->getBodyType(b));
        BodyState s = states[b];
        if (shift != 0)
            BodyDynamics::kick(s, type, forces[b], torques[b], shift);
        translational += 0.5*type.mass*s.velocity.dot(s.velocity);
        momentum += s.velocity*type.mass;
        for (int k = 0; k < 3; k++)
            if (type.rotates(k))
                rotational += 0.5*s.angularMomentum[k]*s.angularMomentum[k]/type.inertia[k];
    }
    double totalMass = model->getTotalMass();
    centerOfMass = (totalMass > 0 ? 0.5*momentum.dot(momentum)/totalMass : 0.0);
}

void ReferenceIntegrateRigidLangevinStepKernel::getBodyStates(ContextImpl& context, vector<BodyState>& result) {
    updateBodies(context);
    result = states;
}

void ReferenceIntegrateRigidLangevinStepKernel::setBodyStates(ContextImpl& context, const vector<BodyState>& newStates) {
    updateBodies(context);
    if (newStates.size() != states.size())
        throw OpenMMException("RigidLangevinIntegrator: got states for "+std::to_string(newStates.size())+" bodies, but the integrator moves "+
                std::to_string(states.size())+" (rigid bodies and free particles)");
    states = newStates;
    writeParticles(context);
}

void ReferenceIntegrateRigidLangevinStepKernel::createCheckpoint(ContextImpl& context, std::ostream& stream) {
    updateBodies(context);
    stream.write((char*) &CheckpointVersion, sizeof(int));
    model->writeTypes(stream);
    int numBodies = states.size();
    stream.write((char*) &numBodies, sizeof(int));
    stream.write((char*) states.data(), numBodies*sizeof(BodyState));
    random->createCheckpoint(stream);
}

void ReferenceIntegrateRigidLangevinStepKernel::loadCheckpoint(ContextImpl& context, std::istream& stream) {
    int version, numBodies;
    stream.read((char*) &version, sizeof(int));
    if (version != CheckpointVersion)
        throw OpenMMException("RigidLangevinIntegrator: the checkpoint was written by an incompatible version of the plugin");
    model->readTypes(stream);
    stream.read((char*) &numBodies, sizeof(int));
    if (!stream || numBodies != model->getNumBodies())
        throw OpenMMException("RigidLangevinIntegrator: the checkpoint's rigid bodies do not match this System's");
    states.resize(numBodies);
    stream.read((char*) states.data(), numBodies*sizeof(BodyState));
    random->loadCheckpoint(stream);
    coefficients.clear();
    particlesChanged = false;
    ignoreStateChanges = true;
}
