/*
 * The integrator as part of an OpenMM Context: checkpoints continue bit-identically, XML
 * serialization round-trips everything, States restore body states exactly, velocities are drawn
 * and projected as rigid motion, a CMMotionRemover works without friction and is refused with it, and
 * periodic wrapping never breaks a body.
 */
#include "RigidBodyTestUtilities.h"
#include "openmm/CMMotionRemover.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/NonbondedForce.h"
#include "openmm/serialization/XmlSerializer.h"
#include <gtest/gtest.h>
#include <memory>
#include <sstream>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

/** Asymmetric bodies, a linear body, free particles and Lennard-Jones interactions in a periodic box. */
struct Scene {
    System system;
    std::vector<Vec3> positions;
    BodyShape shape = asymmetricBody();
    int numBodies = 20;
    bool perParticleForce;
    /**
     * perParticleForce: replace the Lennard-Jones interactions by a harmonic well acting on each
     * particle (with radii set explicitly), for tests that compare a run with its own continuation
     * bit for bit. The CPU platform's nonbonded forces depend on the history of its neighbour list,
     * which loading a checkpoint or a State rebuilds, so that not even OpenMM's own integrators
     * continue bit-identically there.
     */
    explicit Scene(bool perParticleForce = false) : perParticleForce(perParticleForce) {
        NonbondedForce* nb = new NonbondedForce();
        nb->setNonbondedMethod(NonbondedForce::CutoffPeriodic);
        nb->setCutoffDistance(0.9);
        system.setDefaultPeriodicBoxVectors(Vec3(3, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 3));
        for (int b = 0; b < numBodies; b++) {
            Eigen::Vector3d centre(0.6*(b%5)+0.3, 0.6*((b/5)%5)+0.3, 0.9*(b/25)+1.0);
            for (int i = 0; i < 4; i++) {
                system.addParticle(shape.masses[i]);
                nb->addParticle(0.0, 0.2, 0.5);
                positions.push_back(toVec3(centre+shape.reference[i]));
            }
            for (int i = 0; i < 4; i++)
                for (int j = i+1; j < 4; j++)
                    nb->addException(4*b+i, 4*b+j, 0, 1, 0);
        }
        for (int i = 0; i < 10; i++) {
            system.addParticle(30.0);
            nb->addParticle(0.0, 0.3, 0.5);
            positions.push_back(Vec3(0.3*i+0.1, 2.5, 2.5));
        }
        if (perParticleForce) {
            delete nb;
            CustomExternalForce* well = new CustomExternalForce("10*((x-1.5)^2+(y-1.5)^2+(z-1.5)^2)");
            for (int i = 0; i < system.getNumParticles(); i++)
                well->addParticle(i);
            system.addForce(well);
        }
        else
            system.addForce(nb);
    }
    void addBodies(RigidLangevinIntegrator& integrator) const {
        for (int b = 0; b < numBodies; b++)
            integrator.addRigidBody({4*b, 4*b+1, 4*b+2, 4*b+3});
        if (perParticleForce)
            for (int i = 0; i < system.getNumParticles(); i++)
                integrator.setParticleRadius(i, 0.12);
    }
};

/** Whether a test that compares a run with its continuation needs the per-particle force (see Scene). */
bool needsPerParticleForce(const PlatformConfig& platform) {
    return platform.platform == "CPU";
}

void expectIdentical(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (int i = 0; i < (int) a.size(); i++)
        ASSERT_EQ(a[i], b[i]) << "particle " << i;
}

} // namespace

