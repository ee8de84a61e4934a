#include "RigidBodyIntegrator.h"
#include "RigidLangevinKernels.h"
#include "ResistanceTensor.h"
#include "internal/StepCoefficients.h"
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

RigidBodyIntegrator::RigidBodyIntegrator(double temperature, double viscosity, double stepSize) :
        temperature(0), viscosity(0), randomNumberSeed(0), hydrodynamicInteractions(false), hydrodynamicSolver(AutomaticSolver),
        hydrodynamicTolerance(1e-4), krylovMinBlobs(-1), hydrodynamicMemoryBudget(4.0*1024*1024*1024), wall(false), wallHeight(0) {
    setTemperature(temperature);
    setViscosity(viscosity);
    if (!(stepSize > 0) || !std::isfinite(stepSize))
        throw OpenMMException(className()+": the step size must be positive and finite, got "+std::to_string(stepSize)+" ps");
    setStepSize(stepSize);
    setConstraintTolerance(1e-5);
}

void RigidBodyIntegrator::checkBound(const char* method) const {
    if (context == NULL)
        throw OpenMMException(className()+"::"+method+": this Integrator is not bound to a context");
}

void RigidBodyIntegrator::setWall(double height) {
    checkNotBound("setWall");
    if (!std::isfinite(height))
        throw OpenMMException(className()+"::setWall: the wall's height must be finite, got "+std::to_string(height)+" nm");
    wall = true;
    wallHeight = height;
}

void RigidBodyIntegrator::clearWall() {
    checkNotBound("clearWall");
    wall = false;
    wallHeight = 0;
}

bool RigidBodyIntegrator::getWall(double& height) const {
    height = wallHeight;
    return wall;
}

void RigidBodyIntegrator::setTemperature(double temp) {
    if (!(temp >= 0) || !std::isfinite(temp))
        throw OpenMMException(className()+": the temperature must be non-negative and finite, got "+std::to_string(temp)+" K");
    temperature = temp;
}

void RigidBodyIntegrator::setViscosity(double visc) {
    if (!(visc >= 0) || !std::isfinite(visc))
        throw OpenMMException(className()+": the viscosity must be non-negative and finite, got "+std::to_string(visc)+" amu/(nm*ps)");
    viscosity = visc;
}

void RigidBodyIntegrator::setRandomNumberSeed(int seed) {
    randomNumberSeed = seed;
}

void RigidBodyIntegrator::checkNotBound(const char* method) const {
    if (context != NULL)
        throw OpenMMException(className()+"::"+method+": rigid bodies must be defined before the Context is created");
}

void RigidBodyIntegrator::checkBodyIndex(int index, const char* method) const {
    if (index < 0 || index >= (int) bodies.size())
        throw OpenMMException(className()+"::"+method+": there is no rigid body "+std::to_string(index)+
                " (the integrator has "+std::to_string(bodies.size())+" bodies)");
}

int RigidBodyIntegrator::addRigidBody(const vector<int>& particles) {
    checkNotBound("addRigidBody");
    int index = bodies.size();
    if (particles.empty())
        throw OpenMMException(className()+"::addRigidBody: rigid body "+std::to_string(index)+" has no particles");
    for (int i = 0; i < (int) particles.size(); i++) {
        int p = particles[i];
        if (p < 0)
            throw OpenMMException(className()+"::addRigidBody: rigid body "+std::to_string(index)+" contains the negative particle index "+std::to_string(p));
        for (int j = 0; j < i; j++)
            if (particles[j] == p)
                throw OpenMMException(className()+"::addRigidBody: rigid body "+std::to_string(index)+" lists particle "+std::to_string(p)+" twice");
        auto other = particleBody.find(p);
        if (other != particleBody.end())
            throw OpenMMException(className()+"::addRigidBody: particle "+std::to_string(p)+" is already in rigid body "+std::to_string(other->second)+
                    "; a particle can belong to one body only");
    }
    for (int p : particles)
        particleBody[p] = index;
    bodies.push_back(particles);
    return index;
}

