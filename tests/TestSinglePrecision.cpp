/*
 * Single precision on GPU platforms: rotation matrices are stored in float, and each rotation
 * rounds them off orthonormality by ~1e-7; over a million steps that would accumulate to 1e-4 or
 * more (a random walk, or a drift where rounding is biased), deforming bodies by as much. The
 * common kernels re-orthonormalise every few steps. Four fast-spinning bodies (three-moment and
 * linear), kept near the origin so that float positions resolve 1e-7 nm, run 1e6 steps without
 * friction; the distances inside each body must stay within 1e-5 (relative) of their start.
 */
#include "RigidBodyTestUtilities.h"
#include <gtest/gtest.h>
#include <Eigen/Geometry>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

class SinglePrecision : public testing::TestWithParam<PlatformConfig> {
};

double largestRelativeDistanceChange(const std::vector<Vec3>& a, const std::vector<Vec3>& b, const std::vector<std::vector<int> >& bodies) {
    double worst = 0;
    for (const std::vector<int>& body : bodies)
        for (int i : body)
            for (int j : body)
                if (i < j) {
                    double d0 = std::sqrt((a[i]-a[j]).dot(a[i]-a[j])), d1 = std::sqrt((b[i]-b[j]).dot(b[i]-b[j]));
                    worst = std::max(worst, std::abs(d1-d0)/d0);
                }
    return worst;
}

std::vector<PlatformConfig> singlePrecisionConfigs() {
    std::vector<PlatformConfig> configs;
    for (const PlatformConfig& c : platformConfigs({"single"}))
        if (c.isGPU())
            configs.push_back(c);
    return configs;
}

} // namespace

TEST_P(SinglePrecision, RotationsStayOrthonormalOverAMillionSteps) {
    const PlatformConfig& platform = GetParam();
    BodyShape shape = asymmetricBody();
    System system;
    RigidLangevinIntegrator integrator(300, 0, 0.002);
    std::vector<Vec3> positions, velocities;
    std::vector<std::vector<int> > bodies;
    // Three asymmetric bodies spinning about different axes at ~4 rad/ps (a turn every 800 steps)
    // around fixed centres.
    for (int b = 0; b < 3; b++) {
        Eigen::Vector3d center(0.3*b-0.3, 0.1*b, -0.1*b);
        Eigen::Vector3d omega = 4.0*Eigen::Vector3d(1+b, 2-b, 0.5+b).normalized();
        std::vector<int> particles;
        for (int i = 0; i < 4; i++) {
            particles.push_back(system.addParticle(shape.masses[i]));
            positions.push_back(toVec3(center+shape.reference[i]));
            velocities.push_back(toVec3(omega.cross(shape.reference[i])));
        }
        bodies.push_back(particles);
    }
    // A linear body (rotates exactly about its angular velocity, a different code path).
    std::vector<int> linear;
    for (int i = -1; i <= 1; i++) {
        linear.push_back(system.addParticle(i == 0 ? 12.0 : 16.0));
        positions.push_back(Vec3(0.1*i, -0.3, 0.2));
        velocities.push_back(Vec3(0, 0.4*i, 0.3*i));
    }
    bodies.push_back(linear);
    for (const std::vector<int>& body : bodies)
        integrator.addRigidBody(body);
    for (int i = 0; i < system.getNumParticles(); i++)
        integrator.setParticleRadius(i, 0.1);
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions(positions);
    context.setVelocities(velocities);
    integrator.step(1);
    std::vector<Vec3> start = context.getState(State::Positions).getPositions();
    const int numSteps = 1000000;
    integrator.step(numSteps);
    std::vector<Vec3> end = context.getState(State::Positions).getPositions();
    double worst = largestRelativeDistanceChange(start, end, bodies);
    std::cout << platform.name() << ": largest relative change of a distance within a body over " << numSteps << " steps: " << worst << std::endl;
    EXPECT_LT(worst, 1e-5);
    // The bodies spun in place.
    for (int i = 0; i < (int) end.size(); i++)
        EXPECT_LT(std::sqrt((end[i]-start[i]).dot(end[i]-start[i])), 0.5);
}

GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(SinglePrecision);
INSTANTIATE_TEST_SUITE_P(GPUPlatforms, SinglePrecision, testing::ValuesIn(singlePrecisionConfigs()), PlatformConfigName());
