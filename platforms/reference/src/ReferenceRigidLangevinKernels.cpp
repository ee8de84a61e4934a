#include "ReferenceRigidLangevinKernels.h"
#include "internal/BodyDynamics.h"
#include "ReferenceVirtualSites.h"
#include "openmm/internal/ContextImpl.h"

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

void ReferenceIntegrateRigidLangevinStepKernel::initialize(const System& system, const RigidLangevinIntegrator& integrator) {
    RigidLangevinStepKernelBase::initialize(system, integrator);
    random.reset(new GaussianRandom(integrator.getRandomNumberSeed()));
}

void ReferenceIntegrateRigidLangevinStepKernel::initializeBodies(ContextImpl& context, const RigidBodyModel& model) {
    states.resize(model.getNumBodies());
}

void ReferenceIntegrateRigidLangevinStepKernel::uploadBodyStates(ContextImpl& context, const vector<BodyState>& newStates) {
    states = newStates;
    model->placeParticles(states, *data.positions, *data.velocities);
}

void ReferenceIntegrateRigidLangevinStepKernel::downloadBodyStates(ContextImpl& context, vector<BodyState>& result) {
    result = states;
}

void ReferenceIntegrateRigidLangevinStepKernel::uploadCoefficients(ContextImpl& context, const vector<TypeStepCoefficients>& c) {
    // The base class keeps them in `coefficients`.
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
            if (type.isVirtualSite[i])
                continue;  // OpenMM has already added its force to its parents
            const Vec3& force = f[particles[i]];
            forces[b] += force;
            if (type.numRotations > 0)
                torques[b] += type.coords[i].cross(BodyDynamics::toBody(states[b].rotation, force));
        }
    }
}

void ReferenceIntegrateRigidLangevinStepKernel::takeStep(ContextImpl& context, const RigidLangevinIntegrator& integrator, bool removeMotion) {
    const double h = integrator.getStepSize();
    int numBodies = model->getNumBodies();
    if (removeMotion) {
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
    model->placeParticles(states, *data.positions, *data.velocities);
    data.virtualSites->computePositions(context.getSystem(), *data.positions, data.periodicBoxVectors);
    data.time += h;
    data.stepCount++;
}

void ReferenceIntegrateRigidLangevinStepKernel::computeBodyKineticEnergies(ContextImpl& context, double timeShift,
        double& translational, double& rotational, Vec3& momentum) {
    vector<Vec3> forces, torques;
    if (timeShift != 0)
        computeBodyForces(forces, torques);
    translational = rotational = 0;
    momentum = Vec3();
    for (int b = 0; b < model->getNumBodies(); b++) {
        const BodyType& type = model->getType(model->getBodyType(b));
        BodyState s = states[b];
        if (timeShift != 0)
            BodyDynamics::kick(s, type, forces[b], torques[b], timeShift);
        translational += 0.5*type.mass*s.velocity.dot(s.velocity);
        momentum += s.velocity*type.mass;
        for (int k = 0; k < 3; k++)
            if (type.rotates(k))
                rotational += 0.5*s.angularMomentum[k]*s.angularMomentum[k]/type.inertia[k];
    }
}

void ReferenceIntegrateRigidLangevinStepKernel::createRandomCheckpoint(std::ostream& stream) {
    random->createCheckpoint(stream);
}

void ReferenceIntegrateRigidLangevinStepKernel::loadRandomCheckpoint(std::istream& stream) {
    random->loadCheckpoint(stream);
}
