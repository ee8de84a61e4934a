#include "RigidBrownianIntegratorProxy.h"
#include "RigidBrownianIntegrator.h"
#include "internal/RigidBodyIntegratorSerialization.h"
#include "openmm/OpenMMException.h"
#include "openmm/serialization/SerializationNode.h"
#include <memory>

using namespace RigidLangevinPlugin;
using namespace OpenMM;

namespace {

/** 1: the first. */
const int Version = 1;

} // namespace

RigidBrownianIntegratorProxy::RigidBrownianIntegratorProxy() : SerializationProxy("RigidBrownianIntegrator") {
}

void RigidBrownianIntegratorProxy::serialize(const void* object, SerializationNode& node) const {
    node.setIntProperty("version", Version);
    writeRigidBodyIntegrator(*reinterpret_cast<const RigidBrownianIntegrator*>(object), node);
}

void* RigidBrownianIntegratorProxy::deserialize(const SerializationNode& node) const {
    int version = node.getIntProperty("version");
    if (version != Version)
        throw OpenMMException("RigidBrownianIntegratorProxy: unsupported version number "+std::to_string(version)+" (this plugin reads "+
                std::to_string(Version)+")");
    std::unique_ptr<RigidBrownianIntegrator> integrator(new RigidBrownianIntegrator(node.getDoubleProperty("temperature"),
            node.getDoubleProperty("viscosity"), node.getDoubleProperty("stepSize")));
    readRigidBodyIntegrator(node, version, 1, 1, 1, *integrator);
    return integrator.release();
}
