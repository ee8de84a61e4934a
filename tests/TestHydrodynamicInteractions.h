/*
 * Bodies coupled through the solvent (RigidLangevinIntegrator::setHydrodynamicInteractions), against
 * answers computed here independently of the integrator's code path:
 *  - one step at zero temperature is the midpoint rule with the bodies' coupled resistance, which
 *    the hydrodynamics library's CoupledResistance computes from the same blobs and each body's own
 *    bead tensor (to round-off); bodies far apart move with their own friction (within the
 *    size/distance coupling left), close ones do not; the same for 75 bodies, past the switch to
 *    Krylov and over several parts of the GPU platforms' product;
 *  - two spheres of one blob each settle under equal forces at the velocity their
 *    Rotne-Prager-Yamakawa mobility gives, side by side, in line and overlapping (the formula written
 *    out here, to round-off);
 *  - the random momenta of one step have the covariance the midpoint rule gives with 2 kT R / h
 *    noise, eigenmode by eigenmode (a factor 2 in one mode's variance fails) and over all modes (5%
 *    in the noise's variance fails);
 *  - with interactions, velocities stay Maxwell's and positions Boltzmann's: translational and
 *    rotational temperatures and the potential energy of bodies in harmonic traps close together
 *    equal their exact values (interactions change dynamics, never statics), and the temperature
 *    does through the matrix-free step too (5% fails).
 * Every platform runs them, the GPU platforms in every precision (the long statistical runs in
 * double: leavesLongRunsToOtherPlatforms); the CPU and OpenCL runners run them again with the
 * coupled step matrix-free (RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER=krylov: on OpenCL, with the blobs'
 * mobility products in the device kernel).
 */
#include "CoupledResistance.h"
#include "ResistanceTensor.h"
#include "RigidBodyTestUtilities.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/NonbondedForce.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>
#include <sstream>
#include <limits>
#include <memory>
#include <random>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

typedef Eigen::MatrixXd Matrix;

const double BlobRadius = 0.06;

/** Bodies of the asymmetric shape, each turned at random, centred at the given points. */
struct Cluster {
    System system;
    std::vector<Vec3> positions;
    std::vector<int> firstParticle;
    BodyShape shape = asymmetricBody();

    Cluster(RigidLangevinIntegrator& integrator, const std::vector<Vec3>& centres, unsigned seed) {
        std::mt19937 random(seed);
        std::normal_distribution<double> normal;
        for (const Vec3& c : centres) {
            Eigen::Quaterniond q(normal(random), normal(random), normal(random), normal(random));
            Eigen::Matrix3d a = q.normalized().toRotationMatrix();
            Eigen::Vector3d com = Eigen::Vector3d::Zero();
            for (int i = 0; i < (int) shape.masses.size(); i++)
                com += shape.masses[i]*shape.reference[i]/shape.mass;
            std::vector<int> particles;
            firstParticle.push_back(system.getNumParticles());
            for (int i = 0; i < (int) shape.masses.size(); i++) {
                particles.push_back(system.addParticle(shape.masses[i]));
                integrator.setParticleRadius(particles.back(), BlobRadius);
                positions.push_back(c+toVec3(a*(shape.reference[i]-com)));
            }
            int body = integrator.addRigidBody(particles);
            // An explicit tensor, so that the one computed here is the integrator's to round-off (the
            // default bead model's volume correction comes from a grid, accurate to 0.1%).
            std::vector<Vec3> placed = bodyPositions(positions, body);
            integrator.setBodyHydrodynamics(body, ownTensor(placed), placed);
        }
    }
    int numBodies() const {
        return firstParticle.size();
    }
    /** The particles of body b at these positions. */
    std::vector<Vec3> bodyPositions(const std::vector<Vec3>& pos, int b) const {
        return std::vector<Vec3>(pos.begin()+firstParticle[b], pos.begin()+firstParticle[b]+shape.masses.size());
    }
    Vec3 centreOfMass(const std::vector<Vec3>& pos, int b) const {
        Vec3 com;
        for (int i = 0; i < (int) shape.masses.size(); i++)
            com += pos[firstParticle[b]+i]*(shape.masses[i]/shape.mass);
        return com;
    }
    /** A body's own friction where its particles are: they are beads, with the volume correction of their spheres' volumes. */
    ResistanceTensor ownTensor(const std::vector<Vec3>& beads) const {
        std::vector<double> radii(beads.size(), BlobRadius);
        return ResistanceTensor::beads(beads, radii, ResistanceTensor::beadVolume(radii));
    }
    ResistanceTensor ownTensor(const std::vector<Vec3>& pos, int b) const {
        return ownTensor(bodyPositions(pos, b));
    }
    /** The coupled resistance per unit viscosity, lab frame, about the centres of mass, from the hydrodynamics library
     *  (in a periodic box if box is given). */
    Matrix coupledResistance(const std::vector<Vec3>& pos, const Vec3* box = NULL) const {
        CoupledResistance coupled;
        if (box != NULL)
            coupled.setPeriodicBox(box[0], box[1], box[2]);
        for (int b = 0; b < numBodies(); b++) {
            coupled.addBody(bodyPositions(pos, b), std::vector<double>(shape.masses.size(), BlobRadius), centreOfMass(pos, b));
            coupled.setBodyResistance(b, ownTensor(pos, b));
        }
        return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> >(coupled.getResistance().data(), 6*numBodies(), 6*numBodies());
    }
    /** Each body alone with its own friction: the block diagonal of own tensors. */
    Matrix uncoupledResistance(const std::vector<Vec3>& pos) const {
        Matrix r = Matrix::Zero(6*numBodies(), 6*numBodies());
        for (int b = 0; b < numBodies(); b++) {
            std::vector<double> xi = ownTensor(pos, b).getMatrix(centreOfMass(pos, b));
            for (int k = 0; k < 36; k++)
                r(6*b+k/6, 6*b+k%6) = xi[k];
        }
        return r;
    }
    /** The lab-frame mass matrix of the bodies at these positions: mass, and the inertia tensor about the centre of mass. */
    Matrix massMatrix(const std::vector<Vec3>& pos) const {
        Matrix m = Matrix::Zero(6*numBodies(), 6*numBodies());
        for (int b = 0; b < numBodies(); b++) {
            Vec3 com = centreOfMass(pos, b);
            std::vector<Eigen::Vector3d> offsets;
            for (const Vec3& p : bodyPositions(pos, b))
                offsets.push_back(toEigen(p-com));
            m.block<3, 3>(6*b, 6*b) = shape.mass*Eigen::Matrix3d::Identity();
            m.block<3, 3>(6*b+3, 6*b+3) = shape.inertiaTensor(offsets);
        }
        return m;
    }
    /** Every body's lab momentum and angular momentum about its centre of mass, from its particles. */
    Eigen::VectorXd momenta(const std::vector<Vec3>& pos, const std::vector<Vec3>& vel) const {
        Eigen::VectorXd p = Eigen::VectorXd::Zero(6*numBodies());
        for (int b = 0; b < numBodies(); b++) {
            Vec3 com = centreOfMass(pos, b);
            for (int i = 0; i < (int) shape.masses.size(); i++) {
                int k = firstParticle[b]+i;
                p.segment<3>(6*b) += shape.masses[i]*toEigen(vel[k]);
                p.segment<3>(6*b+3) += shape.masses[i]*toEigen(pos[k]-com).cross(toEigen(vel[k]));
            }
        }
        return p;
    }
};