class StateAndSystem : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(StateAndSystem, CheckpointContinuesBitIdentically) {
    const PlatformConfig& platform = GetParam();
    for (RigidLangevinIntegrator::Scheme scheme : {RigidLangevinIntegrator::ExactFlow, RigidLangevinIntegrator::BAOAB, RigidLangevinIntegrator::Original}) {
        Scene scene(needsPerParticleForce(platform));
        RigidLangevinIntegrator integrator(300, 50.0, 0.002);
        integrator.setScheme(scheme);
        integrator.setRandomNumberSeed(13);
        scene.addBodies(integrator);
        Context context(scene.system, integrator, platform.get(), platform.properties());
        context.setPositions(scene.positions);
        context.setVelocitiesToTemperature(300, 1);
        integrator.step(20);
        std::stringstream checkpoint;
        context.createCheckpoint(checkpoint);
        integrator.step(50);
        State first = context.getState(State::Positions | State::Velocities);
        // The same context, rewound.
        checkpoint.seekg(0);
        context.loadCheckpoint(checkpoint);
        integrator.step(50);
        State second = context.getState(State::Positions | State::Velocities);
        expectIdentical(first.getPositions(), second.getPositions());
        expectIdentical(first.getVelocities(), second.getVelocities());
        // A new context, as after a restart.
        RigidLangevinIntegrator integrator2(300, 50.0, 0.002);
        integrator2.setScheme(scheme);
        scene.addBodies(integrator2);
        Context context2(scene.system, integrator2, platform.get(), platform.properties());
        checkpoint.seekg(0);
        context2.loadCheckpoint(checkpoint);
        integrator2.step(50);
        State third = context2.getState(State::Positions | State::Velocities);
        expectIdentical(first.getPositions(), third.getPositions());
        expectIdentical(first.getVelocities(), third.getVelocities());
    }
}

/**
 * A scheme set after the Context exists takes effect at the next step: the common platforms compile
 * the step kernels of a scheme when it is first used. The trajectory is the one a Context created
 * with that scheme takes from the same start and seed, bit for bit.
 */
TEST_P(StateAndSystem, SchemeChangedAfterContextCreation) {
    const PlatformConfig& platform = GetParam();
    std::vector<State> states;
    for (bool changeLater : {false, true}) {
        Scene scene(needsPerParticleForce(platform));
        RigidLangevinIntegrator integrator(300, 50.0, 0.002);
        integrator.setScheme(changeLater ? RigidLangevinIntegrator::ExactFlow : RigidLangevinIntegrator::BAOAB);
        integrator.setRandomNumberSeed(13);
        scene.addBodies(integrator);
        Context context(scene.system, integrator, platform.get(), platform.properties());
        context.setPositions(scene.positions);
        context.setVelocitiesToTemperature(300, 1);
        integrator.setScheme(RigidLangevinIntegrator::BAOAB);
        integrator.step(20);
        states.push_back(context.getState(State::Positions | State::Velocities));
    }
    expectIdentical(states[0].getPositions(), states[1].getPositions());
    expectIdentical(states[0].getVelocities(), states[1].getVelocities());
}

