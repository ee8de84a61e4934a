#ifndef RIGIDLANGEVIN_HOST_STICKY_DIPOLE_FORCE_KERNEL_H_
#define RIGIDLANGEVIN_HOST_STICKY_DIPOLE_FORCE_KERNEL_H_

#include "RigidLangevinKernels.h"
#include "StickyDipoleInteraction.h"
#include "ReferenceNeighborList.h"
#include "ReferencePlatform.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <string>
#include <functional>
#include <set>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * StickyDipoleForce on the host, in double precision (StickyDipoleInteraction.h), for Reference
 * and CPU: site frames, pairs from OpenMM's voxel neighbour list with a cutoff (all pairs without
 * one), then the pairs split into one contiguous share per thread, each accumulating into its own
 * buffers, summed in thread order (the same result for the same number of threads). A platform
 * supplies its threads; Reference runs one.
 *
 * The neighbour list holds the pairs within the cutoff plus a skin, and is rebuilt only when a
 * site has moved more than half the skin since (or the box changed): until then every pair within
 * the cutoff is in it. Building it costs more than the pairs themselves.
 */
class HostCalcStickyDipoleForceKernel : public CalcStickyDipoleForceKernel {
public:
    HostCalcStickyDipoleForceKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ReferencePlatform::PlatformData& data) :
            CalcStickyDipoleForceKernel(name, platform), data(data) {
    }
    void initialize(const OpenMM::System& system, const StickyDipoleForce& force) {
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
        pairs.clear();
        listPositions.clear();
        useSwitching = force.getUseSwitchingFunction();
        switchingDistance = force.getSwitchingDistance();
        double dielectric = force.getReactionFieldDielectric();
        kappa = (method == StickyDipoleForce::NoCutoff ? 0.0 : (dielectric-1)/((2*dielectric+1)*cutoff*cutoff*cutoff));
    }
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) {
        using OpenMM::Vec3;
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
        updatePairs(sitePositions, box, periodic);
        // Per thread: the energy, and the gradient with respect to each site's position and axes.
        int numThreads = getNumThreads();
        std::vector<double> energies(numThreads, 0.0);
        std::vector<std::vector<Vec3> > gd(numThreads), gx(numThreads), gy(numThreads), gz(numThreads);
        runThreads([&] (int thread) {
            gd[thread].assign(numSites, Vec3());
            gx[thread].assign(numSites, Vec3());
            gy[thread].assign(numSites, Vec3());
            gz[thread].assign(numSites, Vec3());
            long long begin = (long long) pairs.size()*thread/numThreads, end = (long long) pairs.size()*(thread+1)/numThreads;
            for (long long p = begin; p < end; p++) {
                int i = pairs[p].first, j = pairs[p].second;
                Vec3 d = sitePositions[j]-sitePositions[i];
                if (periodic) {
                    // The nearest image, for any triclinic box in OpenMM's reduced form.
                    d -= box[2]*std::round(d[2]/box[2][2]);
                    d -= box[1]*std::round(d[1]/box[1][1]);
                    d -= box[0]*std::round(d[0]/box[0][0]);
                }
                double switchFactor = 1, switchDerivative = 0;
                if (method != StickyDipoleForce::NoCutoff) {
                    double r = std::sqrt(d.dot(d));
                    if (r >= cutoff)
                        continue;
                    if (useSwitching)
                        switchFactor = cubicSwitch(r, switchingDistance, cutoff, switchDerivative);
                }
                PairGradient g;
                energies[thread] += pairEnergy(parameters[i], parameters[j], frames[i], frames[j], d, switchFactor, switchDerivative, kappa, g);
                // F_i = -dU/dr_i = dU/dd, F_j = -dU/dd.
                gd[thread][i] += g.d;
                gd[thread][j] -= g.d;
                gx[thread][i] += g.xi;
                gy[thread][i] += g.yi;
                gz[thread][i] += g.zi;
                gx[thread][j] += g.xj;
                gy[thread][j] += g.yj;
                gz[thread][j] += g.zj;
            }
        });
        double energy = 0;
        for (int thread = 0; thread < numThreads; thread++)
            energy += energies[thread];
        if (includeForces)
            for (int i = 0; i < numSites; i++) {
                Vec3 siteForce, x, y, z;
                for (int thread = 0; thread < numThreads; thread++) {
                    siteForce += gd[thread][i];
                    x += gx[thread][i];
                    y += gy[thread][i];
                    z += gz[thread][i];
                }
                forces[particles[i]] += siteForce;
                frames[i].addForces(x, y, z, forces[particles[i]], forces[references1[i]], forces[references2[i]]);
            }
        // The reaction field's self energy of each dipole.
        for (int i = 0; i < numSites; i++)
            energy -= ONE_4PI_EPS0*kappa*parameters[i].dipole*parameters[i].dipole;
        return energy;
    }
protected:
    /** Rebuild the list of pairs if a site may have come within the cutoff of one not in it. */
    void updatePairs(const std::vector<OpenMM::Vec3>& sitePositions, const OpenMM::Vec3* box, bool periodic) {
        int numSites = sitePositions.size();
        if (method == StickyDipoleForce::NoCutoff) {
            if (pairs.empty())
                for (int i = 0; i < numSites; i++)
                    for (int j = i+1; j < numSites; j++)
                        if (exclusions[i].count(j) == 0)
                            pairs.push_back(OpenMM::AtomPair(i, j));
            return;
        }
        // The skin may not take the list beyond half the box, where nearest images stop being unique.
        double skin = 0.1;
        if (periodic) {
            double half = 0.5*std::min(box[0][0], std::min(box[1][1], box[2][2]));
            if (cutoff > half)
                throw OpenMM::OpenMMException("StickyDipoleForce: the cutoff ("+std::to_string(cutoff)+" nm) exceeds half the periodic box ("
                                      +std::to_string(half)+" nm); use a larger box or a shorter cutoff");
            skin = std::min(skin, half-cutoff);
        }
        bool rebuild = (listPositions.size() != sitePositions.size() || skin <= 0);
        for (int k = 0; k < 3 && !rebuild; k++)
            rebuild = !(box[k] == listBox[k]);
        for (int i = 0; i < numSites && !rebuild; i++) {
            OpenMM::Vec3 moved = sitePositions[i]-listPositions[i];
            rebuild = (moved.dot(moved) > 0.25*skin*skin);
        }
        if (!rebuild)
            return;
        OpenMM::computeNeighborListVoxelHash(pairs, numSites, sitePositions, exclusions, box, periodic, cutoff+std::max(skin, 0.0), 0.0, false);
        listPositions = sitePositions;
        for (int k = 0; k < 3; k++)
            listBox[k] = box[k];
    }
    /** How many threads share the pairs. */
    virtual int getNumThreads() {
        return 1;
    }
    /** Run task(thread) for every thread, and return when all are done. */
    virtual void runThreads(const std::function<void (int)>& task) {
        task(0);
    }
private:
    OpenMM::ReferencePlatform::PlatformData& data;
    std::vector<int> particles, references1, references2;
    std::vector<StickyDipoleForce::SiteParameters> parameters;
    std::vector<std::set<int> > exclusions;
    OpenMM::NeighborList pairs;
    std::vector<OpenMM::Vec3> listPositions;  // where the sites were when the list was built
    OpenMM::Vec3 listBox[3];
    StickyDipoleForce::NonbondedMethod method;
    double cutoff, switchingDistance, kappa;
    bool useSwitching;
};

} // namespace RigidLangevinPlugin

#endif /*RIGIDLANGEVIN_HOST_STICKY_DIPOLE_FORCE_KERNEL_H_*/
