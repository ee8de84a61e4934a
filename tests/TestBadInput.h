/*
 * Bad input gets a clear OpenMMException that names the body or particle and says how to fix it:
 * never a crash, a NaN trajectory or a silent wrong answer.
 */
#include "RigidBodyTestUtilities.h"
#include "openmm/AndersenThermostat.h"
#include "openmm/MonteCarloBarostat.h"
#include "openmm/NonbondedForce.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>
#include <cmath>
#include <functional>
#include <limits>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

/** A system of n particles of mass 10 with radius-bearing Lennard-Jones parameters. */
System particles(int n) {
    System system;
    for (int i = 0; i < n; i++)
        system.addParticle(10.0);
    return system;
}

std::vector<double> identityTensor() {
    std::vector<double> t(36, 0.0);
    for (int i = 0; i < 6; i++)
        t[7*i] = 1.0;
    return t;
}

const double NaN = std::numeric_limits<double>::quiet_NaN();

} // namespace

TEST(BadInput, Parameters) {
    expectError([] {RigidLangevinIntegrator(-1, 1, 0.002);}, {"temperature"});
    expectError([] {RigidLangevinIntegrator(300, -1, 0.002);}, {"viscosity"});
    expectError([] {RigidLangevinIntegrator(300, 1, -0.002);}, {"step size"});
    expectError([] {RigidLangevinIntegrator(300, NaN, 0.002);}, {"viscosity"});
    RigidLangevinIntegrator integrator(300, 1, 0.002);
    expectError([&] {integrator.setTemperature(-5);}, {"temperature"});
    expectError([&] {integrator.setViscosity(NaN);}, {"viscosity"});
    expectError([&] {integrator.setScheme((RigidLangevinIntegrator::Scheme) 7);}, {"scheme"});
    expectError([&] {integrator.setParticleRadius(3, 0.0);}, {"particle 3", "positive"});
    expectError([&] {integrator.setParticleRadius(-1, 0.1);}, {"-1"});
    expectError([&] {integrator.getNumDegreesOfFreedom();}, {"context"});
    // A zero step set later is caught when the context is made (OpenMM itself refuses negative ones).
    integrator.setStepSize(0);
    System system = particles(1);
    integrator.setParticleRadius(0, 0.1);
    expectError([&] {Context context(system, integrator, Platform::getPlatformByName(platformUnderTest().name));}, {"step size"});
}

TEST(BadInput, BodyDefinitions) {
    RigidLangevinIntegrator integrator(300, 1, 0.002);
    expectError([&] {integrator.addRigidBody({});}, {"rigid body 0", "no particles"});
    expectError([&] {integrator.addRigidBody({1, -2});}, {"rigid body 0", "-2"});
    expectError([&] {integrator.addRigidBody({1, 2, 1});}, {"rigid body 0", "particle 1", "twice"});
    integrator.addRigidBody({0, 1});
    expectError([&] {integrator.addRigidBody({2, 1});}, {"particle 1", "rigid body 0"});
    std::vector<Vec3> pair = {Vec3(0, 0, 0), Vec3(0.1, 0, 0)};
    expectError([&] {integrator.getRigidBodyParticles(1);}, {"no rigid body 1"});
    expectError([&] {integrator.setBodyResistance(-1, identityTensor(), Vec3(), pair);}, {"no rigid body -1"});
    expectError([&] {integrator.setBodyResistance(0, std::vector<double>(35, 1.0), Vec3(), pair);}, {"rigid body 0", "36"});
    std::vector<double> t = identityTensor();
    t[3] = NaN;
    expectError([&] {integrator.setBodyResistance(0, t, Vec3(), pair);}, {"rigid body 0", "NaN"});
    t = identityTensor();
    t[1] = 0.5;
    expectError([&] {integrator.setBodyResistance(0, t, Vec3(), pair);}, {"rigid body 0", "not symmetric"});
    t = identityTensor();
    t[35] = -1;
    expectError([&] {integrator.setBodyResistance(0, t, Vec3(), pair);}, {"rigid body 0", "positive definite"});
    expectError([&] {integrator.setBodyResistance(0, identityTensor(), Vec3(NaN, 0, 0), pair);}, {"rigid body 0", "origin"});
    expectError([&] {integrator.setBodyResistance(0, identityTensor(), Vec3(), {Vec3()});}, {"rigid body 0", "2 particles", "got 1 positions"});
    expectError([&] {integrator.setBodyResistance(0, identityTensor(), Vec3(), {Vec3(), Vec3(NaN, 0, 0)});}, {"rigid body 0", "particle 1", "not finite"});
}

