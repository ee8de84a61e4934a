/*
 * The common platforms' device product of the blobs' mobility (CommonBlobMobility, the Krylov
 * solves' products on OpenCL and CUDA) against the host's dense product, in both of its precisions:
 * the pair terms in double at tight tolerances (to round-off), in single at loose ones (to about
 * 1e-6, and not to round-off: the single-precision kernel is the one that ran), and in double again
 * where the radii span more than single precision takes. The blobs sit 5 um from the origin with
 * forces of 1e-25, so that a difference of positions rounded before it is taken, or a force or a
 * length left unscaled, fails the single-precision bound. Each runner gives the platform's
 * ComputeContext (computeContextOf).
 *
 * The spectral solver's device product in a periodic box (CommonPseMobility: the positively split
 * Ewald sum with the platform's FFTs) against the host's PSE with the same parameters (to round-off
 * in double; to float's precision in mixed) and against the dense Ewald sum (within epsilon), in a
 * rectangular and a triclinic box, with one radius and with three; and on the host where float
 * cannot reach the tolerance.
 */
#include "RigidBodyTestUtilities.h"
#include "CommonBlobMobility.h"
#include "CommonPseMobility.h"
#include "internal/PositivelySplitEwald.h"
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

/** A Context of one particle on the platform, for its ComputeContext. */
struct PlatformComputeContext {
    explicit PlatformComputeContext(const PlatformConfig& config) : integrator(0.001) {
        system.addParticle(1.0);
        context.reset(createContext(system, integrator, config));
    }
    ComputeContext& cc() {
        return computeContextOf(integrator.contextImpl());
    }
    System system;
    WithContextImpl<VerletIntegrator> integrator;
    std::unique_ptr<Context> context;
};

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
    PlatformComputeContext platform(GetParam());
    CommonBlobMobility device(platform.cc(), "DeviceBlobMobilityTest");
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

namespace {

/** 300 blobs of the radii given (in turn) in a box of about 4 nm, some outside it (wrapped by the products), two overlapping. */
void periodicBlobs(const std::vector<double>& radiusChoices, std::vector<Vec3>& positions, std::vector<double>& radii) {
    std::mt19937 engine(11);
    std::uniform_real_distribution<double> unit(-0.2, 1.2);
    for (int i = 0; i < 300; i++) {
        positions.push_back(Vec3(4.1*unit(engine), 3.9*unit(engine), 4.3*unit(engine)));
        radii.push_back(radiusChoices[i%radiusChoices.size()]);
    }
    positions[1] = positions[0]+Vec3(0.05, 0, 0);
}

/** |a - b|/|b|. */
double relativeDifference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return (a-b).norm()/b.norm();
}

/** The device's PSE product at tolerance against the host's PSE (same parameters) and the dense Ewald sum. */
void comparePse(ComputeContext& cc, double tolerance, const std::vector<double>& radiusChoices, const Vec3 box[3], bool onDevice,
                double maxFromHost, double minFromHost) {
    std::vector<Vec3> positions;
    std::vector<double> radii;
    periodicBlobs(radiusChoices, positions, radii);
    std::mt19937 engine(13);
    std::normal_distribution<double> normal;
    Eigen::VectorXd f(3*positions.size());
    for (int k = 0; k < f.size(); k++)
        f[k] = normal(engine);
    CommonPseMobility device(cc, "DevicePseTest", KrylovSolvers::sequentially);
    device.setTolerance(tolerance);
    device.setBlobs(positions, radii, box);
    ASSERT_EQ(onDevice, device.isOnDevice());
    PositivelySplitEwald host(tolerance, device.getProduct().getSplitting());
    host.setBlobs(positions, radii, box);
    HostBlobMobility dense(KrylovSolvers::sequentially, positions.size());
    dense.setBlobs(positions, radii, box);
    Eigen::VectorXd onDeviceProduct, hostProduct, denseProduct;
    device.multiply(f, onDeviceProduct);
    host.multiply(f, hostProduct);
    dense.multiply(f, denseProduct);
    const double fromHost = relativeDifference(onDeviceProduct, hostProduct);
    EXPECT_LT(fromHost, maxFromHost) << "tolerance " << tolerance << ", " << radiusChoices.size() << " radii";
    EXPECT_GE(fromHost, minFromHost) << "tolerance " << tolerance << ", " << radiusChoices.size() << " radii";
    EXPECT_LT(relativeDifference(onDeviceProduct, denseProduct), tolerance) << "tolerance " << tolerance << ", " << radiusChoices.size() << " radii";
    // Twice the same product: the fixed-point grid is cleared after each.
    Eigen::VectorXd again;
    device.multiply(f, again);
    EXPECT_EQ(0.0, relativeDifference(again, onDeviceProduct));
}

} // namespace