TEST_P(StateAndSystem, SerializationRoundTrip) {
    RigidLangevinIntegrator integrator(310.5, 536.0, 0.0015);
    integrator.setScheme(RigidLangevinIntegrator::BAOAB);
    integrator.setRandomNumberSeed(42);
    integrator.setConstraintTolerance(1e-6);
    integrator.setIntegrationForceGroups(5);
    integrator.addRigidBody({0, 1, 2});
    integrator.addRigidBody({5, 4});
    std::vector<double> tensor = flatten(coupledTensor());
    std::vector<Vec3> reference = {Vec3(0.1, 0.2, 0.3), Vec3(-0.4, 0.5, 0.6)};
    integrator.setBodyResistance(1, tensor, Vec3(0.1, -0.2, 0.3), reference);
    integrator.setParticleRadius(4, 0.17);
    integrator.setParticleRadius(0, 0.2);
    integrator.setHydrodynamicInteractions(true);
    std::vector<Vec3> blobPositions = {Vec3(0.05, 0.1, 0.2), Vec3(-0.3, 0.1, 0.0)};
    std::vector<double> blobRadii = {0.11, 0.13};
    std::vector<Vec3> blobReference = {Vec3(0.0, 0.1, 0.2), Vec3(-0.3, 0.2, 0.1), Vec3(0.2, -0.1, 0.0)};
    integrator.setBodyBlobs(0, blobPositions, blobRadii, blobReference);
    integrator.setWall(-2.5);
    std::stringstream buffer;
    XmlSerializer::serialize<Integrator>(&integrator, "Integrator", buffer);
    const std::string xml = buffer.str();
    RigidLangevinIntegrator* copy = dynamic_cast<RigidLangevinIntegrator*>(XmlSerializer::deserialize<Integrator>(buffer));
    ASSERT_TRUE(copy != NULL);
    EXPECT_EQ(integrator.getTemperature(), copy->getTemperature());
    EXPECT_EQ(integrator.getViscosity(), copy->getViscosity());
    EXPECT_EQ(integrator.getStepSize(), copy->getStepSize());
    EXPECT_EQ(integrator.getScheme(), copy->getScheme());
    EXPECT_EQ(integrator.getRandomNumberSeed(), copy->getRandomNumberSeed());
    EXPECT_EQ(integrator.getConstraintTolerance(), copy->getConstraintTolerance());
    EXPECT_EQ(integrator.getIntegrationForceGroups(), copy->getIntegrationForceGroups());
    ASSERT_EQ(2, copy->getNumRigidBodies());
    EXPECT_EQ(integrator.getRigidBodyParticles(0), copy->getRigidBodyParticles(0));
    EXPECT_EQ(integrator.getRigidBodyParticles(1), copy->getRigidBodyParticles(1));
    std::vector<double> t;
    Vec3 origin;
    std::vector<Vec3> r;
    EXPECT_FALSE(copy->getBodyResistance(0, t, origin, r));
    ASSERT_TRUE(copy->getBodyResistance(1, t, origin, r));
    EXPECT_EQ(tensor, t);
    EXPECT_EQ(Vec3(0.1, -0.2, 0.3), origin);
    EXPECT_EQ(reference, r);
    EXPECT_EQ(integrator.getParticleRadii(), copy->getParticleRadii());
    EXPECT_TRUE(copy->getHydrodynamicInteractions());
    std::vector<Vec3> p, reference0;
    std::vector<double> radii;
    ASSERT_TRUE(copy->getBodyBlobs(0, p, radii, reference0));
    EXPECT_EQ(blobPositions, p);
    EXPECT_EQ(blobRadii, radii);
    EXPECT_EQ(blobReference, reference0);
    EXPECT_FALSE(copy->getBodyBlobs(1, p, radii, reference0));
    double wallHeight;
    ASSERT_TRUE(copy->getWall(wallHeight));
    EXPECT_EQ(-2.5, wallHeight);
    delete copy;

    // Version 2 (before hydrodynamic interactions and the wall) reads as without them; an unknown version is refused.
    auto withVersion = [&](const std::string& version) {
        std::string text = xml;
        size_t at = text.find("version=\"5\"");
        EXPECT_NE(std::string::npos, at);
        text.replace(at, 11, "version=\""+version+"\"");
        at = text.find(" hydrodynamicInteractions=\"1\"");
        EXPECT_NE(std::string::npos, at);
        return text.erase(at, 30);
    };
    std::stringstream version2(withVersion("2"));
    std::unique_ptr<Integrator> old(XmlSerializer::deserialize<Integrator>(version2));
    EXPECT_FALSE(dynamic_cast<RigidLangevinIntegrator&>(*old).getHydrodynamicInteractions());
    EXPECT_FALSE(dynamic_cast<RigidLangevinIntegrator&>(*old).getWall(wallHeight));
    std::stringstream version6(withVersion("6"));
    EXPECT_THROW(XmlSerializer::deserialize<Integrator>(version6), OpenMMException);
}

