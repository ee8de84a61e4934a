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
 * in double precision whatever the platform's precision. Each blob's sum over the others is split
 * into parts (work groups of their own, added in order by a second kernel) until the product has
 * enough work groups to fill the device. The blobs are uploaded once per step
 * (setBlobs), each product's force and velocity once per product; the solvers themselves run on
 * the host (HydrodynamicInteractions::krylovFrictionStep), as on the CPU, so that every platform
 * takes the same Krylov steps. In a periodic box and above a wall the products are the host's
 * (HostBlobMobility: the Ewald-summed M formed once per step, or Rotne-Prager-Blake's on the host's
 * threads; the spectral solver's, SpectralBlobMobility, are the kernel base's and never reach
 * this class: a device FFT path, OpenMM's createFFT, is not there yet); the device kernel is for
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
    /** The host's products take it (HostBlobMobility::setTolerance()); the device kernel stays in double. */
    void setTolerance(double tolerance) override;
    /** Blobs per work group (and per tile of local memory). */
    static const int TileSize = 64;
    /** Tasks a product is split into at least, on any device (a GPU asks for more): see setBlobs. */
    static const int MinWorkGroups = 16;
private:
    OpenMM::ComputeContext& cc;
    OpenMM::ComputeKernel kernel, sumKernel;
    OpenMM::ComputeArray blobs, force, velocity, parts;
    int numBlobs, numParts;
    bool periodic, wall;
    HostBlobMobility onHost;  ///< the products in a periodic box or above a wall
};

} // namespace RigidLangevinPlugin

#endif /*COMMON_BLOB_MOBILITY_H_*/
