/*
 * The CUDA platform, where this machine has one (a GPU, its driver and OpenMM's CUDA platform):
 * its kernels compile and run in every precision and follow Reference without random numbers.
 * Every platform-parameterized test covers CUDA too when it is present; this test says plainly
 * when it is not ("CUDA platform not available: skipped", which ctest reports as skipped).
 */
#include "LennardJonesCluster.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

std::vector<Vec3> runCluster(const std::string& platform, const std::map<std::string, std::string>& properties, int steps) {
    LennardJonesCluster cluster(LennardJonesCluster::PairBonds, true);
    RigidLangevinIntegrator integrator(300, 0, 0.002);
    cluster.addBodies(integrator);
    Context context(cluster.system, integrator, Platform::getPlatformByName(platform), properties);
    context.setPositions(cluster.positions);
    std::vector<Vec3> velocities(cluster.positions.size());
    for (int i = 0; i < (int) velocities.size(); i++)
        velocities[i] = Vec3(0.3*std::sin(i), 0.3*std::cos(2*i), 0.2*std::sin(3*i+1));
    context.setVelocities(velocities);
    integrator.step(steps);
    return context.getState(State::Positions).getPositions();
}

} // namespace

TEST(CudaPlatform, RunsInEveryPrecisionAndFollowsReference) {
    if (!hasPlatform("CUDA")) {
        std::cout << "CUDA platform not available: skipped" << std::endl;
        GTEST_SKIP() << "CUDA platform not available: skipped (no GPU, driver or OpenMM CUDA platform here)";
    }
    std::vector<Vec3> reference = runCluster("Reference", {}, 100);
    // 100 steps: the chaos of the cluster amplifies rounding about tenfold (see TestPlatformParity).
    for (const std::string precision : {"single", "mixed", "double"}) {
        std::vector<Vec3> result = runCluster("CUDA", {{"Precision", precision}}, 100);
        double worst = 0;
        for (int i = 0; i < (int) result.size(); i++)
            worst = std::max(worst, std::sqrt((result[i]-reference[i]).dot(result[i]-reference[i])));
        std::cout << "CUDA " << precision << ": largest distance from Reference after 100 steps " << worst << " nm" << std::endl;
        EXPECT_LT(worst, precision == "double" ? 1e-9 : 1e-4);
    }
}
