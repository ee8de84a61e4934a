#ifndef RIGID_LANGEVIN_RESISTANCE_TENSOR_H_
#define RIGID_LANGEVIN_RESISTANCE_TENSOR_H_

#include "openmm/Vec3.h"
#include "internal/windowsExportRigidLangevin.h"
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
class OPENMM_EXPORT_RIGIDLANGEVIN ResistanceTensor {
public:
    /** An empty tensor (all zero, origin at 0); not valid for dynamics. */
    ResistanceTensor();
    /**
     * A tensor from its 36 values, row-major, about the point origin. Throws if it is not finite,
     * symmetric and positive definite.
     */
    static ResistanceTensor fromMatrix(const std::vector<double>& matrix, const OpenMM::Vec3& origin);
    /** A sphere of the given radius with stick boundary conditions (Stokes: 6 pi R, 8 pi R^3). */
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