const vector<int>& RigidBodyIntegrator::getRigidBodyParticles(int index) const {
    checkBodyIndex(index, "getRigidBodyParticles");
    return bodies[index];
}

namespace {

/** Throw unless referencePositions holds a finite position for each of the body's particles: "<what>:
 *  <needs> the positions of the body's N <particles>, got M positions", or naming the one not finite. */
void checkReferencePositions(const string& what, const string& needs, const string& particles, const vector<int>& body, const vector<Vec3>& referencePositions) {
    if (referencePositions.size() != body.size())
        throw OpenMMException(what+": "+needs+" the positions of the body's "+std::to_string(body.size())+" "+particles+", got "+
                std::to_string(referencePositions.size())+" positions");
    for (int i = 0; i < (int) referencePositions.size(); i++)
        for (int k = 0; k < 3; k++)
            if (!std::isfinite(referencePositions[i][k]))
                throw OpenMMException(what+": reference position "+std::to_string(i)+" (particle "+std::to_string(body[i])+") is not finite");
}

} // namespace

void RigidBodyIntegrator::setBodyResistance(int index, const vector<double>& tensor, const Vec3& origin, const vector<Vec3>& referencePositions) {
    checkNotBound("setBodyResistance");
    checkBodyIndex(index, "setBodyResistance");
    string what = className()+"::setBodyResistance: rigid body "+std::to_string(index);
    if (tensor.size() != 36)
        throw OpenMMException(what+": a resistance tensor needs 36 values (a 6x6 matrix, row-major), got "+std::to_string(tensor.size()));
    try {
        ResistanceTensor::fromMatrix(tensor, origin);
    }
    catch (const OpenMMException& e) {
        string message = e.what();
        throw OpenMMException(what+message.substr(message.find(':')));
    }
    if (!std::isfinite(origin[0]) || !std::isfinite(origin[1]) || !std::isfinite(origin[2]))
        throw OpenMMException(what+": the origin of the resistance tensor is not finite");
    checkReferencePositions(what, "the tensor needs", "particles it was computed for", bodies[index], referencePositions);
    resistances[index] = {tensor, origin, referencePositions};
}

bool RigidBodyIntegrator::getBodyResistance(int index, vector<double>& tensor, Vec3& origin, vector<Vec3>& referencePositions) const {
    checkBodyIndex(index, "getBodyResistance");
    auto r = resistances.find(index);
    if (r == resistances.end()) {
        tensor.clear();
        origin = Vec3();
        referencePositions.clear();
        return false;
    }
    tensor = r->second.tensor;
    origin = r->second.origin;
    referencePositions = r->second.referencePositions;
    return true;
}

void RigidBodyIntegrator::setBodyHydrodynamics(int index, const ResistanceTensor& model, const vector<Vec3>& referencePositions) {
    setBodyResistance(index, model.getMatrix(), model.getOrigin(), referencePositions);
}

void RigidBodyIntegrator::clearBodyResistance(int index) {
    checkNotBound("clearBodyResistance");
    checkBodyIndex(index, "clearBodyResistance");
    resistances.erase(index);
}

void RigidBodyIntegrator::setHydrodynamicInteractions(bool enabled) {
    checkNotBound("setHydrodynamicInteractions");
    hydrodynamicInteractions = enabled;
}

void RigidBodyIntegrator::setHydrodynamicSolver(HydrodynamicSolver solver) {
    if (solver != AutomaticSolver && solver != DenseSolver && solver != KrylovSolver && solver != SpectralSolver)
        throw OpenMMException(className()+"::setHydrodynamicSolver: unknown solver "+std::to_string((int) solver)+
                "; use AutomaticSolver (0), DenseSolver (1), KrylovSolver (2) or SpectralSolver (3)");
    hydrodynamicSolver = solver;
}

void RigidBodyIntegrator::setHydrodynamicTolerance(double tolerance) {
    if (!(tolerance >= 1e-12 && tolerance <= 0.1))
        throw OpenMMException(className()+"::setHydrodynamicTolerance: the tolerance is "+std::to_string(tolerance)+"; it must lie "
                "between 1e-12 (what the solves in double precision reach reliably) and 0.1");
    hydrodynamicTolerance = tolerance;
}

