#ifndef COMMON_CALC_STICKY_DIPOLE_FORCE_KERNEL_H_
#define COMMON_CALC_STICKY_DIPOLE_FORCE_KERNEL_H_

#include "RigidLangevinKernels.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include <vector>

namespace RigidLangevinPlugin {

/**
 * StickyDipoleForce on OpenMM's common compute platforms (OpenCL, CUDA). The pair loop runs inside
 * OpenMM's nonbonded kernel and its neighbour list (NonbondedUtilities::addInteraction); around it:
 *
 * 1. execute(), before the nonbonded kernel: one work item per site builds its frame from the
 *    site and its reference particles and stores the x and y axes per atom, as per-atom parameters
 *    of the interaction (x.w holds 1 + the site's parameter type; 0 marks an atom that is no site,
 *    which the interaction skips).
 * 2. The interaction (kernels/stickyDipolePair.cc): a pair's energy, and per site the force on it
 *    and the derivative of the energy with respect to a rotation of its frame (6 numbers, added to
 *    a fixed-point buffer with atomics; OpenMM's nonbonded kernel applies only central forces).
 * 3. A post-computation, after the nonbonded kernel: per site, the frame rotation's derivative
 *    becomes forces on the site and its reference particles through the frame's construction, as
 *    SiteFrame::addForces() does on the host, so the forces are the exact gradient of the energy.
 *
 * Molecules are identical for OpenMM's atom reordering when their sites have the same parameters;
 * a reorder listener updates where each site and its reference particles are stored.
 */
class CommonCalcStickyDipoleForceKernel : public CalcStickyDipoleForceKernel {
public:
    CommonCalcStickyDipoleForceKernel(std::string name, const OpenMM::Platform& platform, OpenMM::ComputeContext& cc);
    void initialize(const OpenMM::System& system, const StickyDipoleForce& force);
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy);
private:
    class ForceInfo;
    class AtomOrderListener;
    class ApplyForces;
    /** Find where each site and its reference particles are stored now. */
    void updateSiteAtoms();
    OpenMM::ComputeContext& cc;
    std::vector<int> siteParticles, references1, references2, siteTypes;
    double cutoff, selfEnergy;
    bool periodic;
    OpenMM::ComputeArray siteAtoms;     // int4 per site: where the site, reference 1 and 2 are stored; 1 + type
    OpenMM::ComputeArray xAxis, yAxis;  // real4 per atom: the site frames' axes
    OpenMM::ComputeArray typeParams;    // StickyDipoleForceImpl::NumParameterValues reals per site type
    OpenMM::ComputeArray gradients;     // 6 fixed-point values per atom: force on the site, rotation derivative
    OpenMM::ComputeKernel framesKernel, applyKernel;
};

} // namespace RigidLangevinPlugin

#endif /*COMMON_CALC_STICKY_DIPOLE_FORCE_KERNEL_H_*/
