#include "internal/HydrodynamicInteractions.h"
#include "internal/BodyDynamics.h"
#include "internal/CoupledResistanceMath.h"
#include "openmm/OpenMMException.h"
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

using namespace RigidLangevinPlugin;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

/** The tightest relative residual the friction's conjugate gradients are asked for when the
 *  tolerance is tightened for strong friction (1e-12 is the least a user may ask). */
const double FrictionToleranceFloor = 1e-11;

} // namespace

Eigen::VectorXd RigidLangevinPlugin::turnBlobs(const Eigen::VectorXd& v, const double q[3][3], bool toBody) {
    Eigen::VectorXd out(v.size());
    for (int k = 0; k < v.size()/3; k++) {
        Vec3 w(v[3*k], v[3*k+1], v[3*k+2]);
        w = (toBody ? BodyDynamics::toBody(q, w) : BodyDynamics::toLab(q, w));
        out.segment<3>(3*k) << w[0], w[1], w[2];
    }
    return out;
}

std::string RigidLangevinPlugin::hydrodynamicsCaller(const std::string& integrator) {
    return integrator+": hydrodynamic interactions";
}

int RigidLangevinPlugin::checkHydrodynamicSolve(const std::string& solve, const KrylovSolvers::Result& result, int numBodies, int numBlobs,
                                                const std::string& integrator) {
    if (result.outcome == KrylovSolvers::Converged)
        return result.iterations;
    std::string advice;
    if (result.outcome == KrylovSolvers::NotConverged)
        advice = "Blobs that nearly coincide, or very unequal blobs, make the mobility ill-conditioned: give the bodies blobs of similar size that do not "
                 "nearly coincide";
    else if (result.outcome == KrylovSolvers::NotFinite)
        advice = "The blobs were checked finite before the solve, so the bodies' velocities were not (after a force that was not?) or a product "
                 "overflowed: look for such forces and for blobs that nearly coincide, and compare with the dense solver "
                 "(RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER=dense)";
    else
        advice = "The blobs' mobility, and so this operator, is positive definite for every configuration of distinct blobs: here it is singular to "
                 "rounding (blobs that nearly coincide: merge or move them) or its products are wrong; the dense solver "
                 "(RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER=dense) factorises it exactly";
    throw OpenMMException(hydrodynamicsCaller(integrator)+": "+solve+" "+KrylovSolvers::explain(result)+", with "+std::to_string(numBodies)+" bodies of "+std::to_string(numBlobs)+
                          " blobs. "+advice);
}


HydrodynamicInteractions::HydrodynamicInteractions(const RigidBodyModel& model, std::optional<double> wallZ) : model(model), wallZ(wallZ) {
    for (int t = 0; t < model.getNumTypes(); t++) {
        const BodyType& type = model.getType(t);
        TypeBlobs blobs;
        model.getTypeBlobs(t, blobs.coords, blobs.radii);
        std::string caller = hydrodynamicsCaller(model.getIntegratorName())+" of "+model.getBodyName(model.getFirstBodyOfType(t));
        // The blobs' resistance alone and the body's own friction, in its frame about its centre
        // of mass, over the motions it makes.
        Eigen::MatrixXd alone = CoupledResistanceMath::resistance(caller, blobs.coords, blobs.radii, vector<int>(blobs.coords.size(), 0), {Vec3()}, NULL,
                                                                  [&] (int) { return model.getBodyName(model.getFirstBodyOfType(t)); });
        vector<int> active = type.getActiveCoordinates();
        int n = active.size();
        Eigen::MatrixXd d(n, n), own(n, n);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                d(i, j) = alone(active[i], active[j]);
                own(i, j) = type.resistance(active[i], active[j]);
            }
        Eigen::MatrixXd calibration = CoupledResistanceMath::calibration(caller, d, own);
        blobs.calibration.setZero();
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                blobs.calibration(active[i], active[j]) = calibration(i, j);
        // For the matrix-free step: K' in the body frame (blob k moves at V + omega x r_k, the six
        // velocities T P^T u) and the body's own mobility block, factorised for the preconditioners.
        const int numBlobs = blobs.coords.size();
        Eigen::MatrixXd rigid(3*numBlobs, 6);
        for (int k = 0; k < numBlobs; k++) {
            const Vec3& r = blobs.coords[k];
            rigid.block<3, 3>(3*k, 0).setIdentity();
            rigid.block<3, 3>(3*k, 3) << 0, r[2], -r[1], -r[2], 0, r[0], r[1], -r[0], 0;
        }
        Eigen::MatrixXd calibrationColumns(6, n);
        for (int j = 0; j < n; j++)
            calibrationColumns.col(j) = blobs.calibration.col(active[j]);
        blobs.velocities = rigid*calibrationColumns;
        Eigen::MatrixXd self(3*numBlobs, 3*numBlobs);
        for (int j = 0; j < 3*numBlobs; j++) {
            Eigen::VectorXd e = Eigen::VectorXd::Unit(3*numBlobs, j), column;
            CoupledResistanceMath::mobilityProduct(blobs.coords, blobs.radii, e, column);
            self.col(j) = column;
        }
        blobs.selfMobility.compute(self);
        blobs.frictionScale = 0;
        types.push_back(blobs);
    }
    int numCoordinates = 0;
    for (int b = 0; b < model.getNumBodies(); b++) {
        firstCoordinate.push_back(numCoordinates);
        numCoordinates += model.getType(model.getBodyType(b)).getNumDegreesOfFreedom();
    }
    masses.resize(numCoordinates);
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        vector<int> active = type.getActiveCoordinates();
        for (int i = 0; i < (int) active.size(); i++)
            masses[firstCoordinate[b]+i] = (active[i] < 3 ? type.mass : type.inertia[active[i]-3]);
    }
}

