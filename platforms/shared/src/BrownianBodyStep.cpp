#include "internal/BrownianBodyStep.h"
#include "internal/BodyDynamics.h"
#include "internal/RigidFit.h"
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

using namespace RigidLangevinPlugin;
using Eigen::VectorXd;
using OpenMM::Vec3;
using std::vector;

namespace {

typedef BrownianBodyStep::Vector6 Vector6;

/** A body's active body-frame coordinates (velocity, then rates about its rotating axes) as a lab 6-vector. */
Vector6 activeToLab(const BodyState& s, const BodyType& type, const VectorXd& active) {
    Vec3 rates;
    int c = 3;
    for (int axis = 0; axis < 3; axis++)
        if (type.rotates(axis))
            rates[axis] = active[c++];
    Vec3 v = BodyDynamics::toLab(s.rotation, Vec3(active[0], active[1], active[2])), w = BodyDynamics::toLab(s.rotation, rates);
    Vector6 lab;
    lab << v[0], v[1], v[2], w[0], w[1], w[2];
    return lab;
}

/** A lab 6-vector in a body's active body-frame coordinates (the transpose of activeToLab). */
VectorXd labToActive(const BodyState& s, const BodyType& type, const Vector6& lab) {
    Vec3 v = BodyDynamics::toBody(s.rotation, Vec3(lab[0], lab[1], lab[2])), w = BodyDynamics::toBody(s.rotation, Vec3(lab[3], lab[4], lab[5]));
    VectorXd active(type.getNumDegreesOfFreedom());
    active.head<3>() << v[0], v[1], v[2];
    int c = 3;
    for (int axis = 0; axis < 3; axis++)
        if (type.rotates(axis))
            active[c++] = w[axis];
    return active;
}

/** Move a body by a lab translation and turn it by a lab rotation vector (its axes a -> R a: Q <- Q R^T). */
void moveBody(BodyState& s, const BodyType& type, const Vec3& translation, const Vec3& rotation) {
    s.position += translation;
    if (type.numRotations == 0)
        return;
    Eigen::Vector3d phi(rotation[0], rotation[1], rotation[2]);
    double angle = phi.norm();
    if (angle == 0)
        return;
    Eigen::Matrix3d r = Eigen::AngleAxisd(angle, phi/angle).toRotationMatrix();
    fromMatrix3(Eigen::Matrix3d(toMatrix3(s.rotation)*r.transpose()), s.rotation);
}

} // namespace

BrownianBodyStep::BrownianBodyStep(const RigidBodyModel& model, const HydrodynamicInteractions* interactions) :
        model(model), interactions(interactions), numCoordinates(0), driftLength(1.0) {
    for (int b = 0; b < model.getNumBodies(); b++) {
        firstCoordinate.push_back(numCoordinates);
        numCoordinates += model.getType(model.getBodyType(b)).getNumDegreesOfFreedom();
    }
    if (interactions != NULL) {
        bodyMobility.reset(new BodyMobility(*interactions));
        // The length over which the blobs' mobility changes, and the turn of each type that moves its
        // blobs as far: a turn of delta radians would carry a blob at distance r by delta r, far past
        // l on a long body (through the wall at a loose tolerance).
        driftLength = interactions->getSmallestBlobRadius();
        for (int t = 0; t < model.getNumTypes(); t++) {
            vector<Vec3> coords;
            vector<double> radii;
            model.getTypeBlobs(t, coords, radii);
            double farthest = 0;
            for (const Vec3& r : coords)
                farthest = std::max(farthest, std::sqrt(r.dot(r)));
            driftAngle.push_back(std::min(1.0, driftLength/std::max(farthest, 1e-300)));
        }
    }
}

