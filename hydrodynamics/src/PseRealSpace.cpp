#include "internal/PseRealSpace.h"
#include <algorithm>
#include <cmath>

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
    vector<Vec3> scaled(n);
    vector<int> blobCell(n);
    cellStart.assign(numCells[0]*numCells[1]*numCells[2]+1, 0);
    for (int i = 0; i < n; i++) {
        int cell = 0;
        for (int d = 0; d < 3; d++) {
            double s = positions[i].dot(inverse[d]);
            s -= std::floor(s);
            scaled[i][d] = s;
            cell = cell*numCells[d]+std::min(numCells[d]-1, (int) (s*numCells[d]));
        }
        blobCell[i] = cell;
        cellStart[cell+1]++;
    }
    for (int c = 0; c+1 < (int) cellStart.size(); c++)
        cellStart[c+1] += cellStart[c];
    order.resize(n);
    fractional.resize(n);
    vector<int> next(cellStart.begin(), cellStart.end()-1);
    for (int i = 0; i < n; i++) {
        const int k = next[blobCell[i]]++;
        order[k] = i;
        fractional[k] = scaled[i];
    }
}

template <class Visit>
void PseRealSpace::forEachNeighbour(int i, const Visit& visit) const {
    int cell[3];
    for (int d = 0; d < 3; d++)
        cell[d] = std::min(numCells[d]-1, (int) (fractional[i][d]*numCells[d]));
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
    for (int u = 0; u < numNeighbours[0]; u++)
        for (int v = 0; v < numNeighbours[1]; v++)
            for (int w = 0; w < numNeighbours[2]; w++) {
                const int c = (neighbours[0][u]*numCells[1]+neighbours[1][v])*numCells[2]+neighbours[2][w];
                for (int j = cellStart[c]; j < cellStart[c+1]; j++) {
                    if (j == i)
                        continue;
                    const Vec3 s = fractional[j]-fractional[i];
                    const Vec3 d = box[0]*nearest(s[0])+box[1]*nearest(s[1])+box[2]*nearest(s[2]);
                    const double r2 = d.dot(d), cutoff = sortedRadius[i]+sortedRadius[j]+cutoffBeyondContact;
                    if (r2 < cutoff*cutoff)
                        visit(j, d, std::sqrt(r2));
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
    // Count, check the budget, then store.
    vector<long long> counts(n);
    parallel(n, [&] (int begin, int end) {
        for (int i = begin; i < end; i++) {
            long long count = 0;
            forEachNeighbour(i, [&] (int, const Vec3&, double) { count++; });
            counts[i] = count;
        }
    });
    rowStart.assign(n+1, 0);
    for (int i = 0; i < n; i++)
        rowStart[i+1] = rowStart[i]+counts[i];
    checkPairs((double) rowStart[n]);
    singlePairs.clear();
    singlePairs.shrink_to_fit();
    doublePairs.clear();
    doublePairs.shrink_to_fit();
    self.resize(n);
    parallel(n, [&] (int begin, int end) {
        for (int i = begin; i < end; i++) {
            double dyadic;
            table.realSpace(0, sortedGroup[i], sortedGroup[i], self[i], dyadic);
        }
    });
    if (PseParameterChoice::singlePrecisionPairs(parameters.tolerance))
        storePairs(singlePairs, parallel);
    else
        storePairs(doublePairs, parallel);
}

template <class Real>
void PseRealSpace::storePairs(vector<Pair<Real>>& pairs, const ParallelFor& parallel) {
    const int n = self.size();
    pairs.resize(rowStart[n]);
    parallel(n, [&] (int begin, int end) {
        for (int i = begin; i < end; i++) {
            long long k = rowStart[i];
            forEachNeighbour(i, [&] (int j, const Vec3& d, double r) {
                Pair<Real>& pair = pairs[k++];
                pair.j = j;
                double isotropic, dyadicPerR2;
                table.realSpace(r, sortedGroup[i], sortedGroup[j], isotropic, dyadicPerR2);
                pair.isotropic = (Real) isotropic;
                pair.dyadicPerR2 = (Real) dyadicPerR2;
                for (int c = 0; c < 3; c++)
                    pair.d[c] = (Real) d[c];
            });
        }
    });
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
