#include "internal/RigidLangevinStepKernelBase.h"
#include "internal/RotnePragerBlake.h"
#include "internal/BodyDynamics.h"
#include "internal/CheckpointSection.h"
#include "openmm/CMMotionRemover.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/internal/ThreadPool.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <cmath>
#include <cstdlib>
#include <istream>
#include <limits>
#include <ostream>
#include <sstream>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

RigidLangevinStepKernelBase::RigidLangevinStepKernelBase(std::string name, const Platform& platform) :
        IntegrateRigidLangevinStepKernel(name, platform), removerFrequency(0), removerIndex(-1), bodiesInitialized(false), particlesChanged(true),
        ignoreStateChanges(false), positionsSet(false), interactionsEnabled(false), expectedStepCount(-1) {
    for (double& p : coefficientParameters)
        p = std::numeric_limits<double>::quiet_NaN();
}

namespace {

/** The Langevin integrator, or null for the overdamped one. */
const RigidLangevinIntegrator* langevin(const RigidBodyIntegrator& integrator) {
    return dynamic_cast<const RigidLangevinIntegrator*>(&integrator);
}

/** The integrator's class name, for messages. */
std::string integratorName(const RigidBodyIntegrator& integrator) {
    return (langevin(integrator) != NULL ? "RigidLangevinIntegrator" : "RigidBrownianIntegrator");
}

/** The integrator's scheme, as the model's coefficients name it (the same values: RigidLangevinIntegrator.cpp). */
SplittingScheme stepScheme(const RigidBodyIntegrator& integrator) {
    const RigidLangevinIntegrator* inertial = langevin(integrator);
    return (inertial == NULL ? SplittingScheme::Overdamped : static_cast<SplittingScheme>(inertial->getScheme()));
}

/** The time by which the integrator's reported velocities are kicked forward (the model's rule). */
double integratorVelocityOffset(const RigidBodyIntegrator& integrator) {
    return velocityTimeOffset(stepScheme(integrator), integrator.getViscosity(), integrator.getStepSize());
}

/** The bodies the user gave the integrator, as the plain description the model is built from. */
RigidBodyDescription describeBodies(const RigidBodyIntegrator& integrator) {
    RigidBodyDescription description;
    description.bodies.resize(integrator.getNumRigidBodies());
    for (int b = 0; b < integrator.getNumRigidBodies(); b++) {
        RigidBodyDescription::Body& body = description.bodies[b];
        body.particles = integrator.getRigidBodyParticles(b);
        integrator.getBodyResistance(b, body.resistance, body.resistanceOrigin, body.resistanceReference);
        integrator.getBodyBlobs(b, body.blobPositions, body.blobRadii, body.blobReference);
    }
    description.particleRadii = integrator.getParticleRadii();
    description.hydrodynamicInteractions = integrator.getHydrodynamicInteractions();
    description.integratorName = integratorName(integrator);
    return description;
}

} // namespace

void RigidLangevinStepKernelBase::initialize(const System& system, const RigidBodyIntegrator& integrator) {
    model.reset(new RigidBodyModel(system, describeBodies(integrator)));
    for (int i = 0; i < system.getNumForces(); i++) {
        const CMMotionRemover* remover = dynamic_cast<const CMMotionRemover*>(&system.getForce(i));
        if (remover != NULL) {
            removerFrequency = remover->getFrequency();
            removerIndex = i;
        }
    }
    checkMotionRemover(integrator.getViscosity());
    interactionsEnabled = integrator.getHydrodynamicInteractions();
    if (interactionsEnabled)
        checkInteractionScheme(integrator);
    double height;
    wall = (integrator.getWall(height) ? std::optional<double>(height) : std::nullopt);
    if (wall && !interactionsEnabled)
        throw OpenMMException(integratorName(integrator)+": a no-slip wall (setWall()) acts through the blobs' mobility: "
                              "call setHydrodynamicInteractions(true) too (a body alone above the wall then feels it)");
    if (wall && system.usesPeriodicBoundaryConditions())
        throw OpenMMException(integratorName(integrator)+": a no-slip wall (setWall()) with a periodic System is not supported: "
                              "use a non-periodic System (no periodic forces), or clearWall()");
}