void HydrodynamicInteractions::forgetWarmStart() const {
    lastFrictionSolution.resize(0);
}

void HydrodynamicInteractions::setWarmStarts(bool warm) {
    warmStarts = warm;
    forgetWarmStart();
}

CoupledResistanceMath::BodyNames HydrodynamicInteractions::bodyNames() const {
    return [this] (int body) { return model.getBodyName(body); };
}

void HydrodynamicInteractions::validateBlobs(const vector<Vec3>& positions, const vector<double>& radii, const Vec3* boxVectors) const {
    vector<int> owner;
    for (int b = 0; b < model.getNumBodies(); b++)
        owner.insert(owner.end(), types[model.getBodyType(b)].coords.size(), b);
    CoupledResistanceMath::validateBlobs(hydrodynamicsCaller(model.getIntegratorName()), positions, radii, owner, boxVectors, bodyNames(), wallZ);
}

int HydrodynamicInteractions::getNumBlobs() const {
    int count = 0;
    for (int b = 0; b < model.getNumBodies(); b++)
        count += types[model.getBodyType(b)].coords.size();
    return count;
}

void HydrodynamicInteractions::applySelfFactor(const vector<BodyState>& states, SelfFactor which, const Eigen::VectorXd& in, Eigen::VectorXd& out) const {
    // Body b's block is Q L (Q its rotation on each blob): (Q L)^-1 = L^-1 Q^T, (Q L)^-T = Q L^-T.
    out.resize(in.size());
    for (int b = 0, first = 0; b < model.getNumBodies(); b++) {
        const TypeBlobs& blobs = types[model.getBodyType(b)];
        const int n = 3*blobs.coords.size();
        const Eigen::VectorXd v = in.segment(first, n);
        if (which == Lower)
            out.segment(first, n) = turnBlobs(blobs.selfMobility.matrixL()*v, states[b].rotation, false);
        else if (which == InverseLower)
            out.segment(first, n) = blobs.selfMobility.matrixL().solve(turnBlobs(v, states[b].rotation, true));
        else
            out.segment(first, n) = turnBlobs(blobs.selfMobility.matrixU().solve(v), states[b].rotation, false);
        first += n;
    }
}

KrylovSolvers::Operator HydrodynamicInteractions::preconditionedMobility(const vector<BodyState>& states, BlobMobility& mobility) const {
    return [this, &states, &mobility] (const Eigen::VectorXd& v, Eigen::VectorXd& out) {
        Eigen::VectorXd in, product;
        applySelfFactor(states, InverseLowerTranspose, v, in);
        mobility.multiply(in, product);
        applySelfFactor(states, InverseLower, product, out);
    };
}

