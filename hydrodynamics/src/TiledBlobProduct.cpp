#include "internal/TiledBlobProduct.h"
#include "internal/RotnePragerYamakawa.h"
#include <algorithm>
#include <cmath>
#include <cstring>

using namespace RigidLangevinPlugin;
using OpenMM::Vec3;
using std::vector;

// The helpers below pass vectors by value only to each other, inlined into the clones.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace {

// The pair loop in two builds, one for CPUs with AVX2 and FMA (x86-64-v3) and one for the baseline,
// chosen when the library is loaded (GCC's target_clones, as the host step's loop); flatten
// compiles what it calls into each build. Other compilers build the baseline.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__ELF__)
#define RIGIDLANGEVIN_TILED_CLONES __attribute__((target_clones("arch=x86-64-v3", "default"), flatten))
#else
#define RIGIDLANGEVIN_TILED_CLONES
#endif

#define LANES_INLINE inline __attribute__((always_inline))

// Four doubles as one value (GCC's and Clang's vector extensions: an AVX2 register in the AVX2
// build, two SSE2 registers in the baseline one).
const int Lanes = 4;
typedef double vd __attribute__((vector_size(8*Lanes)));
typedef decltype(vd{} < vd{}) vmask;

/** Rows summed together over one tile: their partial sums stay in L1 while the tile is read. */
const int RowBlock = 32;
/** Pairs whose r^2 is outside these bounds skip the lanes: a float cannot hold 1/r^2 for them. */
const double MinSquaredDistance = 1e-30, MaxSquaredDistance = 1e30;

/** The blobs' arrays (padded to whole lanes) and the forces, as the pair loop reads them. */
struct Blobs {
    const double *x, *y, *z, *a, *a2, *fx, *fy, *fz;
    int count, padded;
};

LANES_INLINE vd splat(double v) {
    return vd{v, v, v, v};
}

LANES_INLINE vd load(const double* p) {
    vd v;
    std::memcpy(&v, p, sizeof(v));
    return v;
}

/** 1/sqrt(r2) lane by lane, for r2 in [MinSquaredDistance, MaxSquaredDistance]: a single-precision
 *  estimate (12 bits) refined by two steps of third order, y (1 + e/2 + 3 e^2/8) with
 *  e = 1 - r2 y^2 (36 bits, then double precision's rounding): five operations a step. */
LANES_INLINE vd inverseSqrt(vd r2) {
#if defined(__x86_64__) || defined(__i386__)
    typedef float vf __attribute__((vector_size(4*Lanes)));
    vd y = __builtin_convertvector(__builtin_ia32_rsqrtps(__builtin_convertvector(r2, vf)), vd);
    for (int step = 0; step < 2; step++) {
        const vd e = 1-r2*(y*y);
        y += (y*e)*(0.5+0.375*e);
    }
    return y;
#else
    return vd{1/std::sqrt(r2[0]), 1/std::sqrt(r2[1]), 1/std::sqrt(r2[2]), 1/std::sqrt(r2[3])};
#endif
}

/**
 * Row i's sum over the sources [begin, end) (whole lanes) of the pairs apart (r > a_i + a_j):
 * sum += that part of (M f)_i. masks[c] marks the lanes of chunk c left out (overlapping, the blob
 * itself, padding too far or too close for the lanes); returns whether any lane was.
 */
LANES_INLINE bool addPairsApart(const Blobs& b, int i, int begin, int end, vmask* masks, double sum[3]) {
    const vd xi = splat(b.x[i]), yi = splat(b.y[i]), zi = splat(b.z[i]), ai = splat(b.a[i]), ai2 = splat(b.a2[i]);
    const vd isotropic0 = splat(1/(8*M_PI)), isotropic2 = splat(1/(24*M_PI)), zero = splat(0);
    vd vx = zero, vy = zero, vz = zero;
    vmask any = vmask{} != vmask{};
    for (int j = begin, c = 0; j < end; j += Lanes, c++) {
        const vd dx = load(b.x+j)-xi, dy = load(b.y+j)-yi, dz = load(b.z+j)-zi;
        const vd r2 = dx*dx+dy*dy+dz*dz;
        const vd reach = ai+load(b.a+j);
        const vmask left = (r2 <= reach*reach) | (r2 < MinSquaredDistance) | (r2 > MaxSquaredDistance);
        const vd inverse = inverseSqrt(r2), inverse2 = inverse*inverse;
        const vd sigma2 = (ai2+load(b.a2+j))*inverse2;
        // mu_ij = [(1 + sigma2/3) I + (1 - sigma2) d d^T/r^2]/(8 pi r), sigma2 = (a_i^2 + a_j^2)/r^2.
        const vd isotropic = inverse*(isotropic0+isotropic2*sigma2);
        const vd dyadic = inverse*inverse2*(isotropic0-isotropic0*sigma2);
        const vd fx = load(b.fx+j), fy = load(b.fy+j), fz = load(b.fz+j);
        const vd along = left ? zero : dyadic*(dx*fx+dy*fy+dz*fz);
        const vd across = left ? zero : isotropic;
        vx += across*fx+along*dx;
        vy += across*fy+along*dy;
        vz += across*fz+along*dz;
        masks[c] = left;
        any |= left;
    }
    sum[0] += (vx[0]+vx[1])+(vx[2]+vx[3]);
    sum[1] += (vy[0]+vy[1])+(vy[2]+vy[3]);
    sum[2] += (vz[0]+vz[1])+(vz[2]+vz[3]);
    return (any[0] | any[1] | any[2] | any[3]) != 0;
}