/** Three bodies close together at 300 K (BAOAB with interactions, seed 5), in a Context with their positions. */
struct CloseTrio {
    RigidLangevinIntegrator integrator;
    Cluster cluster;
    std::unique_ptr<Context> context;
    explicit CloseTrio(const PlatformConfig& config) :
            integrator(300, 300, 0.004), cluster(integrator, {Vec3(0, 0, 0), Vec3(0.3, 0.1, 0), Vec3(0.1, 0.35, 0.1)}, 4) {
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.setHydrodynamicInteractions(true);
        integrator.setRandomNumberSeed(5);
        context.reset(createContext(cluster.system, integrator, config));
        context->setPositions(cluster.positions);
    }
};

/** The momenta after one midpoint friction step from momenta p (zero temperature): M (M + h R/2)^-1 (M - h R/2) M^-1 p, R the friction. */
Eigen::VectorXd midpointStep(const Matrix& mass, const Matrix& friction, double h, const Eigen::VectorXd& p) {
    Matrix plus = mass+0.5*h*friction, minus = mass-0.5*h*friction;
    return mass*plus.ldlt().solve(minus*mass.ldlt().solve(p));
}

/** One step of a cluster's bodies from one velocity for all their particles (so that no body turns in
 *  the step's drifts and the resistance stays that of the starting positions), at the integrator's
 *  settings: the bodies' momenta before (p0) and after (p1). */
void stepFromOneVelocity(Cluster& cluster, RigidLangevinIntegrator& integrator, const PlatformConfig& config, Eigen::VectorXd& p0,
                         Eigen::VectorXd& p1) {
    std::unique_ptr<Context> context(createContext(cluster.system, integrator, config));
    context->setPositions(cluster.positions);
    std::vector<Vec3> velocities(cluster.positions.size(), Vec3(0.3, -0.5, 0.7));
    context->setVelocities(velocities);
    p0 = cluster.momenta(cluster.positions, velocities);
    integrator.step(1);
    std::vector<Vec3> pos, vel;
    getParticles(*context, pos, vel);
    p1 = cluster.momenta(pos, vel);
}

/**
 * Whether the long statistical runs (temperatures, bound pairs) are left to the other platforms.
 * With interactions the common platforms take the host's coupled step (RigidLangevinStepKernelBase::
 * coupledFrictionStep, the CPU's code); theirs are only the mobility products, the normal numbers,
 * the force gather and the states' transfers, which the one-step, settling, noise-covariance and
 * checkpoint tests check on them. On OpenCL through PoCL a step's transfers cost so much that the two
 * runs took 170 s of the test budget; CUDA, on a GPU, runs them, in double precision: in single and
 * mixed the coupled step is the same host code, and only the states' storage differs.
 */
bool leavesLongRunsToOtherPlatforms(const PlatformConfig& config) {
    return config.platform == "OpenCL" || config.precision != "double";
}

/**
 * How closely one step's momenta (relative to their size) can match the midpoint rule. The coupled
 * step is the host's, in double precision: to the Krylov solves' tolerance and round-off, 1e-9. The
 * device keeps the bodies' states in float in single precision, and in mixed precision OpenMM moves
 * molecules into a periodic box in float (ComputeContext::reorderAtoms subtracts the box from the
 * float part of each position), so that the step starts from positions rounded to float's 1.2e-7:
 * ten times that (measured: up to 0.3 times).
 */
double momentumTolerance(const PlatformConfig& config, bool periodic) {
    if (config.precision == "single" || (config.precision == "mixed" && periodic))
        return 10*std::numeric_limits<float>::epsilon();
    return 1e-9;
}

/**
 * Eight bodies each in its own harmonic trap on its centre of mass (every particle pulled with
 * stiffness k m_i/M towards the trap centre: U = k/2 (|R - c|^2 + sum m_i |b_i|^2/M), whatever the
 * orientation), the traps at the corners of a cube of side 0.26 nm, so that the bodies drag each
 * other strongly: BAOAB with interactions at 300 K, in a Context with velocities drawn at 300 K.
 */
