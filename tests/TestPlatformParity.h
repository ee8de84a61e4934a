/*
 * Every platform integrates the same equations as the Reference platform. Without random numbers
 * the trajectories must agree: at zero viscosity (velocity Verlet with DLM rotation, and the
 * Original scheme's explicit form), and at zero temperature with friction (the ExactFlow and BAOAB
 * flows, the Original scheme's friction iteration, with every noise term zero). The system is the
 * Lennard-Jones cluster of eight asymmetric bodies with a body of every other kind beside it (every
 * friction class, 0, 2 and 3 rotations), 1000 steps of 2 fs.
 *
 * Tolerances. The cluster is chaotic: a displacement of 1e-9 nm grows about a thousandfold in
 * 1000 steps without friction. No platform can follow Reference more closely than its forces
 * allow: GPU platforms accumulate forces in 64-bit fixed point (2^-32 kJ/mol/nm per contribution,
 * which changes a body's velocity by ~1e-12 nm/ps in the first step), so even in double precision
 * their trajectories part from Reference's by 1e-8 nm in 1000 steps. The test therefore measures
 * how far Reference's own trajectory moves when its start is displaced by 1e-9 nm (relative 2e-9
 * on positions of order 0.5 nm), and requires each double-precision platform to stay that close
 * (and within 1e-9 nm where friction damps the chaos). Single and mixed precision (and the CPU
 * platform's single-precision NonbondedForce) round positions or forces to 6e-8 relative at every
 * step; they must stay within the spread of Reference started 1e-5 nm away (and within 1e-4 nm).
 * A wrong term in the equations of motion moves the bodies by 0.01 to 0.1 nm here; the
 * double-precision runs, which share the single-precision code, check the equations to 1e-9.
 */
#include "LennardJonesCluster.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

const int NumSteps = 1000;

struct ParityRun {
    RigidLangevinIntegrator::Scheme scheme;
    double temperature, viscosity;
    std::string describe() const {
        return "scheme "+std::to_string(scheme)+", T = "+std::to_string(temperature)+" K, viscosity "+std::to_string(viscosity);
    }
};

const ParityRun runs[] = {
    {RigidLangevinIntegrator::ExactFlow, 300, 0},
    {RigidLangevinIntegrator::BAOAB, 300, 0},
    {RigidLangevinIntegrator::Original, 300, 0},
    {RigidLangevinIntegrator::ExactFlow, 0, 30},
    {RigidLangevinIntegrator::BAOAB, 0, 30},
    {RigidLangevinIntegrator::Original, 0, 30},
};

PlatformConfig referenceConfig() {
    PlatformConfig c;
    c.platform = "Reference";
    c.precision = "double";
    return c;
}

/**
 * Compare a platform's trajectory with Reference's. exact: forces and integration in double
 * precision. The tolerance is the spread of Reference's own trajectory from a start displaced by
 * 1e-9 nm (exact) or 1e-5 nm, with a floor of 1e-9 nm or 1e-4 nm (see the top of this file).
 */
void checkParity(const PlatformConfig& config, const ParityRun& run, LennardJonesCluster::Interaction interaction, bool exact) {
    PlatformConfig reference = referenceConfig();
    std::vector<Vec3> expected = clusterTrajectoryEnd(reference, run.scheme, run.temperature, run.viscosity, interaction, NumSteps);
    double displacement = (exact ? 1e-9 : 1e-5);
    double spread = maxDistance(expected, clusterTrajectoryEnd(reference, run.scheme, run.temperature, run.viscosity, interaction, NumSteps, displacement));
    double tolerance = std::max(spread, exact ? 1e-9 : 1e-4);
    double distance = maxDistance(expected, clusterTrajectoryEnd(config, run.scheme, run.temperature, run.viscosity, interaction, NumSteps));
    std::cout << config.name() << (interaction == LennardJonesCluster::Nonbonded ? " (NonbondedForce)" : "") << ", " << run.describe()
              << ": largest distance from Reference after " << NumSteps << " steps " << distance << " nm; Reference from a start "
              << displacement << " nm away: " << spread << " nm" << std::endl;
    EXPECT_LT(distance, tolerance);
}

} // namespace

class PlatformParity : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(PlatformParity, FollowsReferenceWithoutRandomNumbers) {
    const PlatformConfig& config = GetParam();
    for (const ParityRun& run : runs) {
        SCOPED_TRACE(run.describe());
        checkParity(config, run, LennardJonesCluster::PairBonds, config.precision == "double");
    }
}

TEST_P(PlatformParity, FollowsReferenceWithThePlatformsNonbondedForce) {
    // The platform's own NonbondedForce: the CPU platform computes it in single precision.
    const PlatformConfig& config = GetParam();
    bool exact = (config.precision == "double" && config.platform != "CPU");
    checkParity(config, runs[0], LennardJonesCluster::Nonbonded, exact);
}

GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(PlatformParity);
INSTANTIATE_TEST_SUITE_P(OnPlatform, PlatformParity, testing::ValuesIn(nonReferenceConfigs()), PlatformConfigName());