double HydrodynamicInteractions::getSmallestBlobRadius() const {
    double smallest = std::numeric_limits<double>::infinity();
    for (const TypeBlobs& type : types)
        for (double r : type.radii)
            smallest = std::min(smallest, r);
    return smallest;
}

int HydrodynamicInteractions::getNumBlobRadii() const {
    std::set<double> distinct;
    for (const TypeBlobs& type : types)
        distinct.insert(type.radii.begin(), type.radii.end());
    return distinct.size();
}

void HydrodynamicInteractions::placeBlobs(const vector<BodyState>& states, vector<Vec3>& positions, vector<double>& radii) const {
    positions.clear();
    radii.clear();
    for (int b = 0; b < model.getNumBodies(); b++) {
        const TypeBlobs& blobs = types[model.getBodyType(b)];
        for (int k = 0; k < (int) blobs.coords.size(); k++) {
            positions.push_back(states[b].position+BodyDynamics::toLab(states[b].rotation, blobs.coords[k]));
            radii.push_back(blobs.radii[k]);
        }
    }
}

Eigen::MatrixXd HydrodynamicInteractions::computeResistance(const vector<BodyState>& states, const Vec3* boxVectors) const {
    const int numBodies = model.getNumBodies();
    vector<Vec3> positions, origins;
    vector<double> radii;
    vector<int> owner;
    placeBlobs(states, positions, radii);
    for (int b = 0; b < numBodies; b++) {
        owner.insert(owner.end(), types[model.getBodyType(b)].coords.size(), b);
        origins.push_back(states[b].position);
    }
    Eigen::MatrixXd r = CoupledResistanceMath::resistance(hydrodynamicsCaller(model.getIntegratorName()), positions, radii, owner, origins, boxVectors, bodyNames(), wallZ);
    // Each body's rows and columns into its frame (Q, lab to body, on its force and its torque),
    // then calibrated: T_a R_ab T_b.
    for (int b = 0; b < numBodies; b++) {
        Eigen::Matrix<double, 6, 6> g = Eigen::Matrix<double, 6, 6>::Zero();
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                g(i, j) = g(i+3, j+3) = states[b].rotation[i][j];
        Eigen::Matrix<double, 6, 6> transform = types[model.getBodyType(b)].calibration*g;
        r.middleRows(6*b, 6) = (transform*r.middleRows(6*b, 6)).eval();
        r.middleCols(6*b, 6) = (r.middleCols(6*b, 6)*transform.transpose()).eval();
    }
    // The active coordinates only.
    vector<int> index;
    for (int b = 0; b < numBodies; b++)
        for (int c : model.getType(model.getBodyType(b)).getActiveCoordinates())
            index.push_back(6*b+c);
    const int n = index.size();
    Eigen::MatrixXd active(n, n);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            active(i, j) = r(index[i], index[j]);
    return 0.5*(active+active.transpose());
}

Eigen::VectorXd HydrodynamicInteractions::getVelocities(const vector<BodyState>& states) const {
    Eigen::VectorXd u(getNumCoordinates());
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        Vec3 v = BodyDynamics::toBody(states[b].rotation, states[b].velocity);
        int c = firstCoordinate[b];
        for (int k = 0; k < 3; k++)
            u[c++] = v[k];
        for (int axis = 0; axis < 3; axis++)
            if (type.rotates(axis))
                u[c++] = states[b].angularMomentum[axis]/type.inertia[axis];
    }
    return u;
}

void HydrodynamicInteractions::setVelocities(const Eigen::VectorXd& u, vector<BodyState>& states) const {
    for (int b = 0; b < model.getNumBodies(); b++) {
        const BodyType& type = model.getType(model.getBodyType(b));
        int c = firstCoordinate[b];
        states[b].velocity = BodyDynamics::toLab(states[b].rotation, Vec3(u[c], u[c+1], u[c+2]));
        c += 3;
        for (int axis = 0; axis < 3; axis++)
            states[b].angularMomentum[axis] = (type.rotates(axis) ? type.inertia[axis]*u[c++] : 0.0);
    }
}

