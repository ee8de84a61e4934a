/*
 * With zero viscosity the default and BAOAB schemes are velocity Verlet with DLM free rotation:
 * symplectic and time-reversible. Interacting asymmetric bodies must conserve energy with an error
 * that scales as h^2 (halving h quarters it) and does not drift, keep their rotation matrices
 * orthonormal to 1e-12 over 1e5 steps, and retrace their path when the momenta are reversed.
 */
#include "LennardJonesCluster.h"
#include "openmm/serialization/SerializationNode.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

typedef LennardJonesCluster Cluster;

/** Standard deviation and drift (last quarter minus first quarter) of the total energy over 2 ps. */
void energyError(const PlatformConfig& platform, RigidLangevinIntegrator::Scheme scheme, double h, double& deviation, double& drift) {
    Cluster cluster;
    RigidLangevinIntegrator integrator(300, 0, h);
    integrator.setScheme(scheme);
    cluster.addBodies(integrator);
    Context context(cluster.system, integrator, platform.get(), platform.properties());
    context.setPositions(cluster.positions);
    context.setVelocitiesToTemperature(300, 17);
    std::vector<double> energy;
    int every = (int) std::round(0.01/h);
    for (int i = 0; i < 200; i++) {
        integrator.step(every);
        State state = context.getState(State::Energy);
        energy.push_back(state.getKineticEnergy()+state.getPotentialEnergy());
    }
    double mean = 0, square = 0, first = 0, last = 0;
    for (int i = 0; i < 200; i++) {
        mean += energy[i]/200;
        square += energy[i]*energy[i]/200;
        if (i < 50)
            first += energy[i]/50;
        if (i >= 150)
            last += energy[i]/50;
    }
    deviation = std::sqrt(square-mean*mean);
    drift = last-first;
}

} // namespace

class ZeroViscosity : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(ZeroViscosity, EnergyErrorScalesAsStepSquared) {
    const PlatformConfig& platform = GetParam();
    for (RigidLangevinIntegrator::Scheme scheme : {RigidLangevinIntegrator::ExactFlow, RigidLangevinIntegrator::BAOAB}) {
        double dev[3], drift[3];
        double steps[3] = {0.002, 0.001, 0.0005};
        for (int i = 0; i < 3; i++)
            energyError(platform, scheme, steps[i], dev[i], drift[i]);
        std::cout << "scheme " << scheme << ": energy deviation " << dev[0] << ", " << dev[1] << ", " << dev[2]
                  << " kJ/mol at h = 2, 1, 0.5 fs; ratios " << dev[0]/dev[1] << ", " << dev[1]/dev[2] << std::endl;
        // Second order: each halving divides the error by 4 (3.6 to 4.4 allows the higher terms).
        EXPECT_NEAR(4.0, dev[0]/dev[1], 0.4);
        EXPECT_NEAR(4.0, dev[1]/dev[2], 0.4);
        // The energy oscillates about a constant: no drift beyond the fluctuation itself.
        for (int i = 0; i < 3; i++)
            EXPECT_LT(std::abs(drift[i]), dev[i]);
    }
}

TEST_P(ZeroViscosity, RotationsStayOrthonormal) {
    const PlatformConfig& platform = GetParam();
    // Particles sit at R + Q^T b_i, so if Q Q^T = 1 + E the distances between them change by
    // about E relative: unchanged distances to 1e-12 mean Q is orthonormal to 1e-12.
    Cluster cluster;
    RigidLangevinIntegrator integrator(300, 0, 0.002);
    cluster.addBodies(integrator);
    Context context(cluster.system, integrator, platform.get(), platform.properties());
    context.setPositions(cluster.positions);
    context.setVelocitiesToTemperature(300, 5);
    integrator.step(1);
    std::vector<Vec3> start = context.getState(State::Positions).getPositions();
    // The CPU platform runs Reference's rotation code; 1e4 steps there (its per-step overhead makes
    // 1e5 take half a minute) check that it keeps Q as Reference does.
    int numSteps = (platform.platform == "CPU" ? 10000 : 100000);
    integrator.step(numSteps);
    std::vector<Vec3> end = context.getState(State::Positions).getPositions();
    double worst = 0;
    for (int b = 0; b < 8; b++)
        for (int i = 4*b; i < 4*b+4; i++)
            for (int j = i+1; j < 4*b+4; j++) {
                double d0 = std::sqrt((start[i]-start[j]).dot(start[i]-start[j]));
                double d1 = std::sqrt((end[i]-end[j]).dot(end[i]-end[j]));
                worst = std::max(worst, std::abs(d1-d0)/d0);
            }
    std::cout << "largest relative change of a distance within a body over " << numSteps << " steps: " << worst << std::endl;
    EXPECT_LT(worst, 1e-12);
}

TEST_P(ZeroViscosity, ReversingMomentaRetracesThePath) {
    const PlatformConfig& platform = GetParam();
    // Stored velocities lie half a kick behind the positions, so reversing the motion at step N
    // means V -> -(V + h F/m) and L -> -(L + h torque). The test sets particle velocities with that
    // rigid motion; the integrator projects them exactly onto it.
    const double h = 0.002;
    // Pair forces computed in double on every platform (the CPU platform's NonbondedForce is single
    // precision, which no integrator can reverse to 1e-9 nm).
    Cluster cluster(LennardJonesCluster::PairBonds);
    BodyShape shape = asymmetricBody();
    RigidLangevinIntegrator integrator(300, 0, h);
    cluster.addBodies(integrator);
    Context context(cluster.system, integrator, platform.get(), platform.properties());
    context.setPositions(cluster.positions);
    context.setVelocitiesToTemperature(300, 9);
    integrator.step(1);
    std::vector<Vec3> start = context.getState(State::Positions).getPositions();
    integrator.step(500);
    State state = context.getState(State::Positions | State::Velocities | State::Forces);
    const std::vector<Vec3>& pos = state.getPositions();
    std::vector<Vec3> velocities(pos.size());
    for (int b = 0; b < 8; b++) {
        MeasuredBody body = shape.measure(pos, state.getVelocities(), 4*b);
        Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
        std::vector<Eigen::Vector3d> offsets;
        for (int p = 0; p < 4; p++) {
            Eigen::Vector3d f = toEigen(state.getForces()[4*b+p]);
            offsets.push_back(toEigen(pos[4*b+p])-body.com);
            force += f;
            torque += offsets.back().cross(f);
        }
        Eigen::Matrix3d inertia = shape.inertiaTensor(offsets);
        Eigen::Vector3d velocity = -(body.velocity+h*force/shape.mass);
        Eigen::Vector3d omega = inertia.ldlt().solve(-(inertia*body.omega+h*torque));
        for (int p = 0; p < 4; p++)
            velocities[4*b+p] = toVec3(velocity+omega.cross(offsets[p]));
    }
    context.setVelocities(velocities);
    integrator.step(500);
    std::vector<Vec3> end = context.getState(State::Positions).getPositions();
    double maxError = 0;
    for (int i = 0; i < (int) start.size(); i++)
        maxError = std::max(maxError, std::sqrt((end[i]-start[i]).dot(end[i]-start[i])));
    std::cout << "largest distance from the starting positions after 500 steps forward and back: " << maxError << " nm" << std::endl;
    EXPECT_LT(maxError, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, ZeroViscosity, testing::ValuesIn(platformConfigs()), PlatformConfigName());
