#include "internal/PseGaussianGrid.h"
#include "internal/TargetClones.h"
#include <algorithm>
#include <cmath>

using namespace RigidLangevinPlugin;
using OpenMM::Vec3;
using std::vector;

void PseGaussianGrid::blobWeights(const Vec3& position, const Vec3 /*box*/[3], const Vec3 inverse[3], int i) {
    // The support: the P points along each axis nearest the blob, from base; e_d = base_d - u_d is
    // the first point's offset in grid units.
    double e[3];
    for (int d = 0; d < 3; d++) {
        double s = position.dot(inverse[d]);
        s -= std::floor(s);
        const double u = s*grid[d];
        const int first = (int) std::floor(u-0.5*support)+1;
        e[d] = first-u;
        base[3*i+d] = ((first%grid[d])+grid[d])%grid[d];
    }
    // |x - r|^2 = sum_de metric_de (e_d + n_d)(e_e + n_e): the terms in n_d alone go to axis d's
    // factors, those in e alone to the constant, those in n_d n_e to the shared table.
    const double c = 1/(2*sigma*sigma);
    double* w = &factors[(size_t) 3*support*i];
    for (int d = 0; d < 3; d++) {
        double linear = 0;
        for (int other = 0; other < 3; other++)
            if (other != d)
                linear += 2*metric[d][other]*e[other];
        for (int n = 0; n < support; n++)
            w[d*support+n] = std::exp(-c*(metric[d][d]*(e[d]+n)*(e[d]+n)+linear*n));
    }
    const double constant = std::pow(2*M_PI*sigma*sigma, -1.5)*std::exp(-2*c*(metric[0][1]*e[0]*e[1]+metric[0][2]*e[0]*e[2]+metric[1][2]*e[1]*e[2]));
    for (int n = 0; n < support; n++)
        w[n] *= constant;
}

void PseGaussianGrid::setBlobs(const vector<Vec3>& positions, const vector<int>& group, int numGroups, const Vec3 box[3],
                               const PseParameters& parameters, const ParallelFor& parallel) {
    const int n = positions.size(), p = parameters.support;
    const double volume = box[0].dot(box[1].cross(box[2]));
    Vec3 inverse[3], spacing[3];
    for (int d = 0; d < 3; d++) {
        grid[d] = parameters.grid[d];
        inverse[d] = box[(d+1)%3].cross(box[(d+2)%3])/volume;
        spacing[d] = box[d]/grid[d];
    }
    support = p;
    sigma = parameters.gaussianWidth;
    for (int d = 0; d < 3; d++)
        for (int e = 0; e < 3; e++)
            metric[d][e] = spacing[d].dot(spacing[e]);
    cross.resize(p*p*p);
    for (int n0 = 0; n0 < p; n0++)
        for (int n1 = 0; n1 < p; n1++)
            for (int n2 = 0; n2 < p; n2++)
                cross[(n0*p+n1)*p+n2] = std::exp(-(metric[0][1]*n0*n1+metric[0][2]*n0*n2+metric[1][2]*n1*n2)/(sigma*sigma));
    base.resize(3*n);
    factors.resize((size_t) 3*p*n);
    parallel(n, [&] (int begin, int end) {
        for (int i = begin; i < end; i++)
            blobWeights(positions[i], box, inverse, i);
    });
    // The blobs by group, then by their support's first point along the first two axes (a counting
    // sort): blobs that follow each other touch nearby grid points.
    const int planes = grid[0], rows = grid[1];
    vector<int> start((size_t) numGroups*planes*rows+1, 0);
    auto key = [&] (int i) { return ((size_t) group[i]*planes+base[3*i])*rows+base[3*i+1]; };
    for (int i = 0; i < n; i++)
        start[key(i)+1]++;
    for (size_t k = 0; k+1 < start.size(); k++)
        start[k+1] += start[k];
    groupBlobs.resize(n);
    vector<int> next(start.begin(), start.end()-1);
    for (int i = 0; i < n; i++)
        groupBlobs[next[key(i)]++] = i;
    planeStart.resize((size_t) numGroups*(planes+1));
    groupStart.resize(numGroups+1);
    for (int g = 0; g < numGroups; g++) {
        groupStart[g] = start[(size_t) g*planes*rows];
        for (int b = 0; b <= planes; b++)
            planeStart[(size_t) g*(planes+1)+b] = start[((size_t) g*planes+b)*rows];
    }
    groupStart[numGroups] = n;
    orthogonal = (metric[0][1] == 0 && metric[0][2] == 0 && metric[1][2] == 0);
}


namespace RigidLangevinPlugin {

/** One blob's support: its P factors along each axis, its first grid point, the grid. */
struct PseBlobSupport {
    const double* w;
    const int* base;
    int p;
    const int* grid;
    const double* cross;  // null in a rectangular box (all ones)
};

} // namespace RigidLangevinPlugin