void RigidLangevinStepKernelBase::checkInteractionScheme(const RigidBodyIntegrator& integrator) const {
    const RigidLangevinIntegrator* inertial = langevin(integrator);
    if (interactionsEnabled && inertial != NULL && integrator.getViscosity() != 0 && inertial->getScheme() != RigidLangevinIntegrator::BAOAB)
        throw OpenMMException("RigidLangevinIntegrator: hydrodynamic interactions are integrated with the BAOAB scheme, whose friction step couples all "
                "bodies at once; call setScheme(RigidLangevinIntegrator::BAOAB) (in Python, rigidlangevin.RigidLangevinIntegrator.BAOAB)");
}

void RigidLangevinStepKernelBase::initializeInteractions() {
    if (interactionsEnabled) {
        interactions.reset(new HydrodynamicInteractions(*model, wall));
        if (wall)
            blobMobility().setWall(*wall);
        coupledStep.reset(new CoupledBodyStep(*model, *interactions));
    }
    brownianStep.reset();
}

CoupledSolve RigidLangevinStepKernelBase::chooseCoupledSolve(const RigidBodyIntegrator& integrator, const HydrodynamicInteractions& blobs, bool periodic) const {
    const int numBlobs = blobs.getNumBlobs();
    // The PSE takes a few distinct radii (two FFTs per product each); AutomaticSolver does not choose it beyond them.
    const bool spectralTakesRadii = (blobs.getNumBlobRadii() <= PositivelySplitEwald::MaxRadii);
    CoupledSolve solve = {false, integrator.getHydrodynamicTolerance(), KrylovMaxIterations, false};
    const int platformMinBlobs = getDefaultKrylovMinBlobs();
    const char* setting = std::getenv("RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER");
    if (platformMinBlobs >= 0 && setting != NULL && std::string(setting) != "") {
        const std::string value(setting);
        if (value != "krylov" && value != "dense" && value != "spectral")
            throw OpenMMException("RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER is '"+value+"': set it to dense, krylov or spectral, or unset it");
        solve.krylov = (value != "dense");
        solve.spectral = (periodic && value == "spectral");
    }
    else if (integrator.getHydrodynamicSolver() != RigidLangevinIntegrator::AutomaticSolver) {
        solve.krylov = (integrator.getHydrodynamicSolver() != RigidLangevinIntegrator::DenseSolver);
        solve.spectral = (periodic && integrator.getHydrodynamicSolver() == RigidLangevinIntegrator::SpectralSolver);
    }
    else {
        int minBlobs = (integrator.getKrylovMinBlobs() >= 0 ? integrator.getKrylovMinBlobs() : platformMinBlobs);
        solve.krylov = (minBlobs >= 0 && numBlobs >= minBlobs);
        solve.spectral = (solve.krylov && periodic && spectralTakesRadii && (numBlobs >= SpectralMinBlobs || solve.tolerance >= SpectralLooseTolerance));
    }
    // The dense Ewald sum of the matrix-free step: 8 (3B)^2 bytes, formed every step.
    const double denseBytes = 72.0*numBlobs*numBlobs;
    const double budget = integrator.getHydrodynamicMemoryBudget();
    if (solve.krylov && periodic && !solve.spectral && denseBytes > budget)
        throw OpenMMException(integratorName(integrator)+": the matrix-free solver in a periodic box with the dense Ewald sum (KrylovSolver) forms "
                "the blobs' mobility every step, "+std::to_string((long long) (denseBytes/(1<<20)))+" MiB for "+std::to_string(numBlobs)+
                " blobs, more than the budget of "+std::to_string((long long) (budget/(1<<20)))+" MiB (setHydrodynamicMemoryBudget()): "+
                (spectralTakesRadii ? "call setHydrodynamicSolver(SpectralSolver) (the positively split Ewald sum, linear memory) or AutomaticSolver, or raise the budget" :
                 "raise the budget, or give the blobs at most "+std::to_string(PositivelySplitEwald::MaxRadii)+" distinct radii (they have "+
                 std::to_string(blobs.getNumBlobRadii())+"; setParticleRadius(), setBodyBlobs()) so that the spectral solver (the positively split "
                 "Ewald sum, linear memory) can take them"));
    return solve;
}