struct TrappedCube {
    static constexpr double Temperature = 300;
    RigidLangevinIntegrator integrator;
    std::vector<Vec3> traps;
    Cluster cluster;
    double exactPotential;  ///< the mean trap energy: 3/2 kT per body, and the part that does not move
    std::unique_ptr<Context> context;

    TrappedCube(const PlatformConfig& config, double viscosity, double h, double k, int seed) :
            integrator(Temperature, viscosity, h), traps(corners(0.26)), cluster(integrator, traps, 9) {
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.setHydrodynamicInteractions(true);
        integrator.setRandomNumberSeed(seed);
        CustomExternalForce* trap = new CustomExternalForce("0.5*k*w*((x-x0)^2+(y-y0)^2+(z-z0)^2)");
        trap->addGlobalParameter("k", k);
        for (const char* name : {"w", "x0", "y0", "z0"})
            trap->addPerParticleParameter(name);
        const BodyShape& shape = cluster.shape;
        Eigen::Vector3d com = Eigen::Vector3d::Zero();
        for (int i = 0; i < (int) shape.masses.size(); i++)
            com += shape.masses[i]*shape.reference[i]/shape.mass;
        double bodyEnergy = 0;  // k/2 sum m_i |b_i|^2 / M
        for (int i = 0; i < (int) shape.masses.size(); i++)
            bodyEnergy += 0.5*k*shape.masses[i]/shape.mass*(shape.reference[i]-com).squaredNorm();
        for (int b = 0; b < cluster.numBodies(); b++)
            for (int i = 0; i < (int) shape.masses.size(); i++)
                trap->addParticle(cluster.firstParticle[b]+i, {shape.masses[i]/shape.mass, traps[b][0], traps[b][1], traps[b][2]});
        cluster.system.addForce(trap);
        exactPotential = cluster.numBodies()*(1.5*BOLTZ*Temperature+bodyEnergy);
        context.reset(createContext(cluster.system, integrator, config));
        context->setPositions(cluster.positions);
        context->setVelocitiesToTemperature(Temperature, 3);
    }
    static std::vector<Vec3> corners(double side) {
        std::vector<Vec3> c;
        for (int corner = 0; corner < 8; corner++)
            c.push_back(Vec3(corner&1, (corner>>1)&1, (corner>>2)&1)*side);
        return c;
    }
};

/** Two free particles with blobs of radius 0.3 nm in a periodic cube of 2 nm, at (0.5, 0.5, 0.5) and second (BAOAB with interactions). */
struct PeriodicPair {
    System system;
    RigidLangevinIntegrator integrator;
    std::unique_ptr<Context> context;
    PeriodicPair(const PlatformConfig& config, const Vec3& second) : integrator(300, 536, 0.002) {
        for (int i = 0; i < 2; i++)
            system.addParticle(10.0);
        system.setDefaultPeriodicBoxVectors(Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(0, 0, 2));
        NonbondedForce* nothing = new NonbondedForce();  // periodic boundaries, no strength
        nothing->setNonbondedMethod(NonbondedForce::CutoffPeriodic);
        nothing->setCutoffDistance(0.4);
        for (int i = 0; i < 2; i++)
            nothing->addParticle(0, 0.1, 0);
        nothing->addException(0, 1, 0, 0.1, 0);
        system.addForce(nothing);
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.setHydrodynamicInteractions(true);
        for (int i = 0; i < 2; i++)
            integrator.setParticleRadius(i, 0.3);
        context.reset(createContext(system, integrator, config));
        context->setPositions({Vec3(0.5, 0.5, 0.5), second});
    }
};

} // namespace

class HydrodynamicInteractions : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(HydrodynamicInteractions, OneStepIsTheMidpointRuleWithTheCoupledResistance) {
    // Zero temperature and force, every particle at the same velocity: one step drifts the bodies by
    // h/2 together (their resistance unchanged, since no body turns), applies the friction step and
    // drifts again; the bodies' lab momenta and angular momenta come out as the midpoint rule gives
    // with the library's resistance of the same blobs. In a periodic box (1.2 nm, a body's images
    // as close as its neighbours), the library's periodic resistance, which differs from the
    // unbounded one.
    const double viscosity = 5000, h = 0.002;
    const Vec3 box[3] = {Vec3(1.2, 0, 0), Vec3(0, 1.2, 0), Vec3(0, 0, 1.2)};
    for (double spacing : {0.25, 1e4, -0.25}) {
        const bool periodic = (spacing < 0);
        spacing = std::abs(spacing);
        // Float places bodies 1e4 nm away to 1e-3 nm, which leaves their momenta uncertain by more
        // than the 3e-6 coupling this case must tell from none.
        if (spacing > 1 && GetParam().precision == "single")
            continue;
        SCOPED_TRACE("bodies "+std::to_string(spacing)+" nm apart"+(periodic ? " in a periodic box" : ""));
        RigidLangevinIntegrator integrator(0, viscosity, h);
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.setHydrodynamicInteractions(true);
        integrator.setHydrodynamicTolerance(1e-10);  // exact, where the Krylov solves are taken
        Cluster cluster(integrator, {Vec3(0, 0, 0), Vec3(spacing, 0.02, 0), Vec3(0.4*spacing, 0.8*spacing, 0.1)}, 11);
        if (periodic) {
            // Periodic boundaries need a force that uses them: Lennard-Jones without any strength.
            cluster.system.setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
            NonbondedForce* nothing = new NonbondedForce();
            nothing->setNonbondedMethod(NonbondedForce::CutoffPeriodic);
            nothing->setCutoffDistance(0.5);
            for (int i = 0; i < cluster.system.getNumParticles(); i++)
                nothing->addParticle(0, 0.1, 0);
            cluster.system.addForce(nothing);
        }
        Eigen::VectorXd p0, p1;
        stepFromOneVelocity(cluster, integrator, GetParam(), p0, p1);
        Matrix mass = cluster.massMatrix(cluster.positions);
        Eigen::VectorXd coupled = midpointStep(mass, viscosity*cluster.coupledResistance(cluster.positions, periodic ? box : NULL), h, p0);
        Eigen::VectorXd uncoupled = midpointStep(mass, viscosity*cluster.uncoupledResistance(cluster.positions), h, p0);
        double scale = p0.norm();
        std::cout << GetParam() << ", " << spacing << " nm apart: |measured - coupled| " << (p1-coupled).norm()/scale << ", |coupled - uncoupled| "
                  << (coupled-uncoupled).norm()/scale << " (relative to the momenta)" << std::endl;
        EXPECT_LT((p1-coupled).norm(), momentumTolerance(GetParam(), periodic)*scale);
        if (spacing > 1)
            EXPECT_LT((p1-uncoupled).norm(), 1e-4*scale);  // the coupling left is of order size/distance, 1e-5
        else
            EXPECT_GT((p1-uncoupled).norm(), (periodic ? 0.005 : 0.05)*scale);  // close bodies drag each other: the test can tell
        if (periodic) {
            Eigen::VectorXd unbounded = midpointStep(mass, viscosity*cluster.coupledResistance(cluster.positions), h, p0);
            std::cout << GetParam() << ", periodic: |coupled - coupled unbounded| " << (coupled-unbounded).norm()/scale << std::endl;
            EXPECT_GT((p1-unbounded).norm(), 0.02*scale);  // and images do too
        }
    }
}

