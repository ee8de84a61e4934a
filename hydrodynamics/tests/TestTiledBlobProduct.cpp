/*
 * The tiled matrix-free product of the blobs' mobility (TiledBlobProduct) against the dense
 * matrix (CoupledResistanceMath::mobilityMatrix) for random blobs that overlap, lie one inside
 * another and have unequal radii, across several tiles, to round-off; and the same bits on 1, 2
 * and 3 threads. Run natively it checks the build this CPU picks (AVX2 and FMA here); under QEMU as
 * a CPU without AVX2 (ctest TestTiledBlobProductBaseline) the baseline build.
 */
#include "internal/BlobMobility.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/TiledBlobProduct.h"
#include "openmm/internal/ThreadPool.h"
#include <gtest/gtest.h>
#include <random>

using namespace RigidLangevinPlugin;
using OpenMM::Vec3;
using std::vector;

namespace {

/** n blobs of radii in [0.05, 0.4] nm in a cube of side n^(1/3) 0.5 nm (about one blob in ten overlaps
 *  another), a few placed inside others and a few pairs at the same point with unequal radii. */
void randomBlobs(int n, int seed, vector<Vec3>& positions, vector<double>& radii) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(0, 1);
    const double side = 0.5*std::cbrt(n);
    positions.clear();
    radii.clear();
    for (int i = 0; i < n; i++) {
        positions.push_back(Vec3(uniform(random), uniform(random), uniform(random))*side);
        radii.push_back(0.05+0.35*uniform(random));
    }
    for (int i = 0; i+7 < n; i += n/5) {
        positions[i+3] = positions[i]+Vec3(0.01, 0, 0);  // inside, or overlapping, i
        positions[i+7] = positions[i];                    // the same point, another radius
        radii[i+7] = radii[i]+0.1;
    }
}

/** A ParallelFor on pool's threads, each taking one contiguous range, as the CPU platform shares rows. */
KrylovSolvers::ParallelFor poolParallel(OpenMM::ThreadPool& pool) {
    return [&pool] (int count, const std::function<void (int, int)>& task) {
        const int n = pool.getNumThreads();
        pool.execute([&] (OpenMM::ThreadPool&, int t) { task((int) ((long long) count*t/n), (int) ((long long) count*(t+1)/n)); });
        pool.waitForThreads();
    };
}

Eigen::MatrixXd denseMobility(const vector<Vec3>& positions, const vector<double>& radii) {
    Eigen::MatrixXd lower = CoupledResistanceMath::mobilityMatrix(positions, radii);
    return lower.selfadjointView<Eigen::Lower>();
}

} // namespace

TEST(TiledBlobProduct, IsTheDenseProductToRoundOff) {
    // Sizes within one tile, across two (a partial last tile and a partial last lane) and one blob.
    // A pair left out of the lanes and not added back (an overlap, a blob inside another) or one
    // counted twice changes the product by 1e-3 or more; a wrong lane or tile bound by as much.
    for (int n : {1, 5, 37, 1103}) {
        SCOPED_TRACE(n);
        vector<Vec3> positions;
        vector<double> radii;
        randomBlobs(n, n, positions, radii);
        Eigen::MatrixXd dense = denseMobility(positions, radii);
        TiledBlobProduct tiled;
        tiled.setBlobs(positions, radii);
        for (int trial = 0; trial < 3; trial++) {
            Eigen::VectorXd f = Eigen::VectorXd::Random(3*n), out;
            tiled.multiply(f, out);
            Eigen::VectorXd exact = dense*f;
            ASSERT_EQ(3*n, out.size());
            EXPECT_LT((out-exact).norm(), 1e-14*exact.norm());
            EXPECT_LT((out-exact).cwiseAbs().maxCoeff(), 1e-14*exact.cwiseAbs().maxCoeff());
        }
    }
}

TEST(TiledBlobProduct, HostBlobMobilityIsTheDenseProduct) {
    // HostBlobMobility in an unbounded solvent, at both sides of its switch between a stored matrix
    // and the tiled product.
    for (int n : {50, HostBlobMobility::MaxStoredUnboundedBlobs+3}) {
        SCOPED_TRACE(n);
        vector<Vec3> positions;
        vector<double> radii;
        randomBlobs(n, 11, positions, radii);
        Eigen::VectorXd f = Eigen::VectorXd::Random(3*n), out;
        HostBlobMobility host;
        host.setBlobs(positions, radii);
        host.multiply(f, out);
        Eigen::VectorXd exact = denseMobility(positions, radii)*f;
        EXPECT_LT((out-exact).norm(), 1e-14*exact.norm());
    }
}

TEST(TiledBlobProduct, IsTheSameOnAnyNumberOfThreads) {
    // Each row is summed in one order whichever thread takes it: bit for bit the same product.
    vector<Vec3> positions;
    vector<double> radii;
    const int n = 1103;
    randomBlobs(n, 3, positions, radii);
    TiledBlobProduct tiled;
    tiled.setBlobs(positions, radii);
    Eigen::VectorXd f = Eigen::VectorXd::Random(3*n), one;
    tiled.multiply(f, one);
    for (int threads : {1, 2, 3}) {
        OpenMM::ThreadPool pool(threads);
        Eigen::VectorXd out;
        tiled.multiply(f, out, poolParallel(pool));
        for (int i = 0; i < 3*n; i++)
            ASSERT_EQ(one[i], out[i]) << threads << " threads, entry " << i;
    }
}
