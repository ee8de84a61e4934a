#ifndef COMMON_BLOB_MOBILITY_H_
#define COMMON_BLOB_MOBILITY_H_

#include "internal/BlobMobility.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include <string>

namespace RigidLangevinPlugin {

/**
 * The blobs' mobility products for the Krylov solves of bodies coupled through the solvent,
 * computed on the device of a common compute platform: matrix-free, tiled (kernels/blobMobility.cc),
 * whatever the platform's precision in double, or, where the solves' tolerance allows it
 * (setTolerance()), with the pair terms in single precision and their sums in double, as the
 * host's products (HostBlobMobility). Each blob's sum over the others is split
 * into parts (work groups of their own, added in order by a second kernel) until the product has
 * enough work groups to fill the device. The blobs are uploaded once per step
 * (setBlobs), each product's force and velocity once per product; the solvers themselves run on
 * the host (HydrodynamicInteractions::krylovFrictionStep), as on the CPU, so that every platform
 * takes the same Krylov steps. In a periodic box and above a wall the products are the host's
 * (HostBlobMobility: the Ewald-summed M formed once per step, or Rotne-Prager-Blake's on the host's
 * threads; the spectral solver's are CommonPseMobility's, on the device); the device kernel is for
 * an unbounded solvent. Throws an
 * OpenMMException, begun with the integrator's class name, if the device has no double precision.
 */
class CommonBlobMobility : public BlobMobility {
public:
    CommonBlobMobility(OpenMM::ComputeContext& cc, const std::string& integrator);
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors = NULL);
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out);
    /** Above a wall every product is the host's. */
    void setWall(double wallZ);
    /**
     * From the next setBlobs() on, at a tolerance of HostBlobMobility::SinglePrecisionTolerance or
     * looser the device's pair terms are in single precision (each tile's sum too; the tiles' sums
     * in double): the product within about 1e-6 of the exact one (relative), where a GPU does pair
     * terms in float many times faster than in double. Tighter, or where the radii span more than
     * TiledBlobProduct::MaxSingleRadiusRatio, in double. The host's products (a periodic box, a
     * wall) take it too (HostBlobMobility::setTolerance()).
     */
    void setTolerance(double tolerance) override;
    /** Whether the device's pair terms are in single precision (setTolerance() and the radii allow it). */
    bool isSinglePrecision() const {
        return single;
    }
    /** Blobs per work group (and per tile of local memory). */
    static const int TileSize = 64;
    /** Tasks a product is split into at least, on any device (a GPU asks for more): see setBlobs. */
    static const int MinWorkGroups = 16;
private:
    OpenMM::ComputeContext& cc;
    OpenMM::ComputeKernel kernels[2];  ///< the product with the pair terms in double, in single (compiled when first used; in use: kernels[single])
    OpenMM::ComputeKernel sumKernel;   ///< the parts' sum
    OpenMM::ComputeArray blobs, force, velocity, parts;
    int numBlobs, numParts, tilesPerPart;
    bool periodic, wall, singleRequested, single;
    double lengthScale;  ///< the unit of the pair terms' lengths (1 in double)
    /** The product in single's precision (compiled if first used), bound to these blobs (the force's scale is set by each product). */
    void bindProductKernel();
    HostBlobMobility onHost;  ///< the products in a periodic box or above a wall
};

} // namespace RigidLangevinPlugin

#endif /*COMMON_BLOB_MOBILITY_H_*/
