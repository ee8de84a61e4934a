#ifndef RIGID_LANGEVIN_BLOB_MOBILITY_H_
#define RIGID_LANGEVIN_BLOB_MOBILITY_H_

#include "openmm/Vec3.h"
#include "internal/KrylovSolvers.h"
#include "internal/TiledBlobProduct.h"
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
    /**
     * Bound the fluid by a no-slip wall, the plane z = wallZ (nm), the fluid above it: from the next
     * setBlobs() on, M is the regularised Rotne-Prager-Blake mobility (RotnePragerBlake.h), and
     * setBlobs() refuses a blob whose centre is at or below the wall (throwing a
     * RotnePragerBlake::BlobBelowWallException that says which blob) and a periodic box. This
     * default throws: an implementation without a wall says so rather than ignore it.
     */
    virtual void setWall(double wallZ);
    /**
     * The relative error the products may carry from the next setBlobs() on: the tolerance of the
     * Krylov solves they serve. An implementation may compute them less precisely where that keeps
     * their error well below it; by default they are as exact as the implementation can make them.
     */
    virtual void setTolerance(double tolerance) {
        (void) tolerance;
    }
    /**
     * Whether sampleNoise() draws noise of covariance M by a method of this product's own, cheaper
     * than a Lanczos square root on M (the positively split Ewald sum's, exact through its split).
     */
    virtual bool hasOwnNoise() const {
        return false;
    }
    /**
     * out = a sample of covariance M at the blobs of the last setBlobs(), from as many standard
     * normals drawn from normal() as the method needs, any iterative part to tolerance (its outcome
     * returned). This default throws: only an implementation whose hasOwnNoise() is true has one.
     */
    virtual KrylovSolvers::Result sampleNoise(const std::function<double()>& normal, Eigen::VectorXd& out, double tolerance, int maxIterations);
};

/**
 * M on the host, in an unbounded solvent, a periodic box or above a wall (setWall()). Up to
 * MaxStoredBlobs (or the constructor's maxStoredBlobs) setBlobs() forms M once (both triangles)
 * and each product is a matrix-vector product, its rows shared out by parallel; beyond, every
 * product evaluates the pairs again (matrix-free, TiledBlobProduct: vectorised, each pair once,
 * in single precision at loose tolerances, setTolerance()), shared out by parallel too. The limit
 * is where storing stops paying, measured on the development machine's two threads
 * (benchmarks/hydrodynamics/README.md, benchmark_blob_product): forming M costs 10 to 40 tiled
 * products from 100 blobs on, while a step's configuration serves 10 to 60 products (the Brownian
 * step sets three configurations a step) and the stored product saves at most 0.3 to 0.6 of a
 * tiled one up to 300 blobs and nothing from 600. In a periodic box M is always formed (the dense
 * Ewald sum of every pair's images and the wave-space sum, once per setBlobs(), shared out by
 * parallel), whatever the number of blobs; PositivelySplitEwald is the matrix-free periodic product.
 */
class OPENMM_EXPORT_HYDRODYNAMICS HostBlobMobility : public BlobMobility {
public:
    /** Up to how many blobs M is formed (by default) in an unbounded solvent or above a wall. */
    static const int MaxStoredBlobs = 100;
    /**
     * @param parallel        how rows are shared out among threads
     * @param maxStoredBlobs  up to how many blobs M is formed rather than applied matrix-free
     */
    explicit HostBlobMobility(const KrylovSolvers::ParallelFor& parallel = KrylovSolvers::sequentially, int maxStoredBlobs = MaxStoredBlobs)
        : parallel(parallel), maxStoredBlobs(maxStoredBlobs), wall(false), wallZ(0) {
    }
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, const OpenMM::Vec3* boxVectors = NULL);
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out);
    void setWall(double wallZ);
    /**
     * At a tolerance of SinglePrecisionTolerance or looser the matrix-free product's pair terms are
     * in single precision (TiledBlobProduct::setSinglePrecision(): the product within 3e-7 of the
     * exact one, at least 30 times below the tolerance, about twice as fast); tighter, in double.
     * The stored matrix is always in double.
     */
    void setTolerance(double tolerance) override;
    /** The loosest tolerance at which the matrix-free products stay in double precision is just below this. */
    static constexpr double SinglePrecisionTolerance = 1e-5;
private:
    KrylovSolvers::ParallelFor parallel;
    int maxStoredBlobs;
    bool wall;
    double wallZ;
    std::vector<OpenMM::Vec3> positions;
    std::vector<double> radii;
    Eigen::MatrixXd stored;  // M, both triangles; empty when matrix-free
    TiledBlobProduct tiled;  // the matrix-free product in an unbounded solvent
    /** stored's upper triangle from its lower one, on the threads. */
    void fillUpperTriangle();
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_BLOB_MOBILITY_H_*/