/**
 * One step of 75 bodies (300 blobs) 0.3 nm apart on a 5 x 5 x 3 lattice, strongly damped (gamma h/m
 * about 30), at the hydrodynamic tolerance given (0: the default) against the midpoint rule with
 * the coupled resistance: the error of the lab momenta and angular momenta, and their coupling (the
 * step with coupling against the one without), both relative to the momenta.
 */
void manyBodiesStep(const PlatformConfig& config, double tolerance, double& error, double& coupling) {
    const double viscosity = 5000, h = 0.002;
    RigidLangevinIntegrator integrator(0, viscosity, h);
    integrator.setScheme(RigidLangevinIntegrator::BAOAB);
    integrator.setHydrodynamicInteractions(true);
    if (tolerance > 0)
        integrator.setHydrodynamicTolerance(tolerance);
    std::vector<Vec3> centres;
    for (int i = 0; i < 75; i++)
        centres.push_back(Vec3(i%5, (i/5)%5, i/25)*0.3);
    Cluster cluster(integrator, centres, 13);
    Eigen::VectorXd p0, p1;
    stepFromOneVelocity(cluster, integrator, config, p0, p1);
    Matrix mass = cluster.massMatrix(cluster.positions);
    Eigen::VectorXd coupled = midpointStep(mass, viscosity*cluster.coupledResistance(cluster.positions), h, p0);
    Eigen::VectorXd uncoupled = midpointStep(mass, viscosity*cluster.uncoupledResistance(cluster.positions), h, p0);
    error = (p1-coupled).norm()/p0.norm();
    coupling = (p1-uncoupled).norm()/p0.norm();
    std::cout << config << ", 75 bodies, tolerance " << integrator.getHydrodynamicTolerance() << ": |measured - coupled| " << error
              << ", |coupled - uncoupled| " << (coupled-uncoupled).norm()/p0.norm() << " (relative to the momenta)" << std::endl;
}

TEST_P(HydrodynamicInteractions, OneStepOfManyBodiesIsTheMidpointRuleWithTheCoupledResistance) {
    // As the test above, with 75 bodies: past the switch to Krylov on the CPU and the GPU platforms
    // (100 blobs), and on those more than one tile of the device's product (64 blobs), whose sums
    // over the other blobs are split into parts (CommonBlobMobility: here uneven parts, the last tile
    // partly filled). A part left out or counted twice moves the bodies by far more than the Krylov
    // solves' tolerance.
    double error, coupling;
    manyBodiesStep(GetParam(), 1e-10, error, coupling);
    EXPECT_LT(error, momentumTolerance(GetParam(), false));
    EXPECT_GT(coupling, 0.05);
}

TEST_P(HydrodynamicInteractions, OneStepOfManyBodiesIsRightToTheDefaultTolerance) {
    // At the default tolerance, strongly damped: the step is right to about the tolerance. The
    // friction's solution y gives the step as M_b^-1 (z - K^T y), much smaller than M_b^-1 z here,
    // so a solve stopped at the tolerance alone left the step 1.2e-2 off at 1e-4.
    double error, coupling;
    manyBodiesStep(GetParam(), 0, error, coupling);
    EXPECT_LT(error, std::max(3*RigidLangevinIntegrator(0, 1, 1).getHydrodynamicTolerance(), momentumTolerance(GetParam(), false)));
}