VectorXd BrownianBodyStep::generalizedForces(const vector<BodyState>& states, const vector<Vec3>& forces) const {
    VectorXd g(numCoordinates);
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        Vec3 force, torque;
        BodyDynamics::gatherForce(type, model.getBodyParticles(b), states[b], forces, force, torque);
        Vec3 f = BodyDynamics::toBody(states[b].rotation, force);
        int c = firstCoordinate[b];
        for (int k = 0; k < 3; k++)
            g[c++] = f[k];
        for (int axis = 0; axis < 3; axis++)
            if (type.rotates(axis))
                g[c++] = torque[axis];
    }
    return g;
}

VectorXd BrownianBodyStep::ownVelocities(const VectorXd& g, const CoupledStepParameters& step, const vector<TypeStepCoefficients>& coefficients,
                                         const std::function<double ()>& normal) const {
    // U = N F + sqrt(2 kT/h) L w, L L^T = N, each body on its own (N includes the viscosity).
    const double noise = std::sqrt(2*step.kT/step.stepSize);
    VectorXd u(g.size());
    for (int b = 0; b < model.getNumBodies(); b++) {
        const int type = model.getBodyType(b), n = model.getType(type).getNumDegreesOfFreedom(), c = firstCoordinate[b];
        const TypeStepCoefficients& k = coefficients[type];
        u.segment(c, n) = k.mobility.topLeftCorner(n, n)*g.segment(c, n);
        if (step.kT > 0) {
            VectorXd w(n);
            for (int i = 0; i < n; i++)
                w[i] = normal();
            u.segment(c, n) += noise*(k.mobilityFactor.topLeftCorner(n, n).triangularView<Eigen::Lower>()*w).eval();
        }
    }
    return u;
}

VectorXd BrownianBodyStep::denseVelocities(const vector<BodyState>& states, const VectorXd& g, const CoupledStepParameters& step,
                                           const std::function<double ()>& normal) {
    // The blobs' mobility is per unit viscosity: N = N_1/viscosity, and the noise's covariance
    // (2 kT/h) N comes from L^-T w with L L^T = R_1.
    VectorXd u;
    bodyMobility->factorize(states, step.box);
    bodyMobility->denseMultiply(g, u);
    u /= step.viscosity;
    if (step.kT > 0) {
        VectorXd w(g.size()), noise;
        for (int i = 0; i < w.size(); i++)
            w[i] = normal();
        bodyMobility->denseNoise(w, noise);
        u += std::sqrt(2*step.kT/(step.stepSize*step.viscosity))*noise;
    }
    lastIterations = {0, 0, 0};
    return u;
}

VectorXd BrownianBodyStep::krylovVelocities(const vector<BodyState>& states, VectorXd g, const CoupledStepParameters& step, const CoupledSolve& solve,
                                            const std::function<double ()>& normal, BlobMobility& mobility, vector<Vector6>& driftVelocity) {
    // The noise's covariance (2 kT/h) N comes from a slip of covariance (2 kT viscosity/h) M (N = N_1/viscosity).
    VectorXd slip, u;
    lastIterations = {0, 0, 0};
    if (step.kT > 0) {
        lastIterations.noise = bodyMobility->blobNoise(states, normal, slip, solve.tolerance, solve.maxIterations, mobility, step.box);
        slip *= std::sqrt(2*step.kT*step.viscosity/step.stepSize);
        DriftTerms terms = tractionTerms(states, randomDirections(normal), step, solve, mobility);
        g += terms.force;
        slip += terms.slip;
        driftVelocity = terms.velocity;
    }
    lastIterations.friction = bodyMobility->solve(states, g, slip, u, solve.tolerance, solve.maxIterations, mobility, step.box);
    return u/step.viscosity;
}

VectorXd BrownianBodyStep::toActive(const vector<BodyState>& states, const vector<Vector6>& lab) const {
    VectorXd active(numCoordinates);
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        active.segment(firstCoordinate[b], type.getNumDegreesOfFreedom()) = labToActive(states[b], type, lab[b]);
    }
    return active;
}

vector<BrownianBodyStep::Vector6> BrownianBodyStep::toLab(const vector<BodyState>& states, const VectorXd& active) const {
    vector<Vector6> lab(model.getNumBodies());
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        lab[b] = activeToLab(states[b], type, active.segment(firstCoordinate[b], type.getNumDegreesOfFreedom()));
    }
    return lab;
}

