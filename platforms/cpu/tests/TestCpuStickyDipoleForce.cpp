// tests/TestStickyDipoleForce.h on the CPU platform.
//
// The pair term (CpuStickyDipolePairs.cpp) is built twice, for AVX2 and for the baseline, and the
// processor picks one when the library loads. ctest TestCpuStickyDipoleForceBaseline runs these
// tests (all but the long energy-conservation run) under QEMU's user-mode emulator as a processor
// without AVX2, with RIGIDLANGEVIN_HOST_CLONES=compare, so that the baseline build is held to the
// same answers: Reference's to 1e-12 here, the direct sums, the finite differences.
#include "CpuTests.h"
#include "TestStickyDipoleForce.h"

TEST(CpuStickyDipoleForce, EmulatedProcessorPicksTheBaselineBuild) {
    __builtin_cpu_init();
    if (emulatingBaselineBuilds()) {
        ASSERT_FALSE(__builtin_cpu_supports("avx2")) << "the emulated processor offers AVX2, so the baseline build of the pair term would not run";
    }
    std::cout << "The pair term's " << (__builtin_cpu_supports("avx2") ? "AVX2" : "baseline") << " build runs" << std::endl;
}

// The CPU kernel shares the pairs among threads: any number of them gives Reference's energy and
// forces to round-off, with and without a periodic box (the pair term's two ways to the separation).
TEST(CpuStickyDipoleForce, AnyNumberOfThreadsAgreesWithReference) {
    for (bool withCutoff : {false, true}) {
        SCOPED_TRACE(withCutoff ? "periodic cutoff" : "no cutoff");
        WaterBox w = makeWaters("SSD/RF", 4, 0.3, 13);
        if (withCutoff)
            usePeriodicCutoff(w);
        auto evaluate = [&] (Platform& platform, const std::map<std::string, std::string>& properties, std::vector<Vec3>& forces) {
            VerletIntegrator integrator(0.001);
            Context context(w.system, integrator, platform, properties);
            context.setPositions(w.positions);
            State state = context.getState(State::Energy | State::Forces);
            forces = state.getForces();
            return state.getPotentialEnergy();
        };
        std::vector<Vec3> referenceForces, forces;
        double reference = evaluate(Platform::getPlatformByName("Reference"), {}, referenceForces);
        double largest = 0;
        for (const Vec3& f : referenceForces)
            largest = std::max(largest, std::sqrt(f.dot(f)));
        for (const std::string threads : {"1", "2", "3"}) {
            double energy = evaluate(Platform::getPlatformByName("CPU"), {{"Threads", threads}}, forces);
            EXPECT_NEAR(reference, energy, 1e-12*std::abs(reference)) << threads << " threads";
            EXPECT_LT(maxDistance(forces, referenceForces), 1e-12*largest) << threads << " threads";
        }
    }
}