TEST_P(HydrodynamicInteractions, SettlingPairMovesAtItsRotnePragerYamakawaMobility) {
    // Two spheres of one blob each (free particles, radius a) pulled by the same force: once their
    // velocities have relaxed, every step moves them by exactly h (mu_self + mu_pair) F / viscosity
    // (the midpoint rule's steady state), with the pair mobility of Rotne-Prager-Yamakawa across
    // or along the line of centres, or its overlap-regularised form.
    const double a = 0.5, mass = 20, viscosity = 50, h = 0.02, force = 30;
    struct Case {
        const char* name;
        double distance;
        bool inLine;
    };
    for (Case c : {Case{"side by side, r = 3a", 3*a, false}, Case{"in line, r = 3a", 3*a, true}, Case{"in line, overlapping, r = 1.5a", 1.5*a, true}}) {
        SCOPED_TRACE(c.name);
        double r = c.distance;
        double mobility = 1/(6*M_PI*a);
        if (r > 2*a)
            mobility += (c.inLine ? 2-4*a*a/(3*r*r) : 1+2*a*a/(3*r*r))/(8*M_PI*r);
        else
            mobility += (c.inLine ? 1-9*r/(32*a)+3*r/(32*a) : 1-9*r/(32*a))/(6*M_PI*a);
        double exact = mobility*force/viscosity;
        System system;
        system.addParticle(mass);
        system.addParticle(mass);
        CustomExternalForce* pull = new CustomExternalForce("-f*z");
        pull->addGlobalParameter("f", force);
        pull->addParticle(0);
        pull->addParticle(1);
        system.addForce(pull);
        RigidLangevinIntegrator integrator(0, viscosity, h);
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.setHydrodynamicInteractions(true);
        // The Krylov solves of two blobs are exact within six iterations at any tolerance, but at
        // the default the devices' products round their pair terms to single precision (4e-8 of the
        // velocity here; TestDeviceBlobMobility bounds them): a tolerance that keeps them in double.
        integrator.setHydrodynamicTolerance(1e-8);
        integrator.setParticleRadius(0, a);
        integrator.setParticleRadius(1, a);
        std::unique_ptr<Context> context(createContext(system, integrator, GetParam()));
        context->setPositions({Vec3(), c.inLine ? Vec3(0, 0, r) : Vec3(r, 0, 0)});
        integrator.step(400);  // relaxes by ((1-x)/(1+x))^400, x = h viscosity xi/(2m) about 0.2
        std::vector<Vec3> before = context->getState(State::Positions).getPositions();
        integrator.step(100);
        std::vector<Vec3> after = context->getState(State::Positions).getPositions();
        for (int i = 0; i < 2; i++) {
            Vec3 velocity = (after[i]-before[i])/(100*h);
            // Single precision stores each step's position in float, rounding its displacement h v
            // by up to a unit in the last place of |r|: the velocity over 100 steps by up to
            // FLT_EPSILON |r| / h (measured: under a third of that).
            double tolerance = (GetParam().precision == "single" ? std::numeric_limits<float>::epsilon()*std::sqrt(after[i].dot(after[i]))/h : 1e-9*exact);
            std::cout << GetParam() << ", " << c.name << ": particle " << i << " settles at " << velocity[2] << " nm/ps, Rotne-Prager-Yamakawa "
                      << exact << ", alone " << force/(6*M_PI*a*viscosity) << " (tolerance " << tolerance << ")" << std::endl;
            EXPECT_NEAR(velocity[2], exact, tolerance);
            EXPECT_NEAR(velocity[0], 0, tolerance);
            EXPECT_NEAR(velocity[1], 0, tolerance);
        }
    }
}

TEST_P(HydrodynamicInteractions, NoiseCovarianceIsTwoKTResistanceEigenmodeByEigenmode) {
    // From rest, without forces, one step's momenta are (M + h R/2)^-1 sqrt(2 kT h) R^1/2 xi (times
    // M): covariance C = 2 kT h M P^-1 R P^-1 M, P = M + h R/2, R = viscosity x the coupled
    // resistance. Along each eigenvector of C the sampled variance over N steps is its eigenvalue
    // within sqrt(2/N) (4.5 standard errors allowed: a factor 2 in one mode fails), and the sampled
    // covariance of two eigenmodes vanishes within 1/sqrt(N). Over all 18 modes, the mean of the
    // variance ratios is 1 within four of its standard errors (from this run's samples, which are
    // independent), and those are below 2.5%: a noise variance 5% off fails.
    if (GetParam().precision != "double")
        GTEST_SKIP() << "the same samples as in double precision: the coupled step is the host's, in double, with the device's float normals in every "
                        "precision (measured: the same mean to six digits); the one-step tests check the states' float storage";
    const double viscosity = 2000, h = 0.002, temperature = 300;
    const int numSamples = 5000;
    RigidLangevinIntegrator integrator(temperature, viscosity, h);
    integrator.setScheme(RigidLangevinIntegrator::BAOAB);
    integrator.setHydrodynamicInteractions(true);
    integrator.setRandomNumberSeed(17);
    Cluster cluster(integrator, {Vec3(0, 0, 0), Vec3(0.22, 0.05, 0), Vec3(0.1, 0.2, 0.08)}, 5);
    std::unique_ptr<Context> context(createContext(cluster.system, integrator, GetParam()));
    Matrix mass = cluster.massMatrix(cluster.positions);
    Matrix friction = viscosity*cluster.coupledResistance(cluster.positions);
    Matrix p = mass+0.5*h*friction;
    Matrix pInverseM = p.ldlt().solve(mass);
    Matrix expected = 2*BOLTZ*temperature*h*pInverseM.transpose()*friction*pInverseM;
    Eigen::SelfAdjointEigenSolver<Matrix> modes(expected);
    const int n = expected.rows();
    Matrix sampled = Matrix::Zero(n, n);
    Series meanRatio;  // each sample's variance ratio averaged over the modes
    std::vector<Vec3> zero(cluster.positions.size());
    for (int s = 0; s < numSamples; s++) {
        context->setPositions(cluster.positions);
        context->setVelocities(zero);
        integrator.step(1);
        std::vector<Vec3> pos, vel;
        getParticles(*context, pos, vel);
        Eigen::VectorXd a = modes.eigenvectors().transpose()*cluster.momenta(pos, vel);
        sampled += a*a.transpose()/numSamples;
        meanRatio.add(a.cwiseAbs2().cwiseQuotient(modes.eigenvalues()).mean());
    }
    double worstVariance = 0, worstCorrelation = 0;
    for (int i = 0; i < n; i++) {
        double ratio = sampled(i, i)/modes.eigenvalues()[i];
        worstVariance = std::max(worstVariance, std::abs(ratio-1));
        EXPECT_NEAR(ratio, 1, 4.5*std::sqrt(2.0/numSamples)) << "eigenmode " << i << " (eigenvalue " << modes.eigenvalues()[i] << ")";
        for (int j = 0; j < i; j++) {
            double correlation = sampled(i, j)/std::sqrt(modes.eigenvalues()[i]*modes.eigenvalues()[j]);
            worstCorrelation = std::max(worstCorrelation, std::abs(correlation));
            EXPECT_LT(std::abs(correlation), 4.5/std::sqrt(numSamples)) << "eigenmodes " << i << " and " << j;
        }
    }
    const double meanError = meanRatio.standardError(numSamples/2);  // blocks of two independent samples
    std::cout << GetParam() << ": " << n << " eigenmodes over " << numSamples << " samples; largest |variance/eigenvalue - 1| " << worstVariance
              << " (standard error " << std::sqrt(2.0/numSamples) << "), largest correlation " << worstCorrelation << "; mean variance/eigenvalue "
              << meanRatio.mean() << " +- " << meanError << std::endl;
    EXPECT_LT(4*meanError, 0.025) << "too few samples to see a 5% error in the noise variance";
    EXPECT_NEAR(meanRatio.mean(), 1, 4*meanError) << "the noise variance over all eigenmodes";
}

