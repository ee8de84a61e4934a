#ifndef RIGID_LANGEVIN_INTEGRATOR_H_
#define RIGID_LANGEVIN_INTEGRATOR_H_

/* -------------------------------------------------------------------------- *
 *                        openmm-rigid-langevin                               *
 *   Langevin dynamics of rigid bodies of arbitrary shape in implicit         *
 *   solvent, with a full 6x6 hydrodynamic resistance tensor per body.        *
 * -------------------------------------------------------------------------- */

#include "RigidBodyIntegrator.h"

namespace RigidLangevinPlugin {

/**
 * An integrator for Langevin dynamics of rigid bodies in implicit solvent: with inertia, the
 * friction and noise of the solvent acting on every body's velocity and angular velocity.
 *
 * Three schemes are available (see docs/physics.md):
 *  - ExactFlow (default): between two half kicks of the forces, the linear Langevin flow of the
 *    free body is integrated exactly, velocity and displacement drawn jointly. Exact velocity
 *    autocorrelation and diffusion of free bodies at any friction, Brownian dynamics in the stiff
 *    limit, velocity Verlet with DLM rotation at zero viscosity.
 *  - BAOAB: BAOAB splitting with the exact 6x6 Ornstein-Uhlenbeck step. Excellent configurational
 *    sampling; its diffusion is too fast by (gamma h/2) coth(gamma h/2) when friction is stiff.
 *  - Original: the scheme of Sun, Lin and Gezelter (J. Chem. Phys. 128, 234107, 2008): explicit
 *    friction in velocity Verlet, resolved by fixed-point iteration. Kept for comparison only; it is
 *    unstable once (h/2)*max eigenvalue of M^-1*viscosity*Xi reaches 1, and the integrator refuses
 *    to run it there.
 *
 * The bodies, their hydrodynamics and the read-outs of body states are those of every rigid-body
 * integrator: see RigidBodyIntegrator. At zero viscosity a CMMotionRemover acts as under OpenMM's
 * own integrators.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN RigidLangevinIntegrator : public RigidBodyIntegrator {
public:
    /** The integration schemes, see the class description. */
    enum Scheme {
        ExactFlow = 0,
        BAOAB = 1,
        Original = 2
    };
    /**
     * Create a RigidLangevinIntegrator.
     *
     * @param temperature  the temperature of the heat bath (in Kelvin)
     * @param viscosity    the viscosity of the implicit solvent (in amu/(nm*ps))
     * @param stepSize     the step size with which to integrate the system (in picoseconds)
     */
    RigidLangevinIntegrator(double temperature, double viscosity, double stepSize);
    /** Get the integration scheme. */
    Scheme getScheme() const {
        return scheme;
    }
    /** Set the integration scheme. Takes effect at the next step. */
    void setScheme(Scheme scheme);
    /**
     * Compute the instantaneous temperature of the system from the kinetic energy of all rigid
     * bodies and free particles and getNumDegreesOfFreedom(). If the System has a CMMotionRemover
     * (allowed at zero viscosity only), the kinetic energy of the centre of mass and its 3 degrees
     * of freedom are left out.
     */
    double computeSystemTemperature();
    /** Compute the temperature of the translational degrees of freedom alone (bodies and free particles). */
    double computeTranslationalTemperature();
    /** Compute the temperature of the rotational degrees of freedom of the rigid bodies alone. */
    double computeRotationalTemperature();
    /**
     * Advance a simulation through time by taking a series of time steps.
     *
     * @param steps   the number of time steps to take
     */
    void step(int steps);
protected:
    std::string className() const {
        return "RigidLangevinIntegrator";
    }
    double computeKineticEnergy();
    bool kineticEnergyRequiresForce() const;
    std::vector<OpenMM::Vec3> getVelocitiesForTemperature(const OpenMM::System& system, double temperature, int randomSeed) const;
    /**
     * The time by which the stored velocities lag the positions: half a step for velocity Verlet
     * (no friction) and the Original scheme; none with friction under ExactFlow and BAOAB, whose
     * stored velocities are the ones with the exact thermal distribution.
     */
    double getVelocityTimeOffset() const;
private:
    double computeTemperature(int components);
    Scheme scheme;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_INTEGRATOR_H_*/
