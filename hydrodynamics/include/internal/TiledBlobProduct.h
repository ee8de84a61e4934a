#ifndef RIGID_LANGEVIN_TILED_BLOB_PRODUCT_H_
#define RIGID_LANGEVIN_TILED_BLOB_PRODUCT_H_

#include "openmm/Vec3.h"
#include "internal/KrylovSolvers.h"
#include "internal/windowsExportHydrodynamics.h"
#include <Eigen/Core>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * out = M f for the blobs' generalised Rotne-Prager-Yamakawa mobility M per unit viscosity in an
 * unbounded solvent (RotnePragerYamakawa.h), without forming M: every pair's block is evaluated
 * again at each product, in O(B^2) time and O(B) memory.
 *
 * The blobs are kept as a structure of arrays, padded to whole lanes; each blob's row is a sum over
 * tiles of Tile blobs, each tile's pairs four at a time (GCC's vector extensions; a build for AVX2
 * and FMA and one for the baseline, chosen when the library loads), 1/r by a single-precision
 * estimate refined by three Newton steps in double precision (no square root or division per
 * pair). Pairs that overlap (r <= a_i + a_j, including one blob inside another and a blob with
 * itself) are left out of the lanes and added exactly from RotnePragerYamakawa::mobilityBlock();
 * so are pairs too far apart or too close for the single-precision estimate (r^2 outside
 * [1e-30, 1e30]). The result equals the dense matrix's product to round-off.
 *
 * The rows are shared out by the caller's ParallelFor; each row is summed in the same order
 * whichever thread takes it, so the product does not depend on the number of threads.
 */
class OPENMM_EXPORT_HYDRODYNAMICS TiledBlobProduct {
public:
    /** The blobs per tile: the sources one row takes in one pass (8 arrays of Tile doubles: 32 KB). */
    static const int Tile = 512;
    /** Take these blobs (positions in nm, positive radii) for the products that follow. */
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii);
    /** out = M f (3 per blob), its rows shared out by parallel; out is resized. */
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out, const KrylovSolvers::ParallelFor& parallel = KrylovSolvers::sequentially);
    /** The number of blobs. */
    int getNumBlobs() const {
        return numBlobs;
    }
private:
    int numBlobs = 0;
    /** Positions, radii, squared radii and forces, each padded to a whole number of lanes. */
    std::vector<double> x, y, z, radius, radius2, fx, fy, fz;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_TILED_BLOB_PRODUCT_H_*/
