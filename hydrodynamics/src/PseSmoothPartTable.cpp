#include "internal/PseSmoothPartTable.h"
#include "internal/HasimotoSplit.h"
#include "internal/RotnePragerYamakawa.h"
#include <algorithm>
#include <cmath>

using namespace RigidLangevinPlugin;

void PseSmoothPartTable::build(const std::vector<double>& radii, double xi, double maxDistance, double tolerance) {
    if (radii == this->radii && xi == this->xi && maxDistance <= this->maxDistance && tolerance == this->tolerance)
        return;
    this->radii = radii;
    this->xi = xi;
    this->maxDistance = maxDistance;
    this->tolerance = tolerance;
    spacing = std::min(0.05, std::pow(0.01*tolerance, 0.25))/xi;
    numNodes = (int) std::ceil(maxDistance/spacing)+1;
    const int numGroups = radii.size(), stride = 2*(numNodes+3);
    nodes.resize((size_t) numGroups*numGroups*stride);
    for (int gi = 0; gi < numGroups; gi++)
        for (int gj = 0; gj < numGroups; gj++) {
            double* table = &nodes[(size_t) (gi*numGroups+gj)*stride];
            for (int k = 0; k <= numNodes+1; k++)
                HasimotoSplit::smoothPart(k*spacing, radii[gi], radii[gj], xi, table[2*(k+1)], table[2*(k+1)+1]);
            table[0] = table[4];  // node -1 mirrors node 1
            table[1] = table[5];
        }
}

void PseSmoothPartTable::realSpace(double r, int gi, int gj, double& isotropic, double& dyadicPerR2) const {
    double dyadic;
    RotnePragerYamakawa::mobilityCoefficients(r, radii[gi], radii[gj], isotropic, dyadic);
    // Cubic Lagrange interpolation through nodes k-1 .. k+2 around r = (k + t) h.
    const double x = r/spacing;
    const int k = std::min((int) x, numNodes-1);
    const double t = x-k;
    const double w[4] = {-t*(t-1)*(t-2)/6, (t+1)*(t-1)*(t-2)/2, -(t+1)*t*(t-2)/2, (t+1)*t*(t-1)/6};
    const double* table = &nodes[(size_t) (gi*radii.size()+gj)*2*(numNodes+3)+2*k];
    double smoothIsotropic = 0, smoothDyadic = 0;
    for (int n = 0; n < 4; n++) {
        smoothIsotropic += w[n]*table[2*n];
        smoothDyadic += w[n]*table[2*n+1];
    }
    isotropic -= smoothIsotropic;
    dyadicPerR2 = (r > 0 ? (dyadic-smoothDyadic)/(r*r) : 0.0);
}
