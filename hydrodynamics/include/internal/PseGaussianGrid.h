#ifndef RIGID_LANGEVIN_PSE_GAUSSIAN_GRID_H_
#define RIGID_LANGEVIN_PSE_GAUSSIAN_GRID_H_

#include "internal/PseParameters.h"
#include "internal/KrylovSolvers.h"
#include "openmm/Vec3.h"
#include <Eigen/Core>
#include <vector>

namespace RigidLangevinPlugin {

struct PseBlobSupport;

/**
 * Spreading of the blobs' forces onto the positively split Ewald grid and interpolation back, both
 * with the normalised Gaussian g(x) = (2 pi sigma^2)^-3/2 exp(-|x|^2/2 sigma^2) truncated to the
 * P x P x P grid points nearest each blob (interpolation is spreading's transpose, so the wave-space
 * operator stays symmetric positive semidefinite). The grid's points are x_m = sum_d (m_d/M_d) box_d
 * in a triclinic box; there |x_m - r|^2 splits into a product of one factor per axis per blob and a
 * P^3 table shared by all blobs (1 in a rectangular box), so a blob costs 3P exponentials per
 * setBlobs() and P^3 multiplications per product. A grid is M0 x M1 x M2 points of three
 * interleaved components (x fastest).
 *
 * Spreading is a gather by grid plane (along the first box vector): each thread writes whole
 * planes, taking the blobs whose support reaches them, so no two threads write the same point.
 */
class PseGaussianGrid {
public:
    typedef KrylovSolvers::ParallelFor ParallelFor;
    /** The blobs, blob i in radius group group[i] of numGroups. */
    void setBlobs(const std::vector<OpenMM::Vec3>& positions, const std::vector<int>& group, int numGroups, const OpenMM::Vec3 box[3],
                  const PseParameters& parameters, const ParallelFor& parallel);
    /** grid = sum over the blobs of group g of g(x - r_i) f_i (3 per blob in f). */
    void spread(const Eigen::VectorXd& f, int g, double* grid, const ParallelFor& parallel) const;
    /** out_i = sum_m g(x_m - r_i) grid_m for each blob i of group g (others untouched). */
    void interpolate(const double* grid, int g, Eigen::VectorXd& out, const ParallelFor& parallel) const;
    // What a device needs to spread and interpolate alike (CommonPseMobility), after setBlobs():
    /** Per blob, its support's first grid index along each axis (wrapped). */
    const std::vector<int>& getBase() const {
        return base;
    }
    /** Per blob, P factors along each axis (the Gaussian's constant in the first axis's). */
    const std::vector<double>& getFactors() const {
        return factors;
    }
    /** P^3 factors shared by all blobs, (n0 P + n1) P + n2; empty in a rectangular box (all ones). */
    std::vector<double> getCrossFactors() const {
        return (orthogonal ? std::vector<double>() : cross);
    }
    /** The blobs of group g are getGroupBlobs()[getGroupStart()[g] ... getGroupStart()[g+1]). */
    const std::vector<int>& getGroupStart() const {
        return groupStart;
    }
    const std::vector<int>& getGroupBlobs() const {
        return groupBlobs;
    }
private:
    void blobWeights(const OpenMM::Vec3& position, const OpenMM::Vec3 box[3], const OpenMM::Vec3 inverse[3], int i);
    /** Blob i's factors, first grid point and the grid, for the per-blob loops. */
    PseBlobSupport blobSupport(int i) const;
    int grid[3], support;
    bool orthogonal;             // a rectangular box: the shared table is all ones
    double sigma;
    double metric[3][3];        // h_d . h_e, h_d = box_d/M_d
    std::vector<int> base;       // per blob, its support's first grid index along each axis (wrapped)
    std::vector<double> factors; // per blob, P factors along each axis (the constant in the first)
    std::vector<double> cross;   // P^3, exp(-(sum_{d<e} 2 metric_de n_d n_e)/2 sigma^2)
    std::vector<int> groupStart, groupBlobs;  // the blobs of each group, by their support's first point along axes 0, 1
    std::vector<int> planeStart;              // per group, M0+1 offsets into groupBlobs by first plane
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PSE_GAUSSIAN_GRID_H_*/
