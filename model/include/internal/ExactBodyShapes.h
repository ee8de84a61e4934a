#ifndef RIGID_LANGEVIN_EXACT_BODY_SHAPES_H_
#define RIGID_LANGEVIN_EXACT_BODY_SHAPES_H_

#include "internal/BodyParticleLists.h"
#include "openmm/System.h"
#include "openmm/Vec3.h"
#include <memory>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * Makes the shapes a body type is built from obey the System's own rules: the distances its
 * constraints fix (rigid water, as SETTLE keeps them) and the places its virtual sites' definitions
 * give. A shape read from a file is rounded; a body built from it would hold its sites and
 * constrained distances slightly off, so that OpenMM's virtual-site placement and the body disagree.
 *
 * OpenMM's own algorithms do the work (SETTLE or CCMA, and its virtual-site code) on a Reference
 * Context holding only the particles of bodies that have a constraint or a virtual site, with those
 * constraints and sites and no forces.
 */
class ExactBodyShapes {
public:
    /**
     * @param system        the System
     * @param bodyParticles the particles of each rigid body defined by the user
     * @param integrator    the integrator's class name, which begins an error message
     */
    ExactBodyShapes(const OpenMM::System& system, const BodyParticleLists& bodyParticles, const std::string& integrator);
    ~ExactBodyShapes();
    /** Whether any body has a constraint or a virtual site, so that apply() changes anything. */
    bool isNeeded() const {
        return !particles.empty();
    }
    /**
     * Move the particles of constrained bodies so that their constraints hold exactly (mass-weighted,
     * keeping each body's centre of mass) and put their virtual sites where their definitions say.
     *
     * @param positions  every particle's position, with each body whole (not split by the periodic box)
     */
    void apply(std::vector<OpenMM::Vec3>& positions) const;
private:
    std::vector<int> particles;  // System index of each particle of the small System
    std::unique_ptr<OpenMM::System> shapes;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_EXACT_BODY_SHAPES_H_*/
