/*
 * The tiled matrix-free product of the blobs' mobility (TiledBlobProduct) against the dense
 * matrix (CoupledResistanceMath::mobilityMatrix) for random blobs that overlap, lie one inside
 * another and have unequal radii, across several tiles, to round-off; the same above a no-slip
 * wall (RotnePragerBlake::mobilityMatrix) with blobs that also cut the wall; and the same bits on
 * 1, 2 and 3 threads. Run natively it checks the build this CPU picks (AVX2 and FMA here); under QEMU as
 * a CPU without AVX2 (ctest TestTiledBlobProductBaseline) the baseline build.
 */
#include "internal/BlobMobility.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/RotnePragerBlake.h"
#include "internal/TiledBlobProduct.h"
#include "openmm/internal/ThreadPool.h"
#include <gtest/gtest.h>
#include <cstdio>
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

/** randomBlobs() above a wall through the cube's lower part: a quarter of the blobs (and some of
 *  those inside others) within their radius of it, none at or below it, none raised onto another. */
double aboveWall(vector<Vec3>& positions, const vector<double>& radii) {
    const double wallZ = -0.3;
    for (int i = 0; i < (int) positions.size(); i++)
        positions[i][2] = std::max(positions[i][2], wallZ+0.01+1e-4*i);
    RotnePragerBlake::validate("aboveWall", positions, radii, wallZ);
    return wallZ;
}

} // namespace