TEST_P(HydrodynamicInteractions, TemperaturesAndTrapEnergyAreExact) {
    if (leavesLongRunsToOtherPlatforms(GetParam()))
        GTEST_SKIP() << "the long statistical runs are the CPU's and CUDA's in double precision (leavesLongRunsToOtherPlatforms)";
    // The trapped cube (the bodies drag each other strongly): translational and rotational
    // temperatures and the mean potential energy must equal their exact values within 3% (three
    // standard errors inside it), as without interactions.
    TrappedCube cube(GetParam(), 200, 0.004, 3000, 23);
    RigidLangevinIntegrator& integrator = cube.integrator;
    integrator.step(1000);
    const int numSamples = (runsEveryStatisticalCase(GetParam()) ? 20000 : 10000);
    Series translational, rotational, potential;
    for (int s = 0; s < numSamples; s++) {
        integrator.step(5);
        translational.add(integrator.computeTranslationalTemperature());
        rotational.add(integrator.computeRotationalTemperature());
        potential.add(cube.context->getState(State::Energy).getPotentialEnergy());
    }
    const double temperature = TrappedCube::Temperature;
    struct Check {
        const char* name;
        const Series& series;
        double exact;
    };
    for (Check c : {Check{"translational temperature", translational, temperature}, Check{"rotational temperature", rotational, temperature},
                    Check{"trap energy", potential, cube.exactPotential}}) {
        std::cout << GetParam() << ": " << c.name << " " << c.series.mean() << " +- " << c.series.standardError() << ", exact " << c.exact << std::endl;
        EXPECT_LT(3*c.series.standardError(), 0.03*c.exact) << c.name;
        EXPECT_NEAR(c.series.mean(), c.exact, 0.03*c.exact) << c.name;
    }
}

TEST_P(HydrodynamicInteractions, KrylovStepKeepsTheTemperature) {
    if (GetParam().platform == "Reference")
        GTEST_SKIP() << "Reference takes the dense coupled step by definition";
    if (leavesLongRunsToOtherPlatforms(GetParam()))
        GTEST_SKIP() << "the long statistical runs are the CPU's and CUDA's in double precision (leavesLongRunsToOtherPlatforms)";
    // The trapped cube through the matrix-free coupled step (RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER=krylov:
    // the noise from the Lanczos square root and a conjugate-gradient solve, the friction from
    // another), which the CPU platform takes on its own only from 100 blobs, so that the run above
    // (32 blobs) takes the dense one. At ten times its friction the velocities are forgotten within
    // a few steps, so that a short run has the samples: the kinetic temperature of all 48 degrees of
    // freedom within four standard errors of 300 K, and four standard errors below 2.5%: a noise or
    // a friction 5% off fails.
    EnvironmentSetting krylov("RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER", "krylov");
    TrappedCube cube(GetParam(), 2000, 0.004, 3000, 29);
    RigidLangevinIntegrator& integrator = cube.integrator;
    integrator.step(100);
    const int numSamples = 3000;
    Series temperature;
    for (int s = 0; s < numSamples; s++) {
        integrator.step(3);
        temperature.add(integrator.computeSystemTemperature());
    }
    std::vector<int> iterations = integrator.getKrylovIterations();
    std::cout << GetParam() << ", Krylov: temperature " << temperature.mean() << " +- " << temperature.standardError() << " K; the last step's "
              << "Krylov iterations " << iterations[0] << ", " << iterations[1] << ", " << iterations[2] << std::endl;
    EXPECT_GT(iterations[2], 0) << "the step was not the Krylov one";
    EXPECT_LT(4*temperature.standardError(), 0.025*TrappedCube::Temperature);
    EXPECT_NEAR(temperature.mean(), TrappedCube::Temperature, 4*temperature.standardError());
}

