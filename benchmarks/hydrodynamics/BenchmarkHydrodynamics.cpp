// Times the resistance tensor of rough-shell bead models of a bent, banana-like molecule at about
// 500, 1000, 2266 and 5000 beads, against the source document's procedure (B inverted explicitly
// with Eigen's inverse(), then the 3x3 blocks of B^-1 summed). Each measurement runs in a child
// process of its own, so that its peak memory (getrusage) is its own.
//
//   benchmark_hydrodynamics results.csv [--sizes 500,1000,2266,5000] [--peer-max-beads 2266]
//                           [--generic-max-beads 2266] [--repeat 1]
//
// With --repeat R each measurement is made R times and the fastest kept: on a shared machine the
// minimum is the time the work itself takes.
//
// Columns: beads; seconds and peak memory of ResistanceTensor::beads() (kernel chosen as in
// production); the same for the peer; speedup = peer seconds / seconds; the largest difference
// between the two tensors relative to their largest element; seconds of the baseline (non-AVX2)
// build of the kernel where asked, to show what the AVX2 build is worth.

#include "ResistanceTensor.h"
#include "internal/BeadHydrodynamics.h"
#include "internal/RotnePragerYamakawa.h"
#include <Eigen/Dense>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

using namespace RigidLangevinPlugin;
using OpenMM::Vec3;
using std::string;
using std::vector;

namespace {

typedef Eigen::Matrix<double, 6, 6> Matrix6;

/** What one child process reports. */
struct Measurement {
    double seconds = NAN;
    double peakMiB = NAN;
    Matrix6 tensor = Matrix6::Constant(NAN);
};

/**
 * The molecule: 11 overlapping atoms of radius 0.3 nm on an arc of radius 2 nm spanning 120
 * degrees, with a slight twist out of plane so that it has no symmetry at all.
 */
void banana(vector<Vec3>& centres, vector<double>& radii) {
    for (int i = 0; i < 11; i++) {
        double angle = (-60+12*i)*M_PI/180;
        centres.push_back(Vec3(2*std::sin(angle), 2*(1-std::cos(angle)), 0.15*std::sin(2*angle)));
        radii.push_back(0.3);
    }
}

/** The shell bead radius whose tiling has the bead count closest to target. */
double beadRadiusFor(int target, const vector<Vec3>& centres, const vector<double>& radii) {
    double low = 1e-3, high = 0.5;  // counts decrease with the radius
    double best = low;
    int bestCount = -1;
    for (int iteration = 0; iteration < 60; iteration++) {
        double sigma = std::sqrt(low*high);
        int count = ResistanceTensor::roughShellBeads(centres, radii, sigma).size();
        if (bestCount < 0 || std::abs(count-target) < std::abs(bestCount-target)) {
            best = sigma;
            bestCount = count;
        }
        if (count == target)
            break;
        if (count > target)
            low = sigma;
        else
            high = sigma;
    }
    return best;
}

/**
 * The peer: the source's procedure. B in full (both triangles) with the same generalised RPY
 * blocks, C = B.inverse(), then Xtt = sum C_ij, Xrt = sum U_i C_ij, Xrr = -sum U_i C_ij U_j.
 */
Matrix6 explicitInverse(const vector<Vec3>& beads, double sigma, const Vec3& origin) {
    const int n = beads.size();
    Eigen::MatrixXd b(3*n, 3*n);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double block[9];
            if (i == j) {
                b.block<3, 3>(3*i, 3*i) = RotnePragerYamakawa::selfMobility(sigma)*Eigen::Matrix3d::Identity();
                continue;
            }
            Vec3 d = beads[j]-beads[i];
            RotnePragerYamakawa::mobilityBlock(d[0], d[1], d[2], sigma, sigma, block);
            b.block<3, 3>(3*i, 3*j) = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor> >(block);
        }
    Eigen::MatrixXd c = b.inverse();
    vector<Eigen::Matrix3d> u(n);
    for (int i = 0; i < n; i++) {
        Vec3 r = beads[i]-origin;
        u[i] << 0, -r[2], r[1], r[2], 0, -r[0], -r[1], r[0], 0;
    }
    Matrix6 xi = Matrix6::Zero();
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            Eigen::Matrix3d cij = c.block<3, 3>(3*i, 3*j);
            xi.block<3, 3>(0, 0) += cij;
            xi.block<3, 3>(3, 0) += u[i]*cij;
            xi.block<3, 3>(3, 3) -= u[i]*cij*u[j];
        }
    xi.block<3, 3>(0, 3) = xi.block<3, 3>(3, 0).transpose();
    return xi;
}

/** Run work in a child process and time it there; its peak RSS is the child's own. */
Measurement once(const std::function<Matrix6()>& work) {
    int pipeEnds[2];
    if (pipe(pipeEnds) != 0)
        return Measurement();
    pid_t pid = fork();
    if (pid == 0) {
        close(pipeEnds[0]);
        Measurement m;
        auto start = std::chrono::steady_clock::now();
        m.tensor = work();
        m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now()-start).count();
        struct rusage usage;
        getrusage(RUSAGE_SELF, &usage);
        m.peakMiB = usage.ru_maxrss/1024.0;  // Linux reports KiB
        if (write(pipeEnds[1], &m, sizeof(m)) != sizeof(m))
            _exit(1);
        _exit(0);
    }
    close(pipeEnds[1]);
    Measurement m;
    ssize_t got = read(pipeEnds[0], &m, sizeof(m));
    close(pipeEnds[0]);
    int status;
    waitpid(pid, &status, 0);
    if (got != sizeof(m))
        return Measurement();
    return m;
}