void RigidLangevinStepKernelBase::parallelForOn(ThreadPool& pool, int count, const std::function<void (int, int)>& task) {
    const int numThreads = pool.getNumThreads();
    if (numThreads == 1 || count < 64) {
        task(0, count);
        return;
    }
    // Each thread takes whole rows, so the results do not depend on the number of threads.
    pool.execute([&] (ThreadPool& /*pool*/, int thread) {
        task((int) ((long long) count*thread/numThreads), (int) ((long long) count*(thread+1)/numThreads));
    });
    pool.waitForThreads();
}

BlobMobility& RigidLangevinStepKernelBase::stepMobility(const RigidBodyIntegrator& integrator, const CoupledSolve& solve, BlobMobility& platformMobility) {
    BlobMobility* mobility = &platformMobility;
    if (solve.spectral) {
        if (!spectralMobility)
            spectralMobility.reset(createSpectralMobility(integratorName(integrator),
                    [this] (int count, const std::function<void (int, int)>& task) { parallelFor(count, task); }));
        spectralMobility->setMemoryBudget(integrator.getHydrodynamicMemoryBudget());
        mobility = spectralMobility.get();
    }
    mobility->setTolerance(solve.tolerance);
    return *mobility;
}

void RigidLangevinStepKernelBase::takeCoupledStep(ContextImpl& context, const RigidBodyIntegrator& integrator, vector<BodyState>& states,
                                                  const vector<Vec3>& forces, const std::function<double ()>& normal, BlobMobility& mobility,
                                                  const KrylovSolvers::ParallelFor& parallel) {
    Vec3 box[3];
    const bool periodic = context.getSystem().usesPeriodicBoundaryConditions();
    if (periodic)
        context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    CoupledStepParameters step = {integrator.getStepSize(), integrator.getViscosity(), BOLTZ*integrator.getTemperature(), periodic ? box : NULL};
    const CoupledSolve solve = chooseCoupledSolve(integrator, *interactions, periodic);
    coupledStep->take(states, forces, step, solve, normal, stepMobility(integrator, solve, mobility), parallel);
    lastKrylovIterations = coupledStep->getLastIterations();
}

void RigidLangevinStepKernelBase::checkMotionRemover(double viscosity) const {
    // The solvent's friction and noise do not conserve the total momentum: removing it removes
    // real motion (a lone body would not diffuse at all; N bodies diffuse 1/N too slowly) and
    // three degrees of freedom. Without friction (NVE) the remover does what it does elsewhere.
    if (removerFrequency > 0 && viscosity != 0)
        throw OpenMMException(model->getIntegratorName()+": the System has a CMMotionRemover (force "+std::to_string(removerIndex)+
                ") and the viscosity is not zero. The solvent's friction does not conserve the total momentum, so removing it would "
                "remove real motion: a lone body would not diffuse at all. Leave the remover out: createSystem(..., removeCMMotion=False) "
                "in openmm.app, or System.removeForce("+std::to_string(removerIndex)+"). (At zero viscosity a CMMotionRemover is allowed.)");
}

bool RigidLangevinStepKernelBase::kineticEnergyRequiresForce(const RigidLangevinIntegrator& integrator) const {
    return integratorVelocityOffset(integrator) != 0;
}

