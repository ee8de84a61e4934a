#ifndef RIGID_LANGEVIN_ROTNE_PRAGER_BLAKE_H_
#define RIGID_LANGEVIN_ROTNE_PRAGER_BLAKE_H_

#include "internal/KrylovSolvers.h"
#include "internal/windowsExportHydrodynamics.h"
#include "openmm/OpenMMException.h"
#include "openmm/Vec3.h"
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * Blobs above a no-slip wall: the plane z = z0 bounds the fluid (z > z0). The blobs' translational
 * mobility per unit viscosity is Rotne-Prager-Blake's,
 *
 *     mu_ij = (1 + a_i^2/6 lap_x)(1 + a_j^2/6 lap_y) G(x, y)   at x = r_i, y = r_j,
 *
 * G Blake's Green's function of a point force above the wall (Blake, Proc. Camb. Phil. Soc. 70,
 * 303 (1971)): the Oseen tensor of the force plus its image system below the wall (a Stokeslet, a
 * Stokes doublet and a source dipole at the mirror point). For one radius this is Swan & Brady's
 * (Phys. Fluids 19, 113306 (2007), appendix); only translation enters, so their left-handed cross
 * product (which flips signs of the rotational couplings) does not. The first term of G gives the
 * generalised Rotne-Prager-Yamakawa tensor (RotnePragerYamakawa.h, overlapping blobs included); the
 * image part, smooth wherever both blobs lie above the wall, gives imageBlock() below.
 *
 * Why it is positive definite, and what it supports. Faxen's operators are the averages over the
 * blobs' surfaces of a biharmonic field, so mu_ij is G averaged over the surface of blob i and that
 * of blob j: for the image part whenever both spheres lie above the wall (overlapping each other
 * or not), for the free part always (Zuk et al., J. Fluid Mech. 741, R5 (2014)). G is the Green's
 * function of a dissipative flow, so M is positive definite for distinct spheres above the wall,
 * whatever their radii: blobs of unequal radii are supported, each with its own operator (the
 * same formula with a_i and a_j; RigidMultiblobsWall's source-target wall product has it too).
 *
 * Blobs closer to the wall than their radius would cut it and make M indefinite. The regularisation
 * of Balboa Usabiaga, Delmotte & Donev (J. Chem. Phys. 146, 134104 (2017), appendix A): every
 * blob's height h = z - z0 is raised to h~ = max(h, a) and M is damped by B = diag(min(h/a, 1)),
 *
 *     M~ = B M(h~) B,
 *
 * positive definite for every configuration of blob centres above the wall in which no two blobs
 * become the same sphere when raised (validate() refuses that, and a centre at or below the wall).
 *
 * The blocks are written without Eigen, as RotnePragerYamakawa's, so that other kernels can share
 * them; the matrix and product below use Eigen.
 */
namespace RotnePragerBlake {

/**
 * The self-mobility per unit viscosity of a blob of radius a at height h >= a above the wall,
 * parallel and perpendicular to it (Swan & Brady): with x = a/h,
 *   parallel      = (1 - 9x/16 + x^3/8 - x^5/16)/(6 pi a),
 *   perpendicular = (1 - 9x/8 + x^3/2 - x^5/8)/(6 pi a).
 */
inline void selfMobility(double height, double radius, double& parallel, double& perpendicular) {
    const double x = radius/height, x2 = x*x, x3 = x2*x, x5 = x3*x2;
    const double stokes = 1/(6*M_PI*radius);
    parallel = stokes*(1-9*x/16+x3/8-x5/16);
    perpendicular = stokes*(1-9*x/8+x3/2-x5/8);
}

/**
 * The five coefficients of the wall's image block (see imageBlock()) for target blob i at height hi
 * and source blob j at height hj (both at least their radii ai, aj), their lateral offset
 * (rx, ry) = (x_i - x_j, y_i - y_j): the block is, per unit viscosity,
 *     c[0] I + c[1] R R^T + c[2] R e_z^T + c[3] e_z R^T + c[4] e_z e_z^T,
 * R = (rx, ry, hi + hj) the offset of blob i from blob j's mirror image. Derived from Blake's image
 * system and Faxen's operators above (checked against a symbolic derivation and
 * RigidMultiblobsWall's formulas to rounding).
 */
inline void imageCoefficients(double rx, double ry, double hi, double hj, double ai, double aj, double c[5]) {
    const double r3z = hi+hj, r3z2 = r3z*r3z;
    const double u = 1/std::sqrt(rx*rx+ry*ry+r3z2), u2 = u*u;
    const double u3 = u*u2, u5 = u3*u2, u7 = u5*u2, u9 = u7*u2;
    const double ai2 = ai*ai, aj2 = aj*aj, p = ai2*aj2, q = ai2*hj+aj2*hi, hihj = hi*hj;
    const double scale = 1/(8*M_PI);
    c[0] = scale*(-u-(2*hihj+(ai2+aj2)/3)*u3+(2*r3z*q+2*p/3)*u5-(10.0/3)*p*r3z2*u7);
    c[1] = scale*(-u3+(6*hihj+ai2+aj2)*u5-(10*r3z*q+10*p/3)*u7+(70.0/3)*p*r3z2*u9);
    c[2] = scale*(2*hj*u3-(12*hihj*r3z+2*q+2*aj2*r3z)*u5+(20*r3z2*q+(40.0/3)*p*r3z)*u7-(140.0/3)*p*r3z*r3z2*u9);
    c[3] = scale*(2*hj*u3+2*(ai2-aj2)*hj*u5-(20.0/3)*p*r3z*u7);
    c[4] = scale*(-4*hj*hj*u3+(4*aj2*(hj*hj-hi*hi)-8*ai2*hj*r3z-8*p/3)*u5+20*p*r3z2*u7);
}

/**
 * The wall's image part of mu_ij (row-major in block), per unit viscosity, without the
 * regularisation: the velocity of blob i (radius ai, height hi) for a unit force on blob j (radius
 * aj, height hj), lateral offset (rx, ry) = (x_i - x_j, y_i - y_j). Not symmetric; swapping the
 * blobs transposes it. With i = j (rx = ry = 0, hi = hj, ai = aj) it is the wall's part of the
 * self-mobility.
 */
inline void imageBlock(double rx, double ry, double hi, double hj, double ai, double aj, double block[9]) {
    double c[5];
    imageCoefficients(rx, ry, hi, hj, ai, aj, c);
    const double r[3] = {rx, ry, hi+hj};
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++)
            block[3*k+l] = (k == l ? c[0] : 0.0)+c[1]*r[k]*r[l]+(l == 2 ? c[2]*r[k] : 0.0)+(k == 2 ? c[3]*r[l] : 0.0)+(k == 2 && l == 2 ? c[4] : 0.0);
}

/** The regularisation's height h~ = max(h, a) at which a blob of radius a at height h is evaluated. */
inline double evaluatedHeight(double height, double radius) {
    return std::max(height, radius);
}

/** The regularisation's damping min(h/a, 1) of a blob of radius a at height h. */
inline double damping(double height, double radius) {
    return std::min(height/radius, 1.0);
}

/**
 * Thrown where a blob's centre is at or below the wall: getBlob() says which (numbered as the
 * caller gave the blobs), so that a caller can name its body.
 */
class BlobBelowWallException : public OpenMM::OpenMMException {
public:
    BlobBelowWallException(const std::string& message, int blob) : OpenMM::OpenMMException(message), blob(blob) {
    }
    int getBlob() const {
        return blob;
    }
private:
    int blob;
};

/**
 * Throw unless the blobs can have a mobility above the wall z = wallZ: a BlobBelowWallException,
 * its message beginning with caller, naming the first blob whose centre is at or below the wall
 * (or not finite); an OpenMMException naming two blobs that the regularisation raises to the same
 * sphere (equal radii, the same x and y, both within their radius of the wall), which would make M
 * singular. Blobs are named by names if given ("blob i" otherwise). Radii must be positive
 * (BeadHydrodynamics::validate()).
 */
OPENMM_EXPORT_HYDRODYNAMICS void validate(const std::string& caller, const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii,
                                          double wallZ, const std::function<std::string (int blob)>& names = nullptr);

/**
 * The blobs' regularised Rotne-Prager-Blake mobility M~ per unit viscosity above the wall z = wallZ,
 * 3N x 3N: its lower triangle (the upper is left unset), rows shared out by parallel. For blobs
 * that pass validate().
 */
OPENMM_EXPORT_HYDRODYNAMICS Eigen::MatrixXd mobilityMatrix(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, double wallZ,
                                                           const KrylovSolvers::ParallelFor& parallel = KrylovSolvers::sequentially);

/**
 * out = M~ f (mobilityMatrix()'s M~, both triangles) without forming it, its rows shared out by
 * parallel. For blobs that pass validate().
 */
OPENMM_EXPORT_HYDRODYNAMICS void mobilityProduct(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, double wallZ,
                                                 const Eigen::VectorXd& f, Eigen::VectorXd& out,
                                                 const KrylovSolvers::ParallelFor& parallel = KrylovSolvers::sequentially);

} // namespace RotnePragerBlake
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_ROTNE_PRAGER_BLAKE_H_*/