void RigidBodyIntegrator::setKrylovMinBlobs(int blobs) {
    if (blobs < -1)
        throw OpenMMException(className()+"::setKrylovMinBlobs: "+std::to_string(blobs)+" blobs; give a number of blobs, or -1 for the "
                "platform's default");
    krylovMinBlobs = blobs;
}

void RigidBodyIntegrator::setHydrodynamicMemoryBudget(double bytes) {
    if (!(bytes > 0 && std::isfinite(bytes)))
        throw OpenMMException(className()+"::setHydrodynamicMemoryBudget: the budget is "+std::to_string(bytes)+" bytes; give a positive, finite "
                "number of bytes (the default is 4 GiB, 4294967296)");
    hydrodynamicMemoryBudget = bytes;
}

void RigidBodyIntegrator::setBodyBlobs(int index, const vector<Vec3>& blobPositions, const vector<double>& blobRadii, const vector<Vec3>& referencePositions) {
    checkNotBound("setBodyBlobs");
    checkBodyIndex(index, "setBodyBlobs");
    string what = className()+"::setBodyBlobs: rigid body "+std::to_string(index);
    if (blobPositions.empty())
        throw OpenMMException(what+": no blobs were given (clearBodyBlobs() makes its particles with a radius its blobs again)");
    if (blobRadii.size() != blobPositions.size())
        throw OpenMMException(what+": "+std::to_string(blobPositions.size())+" blob positions but "+std::to_string(blobRadii.size())+" radii");
    for (int k = 0; k < (int) blobPositions.size(); k++) {
        if (!std::isfinite(blobPositions[k][0]) || !std::isfinite(blobPositions[k][1]) || !std::isfinite(blobPositions[k][2]))
            throw OpenMMException(what+": the position of blob "+std::to_string(k)+" is not finite");
        if (!(blobRadii[k] > 0) || !std::isfinite(blobRadii[k]))
            throw OpenMMException(what+": blob "+std::to_string(k)+" has radius "+std::to_string(blobRadii[k])+" nm; a blob's radius must be positive and finite");
    }
    checkReferencePositions(what, "the blobs need", "particles they were placed around", bodies[index], referencePositions);
    blobs[index] = {blobPositions, blobRadii, referencePositions};
}

bool RigidBodyIntegrator::getBodyBlobs(int index, vector<Vec3>& blobPositions, vector<double>& blobRadii, vector<Vec3>& referencePositions) const {
    checkBodyIndex(index, "getBodyBlobs");
    auto b = blobs.find(index);
    if (b == blobs.end()) {
        blobPositions.clear();
        blobRadii.clear();
        referencePositions.clear();
        return false;
    }
    blobPositions = b->second.positions;
    blobRadii = b->second.radii;
    referencePositions = b->second.referencePositions;
    return true;
}

void RigidBodyIntegrator::clearBodyBlobs(int index) {
    checkNotBound("clearBodyBlobs");
    checkBodyIndex(index, "clearBodyBlobs");
    blobs.erase(index);
}

void RigidBodyIntegrator::setParticleRadius(int particle, double radius) {
    checkNotBound("setParticleRadius");
    if (particle < 0)
        throw OpenMMException(className()+"::setParticleRadius: invalid particle index "+std::to_string(particle));
    if (!(radius > 0) || !std::isfinite(radius))
        throw OpenMMException(className()+"::setParticleRadius: particle "+std::to_string(particle)+" was given radius "+std::to_string(radius)+
                " nm; a hydrodynamic radius must be positive and finite");
    radii[particle] = radius;
}

double RigidBodyIntegrator::getParticleRadius(int particle) const {
    auto r = radii.find(particle);
    return (r == radii.end() ? -1.0 : r->second);
}