void RigidLangevinStepKernelBase::stateChanged(ContextImpl& /*context*/, State::DataType changed) {
    if (changed != State::Positions && changed != State::Velocities)
        return;
    // States set or loaded: the run continues from them alone (HydrodynamicInteractions::forgetWarmStart).
    if (interactions)
        interactions->forgetWarmStart();
    if (ignoreStateChanges) {
        // ContextImpl::loadCheckpoint() reports positions, then velocities, as changed after the
        // integrator restored its exact body states; the particles already match them.
        if (changed == State::Velocities)
            ignoreStateChanges = false;
        return;
    }
    if (changed == State::Positions) {
        positionsSet = true;
        refusedRestore.clear();
    }
    // A position that deforms a body is refused at the next step or reading of body states, not
    // here: OpenMM's energy minimizer sets positions that break the constraints keeping bodies
    // rigid, and restores those constraints only afterwards.
    particlesChanged = true;
}

void RigidLangevinStepKernelBase::updateBodies(ContextImpl& context) {
    if (!refusedRestore.empty())
        throw OpenMMException(model->getIntegratorName()+": the last "+refusedRestore+" was refused, but OpenMM had already set the Context's positions, "
                "velocities, time and box from it, so the rigid bodies do not match them. Load a "+refusedRestore+" that is accepted, or set the "
                "positions (and velocities) or a State, before stepping");
    if (context.getStepCount() != expectedStepCount)
        particlesChanged = true;  // another integrator (in a CompoundIntegrator) stepped
    if (!particlesChanged)
        return;
    if (!positionsSet)
        throw OpenMMException(model->getIntegratorName()+": the particle positions have not been set; rigid bodies take their shapes from them");
    fitBodiesToParticles(context);
}

void RigidLangevinStepKernelBase::fitBodiesToParticles(ContextImpl& context) {
    vector<Vec3> positions, velocities;
    context.getPositions(positions);
    context.getVelocities(velocities);
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    bool periodic = context.getSystem().usesPeriodicBoundaryConditions();
    vector<BodyState> states;
    try {
        states = model->fitStates(positions, velocities, periodic ? box : NULL);
    }
    catch (...) {
        if (!bodiesInitialized)
            model->clearTypes();  // a first build cut short leaves no half-built types behind
        throw;
    }
    if (!bodiesInitialized) {
        initializeInteractions();
        initializeBodies(context, *model);
        bodiesInitialized = true;
    }
    uploadBodyStates(context, states);
    context.computeVirtualSites();
    particlesChanged = false;
    expectedStepCount = context.getStepCount();
}

void RigidLangevinStepKernelBase::updateCoefficients(ContextImpl& context, const RigidBodyIntegrator& integrator) {
    double parameters[4] = {integrator.getTemperature(), integrator.getViscosity(), integrator.getStepSize(), (double) stepScheme(integrator)};
    bool changed = coefficients.empty();
    for (int i = 0; i < 4; i++)
        changed |= (parameters[i] != coefficientParameters[i]);
    if (!changed)
        return;
    checkMotionRemover(parameters[1]);
    checkInteractionScheme(integrator);
    vector<TypeStepCoefficients> newCoefficients = computeStepCoefficients(*model, stepScheme(integrator), parameters[0], parameters[1], parameters[2]);
    if (stepScheme(integrator) == SplittingScheme::Original)
        checkOriginalSchemeStability(*model, newCoefficients, parameters[2]);
    coefficients = newCoefficients;
    uploadCoefficients(context, coefficients);
    for (int i = 0; i < 4; i++)
        coefficientParameters[i] = parameters[i];
}

