#include "internal/PseRealSpace.h"
#include "internal/TargetClones.h"
#include <algorithm>
#include <cmath>
#include <mutex>

using namespace RigidLangevinPlugin;
using OpenMM::Vec3;
using std::vector;

namespace {

/** s - round(s) for |s| < 1. */
double nearest(double s) {
    return (s > 0.5 ? s-1 : (s < -0.5 ? s+1 : s));
}

} // namespace

void PseRealSpace::buildCells(const vector<Vec3>& positions, double maxRadius) {
    // Cells at least the cutoff wide in every direction: a pair within the cutoff is in the same
    // or adjacent cells (|delta s_d| <= r/width_d), and there are at least two along each axis.
    const int n = positions.size();
    double widths[3];
    PseParameterChoice::boxWidths(box, widths);
    for (int d = 0; d < 3; d++)
        numCells[d] = std::max(1, (int) (widths[d]/(2*maxRadius+cutoffBeyondContact)));
    // Memory O(blobs): no more than about two cells per blob (larger cells are still correct).
    const double excess = std::cbrt((double) numCells[0]*numCells[1]*numCells[2]/(2.0*n+27));
    if (excess > 1)
        for (int d = 0; d < 3; d++)
            numCells[d] = std::max(1, (int) (numCells[d]/excess));
    vector<Vec3> blobFractional(n);
    vector<int> blobCell(n);
    cellStart.assign(numCells[0]*numCells[1]*numCells[2]+1, 0);
    for (int i = 0; i < n; i++) {
        int cell = 0;
        for (int d = 0; d < 3; d++) {
            double s = positions[i].dot(inverse[d]);
            s -= std::floor(s);
            blobFractional[i][d] = s;
            cell = cell*numCells[d]+std::min(numCells[d]-1, (int) (s*numCells[d]));
        }
        blobCell[i] = cell;
        cellStart[cell+1]++;
    }
    for (int c = 0; c+1 < (int) cellStart.size(); c++)
        cellStart[c+1] += cellStart[c];
    order.resize(n);
    vector<int> next(cellStart.begin(), cellStart.end()-1);
    for (int d = 0; d < 3; d++)
        scaled[d].resize(n);
    for (int i = 0; i < n; i++) {
        const int k = next[blobCell[i]]++;
        order[k] = i;
        for (int d = 0; d < 3; d++)
            scaled[d][k] = blobFractional[i][d];
    }
}

RIGIDLANGEVIN_CLONES void PseRealSpace::appendNeighbours(int i, vector<int>& out) const {
    int cell[3];
    for (int d = 0; d < 3; d++)
        cell[d] = std::min(numCells[d]-1, (int) (scaled[d][i]*numCells[d]));
    // The distinct neighbouring cells along each axis (fewer than three where there are fewer cells).
    int neighbours[3][3], numNeighbours[3];
    for (int d = 0; d < 3; d++) {
        numNeighbours[d] = 0;
        for (int o = -1; o <= 1; o++) {
            int c = (cell[d]+o+numCells[d])%numCells[d];
            if (std::find(neighbours[d], neighbours[d]+numNeighbours[d], c) == neighbours[d]+numNeighbours[d])
                neighbours[d][numNeighbours[d]++] = c;
        }
    }
    // Each cell's blobs are contiguous in the cells' order: their distances are computed a block at
    // a time without branches (the nearest image by comparisons, which vectorise), then the blobs
    // within i's cutoff are kept.
    const int Block = 64;
    double excess[Block];
    const double* sx = scaled[0].data();
    const double* sy = scaled[1].data();
    const double* sz = scaled[2].data();
    const double* radius = sortedRadius.data();
    const double fi[3] = {scaled[0][i], scaled[1][i], scaled[2][i]}, reach = sortedRadius[i]+cutoffBeyondContact;
    const double b00 = box[0][0], b01 = box[0][1], b02 = box[0][2], b10 = box[1][0], b11 = box[1][1], b12 = box[1][2];
    const double b20 = box[2][0], b21 = box[2][1], b22 = box[2][2];
    for (int u = 0; u < numNeighbours[0]; u++)
        for (int v = 0; v < numNeighbours[1]; v++)
            for (int w = 0; w < numNeighbours[2]; w++) {
                const int c = (neighbours[0][u]*numCells[1]+neighbours[1][v])*numCells[2]+neighbours[2][w];
                for (int first = cellStart[c]; first < cellStart[c+1]; first += Block) {
                    const int count = std::min(Block, cellStart[c+1]-first);
                    for (int t = 0; t < count; t++) {
                        const int j = first+t;
                        double s0 = sx[j]-fi[0], s1 = sy[j]-fi[1], s2 = sz[j]-fi[2];
                        s0 += (s0 < -0.5 ? 1.0 : 0.0)-(s0 > 0.5 ? 1.0 : 0.0);
                        s1 += (s1 < -0.5 ? 1.0 : 0.0)-(s1 > 0.5 ? 1.0 : 0.0);
                        s2 += (s2 < -0.5 ? 1.0 : 0.0)-(s2 > 0.5 ? 1.0 : 0.0);
                        const double dx = b00*s0+b10*s1+b20*s2, dy = b01*s0+b11*s1+b21*s2, dz = b02*s0+b12*s1+b22*s2;
                        const double cutoff = reach+radius[j];
                        excess[t] = dx*dx+dy*dy+dz*dz-cutoff*cutoff;
                    }
                    for (int t = 0; t < count; t++)
                        if (excess[t] < 0 && first+t != i)
                            out.push_back(first+t);
                }
            }
}

