/*
 * The matrix-free coupled friction step (HydrodynamicInteractions::krylovFrictionStep) when it
 * cannot give an answer, called directly with its solves' limits as arguments: each of its three
 * Krylov solves, given too few iterations, throws naming that solve and its numbers; blobs that the
 * dense path refuses (not finite, the same sphere on two bodies, in a periodic box too large or the
 * same sphere through it) are refused here too, with the same message naming body and blob, before
 * a single product with the mobility.
 */
#include "ReferenceTests.h"
#include "RigidBodyTestUtilities.h"
#include "internal/BlobMobility.h"
#include "internal/HydrodynamicInteractions.h"
#include "internal/RigidBodyModel.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>
#include <cmath>
#include <functional>
#include <random>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using namespace RigidBodyTest;
using std::vector;

namespace {

/**
 * Three bodies of four particles (radius 0.06 nm, the blobs) close together, with velocities; or,
 * as free particles, the same twelve particles, each a body of one blob.
 */
struct ThreeBodies {
    System system;
    RigidBodyDescription description;
    vector<Vec3> positions, velocities;
    std::unique_ptr<RigidBodyModel> model;
    std::unique_ptr<HydrodynamicInteractions> interactions;
    vector<BodyState> states;
    explicit ThreeBodies(bool freeParticles = false) {
        const Vec3 shape[4] = {Vec3(0, 0, 0), Vec3(0.12, 0, 0), Vec3(0, 0.13, 0), Vec3(0.02, 0.03, 0.11)};
        const Vec3 centres[3] = {Vec3(0, 0, 0), Vec3(0.3, 0.05, 0), Vec3(0.1, 0.3, 0.1)};
        std::mt19937 random(3);
        std::normal_distribution<double> normal;
        description.hydrodynamicInteractions = true;
        for (const Vec3& c : centres) {
            RigidBodyDescription::Body body;
            for (const Vec3& p : shape) {
                body.particles.push_back(system.addParticle(10.0));
                description.particleRadii[body.particles.back()] = 0.06;
                positions.push_back(c+p);
                velocities.push_back(Vec3(normal(random), normal(random), normal(random)));
            }
            if (!freeParticles)
                description.bodies.push_back(body);
        }
        model.reset(new RigidBodyModel(system, description));
        states = model->fitStates(positions, velocities, NULL);
        interactions.reset(new HydrodynamicInteractions(*model));
    }
    /** One matrix-free friction step from these states (viscosity 500, h 0.002) with these limits,
     *  its friction solve started from zero (as every step here is a first step). */
    HydrodynamicInteractions::KrylovIterations step(const vector<BodyState>& at, double kT, int maxIterations, BlobMobility& mobility,
                                                    const Vec3* box = NULL) const {
        interactions->forgetWarmStart();
        std::mt19937 random(5);
        std::normal_distribution<double> normal;
        Eigen::VectorXd normals(3*interactions->getNumBlobs());
        for (int i = 0; i < normals.size(); i++)
            normals[i] = normal(random);
        Eigen::VectorXd u = interactions->getVelocities(at);
        return interactions->krylovFrictionStep(at, 500, kT, 0.002, normals, u, 1e-10, maxIterations, mobility, box);
    }
};

/** The host's mobility, counting what the step asks of it; negated (not positive definite) after
 *  its first healthyProducts products if that is not negative. */
struct CountingMobility : BlobMobility {
    HostBlobMobility host;
    int setBlobsCalls = 0, products = 0, healthyProducts = -1;
    void setBlobs(const vector<Vec3>& positions, const vector<double>& radii, const Vec3* boxVectors) {
        setBlobsCalls++;
        host.setBlobs(positions, radii, boxVectors);
    }
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
        products++;
        host.multiply(f, out);
        if (healthyProducts >= 0 && products > healthyProducts)
            out = -out;
    }
};

} // namespace