void RigidLangevinStepKernelBase::execute(ContextImpl& context, const RigidBodyIntegrator& integrator) {
    const bool placedByUs = !particlesChanged && context.getStepCount() == expectedStepCount;
    updateBodies(context);
    updateCoefficients(context, integrator);
    try {
        const RigidLangevinIntegrator* inertial = langevin(integrator);
        if (inertial == NULL)
            takeBrownianStep(context, integrator);
        else {
            // A CMMotionRemover acts on the particle velocities before the step, on the same steps as here.
            bool removeMotion = (removerFrequency > 0 && context.getStepCount()%removerFrequency == 0);
            takeStep(context, *inertial, removeMotion);
        }
    }
    catch (const RotnePragerBlake::BlobBelowWallException& e) {
        if (!placedByUs)
            throw;
        throw OpenMMException(std::string(e.what())+". It was above the wall before the last step, which moved it through: take smaller steps "
                              "(setStepSize()), or make the wall's repulsion (a force of the System) stiffer, so that no body reaches the wall in one step");
    }
    expectedStepCount = context.getStepCount();
}

void RigidLangevinStepKernelBase::takeBrownianStep(ContextImpl& context, const RigidBodyIntegrator& integrator) {
    vector<BodyState> states;
    downloadBodyStates(context, states);
    vector<Vec3> forces;
    context.getForces(forces);
    if (!brownianStep)
        brownianStep.reset(new BrownianBodyStep(*model, interactions.get()));
    Vec3 box[3];
    const bool periodic = context.getSystem().usesPeriodicBoundaryConditions();
    if (periodic)
        context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    CoupledStepParameters step = {integrator.getStepSize(), integrator.getViscosity(), BOLTZ*integrator.getTemperature(), periodic ? box : NULL};
    CoupledSolve solve = (interactions ? chooseCoupledSolve(integrator, *interactions, periodic) :
                          CoupledSolve{false, integrator.getHydrodynamicTolerance(), KrylovMaxIterations, false});
    brownianStep->take(states, forces, step, solve, coefficients, hostNormals(), stepMobility(integrator, solve, blobMobility()));
    lastKrylovIterations = brownianStep->getLastIterations();
    uploadBodyStates(context, states);
    finishHostStep(context, integrator.getStepSize());
}

void RigidLangevinStepKernelBase::advanceCoupledBodies(ContextImpl& context, const RigidBodyIntegrator& integrator) {
    vector<BodyState> states;
    downloadBodyStates(context, states);
    vector<Vec3> forces;
    context.getForces(forces);
    takeCoupledStep(context, integrator, states, forces, hostNormals(), blobMobility(),
                    [this] (int count, const std::function<void (int, int)>& task) { parallelFor(count, task); });
    uploadBodyStates(context, states);
}

void RigidLangevinStepKernelBase::computeKineticEnergies(ContextImpl& context, const RigidLangevinIntegrator& integrator,
        double& translational, double& rotational, double& centerOfMass) {
    updateBodies(context);
    Vec3 momentum;
    computeBodyKineticEnergies(context, integratorVelocityOffset(integrator), translational, rotational, momentum);
    double totalMass = model->getTotalMass();
    centerOfMass = (totalMass > 0 ? 0.5*momentum.dot(momentum)/totalMass : 0.0);
}

const RigidBodyModel& RigidLangevinStepKernelBase::getModel(ContextImpl& context) {
    updateBodies(context);
    return *model;
}

void RigidLangevinStepKernelBase::getBodyStates(ContextImpl& context, vector<BodyState>& states) {
    updateBodies(context);
    downloadBodyStates(context, states);
}

void RigidLangevinStepKernelBase::getSynchronousBodyStates(ContextImpl& context, const RigidBodyIntegrator& integrator, vector<BodyState>& states) {
    getBodyStates(context, states);
    updateCoefficients(context, integrator);
    context.calcForcesAndEnergy(true, false, integrator.getIntegrationForceGroups());
    vector<Vec3> forces;
    context.getForces(forces);
    for (int b = 0; b < model->getNumBodies(); b++) {
        int t = model->getBodyType(b);
        const BodyType& type = model->getType(t);
        Vec3 force, torque;
        BodyDynamics::gatherForce(type, model->getBodyParticles(b), states[b], forces, force, torque);
        BodyDynamics::synchronousVelocity(states[b], type, coefficients[t], force, torque, integrator.getStepSize());
    }
}

