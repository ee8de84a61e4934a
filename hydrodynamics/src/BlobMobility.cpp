#include "internal/BlobMobility.h"
#include "internal/CoupledResistanceMath.h"
#include "internal/PeriodicRotnePragerYamakawa.h"

using namespace RigidLangevinPlugin;

void HostBlobMobility::setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors) {
    this->positions = positions;
    this->radii = radii;
    if (boxVectors != NULL)
        stored = PeriodicRotnePragerYamakawa(boxVectors).mobility(positions, radii, parallel);
    else if ((int) positions.size() <= MaxStoredBlobs)
        stored = CoupledResistanceMath::mobilityMatrix(positions, radii, parallel);
    else
        stored.resize(0, 0);
}

void HostBlobMobility::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    if (stored.size() > 0)
        out.noalias() = stored.selfadjointView<Eigen::Lower>()*f;
    else
        CoupledResistanceMath::mobilityProduct(positions, radii, f, out, parallel);
}
