#include "RigidLangevinIntegrator.h"
#include "openmm/Context.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace RigidLangevinPlugin;

TEST(Smoke, FreeBodyMoves) {
    System system;
    for (int i = 0; i < 3; i++)
        system.addParticle(1.0+i);
    RigidLangevinIntegrator integrator(300, 0, 0.001);
    integrator.addRigidBody({0, 1, 2});
    for (int i = 0; i < 3; i++)
        integrator.setParticleRadius(i, 0.1);
    Context context(system, integrator, Platform::getPlatformByName("Reference"));
    context.setPositions({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0, 0.15, 0.02)});
    context.setVelocitiesToTemperature(300, 1);
    double e0 = context.getState(State::Energy).getKineticEnergy();
    integrator.step(100);
    double e1 = context.getState(State::Energy).getKineticEnergy();
    EXPECT_NEAR(e0, e1, 1e-6*e0);
    EXPECT_EQ(6, integrator.getNumDegreesOfFreedom());
}
