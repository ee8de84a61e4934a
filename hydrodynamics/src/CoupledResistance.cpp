#include "CoupledResistance.h"
#include "internal/BeadHydrodynamics.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/PeriodicRotnePragerYamakawa.h"
#include "internal/ResistanceMath.h"
#include "internal/RotnePragerBlake.h"
#include "internal/RotnePragerYamakawa.h"
#include "beadkernel/ParallelFor.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ThreadPool.h"
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <memory>
#include <string>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::ResistanceMath;
using OpenMM::OpenMMException;
using OpenMM::Vec3;
using std::vector;

namespace {

typedef Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Matrix;

/** Blobs from which the dense resistance runs on threads: below, starting them costs more than they save. */
const int ThreadedMinBlobs = 200;

/** A ParallelFor on pool's threads (null: the calling thread), the range cut into chunks that the
 *  threads take as they become free (the rows of a lower triangle are unequal work). */
KrylovSolvers::ParallelFor poolRanges(OpenMM::ThreadPool* pool) {
    return [pool] (int count, const std::function<void (int, int)>& task) {
        const int chunks = (pool == nullptr ? 1 : std::min(count, 8*pool->getNumThreads()));
        parallelFor(pool, chunks, [&] (Eigen::Index c) { task((int) ((long long) count*c/chunks), (int) ((long long) count*(c+1)/chunks)); });
    };
}

/**
 * R = (L^-1 K)^T (L^-1 K) for L the Cholesky factor in factor's lower triangle, symmetric by
 * construction: the triangular solve and R's lower triangle in bands of columns on pool's threads
 * (Eigen's own run on one), the widest of R's bands first. K's column j is zero above row
 * start[j] (its body's first blob), and so is L^-1's product with it: each band's solve and
 * product skip those rows (with bodies in order, a third of the solve's work and less of R's).
 */
Eigen::MatrixXd squareOfSolved(const Eigen::MatrixXd& factor, Eigen::MatrixXd& k, const vector<Eigen::Index>& start, OpenMM::ThreadPool* pool) {
    const Eigen::Index rows = k.rows(), n = k.cols(), band = 48, bands = (n+band-1)/band;
    vector<Eigen::Index> startFrom(n+1, rows);  // the smallest start[j] of the columns from j on
    for (Eigen::Index j = n-1; j >= 0; j--)
        startFrom[j] = std::min(start[j], startFrom[j+1]);
    parallelFor(pool, bands, [&] (Eigen::Index c) {
        const Eigen::Index first = c*band, width = std::min(band, n-first);
        const Eigen::Index top = *std::min_element(start.begin()+first, start.begin()+first+width);
        factor.block(top, top, rows-top, rows-top).triangularView<Eigen::Lower>().solveInPlace(k.block(top, first, rows-top, width));
    });
    Eigen::MatrixXd r(n, n);
    parallelFor(pool, bands, [&] (Eigen::Index c) {
        const Eigen::Index first = c*band, width = std::min(band, n-first), top = startFrom[first];
        r.block(first, first, n-first, width).noalias() = k.block(top, first, rows-top, n-first).transpose()*k.block(top, first, rows-top, width);
    });
    return r.selfadjointView<Eigen::Lower>();
}

std::vector<double> toVector(const Matrix& m) {
    return std::vector<double>(m.data(), m.data()+m.size());
}

} // namespace

int CoupledResistance::addBody(const vector<Vec3>& blobPositions, const vector<double>& blobRadii, const Vec3& origin) {
    std::string name = "CoupledResistance::addBody (body "+std::to_string(getNumBodies())+")";
    BeadHydrodynamics::validate(name, blobPositions, blobRadii);
    if (!std::isfinite(origin[0]) || !std::isfinite(origin[1]) || !std::isfinite(origin[2]))
        throw OpenMMException(name+": the reference point is not finite");
    blobs.push_back(blobPositions);
    radii.push_back(blobRadii);
    origins.push_back(origin);
    ownResistance.push_back(vector<double>());
    return origins.size()-1;
}

CoupledResistance::CoupledResistance() : periodic(false), wall(false), wallZ(0) {
}

void CoupledResistance::setPeriodicBox(const Vec3& a, const Vec3& b, const Vec3& c) {
    if (wall)
        throw OpenMMException("CoupledResistance::setPeriodicBox: the bodies are above a no-slip wall (setWall()); a wall and a periodic box together are not supported");
    Vec3 vectors[3] = {a, b, c};
    PeriodicRotnePragerYamakawa check(vectors);  // refuses a box that is not one
    for (int i = 0; i < 3; i++)
        box[i] = vectors[i];
    periodic = true;
}

void CoupledResistance::setWall(double z0) {
    if (periodic)
        throw OpenMMException("CoupledResistance::setWall: the bodies are in a periodic box (setPeriodicBox()); a wall and a periodic box together are not supported");
    if (!std::isfinite(z0))
        throw OpenMMException("CoupledResistance::setWall: the wall's height is not finite; give z0 in nm");
    wall = true;
    wallZ = z0;
}

