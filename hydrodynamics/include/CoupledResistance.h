#ifndef RIGID_LANGEVIN_COUPLED_RESISTANCE_H_
#define RIGID_LANGEVIN_COUPLED_RESISTANCE_H_

#include "ResistanceTensor.h"
#include "openmm/Vec3.h"
#include "internal/windowsExportHydrodynamics.h"
#include <vector>

namespace RigidLangevinPlugin {

/**
 * Rigid bodies that feel each other through the solvent: the resistance of several bodies moving
 * at once, each made of blobs (spheres fixed in the body), in an unbounded fluid. This is the
 * standard rigid multiblob formulation (Usabiaga et al., Commun. Appl. Math. Comput. Sci. 11, 217
 * (2016)): M is the blobs' generalised Rotne-Prager-Yamakawa mobility (Zuk et al., J. Fluid Mech.
 * 741, R5 (2014): unequal radii and overlapping blobs included, positive definite for every
 * configuration of distinct blobs), K maps the bodies' velocities to their blobs' velocities
 * (u_k = V_b + omega_b x (r_k - o_b) for blob k of body b, o_b its reference point), and the
 * bodies' resistance per unit viscosity is
 *
 *     R = K^T M^-1 K     (6N x 6N, symmetric positive semidefinite),
 *
 * (forces and torques on every body) = -viscosity R (velocities and angular velocities of every
 * body), body by body in the order added, each with its velocity first and its angular velocity
 * second, the velocity that of its reference point and the torque about it; the blocks' units are
 * those of ResistanceTensor (nm, nm^2, nm^3 per unit viscosity). With one body R is that body's
 * ResistanceTensor::beads() tensor (without volume correction); bodies far apart decouple, each
 * diagonal block tending to its own tensor as the coupling falls off with distance like
 * (size/distance).
 *
 * A body of few blobs resolves its shape only roughly, so alone it has the friction of its blobs, not
 * the one of its own hydrodynamic model. setBodyResistance() calibrates it: with D its blobs'
 * resistance alone and Xi its own tensor, the symmetric positive definite T with T D T = Xi
 * replaces R by T^T R T (T acting on the body's six rows and columns). That is a congruence, so R
 * stays symmetric positive definite for every configuration; the body alone then has exactly Xi,
 * whatever its blobs; and as its blobs are refined (D -> Xi) T tends to the identity and R to the
 * uncalibrated one. The integrator couples bodies this way (RigidLangevinIntegrator::
 * setHydrodynamicInteractions()).
 *
 * The congruence scales the coupling between bodies too. Far apart, two bodies' mobility coupling
 * tends to the Oseen tensor whatever their blobs (a force seen from afar is a point force);
 * calibrated, it is T_a^-1 (coupling) T_b^-1: for spheres of radius a, the Oseen tensor times
 * a_eff/a, a_eff the radius of their blobs' own friction (shells of 65, 136 and 284 blobs on the
 * surface: 3.6%, 2.6% and 1.8% too strong). Blobs far from the body's friction (a few small beads
 * for a large body) couple it by their own size, not its. ResistanceTensor::scaleBlobsToFriction()
 * scales a body's blobs until their translational friction is its own: then T is the identity on
 * translation up to the blobs' anisotropy, and two distant spheres couple by the Oseen tensor to
 * 0.1% (tested); such shells also give a suspension's short-time self-diffusion nearer Batchelor's
 * exact value at every resolution than shells on the surface (tests/test_hydrodynamics.py).
 *
 * Dense and exact: M is Cholesky-factorised and solved for the 6N columns of K (cost (3B)^3/3 for B
 * blobs, memory 72 B^2 bytes). This is the definition of correct that faster methods are tested
 * against; it holds some thousands of blobs. M is factorised by the bead kernel's blocked
 * Cholesky (its AVX2/FMA build where the CPU has it), and from 200 blobs M is formed, factorised
 * and solved on OPENMM_CPU_THREADS threads (default: all cores), with the same result on any
 * number of them: 256 fifteen-blob boomerangs (3840 blobs) take about 20 s on the development
 * machine's 2 cores (49 s before; benchmarks/hydrodynamics/README.md).
 */
class OPENMM_EXPORT_HYDRODYNAMICS CoupledResistance {
public:
    /** Bodies in an unbounded solvent, until setPeriodicBox() is called. */
    CoupledResistance();
    /**
     * Put the bodies in a periodic box (three vectors in nm, OpenMM's reduced triclinic form or
     * any right-handed box): the blobs' mobility M is then the Ewald sum over all their images
     * (Hasimoto's split, both parts positive definite; a lone blob in a cube of side L has the
     * mobility (1 - 2.837297 a/L + 4 pi/3 (a/L)^3)/(6 pi viscosity a) exactly while 2a < L). A
     * body's blobs are taken where they are given, relative to its reference point, so give each
     * body whole. A calibrated body (setBodyResistance()) is calibrated alone in an unbounded
     * solvent, where its own tensor belongs; in the box it then also feels its images.
     *
     * Every blob's diameter must be under half the box's smallest width (the least distance
     * between two opposite faces), as the integrator asks of a body: then two blobs overlap at most
     * the nearest image of each other, and a blob none of its own. Larger blobs overlap several
     * images at once, where the overlap-regularised kernel no longer describes spheres in a box
     * (and Hasimoto's expansion no longer holds); getResistance() refuses them, naming the blob.
     */
    void setPeriodicBox(const OpenMM::Vec3& a, const OpenMM::Vec3& b, const OpenMM::Vec3& c);
    /**
     * Bound the fluid below by a no-slip wall, the plane z = z0 (nm), the bodies above it: the
     * blobs' mobility M is then Rotne-Prager-Blake's (the Rotne-Prager-Yamakawa tensor plus the
     * wall's image system; Swan & Brady, Phys. Fluids 19, 113306 (2007), any radii), with blobs
     * closer to the wall than their radius regularised as Balboa Usabiaga, Delmotte & Donev do (J.
     * Chem. Phys. 146, 134104 (2017): evaluated at a radius above it, damped by their height over
     * their radius), so that R stays symmetric positive definite. A lone blob of radius a at
     * height h then has the mobility (1 - 9x/16 + x^3/8 - x^5/16)/(6 pi a) along the wall and
     * (1 - 9x/8 + x^3/2 - x^5/8)/(6 pi a) across it, x = a/h. R now depends on where the bodies
     * are, not only on where they are relative to each other: with one body added it is that
     * body's resistance at its height and orientation. getResistance() refuses a blob whose centre
     * is at or below the wall, naming its body. A calibrated body (setBodyResistance()) is
     * calibrated alone in an unbounded solvent, where its own tensor belongs; above the wall it
     * then also feels the wall. A wall and a periodic box together are not supported: the second
     * of setWall() and setPeriodicBox() throws.
     */
    void setWall(double z0);
    /**
     * Add a body.
     *
     * @param blobPositions  the centres of its blobs (nm), where the body is
     * @param blobRadii      their radii (nm), positive
     * @param origin         the body's reference point (nm): its velocity is that of this point and
     *                       torques on it are taken about it
     * @return the index of the body
     */
    int addBody(const std::vector<OpenMM::Vec3>& blobPositions, const std::vector<double>& blobRadii, const OpenMM::Vec3& origin);
    /**
     * Calibrate a body so that, alone, it has exactly the friction own (see the class description):
     * a tensor of the same body where it now is, such as ResistanceTensor::shellExtrapolated() or
     * ellipsoid() of its shape, or beads() of its blobs with a volume correction. The body's blobs
     * must resist every motion (six degrees of freedom: not one blob, not all on a line), or
     * getResistance() throws naming it.
     */
    void setBodyResistance(int body, const ResistanceTensor& own);
    /** Get the number of bodies that have been added. */
    int getNumBodies() const {
        return origins.size();
    }
    /**
     * The 36 N^2 values, row-major, of the bodies' resistance R per unit viscosity (see the class
     * description). Throws an OpenMMException naming the blobs (blob k of body b) if two of them are
     * the same sphere, on one body or two, or in a periodic box through it (then M is singular), if
     * a blob's position or radius is not finite and positive, or if in a periodic box a blob is too
     * large for it (see setPeriodicBox()).
     */
    std::vector<double> getResistance() const;
    /**
     * The 36 N^2 values, row-major, of the bodies' mobility R^-1 per unit viscosity: (velocities and
     * angular velocities) = mobility (forces and torques) / viscosity. Throws an OpenMMException
     * naming the body if R is singular: a body of one blob, or of blobs on one line, has no
     * friction for some rotation.
     */
    std::vector<double> getMobility() const;
private:
    std::vector<std::vector<OpenMM::Vec3> > blobs;
    std::vector<std::vector<double> > radii;
    std::vector<OpenMM::Vec3> origins;
    std::vector<std::vector<double> > ownResistance;  // about the body's origin; empty if not calibrated
    bool periodic, wall;
    OpenMM::Vec3 box[3];
    double wallZ;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_COUPLED_RESISTANCE_H_*/
