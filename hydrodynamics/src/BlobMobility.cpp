#include "internal/BlobMobility.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/PeriodicRotnePragerYamakawa.h"
#include "internal/RotnePragerBlake.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>

using namespace RigidLangevinPlugin;
using OpenMM::OpenMMException;

void BlobMobility::setWall(double /*wallZ*/) {
    throw OpenMMException("BlobMobility::setWall: this implementation of the blobs' mobility has no no-slip wall");
}

KrylovSolvers::Result BlobMobility::sampleNoise(const std::function<double()>&, Eigen::VectorXd&, double, int) {
    throw OpenMM::OpenMMException("BlobMobility: this product has no noise of its own (hasOwnNoise() is false): take a Lanczos square root of M");
}

void HostBlobMobility::setWall(double wallZ) {
    if (!std::isfinite(wallZ))
        throw OpenMMException("HostBlobMobility::setWall: the wall's height must be finite (nm)");
    wall = true;
    this->wallZ = wallZ;
}

void HostBlobMobility::setTolerance(double tolerance) {
    tiled.setSinglePrecision(tolerance >= SinglePrecisionTolerance);
}

void HostBlobMobility::setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors) {
    const std::string caller = "HostBlobMobility::setBlobs";
    if (wall && boxVectors != NULL)
        throw OpenMMException(caller+": blobs above a no-slip wall cannot also be in a periodic box (that is not supported)");
    if (wall)
        RotnePragerBlake::validate(caller, positions, radii, wallZ);
    this->positions = positions;
    this->radii = radii;
    if (boxVectors != NULL)
        stored = PeriodicRotnePragerYamakawa(boxVectors).mobility(positions, radii, parallel);
    else if ((int) positions.size() > maxStoredBlobs)
        stored.resize(0, 0);
    else if (wall)
        stored = RotnePragerBlake::mobilityMatrix(positions, radii, wallZ, parallel);
    else
        stored = CoupledResistanceMath::mobilityMatrix(positions, radii, parallel);
    if (stored.size() > 0)
        fillUpperTriangle();
    else if (wall)
        tiled.setBlobsAboveWall(positions, radii, wallZ);
    else
        tiled.setBlobs(positions, radii);
}

void HostBlobMobility::fillUpperTriangle() {
    // Column j's part above the diagonal from row j's below it: each thread its own columns.
    parallel(stored.cols(), [&] (int begin, int end) {
        for (int j = begin; j < end; j++)
            for (int i = 0; i < j; i++)
                stored(i, j) = stored(j, i);
    });
}

void HostBlobMobility::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    if (stored.size() > 0) {
        // M is symmetric and stored whole: its rows [3 begin, 3 end) are those columns transposed,
        // each thread's a contiguous block of memory.
        out.resize(f.size());
        parallel(positions.size(), [&] (int begin, int end) {
            out.segment(3*begin, 3*(end-begin)).noalias() = stored.middleCols(3*begin, 3*(end-begin)).transpose()*f;
        });
    }
    else
        tiled.multiply(f, out, parallel);
}