void PseRealSpace::setBlobs(const vector<Vec3>& positions, const vector<int>& group, const vector<double>& groupRadii, const Vec3 boxVectors[3],
                            const PseParameters& parameters, const ParallelFor& parallel, const std::function<void (double)>& checkPairs) {
    const int n = positions.size();
    const double volume = boxVectors[0].dot(boxVectors[1].cross(boxVectors[2]));
    for (int d = 0; d < 3; d++) {
        box[d] = boxVectors[d];
        inverse[d] = boxVectors[(d+1)%3].cross(boxVectors[(d+2)%3])/volume;
    }
    cutoffBeyondContact = parameters.cutoffBeyondContact;
    const double maxRadius = *std::max_element(groupRadii.begin(), groupRadii.end());
    table.build(groupRadii, parameters.xi, 2*maxRadius+cutoffBeyondContact, parameters.tolerance);
    buildCells(positions, maxRadius);
    sortedGroup.resize(n);
    sortedRadius.resize(n);
    for (int k = 0; k < n; k++) {
        sortedGroup[k] = group[order[k]];
        sortedRadius[k] = groupRadii[sortedGroup[k]];
    }
    // One search: each range of rows keeps its neighbours (4 bytes a pair) while the pairs are
    // counted and the budget checked; then the rows' terms are stored from them.
    vector<long long> counts(n);
    vector<NeighbourRange> ranges;
    std::mutex rangesLock;
    // Room for 5% more neighbours a row than the last configuration had (a vector doubling as it grows would hold up to twice them).
    const double lastPerRow = (rowStart.size() > 1 ? (double) rowStart.back()/(rowStart.size()-1) : 0.0);
    parallel(n, [&] (int begin, int end) {
        NeighbourRange range = {begin, end, {}};
        range.neighbours.reserve((size_t) (1.05*lastPerRow*(end-begin)));
        for (int i = begin; i < end; i++) {
            const size_t before = range.neighbours.size();
            appendNeighbours(i, range.neighbours);
            counts[i] = range.neighbours.size()-before;
        }
        std::lock_guard<std::mutex> guard(rangesLock);
        ranges.push_back(std::move(range));
    });
    rowStart.assign(n+1, 0);
    for (int i = 0; i < n; i++)
        rowStart[i+1] = rowStart[i]+counts[i];
    checkPairs((double) rowStart[n]);
    // The other precision's pairs are released; this one's memory is kept for the next configuration
    // (allocating it again, page by page, cost a tenth of the search).
    const bool single = PseParameterChoice::singlePrecisionPairs(parameters.tolerance);
    if (single)
        vector<Pair<double>>().swap(doublePairs);
    else
        vector<Pair<float>>().swap(singlePairs);
    self.resize(n);
    parallel(n, [&] (int begin, int end) {
        for (int i = begin; i < end; i++) {
            double dyadic;
            table.realSpace(0, sortedGroup[i], sortedGroup[i], self[i], dyadic);
        }
    });
    if (single)
        storePairs(singlePairs, ranges, parallel);
    else
        storePairs(doublePairs, ranges, parallel);
}

