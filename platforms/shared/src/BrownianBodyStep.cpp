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

typedef Eigen::Matrix<double, 6, 1> Vector6;

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
        model(model), interactions(interactions), driftLength(1.0) {
    int coordinates = 0;
    for (int b = 0; b < model.getNumBodies(); b++) {
        firstCoordinate.push_back(coordinates);
        coordinates += model.getType(model.getBodyType(b)).getNumDegreesOfFreedom();
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
    VectorXd g(firstCoordinate.empty() ? 0 : firstCoordinate.back()+model.getType(model.getBodyType(model.getNumBodies()-1)).getNumDegreesOfFreedom());
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

VectorXd BrownianBodyStep::coupledVelocities(const vector<BodyState>& states, const VectorXd& g, const CoupledStepParameters& step,
                                             const CoupledSolve& solve, const std::function<double ()>& normal, BlobMobility& mobility) {
    // The blobs' mobility is per unit viscosity: N = N_1/viscosity, and the noise's covariance
    // (2 kT/h) N comes from a slip of covariance (2 kT viscosity/h) M, or L^-T w with L L^T = R_1.
    VectorXd u;
    if (!solve.krylov) {
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
    VectorXd slip;
    lastIterations = {0, 0, 0};
    if (step.kT > 0) {
        VectorXd w(3*interactions->getNumBlobs());
        for (int i = 0; i < w.size(); i++)
            w[i] = normal();
        lastIterations.noise = bodyMobility->blobNoise(states, w, slip, solve.tolerance, solve.maxIterations, mobility, step.box);
        slip *= std::sqrt(2*step.kT*step.viscosity/step.stepSize);
    }
    lastIterations.friction += bodyMobility->solve(states, g, slip, u, solve.tolerance, solve.maxIterations, mobility, step.box);
    return u/step.viscosity;
}

vector<Vector6> BrownianBodyStep::labMobility(const vector<BodyState>& states, const vector<Vector6>& g, const CoupledStepParameters& step,
                                              const CoupledSolve& solve, const vector<TypeStepCoefficients>& coefficients, BlobMobility& mobility) {
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
    VectorXd active(interactions->getNumCoordinates()), u;
    for (int b = 0; b < numBodies; b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        active.segment(firstCoordinate[b], type.getNumDegreesOfFreedom()) = labToActive(states[b], type, g[b]);
    }
    if (solve.krylov)
        lastIterations.noiseSolve += bodyMobility->solve(states, active, VectorXd(), u, solve.tolerance, solve.maxIterations, mobility, step.box);
    else {
        bodyMobility->factorize(states, step.box);
        bodyMobility->denseMultiply(active, u);
    }
    for (int b = 0; b < numBodies; b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        out[b] = activeToLab(states[b], type, u.segment(firstCoordinate[b], type.getNumDegreesOfFreedom()))/step.viscosity;
    }
    return out;
}

vector<Vector6> BrownianBodyStep::drift(const vector<BodyState>& states, const CoupledStepParameters& step, const CoupledSolve& solve,
                                        const vector<TypeStepCoefficients>& coefficients, const std::function<double ()>& normal, BlobMobility& mobility) {
    // (kT/delta) [N(q + delta D W/2) - N(q - delta D W/2)] D^-1 W: its mean is kT d/dq . N to
    // O(delta^2); the solves' errors add about tolerance/delta, so delta = tolerance^(1/3) where
    // they are iterative.
    const int numBodies = model.getNumBodies();
    const double delta = (interactions != NULL && solve.krylov ? std::max(1e-4, std::cbrt(solve.tolerance)) : 1e-4);
    vector<Vector6> w(numBodies), scaled(numBodies);
    vector<BodyState> plus = states, minus = states;
    for (int b = 0; b < numBodies; b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        for (int i = 0; i < 6; i++)
            w[b][i] = normal();
        scaled[b] = w[b];
        const double angle = (driftAngle.empty() ? 1.0 : driftAngle[model.getBodyType(b)]);
        scaled[b].head<3>() /= driftLength;
        scaled[b].tail<3>() /= angle;
        Vec3 shift = Vec3(w[b][0], w[b][1], w[b][2])*(0.5*delta*driftLength), turn = Vec3(w[b][3], w[b][4], w[b][5])*(0.5*delta*angle);
        moveBody(plus[b], type, shift, turn);
        moveBody(minus[b], type, -shift, -turn);
    }
    vector<Vector6> ahead = labMobility(plus, scaled, step, solve, coefficients, mobility);
    vector<Vector6> behind = labMobility(minus, scaled, step, solve, coefficients, mobility);
    vector<Vector6> result(numBodies);
    for (int b = 0; b < numBodies; b++)
        result[b] = (step.kT/delta)*(ahead[b]-behind[b]);
    return result;
}

void BrownianBodyStep::take(vector<BodyState>& states, const vector<Vec3>& forces, const CoupledStepParameters& step, const CoupledSolve& solve,
                            const vector<TypeStepCoefficients>& coefficients, const std::function<double ()>& normal, BlobMobility& mobility) {
    const double h = step.stepSize;
    VectorXd g = generalizedForces(states, forces);
    VectorXd u = (interactions == NULL ? ownVelocities(g, step, coefficients, normal) : coupledVelocities(states, g, step, solve, normal, mobility));
    vector<Vector6> driftVelocity = (step.kT > 0 ? drift(states, step, solve, coefficients, normal, mobility) : vector<Vector6>(states.size(), Vector6::Zero()));
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
