#include "internal/BodyMobility.h"
#include "internal/BodyDynamics.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <limits>

using namespace RigidLangevinPlugin;
using Eigen::VectorXd;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

/** A body's blob vector (3 per blob) from the lab frame into its frame (toBody), or back. */
VectorXd turnBlobs(const VectorXd& v, const double q[3][3], bool toBody) {
    VectorXd out(v.size());
    for (int k = 0; k < v.size()/3; k++) {
        Vec3 w(v[3*k], v[3*k+1], v[3*k+2]);
        w = (toBody ? BodyDynamics::toBody(q, w) : BodyDynamics::toLab(q, w));
        out.segment<3>(3*k) << w[0], w[1], w[2];
    }
    return out;
}

} // namespace

BodyMobility::BodyMobility(const HydrodynamicInteractions& interactions) : interactions(interactions), model(interactions.getModel()), numBlobs(0) {
    for (int t = 0; t < model.getNumTypes(); t++) {
        const Eigen::MatrixXd& k = interactions.getTypeBlobVelocities(t);
        ownResistance.emplace_back(Eigen::MatrixXd(k.transpose()*interactions.getTypeSelfMobility(t).solve(k)));
    }
    for (int b = 0; b < model.getNumBodies(); b++) {
        firstBlob.push_back(numBlobs);
        numBlobs += interactions.getTypeBlobVelocities(model.getBodyType(b)).rows()/3;
    }
    // The saddle-point problem's scales (see scaling()): the smallest blob radius, and a blob's
    // Stokes mobility per unit viscosity at that radius.
    scaleLength = std::numeric_limits<double>::infinity();
    for (int t = 0; t < model.getNumTypes(); t++) {
        vector<Vec3> coords;
        vector<double> radii;
        model.getTypeBlobs(t, coords, radii);
        for (double r : radii)
            scaleLength = std::min(scaleLength, r);
    }
    scaleMobility = 1/(6*M_PI*scaleLength);
}

VectorXd BodyMobility::scaling(bool rows) const {
    // The blob rows (velocities) and the coordinate rows (forces, torques) of the saddle-point
    // problem differ by a mobility, torques from forces by a length: by about 1/(6 pi a) and a for
    // blobs of radius a. GMRES stops on the norm of all rows together, so unscaled the blob rows
    // would weigh 1/(6 pi a) as much as the forces: in colloid units (a of hundreds of nm) a
    // solve to 1e-3 would stop once each body's forces balance, before the blobs' velocities felt
    // the wall or the other bodies. Rows: blob rows / m0, torque rows / a; columns (unknowns):
    // velocities * m0, angular velocities * m0/a, so that every entry is a force of order one.
    const int blobs = 3*numBlobs;
    VectorXd d(blobs+interactions.getNumCoordinates());
    d.head(blobs).setConstant(rows ? 1/scaleMobility : 1.0);
    for (int b = 0; b < model.getNumBodies(); b++) {
        const int first = blobs+interactions.getFirstCoordinate(b), n = interactions.getTypeBlobVelocities(model.getBodyType(b)).cols();
        d.segment(first, 3).setConstant(rows ? 1.0 : scaleMobility);
        d.segment(first+3, n-3).setConstant(rows ? 1/scaleLength : scaleMobility/scaleLength);
    }
    return d;
}

void BodyMobility::factorize(const vector<BodyState>& states, const Vec3* box) {
    dense.compute(interactions.computeResistance(states, box));
    if (dense.info() != Eigen::Success)
        throw OpenMMException("RigidLangevinIntegrator: hydrodynamic interactions: the bodies' coupled resistance is not positive definite");
}

void BodyMobility::denseMultiply(const VectorXd& g, VectorXd& out) const {
    out = dense.solve(g);
}

void BodyMobility::denseNoise(const VectorXd& w, VectorXd& out) const {
    // R = L L^T: L^-T w has covariance L^-T L^-1 = R^-1 = N.
    out = dense.matrixU().solve(w);
}

void BodyMobility::placeBlobs(const vector<BodyState>& states, BlobMobility& mobility, const Vec3* box) {
    vector<Vec3> positions;
    vector<double> radii;
    interactions.placeBlobs(states, positions, radii);
    interactions.validateBlobs(positions, radii, box);
    mobility.setBlobs(positions, radii, box);
}

void BodyMobility::applyK(const vector<BodyState>& states, const VectorXd& u, VectorXd& out) const {
    out.resize(3*numBlobs);
    for (int b = 0; b < model.getNumBodies(); b++) {
        const Eigen::MatrixXd& k = interactions.getTypeBlobVelocities(model.getBodyType(b));
        out.segment(3*firstBlob[b], k.rows()) = turnBlobs(k*u.segment(interactions.getFirstCoordinate(b), k.cols()), states[b].rotation, false);
    }
}

void BodyMobility::applyKT(const vector<BodyState>& states, const VectorXd& f, VectorXd& out) const {
    out.resize(interactions.getNumCoordinates());
    for (int b = 0; b < model.getNumBodies(); b++) {
        const Eigen::MatrixXd& k = interactions.getTypeBlobVelocities(model.getBodyType(b));
        out.segment(interactions.getFirstCoordinate(b), k.cols()) = k.transpose()*turnBlobs(f.segment(3*firstBlob[b], k.rows()), states[b].rotation, true);
    }
}

void BodyMobility::saddleProduct(const vector<BodyState>& states, BlobMobility& mobility, const VectorXd& in, VectorXd& out) const {
    // [M lambda - K' U; -K'^T lambda]
    const int blobs = 3*numBlobs;
    VectorXd lambda = in.head(blobs), u = in.tail(in.size()-blobs), m, ku, ktl;
    mobility.multiply(lambda, m);
    applyK(states, u, ku);
    applyKT(states, lambda, ktl);
    out.resize(in.size());
    out.head(blobs) = m-ku;
    out.tail(in.size()-blobs) = -ktl;
}

