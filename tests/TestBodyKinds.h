/*
 * The kinds of body PHYSICS.md section 4 singles out: linear bodies (5 degrees of freedom, no
 * rotation about the axis), single-particle bodies (3), bodies carrying massless sites, and free
 * particles mixed with bodies.
 */
#include "RigidBodyTestUtilities.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/NonbondedForce.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

/** Time averages of the translational and rotational temperatures the integrator reports. */
void averageTemperatures(Context& /*context*/, RigidLangevinIntegrator& integrator, int stride, int samples, Series& translational, Series& rotational) {
    for (int i = 0; i < samples; i++) {
        integrator.step(stride);
        translational.add(integrator.computeTranslationalTemperature());
        rotational.add(integrator.computeRotationalTemperature());
    }
}

double maxDistanceChange(const std::vector<Vec3>& a, const std::vector<Vec3>& b, int first, int count) {
    double worst = 0;
    for (int i = first; i < first+count; i++)
        for (int j = i+1; j < first+count; j++) {
            double da = std::sqrt((a[i]-a[j]).dot(a[i]-a[j])), db = std::sqrt((b[i]-b[j]).dot(b[i]-b[j]));
            worst = std::max(worst, std::abs(da-db));
        }
    return worst;
}

} // namespace

class BodyKinds : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(BodyKinds, LinearBodiesHaveFiveDegreesOfFreedomAndEquipartition) {
    const PlatformConfig& platform = GetParam();
    // CO2-like: three particles on a line, plus a massless site on the axis.
    System system;
    RigidLangevinIntegrator integrator(300, 200.0, 0.002);
    integrator.setRandomNumberSeed(3);
    std::vector<Vec3> positions;
    const int numBodies = 300;
    Vec3 axis = Vec3(1, 2, 2)/3;
    for (int b = 0; b < numBodies; b++) {
        int first = system.getNumParticles();
        system.addParticle(16.0);
        system.addParticle(12.0);
        system.addParticle(16.0);
        system.addParticle(0.0);
        Vec3 center(b, 0, 0);
        positions.push_back(center-axis*0.116);
        positions.push_back(center);
        positions.push_back(center+axis*0.116);
        positions.push_back(center+axis*0.05);
        integrator.addRigidBody({first, first+1, first+2, first+3});
        for (int p = first; p < first+3; p++)
            integrator.setParticleRadius(p, 0.12);
    }
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions(positions);
    context.setVelocitiesToTemperature(300, 1);
    EXPECT_EQ(5*numBodies, integrator.getNumDegreesOfFreedom());
    Series translational, rotational;
    averageTemperatures(context, integrator, 5, 400, translational, rotational);
    std::cout << "linear bodies: translational " << translational.mean() << " +- " << translational.standardError()
              << " K, rotational (2 per body) " << rotational.mean() << " +- " << rotational.standardError() << " K" << std::endl;
    // 4 standard errors, each below 2.5 K: a 5% error (15 K) lies 2 standard errors beyond the window.
    EXPECT_NEAR(300, translational.mean(), 4*translational.standardError());
    EXPECT_NEAR(300, rotational.mean(), 4*rotational.standardError());
    EXPECT_LT(translational.standardError(), 2.5);
    EXPECT_LT(rotational.standardError(), 2.5);
    // The bodies stay straight and the site stays where it was on the axis.
    std::vector<Vec3> end = context.getState(State::Positions).getPositions();
    for (int b = 0; b < numBodies; b++)
        EXPECT_LT(maxDistanceChange(positions, end, 4*b, 4), 1e-10);
}

