#include "ReferenceRigidLangevinKernels.h"
#include "StickyDipoleInteraction.h"
#include "ReferenceForce.h"
#include "ReferenceNeighborList.h"

using namespace RigidLangevinPlugin;
using namespace OpenMM;

void ReferenceIntegrateRigidLangevinStepKernel::initialize(const System& system, const RigidLangevinIntegrator& integrator) {
    RigidLangevinStepKernelBase::initialize(system, integrator);
    std::vector<std::unique_ptr<RandomStream> > streams;
    streams.emplace_back(new RandomStream(integrator.getRandomNumberSeed()));
    setChunks(model->getNumBodies(), std::move(streams));
}

void ReferenceIntegrateRigidLangevinStepKernel::createRandomCheckpoint(std::ostream& stream) {
    random[0]->random.createCheckpoint(stream);
}

void ReferenceIntegrateRigidLangevinStepKernel::loadRandomCheckpoint(std::istream& stream) {
    random[0]->random.loadCheckpoint(stream);
}

void ReferenceCalcStickyDipoleForceKernel::initialize(const System& system, const StickyDipoleForce& force) {
    int numSites = force.getNumSites();
    particles.resize(numSites);
    references1.resize(numSites);
    references2.resize(numSites);
    parameters.resize(numSites);
    for (int i = 0; i < numSites; i++)
        force.getSiteParameters(i, particles[i], references1[i], references2[i], parameters[i]);
    exclusions.assign(numSites, std::set<int>());
    for (int i = 0; i < force.getNumExclusions(); i++) {
        int a, b;
        force.getExclusionSites(i, a, b);
        exclusions[a].insert(b);
        exclusions[b].insert(a);
    }
    method = force.getNonbondedMethod();
    cutoff = force.getCutoffDistance();
    useSwitching = force.getUseSwitchingFunction();
    switchingDistance = force.getSwitchingDistance();
    double dielectric = force.getReactionFieldDielectric();
    kappa = (method == StickyDipoleForce::NoCutoff ? 0.0 : (dielectric-1)/((2*dielectric+1)*cutoff*cutoff*cutoff));
}

double ReferenceCalcStickyDipoleForceKernel::execute(ContextImpl& context, bool includeForces, bool includeEnergy) {
    const std::vector<Vec3>& positions = *data.positions;
    std::vector<Vec3>& forces = *data.forces;
    const Vec3* box = data.periodicBoxVectors;
    bool periodic = (method == StickyDipoleForce::CutoffPeriodic);
    int numSites = particles.size();
    std::vector<SiteFrame> frames;
    std::vector<Vec3> sitePositions(numSites);
    for (int i = 0; i < numSites; i++) {
        frames.push_back(SiteFrame(positions[particles[i]], positions[references1[i]], positions[references2[i]]));
        sitePositions[i] = positions[particles[i]];
    }
    NeighborList pairs;
    if (method == StickyDipoleForce::NoCutoff) {
        for (int i = 0; i < numSites; i++)
            for (int j = i+1; j < numSites; j++)
                if (exclusions[i].count(j) == 0)
                    pairs.push_back(AtomPair(i, j));
    }
    else
        computeNeighborListVoxelHash(pairs, numSites, sitePositions, exclusions, box, periodic, cutoff, 0.0, false);
    std::vector<Vec3> gx(numSites), gy(numSites), gz(numSites);
    double energy = 0;
    for (const AtomPair& pair : pairs) {
        int i = pair.first, j = pair.second;
        Vec3 d = (periodic ? ReferenceForce::getDeltaRPeriodic(sitePositions[i], sitePositions[j], box) : sitePositions[j]-sitePositions[i]);
        double r = std::sqrt(d.dot(d)), switchFactor = 1, switchDerivative = 0;
        if (method != StickyDipoleForce::NoCutoff) {
            if (r >= cutoff)
                continue;
            if (useSwitching)
                switchFactor = cubicSwitch(r, switchingDistance, cutoff, switchDerivative);
        }
        PairGradient g;
        energy += pairEnergy(parameters[i], parameters[j], frames[i], frames[j], d, switchFactor, switchDerivative, kappa, g);
        if (!includeForces)
            continue;
        // F_i = -dU/dr_i = dU/dd, F_j = -dU/dd.
        forces[particles[i]] += g.d;
        forces[particles[j]] -= g.d;
        gx[i] += g.xi;
        gy[i] += g.yi;
        gz[i] += g.zi;
        gx[j] += g.xj;
        gy[j] += g.yj;
        gz[j] += g.zj;
    }
    if (includeForces)
        for (int i = 0; i < numSites; i++)
            frames[i].addForces(gx[i], gy[i], gz[i], forces[particles[i]], forces[references1[i]], forces[references2[i]]);
    // The reaction field's self energy of each dipole.
    for (int i = 0; i < numSites; i++)
        energy -= ONE_4PI_EPS0*kappa*parameters[i].dipole*parameters[i].dipole;
    return energy;
}
