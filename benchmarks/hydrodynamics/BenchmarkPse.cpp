// Times the positively split Ewald mobility (PositivelySplitEwald): one product M f and one noise
// sample of covariance M, for 1e2 to 1e5 blobs of radius 1 nm at 5% volume fraction in a cube, at
// two tolerances, against its peer, the dense Ewald sum (PeriodicRotnePragerYamakawa, stored once
// and applied as a matrix-vector product, its noise by Lanczos: what HostBlobMobility does in a
// periodic box today), where that fits in memory.
//
//   benchmark_pse results.csv [--sizes 100,1000,10000,100000] [--tolerances 1e-3,1e-6]
//                 [--peer-max-blobs 2000] [--pairs 5] [--block-seconds 0.3]
//
// Each (blobs, tolerance) runs in a child process of its own, so that its peak memory (getrusage)
// is its own: first the PSE alone (its setup, products and noise, its peak resident memory), then,
// where the peer fits, the PSE and the dense sum alive together, timed in alternating pairs of
// blocks (the order reversed every other pair) and compared pair by pair: the ratio's standard
// error is over the pairs, each of which saw one machine load. Blocks hold as many calls as fill
// --block-seconds. OPENMM_CPU_THREADS sets the threads (default: all cores).

#include "internal/KrylovSolvers.h"
#include "internal/PeriodicRotnePragerYamakawa.h"
#include "internal/PositivelySplitEwald.h"
#include "openmm/internal/ThreadPool.h"
#include "BenchmarkTiming.h"
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

using namespace RigidLangevinPlugin;
using namespace BenchmarkTiming;
using OpenMM::Vec3;
using std::string;
using std::vector;

