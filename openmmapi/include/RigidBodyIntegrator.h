#ifndef RIGID_BODY_INTEGRATOR_H_
#define RIGID_BODY_INTEGRATOR_H_

/* -------------------------------------------------------------------------- *
 *                        openmm-rigid-langevin                               *
 *   Langevin and Brownian dynamics of rigid bodies of arbitrary shape in     *
 *   implicit solvent, with a full 6x6 hydrodynamic resistance tensor.        *
 * -------------------------------------------------------------------------- */

#include "openmm/Integrator.h"
#include "openmm/Kernel.h"
#include "openmm/Vec3.h"
#include "ResistanceTensor.h"
#include "internal/windowsExportRigidLangevin.h"
#include <map>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * What the integrators of rigid bodies in implicit solvent share: the bath (temperature and the
 * solvent's viscosity), the bodies and their hydrodynamics (resistance tensors, radii, blobs,
 * hydrodynamic interactions and how they are solved, a no-slip wall), and the read-outs of body
 * states. RigidLangevinIntegrator moves the bodies with inertia (Langevin dynamics);
 * RigidBrownianIntegrator without (overdamped Brownian dynamics, for colloids).
 *
 * Each rigid body is a set of particles that moves as one: its centre of mass translates and its
 * principal axes rotate, and the solvent acts on it through a 6x6 resistance tensor Xi (per unit
 * viscosity) coupling translation and rotation:
 *
 *     (force, torque) = -viscosity * Xi * (velocity, angular velocity),
 *
 * together with the random force and torque that fluctuation-dissipation requires at the bath
 * temperature. Particles in no body move as free particles with Stokes friction 6*pi*viscosity*r.
 *
 * Units are OpenMM's: temperature in K, viscosity in amu/(nm*ps) (1 poise = 60221.4 amu/(nm*ps);
 * water at 298 K is 536 amu/(nm*ps)), step size in ps, lengths in nm. A resistance tensor per unit
 * viscosity has blocks in nm (translation), nm^2 (coupling) and nm^3 (rotation).
 *
 * Bodies are defined before the Context is created. Their geometry is taken from the positions
 * first set on the Context; identical bodies (same masses, radii and shape up to rotation and
 * translation, within 1e-3 nm) share one set of precomputed matrices and the exact same shape.
 * Positions set later must agree with rigid placements of the bodies (within 1e-3 nm) and
 * velocities are projected onto rigid motion; positions that deform a body are refused at the next
 * step or reading of body states (not by setPositions() itself: OpenMM's energy minimizer sets
 * positions that break the constraints keeping bodies rigid and restores them afterwards).
 * Positions and velocities changed by another integrator (in a CompoundIntegrator) are taken as
 * they are.
 *
 * A State (setState(), with integrator parameters) or a checkpoint restores where the bodies are
 * and how they move, exactly; the physics stays this integrator's: its temperature, viscosity,
 * scheme, radii, explicit tensors and blobs, whatever the integrator that saved it had. Where the
 * saved bodies are not this integrator's (other masses, as after Context::reinitialize(true) that
 * follows setParticleMass(), or bodies or their particles listed in another order), the bodies are
 * fitted to the restored particles instead, as setPositions() and setVelocities() would, so every
 * particle is where it was saved. If the plugin's part of a checkpoint or State is refused
 * (damaged, or its particles deform this integrator's bodies), OpenMM has already restored the
 * positions, velocities, time and box from it: the integrator then refuses to step or report body
 * states until positions are set again or a restore succeeds.
 *
 * A System with a CMMotionRemover is refused (OpenMMException at Context creation, or at the first
 * step after setViscosity()) while the viscosity is not zero: the solvent's friction and noise do
 * not conserve the total momentum, and removing it would remove real motion (a lone body would not
 * diffuse). In openmm.app, createSystem(..., removeCMMotion=False).
 */
class OPENMM_EXPORT_RIGIDLANGEVIN RigidBodyIntegrator : public OpenMM::Integrator {
public:
    /** Get the temperature of the heat bath (in Kelvin). */
    double getTemperature() const {
        return temperature;
    }
    /** Set the temperature of the heat bath (in Kelvin). Takes effect at the next step. */
    void setTemperature(double temp);
    /** Get the viscosity of the solvent (in amu/(nm*ps)). */
    double getViscosity() const {
        return viscosity;
    }
    /**
     * Set the viscosity of the solvent (in amu/(nm*ps)). Resistance tensors are stored per unit
     * viscosity, so this rescales every friction without recomputing any hydrodynamics.
     */
    void setViscosity(double viscosity);
    /**
     * Get the random number seed. See setRandomNumberSeed() for details.
     */
    int getRandomNumberSeed() const {
        return randomNumberSeed;
    }
    /**
     * Set the random number seed. The precise meaning of this parameter is undefined, and is left up
     * to each Platform to interpret in an appropriate way. It is guaranteed that if two simulations
     * are run with different random number seeds, the sequence of random forces will be different. On
     * the other hand, no guarantees are made about the behavior of simulations that use the same seed.
     * In particular, Platforms are permitted to use non-deterministic algorithms which produce different
     * results on successive runs, even if those runs were initialized identically.
     *
     * If seed is set to 0 (which is the default value assigned), a unique seed is chosen when a Context
     * is created from this Integrator. This is done to ensure that each Context receives unique random
     * seeds without you needing to set them explicitly.
     */
    void setRandomNumberSeed(int seed);
    /**
     * Add a rigid body made of the given particles. A body holds one or more particles, at least
     * one of them with mass; massless particles (sites) are carried along and their forces act on
     * the body. A particle may belong to at most one body. Call this before creating a Context.
     *
     * @param particles  the indices of the particles in the body
     * @return the index of the new body
     */
    int addRigidBody(const std::vector<int>& particles);
    /** Get the number of rigid bodies that have been added. */
    int getNumRigidBodies() const {
        return bodies.size();
    }
    /** Get the particles of a rigid body. */
    const std::vector<int>& getRigidBodyParticles(int index) const;
    /**
     * Set an explicit resistance tensor for a body, replacing the default hydrodynamic model.
     *
     * The tensor belongs to the body's shape, not to a frame: it is given together with the
     * positions of the body's particles it was computed for, and the integrator carries it along
     * with the body wherever a Context places it (any initial positions, a later frame, a State).
     * Those positions must match the body's shape in the Context (within 1e-3 nm, after a rigid
     * motion); otherwise creating the Context fails naming the body and particle.
     *
     * @param index               the index of the body
     * @param tensor              36 values, row-major: the 6x6 resistance tensor per unit viscosity,
     *                            ordered so that (force, torque) = -viscosity*tensor*(velocity,
     *                            angular velocity), with velocity that of the point origin and torque
     *                            about it. It must be symmetric and positive definite.
     * @param origin              the reference point of the tensor (nm), in the frame of referencePositions
     * @param referencePositions  the positions of the body's particles (in the order given to
     *                            addRigidBody()) in the frame the tensor and origin are expressed in (nm)
     */
    void setBodyResistance(int index, const std::vector<double>& tensor, const OpenMM::Vec3& origin, const std::vector<OpenMM::Vec3>& referencePositions);
    /**
     * Get the explicit resistance tensor of a body.
     *
     * @param index                    the index of the body
     * @param[out] tensor              the 36 values set by setBodyResistance(), or empty if none was set
     * @param[out] origin              its reference point
     * @param[out] referencePositions  the positions of the body's particles the tensor belongs to
     * @return true if the body has an explicit tensor
     */
    bool getBodyResistance(int index, std::vector<double>& tensor, OpenMM::Vec3& origin, std::vector<OpenMM::Vec3>& referencePositions) const;
    /**
     * Give a body the friction of a hydrodynamic model (ResistanceTensor::ellipsoid(), beads(),
     * shellExtrapolated(), ...) computed for the body's particles at referencePositions. The same
     * as setBodyResistance() with the model's matrix and origin.
     */
    void setBodyHydrodynamics(int index, const ResistanceTensor& model, const std::vector<OpenMM::Vec3>& referencePositions);
    /** Remove the explicit resistance tensor of a body, so that it uses the default model again. */
    void clearBodyResistance(int index);
    /**
     * Set the hydrodynamic radius of a particle (nm). Without one, a particle with mass takes half the
     * sigma of its NonbondedForce Lennard-Jones parameters where epsilon is not zero; a massive particle
     * with neither is an error. Massless particles without a radius take no part in hydrodynamics.
     *
     * A body with several particles and no explicit tensor is a bead model of its particles with a
     * radius: the Rotne-Prager-Yamakawa mobility of overlapping beads with the volume correction of a
     * filling model, V the volume of the union of their spheres (ResistanceTensor::beads()). A
     * single particle is a Stokes sphere. Identical bodies compute it once.
     */
    void setParticleRadius(int particle, double radius);
    /** Get the hydrodynamic radius set for a particle (nm), or -1 if none was set. */
    double getParticleRadius(int particle) const;
    /** Get all radii set by setParticleRadius(), keyed by particle index. */
    const std::map<int, double>& getParticleRadii() const {
        return radii;
    }
    /**
     * Couple all bodies through the solvent (hydrodynamic interactions), or not (the default: each
     * body feels only its own friction, as if alone in the solvent). Call this before creating a
     * Context.
     *
     * With interactions, the solvent's friction and noise act on all bodies together through their
     * coupled resistance: moving one body drags its neighbours. Each body is a set of hydrodynamic
     * blobs (spheres fixed in it: by default its particles with a radius, see setParticleRadius();
     * or those given with setBodyBlobs()), and the bodies' resistance is that of the rigid
     * multiblob model (CoupledResistance: the blobs' generalised Rotne-Prager-Yamakawa mobility,
     * overlapping and unequal blobs included), calibrated so that a body far from every other has
     * exactly the friction it has without interactions (its bead model, or the tensor given with
     * setBodyResistance()), whatever its blobs. The coupling between bodies is as accurate as their
     * blobs resolve their surfaces: a single blob is a far-field (Rotne-Prager) sphere; blobs on the
     * surface (ResistanceTensor::roughShellBeads()) converge to the exact two-body friction as they
     * are refined. The calibration scales the coupling of distant bodies by the ratio of their
     * blobs' friction to their own (see CoupledResistance), so give a body blobs whose friction
     * alone is its tensor's: ResistanceTensor::scaleBlobsToFriction() scales them to it. The
     * friction is recomputed every step, on every platform, in double precision: dense on
     * Reference (Cholesky; cost (3B)^3/3 for B blobs in all), and on CPU, OpenCL and CUDA from 100
     * blobs matrix-free (conjugate gradients for the friction, Lanczos for the noise, each
     * preconditioned by every body's own blocks, to the relative residual of
     * setHydrodynamicTolerance(); setHydrodynamicSolver() and setKrylovMinBlobs() choose; a solve that
     * does not converge, or finds the mobility not positive definite, throws naming it; in a periodic
     * box from 500 blobs, or at a tolerance of 1e-5 or looser, with the positively split Ewald
     * products at linear cost (SpectralSolver), below that with the Ewald-summed mobility formed once
     * a step), dense below that. On OpenCL and CUDA the coupled step is taken on the host, the blobs'
     * mobility products of the Krylov solves in an unbounded solvent on the device (a tiled kernel,
     * double precision; a device without double precision is refused). In a periodic System the blobs feel
     * every image of every body (an Ewald sum of their mobility, exact for any box; see
     * CoupledResistance::setPeriodicBox()), so a lone body in a box of side L is slowed by
     * Hasimoto's finite-size correction, about 2.84 a/L for a sphere of radius a. Each step first
     * checks the blobs, dense or not, and names the body and blob it refuses: positions must be
     * finite, no two blobs may be the same sphere (on one body or two, or through the periodic
     * box), and in a periodic box every blob's diameter must be under half the box's smallest
     * width (the least distance between opposite faces), as a body must be narrower than half the
     * box, so that blobs overlap only the nearest image of each other.
     *
     * The step is BAOAB's (setScheme(BAOAB)) with the friction step the midpoint rule for all bodies
     * at once: it keeps the Maxwell distribution of velocities exactly at any friction and step,
     * the long-time diffusion of a free body exact, and the drift of a body under a constant force
     * exact (the mean of getRigidBodyStates() velocities too). Its velocities decay by
     * (1 - x/2)/(1 + x/2) a step per mode of the friction (x = gamma h of the mode) instead of
     * exp(-x): the velocity autocorrelation is right to O(x^3) a step where x is small, but it
     * alternates in sign where x > 2 (-0.83 a step at x = 21). Keep the fastest mode's gamma h below
     * 2 where velocity autocorrelations matter; positions, diffusion and the ensemble are right at
     * any step. Creating a Context or stepping with interactions under another scheme throws.
     */
    void setHydrodynamicInteractions(bool enabled);
    /**
     * The iterations the last step's Krylov solves of the coupled friction took (see
     * setHydrodynamicInteractions()), to see what a system costs and how well conditioned it is, in
     * three entries, each iteration one product with the blobs' mobility. RigidLangevinIntegrator:
     * the noise's Lanczos iteration (M^-1/2 w, preconditioned by every body's own blobs), 0 (the
     * noise needs no conjugate gradients since it is taken that way), and the friction's conjugate
     * gradients. RigidBrownianIntegrator: the noise's Lanczos iteration (M^1/2 w, preconditioned the
     * same way; with the spectral solver the positively split Ewald sum's own noise, whose Lanczos is
     * on its real-space part alone, each iteration a sparse product), the GMRES iterations of the
     * drift's mobility solve, and those of the step's mobility solve. All zero after a dense step, at zero viscosity or without interactions;
     * the noise's zero at zero temperature. The integrator must be bound to a Context.
     */
    std::vector<int> getKrylovIterations() const;
    /** Get whether bodies are coupled through the solvent (setHydrodynamicInteractions()). */
    bool getHydrodynamicInteractions() const {
        return hydrodynamicInteractions;
    }
    /** How the coupled friction of hydrodynamic interactions is solved (setHydrodynamicSolver()). */
    enum HydrodynamicSolver {
        /** Dense below getKrylovMinBlobs() blobs, matrix-free from there (dense on Reference at the default). */
        AutomaticSolver = 0,
        /** Form and factorise the bodies' coupled resistance (Cholesky): cost (3B)^3/3 for B blobs. */
        DenseSolver = 1,
        /** Matrix-free: conjugate gradients and Lanczos with products of the blobs' mobility (in a
         *  periodic box, the dense Ewald sum formed once a step: exact, but O(B^2) memory and time). */
        KrylovSolver = 2,
        /** As KrylovSolver, but in a periodic box the products are the positively split Ewald sum's
         *  (PSE: matrix-free, linear cost and memory, at epsilon = setHydrodynamicTolerance(), which
         *  must then be at least 1e-10; the blobs may have at most 4 distinct radii, each costing two
         *  sets of FFTs per product); in an unbounded solvent or above a wall, KrylovSolver. */
        SpectralSolver = 3
    };
    /**
     * Set how the coupled friction of hydrodynamic interactions is solved (the default is
     * AutomaticSolver). Takes effect at the next step. In a periodic box AutomaticSolver takes
     * SpectralSolver's products where it is matrix-free and there are at least 500 blobs or the
     * tolerance is 1e-5 or looser (where they are the faster on the CPU:
     * benchmarks/platforms/periodic_hydrodynamics.py), and the blobs have at most 4 distinct radii
     * (SpectralSolver refuses more, naming them); KrylovSolver's dense Ewald sum (72 B^2 bytes
     * for B blobs) is refused beyond setHydrodynamicMemoryBudget(). On OpenCL and CUDA the
     * spectral products run on the device (OpenMM's FFTs), in the context's precision where that
     * reaches the tolerance (float, in single and mixed precision, from 1e-5) and otherwise on the
     * host; their parameters and real-space pairs are prepared on the host once a step. (The environment
     * variable RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER, dense, krylov or spectral, overrides it on every
     * platform but Reference; it is there for the tests, which run each path on small systems.)
     */
    void setHydrodynamicSolver(HydrodynamicSolver solver);
    /** Get how the coupled friction of hydrodynamic interactions is solved (setHydrodynamicSolver()). */
    HydrodynamicSolver getHydrodynamicSolver() const {
        return hydrodynamicSolver;
    }
    /**
     * Set the relative residual at which the matrix-free solves of the coupled friction stop
     * (conjugate gradients and GMRES: |b - A x| <= tolerance |b|; Lanczos: its estimate within
     * tolerance of the one three iterations before), between 1e-12 (what double precision reaches
     * reliably) and 0.1. The default, 1e-4, is chosen from the error it causes
     * (benchmarks/hydrodynamics/tolerance_error.py, boomerang suspensions of 16 to 256 bodies): a step
     * of RigidLangevinIntegrator is then within about 5.4e-5 of the exactly solved step, relative, and
     * one of RigidBrownianIntegrator within 1.6e-4, so a mean or covariance of the motion is off by at
     * most about 0.03%, below what runs resolve; 1e-8 costs about twice the products. With
     * SpectralSolver in a periodic box the tolerance is also the positively split Ewald products'
     * epsilon (their error is at most 0.3 epsilon of |M f|, so it does not limit the solves), which
     * must be at least 1e-10: a spectral step at a tighter tolerance is refused. At 1e-5 or looser
     * (the default included) the matrix-free products on the host (beyond 100 blobs, open space and
     * above a wall) evaluate their pair terms in single precision, within 3e-7 of the exact product
     * and about twice as fast; tighter, in double. Takes effect at the next step.
     */
    void setHydrodynamicTolerance(double tolerance);
    /** Get the relative residual at which the matrix-free solves stop (setHydrodynamicTolerance()). */
    double getHydrodynamicTolerance() const {
        return hydrodynamicTolerance;
    }
    /**
     * Set the number of blobs from which AutomaticSolver solves matrix-free (dense below), or -1 for
     * the platform's default: 100 on CPU, OpenCL and CUDA, where the matrix-free step is already the
     * faster (benchmarks/platforms/hydrodynamic_interactions.py); never on Reference, whose dense,
     * exact step is the definition of correct. Takes effect at the next step.
     */
    void setKrylovMinBlobs(int blobs);
    /** Get the number of blobs from which AutomaticSolver solves matrix-free, or -1 for the platform's default (setKrylovMinBlobs()). */
    int getKrylovMinBlobs() const {
        return krylovMinBlobs;
    }
    /**
     * Set the most memory (bytes) the matrix-free step's products of the blobs' mobility may hold in
     * a periodic box: the spectral solver's positively split Ewald grid and real-space pairs, and
     * KrylovSolver's dense Ewald sum (72 B^2 bytes for B blobs). A step that would need more is
     * refused, before anything large is allocated, with a message giving the bytes it needs. The
     * default is 4 GiB. Takes effect at the next step.
     */
    void setHydrodynamicMemoryBudget(double bytes);
    /** Get the most memory (bytes) the matrix-free step's periodic products may hold (setHydrodynamicMemoryBudget()). */
    double getHydrodynamicMemoryBudget() const {
        return hydrodynamicMemoryBudget;
    }
    /**
     * Give a body the hydrodynamic blobs through which it feels other bodies when hydrodynamic
     * interactions are on (setHydrodynamicInteractions()), replacing its particles with a radius.
     * Like an explicit tensor, the blobs belong to the body's shape: they are given together with
     * the positions of the body's particles they were placed around, and move with the body.
     * A body that does not rotate (its mass at one point) must have its blobs at that point, a
     * linear body on its axis. Call this before creating a Context.
     *
     * @param index               the index of the body
     * @param blobPositions       the centres of its blobs (nm), in the frame of referencePositions
     * @param blobRadii           their radii (nm), positive
     * @param referencePositions  the positions of the body's particles (in the order given to
     *                            addRigidBody()) in the same frame (nm)
     */
    void setBodyBlobs(int index, const std::vector<OpenMM::Vec3>& blobPositions, const std::vector<double>& blobRadii,
                      const std::vector<OpenMM::Vec3>& referencePositions);
    /**
     * Get the blobs given to a body with setBodyBlobs().
     *
     * @param index                    the index of the body
     * @param[out] blobPositions       their centres, or empty if none were given
     * @param[out] blobRadii           their radii
     * @param[out] referencePositions  the positions of the body's particles they belong to
     * @return true if the body has blobs given explicitly
     */
    bool getBodyBlobs(int index, std::vector<OpenMM::Vec3>& blobPositions, std::vector<double>& blobRadii,
                      std::vector<OpenMM::Vec3>& referencePositions) const;
    /** Remove the blobs given to a body, so that its particles with a radius are its blobs again. */
    void clearBodyBlobs(int index);
    /**
     * Get the number of degrees of freedom the integrator moves: 6 per rigid body (5 for a linear
     * body, 3 for a body whose mass is all at one point), plus 3 per free particle with mass.
     * This needs a Context with positions, since whether a body is linear depends on its shape.
     * A CMMotionRemover does not change this count; computeSystemTemperature() accounts for it.
     */
    int getNumDegreesOfFreedom() const;
    /**
     * Get the state of every rigid body added with addRigidBody(), in that order. Needs a Context
     * with positions; computes the forces at them. A particle at body-frame coordinates b (see
     * getRigidBodyCoordinates()) is at center + A b and moves at velocity + angularVelocity x A b.
     *
     * The velocities are synchronous with the positions: the velocity a body has under the forces
     * at its position, which for a body pulled by a constant force F averages exactly its drift
     * velocity (F/(m gamma) for a sphere of friction m gamma) at any step and friction under
     * ExactFlow, and whose fluctuations under a constant force have the exact autocorrelation
     * exp(-gamma t). Under ExactFlow with friction they are the stored velocity plus
     * beta(gamma h) = 1/(gamma h) - 1/(exp(gamma h) - 1) of a full kick h F/m (per mode of
     * M^-1 viscosity Xi): one half without friction (velocity Verlet's on-step velocity), 1/(gamma h)
     * when friction is stiff. Under BAOAB (with or without hydrodynamic interactions) and Original
     * they are the stored velocity plus half a kick: under BAOAB their mean is BAOAB's own drift,
     * (gamma h/2) coth(gamma h/2) times F/(m gamma) (as its diffusion is too fast by that factor),
     * exactly F/(m gamma) with hydrodynamic interactions (whose friction step's autocorrelation is
     * described at setHydrodynamicInteractions()).
     *
     * A State's velocities, and the particle velocities the Context holds, are instead the stored
     * ones, as OpenMM's own integrators store theirs: with friction under ExactFlow and BAOAB the
     * velocities whose distribution is exactly Maxwell's for free bodies (the ones
     * computeKineticEnergy() and the temperatures use), which under a constant force average
     * gamma h/(exp(gamma h) - 1) of the drift (0.90 at gamma h = 0.2, 0.31 at 2, 0 when gamma h is
     * large); without friction and under Original, half a kick behind the positions. Measure drift
     * velocities (sedimentation, electrophoresis) and velocity autocorrelations from these body
     * states, not from a State's velocities.
     *
     * @param[out] centers            each body's centre of mass (nm), unwrapped: it moves on across
     *                                the periodic box, so that a body's displacement is its motion
     *                                (wrap it yourself if you want it in the box)
     * @param[out] orientations       9 values per body, row-major: the rotation A (body frame to
     *                                lab) whose columns are the body's principal axes of inertia in
     *                                the lab frame, in the order of getRigidBodyCoordinates()
     * @param[out] velocities         each body's centre-of-mass velocity (nm/ps), synchronous
     * @param[out] angularVelocities  each body's angular velocity in the lab frame (radians/ps),
     *                                synchronous; a linear body never turns about its own axis
     */
    void getRigidBodyStates(std::vector<OpenMM::Vec3>& centers, std::vector<double>& orientations, std::vector<OpenMM::Vec3>& velocities,
                            std::vector<OpenMM::Vec3>& angularVelocities) const;
    /**
     * Get the coordinates (nm) of a rigid body's particles in its own frame: relative to its centre
     * of mass, along its principal axes (the columns of its orientation in getRigidBodyStates()),
     * in the order given to addRigidBody(). Fixed for the life of a Context; needs one with positions.
     */
    std::vector<OpenMM::Vec3> getRigidBodyCoordinates(int index) const;
    /**
     * Get the number of body types: bodies with the same masses, radii, friction model and shape
     * (up to a rotation, within 1e-3 nm) share one, and with it every precomputed matrix and one
     * hydrodynamic calculation. Free particles count too. Needs a Context with positions.
     */
    int getNumBodyTypes() const;
    /**
     * Bound the fluid by a no-slip wall, the plane z = height (nm), the fluid above it: the blobs'
     * mobility becomes the Rotne-Prager-Blake tensor (the Rotne-Prager-Yamakawa tensor and the
     * wall's image system), so every body's friction depends on its height and orientation, and
     * bodies feel each other through the flow the wall shapes. The wall acts through the blobs'
     * mobility, so it needs hydrodynamic interactions (setHydrodynamicInteractions(true)); a blob
     * centre at or below the wall is refused, naming the body. Gravity and the wall's repulsion are
     * forces of the System (a CustomExternalForce on the blobs' particles). Call this before
     * creating a Context.
     */
    void setWall(double height);
    /** Remove the wall (the default: an unbounded solvent, or the periodic box of the System). */
    void clearWall();
    /**
     * Get the wall (setWall()).
     *
     * @param[out] height  the wall's height (nm) if there is one
     * @return true if the fluid is bounded by a wall
     */
    bool getWall(double& height) const;
protected:
    RigidBodyIntegrator(double temperature, double viscosity, double stepSize);
    void initialize(OpenMM::ContextImpl& context);
    void cleanup();
    std::vector<std::string> getKernelNames();
    void stateChanged(OpenMM::State::DataType changed);
    void createCheckpoint(std::ostream& stream) const;
    void loadCheckpoint(std::istream& stream);
    void serializeParameters(OpenMM::SerializationNode& node) const;
    void deserializeParameters(const OpenMM::SerializationNode& node);
    /** The integrator's class name, for messages ("RigidBodyIntegrator" while it is being constructed). */
    virtual std::string className() const {
        return "RigidBodyIntegrator";
    }
    /** Throw if the integrator is not bound to a Context, naming method. */
    void checkBound(const char* method) const;
    mutable OpenMM::Kernel kernel;
private:
    struct BodyResistance {
        std::vector<double> tensor;
        OpenMM::Vec3 origin;
        std::vector<OpenMM::Vec3> referencePositions;
    };
    struct BodyBlobs {
        std::vector<OpenMM::Vec3> positions;
        std::vector<double> radii;
        std::vector<OpenMM::Vec3> referencePositions;
    };
    void checkNotBound(const char* method) const;
    void checkBodyIndex(int index, const char* method) const;
    double temperature, viscosity;
    int randomNumberSeed;
    bool hydrodynamicInteractions;
    HydrodynamicSolver hydrodynamicSolver;
    double hydrodynamicTolerance;
    int krylovMinBlobs;
    double hydrodynamicMemoryBudget;
    bool wall;
    double wallHeight;
    std::vector<std::vector<int> > bodies;
    std::map<int, BodyResistance> resistances;
    std::map<int, BodyBlobs> blobs;
    std::map<int, double> radii;
    std::map<int, int> particleBody;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_BODY_INTEGRATOR_H_*/
