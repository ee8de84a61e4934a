#ifndef RIGID_LANGEVIN_SHELL_MODEL_H_
#define RIGID_LANGEVIN_SHELL_MODEL_H_

#include "internal/ResistanceMath.h"
#include "internal/windowsExportHydrodynamics.h"
#include "openmm/Vec3.h"
#include <functional>
#include <string>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * Shell models: a body's surface tiled with small beads of radius sigma, whose bead-model
 * resistance tends to that of the body itself as sigma -> 0 (Bloomfield, Dalton & Van Holde 1967;
 * Garcia de la Torre & Bloomfield 1977). The error is linear in sigma to leading order, so the
 * tensor is computed at several sigma and extrapolated linearly to sigma = 0, as in Garcia de la
 * Torre's HYDRO codes. Bead centres lie on the surface; tilings place neighbouring bead centres
 * about 3 sigma apart, a gap of one bead radius (see BEAD_SPACING in ShellModel.cpp for why not the
 * classical touching beads).
 */
namespace ShellModel {

/** A tiling of some surface: the bead centres for a given bead radius. */
typedef std::function<std::vector<OpenMM::Vec3>(double beadRadius)> Tiling;

/**
 * Bead centres on the surface of an ellipsoid of revolution centred at the origin, with semi-axis
 * a along x and b along y and z: rings about the x axis, spaced 3 beadRadius apart along the
 * meridian, each with as many beads as fit 3 beadRadius apart around it.
 */
OPENMM_EXPORT_HYDRODYNAMICS std::vector<OpenMM::Vec3> tileSpheroid(double a, double b, double beadRadius);

/**
 * Throw an OpenMMException, whose message starts with caller, unless there is at least one sphere,
 * one radius per centre, every centre finite and every radius positive and finite.
 */
OPENMM_EXPORT_HYDRODYNAMICS void validateSpheres(const std::string& caller, const std::vector<OpenMM::Vec3>& centers,
                                                 const std::vector<double>& radii);

/**
 * Bead centres on the surface of the union of spheroids (Gay-Berne ellipsoids, say): spheroid i
 * centred at centers[i] with semi-axis a[i] along the unit vector axes[i] and b[i] across it,
 * each tiled as by tileSpheroid (turned so that its x axis lies along axes[i]; the azimuth of its
 * rings is fixed by spheroidFrame), less the beads strictly inside another spheroid and those
 * closer than half the spacing to a bead already placed (along the seams). Throws if the input is
 * invalid or no bead is left.
 */
OPENMM_EXPORT_HYDRODYNAMICS std::vector<OpenMM::Vec3> tileSpheroidUnion(const std::string& caller, const std::vector<OpenMM::Vec3>& centers,
                                                                        const std::vector<OpenMM::Vec3>& axes, const std::vector<double>& a,
                                                                        const std::vector<double>& b, double beadRadius);

/**
 * The frame in which tileSpheroidUnion tiles a spheroid whose symmetry axis is the unit vector
 * axis: columns axis, v, w, right-handed, with v the lab axis least parallel to axis made
 * orthogonal to it (for axis = x: the lab frame itself, so that spheres tile as they always did).
 */
OPENMM_EXPORT_HYDRODYNAMICS Eigen::Matrix3d spheroidFrame(const OpenMM::Vec3& axis);

/**
 * Throw an OpenMMException, whose message starts with caller, unless there is at least one
 * spheroid, one axis and two semi-axes per centre, every centre finite, every axis finite and
 * nonzero, every semi-axis positive and finite.
 */
OPENMM_EXPORT_HYDRODYNAMICS void validateSpheroids(const std::string& caller, const std::vector<OpenMM::Vec3>& centers,
                                                   const std::vector<OpenMM::Vec3>& axes, const std::vector<double>& a,
                                                   const std::vector<double>& b);

/**
 * Bead centres on the surface of the union of spheres (atoms): each sphere tiled as by
 * tileSpheroid, less the beads strictly inside another sphere and those closer than half the
 * spacing to a bead already placed (which happens along the seams where spheres meet). Throws if the input
 * is invalid or no bead is left.
 */
OPENMM_EXPORT_HYDRODYNAMICS std::vector<OpenMM::Vec3> tileSphereUnion(const std::vector<OpenMM::Vec3>& centers,
                                                                      const std::vector<double>& radii, double beadRadius);

/**
 * The least-squares straight line through the tensors (all about the same origin) as a function
 * of bead radius, evaluated at zero bead radius, element by element. Moving the origin is linear
 * in the tensor, so extrapolating about one origin and then moving it is the same as moving first.
 * Needs at least two distinct bead radii.
 */
OPENMM_EXPORT_HYDRODYNAMICS ResistanceMath::Matrix6 extrapolateToZeroBeadSize(const std::vector<double>& beadRadii,
                                                                              const std::vector<ResistanceMath::Matrix6>& tensors);

/**
 * The bead radii at which extrapolated() computes shells: numResolutions values evenly spaced
 * from the radius that gives about maxBeads beads up to twice that radius (about maxBeads/4
 * beads), the range over which the shells' error was measured to be nearly linear. approximateArea, the surface area or a rough estimate of it (nm^2), gives the first
 * guess; the tiling itself is then used to hit maxBeads to within a few percent.
 */
OPENMM_EXPORT_HYDRODYNAMICS std::vector<double> beadRadii(const Tiling& tiling, double approximateArea, int maxBeads, int numResolutions);

/**
 * The shell-model resistance tensor extrapolated to zero bead size, about origin: the tiling at
 * each of beadRadii(), each solved as a bead model of equal beads (no volume correction), then
 * extrapolateToZeroBeadSize(). caller starts the messages of any exception.
 */
OPENMM_EXPORT_HYDRODYNAMICS ResistanceMath::Matrix6 extrapolated(const std::string& caller, const Tiling& tiling, double approximateArea,
                                                                 const OpenMM::Vec3& origin, int maxBeads, int numResolutions);

} // namespace ShellModel
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_SHELL_MODEL_H_*/