TEST_P(HydrodynamicInteractions, BoundPairsSampleTheSameDistributionWithAndWithoutThem) {
    if (leavesLongRunsToOtherPlatforms(GetParam()))
        GTEST_SKIP() << "the long statistical runs are the CPU's and CUDA's in double precision (leavesLongRunsToOtherPlatforms)";
    // Hydrodynamic interactions change dynamics, never statics. Six pairs of spheres (one blob of
    // radius 0.1 nm each, 50 nm between pairs), each pair bound by a spring k r^2/2: the separation's
    // moments are <r^2> = 3 kT/k and <r^4> = 15 (kT/k)^2 exactly, with interactions and without
    // (r is 0.33 nm rms, so the blobs overlap a third of the time, where the regularised kernel
    // holds). Each run against the exact values within four standard errors (the errors a few per
    // cent: a noise of the wrong strength fails), and the two runs against each other.
    const double temperature = 300, k = 70, kT = BOLTZ*temperature;
    const int numPairs = 6;
    const int numSamples = (runsEveryStatisticalCase(GetParam()) ? 3000 : 1500);
    Series moments[2][2];  // [interactions][r^2, r^4]
    for (int on = 0; on < 2; on++) {
        System system;
        CustomBondForce* spring = new CustomBondForce("0.5*k*r^2");
        spring->addGlobalParameter("k", k);
        system.addForce(spring);
        RigidLangevinIntegrator integrator(temperature, 100, 0.01);
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.setHydrodynamicInteractions(on == 1);
        integrator.setRandomNumberSeed(31+on);
        std::vector<Vec3> positions;
        for (int p = 0; p < numPairs; p++) {
            for (int i = 0; i < 2; i++) {
                integrator.setParticleRadius(system.addParticle(10.0), 0.1);
                positions.push_back(Vec3(50.0*p+0.3*i, 0, 0));
            }
            spring->addBond(2*p, 2*p+1);
        }
        std::unique_ptr<Context> context(createContext(system, integrator, GetParam()));
        context->setPositions(positions);
        context->setVelocitiesToTemperature(temperature, 5+on);
        integrator.step(500);
        for (int s = 0; s < numSamples; s++) {
            integrator.step(25);
            std::vector<Vec3> pos = context->getState(State::Positions).getPositions();
            double r2 = 0, r4 = 0;
            for (int p = 0; p < numPairs; p++) {
                Vec3 d = pos[2*p+1]-pos[2*p];
                r2 += d.dot(d)/numPairs;
                r4 += d.dot(d)*d.dot(d)/numPairs;
            }
            moments[on][0].add(r2);
            moments[on][1].add(r4);
        }
    }
    const double exact[2] = {3*kT/k, 15*(kT/k)*(kT/k)};
    const char* names[2] = {"<r^2>", "<r^4>"};
    for (int m = 0; m < 2; m++) {
        for (int on = 0; on < 2; on++) {
            const Series& series = moments[on][m];
            std::cout << GetParam() << ": " << names[m] << (on ? " with" : " without") << " interactions " << series.mean() << " +- "
                      << series.standardError() << ", exact " << exact[m] << std::endl;
            EXPECT_LT(series.standardError(), 0.06*exact[m]) << names[m];
            EXPECT_NEAR(series.mean(), exact[m], 4*series.standardError()) << names[m] << (on ? " with" : " without") << " interactions";
        }
        double both = std::hypot(moments[0][m].standardError(), moments[1][m].standardError());
        EXPECT_NEAR(moments[1][m].mean(), moments[0][m].mean(), 4*both) << names[m] << ": with against without";
    }
}

TEST_P(HydrodynamicInteractions, CheckpointContinuesTheSameTrajectory) {
    // The coupled friction is recomputed from the bodies' states, which a checkpoint restores
    // exactly, as it does the random streams: continuing from it repeats the trajectory bit for bit.
    // Matrix-free too, where the friction solve starts from the last step's solution: writing and
    // loading a checkpoint both forget it (without that the two runs' first steps differ at the
    // solves' tolerance, 1e-10, and the positions then differ in their last bits).
    for (std::string solver : {"dense", "krylov"}) {
        SCOPED_TRACE(solver);
        EnvironmentSetting setting("RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER", solver.c_str());
        CloseTrio trio(GetParam());
        RigidLangevinIntegrator& integrator = trio.integrator;
        Cluster& cluster = trio.cluster;
        std::unique_ptr<Context>& context = trio.context;
        context->setVelocitiesToTemperature(300, 2);
        integrator.step(5);
        std::stringstream checkpoint;
        context->createCheckpoint(checkpoint);
        integrator.step(10);
        State first = context->getState(State::Positions | State::Velocities);
        context->loadCheckpoint(checkpoint);
        integrator.step(10);
        State second = context->getState(State::Positions | State::Velocities);
        for (int i = 0; i < cluster.system.getNumParticles(); i++) {
            ASSERT_EQ(first.getPositions()[i], second.getPositions()[i]) << "particle " << i;
            ASSERT_EQ(first.getVelocities()[i], second.getVelocities()[i]) << "particle " << i;
        }
        EXPECT_GT(std::sqrt((first.getPositions()[0]-cluster.positions[0]).dot(first.getPositions()[0]-cluster.positions[0])), 1e-4);
    }
}

TEST_P(HydrodynamicInteractions, ReportsItsKrylovIterations) {
    // getKrylovIterations(): after a matrix-free step, the noise's Lanczos (preconditioned with each
    // body's own blobs) converged before its Krylov space (3 x 12 blobs: 36 vectors) ran out, the
    // noise took no conjugate gradients, and the friction's conjugate gradients, preconditioned the
    // same way, took at most 20 (without the preconditioner they take 28). After a dense step, and
    // always on Reference (dense by definition), zeros.
    // The solver is chosen as users choose it, by RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER, restored
    // afterwards (EnvironmentSetting).
    for (std::string solver : {"krylov", "dense"}) {
        EnvironmentSetting setting("RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER", solver.c_str());
        CloseTrio trio(GetParam());
        RigidLangevinIntegrator& integrator = trio.integrator;
        EXPECT_EQ(std::vector<int>({0, 0, 0}), integrator.getKrylovIterations()) << "before any step";
        integrator.step(1);
        std::vector<int> iterations = integrator.getKrylovIterations();
        ASSERT_EQ(3u, iterations.size());
        std::cout << GetParam() << ", " << solver << ": Krylov iterations " << iterations[0] << ", " << iterations[1] << ", " << iterations[2] << std::endl;
        for (int k = 0; k < 3; k++) {
            if (solver == "krylov" && GetParam().platform != "Reference" && k != 1) {
                EXPECT_GE(iterations[k], 1) << "solve " << k;
                EXPECT_LT(iterations[k], (k == 0 ? 36 : 21)) << "solve " << k;
            }
            else
                EXPECT_EQ(0, iterations[k]) << "solve " << k;
        }
    }
    RigidLangevinIntegrator unbound(300, 300, 0.004);
    EXPECT_THROW(unbound.getKrylovIterations(), OpenMMException);
}

