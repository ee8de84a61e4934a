#ifndef RIGID_LANGEVIN_BLOB_MOBILITY_H_
#define RIGID_LANGEVIN_BLOB_MOBILITY_H_

#include "openmm/Vec3.h"
#include "internal/KrylovSolvers.h"
#include "internal/windowsExportHydrodynamics.h"
#include <Eigen/Core>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The blobs' generalised Rotne-Prager-Yamakawa mobility M per unit viscosity (RotnePragerYamakawa.h;
 * in a periodic box, PeriodicRotnePragerYamakawa's Ewald sum) as an operator for Krylov solvers:
 * given the blobs once, multiplied by as often as a solve asks. HostBlobMobility computes the products on the host; a platform may
 * compute them on its device (the common platforms' tiled kernel), but every implementation
 * computes the same M.
 */
class OPENMM_EXPORT_HYDRODYNAMICS BlobMobility {
public:
    virtual ~BlobMobility() {
    }
    /** The blobs' lab positions and radii for the products that follow, in the periodic box of
     *  boxVectors (three, OpenMM's reduced form) if given, else in an unbounded solvent. */
    virtual void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors = NULL) = 0;
    /** out = M f, for forces f (3 per blob, in the blobs' order); out is resized to f's size. */
    virtual void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out) = 0;
};

/**
 * M on the host. Up to MaxStoredBlobs blobs setBlobs() forms M once (its lower triangle, 8 (3B)^2
 * bytes: 130 MB at the limit) and each product is a matrix-vector product, several times cheaper
 * than evaluating every pair's block again; beyond, every product evaluates the pairs
 * (matrix-free). Both share their rows out by parallel. In a periodic box M is always formed (the
 * dense Ewald sum of every pair's images and the wave-space sum, once per setBlobs(), shared out by
 * parallel), whatever the number of blobs; PositivelySplitEwald is the matrix-free periodic product.
 */
class OPENMM_EXPORT_HYDRODYNAMICS HostBlobMobility : public BlobMobility {
public:
    static const int MaxStoredBlobs = 1350;
    explicit HostBlobMobility(const KrylovSolvers::ParallelFor& parallel = KrylovSolvers::sequentially) : parallel(parallel) {
    }
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors = NULL);
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out);
private:
    KrylovSolvers::ParallelFor parallel;
    std::vector<OpenMM::Vec3> positions;
    std::vector<double> radii;
    Eigen::MatrixXd stored;  // empty when matrix-free
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_BLOB_MOBILITY_H_*/
