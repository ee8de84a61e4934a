#include "CommonBlobMobility.h"
#include "CommonRigidLangevinKernelSources.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

CommonBlobMobility::CommonBlobMobility(ComputeContext& cc) : cc(cc), numBlobs(0), periodic(false) {
    if (!cc.getSupportsDoublePrecision())
        throw OpenMMException("RigidLangevinIntegrator: hydrodynamic interactions on this device need double precision, which it does not have; "
                "use another device, the CPU platform, or setHydrodynamicInteractions(false)");
    ContextSelector selector(cc);
    ComputeProgram program = cc.compileProgram(CommonRigidLangevinKernelSources::blobMobility, {{"BLOB_TILE", std::to_string(TileSize)}});
    kernel = program->createKernel("multiplyBlobMobility");
}

void CommonBlobMobility::setBlobs(const vector<Vec3>& positions, const vector<double>& radii, const Vec3* boxVectors) {
    numBlobs = positions.size();
    periodic = (boxVectors != NULL);
    if (periodic) {
        periodicOnHost.setBlobs(positions, radii, boxVectors);
        return;
    }
    ContextSelector selector(cc);
    const int size = std::max(numBlobs, 1);
    if (!blobs.isInitialized()) {
        blobs.initialize<double>(cc, 4*size, "rigidBodyBlobs");
        force.initialize<double>(cc, 3*size, "rigidBodyBlobForce");
        velocity.initialize<double>(cc, 3*size, "rigidBodyBlobVelocity");
        kernel->addArg(numBlobs);
        kernel->addArg(blobs);
        kernel->addArg(force);
        kernel->addArg(velocity);
    }
    else if ((int) blobs.getSize() != 4*size) {
        blobs.resize(4*size);
        force.resize(3*size);
        velocity.resize(3*size);
    }
    vector<double> packed(4*size, 0.0);
    for (int k = 0; k < numBlobs; k++) {
        for (int d = 0; d < 3; d++)
            packed[4*k+d] = positions[k][d];
        packed[4*k+3] = radii[k];
    }
    blobs.upload(packed);
    kernel->setArg(0, numBlobs);
}

void CommonBlobMobility::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    if (f.size() != 3*numBlobs)
        throw OpenMMException("CommonBlobMobility: a product with "+std::to_string(f.size())+" force components for "+std::to_string(numBlobs)+" blobs");
    if (periodic) {
        periodicOnHost.multiply(f, out);
        return;
    }
    out.resize(f.size());
    if (numBlobs == 0)
        return;
    ContextSelector selector(cc);
    force.upload(f.data());
    const int numGroups = (numBlobs+TileSize-1)/TileSize;
    kernel->execute(numGroups*TileSize, TileSize);
    velocity.download(out.data());
}
