#include "internal/CarlsonIntegrals.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <string>

using OpenMM::OpenMMException;

namespace {

/**
 * The relative error asked of the duplication loops. Carlson's truncation error after the loop is
 * below it; at 1e-16 the result is limited by rounding alone.
 */
const double RELATIVE_ERROR = 1e-16;

std::string arguments(double x, double y, double z) {
    return "("+std::to_string(x)+", "+std::to_string(y)+", "+std::to_string(z)+")";
}

} // namespace

double RigidLangevinPlugin::CarlsonIntegrals::carlsonRF(double x, double y, double z) {
    if (!(x >= 0 && y >= 0 && z >= 0) || !std::isfinite(x+y+z) || (x == 0)+(y == 0)+(z == 0) > 1)
        throw OpenMMException("carlsonRF"+arguments(x, y, z)+": the arguments must be finite and non-negative, with at most one of them zero");
    // Each duplication step x -> (x+lambda)/4 leaves R_F unchanged and pulls the three arguments
    // towards their mean by a factor 4; once they agree to the tolerance, a fifth-order Taylor
    // expansion about the mean finishes the job (Carlson 1995, Algorithm 1).
    const double x0 = x, y0 = y;
    double a0 = (x+y+z)/3;
    double q = std::pow(3*RELATIVE_ERROR, -1.0/6.0)*std::max({std::abs(a0-x), std::abs(a0-y), std::abs(a0-z)});
    double a = a0, scale = 1;
    while (scale*q >= std::abs(a)) {
        double sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z);
        double lambda = sx*sy+sx*sz+sy*sz;
        x = 0.25*(x+lambda);
        y = 0.25*(y+lambda);
        z = 0.25*(z+lambda);
        a = 0.25*(a+lambda);
        scale *= 0.25;
    }
    // (a0-x0)/4^m equals a-x exactly in exact arithmetic but without its cancellation.
    double dx = (a0-x0)*scale/a, dy = (a0-y0)*scale/a;
    double dz = -dx-dy;
    double e2 = dx*dy-dz*dz;
    double e3 = dx*dy*dz;
    return (1-e2/10+e3/14+e2*e2/24-3*e2*e3/44)/std::sqrt(a);
}

double RigidLangevinPlugin::CarlsonIntegrals::carlsonRD(double x, double y, double z) {
    if (!(x >= 0 && y >= 0 && z > 0) || !std::isfinite(x+y+z) || (x == 0 && y == 0))
        throw OpenMMException("carlsonRD"+arguments(x, y, z)+": the arguments must be finite, x and y non-negative and not both zero, z positive");
    // Duplication as for R_F; the third argument carries the weight of the singular factor, whose
    // contribution from each step is accumulated in sum (Carlson 1995, Algorithm 4).
    const double x0 = x, y0 = y;
    double a0 = (x+y+3*z)/5;
    double q = std::pow(RELATIVE_ERROR/4, -1.0/6.0)*std::max({std::abs(a0-x), std::abs(a0-y), std::abs(a0-z)});
    double a = a0, scale = 1, sum = 0;
    while (scale*q >= std::abs(a)) {
        double sx = std::sqrt(x), sy = std::sqrt(y), sz = std::sqrt(z);
        double lambda = sx*sy+sx*sz+sy*sz;
        sum += scale/(sz*(z+lambda));
        x = 0.25*(x+lambda);
        y = 0.25*(y+lambda);
        z = 0.25*(z+lambda);
        a = 0.25*(a+lambda);
        scale *= 0.25;
    }
    // (a0-x0)/4^m equals a-x exactly in exact arithmetic but without its cancellation.
    double dx = (a0-x0)*scale/a, dy = (a0-y0)*scale/a;
    double dz = -(dx+dy)/3;
    double xy = dx*dy, z2 = dz*dz;
    double e2 = xy-6*z2;
    double e3 = (3*xy-8*z2)*dz;
    double e4 = 3*(xy-z2)*z2;
    double e5 = xy*z2*dz;
    double series = 1-3*e2/14+e3/6+9*e2*e2/88-3*e4/22-9*e2*e3/52+3*e5/26;
    return scale*series/(a*std::sqrt(a))+3*sum;
}
