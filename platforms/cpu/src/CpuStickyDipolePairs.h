#ifndef CPU_STICKY_DIPOLE_PAIRS_H_
#define CPU_STICKY_DIPOLE_PAIRS_H_

namespace RigidLangevinPlugin {

/**
 * StickyDipoleForce's pair term for four pairs at once, in double precision, for the CPU platform:
 * the expressions of pairEnergy() (StickyDipoleInteraction.h) written branch-free over four lanes
 * (the switches as clamped polynomials, the cutoff as a mask), compiled for AVX2 where the processor
 * has it and for the baseline instruction set elsewhere (chosen when the library loads).
 */
struct StickyPairBlock {
    static const int Lanes = 4;
    /** Per lane: r_j - r_i before the nearest image, the axes of i and j, their parameters. */
    alignas(32) double d[3][Lanes];
    alignas(32) double xi[3][Lanes], yi[3][Lanes], zi[3][Lanes], xj[3][Lanes], yj[3][Lanes], zj[3][Lanes];
    /** sigma, epsilon, dipole, nu0, rL, rU, nu0', rL', rU', w0 of i and of j. */
    alignas(32) double pi[10][Lanes], pj[10][Lanes];
    /** 1 for a pair, 0 for an unused lane. */
    alignas(32) double used[Lanes];
};

/** What the pairs give: energy, force on i (the force on j is minus it), and T of i and of j (HostCalcStickyDipoleForceKernel::computePairs()). */
struct StickyPairResults {
    alignas(32) double energy[StickyPairBlock::Lanes];
    alignas(32) double force[3][StickyPairBlock::Lanes];
    alignas(32) double torqueI[3][StickyPairBlock::Lanes], torqueJ[3][StickyPairBlock::Lanes];
};

/** The force's settings the pair term needs. box: the periodic box vectors (reduced form), or null. */
struct StickyPairSettings {
    const double* box;  // 9 values: a, b, c
    bool useCutoff, useSwitching;
    double cutoff, switchingDistance, kappa;
};

void computeStickyPairBlock(const StickyPairBlock& block, const StickyPairSettings& settings, StickyPairResults& results);

} // namespace RigidLangevinPlugin

#endif /*CPU_STICKY_DIPOLE_PAIRS_H_*/
