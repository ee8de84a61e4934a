#ifndef RIGID_BODY_INTEGRATOR_SERIALIZATION_H_
#define RIGID_BODY_INTEGRATOR_SERIALIZATION_H_

#include "RigidBodyIntegrator.h"
#include "internal/windowsExportRigidLangevin.h"
#include "openmm/serialization/SerializationNode.h"

namespace RigidLangevinPlugin {

/** Write what every rigid-body integrator has (RigidBodyIntegrator: the bath, bodies and hydrodynamics) into a proxy's node. */
OPENMM_EXPORT_RIGIDLANGEVIN void writeRigidBodyIntegrator(const RigidBodyIntegrator& integrator, OpenMM::SerializationNode& node);

/**
 * Read what writeRigidBodyIntegrator() wrote into an integrator made from the node's temperature,
 * viscosity and step size, at the proxy's version: the versions from which the node has hydrodynamic
 * interactions, the solver's settings and the wall (older ones are read with the defaults).
 */
OPENMM_EXPORT_RIGIDLANGEVIN void readRigidBodyIntegrator(const OpenMM::SerializationNode& node, int version, int interactionsVersion,
                                                         int settingsVersion, int wallVersion, RigidBodyIntegrator& integrator);

} // namespace RigidLangevinPlugin

#endif /*RIGID_BODY_INTEGRATOR_SERIALIZATION_H_*/
