// What every rigid-body integrator's XmlSerializer proxy writes and reads: the bath, the bodies and
// their hydrodynamics (RigidBodyIntegrator).

#include "internal/RigidBodyIntegratorSerialization.h"
#include "openmm/OpenMMException.h"
#include "openmm/serialization/SerializationNode.h"

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

SerializationNode& writePosition(SerializationNode& node, const Vec3& r) {
    return node.setDoubleProperty("x", r[0]).setDoubleProperty("y", r[1]).setDoubleProperty("z", r[2]);
}

Vec3 readPosition(const SerializationNode& node) {
    return Vec3(node.getDoubleProperty("x"), node.getDoubleProperty("y"), node.getDoubleProperty("z"));
}

} // namespace

void RigidLangevinPlugin::writeRigidBodyIntegrator(const RigidBodyIntegrator& integrator, SerializationNode& node) {
    node.setDoubleProperty("stepSize", integrator.getStepSize());
    node.setDoubleProperty("constraintTolerance", integrator.getConstraintTolerance());
    node.setDoubleProperty("temperature", integrator.getTemperature());
    node.setDoubleProperty("viscosity", integrator.getViscosity());
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
    node.setDoubleProperty("hydrodynamicMemoryBudget", integrator.getHydrodynamicMemoryBudget());
    double wallHeight;
    node.setBoolProperty("wall", integrator.getWall(wallHeight)).setDoubleProperty("wallHeight", wallHeight);
    SerializationNode& radii = node.createChildNode("Radii");
    for (auto& r : integrator.getParticleRadii())
        radii.createChildNode("Particle").setIntProperty("index", r.first).setDoubleProperty("radius", r.second);
}

void RigidLangevinPlugin::readRigidBodyIntegrator(const SerializationNode& node, int version, int interactionsVersion, int settingsVersion,
                                                  int wallVersion, RigidBodyIntegrator& integrator) {
    integrator.setConstraintTolerance(node.getDoubleProperty("constraintTolerance"));
    integrator.setRandomNumberSeed(node.getIntProperty("randomSeed"));
    integrator.setIntegrationForceGroups(node.getIntProperty("integrationForceGroups", 0xFFFFFFFF));
    for (const SerializationNode& body : node.getChildNode("Bodies").getChildren()) {
        vector<int> particles;
        for (const SerializationNode& child : body.getChildren())
            if (child.getName() == "Particle")
                particles.push_back(child.getIntProperty("index"));
        int index = integrator.addRigidBody(particles);
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
            integrator.setBodyResistance(index, tensor, readPosition(resistance), reference);
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
            integrator.setBodyBlobs(index, positions, radii, reference);
        }
    }
    if (version >= interactionsVersion)
        integrator.setHydrodynamicInteractions(node.getBoolProperty("hydrodynamicInteractions"));
    if (version >= settingsVersion) {
        integrator.setHydrodynamicSolver((RigidBodyIntegrator::HydrodynamicSolver) node.getIntProperty("hydrodynamicSolver"));
        integrator.setHydrodynamicTolerance(node.getDoubleProperty("hydrodynamicTolerance"));
        integrator.setKrylovMinBlobs(node.getIntProperty("krylovMinBlobs"));
    }
    // Added without a new version: files written before it read with the default.
    integrator.setHydrodynamicMemoryBudget(node.getDoubleProperty("hydrodynamicMemoryBudget", integrator.getHydrodynamicMemoryBudget()));
    for (const SerializationNode& r : node.getChildNode("Radii").getChildren())
        integrator.setParticleRadius(r.getIntProperty("index"), r.getDoubleProperty("radius"));
    if (version >= wallVersion && node.getBoolProperty("wall"))
        integrator.setWall(node.getDoubleProperty("wallHeight"));
}