TEST(KrylovFrictionStep, EachSolveThatDoesNotConvergeIsNamed) {
    // With room enough the two solves (the noise's preconditioned Lanczos and the friction's conjugate
    // gradients) converge; with fewer iterations than one of them needs, that one throws, named, with
    // the limit it hit. Lanczos checks convergence every third iteration, so it is given three fewer
    // than it took.
    for (bool freeParticles : {false, true}) {
        SCOPED_TRACE(freeParticles ? "twelve free particles" : "three bodies of four blobs");
        ThreeBodies bodies(freeParticles);
        HostBlobMobility mobility;
        const double kT = 2.5;
        HydrodynamicInteractions::KrylovIterations enough = bodies.step(bodies.states, kT, 1000, mobility);
        HydrodynamicInteractions::KrylovIterations cold = bodies.step(bodies.states, 0, 1000, mobility);
        std::cout << (freeParticles ? "free particles" : "bodies") << ": iterations: Lanczos " << enough.noise << ", friction " << enough.friction
                  << "; at kT = 0, friction " << cold.friction << std::endl;
        ASSERT_GT(enough.noise, 3);
        ASSERT_EQ(enough.noiseSolve, 0);
        ASSERT_GT(cold.friction, 1);
        const int lanczosLimit = enough.noise-3;
        const std::string numbers = (freeParticles ? "with 12 bodies of 12 blobs" : "with 3 bodies of 12 blobs");
        expectError([&] { bodies.step(bodies.states, kT, lanczosLimit, mobility); },
                    {"hydrodynamic interactions: the Lanczos inverse square root of the blobs' mobility for the noise (preconditioned by every body's own "
                     "blocks) did not converge in "+std::to_string(lanczosLimit)+" iterations", "asked for 1e-10", numbers, "nearly coincide"});
        expectError([&] { bodies.step(bodies.states, 0, cold.friction-1, mobility); },
                    {"the conjugate gradients for the friction", "did not converge in "+std::to_string(cold.friction-1)+" iterations", numbers});
    }
}

TEST(KrylovFrictionStep, EachSolveThatFindsItsOperatorNotPositiveDefiniteIsNamed) {
    // A mobility whose products turn negative (as a wrong device product would) after the solves
    // before the one under test: that one stops at once, named, saying the operator is not positive
    // definite (without the checks, Lanczos clipped T's negative eigenvalues and conjugate gradients
    // ran on, converging or not).
    ThreeBodies bodies;
    HostBlobMobility host;
    HydrodynamicInteractions::KrylovIterations enough = bodies.step(bodies.states, 2.5, 1000, host);
    struct Case {
        double kT;
        int healthyProducts;
        const char* solve;
    };
    for (Case c : {Case{2.5, 0, "the Lanczos inverse square root of the blobs' mobility for the noise"},
                   Case{2.5, enough.noise, "the conjugate gradients for the friction"},
                   Case{0, 0, "the conjugate gradients for the friction"}}) {
        SCOPED_TRACE(c.solve);
        CountingMobility mobility;
        mobility.healthyProducts = c.healthyProducts;
        expectError([&] { bodies.step(bodies.states, c.kT, 1000, mobility); },
                    {std::string(c.solve), "found the operator not positive definite", "Rayleigh quotient of it on its Krylov space is -", "RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER=dense"});
        EXPECT_LE(mobility.products, c.healthyProducts+4);  // not after 1000 iterations
    }
}