TEST_P(StateAndSystem, StateRestoresBodiesExactly) {
    const PlatformConfig& platform = GetParam();
    // A State carries the exact body states, so positions and velocities come back unchanged
    // through XML, and continuing from it gives the same trajectory as the original run with the
    // same random numbers would (checked here with zero temperature, where there are none).
    Scene scene(needsPerParticleForce(platform));
    RigidLangevinIntegrator integrator(0, 20.0, 0.002);
    scene.addBodies(integrator);
    Context context(scene.system, integrator, platform.get(), platform.properties());
    context.setPositions(scene.positions);
    context.setVelocitiesToTemperature(300, 2);
    integrator.step(10);
    State saved = context.getState(State::Positions | State::Velocities | State::IntegratorParameters);
    std::stringstream xml;
    XmlSerializer::serialize<State>(&saved, "State", xml);
    integrator.step(30);
    State first = context.getState(State::Positions | State::Velocities);
    State* loaded = XmlSerializer::deserialize<State>(xml);
    context.setState(*loaded);
    delete loaded;
    integrator.step(30);
    State second = context.getState(State::Positions | State::Velocities);
    for (int i = 0; i < scene.system.getNumParticles(); i++) {
        EXPECT_LT((first.getPositions()[i]-second.getPositions()[i]).dot(first.getPositions()[i]-second.getPositions()[i]), 1e-24);
        EXPECT_LT((first.getVelocities()[i]-second.getVelocities()[i]).dot(first.getVelocities()[i]-second.getVelocities()[i]), 1e-20);
    }
}

TEST_P(StateAndSystem, VelocitiesForTemperatureAreRigidAndThermal) {
    const PlatformConfig& platform = GetParam();
    // setVelocitiesToTemperature draws Maxwell-Boltzmann velocities in the bodies' own degrees of
    // freedom: particle velocities are rigid motions, and 10 draws of 500 bodies give the
    // temperature to 0.8% (exactly: 250 K sqrt(2/30000)), so that a 5% error fails by 2 standard
    // errors beyond the 4 allowed.
    BodyShape shape = asymmetricBody();
    System system;
    RigidLangevinIntegrator integrator(300, 10.0, 0.002);
    std::vector<Vec3> positions;
    int numBodies = 500;
    for (int b = 0; b < numBodies; b++) {
        for (int i = 0; i < 4; i++) {
            system.addParticle(shape.masses[i]);
            integrator.setParticleRadius(4*b+i, 0.1);
            positions.push_back(toVec3(shape.reference[i]+Eigen::Vector3d(b, 0, 0)));
        }
        integrator.addRigidBody({4*b, 4*b+1, 4*b+2, 4*b+3});
    }
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions(positions);
    const int numDraws = 10;
    double sum = 0;
    for (int draw = 0; draw < numDraws; draw++) {
        context.setVelocitiesToTemperature(250, 3+draw);
        State state = context.getState(State::Positions | State::Velocities | State::Energy);
        double kinetic = 0;
        for (int b = 0; b < numBodies; b++) {
            MeasuredBody body = shape.measure(state.getPositions(), state.getVelocities(), 4*b);
            for (int i = 0; i < 4; i++) {
                Eigen::Vector3d rigid = body.velocity+body.omega.cross(toEigen(state.getPositions()[4*b+i])-body.com);
                EXPECT_LT((rigid-toEigen(state.getVelocities()[4*b+i])).norm(), 1e-10);
            }
            kinetic += 0.5*shape.weightedVelocity(body).squaredNorm();
        }
        EXPECT_NEAR(kinetic, state.getKineticEnergy(), 1e-9*kinetic);
        sum += 2*kinetic/(6*numBodies*BOLTZ);
    }
    double temperature = sum/numDraws;
    double expectedError = 250*std::sqrt(2.0/(6*numBodies*numDraws));
    std::cout << "setVelocitiesToTemperature(250 K): " << temperature << " K, expected error " << expectedError << " K" << std::endl;
    EXPECT_NEAR(250, temperature, 4*expectedError);
}

