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
    /** The number of values parameterValues() gives. */
    static const int NumParameterValues = 10;
    /**
     * A site's parameters as the kernels lay them out: sigma, epsilon, dipole, nu0, rL, rU, nu0',
     * rL', rU', w0 (the GPU pair term and the CPU lanes index them in this order).
     */
    static std::vector<double> parameterValues(const StickyDipoleForce::SiteParameters& p) {
        return {p.sigma, p.epsilon, p.dipole, p.nu0, p.rL, p.rU, p.nu0Prime, p.rLPrime, p.rUPrime, p.w0};
    }
    const StickyDipoleForce& getOwner() const {
        return owner;
    }
    void updateContextState(OpenMM::ContextImpl& /*context*/, bool& /*forcesInvalid*/) {
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