class DevicePseMobility : public testing::TestWithParam<PlatformConfig> {
};

TEST_P(DevicePseMobility, SameProductAsTheHostsPse) {
    PlatformComputeContext platform(GetParam());
    ComputeContext& cc = platform.cc();
    const Vec3 rectangular[3] = {Vec3(4.1, 0, 0), Vec3(0, 3.9, 0), Vec3(0, 0, 4.3)};
    const Vec3 triclinic[3] = {Vec3(4.1, 0, 0), Vec3(0.8, 3.9, 0), Vec3(-1.1, 1.3, 4.3)};
    const Vec3 skewed[3] = {Vec3(4.1, 0, 0), Vec3(2.05, 3.9, 0), Vec3(-2.05, 1.95, 4.3)};
    if (GetParam().precision == "double") {
        comparePse(cc, 1e-8, {0.12}, triclinic, true, 1e-12, 0);
        comparePse(cc, 1e-8, {0.1, 0.15, 0.2}, rectangular, true, 1e-12, 0);
        comparePse(cc, 1e-6, {0.1, 0.15, 0.2}, triclinic, true, 1e-12, 0);
        comparePse(cc, 1e-3, {0.1, 0.15}, triclinic, true, 1e-12, 0);  // real-space pairs in single precision, as on the host
    }
    else {
        // The grid in float: within float's precision of the host's product, not to round-off.
        comparePse(cc, 1e-3, {0.12}, rectangular, true, 1e-6, 1e-9);
        comparePse(cc, 1e-4, {0.1, 0.15, 0.2}, triclinic, true, 1e-6, 1e-9);
        comparePse(cc, 1e-5, {0.1}, triclinic, true, 1e-6, 1e-9);
        // A box as skewed as OpenMM's reduced form allows: the Gaussians' shared factors reach 4.7e29, still in float's range.
        comparePse(cc, 1e-5, {0.1}, skewed, true, 1e-6, 1e-9);
        // Tighter than float's FFTs reach: the host's products.
        comparePse(cc, 1e-7, {0.1, 0.15}, triclinic, false, 1e-15, 0);
    }
}

INSTANTIATE_TEST_SUITE_P(OnPlatform, DevicePseMobility, testing::ValuesIn(platformConfigs({"double", "mixed"})), PlatformConfigName());

TEST(DevicePseCounts, ArraysBeyondIntCountsStayOnTheHost) {
    // 10^6 blobs at 5% volume fraction and 1e-3: 148 pairs a blob in float as at 10^4 (benchmark_pse), 8.9e8 words; a 400^3 grid, support 12.
    const int grid[3] = {400, 400, 400}, largeGrid[3] = {900, 900, 900}, manyModes[3] = {1024, 1024, 1024};
    EXPECT_TRUE(CommonPseMobility::fitsIntCounts(888000000, grid, 1, 1000000, 12));
    EXPECT_TRUE(CommonPseMobility::fitsIntCounts(2147483647ul, grid, 66, 14000000, 12));
    EXPECT_FALSE(CommonPseMobility::fitsIntCounts(2147483648ul, grid, 1, 1000000, 12));   // uploadSubArray's count
    EXPECT_FALSE(CommonPseMobility::fitsIntCounts(300000000, largeGrid, 1, 1000000, 12)); // 3 x 7.3e8 accumulator words
    EXPECT_FALSE(CommonPseMobility::fitsIntCounts(300000000, manyModes, 1, 1000000, 12)); // 3 x 1.07e9
    EXPECT_FALSE(CommonPseMobility::fitsIntCounts(300000000, grid, 67, 1000000, 12));     // 67 spectra of 3.2e7 modes
    EXPECT_FALSE(CommonPseMobility::fitsIntCounts(300000000, grid, 1, 15000000, 12));     // 2.16e9 spread lines
}
