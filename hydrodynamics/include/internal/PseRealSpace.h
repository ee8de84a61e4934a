#ifndef RIGID_LANGEVIN_PSE_REAL_SPACE_H_
#define RIGID_LANGEVIN_PSE_REAL_SPACE_H_

#include "internal/PseParameters.h"
#include "internal/PseSmoothPartTable.h"
#include "internal/KrylovSolvers.h"
#include "openmm/Vec3.h"
#include <Eigen/Core>
#include <functional>
#include <vector>

namespace RigidLangevinPlugin {

/**
 * The real-space part of the positively split Ewald mobility: sum over pairs within their cutoff
 * a_i + a_j + cutoffBeyondContact (nearest image only; the cutoff is below half the box's narrowest
 * width) of F = RPY - G (PseSmoothPartTable), overlapping blobs included, plus each blob's own F(0).
 * The pairs are found with a cell list in the box's fractional coordinates and stored, both
 * directions, as rows (compressed sparse rows) in the cells' order, so that a row's neighbours lie
 * close together in memory: a product gathers f into that order, makes one pass over the rows,
 * each on its own thread with no write conflicts, and scatters the result back.
 */
class PseRealSpace {
public:
    typedef KrylovSolvers::ParallelFor ParallelFor;
    /**
     * Find and store the pairs, blob i of radius groupRadii[group[i]], in one search (its neighbours
     * held at 4 bytes a pair until the terms are stored). checkPairs(numPairs) is
     * called once they are counted and before they are stored (it throws if they would not fit the
     * memory budget).
     */
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<int>& group, const std::vector<double>& groupRadii,
                  const OpenMM::Vec3 box[3], const PseParameters& parameters, const ParallelFor& parallel,
                  const std::function<void (double numPairs)>& checkPairs);
    /** out = M_real f (out resized). */
    void multiply(const Eigen::VectorXd& f, Eigen::VectorXd& out, const ParallelFor& parallel) const;
    /** The stored pairs (each counted in both directions). */
    long long getNumPairs() const {
        return rowStart.empty() ? 0 : rowStart.back();
    }
    /** A pair's terms, in single or double precision (PseParameterChoice::singlePrecisionPairs). */
    template <class Real>
    struct Pair {
        int j;                              // in the cells' order
        Real isotropic, dyadicPerR2, d[3];  // F = isotropic I + dyadicPerR2 d d^T, d = r_j - r_i
    };
    // What a device needs to apply the same operator (CommonPseMobility), after setBlobs(): row i
    // (the blob order[i]) is self[i] I plus its pairs rowStart[i] ... rowStart[i+1], stored in
    // single precision (getSinglePairs() filled) or double (getDoublePairs()).
    const std::vector<int>& getOrder() const {
        return order;
    }
    const std::vector<double>& getSelf() const {
        return self;
    }
    const std::vector<long long>& getRowStart() const {
        return rowStart;
    }
    const std::vector<Pair<float>>& getSinglePairs() const {
        return singlePairs;
    }
    const std::vector<Pair<double>>& getDoublePairs() const {
        return doublePairs;
    }
private:
    /** The neighbours of rows [begin, end), row by row, as the search found them. */
    struct NeighbourRange {
        int begin, end;
        std::vector<int> neighbours;
    };
    /** Store the pairs' terms from the ranges' neighbours. */
    template <class Real>
    void storePairs(std::vector<Pair<Real>>& pairs, std::vector<NeighbourRange>& ranges, const ParallelFor& parallel);
    template <class Real>
    void storePair(Pair<Real>& pair, int i, int j, const OpenMM::Vec3& d, double r) const;
    template <class Real>
    void multiplyRows(const std::vector<Pair<Real>>& pairs, const Eigen::VectorXd& sorted, Eigen::VectorXd& out, const ParallelFor& parallel) const;
    /** Append to out every blob j != i (both in the cells' order) within i's pair cutoff, in the cells' order. */
    void appendNeighbours(int i, std::vector<int>& out) const;
    void buildCells(const std::vector<OpenMM::Vec3>& positions, double maxRadius);
    OpenMM::Vec3 box[3], inverse[3];  // inverse[d].r = fractional coordinate d
    double cutoffBeyondContact;
    PseSmoothPartTable table;
    std::vector<int> order;           // order[k] = the blob k-th in the cells' order
    std::vector<int> sortedGroup;     // by the cells' order
    std::vector<double> sortedRadius, self;
    std::vector<double> scaled[3];    // the blobs' fractional coordinates in the cells' order, one array per axis (the search's vector loads)
    int numCells[3];
    std::vector<int> cellStart;
    std::vector<long long> rowStart;
    std::vector<Pair<float>> singlePairs;   // one of the two is filled
    std::vector<Pair<double>> doublePairs;
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PSE_REAL_SPACE_H_*/
