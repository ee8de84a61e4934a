// Times the blobs' open-space RPY mobility product M f three ways, for 1e2 to 1e4 blobs of radius
// 1 nm at 5% volume fraction in a cube (every pair evaluated: in open space the product has no
// cutoff); with --geometry wall, the regularised Rotne-Prager-Blake product of the same blobs above a no-slip
// wall a radius below the cube; with --precision single, the tiled product's pair terms in single
// precision (TiledBlobProduct::setSinglePrecision), which the peers' double precision then checks:
//
//   tiled   TiledBlobProduct, what HostBlobMobility runs matrix-free now;
//   old     the scalar pair loop it ran before (CoupledResistanceMath::mobilityProduct;
//           RotnePragerBlake::mobilityProduct above the wall);
//   stored  M formed once (as HostBlobMobility does below its stored-matrix limit, both triangles)
//           and applied as a matrix-vector product on the threads: its setup time and its product.
//
//   benchmark_blob_product results.csv [--geometry open|wall] [--precision double|single] [--sizes 100,300,1000,1350,3000,10000] [--old-max-blobs 10000]
//                          [--stored-max-blobs 1350] [--pairs 5] [--block-seconds 0.3]
//
// Each peer is timed against the tiled product in alternating pairs of blocks (the order reversed
// every other pair); ratios are taken pair by pair, so each saw one machine load, and their
// standard errors are over the pairs. "ns per pair per core" is the CPU time of all threads per
// product over n^2 (every ordered pair of blobs, the blob with itself included, as a product over
// all pairs counts them). The products' agreement with the old one is printed as a relative error.
// OPENMM_CPU_THREADS sets the threads (default: all cores).

#include "internal/BlobMobility.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/RotnePragerBlake.h"
#include "internal/TiledBlobProduct.h"
#include "openmm/internal/ThreadPool.h"
#include "BenchmarkTiming.h"
#include <cstdio>
#include <fstream>
#include <iostream>
#include <random>

using namespace RigidLangevinPlugin;
using namespace BenchmarkTiming;
using OpenMM::Vec3;