TEST_P(StateAndSystem, VelocitiesAreProjectedOntoRigidMotion) {
    const PlatformConfig& platform = GetParam();
    // Arbitrary particle velocities become the rigid motion with the same momentum and angular
    // momentum: the kinetic energy reported is that of the projection.
    BodyShape shape = asymmetricBody();
    System system;
    RigidLangevinIntegrator integrator(300, 10.0, 0.002);
    std::vector<Vec3> positions, velocities;
    for (int i = 0; i < 4; i++) {
        system.addParticle(shape.masses[i]);
        integrator.setParticleRadius(i, 0.1);
        positions.push_back(toVec3(shape.reference[i]));
        velocities.push_back(Vec3(0.3*i-0.5, std::sin(i), 0.2*i*i));
    }
    integrator.addRigidBody({0, 1, 2, 3});
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions(positions);
    context.setVelocities(velocities);
    Eigen::Vector3d momentum = Eigen::Vector3d::Zero(), angular = Eigen::Vector3d::Zero();
    Eigen::Vector3d com = Eigen::Vector3d::Zero();
    for (int i = 0; i < 4; i++)
        com += shape.masses[i]*toEigen(positions[i])/shape.mass;
    for (int i = 0; i < 4; i++) {
        momentum += shape.masses[i]*toEigen(velocities[i]);
        angular += shape.masses[i]*(toEigen(positions[i])-com).cross(toEigen(velocities[i]));
    }
    std::vector<Eigen::Vector3d> offsets;
    for (int i = 0; i < 4; i++)
        offsets.push_back(toEigen(positions[i])-com);
    Eigen::Matrix3d inertia = shape.inertiaTensor(offsets);
    double expected = 0.5*momentum.squaredNorm()/shape.mass+0.5*angular.dot(inertia.ldlt().solve(angular));
    EXPECT_NEAR(expected, context.getState(State::Energy).getKineticEnergy(), 1e-10*expected);
}

TEST_P(StateAndSystem, CMMotionRemoverWorksWithoutFriction) {
    const PlatformConfig& platform = GetParam();
    // Without friction the remover zeroes the total momentum once and it stays zero.
    Scene scene;
    scene.system.addForce(new CMMotionRemover(1));
    RigidLangevinIntegrator integrator(300, 0.0, 0.002);
    scene.addBodies(integrator);
    Context context(scene.system, integrator, platform.get(), platform.properties());
    context.setPositions(scene.positions);
    std::vector<Vec3> velocities(scene.system.getNumParticles(), Vec3(0.5, -0.2, 0.1));
    context.setVelocities(velocities);
    integrator.step(20);
    State state = context.getState(State::Velocities);
    Vec3 momentum;
    for (int i = 0; i < scene.system.getNumParticles(); i++)
        momentum += state.getVelocities()[i]*scene.system.getParticleMass(i);
    // Forces sum to zero to rounding: double precision, or fixed point on GPUs; the CPU
    // platform's single-precision nonbonded forces leave 1e-8 after 20 steps.
    EXPECT_LT(std::sqrt(momentum.dot(momentum)), platform.platform == "CPU" ? 1e-6 : 1e-9);
}

TEST_P(StateAndSystem, CMMotionRemoverIsRefusedWithFriction) {
    const PlatformConfig& platform = GetParam();
    // With friction the total momentum is not conserved, and removing it removes real motion (a
    // lone body would not diffuse): a Context with both is refused, naming the fix, and so is a
    // step after the viscosity is raised from zero in a Context that has a remover.
    for (bool atCreation : {true, false}) {
        Scene scene;
        scene.system.addForce(new CMMotionRemover(1));
        RigidLangevinIntegrator integrator(300, atCreation ? 0.89 : 0.0, 0.002);
        scene.addBodies(integrator);
        for (int i = 0; i < scene.system.getNumParticles(); i++)
            integrator.setParticleRadius(i, 0.12);
        try {
            Context context(scene.system, integrator, platform.get(), platform.properties());
            context.setPositions(scene.positions);
            integrator.step(1);
            integrator.setViscosity(0.89);
            integrator.step(1);
            FAIL() << "a CMMotionRemover with friction was accepted (" << (atCreation ? "at creation" : "after setViscosity") << ")";
        }
        catch (const OpenMMException& e) {
            std::string message = e.what();
            EXPECT_NE(message.find("CMMotionRemover (force "+std::to_string(scene.system.getNumForces()-1)+")"), std::string::npos) << message;
            EXPECT_NE(message.find("removeCMMotion=False"), std::string::npos) << message;
        }
    }
}

