#ifndef RIGID_LANGEVIN_INTEGRATOR_PROXY_H_
#define RIGID_LANGEVIN_INTEGRATOR_PROXY_H_

#include "internal/windowsExportRigidLangevin.h"
#include "openmm/serialization/SerializationProxy.h"

namespace RigidLangevinPlugin {

/**
 * The XmlSerializer proxy of RigidLangevinIntegrator: parameters, bodies, explicit resistance
 * tensors and radii. Version 1.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN RigidLangevinIntegratorProxy : public OpenMM::SerializationProxy {
public:
    RigidLangevinIntegratorProxy();
    void serialize(const void* object, OpenMM::SerializationNode& node) const;
    void* deserialize(const OpenMM::SerializationNode& node) const;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_INTEGRATOR_PROXY_H_*/
