#ifndef RIGID_LANGEVIN_HASIMOTO_SPLIT_H_
#define RIGID_LANGEVIN_HASIMOTO_SPLIT_H_

#include "openmm/Vec3.h"
#include "internal/windowsExportHydrodynamics.h"

namespace RigidLangevinPlugin {

/**
 * Hasimoto's split of the generalised Rotne-Prager-Yamakawa mobility (per unit viscosity), shared
 * by the dense Ewald sum (PeriodicRotnePragerYamakawa) and the positively split Ewald product
 * (PositivelySplitEwald). In Fourier space the RPY pair tensor of blobs of radii a_i, a_j is
 * sinc(k a_i) sinc(k a_j) (I - kk)/k^2; the weight phi(k) = (1 + k^2/4xi^2) exp(-k^2/4xi^2) takes the
 * smooth part G (its inverse transform) to wave space and leaves F = RPY - G in real space.
 *
 * G in closed form: (I - kk)/k^2 = (k^2 I - kk)/k^4 makes G = (-lap I + grad grad) Psi, where Psi is
 * the average over both blobs' surfaces of psi = FT^-1[phi/k^4] = -(1/8pi)(rho erf(xi rho) +
 * exp(-xi^2 rho^2)/(xi sqrt(pi))) (up to a constant, which the operator removes). The average of a
 * radial function over two spheres is (1/(4 a_i a_j r)) sum_{s,t=+-1} s t Q(r + s a_i + t a_j), Q
 * being the second antiderivative of rho psi: with x = xi rho, rho psi = -h(x)/(8 pi xi^2),
 *
 *   h(x)  = x^2 erf x + x e^{-x^2}/sqrt(pi),
 *   H1(x) = x^3 erf x/3 + ((2x^2 - 1) e^{-x^2} + 1)/(6 sqrt(pi)),
 *   H2(x) = x^4 erf x/12 - erf x/16 + (x + (2x^3 - x) e^{-x^2}/4)/(6 sqrt(pi)),
 *
 * and G = A I + B rr with, for X = xi r, alpha = xi a_i, beta = xi a_j and each sum over the four
 * arguments X + s alpha + t beta weighted by s t,
 *
 *   A =  xi/(32 pi alpha beta) (sum h/X - sum H1/X^2 + sum H2/X^3),
 *   B = -xi/(32 pi alpha beta) (sum h/X - 3 sum H1/X^2 + 3 sum H2/X^3).
 *
 * The same formulas hold overlapping or not (the surface average is exact for every r); near r = 0
 * the three terms cancel, so there G's Taylor series in X is used (its coefficients are the odd
 * derivatives of h at s alpha + t beta). At r = 0 and a_i = a_j = a, A = xi/(2 pi^1.5) as a -> 0.
 */
namespace HasimotoSplit {

/** Hasimoto's weight phi(k) = (1 + x) exp(-x), x = k^2/4xi^2, for k2 = |k|^2. */
OPENMM_EXPORT_HYDRODYNAMICS double weight(double k2, double xi);

/** The smooth part G = isotropic I + dyadic rr (rr the unit vector's outer product) of blobs of
 *  radii ai, aj at distance r >= 0, for the splitting xi. */
OPENMM_EXPORT_HYDRODYNAMICS void smoothPart(double r, double ai, double aj, double xi, double& isotropic, double& dyadic);

/** The real-space pair function F = RPY - G as isotropic I + dyadicPerR2 d d^T, for blob j at offset
 *  d (|d| = r) from blob i (dyadicPerR2 is 0 at r = 0). */
OPENMM_EXPORT_HYDRODYNAMICS void realSpaceCoefficients(double r, double ai, double aj, double xi, double& isotropic, double& dyadicPerR2);

/** F as a 3x3 block (row-major) for blob j at offset d from blob i. */
OPENMM_EXPORT_HYDRODYNAMICS void realSpaceBlock(const OpenMM::Vec3& d, double ai, double aj, double xi, double block[9]);

} // namespace HasimotoSplit
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_HASIMOTO_SPLIT_H_*/
