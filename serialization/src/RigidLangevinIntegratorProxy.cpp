#include "RigidLangevinIntegratorProxy.h"
#include "RigidLangevinIntegrator.h"
#include "internal/RigidBodyIntegratorSerialization.h"
#include "openmm/OpenMMException.h"
#include "openmm/serialization/SerializationNode.h"
#include <memory>

using namespace RigidLangevinPlugin;
using namespace OpenMM;

namespace {

/** 2: an explicit tensor comes with the positions of the body's particles it belongs to.
 *  3: hydrodynamic interactions (on or off) and bodies' explicit blobs. Version 2 is read as
 *     without interactions and blobs, which is what it described.
 *  4: the hydrodynamic solver, its tolerance and the size from which it is matrix-free. Versions 2
 *     and 3 are read with the defaults, which is what they ran with.
 *  5: a no-slip wall (read as none before). */
const int Version = 5;

} // namespace

RigidLangevinIntegratorProxy::RigidLangevinIntegratorProxy() : SerializationProxy("RigidLangevinIntegrator") {
}

void RigidLangevinIntegratorProxy::serialize(const void* object, SerializationNode& node) const {
    node.setIntProperty("version", Version);
    const RigidLangevinIntegrator& integrator = *reinterpret_cast<const RigidLangevinIntegrator*>(object);
    node.setIntProperty("scheme", integrator.getScheme());
    writeRigidBodyIntegrator(integrator, node);
}

void* RigidLangevinIntegratorProxy::deserialize(const SerializationNode& node) const {
    int version = node.getIntProperty("version");
    if (version < 2 || version > Version)
        throw OpenMMException("RigidLangevinIntegratorProxy: unsupported version number "+std::to_string(version)+" (this plugin reads 2 to "+
                std::to_string(Version)+"; version 1 tied explicit tensors to whatever positions a Context first had)");
    std::unique_ptr<RigidLangevinIntegrator> integrator(new RigidLangevinIntegrator(node.getDoubleProperty("temperature"),
            node.getDoubleProperty("viscosity"), node.getDoubleProperty("stepSize")));
    integrator->setScheme((RigidLangevinIntegrator::Scheme) node.getIntProperty("scheme"));
    readRigidBodyIntegrator(node, version, 3, 4, 5, *integrator);
    return integrator.release();
}
