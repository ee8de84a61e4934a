/*
 * How the host step writes particle positions and velocities (RigidBodyModel::ParticleStores):
 * streaming (non-temporal) stores, which skip reading each cache line before writing it, exactly
 * where a step's arrays exceed the last-level cache and the bodies' particles lie in memory in body
 * order; ordinary stores otherwise; and the environment variable that forces either way for tests
 * and benchmarks (HostParticleStores.h). That both place the same particles bit for bit is
 * CpuPlatform.StreamingParticleStoresPlaceTheSameParticles.
 */
#include "ReferenceTests.h"  // the test runner's platform (the functions need none)
#include "HostParticleStores.h"
#include "RigidBodyTestUtilities.h"
#include "openmm/OpenMMException.h"
#include "openmm/System.h"
#include <gtest/gtest.h>
#include <string>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using RigidBodyTest::ParticleStoresSetting;

namespace {

typedef RigidBodyModel::ParticleStores Stores;

/**
 * A model of ten three-particle bodies and five free particles (bodies of their own, after the
 * others). In order, body b holds particles 3b to 3b+2; otherwise body b holds b, b+10 and b+20.
 */
RigidBodyModel model(bool inOrder) {
    System system;
    RigidBodyDescription description;
    for (int i = 0; i < 35; i++) {
        system.addParticle(1.0);
        description.particleRadii[i] = 0.1;
    }
    for (int b = 0; b < 10; b++) {
        RigidBodyDescription::Body body;
        for (int i = 0; i < 3; i++)
            body.particles.push_back(inOrder ? 3*b+i : b+10*i);
        description.bodies.push_back(body);
    }
    return RigidBodyModel(system, description);
}

} // namespace

TEST(ParticleStores, StreamingExactlyWhereTheStepsArraysExceedTheCache) {
    // Per body 148 bytes (its state, 144, and the start of its particle list), per particle 76
    // (position, velocity and force, 72, and its index): 15 bodies and 35 particles touch 4880.
    RigidBodyModel ordered = model(true);
    EXPECT_EQ(Stores::Streaming, ordered.chooseParticleStores(4879));
    EXPECT_EQ(Stores::Cached, ordered.chooseParticleStores(4880));
    EXPECT_EQ(Stores::Cached, ordered.chooseParticleStores(1LL << 30));
}

TEST(ParticleStores, CachedWhereTheBodiesParticlesAreScattered) {
    // Each body's three particles are ten apart: 30 of 35 particles are not next to the one written
    // before, and streaming stores would write partial lines.
    EXPECT_EQ(Stores::Cached, model(false).chooseParticleStores(0));
}

TEST(ParticleStores, TheEnvironmentForcesEitherWay) {
    RigidBodyModel ordered = model(true);
    EXPECT_EQ(Stores::Cached, hostParticleStores(ordered)) << "unset: 4880 bytes fit in any last-level cache";
    {
        ParticleStoresSetting setting("streaming");
        EXPECT_EQ(Stores::Streaming, hostParticleStores(ordered));
    }
    {
        ParticleStoresSetting setting("auto");
        EXPECT_EQ(Stores::Cached, hostParticleStores(ordered));
    }
    {
        ParticleStoresSetting setting("cached");
        EXPECT_EQ(Stores::Cached, hostParticleStores(ordered));
    }
    ParticleStoresSetting setting("Streaming");
    try {
        hostParticleStores(ordered);
        FAIL() << "a value other than auto, cached or streaming was accepted";
    }
    catch (const OpenMMException& e) {
        EXPECT_NE(std::string::npos, std::string(e.what()).find("RIGIDLANGEVIN_HOST_PARTICLE_STORES is \"Streaming\"")) << e.what();
    }
}