vector<BrownianBodyStep::Vector6> BrownianBodyStep::randomDirections(const std::function<double ()>& normal) const {
    vector<Vector6> w(model.getNumBodies());
    for (Vector6& v : w)
        for (int i = 0; i < 6; i++)
            v[i] = normal();
    return w;
}

vector<BrownianBodyStep::Vector6> BrownianBodyStep::directionForces(const vector<Vector6>& w) const {
    vector<Vector6> f = w;
    for (int b = 0; b < model.getNumBodies(); b++) {
        f[b].head<3>() /= driftLength;
        f[b].tail<3>() /= (driftAngle.empty() ? 1.0 : driftAngle[model.getBodyType(b)]);
    }
    return f;
}

vector<BodyState> BrownianBodyStep::displaced(const vector<BodyState>& states, const vector<Vector6>& w, double sign, double delta) const {
    vector<BodyState> moved = states;
    for (int b = 0; b < model.getNumBodies(); b++) {
        const double angle = (driftAngle.empty() ? 1.0 : driftAngle[model.getBodyType(b)]), half = 0.5*sign*delta;
        moveBody(moved[b], model.getType(model.getBodyType(b)), Vec3(w[b][0], w[b][1], w[b][2])*(half*driftLength), Vec3(w[b][3], w[b][4], w[b][5])*(half*angle));
    }
    return moved;
}

vector<BrownianBodyStep::Vector6> BrownianBodyStep::labMobility(const vector<BodyState>& states, const vector<Vector6>& g, const CoupledStepParameters& step,
                                                                const vector<TypeStepCoefficients>& coefficients) {
    const int numBodies = model.getNumBodies();
    vector<Vector6> out(numBodies);
    if (interactions == NULL) {
        for (int b = 0; b < numBodies; b++) {
            const BodyType& type = model.getType(model.getBodyType(b));
            const int n = type.getNumDegreesOfFreedom();
            out[b] = activeToLab(states[b], type, coefficients[model.getBodyType(b)].mobility.topLeftCorner(n, n)*labToActive(states[b], type, g[b]));
        }
        return out;
    }
    VectorXd u;
    bodyMobility->factorize(states, step.box);
    bodyMobility->denseMultiply(toActive(states, g), u);
    return toLab(states, u/step.viscosity);
}

vector<BrownianBodyStep::Vector6> BrownianBodyStep::mobilityDifference(const vector<BodyState>& states, const vector<Vector6>& w,
                                                                       const CoupledStepParameters& step, const vector<TypeStepCoefficients>& coefficients) {
    // N's solves here are exact, so delta is limited only by rounding.
    const double delta = 1e-4;
    const vector<Vector6> f = directionForces(w);
    vector<Vector6> ahead = labMobility(displaced(states, w, 1, delta), f, step, coefficients);
    vector<Vector6> behind = labMobility(displaced(states, w, -1, delta), f, step, coefficients);
    for (int b = 0; b < model.getNumBodies(); b++)
        ahead[b] = (step.kT/delta)*(ahead[b]-behind[b]);
    return ahead;
}

