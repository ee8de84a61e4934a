#include "CommonBlobMobility.h"
#include "CommonArrays.h"
#include "CommonRigidLangevinKernelSources.h"
#include "openmm/OpenMMException.h"
#include "internal/TiledBlobProduct.h"
#include "openmm/common/ContextSelector.h"
#include <algorithm>

using namespace RigidLangevinPlugin;
using namespace OpenMM;
using std::vector;

CommonBlobMobility::CommonBlobMobility(ComputeContext& cc, const std::string& integrator)
        : cc(cc), numBlobs(0), numParts(1), tilesPerPart(1), periodic(false), wall(false), singleRequested(false), single(false), lengthScale(1) {
    if (!cc.getSupportsDoublePrecision())
        throw OpenMMException(integrator+": hydrodynamic interactions on this device need double precision, which it does not have; "
                "use another device, the CPU platform, or setHydrodynamicInteractions(false)");
}

void CommonBlobMobility::bindProductKernel() {
    ComputeKernel& product = kernels[single ? 1 : 0];
    if (product == NULL) {
        ComputeProgram program = cc.compileProgram(CommonRigidLangevinKernelSources::blobMobility,
                {{"BLOB_TILE", std::to_string(TileSize)}, {"PAIR_SINGLE", single ? "1" : "0"}});
        product = program->createKernel("multiplyBlobMobility");
        for (int k = 0; k < 3; k++)
            product->addArg(0);
        product->addArg(1.0);
        product->addArg(1.0);
        product->addArg(blobs);
        product->addArg(force);
        product->addArg(velocity);
        if (sumKernel == NULL) {
            sumKernel = program->createKernel("sumBlobMobilityParts");
            sumKernel->addArg(0);
            sumKernel->addArg(0);
            sumKernel->addArg(parts);
            sumKernel->addArg(velocity);
        }
    }
    product->setArg(0, numBlobs);
    product->setArg(1, numParts);
    product->setArg(2, tilesPerPart);
    product->setArg(3, lengthScale);
    // With one part the kernel writes the velocity itself and the sum is skipped.
    product->setArg(7, numParts == 1 ? velocity : parts);
    sumKernel->setArg(0, numBlobs);
    sumKernel->setArg(1, numParts);
}

void CommonBlobMobility::setBlobs(const vector<Vec3>& positions, const vector<double>& radii, const Vec3* boxVectors) {
    numBlobs = positions.size();
    periodic = (boxVectors != NULL);
    if (periodic || wall) {
        onHost.setBlobs(positions, radii, boxVectors);
        return;
    }
    ContextSelector selector(cc);
    const int size = std::max(numBlobs, 1);
    // One work item per blob left a GPU mostly idle below some 1e5 blobs (an H200's products of 1e3
    // to 3e4 blobs reached 1.5e9 to 3.9e10 blob pairs a second): the sums over j are split into
    // parts, each a work group per tile of i, until there are as many (tile, part) tasks as the
    // work groups OpenMM launches at most (getNumThreadBlocks(), what fills the device; a launch of
    // more is cut to that many, and the kernel's groups loop over the tasks). Contiguous runs of
    // tiles; no part empty.
    const int numTiles = (size+TileSize-1)/TileSize;
    const int wantedGroups = std::max(MinWorkGroups, cc.getNumThreadBlocks());
    const int wantedParts = std::min(numTiles, (wantedGroups+numTiles-1)/numTiles);
    tilesPerPart = (numTiles+wantedParts-1)/wantedParts;
    numParts = (numTiles+tilesPerPart-1)/tilesPerPart;
    fitArray(cc, blobs, 4*size, sizeof(double), "rigidBodyBlobs", ArrayFit::Exact);
    fitArray(cc, force, 3*size, sizeof(double), "rigidBodyBlobForce", ArrayFit::Exact);
    fitArray(cc, velocity, 3*size, sizeof(double), "rigidBodyBlobVelocity", ArrayFit::Exact);
    fitArray(cc, parts, 3*size*numParts, sizeof(double), "rigidBodyBlobVelocityParts", ArrayFit::Exact);
    single = singleRequested && TiledBlobProduct::radiiFitSinglePrecision(radii.data(), numBlobs);
    lengthScale = (single ? TiledBlobProduct::powerOfTwoAbove(radii.data(), numBlobs) : 1.0);
    bindProductKernel();
    vector<double> packed(4*size, 0.0);
    for (int k = 0; k < numBlobs; k++) {
        for (int d = 0; d < 3; d++)
            packed[4*k+d] = positions[k][d];
        packed[4*k+3] = radii[k];
    }
    blobs.upload(packed);
}

void CommonBlobMobility::setWall(double wallZ) {
    onHost.setWall(wallZ);
    wall = true;
}

void CommonBlobMobility::setTolerance(double tolerance) {
    onHost.setTolerance(tolerance);
    singleRequested = (tolerance >= HostBlobMobility::SinglePrecisionTolerance);
}

void CommonBlobMobility::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) {
    if (f.size() != 3*numBlobs)
        throw OpenMMException("CommonBlobMobility: a product with "+std::to_string(f.size())+" force components for "+std::to_string(numBlobs)+" blobs");
    if (periodic || wall) {
        onHost.multiply(f, out);
        return;
    }
    out.resize(f.size());
    if (numBlobs == 0)
        return;
    ContextSelector selector(cc);
    force.upload(f.data());
    // Forces in units of a power of two near the largest (an exact scaling) for single precision's range.
    ComputeKernel& product = kernels[single ? 1 : 0];
    product->setArg(4, single ? TiledBlobProduct::powerOfTwoAbove(f.data(), f.size()) : 1.0);
    const int numTiles = (numBlobs+TileSize-1)/TileSize;
    product->execute(numTiles*numParts*TileSize, TileSize);
    if (numParts > 1)
        sumKernel->execute(3*numBlobs);
    velocity.download(out.data());
}
