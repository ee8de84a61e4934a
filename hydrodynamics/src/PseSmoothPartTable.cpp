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
    inverseSpacing = 1/spacing;
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
