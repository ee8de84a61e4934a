#include "RigidLangevinIntegratorProxy.h"
#include "RigidLangevinIntegrator.h"
#include "openmm/OpenMMException.h"
#include "openmm/serialization/SerializationNode.h"
#include <memory>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

namespace {

const SerializationNode* findChild(const SerializationNode& node, const std::string& name) {
    for (const SerializationNode& child : node.getChildren())
        if (child.getName() == name)
            return &child;
    return NULL;
}

/** 2: an explicit tensor comes with the positions of the body's particles it belongs to.
 *  3: hydrodynamic interactions (on or off) and bodies' explicit blobs. Version 2 is read as
 *     without interactions and blobs, which is what it described.
 *  4: the hydrodynamic solver, its tolerance and the size from which it is matrix-free. Versions 2
 *     and 3 are read with the defaults, which is what they ran with. */
const int Version = 4;

SerializationNode& writePosition(SerializationNode& node, const Vec3& r) {
    return node.setDoubleProperty("x", r[0]).setDoubleProperty("y", r[1]).setDoubleProperty("z", r[2]);
}

Vec3 readPosition(const SerializationNode& node) {
    return Vec3(node.getDoubleProperty("x"), node.getDoubleProperty("y"), node.getDoubleProperty("z"));
}

} // namespace

RigidLangevinIntegratorProxy::RigidLangevinIntegratorProxy() : SerializationProxy("RigidLangevinIntegrator") {
}

void RigidLangevinIntegratorProxy::serialize(const void* object, SerializationNode& node) const {
    node.setIntProperty("version", Version);
    const RigidLangevinIntegrator& integrator = *reinterpret_cast<const RigidLangevinIntegrator*>(object);
    node.setDoubleProperty("stepSize", integrator.getStepSize());
    node.setDoubleProperty("constraintTolerance", integrator.getConstraintTolerance());
    node.setDoubleProperty("temperature", integrator.getTemperature());
    node.setDoubleProperty("viscosity", integrator.getViscosity());
    node.setIntProperty("scheme", integrator.getScheme());
    node.setIntProperty("randomSeed", integrator.getRandomNumberSeed());
    node.setIntProperty("integrationForceGroups", integrator.getIntegrationForceGroups());
    SerializationNode& bodies = node.createChildNode("Bodies");
    for (int b = 0; b < integrator.getNumRigidBodies(); b++) {
        SerializationNode& body = bodies.createChildNode("Body");
        for (int p : integrator.getRigidBodyParticles(b))
            body.createChildNode("Particle").setIntProperty("index", p);
        vector<double> tensor;
        Vec3 origin;
        vector<Vec3> reference;
        if (integrator.getBodyResistance(b, tensor, origin, reference)) {
            SerializationNode& resistance = body.createChildNode("Resistance");
            writePosition(resistance, origin);
            for (double value : tensor)
                resistance.createChildNode("Value").setDoubleProperty("v", value);
            for (const Vec3& r : reference)
                writePosition(resistance.createChildNode("ReferencePosition"), r);
        }
        vector<Vec3> blobPositions;
        vector<double> blobRadii;
        if (integrator.getBodyBlobs(b, blobPositions, blobRadii, reference)) {
            SerializationNode& blobs = body.createChildNode("Blobs");
            for (int i = 0; i < (int) blobPositions.size(); i++)
                writePosition(blobs.createChildNode("Blob"), blobPositions[i]).setDoubleProperty("radius", blobRadii[i]);
            for (const Vec3& r : reference)
                writePosition(blobs.createChildNode("ReferencePosition"), r);
        }
    }
    node.setBoolProperty("hydrodynamicInteractions", integrator.getHydrodynamicInteractions());
    node.setIntProperty("hydrodynamicSolver", integrator.getHydrodynamicSolver());
    node.setDoubleProperty("hydrodynamicTolerance", integrator.getHydrodynamicTolerance());
    node.setIntProperty("krylovMinBlobs", integrator.getKrylovMinBlobs());
    SerializationNode& radii = node.createChildNode("Radii");
    for (auto& r : integrator.getParticleRadii())
        radii.createChildNode("Particle").setIntProperty("index", r.first).setDoubleProperty("radius", r.second);
}

void* RigidLangevinIntegratorProxy::deserialize(const SerializationNode& node) const {
    int version = node.getIntProperty("version");
    if (version < 2 || version > Version)
        throw OpenMMException("RigidLangevinIntegratorProxy: unsupported version number "+std::to_string(version)+" (this plugin reads 2 to "+
                std::to_string(Version)+"; version 1 tied explicit tensors to whatever positions a Context first had)");
    std::unique_ptr<RigidLangevinIntegrator> integrator(new RigidLangevinIntegrator(node.getDoubleProperty("temperature"),
            node.getDoubleProperty("viscosity"), node.getDoubleProperty("stepSize")));
    integrator->setConstraintTolerance(node.getDoubleProperty("constraintTolerance"));
    integrator->setScheme((RigidLangevinIntegrator::Scheme) node.getIntProperty("scheme"));
    integrator->setRandomNumberSeed(node.getIntProperty("randomSeed"));
    integrator->setIntegrationForceGroups(node.getIntProperty("integrationForceGroups", 0xFFFFFFFF));
    for (const SerializationNode& body : node.getChildNode("Bodies").getChildren()) {
        vector<int> particles;
        for (const SerializationNode& child : body.getChildren())
            if (child.getName() == "Particle")
                particles.push_back(child.getIntProperty("index"));
        int index = integrator->addRigidBody(particles);
        const SerializationNode* resistanceNode = findChild(body, "Resistance");
        if (resistanceNode != NULL) {
            const SerializationNode& resistance = *resistanceNode;
            vector<double> tensor;
            vector<Vec3> reference;
            for (const SerializationNode& child : resistance.getChildren()) {
                if (child.getName() == "Value")
                    tensor.push_back(child.getDoubleProperty("v"));
                else if (child.getName() == "ReferencePosition")
                    reference.push_back(readPosition(child));
            }
            integrator->setBodyResistance(index, tensor, readPosition(resistance), reference);
        }
        const SerializationNode* blobsNode = findChild(body, "Blobs");
        if (blobsNode != NULL) {
            vector<Vec3> positions, reference;
            vector<double> radii;
            for (const SerializationNode& child : blobsNode->getChildren()) {
                if (child.getName() == "Blob") {
                    positions.push_back(readPosition(child));
                    radii.push_back(child.getDoubleProperty("radius"));
                }
                else if (child.getName() == "ReferencePosition")
                    reference.push_back(readPosition(child));
            }
            integrator->setBodyBlobs(index, positions, radii, reference);
        }
    }
    if (version >= 3)
        integrator->setHydrodynamicInteractions(node.getBoolProperty("hydrodynamicInteractions"));
    if (version >= 4) {
        integrator->setHydrodynamicSolver((RigidLangevinIntegrator::HydrodynamicSolver) node.getIntProperty("hydrodynamicSolver"));
        integrator->setHydrodynamicTolerance(node.getDoubleProperty("hydrodynamicTolerance"));
        integrator->setKrylovMinBlobs(node.getIntProperty("krylovMinBlobs"));
    }
    for (const SerializationNode& r : node.getChildNode("Radii").getChildren())
        integrator->setParticleRadius(r.getIntProperty("index"), r.getDoubleProperty("radius"));
    return integrator.release();
}
