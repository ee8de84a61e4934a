#ifndef RIGID_LANGEVIN_PERRIN_FRICTION_H_
#define RIGID_LANGEVIN_PERRIN_FRICTION_H_

#include "internal/windowsExportHydrodynamics.h"

namespace RigidLangevinPlugin {

/**
 * Perrin's friction coefficients of an ellipsoid with stick boundary conditions (F. Perrin,
 * J. Phys. Radium 5, 497 (1934); 7, 1 (1936)), per unit viscosity. The ellipsoid is centred at the
 * origin with its semi-axes along x, y and z, so translation and rotation do not couple and every
 * coefficient belongs to one principal axis.
 */
namespace PerrinFriction {

/** The six principal friction coefficients of an ellipsoid, per unit viscosity. */
struct PrincipalFriction {
    /** Translational friction along x, y, z (nm). */
    double translation[3];
    /** Rotational friction about x, y, z (nm^3). */
    double rotation[3];
};

/**
 * A triaxial ellipsoid with semi-axes a, b, c along x, y, z. With Delta(s) = sqrt((a^2+s)(b^2+s)(c^2+s)),
 * chi = int_0^inf ds/Delta and alpha_i = int_0^inf ds/((a_i^2+s) Delta), Perrin's coefficients are
 *
 *     translation along i: 16 pi / (chi + a_i^2 alpha_i)
 *     rotation about i:    16 pi (a_j^2 + a_k^2) / (3 (a_j^2 alpha_j + a_k^2 alpha_k))
 *
 * and the integrals are Carlson's: chi = 2 R_F(a^2, b^2, c^2), alpha_i = (2/3) R_D(a_j^2, a_k^2, a_i^2).
 * Throws an OpenMMException unless every semi-axis is positive and finite.
 */
OPENMM_EXPORT_HYDRODYNAMICS PrincipalFriction ellipsoid(double a, double b, double c);

/**
 * An ellipsoid of revolution with its symmetry axis along x: semi-axis a along x, b along y and z
 * (prolate for a > b, oblate for a < b), by Perrin's closed forms. The source's forms, with
 * S = 2 atanh(e)/(a e) for a prolate and S = 2 atan(t)/(a t) for an oblate ellipsoid, are 0/0 at
 * a = b; they are evaluated here in a form that is exact and smooth through the sphere. See
 * PerrinFriction.cpp for the rewriting.
 */
OPENMM_EXPORT_HYDRODYNAMICS PrincipalFriction spheroid(double a, double b);

} // namespace PerrinFriction
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PERRIN_FRICTION_H_*/
