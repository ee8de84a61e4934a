#ifndef RIGIDLANGEVIN_STICKY_DIPOLE_FORCE_PROXY_H_
#define RIGIDLANGEVIN_STICKY_DIPOLE_FORCE_PROXY_H_

#include "internal/windowsExportRigidLangevin.h"
#include "openmm/serialization/SerializationProxy.h"

namespace RigidLangevinPlugin {

/** The XmlSerializer proxy of StickyDipoleForce: sites, exclusions, cutoff and reaction field. Version 1. */
class OPENMM_EXPORT_RIGIDLANGEVIN StickyDipoleForceProxy : public OpenMM::SerializationProxy {
public:
    StickyDipoleForceProxy();
    void serialize(const void* object, OpenMM::SerializationNode& node) const;
    void* deserialize(const OpenMM::SerializationNode& node) const;
};

} // namespace RigidLangevinPlugin

#endif /*RIGIDLANGEVIN_STICKY_DIPOLE_FORCE_PROXY_H_*/
