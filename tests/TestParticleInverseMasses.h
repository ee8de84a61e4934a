/*
 * OpenMM keeps each particle's inverse mass in velm.w on the GPU platforms, where its own kernels
 * read it (a CMMotionRemover's, an AndersenThermostat's). The step kernels write velm whole with the
 * inverse mass the body's type holds, rather than reading velm back (the step is bound by memory
 * traffic), so after steps velm.w must be exactly what OpenMM set: 1/m in the device's precision, 0
 * for a massless particle and for a virtual site. Nothing in the public API shows velm.w, so each
 * runner reads the platform's array (inverseMassesOnDevice).
 */
#include "RigidBodyTestUtilities.h"
#include "openmm/NonbondedForce.h"
#include "openmm/VirtualSite.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/common/ContextSelector.h"
#include "openmm/internal/ContextImpl.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

/** velm.w of every particle, in the System's order, as the platform under test holds it now (defined by each runner). */
std::vector<double> inverseMassesOnDevice(ContextImpl& context);

namespace {

/** velm.w from a ComputeContext's array, undoing OpenMM's reordering of atoms. */
std::vector<double> inverseMassesIn(ComputeContext& cc) {
    // CUDA downloads only in the context's own CUDA context, which the test's thread has not made current.
    ContextSelector selector(cc);
    std::vector<double> w(cc.getNumAtoms());
    const std::vector<int>& particleAtSlot = cc.getAtomIndex();
    if (cc.getUseDoublePrecision() || cc.getUseMixedPrecision()) {
        std::vector<mm_double4> velm;
        cc.getVelm().download(velm);
        for (int slot = 0; slot < cc.getNumAtoms(); slot++)
            w[particleAtSlot[slot]] = velm[slot].w;
    }
    else {
        std::vector<mm_float4> velm;
        cc.getVelm().download(velm);
        for (int slot = 0; slot < cc.getNumAtoms(); slot++)
            w[particleAtSlot[slot]] = velm[slot].w;
    }
    return w;
}

} // namespace

class ParticleInverseMasses : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(ParticleInverseMasses, StayWhatOpenMMSet) {
    // Two bodies of one type (masses 12, 1, 16 and a massless particle), a water-shaped body with a
    // virtual site, and a free particle (a body of its own), interacting so that forces act.
    System system;
    NonbondedForce* nonbonded = new NonbondedForce();
    system.addForce(nonbonded);
    WithContextImpl<RigidLangevinIntegrator> integrator(300, 0.01, 0.002);
    integrator.setRandomNumberSeed(3);
    std::vector<Vec3> positions;
    auto add = [&] (double mass, Vec3 position, double charge) {
        int p = system.addParticle(mass);
        nonbonded->addParticle(charge, 0.25, 0.5);
        positions.push_back(position);
        if (mass > 0)
            integrator.setParticleRadius(p, 0.12);
        return p;
    };
    std::vector<std::vector<int> > bodies;
    for (int b = 0; b < 2; b++) {
        Vec3 origin(0.7*b, 0, 0);
        bodies.push_back({add(12, origin, 0.3), add(1, origin+Vec3(0.1, 0, 0), -0.2), add(16, origin+Vec3(0, 0.12, 0), 0.2),
                          add(0, origin+Vec3(0.03, 0.02, 0.09), -0.3)});
    }
    Vec3 water(0, 0.7, 0);
    std::vector<int> w = {add(16, water, 0), add(1.008, water+Vec3(0.09572, 0, 0), 0.52), add(1.008, water+Vec3(-0.024, 0.0927, 0), 0.52)};
    w.push_back(add(0, water+Vec3(0.01, 0.012, 0), -1.04));
    system.setVirtualSite(w[3], new ThreeParticleAverageSite(w[0], w[1], w[2], 0.786646558, 0.106676721, 0.106676721));
    bodies.push_back(w);
    add(7, Vec3(0.7, 0.7, 0), 0.1);
    for (const std::vector<int>& body : bodies) {
        integrator.addRigidBody(body);
        for (int i : body)
            for (int j : body)
                if (i < j)
                    nonbonded->addException(i, j, 0, 1, 0);
    }
    Context context(system, integrator, GetParam().get(), GetParam().properties());
    context.setPositions(positions);
    context.setVelocitiesToTemperature(300, 5);
    integrator.step(20);
    std::vector<double> inverseMasses = inverseMassesOnDevice(integrator.contextImpl());
    ASSERT_EQ(system.getNumParticles(), (int) inverseMasses.size());
    for (int i = 0; i < system.getNumParticles(); i++) {
        double mass = system.getParticleMass(i);
        // What OpenMM computes: 1/m in double, rounded to the device's precision.
        double expected = (mass == 0 ? 0.0 : 1.0/mass);
        if (GetParam().precision == "single")
            expected = (float) expected;
        EXPECT_EQ(expected, inverseMasses[i]) << "particle " << i << " (mass " << mass << ")";
    }
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, ParticleInverseMasses, testing::ValuesIn(platformConfigs({"single", "mixed", "double"})), PlatformConfigName());
