#ifndef RIGID_LANGEVIN_ROTNE_PRAGER_YAMAKAWA_H_
#define RIGID_LANGEVIN_ROTNE_PRAGER_YAMAKAWA_H_

#include <cmath>

namespace RigidLangevinPlugin {

/**
 * The generalised Rotne-Prager-Yamakawa mobility of two beads of any radii, per unit viscosity:
 * the velocity of bead i is mu_ij f_j for a force f_j on bead j. Zuk, Wajnryb, Mizerski & Szymczak,
 * J. Fluid Mech. 741, R5 (2014), as corrected in PHYSICS.md section 2; with r the distance, rr the
 * unit vector's outer product and a_i, a_j the radii,
 *
 *   apart (r > a_i + a_j):          1/(8 pi r) [(I + rr) + (a_i^2 + a_j^2)/r^2 (I/3 - rr)]
 *   overlapping (|a_i-a_j| < r <= a_i+a_j):
 *       1/(6 pi a_i a_j) [(16 r^3 (a_i+a_j) - ((a_i-a_j)^2 + 3 r^2)^2)/(32 r^3) I
 *                         + 3 ((a_i-a_j)^2 - r^2)^2/(32 r^3) rr]
 *   one inside the other (r <= |a_i-a_j|): I/(6 pi max(a_i, a_j))
 *
 * The three pieces join continuously, and the 3N x 3N matrix they make (with self blocks
 * I/(6 pi a_i)) is positive definite for every configuration of distinct beads.
 *
 * Written without Eigen so that kernels compiled for different instruction sets can share it.
 */
namespace RotnePragerYamakawa {

/**
 * mu_ij = isotropic I + dyadic rr (rr the unit vector's outer product) for beads of radii ai and aj
 * at distance r >= 0. Both radii must be positive.
 */
inline void mobilityCoefficients(double r, double ai, double aj, double& isotropic, double& dyadic) {
    if (r > ai+aj) {
        const double sigma2 = (ai*ai+aj*aj)/(r*r);
        isotropic = (1+sigma2/3)/(8*M_PI*r);
        dyadic = (1-sigma2)/(8*M_PI*r);
    }
    else if (r > std::abs(ai-aj)) {
        const double d2 = (ai-aj)*(ai-aj);
        const double r2 = r*r;
        const double r3 = r2*r;
        const double scale = 1/(6*M_PI*ai*aj*32*r3);
        const double s = d2+3*r2;
        const double t = d2-r2;
        isotropic = (16*r3*(ai+aj)-s*s)*scale;
        dyadic = 3*t*t*scale;
    }
    else {
        // The smaller bead moves with the larger one. This also covers r = 0 with unequal radii.
        isotropic = 1/(6*M_PI*std::fmax(ai, aj));
        dyadic = 0;
    }
}

/**
 * The same block as two scalars for a squared distance r2 between centres: mu_ij = isotropic I +
 * dyadicPerR2 d d^T for the offset d between them (either sign), as products over many pairs use it.
 */
inline void pairCoefficients(double r2, double ai, double aj, double& isotropic, double& dyadicPerR2) {
    double dyadic;
    mobilityCoefficients(std::sqrt(r2), ai, aj, isotropic, dyadic);
    dyadicPerR2 = (r2 > 0 ? dyadic/r2 : 0.0);
}

/**
 * The 3x3 block mu_ij (row-major in block) for beads of radii ai and aj, bead j at offset
 * (dx, dy, dz) from bead i. Both radii must be positive. The block is symmetric and unchanged by
 * swapping the beads.
 */
inline void mobilityBlock(double dx, double dy, double dz, double ai, double aj, double block[9]) {
    double isotropic, dyadicPerR2;
    pairCoefficients(dx*dx+dy*dy+dz*dz, ai, aj, isotropic, dyadicPerR2);
    const double d[3] = {dx, dy, dz};
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++)
            block[3*k+l] = dyadicPerR2*d[k]*d[l]+(k == l ? isotropic : 0.0);
}

/** The self block I/(6 pi a): the Stokes mobility of a free sphere, as a scalar. */
inline double selfMobility(double a) {
    return 1/(6*M_PI*a);
}

} // namespace RotnePragerYamakawa
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_ROTNE_PRAGER_YAMAKAWA_H_*/