namespace {

const double Radius = 1.0, VolumeFraction = 0.05;

/** What one child reports (plain data, through a pipe). */
struct Row {
    int blobs = 0, grid = 0, support = 0, lanczos = 0;
    double tolerance = NAN, xi = NAN, pairs = NAN, setupSeconds = NAN, productMs = NAN, productSe = NAN, noiseMs = NAN, noiseSe = NAN,
           productCpuMs = NAN, productCpuSe = NAN, noiseCpuMs = NAN, noiseCpuSe = NAN, pseMiB = NAN,
           peakMiB = NAN, peerSetupSeconds = NAN, peerProductMs = NAN, productRatio = NAN, productRatioSe = NAN, peerNoiseMs = NAN,
           noiseRatio = NAN, noiseRatioSe = NAN, peerPeakMiB = NAN, error = NAN;
};

struct Scene {
    vector<Vec3> positions;
    vector<double> radii;
    Vec3 box[3];
};

Scene makeScene(int n) {
    Scene scene;
    const double side = std::cbrt(n*4*M_PI/3*Radius*Radius*Radius/VolumeFraction);
    scene.box[0] = Vec3(side, 0, 0);
    scene.box[1] = Vec3(0, side, 0);
    scene.box[2] = Vec3(0, 0, side);
    std::mt19937 random(n);
    std::uniform_real_distribution<double> uniform(0, side);
    for (int i = 0; i < n; i++) {
        scene.positions.push_back(Vec3(uniform(random), uniform(random), uniform(random)));
        scene.radii.push_back(Radius);
    }
    return scene;
}

/** The PSE alone: setup, product, noise, memory. */
Row measurePse(int n, double tolerance, int pairs, double blockSeconds) {
    Row row;
    Scene scene = makeScene(n);
    OpenMM::ThreadPool pool(numThreads());
    PositivelySplitEwald pse(tolerance, 0, poolParallel(pool));
    row.blobs = n;
    row.tolerance = tolerance;
    row.setupSeconds = seconds([&] () { pse.setBlobs(scene.positions, scene.radii, scene.box); });
    int grid[3];
    pse.getGridSize(grid);
    row.grid = grid[0];
    row.support = pse.getSupport();
    row.xi = pse.getSplitting();
    row.pairs = pse.getNumPairs();
    row.pseMiB = pse.getMemoryBytes()/1048576;
    std::mt19937_64 random(1);
    std::normal_distribution<double> gaussian;
    Eigen::VectorXd f = Eigen::VectorXd::Random(3*n), u;
    auto product = [&] () { pse.multiply(f, u); };
    auto noise = [&] () { row.lanczos = pse.sampleNoise([&] () { return gaussian(random); }, u, tolerance, 500).iterations; };
    vector<double> products, noises, productsCpu, noisesCpu;
    alternatingPairs(product, noise, pairs, blockSeconds, products, noises, &productsCpu, &noisesCpu);
    meanAndErrorMs(products, row.productMs, row.productSe);
    meanAndErrorMs(noises, row.noiseMs, row.noiseSe);
    meanAndErrorMs(productsCpu, row.productCpuMs, row.productCpuSe);
    meanAndErrorMs(noisesCpu, row.noiseCpuMs, row.noiseCpuSe);
    row.peakMiB = peakMiB();
    return row;
}

/** The PSE against the dense sum, both alive: ratios dense/PSE pair by pair, and the PSE's error. */
void measurePeer(Row& row, int pairs, double blockSeconds) {
    Scene scene = makeScene(row.blobs);
    OpenMM::ThreadPool pool(numThreads());
    KrylovSolvers::ParallelFor parallel = poolParallel(pool);
    PositivelySplitEwald pse(row.tolerance, 0, parallel);
    pse.setBlobs(scene.positions, scene.radii, scene.box);
    Eigen::MatrixXd dense;
    row.peerSetupSeconds = seconds([&] () { dense = PeriodicRotnePragerYamakawa(scene.box).mobility(scene.positions, scene.radii, parallel); });
    const int n = row.blobs;
    Eigen::VectorXd f = Eigen::VectorXd::Random(3*n), u, v;
    pse.multiply(f, u);
    v = dense*f;
    row.error = (u-v).norm()/v.norm();
    std::mt19937_64 random(1);
    std::normal_distribution<double> gaussian;
    // The peer's product shares its rows out as HostBlobMobility's stored product does (Eigen's
    // product on the calling thread there; here the same, for like with like).
    KrylovSolvers::Operator denseProduct = [&] (const Eigen::VectorXd& in, Eigen::VectorXd& out) { out.noalias() = dense*in; };
    auto pseProduct = [&] () { pse.multiply(f, u); };
    auto peerProduct = [&] () { denseProduct(f, v); };
    vector<double> timesPse, timesPeer;
    alternatingPairs(pseProduct, peerProduct, pairs, blockSeconds, timesPse, timesPeer);
    pairRatio(timesPse, timesPeer, row.productRatio, row.productRatioSe);
    double mean, error;
    meanAndError(timesPeer, mean, error);
    row.peerProductMs = 1e3*mean;
    auto pseNoise = [&] () { pse.sampleNoise([&] () { return gaussian(random); }, u, row.tolerance, 500); };
    auto peerNoise = [&] () {
        Eigen::VectorXd w(3*n);
        for (int i = 0; i < 3*n; i++)
            w[i] = gaussian(random);
        KrylovSolvers::lanczosSquareRoot(denseProduct, w, v, row.tolerance, 500);
    };
    timesPse.clear();
    timesPeer.clear();
    alternatingPairs(pseNoise, peerNoise, pairs, blockSeconds, timesPse, timesPeer);
    pairRatio(timesPse, timesPeer, row.noiseRatio, row.noiseRatioSe);
    meanAndError(timesPeer, mean, error);
    row.peerNoiseMs = 1e3*mean;
    row.peerPeakMiB = peakMiB();
}

/** Run work in a child process (its peak memory its own) and return the row it fills. */
Row inChild(const std::function<void (Row&)>& work, const Row& start) {
    int pipeEnds[2];
    if (pipe(pipeEnds) != 0)
        return start;
    pid_t pid = fork();
    if (pid == 0) {
        close(pipeEnds[0]);
        Row row = start;
        try {
            work(row);
        }
        catch (const std::exception& e) {
            std::cerr << "failed: " << e.what() << std::endl;
        }
        if (write(pipeEnds[1], &row, sizeof(row)) != sizeof(row))
            _exit(1);
        _exit(0);
    }
    close(pipeEnds[1]);
    Row row = start;
    ssize_t got = read(pipeEnds[0], &row, sizeof(row));
    close(pipeEnds[0]);
    int status;
    waitpid(pid, &status, 0);
    return (got == sizeof(row) ? row : start);
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argv[1][0] == '-') {
        std::cerr << "usage: " << argv[0] << " results.csv [--sizes 100,1000,10000,100000] [--tolerances 1e-3,1e-6] [--peer-max-blobs 2000]"
                     " [--pairs 5] [--block-seconds 0.3]" << std::endl;
        return 2;
    }
    vector<int> sizes = {100, 1000, 10000, 100000};
    vector<double> tolerances = {1e-3, 1e-6};
    int peerMax = 2000, pairs = 5;
    double blockSeconds = 0.3;
    if (!readOptions(argc, argv, {{"--sizes", [&] (const char* v) { sizes = parseList<int>(v); }},
                                  {"--tolerances", [&] (const char* v) { tolerances = parseList<double>(v); }},
                                  {"--peer-max-blobs", [&] (const char* v) { peerMax = std::atoi(v); }},
                                  {"--pairs", [&] (const char* v) { pairs = std::max(2, std::atoi(v)); }},
                                  {"--block-seconds", [&] (const char* v) { blockSeconds = std::atof(v); }}}))
        return 2;
    printf("Positively split Ewald mobility, blobs of radius %g nm at volume fraction %g in a cube; %d thread(s); %d alternating pairs of %g s blocks\n",
           Radius, VolumeFraction, numThreads(), pairs, blockSeconds);
    printf("%7s %7s %6s %4s %3s %10s %8s %14s %8s %14s %8s %9s %9s %9s %16s %16s %9s\n", "blobs", "epsilon", "xi", "grid", "P", "pairs", "setup s",
           "product ms", "cpu ms", "noise ms", "cpu ms", "PSE MiB", "peak MiB", "peer ms", "dense/PSE prod", "dense/PSE noise", "error");
    std::ofstream csv(argv[1]);
    csv << "blobs,epsilon,threads,xi,grid,support,pairs,setup_s,product_ms,product_ms_se,products_per_s,noise_ms,noise_ms_se,product_cpu_ms,product_cpu_ms_se,noise_cpu_ms,noise_cpu_ms_se,lanczos_iterations,"
           "pse_mib,peak_mib,peer_setup_s,peer_product_ms,product_ratio,product_ratio_se,peer_noise_ms,noise_ratio,noise_ratio_se,peer_peak_mib,"
           "relative_error\n";
    for (int n : sizes)
        for (double tolerance : tolerances) {
            Row start;
            start.blobs = n;
            start.tolerance = tolerance;
            Row row = inChild([&] (Row& r) { r = measurePse(n, tolerance, pairs, blockSeconds); }, start);
            if (n <= peerMax) {
                Row withPeer = inChild([&] (Row& r) { measurePeer(r, pairs, blockSeconds); }, row);
                row = withPeer;
            }
            printf("%7d %7.0e %6.3f %4d %3d %10.0f %8.3f %7.3f ± %5.3f %8.3f %7.2f ± %5.2f %8.2f %9.1f %9.1f %9.3f %8.2f ± %5.2f %8.2f ± %5.2f %9.1e\n",
                   n, tolerance, row.xi, row.grid, row.support, row.pairs, row.setupSeconds, row.productMs, row.productSe, row.productCpuMs, row.noiseMs,
                   row.noiseSe, row.noiseCpuMs, row.pseMiB,
                   row.peakMiB, row.peerProductMs, row.productRatio, row.productRatioSe, row.noiseRatio, row.noiseRatioSe, row.error);
            fflush(stdout);
            csv << n << "," << tolerance << "," << numThreads() << "," << row.xi << "," << row.grid << "," << row.support << "," << row.pairs << ","
                << row.setupSeconds << "," << row.productMs << "," << row.productSe << "," << 1e3/row.productMs << "," << row.noiseMs << ","
                << row.noiseSe << "," << row.productCpuMs << "," << row.productCpuSe << "," << row.noiseCpuMs << "," << row.noiseCpuSe << "," << row.lanczos << "," << row.pseMiB << "," << row.peakMiB << "," << row.peerSetupSeconds << ","
                << row.peerProductMs << "," << row.productRatio << "," << row.productRatioSe << "," << row.peerNoiseMs << "," << row.noiseRatio << ","
                << row.noiseRatioSe << "," << row.peerPeakMiB << "," << row.error << "\n";
            csv.flush();
        }
    return 0;
}