BrownianBodyStep::DriftTerms BrownianBodyStep::tractionTerms(const vector<BodyState>& states, const vector<Vector6>& w, const CoupledStepParameters& step,
                                                             const CoupledSolve& solve, BlobMobility& mobility) {
    // The differences are of products, exact to rounding (single precision's 3e-7 of the product at
    // tolerances from 1e-5 up, HostBlobMobility): delta = sqrt(tolerance), within [1e-4, 1e-2], keeps
    // both the central difference's error (delta^2) and rounding's (3e-7/delta) near the tolerance.
    const double delta = std::min(1e-2, std::max(1e-4, std::sqrt(solve.tolerance)));
    const vector<Vector6> f = directionForces(w);
    const VectorXd g = toActive(states, f);
    VectorXd u, lambda;
    lastIterations.noiseSolve = bodyMobility->solve(states, g, VectorXd(), u, solve.tolerance, solve.maxIterations, mobility, step.box, &lambda);
    const vector<BodyState> plus = displaced(states, w, 1, delta), minus = displaced(states, w, -1, delta);
    DriftTerms terms;
    VectorXd plusKT, minusKT, plusM, minusM, plusK, minusK;
    bodyMobility->applyKT(plus, lambda, plusKT);
    bodyMobility->applyKT(minus, lambda, minusKT);
    terms.force = minusKT-plusKT;
    terms.velocity.resize(model.getNumBodies());
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        const int c = firstCoordinate[b], n = type.getNumDegreesOfFreedom();
        terms.force.segment(c, n) += labToActive(plus[b], type, f[b])-labToActive(minus[b], type, f[b]);
        terms.velocity[b] = (step.kT/(delta*step.viscosity))*(activeToLab(plus[b], type, u.segment(c, n))-activeToLab(minus[b], type, u.segment(c, n)));
    }
    bodyMobility->blobVelocities(plus, lambda, plusM, mobility, step.box);
    bodyMobility->blobVelocities(minus, lambda, minusM, mobility, step.box);
    bodyMobility->applyK(plus, u, plusK);
    bodyMobility->applyK(minus, u, minusK);
    terms.force *= step.kT/delta;
    terms.slip = (step.kT/delta)*((plusM-minusM)-(plusK-minusK));
    return terms;
}

vector<BrownianBodyStep::Vector6> BrownianBodyStep::drift(const vector<BodyState>& states, const vector<Vector6>& w, const CoupledStepParameters& step,
                                                          const CoupledSolve& solve, const vector<TypeStepCoefficients>& coefficients, BlobMobility& mobility) {
    if (interactions == NULL || !solve.krylov)
        return mobilityDifference(states, w, step, coefficients);
    DriftTerms terms = tractionTerms(states, w, step, solve, mobility);
    VectorXd u;
    bodyMobility->solve(states, terms.force, terms.slip, u, solve.tolerance, solve.maxIterations, mobility, step.box);
    const vector<Vector6> solved = toLab(states, u/step.viscosity);
    for (int b = 0; b < model.getNumBodies(); b++)
        terms.velocity[b] += solved[b];
    return terms.velocity;
}

void BrownianBodyStep::take(vector<BodyState>& states, const vector<Vec3>& forces, const CoupledStepParameters& step, const CoupledSolve& solve,
                            const vector<TypeStepCoefficients>& coefficients, const std::function<double ()>& normal, BlobMobility& mobility) {
    const double h = step.stepSize;
    VectorXd g = generalizedForces(states, forces), u;
    vector<Vector6> driftVelocity(states.size(), Vector6::Zero());
    if (interactions != NULL && solve.krylov)
        u = krylovVelocities(states, g, step, solve, normal, mobility, driftVelocity);
    else {
        u = (interactions == NULL ? ownVelocities(g, step, coefficients, normal) : denseVelocities(states, g, step, normal));
        if (step.kT > 0)
            driftVelocity = mobilityDifference(states, randomDirections(normal), step, coefficients);
    }
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        Vector6 velocity = activeToLab(states[b], type, u.segment(firstCoordinate[b], type.getNumDegreesOfFreedom()))+driftVelocity[b];
        Vec3 translation(velocity[0], velocity[1], velocity[2]), rotation(velocity[3], velocity[4], velocity[5]);
        BodyState& s = states[b];
        moveBody(s, type, translation*h, rotation*h);
        // The velocities left are the displacement over h: its mean is the drift.
        s.velocity = translation;
        Vec3 rates = BodyDynamics::toBody(s.rotation, rotation);
        for (int axis = 0; axis < 3; axis++)
            s.angularMomentum[axis] = (type.rotates(axis) ? type.inertia[axis]*rates[axis] : 0.0);
    }
}