void RigidBodyIntegrator::initialize(ContextImpl& contextRef) {
    if (owner != NULL && &contextRef.getOwner() != owner)
        throw OpenMMException("This Integrator is already bound to a context");
    if (!(getStepSize() > 0) || !std::isfinite(getStepSize()))
        throw OpenMMException(className()+": the step size must be positive and finite, got "+std::to_string(getStepSize())+" ps");
    kernel = contextRef.getPlatform().createKernel(IntegrateRigidLangevinStepKernel::Name(), contextRef);
    kernel.getAs<IntegrateRigidLangevinStepKernel>().initialize(contextRef.getSystem(), *this);
    context = &contextRef;
    owner = &contextRef.getOwner();
}

void RigidBodyIntegrator::cleanup() {
    kernel = Kernel();
}

vector<string> RigidBodyIntegrator::getKernelNames() {
    return {IntegrateRigidLangevinStepKernel::Name()};
}

void RigidBodyIntegrator::stateChanged(State::DataType changed) {
    if (context != NULL)
        kernel.getAs<IntegrateRigidLangevinStepKernel>().stateChanged(*context, changed);
}

int RigidBodyIntegrator::getNumDegreesOfFreedom() const {
    if (context == NULL)
        throw OpenMMException(className()+"::getNumDegreesOfFreedom: this Integrator is not bound to a context (the count depends on the bodies' shapes)");
    return kernel.getAs<IntegrateRigidLangevinStepKernel>().getModel(*context).getNumDegreesOfFreedom();
}

int RigidBodyIntegrator::getNumBodyTypes() const {
    if (context == NULL)
        throw OpenMMException(className()+"::getNumBodyTypes: this Integrator is not bound to a context");
    return kernel.getAs<IntegrateRigidLangevinStepKernel>().getModel(*context).getNumTypes();
}

vector<int> RigidBodyIntegrator::getKrylovIterations() const {
    if (context == NULL)
        throw OpenMMException(className()+"::getKrylovIterations: this Integrator is not bound to a context");
    int noise, noiseSolve, friction;
    kernel.getAs<IntegrateRigidLangevinStepKernel>().getKrylovIterations(noise, noiseSolve, friction);
    return {noise, noiseSolve, friction};
}

void RigidBodyIntegrator::getRigidBodyStates(vector<Vec3>& centers, vector<double>& orientations, vector<Vec3>& velocities,
                                                 vector<Vec3>& angularVelocities) const {
    if (context == NULL)
        throw OpenMMException(className()+"::getRigidBodyStates: this Integrator is not bound to a context");
    IntegrateRigidLangevinStepKernel& k = kernel.getAs<IntegrateRigidLangevinStepKernel>();
    const RigidBodyModel& model = k.getModel(*context);
    vector<BodyState> states;
    k.getSynchronousBodyStates(*context, *this, states);
    int numBodies = getNumRigidBodies();
    centers.resize(numBodies);
    orientations.resize(9*numBodies);
    velocities.resize(numBodies);
    angularVelocities.resize(numBodies);
    for (int b = 0; b < numBodies; b++) {
        const BodyState& s = states[b];
        const BodyType& type = model.getType(model.getBodyType(b));
        centers[b] = s.position;
        velocities[b] = s.velocity;
        // Q (lab to body) has the principal axes as rows; A = Q^T. omega_lab = Q^T (j_k / I_k).
        Vec3 omega;
        for (int axis = 0; axis < 3; axis++) {
            double rate = (type.rotates(axis) ? s.angularMomentum[axis]/type.inertia[axis] : 0.0);
            for (int i = 0; i < 3; i++) {
                omega[i] += s.rotation[axis][i]*rate;
                orientations[9*b+3*i+axis] = s.rotation[axis][i];
            }
        }
        angularVelocities[b] = omega;
    }
}

vector<Vec3> RigidBodyIntegrator::getRigidBodyCoordinates(int index) const {
    if (context == NULL)
        throw OpenMMException(className()+"::getRigidBodyCoordinates: this Integrator is not bound to a context");
    if (index < 0 || index >= getNumRigidBodies())
        throw OpenMMException(className()+"::getRigidBodyCoordinates: there is no rigid body "+std::to_string(index)+" (the integrator has "+
                              std::to_string(getNumRigidBodies())+")");
    const RigidBodyModel& model = kernel.getAs<IntegrateRigidLangevinStepKernel>().getModel(*context);
    return model.getType(model.getBodyType(index)).coords;
}