/** The fastest of repeat runs of work, each in a child process of its own. */
Measurement inChild(const std::function<Matrix6()>& work, int repeat) {
    Measurement best;
    for (int i = 0; i < repeat; i++) {
        Measurement m = once(work);
        if (std::isnan(best.seconds) || m.seconds < best.seconds)
            best = m;
    }
    return best;
}

vector<int> parseSizes(const string& text) {
    vector<int> sizes;
    std::stringstream stream(text);
    string item;
    while (std::getline(stream, item, ','))
        sizes.push_back(std::stoi(item));
    return sizes;
}

string format(double value, const char* pattern) {
    if (std::isnan(value))
        return "-";
    char buffer[64];
    snprintf(buffer, sizeof(buffer), pattern, value);
    return buffer;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 2 || argv[1][0] == '-') {
        std::cerr << "usage: " << argv[0] << " results.csv [--sizes 500,1000,2266,5000] [--peer-max-beads 2266] [--generic-max-beads 2266] [--repeat 1]" << std::endl;
        return 2;
    }
    string csvPath = argv[1];
    vector<int> sizes = {500, 1000, 2266, 5000};
    int peerMax = 2266, genericMax = 2266, repeat = 1;
    for (int i = 2; i+1 < argc; i += 2) {
        string option = argv[i];
        if (option == "--sizes")
            sizes = parseSizes(argv[i+1]);
        else if (option == "--peer-max-beads")
            peerMax = std::atoi(argv[i+1]);
        else if (option == "--generic-max-beads")
            genericMax = std::atoi(argv[i+1]);
        else if (option == "--repeat")
            repeat = std::max(1, std::atoi(argv[i+1]));
        else {
            std::cerr << "unknown option " << option << std::endl;
            return 2;
        }
    }
#ifdef __x86_64__
    __builtin_cpu_init();
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) {
        std::cerr << "this benchmark is built with AVX2/FMA (so that the peer uses them too) and this CPU lacks them" << std::endl;
        return 1;
    }
#endif
    int threads = BeadHydrodynamics::getNumThreads();
    bool avx2 = BeadHydrodynamics::isAVX2KernelAvailable();
    printf("Resistance tensors of rough shells of a banana-like molecule; %d thread(s); kernel: %s; peer: B.inverse() compiled with the same flags; fastest of %d\n",
           threads, avx2 ? "AVX2/FMA" : "baseline", repeat);
    printf("%7s %10s %10s %12s %12s %8s %10s %12s\n", "beads", "seconds", "peak MiB", "peer s", "peer MiB", "speedup", "max diff", "baseline s");
    std::ofstream csv(csvPath);
    csv << "beads,seconds,peak_mib,peer_seconds,peer_peak_mib,speedup,max_relative_difference,baseline_kernel_seconds,threads,kernel\n";

    vector<Vec3> centres;
    vector<double> radii;
    banana(centres, radii);
    for (int target : sizes) {
        double sigma = beadRadiusFor(target, centres, radii);
        vector<Vec3> beads = ResistanceTensor::roughShellBeads(centres, radii, sigma);
        vector<double> beadRadii(beads.size(), sigma);
        Vec3 origin = centres[5];
        Measurement ours = inChild([&]() {
            return BeadHydrodynamics::resistance("benchmark", beads, beadRadii, origin);
        }, repeat);
        Measurement peer, baseline;
        if (target <= peerMax)
            peer = inChild([&]() { return explicitInverse(beads, sigma, origin); }, repeat);
        if (target <= genericMax && avx2)
            baseline = inChild([&]() {
                return BeadHydrodynamics::resistance("benchmark", beads, beadRadii, origin, BeadHydrodynamics::GenericKernel);
            }, repeat);
        double speedup = peer.seconds/ours.seconds;
        double difference = (peer.tensor-ours.tensor).cwiseAbs().maxCoeff()/ours.tensor.cwiseAbs().maxCoeff();
        printf("%7d %10s %10s %12s %12s %8s %10s %12s\n", (int) beads.size(), format(ours.seconds, "%.2f").c_str(), format(ours.peakMiB, "%.0f").c_str(),
               format(peer.seconds, "%.2f").c_str(), format(peer.peakMiB, "%.0f").c_str(), format(speedup, "%.1f").c_str(),
               format(difference, "%.1e").c_str(), format(baseline.seconds, "%.2f").c_str());
        fflush(stdout);
        csv << beads.size() << "," << ours.seconds << "," << ours.peakMiB << "," << peer.seconds << "," << peer.peakMiB << ","
            << speedup << "," << difference << "," << baseline.seconds << "," << threads << "," << (avx2 ? "avx2" : "baseline") << "\n";
    }
    return 0;
}