TEST_P(StateAndSystem, BodiesStayWholeAcrossPeriodicBoundaries) {
    const PlatformConfig& platform = GetParam();
    // After the shapes are set, set positions with one body's particles wrapped individually into
    // the box: the body comes back whole, with its shape, and stays whole as it moves.
    Scene scene;
    RigidLangevinIntegrator integrator(300, 50.0, 0.002);
    scene.addBodies(integrator);
    Context context(scene.system, integrator, platform.get(), platform.properties());
    context.setPositions(scene.positions);
    integrator.step(1);
    std::vector<Vec3> positions = scene.positions;
    for (int i = 0; i < 4; i++)
        positions[i] += Vec3(-0.33, 0, 0);  // body 0 now straddles x = 0
    std::vector<Vec3> whole = positions;
    for (Vec3& p : positions)
        if (p[0] < 0)
            p[0] += 3.0;
    context.setPositions(positions);
    context.setVelocitiesToTemperature(300, 2);
    integrator.step(200);
    State state = context.getState(State::Positions);
    for (int b = 0; b < scene.numBodies; b++)
        for (int i = 0; i < 4; i++)
            for (int j = i+1; j < 4; j++) {
                Vec3 d0 = whole[4*b+i]-whole[4*b+j], d1 = state.getPositions()[4*b+i]-state.getPositions()[4*b+j];
                EXPECT_NEAR(std::sqrt(d0.dot(d0)), std::sqrt(d1.dot(d1)), 1e-9);
            }
}

TEST_P(StateAndSystem, BodyLongerThanHalfTheBoxIsRefused) {
    const PlatformConfig& platform = GetParam();
    // A 1.2 nm dimer in a 2 nm box: its particles' nearest images are 0.8 nm apart, another shape.
    // The positions that define the shapes must have it whole and shorter than half the box; the
    // message names the body, its length and the box. The same dimer 0.8 nm long is accepted, and
    // so are its particles wrapped into the box once its shape is set.
    for (double length : {1.2, 0.8}) {
        System system;
        system.setDefaultPeriodicBoxVectors(Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(0, 0, 2));
        system.addParticle(12.0);
        system.addParticle(12.0);
        NonbondedForce* nonbonded = new NonbondedForce();
        nonbonded->setNonbondedMethod(NonbondedForce::CutoffPeriodic);
        nonbonded->setCutoffDistance(0.9);
        nonbonded->addParticle(0, 0.3, 0.5);
        nonbonded->addParticle(0, 0.3, 0.5);
        system.addForce(nonbonded);
        RigidLangevinIntegrator integrator(300, 0.89, 0.002);
        integrator.addRigidBody({0, 1});
        Context context(system, integrator, platform.get(), platform.properties());
        std::vector<Vec3> positions = {Vec3(0.3, 1, 1), Vec3(0.3+length, 1, 1)};
        if (length > 1) {
            try {
                context.setPositions(positions);
                integrator.step(1);
                FAIL() << "a 1.2 nm dimer in a 2 nm box was accepted";
            }
            catch (const OpenMMException& e) {
                std::string message = e.what();
                EXPECT_NE(message.find("rigid body 0 is longer than half the periodic box"), std::string::npos) << message;
                EXPECT_NE(message.find("1.2 nm apart, but half the box is 1 nm"), std::string::npos) << message;
            }
        }
        else {
            context.setPositions(positions);
            integrator.step(1);
            positions = context.getState(State::Positions).getPositions();
            positions[1] -= Vec3(2, 0, 0);  // wrapped: the shape is known, so the dimer comes back whole
            context.setPositions(positions);
            integrator.step(1);
            State state = context.getState(State::Positions);
            Vec3 d = state.getPositions()[1]-state.getPositions()[0];
            EXPECT_NEAR(0.8, std::sqrt(d.dot(d)), 1e-9);
        }
    }
}

