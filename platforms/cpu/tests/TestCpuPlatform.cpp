/*
 * The CPU platform's kernel is deterministic: the bodies are split into a fixed set of chunks, each
 * with its own random stream, and threads take whole chunks. A trajectory is then fixed by the
 * random number seed (and the forces): the same with the same seed and number of threads, and even
 * with another number of threads, since the chunks do not depend on it. Enough bodies that the
 * kernel runs threaded (CpuIntegrateRigidLangevinStepKernel::MinBodiesForThreads). The host step
 * (Reference and CPU) gives the same trajectory with streaming stores of the particles as with
 * ordinary ones.
 */
#include "CpuTests.h"
#include "RigidBodyTestUtilities.h"
#include "openmm/CustomExternalForce.h"
#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <map>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

/**
 * 300 asymmetric bodies and 100 free particles in a harmonic well (a per-particle force, which the
 * CPU platform computes the same way whatever its threads), with friction and noise.
 */
State run(const std::string& threads, int seed, RigidLangevinIntegrator::Scheme scheme, const std::string& platform = "CPU",
          bool hydrodynamicInteractions = false) {
    BodyShape shape = asymmetricBody();
    // With hydrodynamic interactions, fewer bodies and blobs (three of each body's particles; the
    // dense coupled friction's cost grows as the cube of the blobs), still enough bodies that the
    // kernel runs threaded.
    const int numBodies = (hydrodynamicInteractions ? 210 : 300), numFree = (hydrodynamicInteractions ? 0 : 100);
    System system;
    CustomExternalForce* well = new CustomExternalForce("5*(x^2+y^2+z^2)");
    system.addForce(well);
    RigidLangevinIntegrator integrator(300, 100.0, 0.002);
    integrator.setScheme(scheme);
    integrator.setRandomNumberSeed(seed);
    integrator.setHydrodynamicInteractions(hydrodynamicInteractions);
    std::vector<Vec3> positions;
    for (int b = 0; b < numBodies; b++) {
        Eigen::Matrix3d r = Eigen::AngleAxisd(0.1*b, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
        Eigen::Vector3d center(0.5*(b%10), 0.5*((b/10)%10), 0.5*(b/100));
        std::vector<int> particles;
        for (int i = 0; i < 4; i++) {
            particles.push_back(system.addParticle(shape.masses[i]));
            positions.push_back(toVec3(center+r*shape.reference[i]));
        }
        integrator.addRigidBody(particles);
    }
    for (int i = 0; i < numFree; i++) {
        system.addParticle(20.0);
        positions.push_back(Vec3(0.5*(i%10), 0.5*(i/10), 2.0));
    }
    for (int i = 0; i < system.getNumParticles(); i++) {
        well->addParticle(i);
        integrator.setParticleRadius(i, 0.1);
    }
    if (hydrodynamicInteractions)
        for (int b = 0; b < numBodies; b++) {
            std::vector<Vec3> bodyPositions(positions.begin()+4*b, positions.begin()+4*b+4);
            integrator.setBodyBlobs(b, {bodyPositions[0], bodyPositions[1], bodyPositions[2]}, {0.1, 0.1, 0.1}, bodyPositions);
        }
    std::map<std::string, std::string> properties;
    if (platform == "CPU")
        properties["Threads"] = threads;
    Context context(system, integrator, Platform::getPlatformByName(platform), properties);
    context.setPositions(positions);
    context.setVelocitiesToTemperature(300, 5);
    integrator.step(hydrodynamicInteractions ? 3 : 200);
    return context.getState(State::Positions | State::Velocities);
}

bool identical(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    for (int i = 0; i < (int) a.size(); i++)
        if (!(a[i] == b[i]))
            return false;
    return true;
}

} // namespace

TEST(CpuPlatform, DeterministicForASeedAndAnyNumberOfThreads) {
    for (RigidLangevinIntegrator::Scheme scheme : {RigidLangevinIntegrator::ExactFlow, RigidLangevinIntegrator::BAOAB}) {
        SCOPED_TRACE("scheme "+std::to_string(scheme));
        std::vector<Vec3> first = run("2", 11, scheme).getPositions();
        EXPECT_TRUE(identical(first, run("2", 11, scheme).getPositions())) << "same seed, same threads";
        EXPECT_TRUE(identical(first, run("1", 11, scheme).getPositions())) << "same seed, one thread";
        EXPECT_TRUE(identical(first, run("3", 11, scheme).getPositions())) << "same seed, three threads";
        EXPECT_FALSE(identical(first, run("2", 12, scheme).getPositions())) << "another seed";
    }
}

TEST(CpuPlatform, HydrodynamicInteractionsDeterministicForAnyNumberOfThreads) {
    // Coupled through the solvent, the bodies' noise is drawn for all of them at once: the
    // trajectory is still fixed by the seed, whatever the threads.
    const RigidLangevinIntegrator::Scheme scheme = RigidLangevinIntegrator::BAOAB;
    std::vector<Vec3> first = run("2", 11, scheme, "CPU", true).getPositions();
    EXPECT_TRUE(identical(first, run("1", 11, scheme, "CPU", true).getPositions())) << "same seed, one thread";
    EXPECT_TRUE(identical(first, run("3", 11, scheme, "CPU", true).getPositions())) << "same seed, three threads";
    EXPECT_FALSE(identical(first, run("2", 12, scheme, "CPU", true).getPositions())) << "another seed";
}

TEST(CpuPlatform, StreamingParticleStoresPlaceTheSameParticles) {
    // The host step (Reference and CPU) writes particle positions and velocities with streaming
    // stores where a System's arrays exceed the last-level cache (TestParticleStores); a System
    // this small is stepped with ordinary ones unless the environment forces streaming.
    for (std::string platform : {"CPU", "Reference"})
        for (RigidLangevinIntegrator::Scheme scheme : {RigidLangevinIntegrator::ExactFlow, RigidLangevinIntegrator::BAOAB}) {
            SCOPED_TRACE(platform+", scheme "+std::to_string(scheme));
            State cached = run("2", 11, scheme, platform);
            State streaming = [&] {
                ParticleStoresSetting setting("streaming");
                return run("2", 11, scheme, platform);
            }();
            EXPECT_TRUE(identical(cached.getPositions(), streaming.getPositions()));
            EXPECT_TRUE(identical(cached.getVelocities(), streaming.getVelocities()));
        }
}
