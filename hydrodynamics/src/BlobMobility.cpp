#include "internal/BlobMobility.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/PeriodicRotnePragerYamakawa.h"
#include "internal/RotnePragerBlake.h"
#include "openmm/OpenMMException.h"
#include <cmath>

using namespace RigidLangevinPlugin;
using OpenMM::OpenMMException;

void BlobMobility::setWall(double /*wallZ*/) {
    throw OpenMMException("BlobMobility::setWall: this implementation of the blobs' mobility has no no-slip wall");
}

void HostBlobMobility::setWall(double wallZ) {
    if (!std::isfinite(wallZ))
        throw OpenMMException("HostBlobMobility::setWall: the wall's height must be finite (nm)");
    wall = true;
    this->wallZ = wallZ;
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
}

void HostBlobMobility::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    if (stored.size() > 0)
        out.noalias() = stored.selfadjointView<Eigen::Lower>()*f;
    else if (wall)
        RotnePragerBlake::mobilityProduct(positions, radii, wallZ, f, out, parallel);
    else
        CoupledResistanceMath::mobilityProduct(positions, radii, f, out, parallel);
}
