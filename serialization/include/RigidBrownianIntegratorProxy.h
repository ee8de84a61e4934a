#ifndef RIGID_BROWNIAN_INTEGRATOR_PROXY_H_
#define RIGID_BROWNIAN_INTEGRATOR_PROXY_H_

#include "internal/windowsExportRigidLangevin.h"
#include "openmm/serialization/SerializationProxy.h"

namespace RigidLangevinPlugin {

/** The XmlSerializer proxy of RigidBrownianIntegrator: its bath, bodies and hydrodynamics (as every rigid-body integrator's). */
class OPENMM_EXPORT_RIGIDLANGEVIN RigidBrownianIntegratorProxy : public OpenMM::SerializationProxy {
public:
    RigidBrownianIntegratorProxy();
    void serialize(const void* object, OpenMM::SerializationNode& node) const;
    void* deserialize(const OpenMM::SerializationNode& node) const;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_BROWNIAN_INTEGRATOR_PROXY_H_*/