template <class Real>
void PseRealSpace::storePairs(vector<Pair<Real>>& pairs, vector<NeighbourRange>& ranges, const ParallelFor& parallel) {
    // Memory kept from the last configuration is reused; where it is too small it is released before
    // the new is allocated (growing it in place would copy the old pairs and hold both), with 1% to
    // spare, as the count moves a little from one configuration to the next.
    const size_t numPairs = rowStart.back();
    if (pairs.capacity() < numPairs) {
        vector<Pair<Real>>().swap(pairs);
        pairs.reserve(numPairs+numPairs/100);
    }
    pairs.resize(numPairs);
    // Shared out by rows (there may be fewer ranges than threads would take), each row's neighbours
    // found in the range that holds it.
    std::sort(ranges.begin(), ranges.end(), [] (const NeighbourRange& a, const NeighbourRange& b) { return a.begin < b.begin; });
    parallel(self.size(), [&] (int begin, int end) {
        size_t r = std::upper_bound(ranges.begin(), ranges.end(), begin, [] (int row, const NeighbourRange& range) { return row < range.begin; })-ranges.begin()-1;
        for (int i = begin; i < end; i++) {
            while (i >= ranges[r].end)
                r++;
            const int* neighbours = ranges[r].neighbours.data()-rowStart[ranges[r].begin];
            for (long long k = rowStart[i]; k < rowStart[i+1]; k++) {
                // The nearest image's offset, d = r_j - r_i.
                const int j = neighbours[k];
                const Vec3 s(scaled[0][j]-scaled[0][i], scaled[1][j]-scaled[1][i], scaled[2][j]-scaled[2][i]);
                const Vec3 d = box[0]*nearest(s[0])+box[1]*nearest(s[1])+box[2]*nearest(s[2]);
                storePair(pairs[k], i, j, d, std::sqrt(d.dot(d)));
            }
        }
    });
}

template <class Real>
void PseRealSpace::storePair(Pair<Real>& pair, int i, int j, const Vec3& d, double r) const {
    pair.j = j;
    double isotropic, dyadicPerR2;
    table.realSpace(r, sortedGroup[i], sortedGroup[j], isotropic, dyadicPerR2);
    pair.isotropic = (Real) isotropic;
    pair.dyadicPerR2 = (Real) dyadicPerR2;
    for (int c = 0; c < 3; c++)
        pair.d[c] = (Real) d[c];
}

void PseRealSpace::multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out, const ParallelFor& parallel) const {
    const int n = self.size();
    Eigen::VectorXd sorted(3*n);
    for (int k = 0; k < n; k++)
        sorted.segment<3>(3*k) = f.segment<3>(3*order[k]);
    out.resize(3*n);
    if (singlePairs.empty())
        multiplyRows(doublePairs, sorted, out, parallel);
    else
        multiplyRows(singlePairs, sorted, out, parallel);
}

template <class Real>
void PseRealSpace::multiplyRows(const vector<Pair<Real>>& pairs, const Eigen::VectorXd& sorted, Eigen::VectorXd& out, const ParallelFor& parallel) const {
    parallel(self.size(), [&] (int begin, int end) {
        for (int i = begin; i < end; i++) {
            const double* fi = sorted.data()+3*i;
            double u[3] = {self[i]*fi[0], self[i]*fi[1], self[i]*fi[2]};
            for (long long k = rowStart[i]; k < rowStart[i+1]; k++) {
                const Pair<Real>& pair = pairs[k];
                const double* fj = sorted.data()+3*pair.j;
                const double projection = pair.dyadicPerR2*(pair.d[0]*fj[0]+pair.d[1]*fj[1]+pair.d[2]*fj[2]);
                for (int c = 0; c < 3; c++)
                    u[c] += pair.isotropic*fj[c]+projection*pair.d[c];
            }
            for (int c = 0; c < 3; c++)
                out[3*order[i]+c] = u[c];
        }
    });
}
