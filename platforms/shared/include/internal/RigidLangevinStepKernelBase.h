#ifndef RIGID_LANGEVIN_STEP_KERNEL_BASE_H_
#define RIGID_LANGEVIN_STEP_KERNEL_BASE_H_

#include "RigidLangevinKernels.h"
#include "internal/BrownianBodyStep.h"
#include "internal/CoupledBodyStep.h"
#include "internal/HydrodynamicInteractions.h"
#include "internal/RigidBodyModel.h"
#include "internal/SpectralBlobMobility.h"
#include "internal/StepCoefficients.h"
#include "internal/windowsExportRigidLangevin.h"
#include <functional>
#include <memory>
#include <vector>

namespace OpenMM {
class ThreadPool;
}

namespace RigidLangevinPlugin {

/**
 * What every platform's step kernel shares: the body model, fitting bodies to particles the user
 * set, recomputing step coefficients when a parameter changes, when a CMMotionRemover acts, which
 * kinetic energy is reported, checkpoints, and the steps taken on the host (the coupled Langevin
 * step with hydrodynamic interactions, CoupledBodyStep, and the overdamped step of
 * RigidBrownianIntegrator, BrownianBodyStep). A platform supplies where body states and
 * coefficients live, its Langevin step, kinetic energies, its random numbers (and their state),
 * where the blobs' mobility products are computed, and its threads.
 */
class OPENMM_EXPORT_RIGIDLANGEVIN RigidLangevinStepKernelBase : public IntegrateRigidLangevinStepKernel {
public:
    RigidLangevinStepKernelBase(std::string name, const OpenMM::Platform& platform);
    void initialize(const OpenMM::System& system, const RigidBodyIntegrator& integrator);
    void execute(OpenMM::ContextImpl& context, const RigidBodyIntegrator& integrator);
    void computeKineticEnergies(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator,
                                double& translational, double& rotational, double& centerOfMass);
    bool kineticEnergyRequiresForce(const RigidLangevinIntegrator& integrator) const;
    void stateChanged(OpenMM::ContextImpl& context, OpenMM::State::DataType changed);
    const RigidBodyModel& getModel(OpenMM::ContextImpl& context);
    void getBodyStates(OpenMM::ContextImpl& context, std::vector<BodyState>& states);
    void getSynchronousBodyStates(OpenMM::ContextImpl& context, const RigidBodyIntegrator& integrator, std::vector<BodyState>& states);
    void getKrylovIterations(int& noise, int& noiseSolve, int& friction) const {
        noise = lastKrylovIterations.noise;
        noiseSolve = lastKrylovIterations.noiseSolve;
        friction = lastKrylovIterations.friction;
    }
    void restoreFromState(OpenMM::ContextImpl& context, const OpenMM::SerializationNode& types, const std::vector<BodyState>& states);
    void createCheckpoint(OpenMM::ContextImpl& context, std::ostream& stream);
    void loadCheckpoint(OpenMM::ContextImpl& context, std::istream& stream);
protected:
    /** Called when the model is built, or its types restored from a checkpoint: set up per-body and per-type storage. */
    virtual void initializeBodies(OpenMM::ContextImpl& context, const RigidBodyModel& model) = 0;
    /** Store body states and place every body's particles (positions, velocities) from them. */
    virtual void uploadBodyStates(OpenMM::ContextImpl& context, const std::vector<BodyState>& states) = 0;
    /** Read the current body states. */
    virtual void downloadBodyStates(OpenMM::ContextImpl& context, std::vector<BodyState>& states) = 0;
    /** Store the step coefficients of every body type. */
    virtual void uploadCoefficients(OpenMM::ContextImpl& context, const std::vector<TypeStepCoefficients>& coefficients) = 0;
    /**
     * Take one step of every body with the forces in the context, place the particles and advance
     * the context's time and step count. If removeMotion, first subtract the velocity of the centre
     * of mass from every body (a CMMotionRemover acted on the particles before this step).
     */
    virtual void takeStep(OpenMM::ContextImpl& context, const RigidLangevinIntegrator& integrator, bool removeMotion) = 0;
    /**
     * Sum 1/2 m V^2, 1/2 sum_k j_k^2/I_k and the total momentum over all bodies, with each body's
     * velocities first kicked forward by timeShift (force and torque from the context's forces).
     */
    virtual void computeBodyKineticEnergies(OpenMM::ContextImpl& context, double timeShift, double& translational,
                                            double& rotational, OpenMM::Vec3& momentum) = 0;
    /** Write and read the state of the random number generator. */
    virtual void createRandomCheckpoint(std::ostream& stream) = 0;
    virtual void loadRandomCheckpoint(std::istream& stream) = 0;
    /**
     * The fewest blobs from which this platform takes the coupled step matrix-free by default
     * (RigidLangevinIntegrator::setKrylovMinBlobs(-1)), or -1 for never (Reference: dense and exact,
     * the definition of correct).
     */
    virtual int getDefaultKrylovMinBlobs() const {
        return -1;
    }
    /**
     * Standard normal numbers for one step taken on the host (coupled or overdamped), from one
     * stream, so that a trajectory does not depend on the number of threads. Called once a step;
     * the function returned draws that step's numbers.
     */
    virtual std::function<double ()> hostNormals() = 0;
    /** This platform's products of the blobs' mobility (on the host or a device). */
    virtual BlobMobility& blobMobility() = 0;
    /** The spectral solver's products for this platform: the host's positively split Ewald (SpectralBlobMobility) unless it has its own. */
    virtual SpectralBlobMobility* createSpectralMobility(const std::string& integratorName, const KrylovSolvers::ParallelFor& parallel) {
        return new SpectralBlobMobility(integratorName, parallel);
    }
    /** Run task over [0, count) in ranges, on the platform's threads where it has them. */
    virtual void parallelFor(int count, const std::function<void (int, int)>& task) {
        task(0, count);
    }
    /** parallelFor on pool's threads: one contiguous range each (on the calling thread below 64). */
    static void parallelForOn(OpenMM::ThreadPool& pool, int count, const std::function<void (int, int)>& task);
    /** After a step taken on the host: place sites outside bodies, advance the time by h and the step count by one. */
    virtual void finishHostStep(OpenMM::ContextImpl& context, double h) = 0;
    /**
     * With hydrodynamic interactions under RigidLangevinIntegrator: the coupled step of all bodies
     * (takeCoupledStep) with this platform's states, forces, normal numbers, mobility products and
     * threads. The caller finishes the step (finishHostStep()).
     */
    void advanceCoupledBodies(OpenMM::ContextImpl& context, const RigidBodyIntegrator& integrator);
    /**
     * How this platform solves the coupled step of these blobs (in a periodic box if periodic):
     * as the integrator's hydrodynamic solver settings say (AutomaticSolver: matrix-free from
     * getKrylovMinBlobs() blobs, and in a periodic box spectral as SpectralMinBlobs and
     * SpectralLooseTolerance say, where the blobs have at most PositivelySplitEwald::MaxRadii
     * distinct radii), or, on every
     * platform but Reference, as the environment variable RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER (dense,
     * krylov or spectral; for the tests, which run each path on small systems) overrides them.
     * Throws on any other value of the variable, and where the matrix-free step's dense Ewald sum
     * (KrylovSolver in a periodic box) would exceed the integrator's setHydrodynamicMemoryBudget().
     */
    CoupledSolve chooseCoupledSolve(const RigidBodyIntegrator& integrator, const HydrodynamicInteractions& blobs, bool periodic) const;
    /** The blobs' mobility products for a matrix-free step solved as solve says: the platform's
     *  (platformMobility) or the spectral solver's, told the solves' tolerance (BlobMobility::setTolerance()). */
    BlobMobility& stepMobility(const RigidBodyIntegrator& integrator, const CoupledSolve& solve, BlobMobility& platformMobility);
    /** Each matrix-free solve's iteration limit: beyond it the step throws, naming the solve. */
    static const int KrylovMaxIterations = 1000;
    /**
     * When AutomaticSolver takes the positively split Ewald products in a periodic box (if it is
     * matrix-free at all): from SpectralMinBlobs blobs, or at any size at a tolerance of
     * SpectralLooseTolerance or looser. Measured on the CPU platform (2 threads, one-blob spheres at
     * 5% volume fraction; benchmarks/platforms/periodic_hydrodynamics.py): at tolerance 1e-10 the
     * dense Ewald sum formed once a step is the cheaper at 300 blobs and the PSE from 1000; at 1e-6
     * the PSE from 300, at 1e-5 and looser from 100.
     */
    static const int SpectralMinBlobs = 500;
    static constexpr double SpectralLooseTolerance = 1e-5;
    /**
     * The step of bodies coupled through the solvent (CoupledBodyStep), with the integrator's
     * settings and the System's periodic box: every platform takes this step, supplying the bodies'
     * states and the particles' forces, its normal numbers (one per coordinate when dense; three per
     * blob, only at a nonzero temperature, when matrix-free), where the blobs' mobility products are
     * computed and its threads for the per-body work. Advances the states in place.
     */
    void takeCoupledStep(OpenMM::ContextImpl& context, const RigidBodyIntegrator& integrator, std::vector<BodyState>& states,
                         const std::vector<OpenMM::Vec3>& forces, const std::function<double ()>& normal, BlobMobility& mobility,
                         const KrylovSolvers::ParallelFor& parallel);
    /** The iterations the last coupled step's Krylov solves took (all zero after a dense one). */
    HydrodynamicInteractions::KrylovIterations lastKrylovIterations = {0, 0, 0};
    /**
     * Fit the bodies to the particles if those were set from outside since the last step (or moved
     * by another integrator: the context's step count is not the one this kernel left). Throws if
     * the last restore was refused and no positions were set since.
     */
    void updateBodies(OpenMM::ContextImpl& context);
    std::unique_ptr<RigidBodyModel> model;
    std::vector<TypeStepCoefficients> coefficients;
    /** The bodies' coupling through the solvent, once their types exist; null without hydrodynamic interactions. */
    std::unique_ptr<HydrodynamicInteractions> interactions;
    /** The coupled step with interactions; null without. */
    std::unique_ptr<CoupledBodyStep> coupledStep;
    /** The overdamped step, once RigidBrownianIntegrator has taken one. */
    std::unique_ptr<BrownianBodyStep> brownianStep;
    /** The spectral solver's products, once it has been used. */
    std::unique_ptr<SpectralBlobMobility> spectralMobility;
    int removerFrequency, removerIndex;
private:
    void updateCoefficients(OpenMM::ContextImpl& context, const RigidBodyIntegrator& integrator);
    /** The overdamped step of RigidBrownianIntegrator (BrownianBodyStep), on the host for every platform. */
    void takeBrownianStep(OpenMM::ContextImpl& context, const RigidBodyIntegrator& integrator);
    /** Refuse a CMMotionRemover at a nonzero viscosity (with an OpenMMException that says why and how to leave it out). */
    void checkMotionRemover(double viscosity) const;
    /** Refuse hydrodynamic interactions with a scheme other than BAOAB while there is friction. */
    void checkInteractionScheme(const RigidBodyIntegrator& integrator) const;
    /** Build the bodies' coupling from the model's types, if interactions are on. */
    void initializeInteractions();
    /** Fit the bodies to the particles in the context (building the body types the first time), and place them. */
    void fitBodiesToParticles(OpenMM::ContextImpl& context);
    /**
     * Put the bodies where a State or checkpoint saved them (its positions and velocities are in the
     * context already): its exact body states where they describe this System's bodies
     * (RigidBodyModel::restoreStates()), else fitted to the restored particles.
     */
    void restoreSavedBodies(OpenMM::ContextImpl& context, const SavedBodies& saved);
    /**
     * Run a restore; if it throws, refuse to step (and to read body states) until positions are set
     * or a restore succeeds: OpenMM has already put the file's positions, velocities, time and box
     * into the context, and the bodies no longer match them.
     */
    void refuseStepsIfRestoreFails(const std::string& source, const std::function<void ()>& restore);
    double coefficientParameters[4];
    bool bodiesInitialized, particlesChanged, ignoreStateChanges, positionsSet, interactionsEnabled;
    std::optional<double> wall;  ///< the no-slip wall's height, if the integrator has one
    /** What the last refused restore was ("State", "checkpoint"), or empty. */
    std::string refusedRestore;
    /** The context's step count when this kernel last left the bodies and particles in agreement. */
    long long expectedStepCount;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_STEP_KERNEL_BASE_H_*/
