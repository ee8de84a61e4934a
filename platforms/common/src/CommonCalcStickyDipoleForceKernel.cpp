#include "CommonCalcStickyDipoleForceKernel.h"
#include "CommonRigidLangevinKernelSources.h"
#include "internal/StickyDipoleForceImpl.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ComputeForceInfo.h"
#include "openmm/common/ContextSelector.h"
#include "openmm/common/NonbondedUtilities.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <algorithm>
#include <map>
#include <set>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::string;
using std::vector;

/** Tells OpenMM's atom reordering which molecules it may swap: those whose sites have the same parameters. */
class CommonCalcStickyDipoleForceKernel::ForceInfo : public ComputeForceInfo {
public:
    ForceInfo(const StickyDipoleForce& force) : force(force) {
        for (int i = 0; i < force.getNumSites(); i++) {
            int particle, reference1, reference2;
            StickyDipoleForce::SiteParameters parameters;
            force.getSiteParameters(i, particle, reference1, reference2, parameters);
            siteOfParticle[particle] = i;
        }
    }
    bool areParticlesIdentical(int particle1, int particle2) {
        auto site1 = siteOfParticle.find(particle1), site2 = siteOfParticle.find(particle2);
        if (site1 == siteOfParticle.end() || site2 == siteOfParticle.end())
            return site1 == site2;
        return parametersOf(site1->second) == parametersOf(site2->second);
    }
    int getNumParticleGroups() {
        return force.getNumSites()+force.getNumExclusions();
    }
    void getParticlesInGroup(int index, vector<int>& particles) {
        int particle, reference1, reference2;
        StickyDipoleForce::SiteParameters parameters;
        if (index < force.getNumSites()) {
            force.getSiteParameters(index, particle, reference1, reference2, parameters);
            particles = {particle, reference1, reference2};
            return;
        }
        int site1, site2;
        force.getExclusionSites(index-force.getNumSites(), site1, site2);
        force.getSiteParameters(site1, particle, reference1, reference2, parameters);
        particles = {particle};
        force.getSiteParameters(site2, particle, reference1, reference2, parameters);
        particles.push_back(particle);
    }
    bool areGroupsIdentical(int group1, int group2) {
        if ((group1 < force.getNumSites()) != (group2 < force.getNumSites()))
            return false;
        return group1 >= force.getNumSites() || parametersOf(group1) == parametersOf(group2);
    }
private:
    vector<double> parametersOf(int site) {
        int particle, reference1, reference2;
        StickyDipoleForce::SiteParameters parameters;
        force.getSiteParameters(site, particle, reference1, reference2, parameters);
        return StickyDipoleForceImpl::parameterValues(parameters);
    }
    const StickyDipoleForce& force;
    std::map<int, int> siteOfParticle;
};

class CommonCalcStickyDipoleForceKernel::AtomOrderListener : public ComputeContext::ReorderListener {
public:
    explicit AtomOrderListener(CommonCalcStickyDipoleForceKernel& owner) : owner(owner) {
    }
    void execute() {
        owner.updateSiteAtoms();
    }
private:
    CommonCalcStickyDipoleForceKernel& owner;
};

/** After OpenMM's nonbonded kernel: the frames' rotation derivatives become forces on the sites and reference particles. */
class CommonCalcStickyDipoleForceKernel::ApplyForces : public ComputeContext::ForcePostComputation {
public:
    ApplyForces(ComputeKernel kernel, int numSites, int forceGroup) : kernel(kernel), numSites(numSites), forceGroup(forceGroup) {
    }
    double computeForceAndEnergy(bool includeForces, bool /*includeEnergy*/, int groups) {
        if (includeForces && (groups&(1<<forceGroup)) != 0)
            kernel->execute(numSites);
        return 0;
    }
private:
    ComputeKernel kernel;
    int numSites, forceGroup;
};

CommonCalcStickyDipoleForceKernel::CommonCalcStickyDipoleForceKernel(string name, const Platform& platform, ComputeContext& cc) :
        CalcStickyDipoleForceKernel(name, platform), cc(cc), cutoff(0), selfEnergy(0), periodic(false) {
}

