#ifndef RIGID_LANGEVIN_RIGID_BODY_DESCRIPTION_H_
#define RIGID_LANGEVIN_RIGID_BODY_DESCRIPTION_H_

#include "openmm/Vec3.h"
#include <map>
#include <string>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The rigid bodies of a System as a user describes them, with nothing of an integrator or a
 * Context: the particles of each body, an explicit resistance tensor and hydrodynamic blobs where
 * they were given, hydrodynamic radii set by hand, and whether bodies interact through the solvent. RigidBodyModel is built from this and the System, so that the
 * model depends on plain data and the integrator (the public API) on neither.
 */
struct RigidBodyDescription {
    struct Body {
        std::vector<int> particles;
        /** An explicit 6x6 resistance tensor per unit viscosity (row-major), or empty for one from the radii. */
        std::vector<double> resistance;
        /** The point the explicit tensor is given about. */
        OpenMM::Vec3 resistanceOrigin;
        /** The positions of the body's particles the explicit tensor was computed for. */
        std::vector<OpenMM::Vec3> resistanceReference;
        /** Hydrodynamic blobs given explicitly (centres and radii, nm), or empty for the particles with a radius. */
        std::vector<OpenMM::Vec3> blobPositions;
        std::vector<double> blobRadii;
        /** The positions of the body's particles the blobs were given with. */
        std::vector<OpenMM::Vec3> blobReference;
    };
    std::vector<Body> bodies;
    /** Whether bodies feel each other through the solvent (hydrodynamic interactions). */
    bool hydrodynamicInteractions = false;
    /** Hydrodynamic radii set by hand, by particle index; others come from the System's NonbondedForce. */
    std::map<int, double> particleRadii;
    /** The integrator's class name, which begins the model's error messages. */
    std::string integratorName = "RigidLangevinIntegrator";
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_RIGID_BODY_DESCRIPTION_H_*/
