#ifndef RIGID_LANGEVIN_RESISTANCE_TENSOR_H_
#define RIGID_LANGEVIN_RESISTANCE_TENSOR_H_

#include "openmm/Vec3.h"
#include "internal/windowsExportHydrodynamics.h"
#include <string>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * A hydrodynamic resistance tensor per unit viscosity: the symmetric positive definite 6x6 matrix Xi
 * with
 *
 *     (force, torque) = -viscosity * Xi * (velocity, angular velocity)
 *
 * where velocity is that of a reference point (the origin) and torque is taken about it. Blocks:
 * Xi = [[Xtt, Xtr], [Xrt, Xrr]], rows force/torque, columns velocity/angular velocity, with
 * Xtr = Xrt^T. Units per unit viscosity: nm (Xtt), nm^2 (coupling), nm^3 (Xrr).
 *
 * The tensor is stored about its origin; getMatrix() gives it about any point, using the rigid
 * motion of the body (v_O = v_P + r_OP x omega, torque_P = torque_O - r_OP x force).
 */
class OPENMM_EXPORT_HYDRODYNAMICS ResistanceTensor {
public:
    /** An empty tensor (all zero, origin at 0); not valid for dynamics. */
    ResistanceTensor();
    /**
     * A tensor from its 36 values, row-major, about the point origin. Throws if it is not finite,
     * symmetric and positive definite.
     */
    static ResistanceTensor fromMatrix(const std::vector<double>& matrix, const OpenMM::Vec3& origin);
    /** A sphere of the given radius (nm) centred at center (nm), with stick boundary conditions (Stokes: 6 pi R, 8 pi R^3). */
    static ResistanceTensor sphere(double radius, const OpenMM::Vec3& center = OpenMM::Vec3());
    /**
     * A triaxial ellipsoid with semi-axes a, b, c (nm) along x, y, z, centred at center, with stick
     * boundary conditions: Perrin's friction coefficients, evaluated with Carlson's symmetric
     * elliptic integrals R_F and R_D. The tensor is diagonal about the centre.
     */
    static ResistanceTensor ellipsoid(double a, double b, double c, const OpenMM::Vec3& center = OpenMM::Vec3());
    /**
     * An ellipsoid of revolution with semi-axis a (nm) along its symmetry axis x and b along y and
     * z, centred at center: Perrin's closed forms (prolate a > b, oblate a < b, the sphere a = b).
     * Agrees with ellipsoid(a, b, b) to rounding error.
     */
    static ResistanceTensor spheroid(double a, double b, const OpenMM::Vec3& center = OpenMM::Vec3());
    /**
     * A rigid assembly of spherical beads (centres positions and radii radii, in nm) with
     * hydrodynamic interaction: the generalised
     * Rotne-Prager-Yamakawa mobility of Zuk et al. (J. Fluid Mech. 741, R5 (2014)), which holds for
     * beads of different sizes, overlapping and nested ones included, with self mobility
     * 1/(6 pi r_i). The 3N x 3N mobility matrix is Cholesky-factorised, not inverted, on all cores
     * (OPENMM_CPU_THREADS sets how many): on two cores 2000 beads take about a second and 5000
     * about 13 s, in 72 N^2 bytes (about half of them touched).
     *
     * correctionVolume is V (nm^3) in the volume correction +6 V I on the rotational block
     * (Garcia de la Torre & Rodes 1983; Carrasco & Garcia de la Torre 1999): bead models miss the
     * rotational friction of the volume the beads fill, and V is that volume -- the volume of the
     * particle a filling model represents. For non-overlapping beads it is the sum of the bead
     * volumes, beadVolume(radii). Leave it 0 for shell models (whose beads represent a surface and
     * whose error is removed by extrapolation instead, see shellExtrapolated()) and for models that
     * should be taken as they are.
     *
     * Beads on one line have no friction for rotation about it unless correctionVolume > 0: the
     * tensor is then singular, as the integrator expects of a linear body.
     *
     * The origin of the result is the beads' centroid. Throws an OpenMMException for an empty
     * model, a NaN or infinite position, a radius that is not positive and finite, or two
     * coincident beads (same position and radius), naming the bead(s).
     */
    static ResistanceTensor beads(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii,
                                  double correctionVolume = 0);
    /** The sum of the volumes 4/3 pi r^3 of beads with these radii (nm^3). */
    static double beadVolume(const std::vector<double>& radii);
    /**
     * The volume of the union of spheres (nm^3): of a molecule whose atoms overlap, say. Exact along
     * lines parallel to x, integrated over a grid of such lines fine enough for about 0.1%. The
     * volume correction of a filling bead model whose beads overlap takes this, not beadVolume().
     */
    static double unionVolume(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii);
    /**
     * A rough shell model of a molecule: the surface of the union of its atoms' spheres (centres
     * positions, radii radii, in nm) tiled with beads of radius beadRadius (nm) whose centres lie on that
     * surface, about 3 beadRadius apart (see roughShellBeads()), solved as in beads() without
     * volume correction. The result is that of a finite bead size, larger than the molecule's own
     * by a relative amount of order beadRadius/size; shellExtrapolated() removes that. Its origin
     * is the atoms' centroid.
     */
    static ResistanceTensor roughShell(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, double beadRadius);
    /** The bead centres of roughShell(positions, radii, beadRadius); every bead has radius beadRadius. */
    static std::vector<OpenMM::Vec3> roughShellBeads(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii,
                                                     double beadRadius);
    /**
     * The resistance of the union of the atoms' spheres itself: rough shells at numResolutions bead
     * radii, from the one that gives about maxBeads beads up to twice that, each element of the
     * tensor (about the atoms' centroid) fitted by a straight line in the bead radius and taken at
     * zero bead radius, as Garcia de la Torre's HYDRO codes do. It takes about twice as long as
     * beads() on the largest shell: well under a second at 1000 beads, a few seconds at 2000. At
     * the default 2000 it reproduced a sphere, prolate spheroids of axial ratio 2 and 5 and two
     * touching spheres to within 0.5% (1% at 1000 beads). Its origin is the atoms' centroid.
     * Throws if an atom is invalid or if the extrapolated tensor is not positive definite.
     */
    static ResistanceTensor shellExtrapolated(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii,
                                              int maxBeads = 2000, int numResolutions = 6);
    /**
     * A rough shell model of a union of spheroids (the ellipsoids of a Gay-Berne body, say; sphere
     * unions are roughShell()): spheroid i centred at centers[i] (nm) with semi-axis a[i] along the
     * direction axes[i] (any nonzero length) and semi-axis b[i] across it. Its surface is tiled as
     * in roughShell() (each spheroid in rings about its axis; beads inside another spheroid or on
     * a seam dropped) with beads of radius beadRadius and solved as in beads(). Its origin is the
     * centroid of the centres.
     */
    static ResistanceTensor spheroidRoughShell(const std::vector<OpenMM::Vec3>& centers, const std::vector<OpenMM::Vec3>& axes,
                                               const std::vector<double>& a, const std::vector<double>& b, double beadRadius);
    /** The bead centres of spheroidRoughShell(centers, axes, a, b, beadRadius); every bead has radius beadRadius. */
    static std::vector<OpenMM::Vec3> spheroidRoughShellBeads(const std::vector<OpenMM::Vec3>& centers, const std::vector<OpenMM::Vec3>& axes,
                                                             const std::vector<double>& a, const std::vector<double>& b, double beadRadius);
    /**
     * The resistance of the union of spheroids itself: spheroidRoughShell() at numResolutions bead
     * radii extrapolated to zero bead size exactly as shellExtrapolated() does for spheres. Its
     * origin is the centroid of the centres. Throws if a spheroid is invalid or if the extrapolated
     * tensor is not positive definite.
     */
    static ResistanceTensor spheroidShellExtrapolated(const std::vector<OpenMM::Vec3>& centers, const std::vector<OpenMM::Vec3>& axes,
                                                      const std::vector<double>& a, const std::vector<double>& b, int maxBeads = 2000,
                                                      int numResolutions = 6);
    /**
     * Blobs for hydrodynamic interactions (CoupledResistance, RigidLangevinIntegrator::
     * setBodyBlobs()) whose friction alone matches a body's own tensor: the blobs' centres scaled
     * about center (radii unchanged) until the trace of their translational friction (beads()
     * without volume correction) equals that of target's, to 1e-12. A body calibrated to target
     * (CoupledResistance::setBodyResistance()) then couples to distant bodies by the Oseen tensor
     * itself rather than one scaled by its blobs' friction: a rough shell of a sphere on its
     * surface (roughShellBeads()) over-resists by about the bead radius, scaled it sits just
     * inside. Throws an OpenMMException, naming the fix, if the blobs are invalid (as in beads()),
     * center is not finite, or no scale between 0.1 and 10 reaches the target (blobs too large or
     * too small for it).
     */
    static std::vector<OpenMM::Vec3> scaleBlobsToFriction(const std::vector<OpenMM::Vec3>& blobPositions, const std::vector<double>& blobRadii,
                                                          const OpenMM::Vec3& center, const ResistanceTensor& target);
    /**
     * A free-draining bead model: each bead feels Stokes friction 6 pi r_i of its own velocity, with
     * no hydrodynamic interaction between beads. Beads of zero radius are skipped. The origin is
     * the first bead's position.
     */
    static ResistanceTensor freeDrainingBeads(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii);
    /** The reference point the tensor is stored about. */
    const OpenMM::Vec3& getOrigin() const {
        return origin;
    }
    /** The 36 values, row-major, of the tensor about the point origin. */
    std::vector<double> getMatrix(const OpenMM::Vec3& origin) const;
    /** The 36 values, row-major, about the tensor's own origin. */
    std::vector<double> getMatrix() const;
    /**
     * The centre of resistance: the unique point about which the coupling block is symmetric.
     */
    OpenMM::Vec3 getCenterOfResistance() const;
    /**
     * The centre of diffusion: the unique point about which the coupling block of the diffusion
     * tensor is symmetric; the point whose long-time translational diffusion the tensor describes.
     * Throws if the tensor is singular.
     */
    OpenMM::Vec3 getCenterOfDiffusion() const;
    /**
     * The diffusion tensor kT (viscosity Xi)^-1 about the tensor's origin, with kT = BOLTZ*temperature:
     * 36 values, row-major, blocks in nm^2/ps, nm/ps and 1/ps for temperature in K and viscosity in
     * amu/(nm ps) (1 cP = 602.214 amu/(nm ps)). Throws if the tensor is singular (a linear body has
     * no friction about its axis) or an argument is not positive and finite.
     */
    std::vector<double> getDiffusionTensor(double temperature, double viscosity) const;
    /** The diffusion tensor about the point origin. */
    std::vector<double> getDiffusionTensor(double temperature, double viscosity, const OpenMM::Vec3& origin) const;
    /**
     * The same tensor for the body turned by a rotation R (row-major 3x3, proper orthogonal):
     * blocks become R X R^T and the origin R*origin.
     */
    ResistanceTensor rotated(const std::vector<double>& rotation) const;
    /** The same tensor for the body moved by a displacement: the origin moves with it. */
    ResistanceTensor translated(const OpenMM::Vec3& displacement) const;
    /** The same tensor scaled by a factor (e.g. a viscosity, to get the friction itself). */
    ResistanceTensor scaled(double factor) const;
    /**
     * Throw an OpenMMException unless the tensor is finite, symmetric (to 1e-8 relative) and
     * positive definite. The message starts with what, which should name the body.
     */
    void validate(const std::string& what) const;
private:
    double values[36];
    OpenMM::Vec3 origin;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_RESISTANCE_TENSOR_H_*/
