#include "internal/StickyDipoleForceImpl.h"
#include "RigidLangevinKernels.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include <cmath>
#include <set>
#include <string>

using namespace RigidLangevinPlugin;
using namespace OpenMM;

namespace {

bool positiveOrZero(double x) {
    return std::isfinite(x) && x >= 0;
}

} // namespace

void StickyDipoleForceImpl::initialize(ContextImpl& context) {
    const System& system = context.getSystem();
    int numParticles = system.getNumParticles();
    std::set<int> siteParticles;
    for (int i = 0; i < owner.getNumSites(); i++) {
        int particle, ref1, ref2;
        StickyDipoleForce::SiteParameters p;
        owner.getSiteParameters(i, particle, ref1, ref2, p);
        std::string site = "StickyDipoleForce: site "+std::to_string(i);
        for (int index : {particle, ref1, ref2})
            if (index < 0 || index >= numParticles)
                throw OpenMMException(site+" refers to particle "+std::to_string(index)+", but the System has "+std::to_string(numParticles)+" particles");
        if (ref1 == particle || ref2 == particle || ref1 == ref2)
            throw OpenMMException(site+": its particle ("+std::to_string(particle)+") and its two reference particles ("+std::to_string(ref1)+", "
                                  +std::to_string(ref2)+") must be three different particles");
        if (!siteParticles.insert(particle).second)
            throw OpenMMException(site+": particle "+std::to_string(particle)+" carries another site already");
        if (!positiveOrZero(p.sigma) || !positiveOrZero(p.epsilon) || !std::isfinite(p.dipole) || !std::isfinite(p.nu0) || !std::isfinite(p.nu0Prime)
                || !std::isfinite(p.w0))
            throw OpenMMException(site+": sigma and epsilon must be finite and not negative, dipole, nu0, nu0' and w0 finite");
        // A switch from 1 to 0 over no distance would be a step in the energy; without its term it does not matter.
        auto switchOk = [] (double lower, double upper, double strength) {
            return lower >= 0 && std::isfinite(upper) && (lower < upper || (strength == 0 && lower <= upper));
        };
        if (!switchOk(p.rL, p.rU, p.nu0) || !switchOk(p.rLPrime, p.rUPrime, p.nu0Prime))
            throw OpenMMException(site+": the sticky switches need 0 <= rL < rU and 0 <= rL' < rU' (or equal where nu0 or nu0' is 0; got rL = "
                                  +std::to_string(p.rL)+", rU = "+std::to_string(p.rU)+", rL' = "+std::to_string(p.rLPrime)+", rU' = "
                                  +std::to_string(p.rUPrime)+" nm)");
    }
    std::set<std::pair<int, int> > excluded;
    for (int i = 0; i < owner.getNumExclusions(); i++) {
        int a, b;
        owner.getExclusionSites(i, a, b);
        if (a < 0 || b < 0 || a >= owner.getNumSites() || b >= owner.getNumSites() || a == b)
            throw OpenMMException("StickyDipoleForce: exclusion "+std::to_string(i)+" names sites "+std::to_string(a)+" and "+std::to_string(b)
                                  +"; they must be two different sites among the "+std::to_string(owner.getNumSites()));
        if (!excluded.insert(std::make_pair(std::min(a, b), std::max(a, b))).second)
            throw OpenMMException("StickyDipoleForce: exclusion "+std::to_string(i)+" repeats the exclusion of sites "+std::to_string(a)+" and "+std::to_string(b));
    }
    if (owner.getNonbondedMethod() != StickyDipoleForce::NoCutoff) {
        double cutoff = owner.getCutoffDistance();
        if (!(cutoff > 0 && std::isfinite(cutoff)))
            throw OpenMMException("StickyDipoleForce: the cutoff distance must be positive (got "+std::to_string(cutoff)+" nm)");
        if (owner.getUseSwitchingFunction() && !(owner.getSwitchingDistance() >= 0 && owner.getSwitchingDistance() < cutoff))
            throw OpenMMException("StickyDipoleForce: the switching distance ("+std::to_string(owner.getSwitchingDistance())
                                  +" nm) must lie between 0 and the cutoff ("+std::to_string(cutoff)+" nm)");
        if (!(owner.getReactionFieldDielectric() >= 1))
            throw OpenMMException("StickyDipoleForce: the reaction field dielectric must be at least 1 (1: no reaction field)");
        if (owner.getNonbondedMethod() == StickyDipoleForce::CutoffPeriodic) {
            Vec3 a, b, c;
            system.getDefaultPeriodicBoxVectors(a, b, c);
            double half = 0.5*std::min(a[0], std::min(b[1], c[2]));
            if (cutoff > half)
                throw OpenMMException("StickyDipoleForce: the cutoff ("+std::to_string(cutoff)+" nm) exceeds half the periodic box ("+std::to_string(half)+" nm)");
        }
    }
    kernel = context.getPlatform().createKernel(CalcStickyDipoleForceKernel::Name(), context);
    kernel.getAs<CalcStickyDipoleForceKernel>().initialize(system, owner);
}

double StickyDipoleForceImpl::calcForcesAndEnergy(ContextImpl& context, bool includeForces, bool includeEnergy, int groups) {
    if ((groups&(1<<owner.getForceGroup())) != 0)
        return kernel.getAs<CalcStickyDipoleForceKernel>().execute(context, includeForces, includeEnergy);
    return 0.0;
}

std::vector<std::string> StickyDipoleForceImpl::getKernelNames() {
    return {CalcStickyDipoleForceKernel::Name()};
}

std::vector<std::pair<int, int> > StickyDipoleForceImpl::getBondedParticles() const {
    std::vector<std::pair<int, int> > bonds;
    for (int i = 0; i < owner.getNumSites(); i++) {
        int particle, ref1, ref2;
        StickyDipoleForce::SiteParameters p;
        owner.getSiteParameters(i, particle, ref1, ref2, p);
        bonds.push_back(std::make_pair(particle, ref1));
        bonds.push_back(std::make_pair(particle, ref2));
    }
    return bonds;
}
