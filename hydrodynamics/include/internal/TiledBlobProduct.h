#ifndef RIGID_LANGEVIN_TILED_BLOB_PRODUCT_H_
#define RIGID_LANGEVIN_TILED_BLOB_PRODUCT_H_

#include "openmm/Vec3.h"
#include "internal/KrylovSolvers.h"
#include "internal/windowsExportHydrodynamics.h"
#include <Eigen/Core>
#include <vector>

namespace RigidLangevinPlugin {

namespace TiledBlobLanes {
template <class Real> struct Blobs;
}

/**
 * out = M f for the blobs' generalised Rotne-Prager-Yamakawa mobility M per unit viscosity in an
 * unbounded solvent (RotnePragerYamakawa.h), or their regularised Rotne-Prager-Blake mobility above
 * a no-slip wall (RotnePragerBlake.h), without forming M: every pair's block is evaluated again at
 * each product, in O(B^2) time and O(B) memory.
 *
 * The blobs are kept as a structure of arrays, padded to whole lanes, lengths in units of a power of
 * two near the largest radius and forces of one near the largest force (exact scalings, so that
 * single precision's range holds every term); each blob's row is a sum over tiles of Tile blobs,
 * each tile's pairs four at a time in double precision or eight in single (setSinglePrecision();
 * GCC's vector extensions; a build for AVX2 and FMA and one for the baseline, chosen when the
 * library loads). Differences of positions are exact in double and, in single, taken from each
 * position held as two floats (its rounding and the remainder), good to float's precision relative
 * to the distance however far the blobs are from the origin; 1/r comes
 * from a single-precision estimate refined by third-order steps (two in double, one in single: no
 * square root or division per pair); each lane sums its pairs of one tile in its own precision, and
 * every row's sums over the tiles are in double. Pairs that overlap
 * (r <= a_i + a_j, including one blob inside another and a blob with itself) are left out of the
 * lanes and added exactly, in double, from RotnePragerYamakawa::mobilityBlock(); so are pairs too
 * far apart or too close for the lanes (scaled r^2 outside [1e-30, 1e30] in double, [1e-10, 1e20]
 * in single). In an unbounded solvent a row's free blocks with up to 32 chunks of lanes are
 * evaluated before they are applied, so that their chains of dependent operations overlap. Above a
 * wall each pair's image part is added in the same lanes, every pair (a blob's
 * own image too: the wall's part of its self-mobility); it is smooth wherever both blobs are at
 * their evaluated heights, so none is left out. In double precision the result equals the dense
 * matrix's product to round-off; in single, to about 3e-7 (relative).
 *
 * Up to MaxPairTiles tiles (about 16 tiles of 64 to MaxPairTile blobs; 32768 blobs at most) each pair is
 * evaluated once for both of its blobs (the wall's image block for the second blob is the first's
 * transposed): tasks over pairs of tiles, each summing into sums of its own, shared out by the
 * caller's ParallelFor, then every blob's sums added over the tasks in one order. Beyond, the
 * rows are shared out and each pair is evaluated for each of its blobs. Either way the product
 * does not depend on the number of threads.
 */
class OPENMM_EXPORT_HYDRODYNAMICS TiledBlobProduct {
public:
    /** The blobs per tile: the sources one row takes in one pass (8 arrays of Tile doubles: 32 KB; fewer bytes in single precision). */
    static const int Tile = 512;
    /** Take these blobs (positions in nm, positive radii) for the products that follow. */
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii);
    /** Take these blobs above the no-slip wall z = wallZ (nm): blobs that pass RotnePragerBlake::validate(). */
    void setBlobsAboveWall(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii, double wallZ);
    /** out = M f (3 per blob), its rows shared out by parallel; out is resized. */
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out, const KrylovSolvers::ParallelFor& parallel = KrylovSolvers::sequentially);
    /**
     * Evaluate the pair terms in single precision (eight lanes; sums over tiles in double,
     * overlapping pairs exactly in double) rather than double, for this and later setBlobs(): each pair's block is
     * then within about 1e-6 of the exact one (TestTiledBlobProduct measures the product's error),
     * for tolerances that allow it (HostBlobMobility::setTolerance()). Where the blobs' radii span
     * more than MaxSingleRadiusRatio, the terms stay in double.
     */
    void setSinglePrecision(bool single);
    /** Whether the pair terms are in single precision (setSinglePrecision() and the radii allow it). */
    bool isSinglePrecision() const {
        return single;
    }
    /** The widest span of radii (largest over smallest) that single precision takes. */
    static constexpr double MaxSingleRadiusRatio = 1000;
    /**
     * Whether radii span at most MaxSingleRadiusRatio (and so single-precision pair terms hold them:
     * wider, 1/r^3 of the closest pairs would leave float's range); true for none. CommonBlobMobility's
     * device kernel takes the same rule.
     */
    static bool radiiFitSinglePrecision(const double* radii, int count);
    /**
     * The power of two nearest above the largest magnitude in values (1 if none is positive and
     * finite): lengths and forces in units of it (an exact scaling) keep single-precision pair terms
     * well inside float's range (CommonBlobMobility's device kernel uses it too).
     */
    static double powerOfTwoAbove(const double* values, int count);
    /** The number of blobs. */
    int getNumBlobs() const {
        return numBlobs;
    }