namespace {


/** The grid indices, wrapped, of the support from first on an axis of m points (p <= m). */
inline void supportIndices(int first, int p, int m, int* index) {
    for (int n = 0; n < p; n++)
        index[n] = (first+n >= m ? first+n-m : first+n);
}

/** Blob s's share of plane n0 of its support. */
RIGIDLANGEVIN_CLONES void spreadBlob(const PseBlobSupport& s, int n0, const double force[3], double* plane) {
    const int p = s.p;
    int index1[PseMaxSupport], index2[PseMaxSupport];
    supportIndices(s.base[1], p, s.grid[1], index1);
    supportIndices(s.base[2], p, s.grid[2], index2);
    // Along the last axis the support is contiguous unless it wraps: then one loop of 3P
    // multiply-adds over the interleaved components, which vectorises.
    const bool contiguous = (s.base[2]+p <= s.grid[2] && s.cross == nullptr);
    double weightedForce[3*PseMaxSupport];
    for (int n2 = 0; n2 < p; n2++)
        for (int c = 0; c < 3; c++)
            weightedForce[3*n2+c] = s.w[2*p+n2]*force[c];
    for (int n1 = 0; n1 < p; n1++) {
        const double w01 = s.w[n0]*s.w[p+n1];
        double* row = plane+(size_t) index1[n1]*s.grid[2]*3;
        if (contiguous) {
            double* point = row+3*s.base[2];
            for (int k = 0; k < 3*p; k++)
                point[k] += w01*weightedForce[k];
            continue;
        }
        for (int n2 = 0; n2 < p; n2++) {
            const double weight = w01*(s.cross == nullptr ? 1.0 : s.cross[(n0*p+n1)*p+n2]);
            double* point = row+3*index2[n2];
            for (int c = 0; c < 3; c++)
                point[c] += weight*weightedForce[3*n2+c];
        }
    }
}

/** u = blob s's Gaussian times the grid in, over its support. */
RIGIDLANGEVIN_CLONES void interpolateBlob(const PseBlobSupport& s, const double* in, double u[3]) {
    const int p = s.p;
    int index0[PseMaxSupport], index1[PseMaxSupport], index2[PseMaxSupport];
    supportIndices(s.base[0], p, s.grid[0], index0);
    supportIndices(s.base[1], p, s.grid[1], index1);
    supportIndices(s.base[2], p, s.grid[2], index2);
    const bool contiguous = (s.base[2]+p <= s.grid[2] && s.cross == nullptr);
    // The sums of the last axis's weights times the grid, per interleaved component (as spreading).
    double sums[3*PseMaxSupport] = {0};
    for (int n0 = 0; n0 < p; n0++)
        for (int n1 = 0; n1 < p; n1++) {
            const double w01 = s.w[n0]*s.w[p+n1];
            const double* row = in+((size_t) index0[n0]*s.grid[1]+index1[n1])*s.grid[2]*3;
            if (contiguous) {
                const double* point = row+3*s.base[2];
                for (int k = 0; k < 3*p; k++)
                    sums[k] += w01*point[k];
                continue;
            }
            for (int n2 = 0; n2 < p; n2++) {
                const double weight = w01*(s.cross == nullptr ? 1.0 : s.cross[(n0*p+n1)*p+n2]);
                const double* point = row+3*index2[n2];
                for (int c = 0; c < 3; c++)
                    sums[3*n2+c] += weight*point[c];
            }
        }
    u[0] = u[1] = u[2] = 0;
    for (int n2 = 0; n2 < p; n2++)
        for (int c = 0; c < 3; c++)
            u[c] += s.w[2*p+n2]*sums[3*n2+c];
}

} // namespace

PseBlobSupport PseGaussianGrid::blobSupport(int i) const {
    return {&factors[(size_t) 3*support*i], &base[3*i], support, grid, (orthogonal ? nullptr : cross.data())};
}

void PseGaussianGrid::spread(const Eigen::VectorXd& f, int g, double* out, const ParallelFor& parallel) const {
    const int planes = grid[0];
    const size_t planeSize = (size_t) grid[1]*grid[2]*3;
    const int* starts = &planeStart[(size_t) g*(planes+1)];
    parallel(planes, [&] (int begin, int end) {
        for (int i0 = begin; i0 < end; i0++) {
            double* plane = out+i0*planeSize;
            std::fill(plane, plane+planeSize, 0.0);
            // The blobs whose support's first plane is n0 before this one (P <= M0).
            for (int n0 = 0; n0 < support; n0++) {
                const int first = (i0-n0+planes)%planes;
                for (int k = starts[first]; k < starts[first+1]; k++) {
                    const int i = groupBlobs[k];
                    const double force[3] = {f[3*i], f[3*i+1], f[3*i+2]};
                    spreadBlob(blobSupport(i), n0, force, plane);
                }
            }
        }
    });
}

void PseGaussianGrid::interpolate(const double* in, int g, Eigen::VectorXd& out, const ParallelFor& parallel) const {
    const int first = groupStart[g];
    parallel(groupStart[g+1]-first, [&] (int begin, int end) {
        for (int k = first+begin; k < first+end; k++) {
            const int i = groupBlobs[k];
            double u[3];
            interpolateBlob(blobSupport(i), in, u);
            for (int c = 0; c < 3; c++)
                out[3*i+c] = u[c];
        }
    });
}
