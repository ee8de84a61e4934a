#ifndef RIGID_LANGEVIN_PSE_SMOOTH_PART_TABLE_H_
#define RIGID_LANGEVIN_PSE_SMOOTH_PART_TABLE_H_

#include <vector>

namespace RigidLangevinPlugin {

/**
 * The real-space pair function F = RPY - G of the positively split Ewald mobility for a few blob
 * radii, fast: RPY in closed form (RotnePragerYamakawa.h) and Hasimoto's smooth part G = A I + B rr
 * from a table of A(r) and B(r) per pair of radii, interpolated by cubic Lagrange polynomials on
 * uniform nodes (A and B are even, smooth functions of r varying on the scale 1/xi, so the table is
 * extended to negative r by symmetry). The node spacing c/xi, c = (epsilon/100)^1/4 (at most 0.05),
 * keeps the interpolation error near 1e-3 epsilon of G (TestPositivelySplitEwald checks the whole
 * product against the dense sum); the closed form (HasimotoSplit.h) costs some ten times more.
 */
class PseSmoothPartTable {
public:
    /** Tabulate G for every pair of radii on [0, maxDistance]; nothing is done if the arguments
     *  are those of the last call. */
    void build(const std::vector<double>& radii, double xi, double maxDistance, double tolerance);
    /** F = isotropic I + dyadicPerR2 d d^T for blobs of radius groups gi, gj at distance r. */
    void realSpace(double r, int gi, int gj, double& isotropic, double& dyadicPerR2) const;
private:
    std::vector<double> radii;
    double xi = 0, maxDistance = 0, tolerance = 0, spacing = 1;
    int numNodes = 0;
    std::vector<double> nodes;  // per pair of groups, per node from -1 to numNodes+1: A, B
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PSE_SMOOTH_PART_TABLE_H_*/