void CoupledResistance::setBodyResistance(int body, const ResistanceTensor& own) {
    if (body < 0 || body >= getNumBodies())
        throw OpenMMException("CoupledResistance::setBodyResistance: there is no body "+std::to_string(body)+" (there are "+std::to_string(getNumBodies())+")");
    ownResistance[body] = own.getMatrix(origins[body]);
}

vector<double> CoupledResistance::getResistance() const {
    const int numBodies = getNumBodies();
    if (numBodies == 0)
        throw OpenMMException("CoupledResistance::getResistance: no bodies have been added");
    vector<Vec3> positions;
    vector<double> allRadii;
    vector<int> owner;
    for (int b = 0; b < numBodies; b++)
        for (int k = 0; k < (int) blobs[b].size(); k++) {
            positions.push_back(blobs[b][k]);
            allRadii.push_back(radii[b][k]);
            owner.push_back(b);
        }
    Matrix resistance = CoupledResistanceMath::resistance("CoupledResistance::getResistance", positions, allRadii, owner, origins, periodic ? box : NULL,
                                                          CoupledResistanceMath::BodyNames(), wall ? std::optional<double>(wallZ) : std::nullopt);
    // Calibrated bodies: T^T R T, T block-diagonal, each block from the body's blobs alone.
    for (int b = 0; b < numBodies; b++) {
        if (ownResistance[b].empty())
            continue;
        std::string name = "CoupledResistance::getResistance (body "+std::to_string(b)+")";
        Eigen::MatrixXd alone = CoupledResistanceMath::resistance(name, blobs[b], radii[b], vector<int>(blobs[b].size(), 0), {origins[b]}, NULL,
                                                                  [b] (int) { return "body "+std::to_string(b); });
        Eigen::MatrixXd own = Eigen::Map<const Matrix>(ownResistance[b].data(), 6, 6);
        Eigen::MatrixXd t = CoupledResistanceMath::calibration(name, alone, own);
        resistance.middleRows(6*b, 6) = (t*resistance.middleRows(6*b, 6)).eval();
        resistance.middleCols(6*b, 6) = (resistance.middleCols(6*b, 6)*t).eval();
    }
    resistance = (0.5*(resistance+resistance.transpose())).eval();
    return toVector(resistance);
}

vector<double> CoupledResistance::getMobility() const {
    const int n = 6*getNumBodies();
    vector<double> values = getResistance();
    Eigen::Map<Matrix> resistance(values.data(), n, n);
    // A body that cannot rotate about some axis (one blob, or blobs on a line) leaves R singular:
    // name it rather than return an inverse of rounding errors.
    for (int b = 0; b < getNumBodies(); b++) {
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> rotation(resistance.block<3, 3>(6*b+3, 6*b+3));
        if (!(rotation.eigenvalues()[0] > 1e-10*rotation.eigenvalues()[2]) || rotation.eigenvalues()[2] <= 0)
            throw OpenMMException("CoupledResistance::getMobility: body "+std::to_string(b)+" has no friction for some rotation (it is one blob, "
                                  "or blobs on one line), so the bodies' resistance has no inverse; give it blobs off its axis");
    }
    Eigen::LLT<Matrix> cholesky(resistance);
    if (cholesky.info() != Eigen::Success)
        throw OpenMMException("CoupledResistance::getMobility: the bodies' resistance is not positive definite");
    Matrix mobility = cholesky.solve(Matrix::Identity(n, n));
    mobility = (0.5*(mobility+mobility.transpose())).eval();
    return toVector(mobility);
}

void CoupledResistanceMath::validateBlobs(const std::string& caller, const vector<Vec3>& positions, const vector<double>& radii, const vector<int>& owner,
                                          const Vec3* boxVectors, const BodyNames& bodyNames, std::optional<double> wallZ) {
    // Each blob by its index in its body: blob i's owner holds the blobs since the body's first.
    auto names = [&] (int i) {
        int first = i;
        while (first > 0 && owner[first-1] == owner[i])
            first--;
        return "blob "+std::to_string(i-first)+" of "+(bodyNames ? bodyNames(owner[i]) : "body "+std::to_string(owner[i]));
    };
    if (owner.size() != positions.size())
        throw OpenMMException(caller+": "+std::to_string(positions.size())+" blobs but "+std::to_string(owner.size())+" owners");
    BeadHydrodynamics::validate(caller, positions, radii, names);
    if (boxVectors != NULL && wallZ)
        throw OpenMMException(caller+": bodies above a no-slip wall cannot also be in a periodic box (that is not supported)");
    if (boxVectors != NULL)
        PeriodicRotnePragerYamakawa(boxVectors).validate(caller, positions, radii, names);
    if (wallZ)
        RotnePragerBlake::validate(caller, positions, radii, *wallZ, names);
}

