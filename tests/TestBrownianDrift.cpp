/*
 * The stochastic drift of RigidBrownianIntegrator's matrix-free step (BrownianBodyStep), whose
 * traction form differentiates the parts of the bodies' mobility N = A (K'^T M^-1 K')^-1 A^T (products
 * at displaced blobs after one solve), against the dense step's, which differentiates N itself. For
 * one random direction both are the same derivative of N, each to its central difference's
 * delta^2, so they agree direction by direction, not only on average: here for three bodies above a
 * no-slip wall (so M depends on every body's height and on their distances), one of them linear (no
 * rotation about its axis, so A is not square).
 *
 * They agree to 2e-9 to 9e-9 at tolerance 1e-10 (bound 1e-6) and to 3e-4 to 3e-3 at 1e-3 (bound
 * 1e-2). Leaving out any one of the traction form's five differences ((dA) U, (dA^T) w, (dK'^T)
 * lambda, (dM) lambda, (dK') U) makes them disagree by 26% to 204% of the drift (checked by hand,
 * each direction failing). And a solve that fails names RigidBrownianIntegrator, the only user of the
 * bodies' mobility (it named RigidLangevinIntegrator).
 */
#include "ReferenceTests.h"
#include "internal/BlobMobility.h"
#include "internal/BrownianBodyStep.h"
#include "internal/HydrodynamicInteractions.h"
#include "internal/RigidBodyModel.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>
#include <cmath>
#include <memory>
#include <random>
#include <string>

using namespace OpenMM;
using namespace RigidLangevinPlugin;
using std::vector;

namespace {

typedef BrownianBodyStep::Vector6 Vector6;

/** Two bodies of four blobs and a linear one of three (blob radius 0.06 nm), 0.03-0.2 nm above the wall z = 0. */
struct BodiesAboveWall {
    System system;
    RigidBodyDescription description;
    std::unique_ptr<RigidBodyModel> model;
    std::unique_ptr<HydrodynamicInteractions> interactions;
    vector<BodyState> states;
    BodiesAboveWall() {
        const vector<vector<Vec3> > bodies = {
            {Vec3(0, 0, 0.1), Vec3(0.12, 0, 0.12), Vec3(0, 0.13, 0.09), Vec3(0.02, 0.03, 0.21)},
            {Vec3(0.3, 0.05, 0.12), Vec3(0.42, 0.05, 0.1), Vec3(0.3, 0.18, 0.16), Vec3(0.33, 0.08, 0.25)},
            {Vec3(0.1, 0.3, 0.09), Vec3(0.2, 0.33, 0.14), Vec3(0.3, 0.36, 0.19)}};
        vector<Vec3> positions;
        description.hydrodynamicInteractions = true;
        description.integratorName = "RigidBrownianIntegrator";  // as the kernels describe a RigidBrownianIntegrator's bodies
        for (const vector<Vec3>& blobs : bodies) {
            RigidBodyDescription::Body body;
            for (const Vec3& p : blobs) {
                body.particles.push_back(system.addParticle(10.0));
                description.particleRadii[body.particles.back()] = 0.06;
                positions.push_back(p);
            }
            description.bodies.push_back(body);
        }
        model.reset(new RigidBodyModel(system, description));
        states = model->fitStates(positions, vector<Vec3>(positions.size()), NULL);
        interactions.reset(new HydrodynamicInteractions(*model, 0.0));
    }
};

vector<Vector6> randomDirections(int bodies, unsigned seed) {
    std::mt19937 random(seed);
    std::normal_distribution<double> normal;
    vector<Vector6> w(bodies);
    for (Vector6& v : w)
        for (int i = 0; i < 6; i++)
            v[i] = normal(random);
    return w;
}

/** |a - b| / |b| over all bodies' six entries. */
double relativeDifference(const vector<Vector6>& a, const vector<Vector6>& b) {
    double difference = 0, norm = 0;
    for (size_t i = 0; i < a.size(); i++) {
        difference += (a[i]-b[i]).squaredNorm();
        norm += b[i].squaredNorm();
    }
    return std::sqrt(difference/norm);
}

} // namespace

TEST(BrownianDrift, MatrixFreeTractionFormIsTheDenseDerivativeForEachDirection) {
    BodiesAboveWall scene;
    ASSERT_EQ(scene.model->getType(scene.model->getBodyType(2)).getNumDegreesOfFreedom(), 5);
    BrownianBodyStep step(*scene.model, scene.interactions.get());
    HostBlobMobility mobility;
    mobility.setWall(0.0);
    const CoupledStepParameters parameters = {0.002, 0.9, 2.5, NULL};
    const vector<TypeStepCoefficients> noCoefficients;
    for (unsigned seed = 1; seed <= 3; seed++) {
        const vector<Vector6> w = randomDirections(3, seed);
        const vector<Vector6> dense = step.drift(scene.states, w, parameters, {false, 0, 0, false}, noCoefficients, mobility);
        const vector<Vector6> tight = step.drift(scene.states, w, parameters, {true, 1e-10, 200, false}, noCoefficients, mobility);
        const vector<Vector6> loose = step.drift(scene.states, w, parameters, {true, 1e-3, 200, false}, noCoefficients, mobility);
        EXPECT_LT(relativeDifference(tight, dense), 1e-6) << "direction " << seed;
        EXPECT_LT(relativeDifference(loose, dense), 1e-2) << "direction " << seed;
    }
}

TEST(BrownianDrift, AFailedSolveNamesTheIntegratorAndTheSolve) {
    // The bodies' mobility serves only RigidBrownianIntegrator: a GMRES solve stopped after one
    // iteration says so, not RigidLangevinIntegrator.
    BodiesAboveWall scene;
    BrownianBodyStep step(*scene.model, scene.interactions.get());
    HostBlobMobility mobility;
    mobility.setWall(0.0);
    const CoupledStepParameters parameters = {0.002, 0.9, 2.5, NULL};
    try {
        step.drift(scene.states, randomDirections(3, 1), parameters, {true, 1e-10, 1, false}, vector<TypeStepCoefficients>(), mobility);
        FAIL() << "a solve given one iteration converged";
    }
    catch (const OpenMMException& e) {
        EXPECT_NE(std::string(e.what()).find("RigidBrownianIntegrator: hydrodynamic interactions: GMRES for the bodies' mobility"), std::string::npos) << e.what();
    }
}