void RigidBodyIntegrator::createCheckpoint(std::ostream& stream) const {
    kernel.getAs<IntegrateRigidLangevinStepKernel>().createCheckpoint(*context, stream);
}

void RigidBodyIntegrator::loadCheckpoint(std::istream& stream) {
    kernel.getAs<IntegrateRigidLangevinStepKernel>().loadCheckpoint(*context, stream);
}

namespace {

const char* RotationNames[3][3] = {{"q00", "q01", "q02"}, {"q10", "q11", "q12"}, {"q20", "q21", "q22"}};

/** 2: the body types come with the states, which are expressed in their frames. */
const int ParametersVersion = 2;

} // namespace

void RigidBodyIntegrator::serializeParameters(SerializationNode& node) const {
    // The exact body states, so that loading a State continues from them rather than refitting
    // bodies to particle positions, and the body types that define their frames: another Context,
    // building its types from other positions, may choose other principal axes.
    node.setIntProperty("version", ParametersVersion);
    if (context == NULL)
        return;
    IntegrateRigidLangevinStepKernel& k = kernel.getAs<IntegrateRigidLangevinStepKernel>();
    vector<BodyState> states;
    k.getBodyStates(*context, states);
    k.getModel(*context).writeTypes(node);
    SerializationNode& bodiesNode = node.createChildNode("BodyStates");
    for (const BodyState& s : states) {
        SerializationNode& b = bodiesNode.createChildNode("Body");
        b.setDoubleProperty("x", s.position[0]).setDoubleProperty("y", s.position[1]).setDoubleProperty("z", s.position[2]);
        b.setDoubleProperty("vx", s.velocity[0]).setDoubleProperty("vy", s.velocity[1]).setDoubleProperty("vz", s.velocity[2]);
        b.setDoubleProperty("jx", s.angularMomentum[0]).setDoubleProperty("jy", s.angularMomentum[1]).setDoubleProperty("jz", s.angularMomentum[2]);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                b.setDoubleProperty(RotationNames[i][j], s.rotation[i][j]);
    }
}

void RigidBodyIntegrator::deserializeParameters(const SerializationNode& node) {
    int version = node.getIntProperty("version");
    if (version != ParametersVersion)
        throw OpenMMException(className()+": the State's integrator parameters have version "+std::to_string(version)+", this plugin reads version "+
                std::to_string(ParametersVersion)+" (States of version 1 lack the body types their states refer to). Load it with "
                "setPositions() and setVelocities() instead of setState(), or save it again with this version");
    const SerializationNode* bodyStates = NULL;
    const SerializationNode* types = NULL;
    for (const SerializationNode& child : node.getChildren()) {
        if (child.getName() == "BodyStates")
            bodyStates = &child;
        if (child.getName() == "BodyTypes")
            types = &child;
    }
    if (context == NULL || bodyStates == NULL)
        return;
    if (types == NULL)
        throw OpenMMException(className()+": the State has body states but no body types");
    vector<BodyState> states;
    try {
        for (const SerializationNode& b : bodyStates->getChildren()) {
            BodyState s;
            s.position = Vec3(b.getDoubleProperty("x"), b.getDoubleProperty("y"), b.getDoubleProperty("z"));
            s.velocity = Vec3(b.getDoubleProperty("vx"), b.getDoubleProperty("vy"), b.getDoubleProperty("vz"));
            s.angularMomentum = Vec3(b.getDoubleProperty("jx"), b.getDoubleProperty("jy"), b.getDoubleProperty("jz"));
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    s.rotation[i][j] = b.getDoubleProperty(RotationNames[i][j]);
            states.push_back(s);
        }
    }
    catch (const OpenMMException& e) {
        throw OpenMMException(className()+string(": the State's body states are incomplete: ")+e.what());
    }
    kernel.getAs<IntegrateRigidLangevinStepKernel>().restoreFromState(*context, node, states);
}

