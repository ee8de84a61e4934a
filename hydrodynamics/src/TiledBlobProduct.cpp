#include "internal/TiledBlobProduct.h"
#include "internal/RotnePragerBlake.h"
#include "internal/RotnePragerYamakawa.h"
#include "TiledBlobLanes.h"
#include <algorithm>
#include <cmath>
#include <cstring>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::TiledBlobLanes;
using OpenMM::Vec3;
using std::vector;

namespace {

// The pair loop in two builds, one for CPUs with AVX2 and FMA (x86-64-v3) and one for the baseline,
// chosen when the library is loaded (GCC's target_clones, as the host step's loop); flatten
// compiles what it calls into each build. Other compilers build the baseline.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__ELF__)
#define RIGIDLANGEVIN_TILED_CLONES __attribute__((target_clones("arch=x86-64-v3", "default"), flatten))
#else
#define RIGIDLANGEVIN_TILED_CLONES
#endif

/** Rows summed together over one tile: their partial sums stay in L1 while the tile is read. */
const int RowBlock = 32;

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
 * Row i's sum over the sources [begin, end) (whole lanes) of the pairs apart (r > a_i + a_j):
 * sum += that part of (M f)_i. masks[c] marks the lanes of chunk c left out (overlapping, the blob
 * itself, padding too far or too close for the lanes); returns whether any lane was.
 */
template <class Real, class Mask> LANES_INLINE bool addPairsApart(const Blobs<Real>& b, int i, int begin, int end, Mask* masks, double sum[3]) {
    typedef typename Lanes<Real>::Vector V;
    const V ai = splat<Real>(b.a[i]), ai2 = splat<Real>(b.a2[i]), zero = splat<Real>(0);
    const Real isotropic0 = 1/(8*M_PI), isotropic2 = 1/(24*M_PI);
    V vx = zero, vy = zero, vz = zero;
    Mask any = Mask{} != Mask{};
    for (int j = begin, c = 0; j < end; j += Lanes<Real>::Count, c++) {
        const V dx = difference<V>(b.x+j, b.x[i]), dy = difference<V>(b.y+j, b.y[i]), dz = difference<V>(b.z+j, b.z[i]);
        const V r2 = dx*dx+dy*dy+dz*dz;
        const V reach = ai+load<V>(b.a+j);
        const Mask left = (r2 <= reach*reach) | (r2 < (Real) SquaredDistanceBounds<Real>::Min) | (r2 > (Real) SquaredDistanceBounds<Real>::Max);
        const V inverse = inverseSqrt<Real>(r2), inverse2 = inverse*inverse;
        const V sigma2 = (ai2+load<V>(b.a2+j))*inverse2;
        // mu_ij = [(1 + sigma2/3) I + (1 - sigma2) d d^T/r^2]/(8 pi r), sigma2 = (a_i^2 + a_j^2)/r^2.
        const V isotropic = inverse*(isotropic0+isotropic2*sigma2);
        const V dyadic = inverse*inverse2*(isotropic0-isotropic0*sigma2);
        const V fx = load<V>(b.fx+j), fy = load<V>(b.fy+j), fz = load<V>(b.fz+j);
        const V along = left ? zero : dyadic*(dx*fx+dy*fy+dz*fz);
        const V across = left ? zero : isotropic;
        vx += across*fx+along*dx;
        vy += across*fy+along*dy;
        vz += across*fz+along*dz;
        masks[c] = left;
        any |= left;
    }
    sum[0] += laneSum(vx);
    sum[1] += laneSum(vy);
    sum[2] += laneSum(vz);
    for (int lane = 0; lane < Lanes<Real>::Count; lane++)
        if (any[lane])
            return true;
    return false;
}

/** Add the pairs addPairsApart() left out of row i's sum (masks), each block exactly in double. */
template <class Real, class Mask> inline void addPairsLeftOut(const Blobs<Real>& b, int i, int begin, int end, const Mask* masks, double sum[3]) {
    for (int j = begin, c = 0; j < end; j += Lanes<Real>::Count, c++)
        for (int lane = 0; lane < Lanes<Real>::Count; lane++) {
            const int k = j+lane;
            if (masks[c][lane] == 0 || k == i || k >= b.count)
                continue;
            double block[9];
            RotnePragerYamakawa::mobilityBlock(b.x[k]-b.x[i], b.y[k]-b.y[i], b.z[k]-b.z[i], b.exactA[i], b.exactA[k], block);
            for (int row = 0; row < 3; row++)
                sum[row] += block[3*row]*b.exactFx[k]+block[3*row+1]*b.exactFy[k]+block[3*row+2]*b.exactFz[k];
        }
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
        const V rx = -difference<V>(b.x+j, b.x[i]), ry = -difference<V>(b.y+j, b.y[i]), hj = load<V>(b.h+j), aj2 = load<V>(b.a2+j);
        const V rz = hi+hj, rz2 = rz*rz;
        const V u = inverseSqrt<Real>(rx*rx+ry*ry+rz2), u2 = u*u, u3 = u*u2;
        // The coefficients as polynomials in u^2 (Horner), grouped as imageCoefficients() writes them.
        const V p = ai2*aj2, q = ai2*hj+aj2*hi, hihj = hi*hj, w = p*rz2, hj2 = 2*hj;
        const V c0 = -u*(1+u2*((2*hihj+(ai2+aj2)*(Real) (1.0/3))-u2*((2*rz*q+p*(Real) (2.0/3))-u2*((Real) (10.0/3)*w))));
        const V c1 = -u3*(1-u2*((6*hihj+ai2+aj2)-u2*((10*rz*q+p*(Real) (10.0/3))-u2*((Real) (70.0/3)*w))));
        const V c2 = u3*(hj2-u2*((12*hihj+2*aj2)*rz+2*q-u2*((20*rz*q+(Real) (40.0/3)*p)*rz-u2*((Real) (140.0/3)*w*rz))));
        const V c3 = u3*(hj2+u2*(hj2*(ai2-aj2)-u2*((Real) (20.0/3)*p*rz)));
        const V c4 = u3*(-hj2*hj2+u2*((4*aj2*(hj*hj-hi*hi)-8*ai2*hj*rz-p*(Real) (8.0/3))+u2*(20*w)));
        const V fx = load<V>(b.fx+j), fy = load<V>(b.fy+j), fz = load<V>(b.fz+j);
        const V along = rx*fx+ry*fy+rz*fz, dyadic = c1*along+c2*fz;
        vx += c0*fx+dyadic*rx;
        vy += c0*fy+dyadic*ry;
        vz += c0*fz+dyadic*rz+c3*along+c4*fz;
    }
    const double scale = 1/(8*M_PI);
    sum[0] += scale*laneSum(vx);
    sum[1] += scale*laneSum(vy);
    sum[2] += scale*laneSum(vz);
}

