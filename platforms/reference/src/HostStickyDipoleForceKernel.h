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
    void initialize(const OpenMM::System& /*system*/, const StickyDipoleForce& force) {
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
    double execute(OpenMM::ContextImpl& /*context*/, bool includeForces, bool /*includeEnergy*/) {
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
        // Per thread: the energy, and per site the force on it and T, the derivative of the energy
        // under a rotation of its frame (see computePairs()).
        int numThreads = getNumThreads();
        std::vector<double> energies(numThreads, 0.0);
        std::vector<std::vector<Vec3> > siteForces(numThreads), torques(numThreads);
        runThreads([&] (int thread) {
            siteForces[thread].assign(numSites, Vec3());
            torques[thread].assign(numSites, Vec3());
            long long begin = (long long) pairs.size()*thread/numThreads, end = (long long) pairs.size()*(thread+1)/numThreads;
            energies[thread] = computePairs(begin, end, sitePositions, frames, box, siteForces[thread], torques[thread]);
        });
        double energy = 0;
        for (int thread = 0; thread < numThreads; thread++)
            energy += energies[thread];
        if (includeForces)
            for (int i = 0; i < numSites; i++) {
                Vec3 siteForce, torque;
                for (int thread = 0; thread < numThreads; thread++) {
                    siteForce += siteForces[thread][i];
                    torque += torques[thread][i];
                }
                // Any dU/dx, dU/dy, dU/dz with this T give the same forces through the frame, which
                // only rotates: T x axis / 2 is one.
                const SiteFrame& f = frames[i];
                forces[particles[i]] += siteForce;
                f.addForces(torque.cross(f.x)*0.5, torque.cross(f.y)*0.5, torque.cross(f.z)*0.5, forces[particles[i]], forces[references1[i]],
                            forces[references2[i]]);
            }
        // The reaction field's self energy of each dipole.
        for (int i = 0; i < numSites; i++)
            energy -= ONE_4PI_EPS0*kappa*parameters[i].dipole*parameters[i].dipole;
        return energy;
    }
protected:
    /**
     * The pairs [begin, end) of the list: add to siteForces each site's force and to torques its
     * T = x cross dU/dx + y cross dU/dy + z cross dU/dz (x, y, z its axes), the derivative of the
     * energy under an infinitesimal rotation of the frame; return their energy. A platform may
     * evaluate them its own way (the CPU platform: four at a time).
     */
    virtual double computePairs(long long begin, long long end, const std::vector<OpenMM::Vec3>& sitePositions, const std::vector<SiteFrame>& frames,
                                const OpenMM::Vec3* box, std::vector<OpenMM::Vec3>& siteForces, std::vector<OpenMM::Vec3>& torques) {
        using OpenMM::Vec3;
        bool periodic = (method == StickyDipoleForce::CutoffPeriodic);
        double energy = 0;
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
            energy += pairEnergy(parameters[i], parameters[j], frames[i], frames[j], d, switchFactor, switchDerivative, kappa, g);
            // F_i = -dU/dr_i = dU/dd, F_j = -dU/dd.
            siteForces[i] += g.d;
            siteForces[j] -= g.d;
            torques[i] += frames[i].x.cross(g.xi)+frames[i].y.cross(g.yi)+frames[i].z.cross(g.zi);
            torques[j] += frames[j].x.cross(g.xj)+frames[j].y.cross(g.yj)+frames[j].z.cross(g.zj);
        }
        return energy;
    }
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
    std::vector<StickyDipoleForce::SiteParameters> parameters;
    OpenMM::NeighborList pairs;
    StickyDipoleForce::NonbondedMethod method;
    double cutoff, switchingDistance, kappa;
    bool useSwitching;
private:
    OpenMM::ReferencePlatform::PlatformData& data;
    std::vector<int> particles, references1, references2;
    std::vector<std::set<int> > exclusions;
    std::vector<OpenMM::Vec3> listPositions;  // where the sites were when the list was built
    OpenMM::Vec3 listBox[3];
};

} // namespace RigidLangevinPlugin

#endif /*RIGIDLANGEVIN_HOST_STICKY_DIPOLE_FORCE_KERNEL_H_*/