private:
    int numBlobs = 0;
    bool wall = false, singleRequested = false, single = false;
    /** The unit of length of the arrays below (a power of two near the largest radius). */
    double lengthScale = 1;
    /** Positions (above a wall, z the evaluated height), radii, squared radii and forces, each padded
     *  to a whole number of lanes, in units of lengthScale (forces: of a power of two near the largest). */
    std::vector<double> x, y, z, radius, radius2, fx, fy, fz;
    /** Radii, squared radii, heights and forces in single precision, when the pair terms are. */
    std::vector<float> singleRadius, singleRadius2, singleHeight, singleFx, singleFy, singleFz;
    /** Then x, y and z too, each as its rounding to single precision and what that left (TiledBlobLanes::Blobs). */
    std::vector<float> singleHigh[3], singleLow[3];
    /** Each blob's damping by the wall's regularisation (1 in an unbounded solvent). */
    std::vector<double> damping;
    /** Each pair task's sums (multiplyByTilePairs()). */
    std::vector<double> tileSums;
    void store(const std::vector<OpenMM::Vec3>& positions, const std::vector<double>& radii);
    void fillSingleArrays();
    /** The blobs' size of a tile for multiplyByTilePairs() (0: too many blobs, row by row instead). */
    static int pairTileSize(int padded);
    /** At most this many tiles (the tasks' sums hold 3 x tiles x padded doubles: 100 MB at 32768 blobs). */
    static const int MaxPairTiles = 128;
    /** At most this many blobs in a tile of the pair tasks. */
    static const int MaxPairTile = 256;
    TiledBlobLanes::Blobs<double> inDouble() const;
    TiledBlobLanes::Blobs<float> inSingle() const;
    /** sums (3 per row from begin's) += the rows' pairs with the sources [sourceBegin, sourceEnd), each row on its own. */
    void addRowSums(int begin, int end, int sourceBegin, int sourceEnd, double* sums) const;
    /** rowSums and columnSums (3 per blob from rowBegin's and columnBegin's) += the pairs of two disjoint tiles, each once. */
    void addTilePairSums(int rowBegin, int rowEnd, int columnBegin, int columnEnd, double* rowSums, double* columnSums) const;
    /** out (3 per blob, without the self term) = M f by tasks over pairs of tiles, each pair of blobs evaluated once. */
    void multiplyByTilePairs(int tile, Eigen::VectorXd& out, const KrylovSolvers::ParallelFor& parallel);
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_TILED_BLOB_PRODUCT_H_*/
