/*
 * The host step (platforms/reference/src/HostRigidLangevinStepKernel.h, in the Reference and CPU
 * libraries) is compiled twice, for x86-64-v3 (AVX2 and FMA) and for the baseline, and the
 * processor picks one when the library is loaded (GCC's target_clones). Every other test runs only
 * the clone this machine picks. This one compares the two: run natively (ctest TestCpuHostClones)
 * it records where the Lennard-Jones cluster's bodies are after 500 steps, on Reference and CPU, in
 * every scheme, without friction and with friction and noise; run with RIGIDLANGEVIN_HOST_CLONES=compare
 * under QEMU's user-mode emulator as a processor without AVX2 (ctest TestCpuHostClonesBaseline),
 * which makes the baseline clone picked, it steps the same runs and compares.
 *
 * Tolerance. The clones differ only in rounding: the x86-64-v3 clone fuses a*b+c into one
 * operation (a rounding of ~1e-16 relative less), and the random numbers are the same (one seed,
 * one generator). Rounding differences grow with the cluster's chaos, so each recorded run also
 * records how far its own trajectory moves from a start displaced by 1e-12 nm (2e-12 to 5e-11 nm
 * after 500 steps); the baseline must stay within ten times that, with a floor of 1e-11 nm. Measured
 * on an AVX2 machine, the baseline clone ended 3e-14 to 4e-12 nm from the native one; a force 1e-6
 * too large in the baseline clone alone ended 5e-7 to 1e-5 nm away, and fails.
 */
#include "CpuTests.h"
#include "LennardJonesCluster.h"
#include <gtest/gtest.h>
#include <fstream>
#include <iomanip>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;

namespace {

const int NumSteps = 500;
// Written by the native run and read by the emulated one, in ctest's working directory (both tests
// are in this directory's CMakeLists.txt).
const char* RecordFile = "host_clones_record.txt";

/** The clone GCC's resolver picks on this processor (the same test as target_clones' "arch=x86-64-v3"). */
std::string pickedClone() {
    __builtin_cpu_init();
    return __builtin_cpu_supports("x86-64-v3") ? "x86-64-v3" : "baseline";
}

struct CloneRun {
    std::string platform;
    RigidLangevinIntegrator::Scheme scheme;
    double viscosity;
    std::string name() const {
        return platform+"_scheme"+std::to_string(scheme)+"_viscosity"+std::to_string((int) viscosity);
    }
};

std::vector<CloneRun> runs() {
    std::vector<CloneRun> all;
    for (const char* platform : {"Reference", "CPU"})
        for (RigidLangevinIntegrator::Scheme scheme : {RigidLangevinIntegrator::ExactFlow, RigidLangevinIntegrator::BAOAB, RigidLangevinIntegrator::Original})
            for (double viscosity : {0.0, 30.0})
                all.push_back({platform, scheme, viscosity});
    return all;
}

/** Positions after NumSteps steps of the run, from the start displaced by displacement. */
std::vector<Vec3> trajectoryEnd(const CloneRun& run, double displacement = 0) {
    PlatformConfig config;
    config.platform = run.platform;
    config.precision = "double";
    return clusterTrajectoryEnd(config, run.scheme, 300, run.viscosity, LennardJonesCluster::PairBonds, NumSteps, displacement);
}

struct Recorded {
    double spread;
    std::vector<Vec3> positions;
};

void record() {
    std::ofstream out(RecordFile);
    out << std::setprecision(17) << "clone " << pickedClone() << "\n";
    for (const CloneRun& run : runs()) {
        std::vector<Vec3> end = trajectoryEnd(run);
        double spread = maxDistance(end, trajectoryEnd(run, 1e-12));
        out << run.name() << " " << spread << " " << end.size() << "\n";
        for (const Vec3& p : end)
            out << p[0] << " " << p[1] << " " << p[2] << "\n";
        std::cout << run.name() << ": recorded; a start 1e-12 nm away ends " << spread << " nm away" << std::endl;
    }
    ASSERT_TRUE(out.good()) << "could not write " << RecordFile;
}

std::map<std::string, Recorded> readRecord(std::string& clone) {
    std::ifstream in(RecordFile);
    std::map<std::string, Recorded> recorded;
    std::string word;
    if (!(in >> word >> clone) || word != "clone")
        return recorded;
    std::string name;
    Recorded r;
    int count;
    while (in >> name >> r.spread >> count) {
        r.positions.resize(count);
        for (Vec3& p : r.positions)
            in >> p[0] >> p[1] >> p[2];
        recorded[name] = r;
    }
    return recorded;
}

} // namespace

TEST(HostClones, BaselineFollowsTheNativeClone) {
    if (!emulatingBaselineBuilds()) {
        record();
        return;
    }
    ASSERT_EQ(pickedClone(), "baseline") << "the emulated processor offers x86-64-v3, so this run would compare a clone with itself";
    std::string recordedClone;
    std::map<std::string, Recorded> recorded = readRecord(recordedClone);
    ASSERT_EQ(recorded.size(), runs().size()) << RecordFile << " is missing or incomplete: run the native test (TestCpuHostClones) first";
    if (recordedClone != "x86-64-v3") {
        // This machine picks the baseline itself: every other test has run it, and there is nothing to compare.
        std::cout << "Host clones comparison not possible: skipped (this processor picks the baseline clone natively)" << std::endl;
        return;
    }
    for (const CloneRun& run : runs()) {
        const Recorded& expected = recorded[run.name()];
        double distance = maxDistance(expected.positions, trajectoryEnd(run));
        double tolerance = std::max(10*expected.spread, 1e-11);
        std::cout << run.name() << ": baseline clone " << distance << " nm from the x86-64-v3 clone (tolerance " << tolerance << " nm)" << std::endl;
        EXPECT_LT(distance, tolerance) << run.name();
    }
}
