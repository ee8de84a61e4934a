#include "StickyDipoleForce.h"
#include "internal/StickyDipoleForceImpl.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <string>

using namespace RigidLangevinPlugin;
using namespace OpenMM;

namespace {

// Published units: lengths in Angstroms, energies in kcal/mol, dipoles in Debye.
const double ANGSTROM = 0.1, KCAL = 4.184, DEBYE = 0.0208194;

void checkIndex(int index, int size, const std::string& what) {
    if (index < 0 || index >= size)
        throw OpenMMException("StickyDipoleForce: "+what+" "+std::to_string(index)+" is out of range (there are "+std::to_string(size)+")");
}

} // namespace

StickyDipoleForce::SiteParameters::SiteParameters() : sigma(0), epsilon(0), dipole(0), nu0(0), rL(0), rU(0), nu0Prime(0),
        rLPrime(0), rUPrime(0), w0(0) {
}

StickyDipoleForce::SiteParameters StickyDipoleForce::getModelParameters(const std::string& model) {
    // sigma (A), epsilon (kcal/mol), dipole (D), nu0 = nu0' (kcal/mol), rL, rU, rL', rU' (A); w0 = 0.07715.
    // SSD: Liu & Ichiye (1996) as revised with SSD1 by Tan et al. (2003); SSD/E, SSD/RF: Fennell &
    // Gezelter (2004). The same values are in OpenMD's forceFields/Water.frc.
    struct Row {
        const char* name;
        double sigma, epsilon, dipole, nu0, rL, rU, rLPrime, rUPrime;
    };
    const Row rows[] = {
        {"SSD", 3.051, 0.152, 2.35, 3.7284, 2.75, 3.35, 2.75, 4.0},
        {"SSD1", 3.016, 0.152, 2.35, 3.6613, 2.75, 3.35, 2.75, 4.0},
        {"SSD/E", 3.035, 0.152, 2.42, 3.90, 2.40, 3.80, 2.75, 3.35},
        {"SSD/RF", 3.019, 0.152, 2.48, 3.90, 2.40, 3.80, 2.75, 3.35},
    };
    for (const Row& row : rows)
        if (model == row.name) {
            SiteParameters p;
            p.sigma = row.sigma*ANGSTROM;
            p.epsilon = row.epsilon*KCAL;
            p.dipole = row.dipole*DEBYE;
            p.nu0 = p.nu0Prime = row.nu0*KCAL;
            p.rL = row.rL*ANGSTROM;
            p.rU = row.rU*ANGSTROM;
            p.rLPrime = row.rLPrime*ANGSTROM;
            p.rUPrime = row.rUPrime*ANGSTROM;
            p.w0 = 0.07715;
            return p;
        }
    throw OpenMMException("StickyDipoleForce: unknown model '"+model+"'; the models are SSD, SSD1, SSD/E and SSD/RF");
}

StickyDipoleForce::StickyDipoleForce() : method(NoCutoff), cutoff(1.0), switchingDistance(-1.0), reactionFieldDielectric(80.0),
        useSwitching(false) {
}

int StickyDipoleForce::addSite(int particle, int reference1, int reference2, const SiteParameters& parameters) {
    Site site = {particle, reference1, reference2, parameters};
    sites.push_back(site);
    return sites.size()-1;
}

void StickyDipoleForce::getSiteParameters(int index, int& particle, int& reference1, int& reference2, SiteParameters& parameters) const {
    checkIndex(index, sites.size(), "site");
    particle = sites[index].particle;
    reference1 = sites[index].reference1;
    reference2 = sites[index].reference2;
    parameters = sites[index].parameters;
}

void StickyDipoleForce::setSiteParameters(int index, int particle, int reference1, int reference2, const SiteParameters& parameters) {
    checkIndex(index, sites.size(), "site");
    Site site = {particle, reference1, reference2, parameters};
    sites[index] = site;
}

int StickyDipoleForce::addExclusion(int site1, int site2) {
    exclusions.push_back(std::make_pair(site1, site2));
    return exclusions.size()-1;
}

void StickyDipoleForce::getExclusionSites(int index, int& site1, int& site2) const {
    checkIndex(index, exclusions.size(), "exclusion");
    site1 = exclusions[index].first;
    site2 = exclusions[index].second;
}

void StickyDipoleForce::setNonbondedMethod(NonbondedMethod m) {
    if (m != NoCutoff && m != CutoffNonPeriodic && m != CutoffPeriodic)
        throw OpenMMException("StickyDipoleForce: illegal nonbonded method "+std::to_string(m));
    method = m;
}

void StickyDipoleForce::setCutoffDistance(double distance) {
    cutoff = distance;
}

void StickyDipoleForce::setUseSwitchingFunction(bool use) {
    useSwitching = use;
}

void StickyDipoleForce::setSwitchingDistance(double distance) {
    switchingDistance = distance;
}

void StickyDipoleForce::setReactionFieldDielectric(double dielectric) {
    reactionFieldDielectric = dielectric;
}

ForceImpl* StickyDipoleForce::createImpl() const {
    return new StickyDipoleForceImpl(*this);
}
