/*
 * The common platforms' device product of the blobs' mobility (CommonBlobMobility, the Krylov
 * solves' products on OpenCL and CUDA) against the host's dense product, in both of its precisions:
 * the pair terms in double at tight tolerances (to round-off), in single at loose ones (to about
 * 1e-6, and not to round-off: the single-precision kernel is the one that ran), and in double again
 * where the radii span more than single precision takes. The blobs sit 5 um from the origin with
 * forces of 1e-25, so that a difference of positions rounded before it is taken, or a force or a
 * length left unscaled, fails the single-precision bound. Each runner gives the platform's
 * ComputeContext (computeContextOf).
 */
#include "RigidBodyTestUtilities.h"
#include "CommonBlobMobility.h"
#include "internal/BlobMobility.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/internal/ContextImpl.h"
#include <gtest/gtest.h>
#include <random>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

/** The platform's ComputeContext behind a Context of it (defined by each runner). */
ComputeContext& computeContextOf(ContextImpl& context);

namespace {

/** 150 blobs (three tiles of 64, the last partly filled) in a 2 nm cube 5000 nm from the origin,
 *  radii from 0.1 to 0.1 x span, some overlapping, one inside another. */
void someBlobs(double span, std::vector<Vec3>& positions, std::vector<double>& radii) {
    std::mt19937 engine(5);
    std::uniform_real_distribution<double> unit(0, 1);
    const Vec3 far(5000, -3000, 2000);
    for (int i = 0; i < 150; i++) {
        positions.push_back(far+Vec3(2*unit(engine), 2*unit(engine), 2*unit(engine)));
        radii.push_back(0.1*std::pow(span, unit(engine)));
    }
    positions[1] = positions[0]+Vec3(0.5*radii[0], 0, 0);   // overlapping
    radii[2] = 0.3;
    positions[3] = positions[2]+Vec3(0.05, 0, 0);           // inside blob 2
    radii[3] = 0.1;
}

/** The largest difference of the device's product from the dense host product, relative to the largest component of the latter. */
double relativeError(CommonBlobMobility& device, const std::vector<Vec3>& positions, const std::vector<double>& radii, const Eigen::VectorXd& f) {
    HostBlobMobility dense(KrylovSolvers::sequentially, positions.size());
    dense.setBlobs(positions, radii);
    Eigen::VectorXd exact, product;
    dense.multiply(f, exact);
    device.setBlobs(positions, radii);
    device.multiply(f, product);
    return (product-exact).cwiseAbs().maxCoeff()/exact.cwiseAbs().maxCoeff();
}

} // namespace

class DeviceBlobMobility : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(DeviceBlobMobility, PairTermsInTheTolerancesPrecision) {
    System system;
    system.addParticle(1.0);
    WithContextImpl<VerletIntegrator> integrator(0.001);
    std::unique_ptr<Context> context(createContext(system, integrator, GetParam()));
    CommonBlobMobility device(computeContextOf(integrator.contextImpl()), "DeviceBlobMobilityTest");
    std::vector<Vec3> positions;
    std::vector<double> radii;
    someBlobs(3, positions, radii);
    std::mt19937 engine(7);
    std::normal_distribution<double> normal;
    Eigen::VectorXd f(3*positions.size());
    for (int k = 0; k < f.size(); k++)
        f[k] = 1e-42*normal(engine);

    device.setTolerance(1e-8);
    double error = relativeError(device, positions, radii, f);
    EXPECT_FALSE(device.isSinglePrecision());
    EXPECT_LT(error, 1e-12);

    device.setTolerance(RigidLangevinIntegrator(300, 1, 0.001).getHydrodynamicTolerance());
    error = relativeError(device, positions, radii, f);
    EXPECT_TRUE(device.isSinglePrecision());
    EXPECT_LT(error, 2e-6);
    EXPECT_GT(error, 1e-10);  // rounded to single precision somewhere: the single-precision kernel ran

    // Radii spanning 3000 times: in double at any tolerance.
    positions.clear();
    radii.clear();
    someBlobs(3000, positions, radii);
    error = relativeError(device, positions, radii, f);
    EXPECT_FALSE(device.isSinglePrecision());
    EXPECT_LT(error, 1e-12);
}

// The device's products run in double precision on every device, whatever the platform's precision.
INSTANTIATE_TEST_SUITE_P(OnPlatform, DeviceBlobMobility, testing::ValuesIn(platformConfigs({"double"})), PlatformConfigName());
