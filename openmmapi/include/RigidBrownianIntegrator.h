#ifndef RIGID_BROWNIAN_INTEGRATOR_H_
#define RIGID_BROWNIAN_INTEGRATOR_H_

/* -------------------------------------------------------------------------- *
 *                        openmm-rigid-langevin                               *
 *   Overdamped Brownian dynamics of rigid bodies of arbitrary shape in       *
 *   implicit solvent: colloids, with hydrodynamic interactions and a wall.   *
 * -------------------------------------------------------------------------- */

#include "RigidBodyIntegrator.h"

namespace RigidLangevinPlugin {

/**
 * An integrator for overdamped Brownian dynamics of rigid bodies in implicit solvent: the regime
 * of colloids, whose velocities relax within ~1e-7 s while their configuration changes over
 * milliseconds to seconds. Bodies carry no inertia; over a step h each body's position and
 * orientation move by
 *
 *     dq = N F h + sqrt(2 kT h) N^1/2 W + kT (d/dq . N) h,
 *
 * q the positions and orientations of all bodies (the orientation moved by a rotation vector in
 * the lab frame, applied by the exponential map), F their forces and torques from the System, W
 * standard normal numbers, and N the bodies' mobility: each body's own (viscosity Xi)^-1 without
 * hydrodynamic interactions, their coupled mobility (the inverse of the rigid-multiblob resistance,
 * see setHydrodynamicInteractions()) with them, and above a no-slip wall (setWall()) the mobility
 * the wall shapes. The last term, the stochastic drift, is what keeps the Gibbs-Boltzmann
 * distribution of positions and orientations stationary wherever N depends on the configuration: a
 * wall, hydrodynamic interactions, or a body whose centre of mass (the point the integrator tracks)
 * is not its centre of mobility.
 *
 * The scheme is Euler-Maruyama with the drift from random finite differences (Delong, Usabiaga,
 * Delmotte, Donev et al., J. Chem. Phys. 140, 134110 (2014)): kT (d/dq . N) is estimated without
 * derivatives as kT times N's derivative along a random displacement W' (independent standard
 * normal numbers times the smallest blob radius a, and turns that move a body's farthest blob as
 * far: a/r radians, at most 1) applied to W', a central difference over +-delta/2 of it. It is
 * weakly first order. Dense (and without interactions), the difference is of N itself, delta =
 * 1e-4. Matrix-free, it is taken in the traction form of Sprinkle, Balboa Usabiaga, Patankar and
 * Donev (J. Chem. Phys. 147, 244103 (2017)), whose differences are of products with the blobs'
 * mobility at displaced blobs after one solve, and whose result joins the step's own solve as a
 * force and a slip: a step takes one Lanczos iteration (the noise through the blobs, M^1/2 W) and
 * two mobility solves (the drift's, and the forces, noise and drift together), each a saddle-point
 * problem solved by GMRES with every body's own blocks as preconditioner, and two more products;
 * delta = tolerance^1/2, within [1e-4, 1e-2], so that neither the difference's error (delta^2) nor
 * the products' rounding (single precision's 3e-7 over delta) exceeds about the tolerance. That is
 * one solve fewer than RigidMultiblobsWall's recommended trapezoidal-slip scheme (three solves and
 * a Lanczos), with the drift explicit and testable direction by direction against the dense one,
 * and one code path for every mobility (unbounded, above a wall, in a periodic box). Without
 * interactions every body's 6x6 mobility is precomputed and a step needs no solve.
 *
 * The step size is set by the forces (a body must not move across the structure of its potential,
 * or through a wall, in one step), not by inertia: a colloid scene in OpenMM's units (lengths of
 * 1e3-1e4 nm, steps of 1e9-1e10 ps) runs in double precision without loss. A body that crosses the
 * wall in one step is refused with a message saying so. The velocities reported (a State's and the
 * body states') are the displacements of the last step over the step size, so their mean is the
 * drift velocity; they carry no kinetic energy: computeKineticEnergy() is zero, since overdamped
 * bodies have no thermal velocities to speak of.
 *
 * The bodies, their hydrodynamics, States, checkpoints and the read-outs of body states are those
 * of every rigid-body integrator: see RigidBodyIntegrator.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN RigidBrownianIntegrator : public RigidBodyIntegrator {
public:
    /**
     * Create a RigidBrownianIntegrator.
     *
     * @param temperature  the temperature of the heat bath (in Kelvin)
     * @param viscosity    the viscosity of the implicit solvent (in amu/(nm*ps)); must be positive
     * @param stepSize     the step size with which to integrate the system (in picoseconds)
     */
    RigidBrownianIntegrator(double temperature, double viscosity, double stepSize);
    /**
     * Advance a simulation through time by taking a series of time steps.
     *
     * @param steps   the number of time steps to take
     */
    void step(int steps);
protected:
    std::string className() const {
        return "RigidBrownianIntegrator";
    }
    double computeKineticEnergy();
    bool kineticEnergyRequiresForce() const;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_BROWNIAN_INTEGRATOR_H_*/