TEST(TiledBlobProduct, IsTheDenseProductToRoundOff) {
    // Sizes within one tile, across two (a partial last tile and a partial last lane) and one blob.
    // A pair left out of the lanes and not added back (an overlap, a blob inside another) or one
    // counted twice changes the product by 1e-3 or more; a wrong lane or tile bound by as much.
    // Above a wall, the image part in lanes, the evaluated heights and the damping: a sign or a
    // coefficient of the image block wrong, a blob's own image left out or a damping missing
    // changes it by 1e-3 or more too (a quarter of the blobs sit within their radius of the wall).
    for (bool wall : {false, true})
        for (int n : {1, 5, 37, 1103}) {
            SCOPED_TRACE(std::string(wall ? "above a wall, " : "unbounded, ")+std::to_string(n));
            vector<Vec3> positions;
            vector<double> radii;
            randomBlobs(n, n, positions, radii);
            TiledBlobProduct tiled;
            Eigen::MatrixXd dense;
            if (wall) {
                const double wallZ = aboveWall(positions, radii);
                dense = RotnePragerBlake::mobilityMatrix(positions, radii, wallZ).selfadjointView<Eigen::Lower>();
                tiled.setBlobsAboveWall(positions, radii, wallZ);
            }
            else {
                dense = denseMobility(positions, radii);
                tiled.setBlobs(positions, radii);
            }
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

TEST(TiledBlobProduct, InSinglePrecisionIsTheDenseProductToAMillionth) {
    // Single-precision pair terms: each within about 1e-7 of its block, each lane's sum over a tile
    // in single, the tiles' sums in double. The product's error is measured against the dense
    // matrix, unbounded and above the wall, for blobs in colloid units (radii 50-400 nm: the scaled
    // lengths) 0.36 mm from the origin, and must stay under 1e-6 (positions rounded to single before
    // their differences show as 6e-6 or more, 6e-7 at a tenth of the distance; a wrong term as 1e-3).
    for (bool wall : {false, true})
        for (int n : {37, 1103}) {
            SCOPED_TRACE(std::string(wall ? "above a wall, " : "unbounded, ")+std::to_string(n));
            vector<Vec3> positions;
            vector<double> radii;
            randomBlobs(n, n, positions, radii);
            const double wallZ = (wall ? aboveWall(positions, radii) : 0.0);
            for (int i = 0; i < n; i++) {
                positions[i] = positions[i]*1000.0+Vec3(3e5, -2e5, 0);
                radii[i] *= 1000.0;
            }
            Eigen::MatrixXd dense = (wall ? RotnePragerBlake::mobilityMatrix(positions, radii, 1000*wallZ) : CoupledResistanceMath::mobilityMatrix(positions, radii))
                                        .selfadjointView<Eigen::Lower>();
            TiledBlobProduct tiled;
            tiled.setSinglePrecision(true);
            if (wall)
                tiled.setBlobsAboveWall(positions, radii, 1000*wallZ);
            else
                tiled.setBlobs(positions, radii);
            ASSERT_TRUE(tiled.isSinglePrecision());
            Eigen::VectorXd f = 1e-3*Eigen::VectorXd::Random(3*n), out;
            tiled.multiply(f, out);
            Eigen::VectorXd exact = dense*f;
            const double error = (out-exact).norm()/exact.norm();
            std::printf("single precision, %s, %d blobs: relative error %.2e\n", wall ? "wall" : "unbounded", n, error);
            EXPECT_LT(error, 1e-6);
            EXPECT_GT(error, 1e-10);  // it is single precision
        }
}

TEST(TiledBlobProduct, RadiiTooUnequalForSinglePrecisionStayInDouble) {
    vector<Vec3> positions = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
    vector<double> radii = {0.3, 0.3/(1.01*TiledBlobProduct::MaxSingleRadiusRatio)};
    TiledBlobProduct tiled;
    tiled.setSinglePrecision(true);
    tiled.setBlobs(positions, radii);
    EXPECT_FALSE(tiled.isSinglePrecision());
    radii[1] = 0.3/(0.99*TiledBlobProduct::MaxSingleRadiusRatio);
    tiled.setBlobs(positions, radii);
    EXPECT_TRUE(tiled.isSinglePrecision());
}

TEST(TiledBlobProduct, HostBlobMobilityIsTheDenseProduct) {
    // HostBlobMobility in an unbounded solvent, at both sides of its switch between a stored matrix
    // and the tiled product.
    for (int n : {50, HostBlobMobility::MaxStoredBlobs+3}) {
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

TEST(TiledBlobProduct, HostBlobMobilityTakesSinglePrecisionFromTheTolerance) {
    // Matrix-free, at SinglePrecisionTolerance and looser the products are single precision's (off
    // by 1e-8 to 1e-6), tighter they are exact; a stored matrix is exact at any tolerance.
    const int n = 400;
    vector<Vec3> positions;
    vector<double> radii;
    randomBlobs(n, 11, positions, radii);
    Eigen::VectorXd f = Eigen::VectorXd::Random(3*n), out;
    Eigen::VectorXd exact = denseMobility(positions, radii)*f;
    for (double tolerance : {1e-3, HostBlobMobility::SinglePrecisionTolerance, 0.9*HostBlobMobility::SinglePrecisionTolerance})
        for (bool stored : {false, true}) {
            SCOPED_TRACE(std::to_string(tolerance)+(stored ? ", stored" : ", matrix-free"));
            HostBlobMobility host(KrylovSolvers::sequentially, stored ? n : 0);
            host.setTolerance(tolerance);
            host.setBlobs(positions, radii);
            host.multiply(f, out);
            const double error = (out-exact).norm()/exact.norm();
            if (!stored && tolerance >= HostBlobMobility::SinglePrecisionTolerance) {
                EXPECT_LT(error, 1e-6);
                EXPECT_GT(error, 1e-10);
            }
            else
                EXPECT_LT(error, 1e-14);
        }
}

TEST(TiledBlobProduct, IsTheSameOnAnyNumberOfThreads) {
    // Each row is summed in one order whichever thread takes it: bit for bit the same product, in
    // an unbounded solvent and above a wall, in double and in single precision.
    vector<Vec3> positions;
    vector<double> radii;
    const int n = 1103;
    randomBlobs(n, 3, positions, radii);
    for (int variant = 0; variant < 4; variant++) {
        const bool wall = variant%2, single = variant/2;
        SCOPED_TRACE(std::string(wall ? "above a wall" : "unbounded")+(single ? ", single precision" : ""));
        TiledBlobProduct tiled;
        tiled.setSinglePrecision(single);
        if (wall)
            tiled.setBlobsAboveWall(positions, radii, aboveWall(positions, radii));
        else
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
}