/** out (3 per blob) = M f for the rows [begin, end) in scaled units: each block of rows against every tile in turn. */
template <class Real> LANES_INLINE void multiplyRows(const Blobs<Real>& b, int begin, int end, double* out) {
    typedef decltype(typename Lanes<Real>::Vector{} < typename Lanes<Real>::Vector{}) Mask;
    Mask masks[TiledBlobProduct::Tile/Lanes<Real>::Count];
    for (int first = begin; first < end; first += RowBlock) {
        const int last = std::min(end, first+RowBlock);
        double sums[3*RowBlock] = {0};
        for (int tile = 0; tile < b.padded; tile += TiledBlobProduct::Tile) {
            const int tileEnd = std::min(b.padded, tile+TiledBlobProduct::Tile);
            for (int i = first; i < last; i++) {
                double* sum = sums+3*(i-first);
                if (addPairsApart(b, i, tile, tileEnd, masks, sum))
                    addPairsLeftOut(b, i, tile, tileEnd, masks, sum);
                if (b.wall)
                    addImagePairs(b, i, tile, tileEnd, sum);
            }
        }
        for (int i = first; i < last; i++) {
            const double self = RotnePragerYamakawa::selfMobility(b.exactA[i]);
            out[3*i] = self*b.exactFx[i]+sums[3*(i-first)];
            out[3*i+1] = self*b.exactFy[i]+sums[3*(i-first)+1];
            out[3*i+2] = self*b.exactFz[i]+sums[3*(i-first)+2];
        }
    }
}

RIGIDLANGEVIN_TILED_CLONES void multiplyRowsInDouble(const Blobs<double>& b, int begin, int end, double* out) {
    multiplyRows(b, begin, end, out);
}

RIGIDLANGEVIN_TILED_CLONES void multiplyRowsInSingle(const Blobs<float>& b, int begin, int end, double* out) {
    multiplyRows(b, begin, end, out);
}

/** The power of two nearest above the largest magnitude in values (1 if none is positive): scaling by it is exact. */
double powerOfTwoAbove(const double* values, int count) {
    double largest = 0;
    for (int i = 0; i < count; i++)
        largest = std::max(largest, std::abs(values[i]));
    if (!(largest > 0) || !std::isfinite(largest))
        return 1;
    int exponent;
    std::frexp(largest, &exponent);
    return std::ldexp(1.0, exponent);
}

} // namespace

void TiledBlobProduct::setBlobs(const vector<Vec3>& positions, const vector<double>& radii) {
    wall = false;
    store(positions, radii);
    damping.assign(numBlobs, 1.0);
}