Eigen::MatrixXd CoupledResistanceMath::resistance(const std::string& caller, const vector<Vec3>& positions, const vector<double>& radii,
                                                  const vector<int>& owner, const vector<Vec3>& origins, const Vec3* boxVectors, const BodyNames& bodyNames,
                                                  std::optional<double> wallZ) {
    // Two bodies may hold the same sphere: M would be singular, and the message names both blobs.
    validateBlobs(caller, positions, radii, owner, boxVectors, bodyNames, wallZ);
    const int numBlobs = positions.size();
    const int numBodies = origins.size();
    // OPENMM_CPU_THREADS threads (BeadHydrodynamics::getNumThreads()) where there is work enough.
    std::unique_ptr<OpenMM::ThreadPool> pool;
    if (numBlobs >= ThreadedMinBlobs && BeadHydrodynamics::getNumThreads() > 1)
        pool.reset(new OpenMM::ThreadPool(BeadHydrodynamics::getNumThreads()));
    const KrylovSolvers::ParallelFor parallel = poolRanges(pool.get());
    // The lower triangle is enough.
    Eigen::MatrixXd mobility = (boxVectors != NULL ? PeriodicRotnePragerYamakawa(boxVectors).mobility(positions, radii, parallel) :
                                wallZ ? RotnePragerBlake::mobilityMatrix(positions, radii, *wallZ, parallel) : mobilityMatrix(positions, radii, parallel));
    // K: blob k of body b moves at V_b - skew(r_k - o_b) omega_b; its body's columns start at its first blob.
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(3*numBlobs, 6*numBodies);
    vector<Eigen::Index> start(6*numBodies, 3*numBlobs);
    for (int i = numBlobs-1; i >= 0; i--) {
        int b = owner[i];
        k.block<3, 3>(3*i, 6*b) = Eigen::Matrix3d::Identity();
        k.block<3, 3>(3*i, 6*b+3) = -skew(toEigen(positions[i]-origins[b]));
        std::fill(start.begin()+6*b, start.begin()+6*b+6, 3*i);
    }
    if (!BeadHydrodynamics::choleskyInPlace(mobility.rows(), mobility.data(), pool ? pool->getNumThreads() : 1))
        throw OpenMMException(caller+": the blobs' mobility matrix could not be factorised (look for nearly coincident blobs)");
    return squareOfSolved(mobility, k, start, pool.get());
}

Eigen::MatrixXd CoupledResistanceMath::mobilityMatrix(const vector<Vec3>& positions, const vector<double>& radii, const KrylovSolvers::ParallelFor& parallel) {
    return lowerTriangle(positions.size(), [&] (int i, int j, double block[9]) {
        if (i == j) {
            const double self = RotnePragerYamakawa::selfMobility(radii[i]);
            for (int k = 0; k < 9; k++)
                block[k] = (k%4 == 0 ? self : 0.0);
            return;
        }
        Vec3 d = positions[j]-positions[i];
        RotnePragerYamakawa::mobilityBlock(d[0], d[1], d[2], radii[i], radii[j], block);
    }, parallel);
}

void CoupledResistanceMath::mobilityProduct(const vector<Vec3>& positions, const vector<double>& radii, const Eigen::VectorXd& f, Eigen::VectorXd& out,
                                            const KrylovSolvers::ParallelFor& parallel) {
    const int n = positions.size();
    out.resize(3*n);
    parallel(n, [&] (int begin, int end) {
        for (int i = begin; i < end; i++) {
            double self = RotnePragerYamakawa::selfMobility(radii[i]);
            double v[3] = {self*f[3*i], self*f[3*i+1], self*f[3*i+2]};
            for (int j = 0; j < n; j++) {
                if (j == i)
                    continue;
                double block[9];
                Vec3 d = positions[j]-positions[i];
                RotnePragerYamakawa::mobilityBlock(d[0], d[1], d[2], radii[i], radii[j], block);
                for (int k = 0; k < 3; k++)
                    v[k] += block[3*k]*f[3*j]+block[3*k+1]*f[3*j+1]+block[3*k+2]*f[3*j+2];
            }
            out[3*i] = v[0];
            out[3*i+1] = v[1];
            out[3*i+2] = v[2];
        }
    });
}

Eigen::MatrixXd CoupledResistanceMath::calibration(const std::string& caller, const Eigen::MatrixXd& blobResistance, const Eigen::MatrixXd& own) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> d(blobResistance);
    Eigen::VectorXd lambda = d.eigenvalues();
    if (!(lambda[0] > 1e-10*lambda[lambda.size()-1]))
        throw OpenMMException(caller+": its blobs do not resist every motion it can make (the smallest eigenvalue of their resistance is "+
                              std::to_string(lambda[0])+" of the largest "+std::to_string(lambda[lambda.size()-1])+"): give it blobs that resolve its shape");
    Eigen::MatrixXd root = d.eigenvectors()*lambda.cwiseSqrt().asDiagonal()*d.eigenvectors().transpose();
    Eigen::MatrixXd inverseRoot = d.eigenvectors()*lambda.cwiseSqrt().cwiseInverse().asDiagonal()*d.eigenvectors().transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> s(root*own*root);
    if (!(s.eigenvalues()[0] > 0))
        throw OpenMMException(caller+": its own resistance tensor is not positive definite");
    Eigen::MatrixXd middle = s.eigenvectors()*s.eigenvalues().cwiseSqrt().asDiagonal()*s.eigenvectors().transpose();
    Eigen::MatrixXd t = inverseRoot*middle*inverseRoot;
    return 0.5*(t+t.transpose());
}