void RigidLangevinPlugin::midpointFrictionStep(const Eigen::MatrixXd& resistance, const Eigen::VectorXd& masses, double viscosity, double kT,
                                               double h, const Eigen::VectorXd& normals, Eigen::VectorXd& u) {
    const double half = 0.5*h*viscosity;
    Eigen::VectorXd rhs = masses.cwiseProduct(u)-half*(resistance*u);
    if (kT > 0) {
        Eigen::LLT<Eigen::MatrixXd> root(resistance);
        if (root.info() != Eigen::Success)
            throw OpenMMException("RigidLangevinIntegrator: the bodies' coupled resistance is not positive definite");
        Eigen::VectorXd noise = root.matrixL()*normals;
        rhs += std::sqrt(2*kT*h*viscosity)*noise;
    }
    Eigen::MatrixXd a = resistance*half;
    a.diagonal() += masses;
    Eigen::LLT<Eigen::MatrixXd> solver(a);
    if (solver.info() != Eigen::Success)
        throw OpenMMException("RigidLangevinIntegrator: the bodies' coupled friction step could not be solved (its matrix is not positive definite)");
    u = solver.solve(rhs);
}

HydrodynamicInteractions::KrylovIterations HydrodynamicInteractions::krylovFrictionStep(const vector<BodyState>& states, double viscosity, double kT, double h,
        const Eigen::VectorXd& normals, Eigen::VectorXd& u, double tolerance, int maxIterations, BlobMobility& blobMobility,
        const Vec3* boxVectors) const {
    using Eigen::VectorXd;
    const int numBodies = model.getNumBodies();
    vector<Vec3> positions;
    vector<double> radii;
    placeBlobs(states, positions, radii);
    const int numBlobs = positions.size();
    vector<int> firstBlob(numBodies);
    for (int b = 0, k = 0; b < numBodies; k += types[model.getBodyType(b)].coords.size(), b++)
        firstBlob[b] = k;
    // What the dense path refuses, refused here before any product: non-finite positions would
    // spend every iteration on NaN, and two blobs the same sphere make M singular.
    validateBlobs(positions, radii, boxVectors);
    const double c = 0.5*h*viscosity;
    // Each type's friction preconditioner, for this c.
    for (int t = 0; t < (int) types.size(); t++) {
        const TypeBlobs& blobs = types[t];
        if (blobs.frictionScale == c)
            continue;
        vector<int> active = model.getType(t).getActiveCoordinates();
        VectorXd inverseMass(active.size());
        for (int i = 0; i < (int) active.size(); i++)
            inverseMass[i] = 1/(active[i] < 3 ? model.getType(t).mass : model.getType(t).inertia[active[i]-3]);
        Eigen::MatrixXd self = blobs.selfMobility.reconstructedMatrix()/c+blobs.velocities*inverseMass.asDiagonal()*blobs.velocities.transpose();
        blobs.friction.compute(self);
        blobs.frictionScale = c;
    }
    // Blob vectors (3 per blob, lab frame) to and from the bodies' frames.
    auto bodyBlobs = [&] (const VectorXd& lab, int b) {
        return turnBlobs(lab.segment(3*firstBlob[b], 3*types[model.getBodyType(b)].coords.size()), states[b].rotation, true);
    };
    auto toLabBlobs = [&] (const VectorXd& frame, int b, VectorXd& lab) {
        lab.segment(3*firstBlob[b], frame.size()) = turnBlobs(frame, states[b].rotation, false);
    };
    // K' u: the blobs' lab velocities; K'^T f: the generalised forces of blob forces f.
    auto applyK = [&] (const VectorXd& v, VectorXd& out) {
        out.resize(3*numBlobs);
        for (int b = 0; b < numBodies; b++) {
            const TypeBlobs& blobs = types[model.getBodyType(b)];
            toLabBlobs(blobs.velocities*v.segment(firstCoordinate[b], blobs.velocities.cols()), b, out);
        }
    };
    auto applyKT = [&] (const VectorXd& f, VectorXd& out) {
        out.resize(getNumCoordinates());
        for (int b = 0; b < numBodies; b++) {
            const TypeBlobs& blobs = types[model.getBodyType(b)];
            out.segment(firstCoordinate[b], blobs.velocities.cols()) = blobs.velocities.transpose()*bodyBlobs(f, b);
        }
    };
    blobMobility.setBlobs(positions, radii, boxVectors);
    KrylovSolvers::Operator mobility = [&] (const VectorXd& f, VectorXd& out) {
        blobMobility.multiply(f, out);
    };
    // Every body's own block of the friction's operator solved in its frame.
    KrylovSolvers::Operator blockSolver = [&] (const VectorXd& in, VectorXd& out) {
        out.resize(in.size());
        for (int b = 0; b < numBodies; b++) {
            const TypeBlobs& blobs = types[model.getBodyType(b)];
            toLabBlobs(blobs.friction.solve(bodyBlobs(in, b)), b, out);
        }
    };
    KrylovIterations iterations = {0, 0, 0};
    const VectorXd& masses = getMasses();
    VectorXd z = 2*masses.cwiseProduct(u);
    if (kT > 0) {
        // Noise of covariance M^-1 as L^-T A^-1/2 w, with A = L^-1 M L^-T preconditioned by every
        // body's own blocks L L^T: one Lanczos on the well-conditioned A, where M^-1 (M^1/2 w) took a
        // Lanczos on M and conjugate gradients (about twice the products, and more as bodies are added).
        KrylovSolvers::Operator preconditioned = preconditionedMobility(states, blobMobility);
        VectorXd root, solved;
        iterations.noise = checkHydrodynamicSolve("the Lanczos inverse square root of the blobs' mobility for the noise (preconditioned by every body's own blocks)",
                                                  KrylovSolvers::lanczosPower(preconditioned, normals, root, -0.5, tolerance, maxIterations), numBodies, numBlobs,
                                                  model.getIntegratorName());
        applySelfFactor(states, InverseLowerTranspose, root, solved);
        VectorXd xi;
        applyKT(solved, xi);
        z += std::sqrt(2*kT*h*viscosity)*xi;
    }
    VectorXd rhs, y;
    applyK(z.cwiseQuotient(masses), rhs);
    KrylovSolvers::Operator schur = [&] (const VectorXd& v, VectorXd& out) {
        VectorXd back, forward;
        mobility(v, out);
        applyKT(v, back);
        applyK(back.cwiseQuotient(masses), forward);
        out = out/c+forward;
    };
    // The friction's y changes little from step to step (the blobs move a little, z keeps part of u):
    // start from the best multiple of the last step's (one product), or from zero after a checkpoint.
    VectorXd startProduct;
    KrylovSolvers::scaledStart(schur, lastFrictionSolution, rhs, y, startProduct);
    const std::string frictionSolve = "the conjugate gradients for the friction (on M/c + K M_b^-1 K^T, M the blobs' mobility)";
    iterations.friction = checkHydrodynamicSolve(frictionSolve, KrylovSolvers::conjugateGradient(schur, blockSolver, rhs, y, tolerance, maxIterations, &startProduct),
                                                 numBodies, numBlobs, model.getIntegratorName());
    VectorXd back;
    applyKT(y, back);
    // The step's (M_b + c R)^-1 z = M_b^-1 (z - K^T y) is, where the friction is strong, much smaller
    // than M_b^-1 z, and y's error, through K^T, larger relative to it by |z|/|z - K^T y| (about
    // gamma h/m): solve on, from y, to the tolerance times that ratio, so that the step is right to
    // the tolerance at any friction (not to floor it below what double precision reaches).
    const double tighter = std::max(tolerance*(z-back).norm()/z.norm(), FrictionToleranceFloor);
    if (tighter < tolerance) {
        // maxIterations bounds the friction's iterations together, and a failure reports them together.
        KrylovSolvers::Result more = KrylovSolvers::conjugateGradient(schur, blockSolver, rhs, y, tighter, maxIterations-iterations.friction);
        more.iterations += iterations.friction;
        iterations.friction = checkHydrodynamicSolve(frictionSolve, more, numBodies, numBlobs, model.getIntegratorName());
        applyKT(y, back);
    }
    if (warmStarts)
        lastFrictionSolution = y;
    u = (z-back).cwiseQuotient(masses)-u;
    return iterations;
}