/** Add the pairs addPairsApart() left out of row i's sum (masks), each block exactly. */
inline void addPairsLeftOut(const Blobs& b, int i, int begin, int end, const vmask* masks, double sum[3]) {
    for (int j = begin, c = 0; j < end; j += Lanes, c++)
        for (int lane = 0; lane < Lanes; lane++) {
            const int k = j+lane;
            if (masks[c][lane] == 0 || k == i || k >= b.count)
                continue;
            double block[9];
            RotnePragerYamakawa::mobilityBlock(b.x[k]-b.x[i], b.y[k]-b.y[i], b.z[k]-b.z[i], b.a[i], b.a[k], block);
            for (int row = 0; row < 3; row++)
                sum[row] += block[3*row]*b.fx[k]+block[3*row+1]*b.fy[k]+block[3*row+2]*b.fz[k];
        }
}

/** out (3 per blob) = M f for the rows [begin, end): each block of rows against every tile in turn. */
RIGIDLANGEVIN_TILED_CLONES void multiplyRows(const Blobs& b, int begin, int end, double* out) {
    vmask masks[TiledBlobProduct::Tile/Lanes];
    for (int first = begin; first < end; first += RowBlock) {
        const int last = std::min(end, first+RowBlock);
        double sums[3*RowBlock] = {0};
        for (int tile = 0; tile < b.padded; tile += TiledBlobProduct::Tile) {
            const int tileEnd = std::min(b.padded, tile+TiledBlobProduct::Tile);
            for (int i = first; i < last; i++) {
                double* sum = sums+3*(i-first);
                if (addPairsApart(b, i, tile, tileEnd, masks, sum))
                    addPairsLeftOut(b, i, tile, tileEnd, masks, sum);
            }
        }
        for (int i = first; i < last; i++) {
            const double self = RotnePragerYamakawa::selfMobility(b.a[i]);
            out[3*i] = self*b.fx[i]+sums[3*(i-first)];
            out[3*i+1] = self*b.fy[i]+sums[3*(i-first)+1];
            out[3*i+2] = self*b.fz[i]+sums[3*(i-first)+2];
        }
    }
}

} // namespace

void TiledBlobProduct::setBlobs(const vector<Vec3>& positions, const vector<double>& radii) {
    numBlobs = positions.size();
    const int padded = (numBlobs+Lanes-1)/Lanes*Lanes;
    // Padding: far from everything (its lanes then add zero force times finite numbers), radius one.
    for (vector<double>* v : {&x, &y, &z, &fx, &fy, &fz})
        v->assign(padded, 0.0);
    radius.assign(padded, 1.0);
    radius2.assign(padded, 1.0);
    for (int i = 0; i < padded; i++) {
        const Vec3 p = (i < numBlobs ? positions[i] : Vec3(1e10, 1e10, 1e10));
        x[i] = p[0];
        y[i] = p[1];
        z[i] = p[2];
        if (i < numBlobs) {
            radius[i] = radii[i];
            radius2[i] = radii[i]*radii[i];
        }
    }
}

void TiledBlobProduct::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out, const KrylovSolvers::ParallelFor& parallel) {
    for (int i = 0; i < numBlobs; i++) {
        fx[i] = f[3*i];
        fy[i] = f[3*i+1];
        fz[i] = f[3*i+2];
    }
    out.resize(3*numBlobs);
    const Blobs blobs = {x.data(), y.data(), z.data(), radius.data(), radius2.data(), fx.data(), fy.data(), fz.data(), numBlobs, (int) x.size()};
    parallel(numBlobs, [&] (int begin, int end) { multiplyRows(blobs, begin, end, out.data()); });
}