void RigidLangevinStepKernelBase::restoreFromState(ContextImpl& context, const SerializationNode& types, const vector<BodyState>& states) {
    refuseStepsIfRestoreFails("State", [&] () {
        SavedBodies saved;
        model->readTypes(types, saved);
        saved.states = states;
        model->checkSavedTypes(saved, "State");
        restoreSavedBodies(context, saved);
    });
}

void RigidLangevinStepKernelBase::refuseStepsIfRestoreFails(const std::string& source, const std::function<void ()>& restore) {
    try {
        restore();
    }
    catch (...) {
        refusedRestore = source;
        throw;
    }
    refusedRestore.clear();
}

void RigidLangevinStepKernelBase::restoreSavedBodies(ContextImpl& context, const SavedBodies& saved) {
    // The file's particles are in the context; the first time, the body types are built from them.
    if (!bodiesInitialized)
        fitBodiesToParticles(context);
    vector<Vec3> positions;
    context.getPositions(positions);
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    bool periodic = context.getSystem().usesPeriodicBoundaryConditions();
    vector<BodyState> states;
    bool typesChanged;
    if (model->restoreStates(saved, positions, periodic ? box : NULL, states, typesChanged)) {
        if (typesChanged) {
            initializeInteractions();
            initializeBodies(context, *model);
            coefficients.clear();
        }
        uploadBodyStates(context, states);
        context.computeVirtualSites();
        particlesChanged = false;
        expectedStepCount = context.getStepCount();
    }
    else
        fitBodiesToParticles(context);
    positionsSet = true;
}

// Checkpoint formats (CheckpointSection frames them): 2, body types carry their virtual-site flags;
// 3, the common platforms' random numbers are the integrator's (seed and step); 4, the same payload
// framed with a length and a CRC-32.

void RigidLangevinStepKernelBase::createCheckpoint(ContextImpl& context, std::ostream& stream) {
    if (interactions)
        interactions->forgetWarmStart();  // as loadCheckpoint() will: both runs continue alike
    vector<BodyState> states;
    getBodyStates(context, states);
    std::ostringstream payload;
    model->writeTypes(payload);
    int numBodies = states.size();
    payload.write((char*) &numBodies, sizeof(int));
    payload.write((char*) states.data(), numBodies*sizeof(BodyState));
    createRandomCheckpoint(payload);
    CheckpointSection::write(stream, payload.str());
}

void RigidLangevinStepKernelBase::loadCheckpoint(ContextImpl& context, std::istream& stream) {
    refuseStepsIfRestoreFails("checkpoint", [&] () {
        int version;
        std::istringstream framed(CheckpointSection::read(stream, version, model->getIntegratorName()));
        // Format 3 has no frame: its payload is read from the checkpoint itself.
        std::istream& in = (version == CheckpointSection::UnframedVersion ? stream : framed);
        SavedBodies saved;
        model->readTypes(in, saved);
        int numBodies;
        in.read((char*) &numBodies, sizeof(int));
        if (!in || numBodies < 0 || numBodies > model->getNumBodies()+(1<<20))
            throw OpenMMException(model->getIntegratorName()+": the checkpoint is corrupt (it has "+std::to_string(numBodies)+" body states)");
        saved.states.resize(numBodies);
        in.read((char*) saved.states.data(), numBodies*sizeof(BodyState));
        loadRandomCheckpoint(in);
        if (!in)
            throw OpenMMException(model->getIntegratorName()+": the checkpoint is truncated (it ends inside the body states or the random number generator)");
        model->checkSavedTypes(saved, "checkpoint");
        restoreSavedBodies(context, saved);
        ignoreStateChanges = true;
    });
}