namespace {

const double Radius = 1.0, VolumeFraction = 0.05, WallZ = -Radius;

struct Row {
    int blobs = 0;
    double tiledMs = NAN, tiledSe = NAN, tiledNs = NAN, tiledNsSe = NAN, oldRatio = NAN, oldRatioSe = NAN, oldNs = NAN, oldNsSe = NAN,
           storedSetupMs = NAN, storedRatio = NAN, storedRatioSe = NAN, storedNs = NAN, storedNsSe = NAN, error = NAN;
};

void makeBlobs(int n, vector<Vec3>& positions, vector<double>& radii) {
    const double side = std::cbrt(n*4*M_PI/3*Radius*Radius*Radius/VolumeFraction);
    std::mt19937 random(n);
    std::uniform_real_distribution<double> uniform(0, side);
    for (int i = 0; i < n; i++) {
        positions.push_back(Vec3(uniform(random), uniform(random), uniform(random)));
        radii.push_back(Radius);
    }
}

/** CPU seconds per call as ns per pair per core (n^2 pairs), with its standard error. */
void nsPerPair(const vector<double>& cpu, int n, double& ns, double& error) {
    meanAndError(cpu, ns, error);
    ns *= 1e9/((double) n*n);
    error *= 1e9/((double) n*n);
}

/** The tiled product against a peer: the peer's time over the tiled one's, and both per pair. */
void againstTiled(const std::function<void ()>& tiled, const std::function<void ()>& peer, int n, int pairs, double blockSeconds, Row& row,
                  double& ratio, double& ratioSe, double& peerNs, double& peerNsSe) {
    vector<double> timesTiled, timesPeer, cpuTiled, cpuPeer;
    alternatingPairs(tiled, peer, pairs, blockSeconds, timesTiled, timesPeer, &cpuTiled, &cpuPeer);
    pairRatio(timesTiled, timesPeer, ratio, ratioSe);
    nsPerPair(cpuPeer, n, peerNs, peerNsSe);
    if (std::isnan(row.tiledMs)) {
        meanAndErrorMs(timesTiled, row.tiledMs, row.tiledSe);
        nsPerPair(cpuTiled, n, row.tiledNs, row.tiledNsSe);
    }
}

Row measure(int n, bool wall, bool single, int oldMax, int storedMax, int pairs, double blockSeconds, OpenMM::ThreadPool& pool) {
    Row row;
    row.blobs = n;
    KrylovSolvers::ParallelFor parallel = poolParallel(pool);
    vector<Vec3> positions;
    vector<double> radii;
    makeBlobs(n, positions, radii);
    Eigen::VectorXd f = Eigen::VectorXd::Random(3*n), out, peerOut;
    TiledBlobProduct tiled;
    tiled.setSinglePrecision(single);
    if (wall)
        tiled.setBlobsAboveWall(positions, radii, WallZ);
    else
        tiled.setBlobs(positions, radii);
    auto tiledProduct = [&] () { tiled.multiply(f, out, parallel); };
    if (n <= oldMax) {
        auto oldProduct = [&] () {
            if (wall)
                RotnePragerBlake::mobilityProduct(positions, radii, WallZ, f, peerOut, parallel);
            else
                CoupledResistanceMath::mobilityProduct(positions, radii, f, peerOut, parallel);
        };
        againstTiled(tiledProduct, oldProduct, n, pairs, blockSeconds, row, row.oldRatio, row.oldRatioSe, row.oldNs, row.oldNsSe);
        row.error = (out-peerOut).norm()/peerOut.norm();
    }
    if (n <= storedMax) {
        // As HostBlobMobility stores M (at any size here): both triangles, rows shared out.
        Eigen::MatrixXd stored;
        row.storedSetupMs = 1e3*seconds([&] () {
            stored = (wall ? RotnePragerBlake::mobilityMatrix(positions, radii, WallZ, parallel)
                           : CoupledResistanceMath::mobilityMatrix(positions, radii, parallel)).selfadjointView<Eigen::Lower>();
        });
        peerOut.resize(3*n);
        auto storedProduct = [&] () {
            parallel(n, [&] (int begin, int end) {
                peerOut.segment(3*begin, 3*(end-begin)).noalias() = stored.middleCols(3*begin, 3*(end-begin)).transpose()*f;
            });
        };
        againstTiled(tiledProduct, storedProduct, n, pairs, blockSeconds, row, row.storedRatio, row.storedRatioSe, row.storedNs, row.storedNsSe);
    }
    if (std::isnan(row.tiledMs)) {
        vector<double> times, cpu;
        alternatingPairs(tiledProduct, tiledProduct, pairs/2+1, blockSeconds, times, times, &cpu, &cpu);
        meanAndErrorMs(times, row.tiledMs, row.tiledSe);
        nsPerPair(cpu, n, row.tiledNs, row.tiledNsSe);
    }
    return row;
}

void write(std::ofstream& csv, const Row& r) {
    printf("%7d %9.3f ± %6.3f %7.3f ± %5.3f %6.2f ± %4.2f %7.2f ± %5.2f %9.1f %6.2f ± %4.2f %7.2f ± %5.2f %9.1e\n", r.blobs, r.tiledMs, r.tiledSe,
           r.tiledNs, r.tiledNsSe, r.oldRatio, r.oldRatioSe, r.oldNs, r.oldNsSe, r.storedSetupMs, r.storedRatio, r.storedRatioSe, r.storedNs,
           r.storedNsSe, r.error);
    fflush(stdout);
    csv << r.blobs << "," << numThreads() << "," << r.tiledMs << "," << r.tiledSe << "," << 1e3/r.tiledMs << "," << r.tiledNs << "," << r.tiledNsSe
        << "," << r.oldRatio << "," << r.oldRatioSe << "," << r.oldNs << "," << r.oldNsSe << "," << r.storedSetupMs << "," << r.storedRatio << ","
        << r.storedRatioSe << "," << r.storedNs << "," << r.storedNsSe << "," << r.error << "\n";
    csv.flush();
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argv[1][0] == '-') {
        std::cerr << "usage: " << argv[0] << " results.csv [--geometry open|wall] [--precision double|single] [--sizes 100,300,1000,1350,3000,10000] [--old-max-blobs 10000] [--stored-max-blobs 1350]"
                     " [--pairs 5] [--block-seconds 0.3]" << std::endl;
        return 2;
    }
    vector<int> sizes = {100, 300, 1000, 1350, 3000, 10000};
    int oldMax = 10000, storedMax = HostBlobMobility::MaxStoredBlobs, pairs = 5;
    double blockSeconds = 0.3;
    bool wall = false, single = false;
    if (!readOptions(argc, argv, {{"--geometry", [&] (const char* v) { wall = (std::string(v) == "wall"); }},
                                  {"--precision", [&] (const char* v) { single = (std::string(v) == "single"); }},
                                  {"--sizes", [&] (const char* v) { sizes = parseList<int>(v); }},
                                  {"--old-max-blobs", [&] (const char* v) { oldMax = std::atoi(v); }},
                                  {"--stored-max-blobs", [&] (const char* v) { storedMax = std::atoi(v); }},
                                  {"--pairs", [&] (const char* v) { pairs = std::max(2, std::atoi(v)); }},
                                  {"--block-seconds", [&] (const char* v) { blockSeconds = std::atof(v); }}}))
        return 2;
    OpenMM::ThreadPool pool(numThreads());
    printf("%s product M f (tiled in %s precision), blobs of radius %g nm at volume fraction %g in a cube; %d thread(s); %d alternating pairs of %g s blocks\n",
           wall ? "Rotne-Prager-Blake (a no-slip wall a radius below the cube)" : "Open-space RPY", single ? "single" : "double", Radius, VolumeFraction, numThreads(), pairs, blockSeconds);
    printf("%7s %20s %15s %13s %15s %9s %13s %15s %9s\n", "blobs", "tiled ms", "ns/pair/core", "old/tiled", "old ns/pair", "M setup ms", "stored/tiled",
           "stored ns/pair", "error");
    std::ofstream csv(argv[1]);
    csv << "blobs,threads,tiled_ms,tiled_ms_se,tiled_products_per_s,tiled_ns_per_pair_core,tiled_ns_se,old_ratio,old_ratio_se,old_ns_per_pair_core,"
           "old_ns_se,stored_setup_ms,stored_ratio,stored_ratio_se,stored_ns_per_pair_core,stored_ns_se,relative_error\n";
    for (int n : sizes)
        write(csv, measure(n, wall, single, oldMax, storedMax, pairs, blockSeconds, pool));
    return 0;
}
