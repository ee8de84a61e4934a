#ifndef RIGIDLANGEVIN_STICKY_DIPOLE_FORCE_IMPL_H_
#define RIGIDLANGEVIN_STICKY_DIPOLE_FORCE_IMPL_H_

#include "StickyDipoleForce.h"
#include "openmm/Kernel.h"
#include "openmm/internal/ForceImpl.h"
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace RigidLangevinPlugin {

/** The internal implementation of StickyDipoleForce: checks the force against the System, runs its kernel. */
class OPENMM_EXPORT_RIGIDLANGEVIN StickyDipoleForceImpl : public OpenMM::ForceImpl {
public:
    explicit StickyDipoleForceImpl(const StickyDipoleForce& owner) : owner(owner) {
    }
    void initialize(OpenMM::ContextImpl& context);
    const StickyDipoleForce& getOwner() const {
        return owner;
    }
    void updateContextState(OpenMM::ContextImpl& context, bool& forcesInvalid) {
    }
    double calcForcesAndEnergy(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy, int groups);
    std::map<std::string, double> getDefaultParameters() {
        return std::map<std::string, double>();
    }
    std::vector<std::string> getKernelNames();
    /** A site and its reference particles move as one molecule (OpenMM keeps them in one periodic image). */
    std::vector<std::pair<int, int> > getBondedParticles() const;
private:
    const StickyDipoleForce& owner;
    OpenMM::Kernel kernel;
};

} // namespace RigidLangevinPlugin

#endif /*RIGIDLANGEVIN_STICKY_DIPOLE_FORCE_IMPL_H_*/
