#include "internal/BodyMobility.h"
#include "internal/BodyDynamics.h"
#include "openmm/OpenMMException.h"
#include <cmath>

using namespace RigidLangevinPlugin;
using Eigen::VectorXd;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

BodyMobility::BodyMobility(const HydrodynamicInteractions& interactions) : interactions(interactions), model(interactions.getModel()), numBlobs(0) {
    for (int t = 0; t < model.getNumTypes(); t++) {
        const Eigen::MatrixXd& k = interactions.getTypeBlobVelocities(t);
        ownResistance.emplace_back(Eigen::MatrixXd(k.transpose()*interactions.getTypeSelfMobility(t).solve(k)));
    }
    for (int b = 0; b < model.getNumBodies(); b++) {
        firstBlob.push_back(numBlobs);
        numBlobs += interactions.getTypeBlobVelocities(model.getBodyType(b)).rows()/3;
    }
}

void BodyMobility::factorize(const vector<BodyState>& states, const Vec3* box) {
    dense.compute(interactions.computeResistance(states, box));
    if (dense.info() != Eigen::Success)
        throw OpenMMException(hydrodynamicsCaller(model.getIntegratorName())+": the bodies' coupled resistance is not positive definite");
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

VectorXd BodyMobility::unitScales(double& mu0) const {
    // Blob forces stay as they are; a body's translational velocity is measured in mu0 (a blob of
    // the smallest radius a under unit force) and its rotation rates in mu0/a.
    const double a = interactions.getSmallestBlobRadius();
    mu0 = 1/(6*M_PI*a);
    VectorXd d = VectorXd::Ones(3*numBlobs+interactions.getNumCoordinates());
    for (int b = 0; b < model.getNumBodies(); b++) {
        const int first = 3*numBlobs+interactions.getFirstCoordinate(b);
        const int n = model.getType(model.getBodyType(b)).getNumDegreesOfFreedom();
        d.segment(first, n).setConstant(mu0/a);
        d.segment(first, 3).setConstant(mu0);
    }
    return d;
}

int BodyMobility::solve(const vector<BodyState>& states, const VectorXd& g, const VectorXd& slip, VectorXd& out, double tolerance, int maxIterations,
                        BlobMobility& mobility, const Vec3* box, VectorXd* blobForces) {
    placeBlobs(states, mobility, box);
    const int blobs = 3*numBlobs, coordinates = interactions.getNumCoordinates();
    VectorXd rhs(blobs+coordinates), x;
    rhs.head(blobs) = (slip.size() == 0 ? VectorXd(VectorXd::Zero(blobs)) : VectorXd(-slip));
    rhs.tail(coordinates) = -g;
    // GMRES stops at a relative residual of the whole vector, so its parts must be comparable: the
    // system is solved as (D A D/mu0) y = D b/mu0, x = D y, with D = unitScales(). Then blob velocities
    // are in mu0 per unit force, forces and torques per a: without it, in nm, the blobs' rows (about
    // mu0 ~ 1e-4 of the bodies') held no weight in the residual and the velocities from them were wrong
    // by up to 7% at any tolerance.
    double mu0;
    const VectorXd d = unitScales(mu0);
    KrylovSolvers::Operator product = [&] (const VectorXd& in, VectorXd& result) {
        saddleProduct(states, mobility, d.cwiseProduct(in), result);
        result = d.cwiseProduct(result)/mu0;
    };
    KrylovSolvers::Operator preconditioner = [&] (const VectorXd& in, VectorXd& result) {
        blockPreconditioner(states, in.cwiseQuotient(d), result);
        result = mu0*result.cwiseQuotient(d);
    };
    int iterations = checkHydrodynamicSolve("GMRES for the bodies' mobility (the saddle-point problem of their blobs)",
                                            KrylovSolvers::gmres(product, preconditioner, d.cwiseProduct(rhs)/mu0, x, tolerance, maxIterations),
                                            model.getNumBodies(), numBlobs, model.getIntegratorName());
    out = d.tail(coordinates).cwiseProduct(x.tail(coordinates));
    if (blobForces != NULL)
        *blobForces = d.head(blobs).cwiseProduct(x.head(blobs));
    return iterations;
}

void BodyMobility::blobVelocities(const vector<BodyState>& states, const VectorXd& f, VectorXd& out, BlobMobility& mobility, const Vec3* box) {
    placeBlobs(states, mobility, box);
    mobility.multiply(f, out);
}

int BodyMobility::blobNoise(const vector<BodyState>& states, const std::function<double ()>& normal, VectorXd& slip, double tolerance,
                            int maxIterations, BlobMobility& mobility, const Vec3* box) {
    placeBlobs(states, mobility, box);
    if (mobility.hasOwnNoise())
        return checkHydrodynamicSolve("the Lanczos square root of the positively split Ewald sum's real-space part for the noise",
                                      mobility.sampleNoise(normal, slip, tolerance, maxIterations), model.getNumBodies(), numBlobs,
                                      model.getIntegratorName());
    VectorXd w(3*numBlobs);
    for (int i = 0; i < w.size(); i++)
        w[i] = normal();
    // slip = L A^1/2 w with A = L^-1 M L^-T, L L^T every body's own blocks of M: covariance L A L^T = M,
    // in the iterations of the well-conditioned A rather than of M.
    VectorXd root;
    int iterations = checkHydrodynamicSolve("the Lanczos square root of the blobs' mobility for the noise (preconditioned by every body's own blocks)",
                                            KrylovSolvers::lanczosPower(interactions.preconditionedMobility(states, mobility), w, root, 0.5, tolerance,
                                                                        maxIterations), model.getNumBodies(), numBlobs, model.getIntegratorName());
    interactions.applySelfFactor(states, HydrodynamicInteractions::Lower, root, slip);
    return iterations;
}