TEST_P(StateAndSystem, ExplicitTensorFollowsTheBody) {
    // An asymmetric body with a coupled tensor about a point off its centre of mass, given with
    // the positions it was computed for, driven at zero temperature by constant forces on its
    // particles. A Context that starts from the body turned and moved, with the forces turned the
    // same way, must follow the same motion turned: the tensor belongs to the body, not to a frame.
    const PlatformConfig& platform = GetParam();
    BodyShape shape = asymmetricBody();
    std::vector<Vec3> reference;
    for (const Eigen::Vector3d& r : shape.reference)
        reference.push_back(toVec3(r));
    Eigen::Matrix3d turn = Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.3, -1, 0.5).normalized()).toRotationMatrix();
    Eigen::Vector3d shift(0.7, -1.2, 2.5);
    std::vector<Eigen::Vector3d> forces = {{3, -1, 2}, {-2, 4, 1}, {1, 1, -3}, {0.5, -2, 1}};
    std::vector<Vec3> finalPositions[2];
    for (int run = 0; run < 2; run++) {
        System system;
        CustomExternalForce* push = new CustomExternalForce("-fx*x-fy*y-fz*z");
        push->addPerParticleParameter("fx");
        push->addPerParticleParameter("fy");
        push->addPerParticleParameter("fz");
        std::vector<Vec3> start;
        for (int i = 0; i < 4; i++) {
            system.addParticle(shape.masses[i]);
            Eigen::Vector3d f = (run == 0 ? forces[i] : Eigen::Vector3d(turn*forces[i]));
            push->addParticle(i, {f[0], f[1], f[2]});
            start.push_back(run == 0 ? reference[i] : toVec3(turn*shape.reference[i]+shift));
        }
        system.addForce(push);
        RigidLangevinIntegrator integrator(0, 10.0, 0.002);
        integrator.addRigidBody({0, 1, 2, 3});
        integrator.setBodyResistance(0, flatten(coupledTensor()), Vec3(0.05, -0.03, 0.02), reference);
        std::unique_ptr<Context> context(createContext(system, integrator, platform));
        context->setPositions(start);
        integrator.step(1000);
        finalPositions[run] = context->getState(State::Positions).getPositions();
    }
    double worst = 0, moved = 0;
    for (int i = 0; i < 4; i++) {
        Eigen::Vector3d expected = turn*toEigen(finalPositions[0][i])+shift;
        worst = std::max(worst, (expected-toEigen(finalPositions[1][i])).norm());
        moved = std::max(moved, (toEigen(finalPositions[0][i])-shape.reference[i]).norm());
    }
    std::cout << "turned start: largest difference from the turned motion " << worst << " nm (the body moved " << moved << " nm)" << std::endl;
    EXPECT_GT(moved, 0.05);
    // GPU platforms sum forces in 64-bit fixed point (2^-32 kJ/mol/nm), and that resolution differs
    // between the two frames; a tensor left in the first frame would be off by about the motion itself.
    double tolerance = (platform.precision != "double" ? 1e-4 : platform.isGPU() ? 1e-7 : 1e-10);
    EXPECT_LT(worst, tolerance);
}

TEST_P(StateAndSystem, ExplicitTensorWithPositionsOfAnotherShapeIsAnError) {
    const PlatformConfig& platform = GetParam();
    BodyShape shape = asymmetricBody();
    System system;
    std::vector<Vec3> positions, stretched;
    for (int i = 0; i < 4; i++) {
        system.addParticle(shape.masses[i]);
        positions.push_back(toVec3(shape.reference[i]));
        stretched.push_back(toVec3(1.1*shape.reference[i]));
    }
    RigidLangevinIntegrator integrator(300, 100.0, 0.002);
    integrator.addRigidBody({0, 1, 2, 3});
    integrator.setBodyResistance(0, flatten(coupledTensor()), Vec3(), stretched);
    std::unique_ptr<Context> context(createContext(system, integrator, platform));
    context->setPositions(positions);
    try {
        integrator.step(1);
        FAIL() << "a tensor given with positions of another shape was accepted";
    }
    catch (const OpenMMException& e) {
        EXPECT_NE(std::string::npos, std::string(e.what()).find("reference positions given with the resistance tensor of rigid body 0 do not match its shape")) << e.what();
    }
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, StateAndSystem, testing::ValuesIn(platformConfigs()), PlatformConfigName());
