#ifndef RIGID_LANGEVIN_TILED_BLOB_LANES_H_
#define RIGID_LANGEVIN_TILED_BLOB_LANES_H_

// The pair terms of TiledBlobProduct, a tile's sources a few at a time in the lanes of one register
// (GCC's and Clang's vector extensions: an AVX2 register in the AVX2 build, two SSE2 registers in
// the baseline one), in double precision (four lanes) or single (eight). Private to
// TiledBlobProduct.cpp: everything here is inlined into its clones.

#include "internal/RotnePragerYamakawa.h"
#include <cmath>
#include <cstring>

// The helpers below pass vectors by value only to each other, inlined into the clones.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace RigidLangevinPlugin {
namespace TiledBlobLanes {

#define LANES_INLINE inline __attribute__((always_inline))

/** The lanes of one precision, each type one 32-byte register. */
template <class Real> struct Lanes;
template <> struct Lanes<double> {
    static const int Count = 4;
    typedef double Vector __attribute__((vector_size(32)));
    typedef decltype(Vector{} < Vector{}) Mask;
    /** Refinements of the single-precision 1/sqrt estimate (12 bits, then 36, then double's rounding). */
    static const int Refinements = 2;
};
template <> struct Lanes<float> {
    static const int Count = 8;
    typedef float Vector __attribute__((vector_size(32)));
    typedef decltype(Vector{} < Vector{}) Mask;
    static const int Refinements = 1;
};

/** Every array is padded to a multiple of this (the larger lane count). */
const int Padding = 8;

/**
 * A tile's view of the blobs for pair terms in Real: positions (scaled, see TiledBlobProduct.cpp)
 * in double; in single precision each also as two floats, its rounding (high) and what that left
 * (low), so that a difference of positions is good to float's precision relative to the distance
 * (positionDifference()); radii, squared radii, heights (above a wall: z itself) and forces in
 * Real; radii and forces in double for the pairs done exactly.
 */
template <class Real> struct Blobs {
    const double *x, *y, *z;
    const Real *a, *a2, *h, *fx, *fy, *fz;
    const double *exactA, *exactFx, *exactFy, *exactFz;
    int count, padded;
    bool wall;
    const float *high[3], *low[3];  ///< single precision only
};

template <class Real> LANES_INLINE typename Lanes<Real>::Vector splat(double value) {
    return typename Lanes<Real>::Vector{}+(Real) value;
}

template <class V> LANES_INLINE V load(const void* p) {
    V v;
    std::memcpy(&v, p, sizeof(v));
    return v;
}

/**
 * The differences of positions p_j - p_i along axis (0, 1, 2) for the lanes' sources from j: in
 * double, exactly as stored; in single, (high_j - high_i) + (low_j - low_i), float operations only
 * (converting differences taken in double cost more and lengthened each pair's chain of dependent
 * operations), good to about two float roundings of the difference.
 */
template <class Real> LANES_INLINE typename Lanes<Real>::Vector positionDifference(const Blobs<Real>& b, int axis, int j, int i);
template <> LANES_INLINE Lanes<double>::Vector positionDifference(const Blobs<double>& b, int axis, int j, int i) {
    const double* p = (axis == 0 ? b.x : axis == 1 ? b.y : b.z);
    return load<Lanes<double>::Vector>(p+j)-p[i];
}
template <> LANES_INLINE Lanes<float>::Vector positionDifference(const Blobs<float>& b, int axis, int j, int i) {
    typedef Lanes<float>::Vector V;
    return (load<V>(b.high[axis]+j)-b.high[axis][i])+(load<V>(b.low[axis]+j)-b.low[axis][i]);
}

/** Four single-precision 1/sqrt estimates (12 bits) of four floats. */
typedef float Four __attribute__((vector_size(16)));
LANES_INLINE Four estimateInverseSqrt(Four r2) {
#if defined(__x86_64__) || defined(__i386__)
    return __builtin_ia32_rsqrtps(r2);
#else
    return Four{1/std::sqrt(r2[0]), 1/std::sqrt(r2[1]), 1/std::sqrt(r2[2]), 1/std::sqrt(r2[3])};
#endif
}

template <class V> LANES_INLINE V estimate(V r2);
template <> LANES_INLINE Lanes<double>::Vector estimate(Lanes<double>::Vector r2) {
    return __builtin_convertvector(estimateInverseSqrt(__builtin_convertvector(r2, Four)), Lanes<double>::Vector);
}
template <> LANES_INLINE Lanes<float>::Vector estimate(Lanes<float>::Vector r2) {
    // Halves by shuffles, not through memory (a 32-byte load of two 16-byte stores stalls).
    const Four low = estimateInverseSqrt(__builtin_shufflevector(r2, r2, 0, 1, 2, 3));
    const Four high = estimateInverseSqrt(__builtin_shufflevector(r2, r2, 4, 5, 6, 7));
    return __builtin_shufflevector(low, high, 0, 1, 2, 3, 4, 5, 6, 7);
}

/** 1/sqrt(r2) lane by lane, for r2 within the bounds a float holds: the single-precision estimate
 *  refined by steps of third order, y (1 + e/2 + 3 e^2/8) with e = 1 - r2 y^2 (five operations each). */
template <class Real> LANES_INLINE typename Lanes<Real>::Vector inverseSqrt(typename Lanes<Real>::Vector r2) {
    typename Lanes<Real>::Vector y = estimate(r2);
    for (int step = 0; step < Lanes<Real>::Refinements; step++) {
        const typename Lanes<Real>::Vector e = 1-r2*(y*y);
        y += (y*e)*((Real) 0.5+(Real) 0.375*e);
    }
    return y;
}

/** The sum of a vector's lanes, in double. */
template <class V> LANES_INLINE double laneSum(V v) {
    double sum = 0;
    for (int lane = 0; lane < (int) (sizeof(V)/sizeof(v[0])); lane++)
        sum += v[lane];
    return sum;
}

} // namespace TiledBlobLanes
} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_TILED_BLOB_LANES_H_*/
