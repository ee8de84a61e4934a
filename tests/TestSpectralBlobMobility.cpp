/*
 * SpectralBlobMobility, the integrators' spectral products in a periodic box: what the positively
 * split Ewald sum cannot do is refused naming the integrator's settings (a tolerance below what it
 * reaches, a memory budget exceeded before anything large is allocated, a box too narrow for its
 * blobs), and its products are the PSE's at epsilon = the hydrodynamic tolerance.
 */
#include "ReferenceTests.h"
#include "internal/PeriodicRotnePragerYamakawa.h"
#include "internal/SpectralBlobMobility.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>
#include <random>
#include <string>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using std::vector;

namespace {

/** count blobs of radius 0.5 nm at random in a cube of side (nm), whose vectors are box. */
void randomBlobs(int count, double side, vector<Vec3>& positions, vector<double>& radii, Vec3 box[3]) {
    std::mt19937 random(5);
    std::uniform_real_distribution<double> uniform(0, side);
    positions.clear();
    for (int i = 0; i < count; i++)
        positions.push_back(Vec3(uniform(random), uniform(random), uniform(random)));
    radii.assign(count, 0.5);
    box[0] = Vec3(side, 0, 0);
    box[1] = Vec3(0, side, 0);
    box[2] = Vec3(0, 0, side);
}

/** The message of what call throws, or "" if it does not throw an OpenMMException. */
std::string refusal(const std::function<void ()>& call) {
    try {
        call();
    }
    catch (const OpenMMException& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(SpectralBlobMobility, ProductsAreThePositivelySplitEwaldSumsAtTheTolerance) {
    // Against the dense Ewald sum: within the tolerance of |M f| (measured 0.3 epsilon at most), and
    // a tolerance 1e4 times looser is visibly looser (the epsilon does follow the tolerance).
    vector<Vec3> positions;
    vector<double> radii;
    Vec3 box[3];
    randomBlobs(60, 12.0, positions, radii, box);
    Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(180, -1, 1), out;
    Eigen::MatrixXd dense = PeriodicRotnePragerYamakawa(box).mobility(positions, radii);
    Eigen::VectorXd exact = dense.selfadjointView<Eigen::Lower>()*f;
    SpectralBlobMobility spectral("RigidLangevinIntegrator", KrylovSolvers::sequentially);
    double errors[2];
    for (int i = 0; i < 2; i++) {
        spectral.setTolerance(i == 0 ? 1e-8 : 1e-4);
        spectral.setBlobs(positions, radii, box);
        spectral.multiply(f, out);
        errors[i] = (out-exact).norm()/exact.norm();
    }
    EXPECT_LT(errors[0], 1e-8);
    EXPECT_GT(errors[1], 100*errors[0]);
    EXPECT_LT(errors[1], 1e-4);
}

TEST(SpectralBlobMobility, RefusalsNameTheIntegratorsSettings) {
    vector<Vec3> positions;
    vector<double> radii;
    Vec3 box[3];
    randomBlobs(2000, 40.0, positions, radii, box);
    SpectralBlobMobility spectral("RigidBrownianIntegrator", KrylovSolvers::sequentially);
    spectral.setMemoryBudget(1 << 20);
    std::string message = refusal([&] { spectral.setTolerance(1e-11); });
    EXPECT_NE(message.find("RigidBrownianIntegrator"), std::string::npos) << message;
    EXPECT_NE(message.find("setHydrodynamicTolerance() with at least 1e-10"), std::string::npos) << message;
    // 2000 blobs need some 20 MiB: over a budget of 1 MiB, refused before the grid is allocated.
    spectral.setTolerance(1e-6);
    message = refusal([&] { spectral.setBlobs(positions, radii, box); });
    EXPECT_NE(message.find("more than the memory budget of 0.0009766 GiB"), std::string::npos) << message;
    EXPECT_NE(message.find("raise setHydrodynamicMemoryBudget()"), std::string::npos) << message;
    EXPECT_NE(message.find("loosen setHydrodynamicTolerance()"), std::string::npos) << message;
    // Blobs of radius 0.5 nm in a box 1.9 nm wide: no real-space cutoff fits.
    randomBlobs(4, 1.9, positions, radii, box);
    message = refusal([&] { spectral.setBlobs(positions, radii, box); });
    EXPECT_NE(message.find("too small for blobs of radius 0.5 nm"), std::string::npos) << message;
    EXPECT_NE(message.find("a bigger box"), std::string::npos) << message;
}