void BodyMobility::blockPreconditioner(const vector<BodyState>& states, const VectorXd& in, VectorXd& out) const {
    // Each body's own saddle-point problem solved exactly in its frame: with r1 its blobs' part and
    // r2 its coordinates', U = -D^-1 (r2 + K'^T M_bb^-1 r1), lambda = M_bb^-1 (r1 + K' U), D its
    // blobs' own resistance K'^T M_bb^-1 K'.
    const int blobs = 3*numBlobs;
    out.resize(in.size());
    for (int b = 0; b < model.getNumBodies(); b++) {
        const int t = model.getBodyType(b);
        const Eigen::MatrixXd& k = interactions.getTypeBlobVelocities(t);
        const Eigen::LLT<Eigen::MatrixXd>& self = interactions.getTypeSelfMobility(t);
        const int first = interactions.getFirstCoordinate(b);
        VectorXd r1 = turnBlobs(in.segment(3*firstBlob[b], k.rows()), states[b].rotation, true);
        VectorXd m1 = self.solve(r1);
        VectorXd u = -ownResistance[t].solve(in.segment(blobs+first, k.cols())+k.transpose()*m1);
        out.segment(3*firstBlob[b], k.rows()) = turnBlobs(m1+self.solve(k*u), states[b].rotation, false);
        out.segment(blobs+first, k.cols()) = u;
    }
}

int BodyMobility::solve(const vector<BodyState>& states, const VectorXd& g, const VectorXd& slip, VectorXd& out, double tolerance, int maxIterations,
                        BlobMobility& mobility, const Vec3* box) {
    placeBlobs(states, mobility, box);
    const int blobs = 3*numBlobs, coordinates = interactions.getNumCoordinates();
    VectorXd rhs(blobs+coordinates), x;
    rhs.head(blobs) = (slip.size() == 0 ? VectorXd(VectorXd::Zero(blobs)) : VectorXd(-slip));
    rhs.tail(coordinates) = -g;
    // GMRES on the scaled problem (S_r A S_c) (S_c^-1 x) = S_r b, preconditioned by S_c^-1 P S_r^-1.
    const VectorXd rows = scaling(true), columns = scaling(false);
    KrylovSolvers::Operator product = [&] (const VectorXd& in, VectorXd& result) {
        saddleProduct(states, mobility, VectorXd(columns.cwiseProduct(in)), result);
        result = rows.cwiseProduct(result);
    };
    KrylovSolvers::Operator preconditioner = [&] (const VectorXd& in, VectorXd& result) {
        blockPreconditioner(states, VectorXd(in.cwiseQuotient(rows)), result);
        result = result.cwiseQuotient(columns);
    };
    int iterations = checkHydrodynamicSolve("GMRES for the bodies' mobility (the saddle-point problem of their blobs)",
                                            KrylovSolvers::gmres(product, preconditioner, VectorXd(rows.cwiseProduct(rhs)), x, tolerance, maxIterations),
                                            model.getNumBodies(), numBlobs);
    out = columns.tail(coordinates).cwiseProduct(x.tail(coordinates));
    return iterations;
}

void BodyMobility::applyOwnFactor(const vector<BodyState>& states, const VectorXd& in, VectorXd& out, OwnFactor which) const {
    // Body b's own blobs' mobility in the lab frame is Q M_b Q^T = (Q L_b)(Q L_b)^T, Q its rotation
    // on every blob and L_b the Cholesky factor of M_b (its frame's, factorised once per type).
    out.resize(in.size());
    for (int b = 0; b < model.getNumBodies(); b++) {
        const Eigen::LLT<Eigen::MatrixXd>& self = interactions.getTypeSelfMobility(model.getBodyType(b));
        const int first = 3*firstBlob[b], size = self.rows();
        const VectorXd segment = in.segment(first, size);
        if (which == Factor)
            out.segment(first, size) = turnBlobs(self.matrixL()*segment, states[b].rotation, false);
        else if (which == Inverse)
            out.segment(first, size) = self.matrixL().solve(turnBlobs(segment, states[b].rotation, true));
        else
            out.segment(first, size) = turnBlobs(self.matrixU().solve(segment), states[b].rotation, false);
    }
}

int BodyMobility::blobNoise(const vector<BodyState>& states, const VectorXd& w, VectorXd& slip, double tolerance, int maxIterations,
                            BlobMobility& mobility, const Vec3* box) {
    // Lanczos on L^-1 M L^-T, L every body's own blocks' factor (applyOwnFactor): close to the
    // identity wherever a body's own blobs dominate its mobility, so it converges in a few
    // iterations (RigidMultiblobsWall's preconditioning). slip = L (L^-1 M L^-T)^1/2 w has
    // covariance M, as M^1/2 w has.
    placeBlobs(states, mobility, box);
    KrylovSolvers::Operator product = [&] (const VectorXd& in, VectorXd& result) {
        VectorXd spread, moved;
        applyOwnFactor(states, in, spread, InverseTranspose);
        mobility.multiply(spread, moved);
        applyOwnFactor(states, moved, result, Inverse);
    };
    VectorXd root;
    const int iterations = checkHydrodynamicSolve("the Lanczos square root of the blobs' mobility for the noise",
                                                  KrylovSolvers::lanczosSquareRoot(product, w, root, tolerance, maxIterations), model.getNumBodies(), numBlobs);
    applyOwnFactor(states, root, slip, Factor);
    return iterations;
}