TEST(KrylovFrictionStep, RefusesWhatTheDensePathRefusesBeforeAnyProduct) {
    // Each bad configuration is refused by the matrix-free step before it sets the mobility's blobs,
    // with the dense path's own message (computeResistance, the same validation).
    ThreeBodies bodies;
    const Vec3 cube[3] = {Vec3(1.0, 0, 0), Vec3(0, 1.0, 0), Vec3(0, 0, 1.0)};
    const Vec3 small[3] = {Vec3(0.23, 0, 0), Vec3(0, 0.8, 0), Vec3(0, 0, 0.8)};
    struct Case {
        const char* name;
        std::function<void (vector<BodyState>&)> change;
        const Vec3* box;
        vector<std::string> parts;
    };
    const double NaN = std::nan("");
    vector<Case> cases = {
        {"a position that is not finite", [&] (vector<BodyState>& s) { s[1].position[2] = NaN; }, NULL,
         {"RigidLangevinIntegrator: hydrodynamic interactions: blob 0 of rigid body 1 has position", "nan", "finite"}},
        {"the same spheres on two bodies", [] (vector<BodyState>& s) { s[2] = s[0]; }, NULL,
         {"of rigid body 0 and blob ", " of rigid body 2 are coincident"}},
        {"the same spheres through the box", [&] (vector<BodyState>& s) { s[2] = s[0]; s[2].position += cube[1]-cube[2]; }, cube,
         {"of rigid body 0 and blob ", " of rigid body 2 are the same sphere through the periodic box"}},
        {"blobs too large for the box", [] (vector<BodyState>&) {}, small,
         {"blob 0 of rigid body 0 has radius 0.06 nm, too large for the periodic box", "(0.115 nm)", "larger box", "smaller blobs"}},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        vector<BodyState> states = bodies.states;
        c.change(states);
        CountingMobility mobility;
        expectError([&] { bodies.step(states, 2.5, 1000, mobility, c.box); }, c.parts);
        EXPECT_EQ(0, mobility.setBlobsCalls);
        EXPECT_EQ(0, mobility.products);
        expectError([&] { bodies.interactions->computeResistance(states, c.box); }, c.parts);
    }
    // And the same bodies as they were, in the cube, pass.
    CountingMobility mobility;
    bodies.step(bodies.states, 2.5, 1000, mobility, cube);
    EXPECT_EQ(1, mobility.setBlobsCalls);
    EXPECT_GT(mobility.products, 3);
}

TEST(KrylovFrictionStep, WarmStartsGiveTheSameStepInFewerIterations) {
    // The friction solve starts from the best multiple of the last step's solution. At kT = 0, a
    // step from the same states with velocities -0.5 u has the solution -0.5 y exactly: it needs no
    // iteration (a start not taken, or scaled wrongly, needs as many as from zero: 16 here). At
    // 2.5 kJ/mol, from moved states, the step is the one a cold start gives to well within the
    // solves' tolerance (1e-10: measured 1.6e-11 relative), and forgetWarmStart() starts from zero.
    ThreeBodies bodies;
    HostBlobMobility mobility;
    Eigen::VectorXd normals = Eigen::VectorXd::Zero(3*bodies.interactions->getNumBlobs());
    Eigen::VectorXd u = bodies.interactions->getVelocities(bodies.states), first = u;
    auto step = [&] (const vector<BodyState>& at, double kT, Eigen::VectorXd& velocities) {
        return bodies.interactions->krylovFrictionStep(at, 500, kT, 0.002, normals, velocities, 1e-10, 1000, mobility).friction;
    };
    bodies.interactions->forgetWarmStart();
    const int cold = step(bodies.states, 0, first);
    Eigen::VectorXd again = -0.5*u;
    EXPECT_GT(cold, 3);
    EXPECT_EQ(0, step(bodies.states, 0, again));
    EXPECT_LT((again+0.5*first).norm(), 1e-9*first.norm());
    bodies.interactions->forgetWarmStart();
    EXPECT_EQ(cold, step(bodies.states, 0, again = u)) << "forgotten: from zero";
    // With noise, from moved states: warm against cold.
    std::mt19937 random(11);
    std::normal_distribution<double> normal;
    for (int i = 0; i < normals.size(); i++)
        normals[i] = normal(random);
    vector<BodyState> moved = bodies.states;
    for (BodyState& s : moved)
        s.position += Vec3(0.003, -0.002, 0.001);
    Eigen::VectorXd warm = u, fromZero = u;
    step(moved, 2.5, warm);
    bodies.interactions->forgetWarmStart();
    step(moved, 2.5, fromZero);
    std::cout << "cold friction solve: " << cold << " iterations; warm against cold with noise: " << (warm-fromZero).norm()/fromZero.norm() << std::endl;
    EXPECT_LT((warm-fromZero).norm(), 1e-9*fromZero.norm());
    EXPECT_GT((warm-fromZero).norm(), 0) << "the warm start was not taken";
}