void CommonCalcStickyDipoleForceKernel::initialize(const System& /*system*/, const StickyDipoleForce& force) {
    ContextSelector selector(cc);
    int numSites = force.getNumSites();
    if (numSites == 0)
        return;
    bool useDouble = cc.getUseDoublePrecision();
    int paddedAtoms = cc.getPaddedNumAtoms();

    // Sites, and their parameters as a table of types.
    vector<vector<double> > types;
    vector<double> typeTable;
    siteParticles.resize(numSites);
    references1.resize(numSites);
    references2.resize(numSites);
    siteTypes.resize(numSites);
    StickyDipoleForce::NonbondedMethod method = force.getNonbondedMethod();
    cutoff = force.getCutoffDistance();
    double dielectric = force.getReactionFieldDielectric();
    double kappa = (method == StickyDipoleForce::NoCutoff ? 0.0 : (dielectric-1)/((2*dielectric+1)*cutoff*cutoff*cutoff));
    selfEnergy = 0;
    for (int i = 0; i < numSites; i++) {
        StickyDipoleForce::SiteParameters parameters;
        force.getSiteParameters(i, siteParticles[i], references1[i], references2[i], parameters);
        vector<double> values = StickyDipoleForceImpl::parameterValues(parameters);
        auto found = std::find(types.begin(), types.end(), values);
        siteTypes[i] = found-types.begin();
        if (found == types.end()) {
            types.push_back(values);
            typeTable.insert(typeTable.end(), values.begin(), values.end());
        }
        selfEnergy -= ONE_4PI_EPS0*kappa*parameters.dipole*parameters.dipole;
    }
    int elementSize = (useDouble ? sizeof(double) : sizeof(float));
    typeParams.initialize(cc, typeTable.size(), elementSize, "stickyDipoleTypes");
    typeParams.upload(typeTable, true);
    xAxis.initialize(cc, paddedAtoms, 4*elementSize, "stickyDipoleXAxis");
    yAxis.initialize(cc, paddedAtoms, 4*elementSize, "stickyDipoleYAxis");
    cc.clearBuffer(xAxis);  // atoms that are no sites keep type 0
    cc.clearBuffer(yAxis);
    gradients.initialize<long long>(cc, 6*paddedAtoms, "stickyDipoleGradients");
    cc.addAutoclearBuffer(gradients);
    siteAtoms.initialize<mm_int4>(cc, numSites, "stickyDipoleSiteAtoms");
    updateSiteAtoms();

    // The kernels around the pair loop.
    std::map<string, string> defines;
    defines["PADDED_NUM_ATOMS"] = cc.intToString(paddedAtoms);
    ComputeProgram program = cc.compileProgram(CommonRigidLangevinKernelSources::stickyDipoleSites, defines);
    framesKernel = program->createKernel("computeStickyDipoleFrames");
    framesKernel->addArg(numSites);
    framesKernel->addArg(cc.getPosq());
    framesKernel->addArg(siteAtoms);
    framesKernel->addArg(xAxis);
    framesKernel->addArg(yAxis);
    applyKernel = program->createKernel("applyStickyDipoleForces");
    applyKernel->addArg(numSites);
    applyKernel->addArg(cc.getPosq());
    applyKernel->addArg(siteAtoms);
    applyKernel->addArg(gradients);
    applyKernel->addArg(cc.getLongForceBuffer());

    // The pair loop, inside OpenMM's nonbonded kernel. Its names carry a prefix unique to this force.
    string prefix = "stickyDipole"+cc.intToString(cc.getForceInfos().size())+"_";
    bool useCutoff = (method != StickyDipoleForce::NoCutoff);
    periodic = (method == StickyDipoleForce::CutoffPeriodic);
    vector<vector<int> > exclusionList(cc.getNumAtoms());
    for (int i = 0; i < cc.getNumAtoms(); i++)
        exclusionList[i].push_back(i);
    for (int i = 0; i < force.getNumExclusions(); i++) {
        int site1, site2;
        force.getExclusionSites(i, site1, site2);
        exclusionList[siteParticles[site1]].push_back(siteParticles[site2]);
        exclusionList[siteParticles[site2]].push_back(siteParticles[site1]);
    }
    bool useExclusions = (force.getNumExclusions() > 0);
    std::map<string, string> replacements;
    replacements["SITE_X1"] = prefix+"x1";
    replacements["SITE_X2"] = prefix+"x2";
    replacements["SITE_Y1"] = prefix+"y1";
    replacements["SITE_Y2"] = prefix+"y2";
    replacements["TYPE_PARAMS"] = prefix+"types";
    replacements["GRADIENTS"] = prefix+"gradients";
    replacements["TYPE_STRIDE"] = cc.intToString(StickyDipoleForceImpl::NumParameterValues);
    replacements["IS_EXCLUDED"] = (useExclusions ? "isExcluded" : "false");
    replacements["USE_SWITCH"] = (useCutoff && force.getUseSwitchingFunction() ? "1" : "0");
    replacements["SWITCH_LOWER"] = "("+cc.doubleToString(force.getSwitchingDistance())+")";
    replacements["SWITCH_UPPER"] = "("+cc.doubleToString(cutoff)+")";
    replacements["COULOMB"] = "("+cc.doubleToString(ONE_4PI_EPS0)+")";
    replacements["KAPPA"] = "("+cc.doubleToString(kappa)+")";
    replacements["THREE_FIFTHS"] = "("+cc.doubleToString(0.6)+")";
    replacements["FOUR_FIFTHS"] = "("+cc.doubleToString(0.8)+")";
    replacements["ONE_FIFTH"] = "("+cc.doubleToString(0.2)+")";
    string source = cc.replaceStrings(CommonRigidLangevinKernelSources::stickyDipolePair, replacements);
    NonbondedUtilities& nb = cc.getNonbondedUtilities();
    nb.addInteraction(useCutoff, periodic, useExclusions, cutoff, exclusionList, source, force.getForceGroup());
    string realType = (useDouble ? "double" : "float");
    nb.addParameter(ComputeParameterInfo(xAxis, prefix+"x", realType, 4, false));
    nb.addParameter(ComputeParameterInfo(yAxis, prefix+"y", realType, 4, false));
    nb.addArgument(ComputeParameterInfo(typeParams, prefix+"types", realType, 1));
    nb.addArgument(ComputeParameterInfo(gradients, prefix+"gradients", "mm_ulong", 1, false));
    cc.addForce(new ForceInfo(force));
    cc.addReorderListener(new AtomOrderListener(*this));
    cc.addPostComputation(new ApplyForces(applyKernel, numSites, force.getForceGroup()));
}