void TiledBlobProduct::setBlobsAboveWall(const vector<Vec3>& positions, const vector<double>& radii, double wallZ) {
    // M~ = B M(h~) B (RotnePragerBlake.h): z holds the evaluated heights h~, damping B's diagonal.
    vector<Vec3> raised(positions);
    damping.resize(positions.size());
    for (int i = 0; i < (int) positions.size(); i++) {
        const double h = positions[i][2]-wallZ;
        raised[i][2] = RotnePragerBlake::evaluatedHeight(h, radii[i]);
        damping[i] = RotnePragerBlake::damping(h, radii[i]);
    }
    wall = true;
    store(raised, radii);
}

void TiledBlobProduct::setSinglePrecision(bool single) {
    if (single != singleRequested) {
        singleRequested = single;
        fillSingleArrays();
    }
}

void TiledBlobProduct::store(const vector<Vec3>& positions, const vector<double>& radii) {
    numBlobs = positions.size();
    const int padded = (numBlobs+Padding-1)/Padding*Padding;
    // Lengths in units of a power of two near the largest radius (exactly), so that single
    // precision's range holds every pair term; M scales as 1/length.
    lengthScale = powerOfTwoAbove(radii.data(), numBlobs);
    // Padding: far from everything and from the wall (its lanes then add zero force times finite
    // numbers), radius one.
    for (vector<double>* v : {&x, &y, &z, &fx, &fy, &fz})
        v->assign(padded, 0.0);
    radius.assign(padded, 1.0);
    radius2.assign(padded, 1.0);
    for (int i = 0; i < padded; i++) {
        const Vec3 p = (i < numBlobs ? positions[i]/lengthScale : Vec3(1e9, 1e9, 1e9));
        x[i] = p[0];
        y[i] = p[1];
        z[i] = p[2];
        if (i < numBlobs) {
            radius[i] = radii[i]/lengthScale;
            radius2[i] = radius[i]*radius[i];
        }
    }
    fillSingleArrays();
}

void TiledBlobProduct::fillSingleArrays() {
    // Radii spanning more than MaxSingleRadiusRatio would take 1/r^3 of the closest pairs out of
    // single precision's range.
    const auto span = std::minmax_element(radius.begin(), radius.begin()+numBlobs);
    single = singleRequested && (numBlobs == 0 || *span.first*MaxSingleRadiusRatio >= *span.second);
    for (auto copy : {std::make_pair(&radius, &singleRadius), std::make_pair(&radius2, &singleRadius2), std::make_pair(&z, &singleHeight)}) {
        copy.second->assign(single ? copy.first->size() : 0, 0.0f);
        for (int i = 0; i < (int) copy.second->size(); i++)
            (*copy.second)[i] = (float) (*copy.first)[i];
    }
    for (vector<float>* v : {&singleFx, &singleFy, &singleFz})
        v->assign(single ? x.size() : 0, 0.0f);
}

void TiledBlobProduct::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out, const KrylovSolvers::ParallelFor& parallel) {
    // Forces in units of a power of two near the largest (exactly), for single precision's range.
    const double forceScale = powerOfTwoAbove(f.data(), 3*numBlobs), toForces = 1/forceScale;
    for (int i = 0; i < numBlobs; i++) {
        fx[i] = toForces*damping[i]*f[3*i];
        fy[i] = toForces*damping[i]*f[3*i+1];
        fz[i] = toForces*damping[i]*f[3*i+2];
    }
    for (int i = 0; i < (single ? numBlobs : 0); i++) {
        singleFx[i] = (float) fx[i];
        singleFy[i] = (float) fy[i];
        singleFz[i] = (float) fz[i];
    }
    out.resize(3*numBlobs);
    const int padded = x.size();
    const Blobs<double> inDouble = {x.data(), y.data(), z.data(), radius.data(), radius2.data(), z.data(), fx.data(), fy.data(), fz.data(),
                                    radius.data(), fx.data(), fy.data(), fz.data(), numBlobs, padded, wall};
    const Blobs<float> inSingle = {x.data(), y.data(), z.data(), singleRadius.data(), singleRadius2.data(), singleHeight.data(), singleFx.data(),
                                   singleFy.data(), singleFz.data(), radius.data(), fx.data(), fy.data(), fz.data(), numBlobs, padded, wall};
    const double toVelocities = forceScale/lengthScale;
    parallel(numBlobs, [&] (int begin, int end) {
        if (single)
            multiplyRowsInSingle(inSingle, begin, end, out.data());
        else
            multiplyRowsInDouble(inDouble, begin, end, out.data());
        for (int i = begin; i < end; i++)
            out.segment<3>(3*i) *= toVelocities*damping[i];
    });
}
