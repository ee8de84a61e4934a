#ifndef RIGID_LANGEVIN_CARLSON_INTEGRALS_H_
#define RIGID_LANGEVIN_CARLSON_INTEGRALS_H_

#include "internal/windowsExportHydrodynamics.h"

namespace RigidLangevinPlugin {

/**
 * Carlson's symmetric elliptic integrals, computed by the duplication algorithm of
 * B. C. Carlson, "Numerical computation of real or complex elliptic integrals", Numer. Algorithms
 * 10, 13-26 (1995) (also DLMF 19.36.1). They are what Perrin's friction coefficients of a triaxial
 * ellipsoid reduce to. Both are accurate to a few units in the last place for arguments whose
 * ratios stay within about 1e-300..1e300.
 */
namespace CarlsonIntegrals {

/**
 * R_F(x, y, z) = 1/2 integral_0^inf dt / sqrt((t+x)(t+y)(t+z)), for x, y, z >= 0 with at most one
 * of them zero. Throws an OpenMMException otherwise.
 */
OPENMM_EXPORT_HYDRODYNAMICS double carlsonRF(double x, double y, double z);

/**
 * R_D(x, y, z) = 3/2 integral_0^inf dt / (sqrt((t+x)(t+y)) (t+z)^(3/2)), for x, y >= 0 (not both
 * zero) and z > 0. Throws an OpenMMException otherwise.
 */
OPENMM_EXPORT_HYDRODYNAMICS double carlsonRD(double x, double y, double z);

} // namespace CarlsonIntegrals
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_CARLSON_INTEGRALS_H_*/