TEST_P(BodyKinds, LinearBodiesConserveEnergyWithoutFriction) {
    const PlatformConfig& platform = GetParam();
    // Two linear bodies interacting through Lennard-Jones: energy error of second order.
    double deviation[2];
    for (int run = 0; run < 2; run++) {
        double h = (run == 0 ? 0.002 : 0.001);
        System system;
        NonbondedForce* nb = new NonbondedForce();
        system.addForce(nb);
        RigidLangevinIntegrator integrator(300, 0, h);
        std::vector<Vec3> positions;
        for (int b = 0; b < 2; b++) {
            for (int i = 0; i < 3; i++) {
                system.addParticle(i == 1 ? 12.0 : 16.0);
                nb->addParticle(0, 0.3, 0.8);
                positions.push_back(Vec3(0.5*b+0.1*i, 0.05*b, 0.02*i*b));
            }
            integrator.addRigidBody({3*b, 3*b+1, 3*b+2});
            for (int i = 0; i < 3; i++)
                for (int j = i+1; j < 3; j++)
                    nb->addException(3*b+i, 3*b+j, 0, 1, 0);
        }
        Context context(system, integrator, platform.get(), platform.properties());
        context.setPositions(positions);
        context.setVelocitiesToTemperature(300, 2);
        deviation[run] = energyFluctuation(context, integrator, (int) std::round(0.005/h), 400);
    }
    std::cout << "linear bodies: energy deviation " << deviation[0] << ", " << deviation[1] << " kJ/mol at h = 2, 1 fs" << std::endl;
    EXPECT_NEAR(4.0, deviation[0]/deviation[1], 0.5);
    EXPECT_LT(deviation[0], 0.01);
}

TEST_P(BodyKinds, SingleParticleBodyIsAFreeParticle) {
    const PlatformConfig& platform = GetParam();
    // The same particle as a one-particle body or as a free particle: 3 degrees of freedom and
    // the same trajectory from the same random numbers.
    std::vector<Vec3> result[2];
    for (int asBody = 0; asBody < 2; asBody++) {
        System system;
        system.addParticle(40.0);
        RigidLangevinIntegrator integrator(300, 500.0, 0.002);
        integrator.setRandomNumberSeed(77);
        integrator.setParticleRadius(0, 0.2);
        if (asBody)
            integrator.addRigidBody({0});
        Context context(system, integrator, platform.get(), platform.properties());
        context.setPositions({Vec3(0.1, 0.2, 0.3)});
        context.setVelocities({Vec3(1, -1, 0.5)});
        EXPECT_EQ(3, integrator.getNumDegreesOfFreedom());
        integrator.step(100);
        result[asBody] = context.getState(State::Positions).getPositions();
    }
    EXPECT_EQ(result[0][0], result[1][0]);
}

TEST_P(BodyKinds, MasslessSiteCarriesForceAndTorque) {
    const PlatformConfig& platform = GetParam();
    // Three massive particles and a massless site off their plane; only the site feels an external
    // harmonic tether. Without friction the body must conserve energy (force and torque from the
    // site are right) and carry the site rigidly.
    double deviation[2];
    for (int run = 0; run < 2; run++) {
        double h = (run == 0 ? 0.002 : 0.001);
        System system;
        for (double m : {16.0, 1.0, 1.0, 0.0})
            system.addParticle(m);
        CustomExternalForce* tether = new CustomExternalForce("1000*((x-0.3)^2+(y-0.1)^2+(z+0.2)^2)");
        tether->addParticle(3);
        system.addForce(tether);
        RigidLangevinIntegrator integrator(300, 0, h);
        integrator.addRigidBody({0, 1, 2, 3});
        for (int p = 0; p < 3; p++)
            integrator.setParticleRadius(p, 0.1);
        std::vector<Vec3> positions = {Vec3(0, 0, 0), Vec3(0.0957, 0, 0), Vec3(-0.024, 0.0927, 0), Vec3(0.02, 0.03, 0.04)};
        Context context(system, integrator, platform.get(), platform.properties());
        context.setPositions(positions);
        context.setVelocitiesToTemperature(300, 4);
        EXPECT_EQ(6, integrator.getNumDegreesOfFreedom());
        deviation[run] = energyFluctuation(context, integrator, (int) std::round(0.005/h), 400);
        EXPECT_LT(maxDistanceChange(positions, context.getState(State::Positions).getPositions(), 0, 4), 1e-10);
        // The body moved: the tether pulled it.
        Vec3 moved = context.getState(State::Positions).getPositions()[3]-positions[3];
        EXPECT_GT(std::sqrt(moved.dot(moved)), 0.01);
    }
    std::cout << "massless site: energy deviation " << deviation[0] << ", " << deviation[1] << " kJ/mol at h = 2, 1 fs" << std::endl;
    EXPECT_NEAR(4.0, deviation[0]/deviation[1], 0.5);
}

