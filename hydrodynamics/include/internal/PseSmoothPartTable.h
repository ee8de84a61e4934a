#ifndef RIGID_LANGEVIN_PSE_SMOOTH_PART_TABLE_H_
#define RIGID_LANGEVIN_PSE_SMOOTH_PART_TABLE_H_

#include "internal/RotnePragerYamakawa.h"
#include <algorithm>
#include <cmath>
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
    /** F = isotropic I + dyadicPerR2 d d^T for blobs of radius groups gi, gj at distance r (inline:
     *  the real-space pairs' terms call it once a pair). */
    void realSpace(double r, int gi, int gj, double& isotropic, double& dyadicPerR2) const {
        double dyadic;
        const double ai = radii[gi], aj = radii[gj];
        const double inverse = (r > 0 ? 1/r : 0.0), inverse2 = inverse*inverse;
        if (r > ai+aj) {
            // RPY apart (RotnePragerYamakawa::mobilityCoefficients) with the one division above.
            const double scale = inverse*(1/(8*M_PI));
            const double sigma2 = (ai*ai+aj*aj)*inverse2;
            isotropic = (1+sigma2*(1.0/3))*scale;
            dyadic = (1-sigma2)*scale;
        }
        else
            RotnePragerYamakawa::mobilityCoefficients(r, ai, aj, isotropic, dyadic);
        // Cubic Lagrange interpolation through nodes k-1 .. k+2 around r = (k + t) h.
        const double x = r*inverseSpacing;
        const int k = std::min((int) x, numNodes-1);
        const double t = x-k;
        const double w[4] = {-t*(t-1)*(t-2)*(1.0/6), (t+1)*(t-1)*(t-2)*0.5, -(t+1)*t*(t-2)*0.5, (t+1)*t*(t-1)*(1.0/6)};
        const double* table = &nodes[(size_t) (gi*radii.size()+gj)*2*(numNodes+3)+2*k];
        double smoothIsotropic = 0, smoothDyadic = 0;
        for (int n = 0; n < 4; n++) {
            smoothIsotropic += w[n]*table[2*n];
            smoothDyadic += w[n]*table[2*n+1];
        }
        isotropic -= smoothIsotropic;
        dyadicPerR2 = (dyadic-smoothDyadic)*inverse2;
    }
private:
    std::vector<double> radii;
    double xi = 0, maxDistance = 0, tolerance = 0, spacing = 1, inverseSpacing = 1;
    int numNodes = 0;
    std::vector<double> nodes;  // per pair of groups, per node from -1 to numNodes+1: A, B
};

} // namespace RigidLangevinPlugin

#endif /*RIGID_LANGEVIN_PSE_SMOOTH_PART_TABLE_H_*/