TEST_P(HydrodynamicInteractions, RefusesWhatItCannotDo) {
    System system;
    for (int i = 0; i < 3; i++)
        system.addParticle(10.0);
    auto expectRefusal = [&] (RigidLangevinIntegrator& integrator, const std::string& words) {
        try {
            std::unique_ptr<Context> context(createContext(system, integrator, GetParam()));
            context->setPositions({Vec3(0, 0, 0), Vec3(0.3, 0, 0), Vec3(0, 0.3, 0)});
            integrator.step(1);
            ADD_FAILURE() << "not refused: " << words;
        }
        catch (const OpenMMException& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
    };
    {
        // Another scheme.
        RigidLangevinIntegrator integrator(300, 536, 0.002);
        integrator.setHydrodynamicInteractions(true);
        for (int i = 0; i < 3; i++)
            integrator.setParticleRadius(i, 0.1);
        expectRefusal(integrator, "setScheme(RigidLangevinIntegrator::BAOAB)");
    }
    {
        // A body of one blob that rotates: its blobs do not resist rotation.
        RigidLangevinIntegrator integrator(300, 536, 0.002);
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.setHydrodynamicInteractions(true);
        integrator.addRigidBody({0, 1, 2});
        integrator.setParticleRadius(0, 0.1);
        std::vector<double> xi = flatten(Eigen::Matrix<double, 6, 6>::Identity());
        integrator.setBodyResistance(0, xi, Vec3(), {Vec3(0, 0, 0), Vec3(0.3, 0, 0), Vec3(0, 0.3, 0)});
        expectRefusal(integrator, "rigid body 0: its blobs do not resist every motion");
    }
    {
        // Blobs off the point of a body that cannot turn.
        System single;
        single.addParticle(10.0);
        RigidLangevinIntegrator integrator(300, 536, 0.002);
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.setHydrodynamicInteractions(true);
        integrator.addRigidBody({0});
        integrator.setParticleRadius(0, 0.1);
        integrator.setBodyBlobs(0, {Vec3(0.1, 0, 0), Vec3(-0.1, 0, 0)}, {0.1, 0.1}, {Vec3()});
        try {
            std::unique_ptr<Context> context(createContext(single, integrator, GetParam()));
            context->setPositions({Vec3()});
            integrator.step(1);
            ADD_FAILURE() << "blobs off a point body were accepted";
        }
        catch (const OpenMMException& e) {
            EXPECT_NE(std::string(e.what()).find("cannot turn at all"), std::string::npos) << e.what();
        }
    }
    {
        // Two free particles of the same radius in the same place are one sphere held twice by two
        // bodies: their mobility is singular, refused naming both (dense, and in the Krylov runs
        // matrix-free, where it once gave a finite, meaningless step).
        RigidLangevinIntegrator integrator(300, 536, 0.002);
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.setHydrodynamicInteractions(true);
        for (int i = 0; i < 3; i++)
            integrator.setParticleRadius(i, 0.1);
        std::unique_ptr<Context> context(createContext(system, integrator, GetParam()));
        context->setPositions({Vec3(0, 0.3, 0), Vec3(0.3, 0, 0), Vec3(0, 0.3, 0)});
        expectError([&] { integrator.step(1); }, {"blob 0 of free particle 0 and blob 0 of free particle 2 are coincident"});
    }
}

TEST_P(HydrodynamicInteractions, RefusesBlobsThePeriodicBoxCannotHold) {
    // In a periodic box every blob's diameter must be under half the box's smallest width, and no
    // two blobs may be one sphere through the box. Both are checked at every step with the box of
    // the moment (here made smaller by setPeriodicBoxVectors after two steps), densely and, in the
    // Krylov runs, matrix-free, naming the blob and what to change.
    PeriodicPair pair(GetParam(), Vec3(1.3, 0.5, 0.5));
    RigidLangevinIntegrator& integrator = pair.integrator;
    integrator.step(2);  // blobs 0.6 nm across, under half of 2 nm
    pair.context->setPeriodicBoxVectors(Vec3(1.1, 0, 0), Vec3(0, 1.1, 0), Vec3(0, 0, 1.1));
    expectError([&] { integrator.step(1); },
                {"blob 0 of free particle 0 has radius 0.3 nm, too large for the periodic box", "(0.55 nm)", "larger box", "smaller blobs"});
    PeriodicPair images(GetParam(), Vec3(2.5, 0.5, -1.5));
    expectError([&] { images.integrator.step(1); }, {"blob 0 of free particle 0 and blob 0 of free particle 1 are the same sphere through the periodic box"});
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, HydrodynamicInteractions, testing::ValuesIn(platformConfigs()), PlatformConfigName());
INSTANTIATE_TEST_SUITE_P(LowerPrecision, HydrodynamicInteractions, testing::ValuesIn(lowerPrecisionConfigs()), PlatformConfigName());
