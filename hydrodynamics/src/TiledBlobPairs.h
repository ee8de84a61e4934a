#ifndef RIGID_LANGEVIN_TILED_BLOB_PAIRS_H_
#define RIGID_LANGEVIN_TILED_BLOB_PAIRS_H_

// The pair terms of TiledBlobProduct in lanes (TiledBlobLanes.h): one row's sum over a tile's
// sources, and each pair of two tiles once for both of its blobs. Private to TiledBlobProduct.cpp.

#include "TiledBlobLanes.h"
#include <algorithm>

namespace RigidLangevinPlugin {
namespace TiledBlobLanes {

/** Pairs whose scaled r^2 is outside these bounds skip the lanes (single-precision estimates of
 *  1/sqrt, and in single precision 1/r^3, must not overflow or underflow). */
template <class Real> struct SquaredDistanceBounds;
template <> struct SquaredDistanceBounds<double> {
    static constexpr double Min = 1e-30, Max = 1e30;
};
template <> struct SquaredDistanceBounds<float> {
    static constexpr double Min = 1e-10, Max = 1e20;
};

/**
 * The free (Rotne-Prager-Yamakawa) part of the pairs of blob i with the lanes' sources from j, for
 * those apart (r > a_i + a_j): d = r_j - r_i, and mu_ij = isotropic I + dyadic d d^T, both zero in
 * the lanes returned as left out (overlapping, the blob itself, padding too far or too close for
 * the lanes).
 */
template <class Real, class Mask>
LANES_INLINE Mask freePairs(const Blobs<Real>& b, int i, int j, typename Lanes<Real>::Vector ai, typename Lanes<Real>::Vector ai2, typename Lanes<Real>::Vector d[3],
                            typename Lanes<Real>::Vector& isotropic, typename Lanes<Real>::Vector& dyadic) {
    typedef typename Lanes<Real>::Vector V;
    const Real isotropic0 = 1/(8*M_PI), isotropic2 = 1/(24*M_PI);
    for (int axis = 0; axis < 3; axis++)
        d[axis] = positionDifference(b, axis, j, i);
    const V r2 = d[0]*d[0]+d[1]*d[1]+d[2]*d[2];
    const V reach = ai+load<V>(b.a+j);
    const Mask left = (r2 <= reach*reach) | (r2 < (Real) SquaredDistanceBounds<Real>::Min) | (r2 > (Real) SquaredDistanceBounds<Real>::Max);
    const V inverse = inverseSqrt<Real>(r2), inverse2 = inverse*inverse;
    const V sigma2 = (ai2+load<V>(b.a2+j))*inverse2, zero = splat<Real>(0);
    // mu_ij = [(1 + sigma2/3) I + (1 - sigma2) d d^T/r^2]/(8 pi r), sigma2 = (a_i^2 + a_j^2)/r^2.
    isotropic = left ? zero : inverse*(isotropic0+isotropic2*sigma2);
    dyadic = left ? zero : inverse*inverse2*(isotropic0-isotropic0*sigma2);
    return left;
}

/** sum += each vector's lanes summed, in double. */
template <class V> LANES_INLINE void addLaneSums(double sum[3], V x, V y, V z) {
    sum[0] += laneSum(x);
    sum[1] += laneSum(y);
    sum[2] += laneSum(z);
}

/** Whether any lane of any is set. */
template <class Real, class Mask> LANES_INLINE bool anyLane(Mask any) {
    for (int lane = 0; lane < Lanes<Real>::Count; lane++)
        if (any[lane])
            return true;
    return false;
}

/** Chunks of lanes whose free blocks forFreeBlocks() evaluates before it applies them (a pair tile's at most). */
const int TermChunks = 32;

/**
 * The free blocks of row blob i's pairs with the sources [begin, end) (whole lanes), TermChunks
 * chunks of lanes at a time: the blocks of all of them first (freePairs()), then apply(j, d,
 * isotropic, dyadic) for each chunk, sources from j, in order. Each block is a long chain of
 * dependent operations (the differences, 1/sqrt and its refinement, the coefficients) that one
 * chunk's products could not hide, while the blocks of different chunks are independent, so the
 * processor overlaps them (3840 blobs, one thread: 15.6 to 12.8 ms a product in single precision,
 * with its positions as two floats, and 33.9 to 26.9 in double). masks[c] marks the lanes of chunk
 * c left out (overlapping, the blob itself, padding too far or too close for the lanes); returns
 * whether any lane was.
 */
template <class Real, class Mask, class Apply>
LANES_INLINE bool forFreeBlocks(const Blobs<Real>& b, int i, int begin, int end, Mask* masks, const Apply& apply) {
    typedef typename Lanes<Real>::Vector V;
    const V ai = splat<Real>(b.a[i]), ai2 = splat<Real>(b.a2[i]);
    Mask any = Mask{} != Mask{};
    V d[TermChunks][3], isotropic[TermChunks], dyadic[TermChunks];
    for (int first = begin, firstChunk = 0; first < end; first += TermChunks*Lanes<Real>::Count, firstChunk += TermChunks) {
        const int chunks = std::min(TermChunks, (end-first)/Lanes<Real>::Count);
        for (int c = 0; c < chunks; c++) {
            const Mask left = freePairs<Real, Mask>(b, i, first+c*Lanes<Real>::Count, ai, ai2, d[c], isotropic[c], dyadic[c]);
            masks[firstChunk+c] = left;
            any |= left;
        }
        for (int c = 0; c < chunks; c++)
            apply(first+c*Lanes<Real>::Count, d[c], isotropic[c], dyadic[c]);
    }
    return anyLane<Real>(any);
}

/**
 * Row i's sum over the sources [begin, end) (whole lanes) of the pairs apart (r > a_i + a_j):
 * sum += that part of (M f)_i; masks and the return value as forFreeBlocks()'s.
 */
template <class Real, class Mask> LANES_INLINE bool addPairsApart(const Blobs<Real>& b, int i, int begin, int end, Mask* masks, double sum[3]) {
    typedef typename Lanes<Real>::Vector V;
    V vx = splat<Real>(0), vy = vx, vz = vx;
    const bool any = forFreeBlocks<Real, Mask>(b, i, begin, end, masks, [&] (int j, const V d[3], V isotropic, V dyadic) {
        const V fx = load<V>(b.fx+j), fy = load<V>(b.fy+j), fz = load<V>(b.fz+j);
        const V along = dyadic*(d[0]*fx+d[1]*fy+d[2]*fz);
        vx += isotropic*fx+along*d[0];
        vy += isotropic*fy+along*d[1];
        vz += isotropic*fz+along*d[2];
    });
    addLaneSums(sum, vx, vy, vz);
    return any;
}

/**
 * Add the free part of the pairs that addPairsApart() or addPairsBothWays() left out (masks), each
 * block exactly in double: to row i's sum and, where columnSums is given (3 doubles per source from
 * begin), to the sources' sums too (the block is symmetric). Blob i itself is skipped.
 */
template <class Real, class Mask>
inline void addPairsLeftOut(const Blobs<Real>& b, int i, int begin, int end, const Mask* masks, double sum[3], double* columnSums = nullptr) {
    for (int j = begin, c = 0; j < end; j += Lanes<Real>::Count, c++)
        for (int lane = 0; lane < Lanes<Real>::Count; lane++) {
            const int k = j+lane;
            if (masks[c][lane] == 0 || k == i || k >= b.count)
                continue;
            double block[9];
            RotnePragerYamakawa::mobilityBlock(b.x[k]-b.x[i], b.y[k]-b.y[i], b.z[k]-b.z[i], b.exactA[i], b.exactA[k], block);
            for (int row = 0; row < 3; row++) {
                sum[row] += block[3*row]*b.exactFx[k]+block[3*row+1]*b.exactFy[k]+block[3*row+2]*b.exactFz[k];
                if (columnSums != nullptr)
                    columnSums[3*(k-begin)+row] += block[3*row]*b.exactFx[i]+block[3*row+1]*b.exactFy[i]+block[3*row+2]*b.exactFz[i];
            }
        }
}

/**
 * The wall's image block's five coefficients (RotnePragerBlake::imageCoefficients(), times its
 * 1/(8 pi)) in lanes, for target blobs at height hi and sources at hj, R = (rx, ry, rz = hi + hj)
 * from each source's mirror image to its target: the block is
 * c0 I + c1 R R^T + c2 R e_z^T + c3 e_z R^T + c4 e_z e_z^T, and its transpose is the source's block
 * for the target's force.
 */
template <class Real> LANES_INLINE void imageCoefficients(typename Lanes<Real>::Vector rx, typename Lanes<Real>::Vector ry, typename Lanes<Real>::Vector rz,
                                                          typename Lanes<Real>::Vector hi, typename Lanes<Real>::Vector hj, typename Lanes<Real>::Vector ai2,
                                                          typename Lanes<Real>::Vector aj2, typename Lanes<Real>::Vector c[5]) {
    typedef typename Lanes<Real>::Vector V;
    const V rz2 = rz*rz;
    const V u = inverseSqrt<Real>(rx*rx+ry*ry+rz2)*(Real) (1/(8*M_PI)), u2 = u*u*(Real) (64*M_PI*M_PI), u3 = u*u2;
    // Polynomials in u^2 (Horner), grouped as imageCoefficients() writes them.
    const V p = ai2*aj2, q = ai2*hj+aj2*hi, hihj = hi*hj, w = p*rz2, hj2 = 2*hj;
    c[0] = -u*(1+u2*((2*hihj+(ai2+aj2)*(Real) (1.0/3))-u2*((2*rz*q+p*(Real) (2.0/3))-u2*((Real) (10.0/3)*w))));
    c[1] = -u3*(1-u2*((6*hihj+ai2+aj2)-u2*((10*rz*q+p*(Real) (10.0/3))-u2*((Real) (70.0/3)*w))));
    c[2] = u3*(hj2-u2*((12*hihj+2*aj2)*rz+2*q-u2*((20*rz*q+(Real) (40.0/3)*p)*rz-u2*((Real) (140.0/3)*w*rz))));
    c[3] = u3*(hj2+u2*(hj2*(ai2-aj2)-u2*((Real) (20.0/3)*p*rz)));
    c[4] = u3*(-hj2*hj2+u2*((4*aj2*(hj*hj-hi*hi)-8*ai2*hj*rz-p*(Real) (8.0/3))+u2*(20*w)));
}

/**
 * Row i's sum over the sources [begin, end) (whole lanes) of the wall's image part of the pairs
 * (RotnePragerBlake::imageCoefficients(), the same formulas in lanes): every source, blob i's own
 * image included (the wall's part of its self-mobility), since the image part is smooth wherever
 * both blobs' evaluated heights are at least their radii. R^2 >= (h_i + h_j)^2 > 0: no lane is left out.
 */
template <class Real> LANES_INLINE void addImagePairs(const Blobs<Real>& b, int i, int begin, int end, double sum[3]) {
    typedef typename Lanes<Real>::Vector V;
    const V hi = splat<Real>(b.h[i]), ai2 = splat<Real>(b.a2[i]), zero = splat<Real>(0);
    V vx = zero, vy = zero, vz = zero;
    for (int j = begin; j < end; j += Lanes<Real>::Count) {
        const V rx = -positionDifference(b, 0, j, i), ry = -positionDifference(b, 1, j, i), hj = load<V>(b.h+j), aj2 = load<V>(b.a2+j);
        const V rz = hi+hj;
        V c[5];
        imageCoefficients<Real>(rx, ry, rz, hi, hj, ai2, aj2, c);
        const V fx = load<V>(b.fx+j), fy = load<V>(b.fy+j), fz = load<V>(b.fz+j);
        const V along = rx*fx+ry*fy+rz*fz, dyadic = c[1]*along+c[2]*fz;
        vx += c[0]*fx+dyadic*rx;
        vy += c[0]*fy+dyadic*ry;
        vz += c[0]*fz+dyadic*rz+c[3]*along+c[4]*fz;
    }
    addLaneSums(sum, vx, vy, vz);
}

/**
 * addPairsBothWays() in an unbounded solvent, the free blocks through forFreeBlocks(). Above a wall
 * the image part makes each chunk's chain as long again, and its terms apart took 5% longer:
 * addPairsBothWays() keeps them together there.
 */
template <class Real, class Mask>
LANES_INLINE bool addFreePairsBothWays(const Blobs<Real>& b, int i, int begin, int end, Mask* masks, double sum[3], Real* column[3]) {
    typedef typename Lanes<Real>::Vector V;
    const V fxi = splat<Real>(b.fx[i]), fyi = splat<Real>(b.fy[i]), fzi = splat<Real>(b.fz[i]);
    V vx = splat<Real>(0), vy = vx, vz = vx;
    const bool any = forFreeBlocks<Real, Mask>(b, i, begin, end, masks, [&] (int j, const V d[3], V isotropic, V dyadic) {
        const V dx = d[0], dy = d[1], dz = d[2];
        const V fx = load<V>(b.fx+j), fy = load<V>(b.fy+j), fz = load<V>(b.fz+j);
        const V alongJ = dyadic*(dx*fx+dy*fy+dz*fz), alongI = dyadic*(dx*fxi+dy*fyi+dz*fzi);
        vx += isotropic*fx+alongJ*dx;
        vy += isotropic*fy+alongJ*dy;
        vz += isotropic*fz+alongJ*dz;
        V wx = isotropic*fxi+alongI*dx, wy = isotropic*fyi+alongI*dy, wz = isotropic*fzi+alongI*dz;
        const int at = j-begin;
        std::memcpy(column[0]+at, &(wx += load<V>(column[0]+at)), sizeof(V));
        std::memcpy(column[1]+at, &(wy += load<V>(column[1]+at)), sizeof(V));
        std::memcpy(column[2]+at, &(wz += load<V>(column[2]+at)), sizeof(V));
    });
    addLaneSums(sum, vx, vy, vz);
    return any;
}

/**
 * The pairs of row blob i with the sources [begin, end) (whole lanes) of another tile, each once for
 * both of its blobs: sum += the pairs' part of (M f)_i, and column[k][j - begin] += that of
 * (M f)_j, in the lanes' precision (column[0..2]: x, y, z). The free part of the pairs apart
 * (r > a_i + a_j; masks and the return value as addPairsApart()'s, the rest added by
 * addPairsLeftOut() with the columns' sums); above a wall (Wall) the image part of every pair, whose block for
 * j's row is the transpose of i's.
 */
template <class Real, bool Wall, class Mask>
LANES_INLINE bool addPairsBothWays(const Blobs<Real>& b, int i, int begin, int end, Mask* masks, double sum[3], Real* column[3]) {
    if (!Wall)
        return addFreePairsBothWays<Real, Mask>(b, i, begin, end, masks, sum, column);
    typedef typename Lanes<Real>::Vector V;
    const V ai = splat<Real>(b.a[i]), ai2 = splat<Real>(b.a2[i]), hi = splat<Real>(b.h[i]), zero = splat<Real>(0);
    const V fxi = splat<Real>(b.fx[i]), fyi = splat<Real>(b.fy[i]), fzi = splat<Real>(b.fz[i]);
    V vx = zero, vy = zero, vz = zero;
    Mask any = Mask{} != Mask{};
    for (int j = begin, c = 0; j < end; j += Lanes<Real>::Count, c++) {
        V d[3], isotropic, dyadic;
        const Mask left = freePairs<Real, Mask>(b, i, j, ai, ai2, d, isotropic, dyadic);
        const V dx = d[0], dy = d[1], dz = d[2];
        const V fx = load<V>(b.fx+j), fy = load<V>(b.fy+j), fz = load<V>(b.fz+j);
        const V alongJ = dyadic*(dx*fx+dy*fy+dz*fz), alongI = dyadic*(dx*fxi+dy*fyi+dz*fzi);
        V ux = isotropic*fx+alongJ*dx, uy = isotropic*fy+alongJ*dy, uz = isotropic*fz+alongJ*dz;
        V wx = isotropic*fxi+alongI*dx, wy = isotropic*fyi+alongI*dy, wz = isotropic*fzi+alongI*dz;
        const V rx = -dx, ry = -dy, hj = load<V>(b.h+j), rz = hi+hj;
        V k[5];
        imageCoefficients<Real>(rx, ry, rz, hi, hj, ai2, load<V>(b.a2+j), k);
        const V rj = rx*fx+ry*fy+rz*fz, ri = rx*fxi+ry*fyi+rz*fzi;
        const V toI = k[1]*rj+k[2]*fz, toJ = k[1]*ri+k[3]*fzi;
        ux += k[0]*fx+toI*rx;
        uy += k[0]*fy+toI*ry;
        uz += k[0]*fz+toI*rz+k[3]*rj+k[4]*fz;
        wx += k[0]*fxi+toJ*rx;
        wy += k[0]*fyi+toJ*ry;
        wz += k[0]*fzi+toJ*rz+k[2]*ri+k[4]*fzi;
        vx += ux;
        vy += uy;
        vz += uz;
        const int at = j-begin;
        std::memcpy(column[0]+at, &(wx += load<V>(column[0]+at)), sizeof(V));
        std::memcpy(column[1]+at, &(wy += load<V>(column[1]+at)), sizeof(V));
        std::memcpy(column[2]+at, &(wz += load<V>(column[2]+at)), sizeof(V));
        masks[c] = left;
        any |= left;
    }
    addLaneSums(sum, vx, vy, vz);
    return anyLane<Real>(any);
}

} // namespace TiledBlobLanes
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_TILED_BLOB_PAIRS_H_*/
