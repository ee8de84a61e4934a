// tests/TestStickyDipoleForce.h on the CPU platform.
#include "CpuTests.h"
#include "TestStickyDipoleForce.h"

// The CPU kernel shares the pairs among threads: any number of them gives Reference's energy and
// forces to round-off.
TEST(CpuStickyDipoleForce, AnyNumberOfThreadsAgreesWithReference) {
    WaterBox w = makeWaters("SSD/RF", 4, 0.3, 13);
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
        for (int i = 0; i < (int) forces.size(); i++)
            EXPECT_LT(std::sqrt((forces[i]-referenceForces[i]).dot(forces[i]-referenceForces[i])), 1e-12*largest) << "particle " << i << ", " << threads << " threads";
    }
}
