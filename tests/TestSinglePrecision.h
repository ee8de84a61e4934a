/*
 * Single precision on GPU platforms: rotation matrices are stored in float, and each rotation
 * rounds them off orthonormality by ~1e-7; over a million steps that would accumulate to 1e-4 or
 * more (a random walk, or a drift where rounding is biased), deforming bodies by as much. The
 * common kernels make the rotation orthonormal whenever they read it. Four fast-spinning bodies
 * (three-moment and linear), kept near the origin so that float positions resolve 1e-7 nm, run 1e6
 * steps without friction; the distances inside each body must stay within 1e-5 (relative) of their
 * start.
 *
 * Body centres are kept in the periodic box (with a count of the boxes left), so that a body that
 * has diffused far is resolved as well as at the start: bodies crossing a 3 nm box 300 times must
 * keep their shape to single precision and fly exactly as free bodies do.
 */
#include "RigidBodyTestUtilities.h"
#include <gtest/gtest.h>
#include "openmm/CustomNonbondedForce.h"
#include <Eigen/Geometry>
#include <limits>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

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

class SinglePrecision : public testing::TestWithParam<PlatformConfig> {
};

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

namespace {

/** Three free asymmetric bodies at 20 nm/ps in a periodic box without interactions (but with
 * OpenMM's atom reordering and its own cell offsets), 50000 steps: 2000 nm, 670 boxes. */
void flyFar(const PlatformConfig& platform, const Vec3 (&box)[3]) {
    BodyShape shape = asymmetricBody();
    const double speed = 20, h = 0.002;
    const int numSteps = 50000;
    System system;
    system.setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    CustomNonbondedForce* periodicBox = new CustomNonbondedForce("0");
    periodicBox->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    periodicBox->setCutoffDistance(1.0);
    system.addForce(periodicBox);
    RigidLangevinIntegrator integrator(300, 0, h);
    std::vector<Vec3> positions, velocities, centerVelocities;
    std::vector<std::vector<int> > bodies;
    for (int b = 0; b < 3; b++) {
        Eigen::Vector3d center(0.9*b+0.2, 1.0*b+0.3, 2.5-0.8*b);
        Eigen::Vector3d velocity = speed*Eigen::Vector3d(1+b, 2-b, 0.5-b).normalized();
        Eigen::Vector3d omega = 3.0*Eigen::Vector3d(2-b, 1+b, 1).normalized();
        centerVelocities.push_back(toVec3(velocity));
        std::vector<int> particles;
        for (int i = 0; i < 4; i++) {
            particles.push_back(system.addParticle(shape.masses[i]));
            periodicBox->addParticle();
            positions.push_back(toVec3(center+shape.reference[i]));
            velocities.push_back(toVec3(velocity+omega.cross(shape.reference[i])));
        }
        bodies.push_back(particles);
        integrator.addRigidBody(particles);
    }
    for (int i = 0; i < system.getNumParticles(); i++)
        integrator.setParticleRadius(i, 0.1);
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions(positions);
    context.setVelocities(velocities);
    std::vector<Vec3> start = context.getState(State::Positions).getPositions();
    integrator.step(numSteps);
    std::vector<Vec3> end = context.getState(State::Positions).getPositions();
    double worst = largestRelativeDistanceChange(start, end, bodies);
    std::cout << platform.name() << ", box " << box[0] << box[1] << box[2] << ": largest relative change of a distance within a body after "
              << speed*h*numSteps << " nm: " << worst << std::endl;
    EXPECT_LT(worst, 1e-5);
    // Free flight: each centre of mass moved by v t, to within the rounding of a position in the box
    // at each step (at most extent*epsilon/2 in float; kept at 2000 nm it would be 500 times that).
    double extent = box[0][0]+std::abs(box[1][0])+std::abs(box[2][0]);
    const double bound = numSteps*extent*std::numeric_limits<float>::epsilon();
    for (int b = 0; b < 3; b++) {
        Vec3 moved;
        for (int k = 0; k < 4; k++)
            moved += (end[bodies[b][k]]-start[bodies[b][k]])*(shape.masses[k]/shape.mass);
        Vec3 error = moved-centerVelocities[b]*(h*numSteps);
        std::cout << "body " << b << ": centre of mass off free flight by " << std::sqrt(error.dot(error)) << " nm (bound " << bound << ")" << std::endl;
        EXPECT_LT(std::sqrt(error.dot(error)), bound);
    }
}

} // namespace

TEST_P(SinglePrecision, BodiesFarFromTheStartKeepTheirShape) {
    const Vec3 rectangular[3] = {Vec3(3, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 3)};
    flyFar(GetParam(), rectangular);
}

TEST_P(SinglePrecision, BodiesFarFromTheStartKeepTheirShapeInATriclinicBox) {
    const Vec3 triclinic[3] = {Vec3(3, 0, 0), Vec3(1.0, 3, 0), Vec3(-1.2, 1.1, 3)};
    flyFar(GetParam(), triclinic);
}

GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(SinglePrecision);
INSTANTIATE_TEST_SUITE_P(OnPlatform, SinglePrecision, testing::ValuesIn(singlePrecisionConfigs()), PlatformConfigName());