// Checked where a context is made or first steps: on every platform.
class BadInputOnPlatform : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(BadInputOnPlatform, BodiesAgainstTheSystem) {
    const PlatformConfig& config = GetParam();
    Platform& platform = config.get();
    {
        System system = particles(3);
        RigidLangevinIntegrator integrator(300, 1, 0.002);
        integrator.addRigidBody({0, 5});
        expectError([&] {Context c(system, integrator, platform, config.properties());}, {"rigid body 0", "particle 5", "3 particles"});
    }
    {
        System system;
        system.addParticle(0.0);
        system.addParticle(0.0);
        RigidLangevinIntegrator integrator(300, 1, 0.002);
        integrator.addRigidBody({0, 1});
        expectError([&] {Context c(system, integrator, platform, config.properties());}, {"rigid body 0", "no particle with mass"});
    }
    {
        System system = particles(4);
        system.addConstraint(0, 1, 0.1);  // inside body 0: satisfied by rigidity
        system.addConstraint(1, 2, 0.1);  // links body 0 to body 1
        RigidLangevinIntegrator integrator(300, 1, 0.002);
        integrator.addRigidBody({0, 1});
        integrator.addRigidBody({2, 3});
        for (int i = 0; i < 4; i++)
            integrator.setParticleRadius(i, 0.1);
        expectError([&] {Context c(system, integrator, platform, config.properties());}, {"constraint 1", "particles 1 and 2"});
    }
    {
        System system = particles(2);
        RigidLangevinIntegrator integrator(300, 1, 0.002);
        integrator.addRigidBody({0, 1});
        integrator.setParticleRadius(0, 0.1);
        expectError([&] {Context c(system, integrator, platform, config.properties());}, {"particle 1", "rigid body 0", "setParticleRadius"});
    }
    for (int kind = 0; kind < 2; kind++) {
        // Forces that move particles or set velocities themselves would be silently undone.
        System system = particles(2);
        system.setDefaultPeriodicBoxVectors(Vec3(3, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 3));
        if (kind == 0)
            system.addForce(new MonteCarloBarostat(1.0, 300.0));
        else
            system.addForce(new AndersenThermostat(300.0, 1.0));
        RigidLangevinIntegrator integrator(300, 1, 0.002);
        integrator.setParticleRadius(0, 0.1);
        integrator.setParticleRadius(1, 0.1);
        NonbondedForce* periodic = new NonbondedForce();
        periodic->setNonbondedMethod(NonbondedForce::CutoffPeriodic);
        periodic->addParticle(0, 0.3, 0.5);
        periodic->addParticle(0, 0.3, 0.5);
        system.addForce(periodic);
        expectError([&] {Context c(system, integrator, platform);}, {kind == 0 ? "barostat" : "AndersenThermostat", "force 0"});
    }
}

TEST_P(BadInputOnPlatform, Positions) {
    const PlatformConfig& config = GetParam();
    Platform& platform = config.get();
    {
        // A body wider than half the periodic box cannot be made whole unambiguously.
        System system = particles(3);
        system.setDefaultPeriodicBoxVectors(Vec3(2, 0, 0), Vec3(0, 2, 0), Vec3(0, 0, 2));
        NonbondedForce* periodic = new NonbondedForce();
        periodic->setNonbondedMethod(NonbondedForce::CutoffPeriodic);
        periodic->setCutoffDistance(0.9);
        for (int i = 0; i < 3; i++)
            periodic->addParticle(0, 0.3, 0);
        system.addForce(periodic);
        RigidLangevinIntegrator integrator(300, 1, 0.002);
        integrator.addRigidBody({0, 1, 2});
        for (int i = 0; i < 3; i++)
            integrator.setParticleRadius(i, 0.1);
        Context context(system, integrator, platform, config.properties());
        context.setPositions({Vec3(0, 0, 0), Vec3(0.7, 0, 0), Vec3(1.4, 0.1, 0)});
        expectError([&] {integrator.step(1);}, {"rigid body 0", "longer than half the periodic box", "1.40357 nm apart"});
    }
    {
        // Positions set later must be a rigid placement of every body.
        System system = particles(3);
        RigidLangevinIntegrator integrator(300, 1, 0.002);
        integrator.addRigidBody({0, 1, 2});
        for (int i = 0; i < 3; i++)
            integrator.setParticleRadius(i, 0.1);
        Context context(system, integrator, platform, config.properties());
        context.setPositions({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.1, 0)});
        integrator.step(1);
        context.setPositions({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.12, 0)});
        expectError([&] {integrator.step(1);}, {"deform", "rigid body 0", "reinitialize"});
    }
    {
        System system = particles(3);
        RigidLangevinIntegrator integrator(300, 1, 0.002);
        integrator.addRigidBody({0, 1, 2});
        for (int i = 0; i < 3; i++)
            integrator.setParticleRadius(i, 0.1);
        Context context(system, integrator, platform, config.properties());
        expectError([&] {integrator.getNumDegreesOfFreedom();}, {"positions have not been set"});
        context.setPositions({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(NaN, 0.1, 0)});
        // The integrator names the particle; a platform that checks coordinates itself before
        // computing forces (CPU) may say so first.
        if (config.platform == "CPU")
            expectError([&] {integrator.step(1);}, {"NaN"});
        else
            expectError([&] {integrator.step(1);}, {"particle 2", "not finite"});
    }
}

TEST_P(BadInputOnPlatform, OriginalSchemeRefusesStiffFriction) {
    const PlatformConfig& platform = GetParam();
    System system = particles(1);
    RigidLangevinIntegrator integrator(300, 1e4, 0.002);
    integrator.setScheme(RigidLangevinIntegrator::Original);
    integrator.setParticleRadius(0, 0.15);
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions({Vec3()});
    expectError([&] {integrator.step(1);}, {"Original scheme", "ExactFlow"});
    // Where it is stable it runs. Reading the State also waits for the queued steps: a test that
    // ends with kernels still queued lets PoCL compile them while the process exits, and its
    // compiler then crashes in LLVM's static destructors (seen 2 runs in 12).
    integrator.setViscosity(10);
    integrator.step(10);
    Vec3 position = context.getState(State::Positions).getPositions()[0];
    ASSERT_TRUE(std::isfinite(position[0]) && std::isfinite(position[1]) && std::isfinite(position[2]));
    ASSERT_GT(position.dot(position), 0.0);
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, BadInputOnPlatform, testing::ValuesIn(platformConfigs()), PlatformConfigName());
