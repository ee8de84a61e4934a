/*
 * Equipartition of free asymmetric bodies whose 6x6 resistance tensor couples translation and
 * rotation and is given about a point off the centre of mass (PHYSICS.md section 5): the
 * mass-weighted generalized velocity (sqrt(m) V, sqrt(I_k) omega_k along the principal axes) must
 * have covariance kT times the identity, at any friction, in the ExactFlow and BAOAB schemes. The
 * stiff end (gamma h = 1000, the viscosity of 1 poise on a water-sized body) is the point.
 */
#include "RigidBodyTestUtilities.h"
#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <chrono>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

struct Covariance {
    Eigen::Matrix<double, 6, 6> mean, error;
};

/** gammaH: the translational friction rate (trace(Xtt)/3 viscosity/m) times the step. */
Covariance measureCovariance(const PlatformConfig& platform, RigidLangevinIntegrator::Scheme scheme, double gammaH, int numBodies, int stride, int numSamples) {
    const double temperature = 300, h = 0.002;
    BodyShape shape = asymmetricBody();
    Eigen::Matrix<double, 6, 6> xi = coupledTensor();
    Eigen::Vector3d offset(0.05, 0.03, 0.01);  // tensor origin relative to the centre of mass
    double viscosity = gammaH/(h*xi.block<3, 3>(0, 0).trace()/3/shape.mass);
    System system;
    RigidLangevinIntegrator integrator(temperature, viscosity, h);
    integrator.setScheme(scheme);
    integrator.setRandomNumberSeed(1234);
    std::vector<Vec3> positions;
    for (int b = 0; b < numBodies; b++) {
        // Each body turned differently, with its tensor given in the lab frame accordingly, so all
        // must still be recognised as one type.
        Eigen::Matrix3d r = Eigen::AngleAxisd(0.37*b, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
        Eigen::Vector3d centre(2.0*b, 0, 0);
        std::vector<int> particles;
        for (int i = 0; i < 4; i++) {
            particles.push_back(system.addParticle(shape.masses[i]));
            positions.push_back(toVec3(centre+r*shape.reference[i]));
        }
        integrator.addRigidBody(particles);
        Eigen::Matrix<double, 6, 6> rotation = Eigen::Matrix<double, 6, 6>::Zero();
        rotation.block<3, 3>(0, 0) = r;
        rotation.block<3, 3>(3, 3) = r;
        integrator.setBodyResistance(b, flatten(rotation*xi*rotation.transpose()), toVec3(centre+r*offset), std::vector<Vec3>(positions.end()-4, positions.end()));
    }
    Context context(system, integrator, platform.get(), platform.properties());
    context.setPositions(positions);
    context.setVelocitiesToTemperature(temperature, 99);
    double kT = BOLTZ*temperature;
    Series series[6][6];
    std::vector<Vec3> pos, vel;
    for (int s = 0; s < numSamples; s++) {
        integrator.step(stride);
        getParticles(context, pos, vel);
        Eigen::Matrix<double, 6, 6> sum = Eigen::Matrix<double, 6, 6>::Zero();
        for (int b = 0; b < numBodies; b++) {
            Eigen::Matrix<double, 6, 1> w = shape.weightedVelocity(shape.measure(pos, vel, 4*b));
            sum += w*w.transpose();
        }
        for (int i = 0; i < 6; i++)
            for (int j = 0; j < 6; j++)
                series[i][j].add(sum(i, j)/(numBodies*kT));
    }
    Covariance run;
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) {
            run.mean(i, j) = series[i][j].mean();
            run.error(i, j) = series[i][j].standardError();
        }
    return run;
}

void checkEquipartition(const Covariance& run) {
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) {
            SCOPED_TRACE("covariance element ("+std::to_string(i)+", "+std::to_string(j)+")");
            // The tolerance is four standard errors of the correlated samples, each below 0.0075, so
            // that a 5% deviation lies at least 2.6 standard errors beyond it.
            ASSERT_LT(run.error(i, j), 0.0075);
            EXPECT_NEAR(i == j ? 1.0 : 0.0, run.mean(i, j), 4*run.error(i, j));
        }
}

struct Case {
    RigidLangevinIntegrator::Scheme scheme;
    double gammaH;
    int numBodies, stride, numSamples;
    bool representative;  ///< run on every platform (see runsEveryStatisticalCase())
};

// 800 independent bodies, 300 samples each: standard errors below 0.0075.
const Case cases[] = {
    {RigidLangevinIntegrator::ExactFlow, 1e-3, 800, 100, 300, false},
    {RigidLangevinIntegrator::ExactFlow, 1.0, 800, 1, 300, true},
    {RigidLangevinIntegrator::ExactFlow, 1e3, 800, 1, 300, false},
    {RigidLangevinIntegrator::BAOAB, 1e-3, 800, 100, 300, false},
    {RigidLangevinIntegrator::BAOAB, 1.0, 800, 1, 300, true},
    {RigidLangevinIntegrator::BAOAB, 1e3, 800, 1, 300, false},
};

} // namespace

class Equipartition : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(Equipartition, FreeCoupledBodyAtEveryFriction) {
    const PlatformConfig& platform = GetParam();
    for (const Case& c : cases) {
        if (!c.representative && !runsEveryStatisticalCase(platform))
            continue;
        SCOPED_TRACE("scheme "+std::to_string(c.scheme)+", gamma h = "+std::to_string(c.gammaH));
        auto start = std::chrono::steady_clock::now();
        checkEquipartition(measureCovariance(platform, c.scheme, c.gammaH, c.numBodies, c.stride, c.numSamples));
        std::cout << platform.name() << ", scheme " << c.scheme << ", gamma h = " << c.gammaH << ": "
                  << std::chrono::duration<double>(std::chrono::steady_clock::now()-start).count() << " s" << std::endl;
    }
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, Equipartition, testing::ValuesIn(platformConfigs()), PlatformConfigName());
// Single and mixed precision have code paths of their own (float arithmetic, rotations made orthonormal on every read).
INSTANTIATE_TEST_SUITE_P(LowerPrecision, Equipartition, testing::ValuesIn(lowerPrecisionConfigs()), PlatformConfigName());