void CommonCalcStickyDipoleForceKernel::updateSiteAtoms() {
    if (siteParticles.empty())
        return;
    ContextSelector selector(cc);
    const vector<int>& order = cc.getAtomIndex();
    vector<int> storedAt(order.size());
    for (int i = 0; i < (int) order.size(); i++)
        storedAt[order[i]] = i;
    vector<mm_int4> atoms(siteParticles.size());
    for (int i = 0; i < (int) siteParticles.size(); i++)
        atoms[i] = mm_int4(storedAt[siteParticles[i]], storedAt[references1[i]], storedAt[references2[i]], siteTypes[i]+1);
    siteAtoms.upload(atoms);
}

double CommonCalcStickyDipoleForceKernel::execute(ContextImpl& /*context*/, bool /*includeForces*/, bool includeEnergy) {
    if (siteParticles.empty())
        return 0;
    ContextSelector selector(cc);
    if (periodic) {
        Vec3 a, b, c;
        cc.getPeriodicBoxVectors(a, b, c);
        double half = 0.5*std::min(a[0], std::min(b[1], c[2]));
        if (cutoff > half)
            throw OpenMMException("StickyDipoleForce: the cutoff ("+std::to_string(cutoff)+" nm) exceeds half the periodic box ("
                                  +std::to_string(half)+" nm); use a larger box or a shorter cutoff");
    }
    framesKernel->execute(siteParticles.size());
    return (includeEnergy ? selfEnergy : 0.0);
}