TEST_P(BodyKinds, FreeParticlesMixedWithBodies) {
    const PlatformConfig& platform = GetParam();
    // 100 asymmetric bodies and 200 free particles, no forces: both thermalise to the bath; a
    // massless free particle stays where it is.
    System system;
    RigidLangevinIntegrator integrator(300, 300.0, 0.002);
    integrator.setRandomNumberSeed(8);
    std::vector<Vec3> positions = addBodiesInARow(system, integrator, asymmetricBody(), 100, 0.1);
    for (int i = 0; i < 200; i++) {
        int p = system.addParticle(20.0);
        integrator.setParticleRadius(p, 0.15);
        positions.push_back(Vec3(i, 5, 0));
    }
    int ghost = system.addParticle(0.0);
    positions.push_back(Vec3(1, 2, 3));
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions(positions);
    context.setVelocitiesToTemperature(300, 6);
    EXPECT_EQ(100*6+200*3, integrator.getNumDegreesOfFreedom());
    Series translational, rotational;
    averageTemperatures(context, integrator, 5, 400, translational, rotational);
    std::cout << "mixed system: translational " << translational.mean() << " +- " << translational.standardError()
              << " K, rotational " << rotational.mean() << " +- " << rotational.standardError() << " K" << std::endl;
    EXPECT_NEAR(300, translational.mean(), 4*translational.standardError());
    EXPECT_NEAR(300, rotational.mean(), 4*rotational.standardError());
    EXPECT_LT(translational.standardError(), 2.5);
    EXPECT_LT(rotational.standardError(), 2.5);
    EXPECT_EQ(Vec3(1, 2, 3), context.getState(State::Positions).getPositions()[ghost]);
}

TEST_P(BodyKinds, MasslessSiteOffALinearBodyIsAnError) {
    const PlatformConfig& platform = GetParam();
    System system;
    for (double m : {16.0, 12.0, 0.0})
        system.addParticle(m);
    RigidLangevinIntegrator integrator(300, 100.0, 0.002);
    integrator.addRigidBody({0, 1, 2});
    integrator.setParticleRadius(0, 0.1);
    integrator.setParticleRadius(1, 0.1);
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.05, 0.05, 0)});
    try {
        integrator.step(1);
        FAIL() << "expected an exception";
    }
    catch (const OpenMMException& e) {
        std::string message = e.what();
        EXPECT_NE(std::string::npos, message.find("rigid body 0"));
        EXPECT_NE(std::string::npos, message.find("particle 2"));
    }
}

TEST_P(BodyKinds, HydrodynamicRadiiFromLennardJones) {
    const PlatformConfig& platform = GetParam();
    // At zero temperature a constant force F drives a free particle to the terminal velocity
    // F/(6 pi eta r). Particle 0 takes r = sigma/2 from its Lennard-Jones parameters, particle 1 the
    // radius set explicitly, which overrides its sigma; particle 2 has epsilon = 0 (like water
    // hydrogens with sigma = 1 nm) and so has no radius unless one is set.
    System system;
    NonbondedForce* nb = new NonbondedForce();
    for (int i = 0; i < 3; i++) {
        system.addParticle(18.0);
        nb->addParticle(0.0, i == 2 ? 1.0 : 0.3, i == 2 ? 0.0 : 0.5);
    }
    system.addForce(nb);
    CustomExternalForce* push = new CustomExternalForce("-2.5*x");
    for (int i = 0; i < 3; i++)
        push->addParticle(i);
    system.addForce(push);
    const double viscosity = 500.0;
    RigidLangevinIntegrator integrator(0.0, viscosity, 0.002);
    integrator.setParticleRadius(1, 0.2);
    std::vector<Vec3> positions = {Vec3(0, 0, 0), Vec3(0, 3, 0), Vec3(0, 6, 0)};
    try {
        Context context(system, integrator, platform.get(), platform.properties());
        FAIL() << "particle 2 has no radius";
    }
    catch (const OpenMMException& e) {
        EXPECT_NE(std::string::npos, std::string(e.what()).find("particle 2"));
    }
    integrator.setParticleRadius(2, 0.25);
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions(positions);
    integrator.step(2000);
    std::vector<Vec3> before = context.getState(State::Positions).getPositions();
    integrator.step(1000);
    std::vector<Vec3> after = context.getState(State::Positions).getPositions();
    double radii[3] = {0.15, 0.2, 0.25};
    for (int i = 0; i < 3; i++) {
        double velocity = (after[i][0]-before[i][0])/(1000*0.002);
        EXPECT_NEAR(2.5/(6*M_PI*viscosity*radii[i]), velocity, 1e-9) << "particle " << i;
    }
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, BodyKinds, testing::ValuesIn(platformConfigs()), PlatformConfigName());
