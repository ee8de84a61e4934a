/*
 * SpectralBlobMobility, the integrators' spectral products in a periodic box: what the positively
 * split Ewald sum cannot do is refused naming the integrator's settings (a tolerance below what it
 * reaches, a memory budget exceeded before anything large is allocated, a box too narrow for its
 * blobs), and its products are the PSE's at epsilon = the hydrodynamic tolerance. Through
 * RigidBrownianIntegrator, its noise (the PSE's own, exact through the split) has the covariance of
 * the dense Ewald sum's M, eigenmode by eigenmode.
 */
#include "ReferenceTests.h"
#include "RigidBrownianIntegrator.h"
#include "internal/PeriodicRotnePragerYamakawa.h"
#include "internal/SpectralBlobMobility.h"
#include "openmm/Context.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <Eigen/Eigenvalues>
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
    EXPECT_EQ(message.find("KrylovSolver"), std::string::npos) << message;  // the dense sum needs more memory still
    // Blobs of radius 0.5 nm in a box 1.9 nm wide: no real-space cutoff fits, and no setting but the box helps.
    randomBlobs(4, 1.9, positions, radii, box);
    message = refusal([&] { spectral.setBlobs(positions, radii, box); });
    EXPECT_NE(message.find("too small for blobs of radius 0.5 nm"), std::string::npos) << message;
    EXPECT_NE(message.find("a bigger box"), std::string::npos) << message;
    EXPECT_EQ(message.find("setHydrodynamicMemoryBudget"), std::string::npos) << message;
    EXPECT_EQ(message.find("setHydrodynamicTolerance"), std::string::npos) << message;
    // Five distinct radii where the PSE takes four: the radii or the dense solver, not the budget.
    randomBlobs(60, 12.0, positions, radii, box);
    for (int i = 0; i < 60; i++)
        radii[i] = 0.3+0.05*(i%5);
    message = refusal([&] { spectral.setBlobs(positions, radii, box); });
    EXPECT_NE(message.find("5 distinct radii"), std::string::npos) << message;
    EXPECT_NE(message.find("at most 4 distinct radii (setParticleRadius(), setBodyBlobs())"), std::string::npos) << message;
    EXPECT_NE(message.find("setHydrodynamicSolver(KrylovSolver)"), std::string::npos) << message;
    EXPECT_EQ(message.find("setHydrodynamicMemoryBudget"), std::string::npos) << message;
}

namespace {

/** count spheres of radius at random without overlap (nearest image) in a cube of side. */
vector<Vec3> separatedSpheres(int count, double radius, double side) {
    std::mt19937 random(3);
    std::uniform_real_distribution<double> uniform(0, side);
    vector<Vec3> centres;
    while ((int) centres.size() < count) {
        Vec3 p(uniform(random), uniform(random), uniform(random));
        bool apart = true;
        for (const Vec3& q : centres) {
            Vec3 d = p-q;
            for (int k = 0; k < 3; k++)
                d[k] -= side*std::round(d[k]/side);
            apart = apart && d.dot(d) >= 4*radius*radius;
        }
        if (apart)
            centres.push_back(p);
    }
    return centres;
}

} // namespace

TEST(SpectralBlobMobility, BrownianNoiseThroughTheSplitHasTheDenseEwaldCovariance) {
    // 100 one-blob spheres (radius 0.5 nm, 5% volume fraction, no forces), 200 steps of
    // RigidBrownianIntegrator with the spectral solver, each from the same positions: the
    // displacement of the spheres (their blobs) has covariance (2 kT h/viscosity) M, M the dense
    // Ewald sum (the stochastic drift adds nothing here: periodic RPY is divergence-free). Projected
    // on each eigenvector of M and scaled by its eigenvalue, every mode's variance is 1: checked on
    // the softest and the stiffest third of the modes (the collective flows and the
    // near-contact ones), each about 1% in standard error (measured 1.011 and 1.012, each +- 0.009).
    // A noise 5% too strong gave 1.062 and 1.063 (fails by six errors), its wave part left out 0.86
    // and 0.41.
    const int count = 100, steps = 200;
    const double radius = 0.5, viscosity = 1.0, h = 0.002, temperature = 300;
    const double side = std::cbrt(count*4*M_PI/3*radius*radius*radius/0.05);
    const vector<Vec3> centres = separatedSpheres(count, radius, side);
    System system;
    Vec3 box[3] = {Vec3(side, 0, 0), Vec3(0, side, 0), Vec3(0, 0, side)};
    system.setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    CustomNonbondedForce* periodic = new CustomNonbondedForce("0");
    periodic->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    periodic->setCutoffDistance(1.0);
    system.addForce(periodic);
    RigidBrownianIntegrator integrator(temperature, viscosity, h);
    integrator.setHydrodynamicInteractions(true);
    integrator.setHydrodynamicSolver(RigidBrownianIntegrator::SpectralSolver);
    integrator.setHydrodynamicTolerance(1e-4);
    integrator.setRandomNumberSeed(11);
    for (int i = 0; i < count; i++) {
        system.addParticle(1.0);
        periodic->addParticle();
        integrator.addRigidBody({i});
        integrator.setParticleRadius(i, radius);
    }
    Context context(system, integrator, Platform::getPlatformByName("Reference"));
    Eigen::MatrixXd dense = PeriodicRotnePragerYamakawa(box).mobility(centres, vector<double>(count, radius));
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> modes(dense.selfadjointView<Eigen::Lower>());
    const Eigen::VectorXd scale = (2*BOLTZ*temperature*h/viscosity*modes.eigenvalues()).cwiseSqrt();
    const int third = count;  // 3 count modes: a third is count of them
    vector<double> soft, stiff;
    for (int s = 0; s < steps; s++) {
        context.setPositions(centres);
        integrator.step(1);
        const vector<Vec3> moved = context.getState(State::Positions).getPositions();
        Eigen::VectorXd d(3*count);
        for (int i = 0; i < count; i++)
            for (int k = 0; k < 3; k++)
                d[3*i+k] = moved[i][k]-centres[i][k]-side*std::round((moved[i][k]-centres[i][k])/side);
        const Eigen::VectorXd y = (modes.eigenvectors().transpose()*d).cwiseQuotient(scale);
        soft.push_back(y.head(third).squaredNorm()/third);
        stiff.push_back(y.tail(third).squaredNorm()/third);
    }
    EXPECT_GT(integrator.getKrylovIterations()[0], 0);
    for (const vector<double>* group : {&soft, &stiff}) {
        double mean = 0, square = 0;
        for (double v : *group) {
            mean += v/steps;
            square += v*v/steps;
        }
        const double error = std::sqrt((square-mean*mean)/(steps-1));
        std::cout << (group == &soft ? "softest" : "stiffest") << " third of the modes: variance " << mean << " +- " << error << std::endl;
        EXPECT_LT(error, 0.0125);
        EXPECT_NEAR(1.0, mean, 4*error);
    }
}
