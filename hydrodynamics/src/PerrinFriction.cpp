#include "internal/PerrinFriction.h"
#include "internal/CarlsonIntegrals.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <string>

using namespace RigidLangevinPlugin;
using namespace RigidLangevinPlugin::PerrinFriction;
using OpenMM::OpenMMException;

namespace {

void checkSemiAxis(const char* function, const char* name, double value) {
    if (!(value > 0) || !std::isfinite(value))
        throw OpenMMException(std::string("PerrinFriction::")+function+": semi-axis "+name+" is "+std::to_string(value)+"; semi-axes must be positive and finite (nm)");
}

/**
 * The shape function of an ellipsoid of revolution in terms of eps = 1 - b^2/a^2 (eps in (0, 1) for
 * a prolate, eps < 0 for an oblate ellipsoid): g(eps) = atanh(sqrt(eps))/sqrt(eps), continued to
 * atan(sqrt(-eps))/sqrt(-eps) for eps < 0, so that the source's S = 2 g/a in both cases. Returns g
 * and q = (g - 1)/eps, the combination whose direct evaluation cancels near the sphere; near it both
 * come from the series g = sum_n eps^n/(2n+1), which converges for |eps| < 1.
 */
void shapeFunctions(double eps, double& g, double& q) {
    if (std::abs(eps) < 0.25) {
        // 40 terms take 0.25^n/(2n+1) far below the double precision of the leading 1/3.
        q = 0;
        double power = 1;
        for (int n = 1; n <= 40; n++) {
            q += power/(2*n+1);
            power *= eps;
        }
        g = 1+eps*q;
        return;
    }
    double root = std::sqrt(std::abs(eps));
    g = (eps > 0 ? std::atanh(root) : std::atan(root))/root;
    q = (g-1)/eps;
}

} // namespace

PrincipalFriction PerrinFriction::ellipsoid(double a, double b, double c) {
    checkSemiAxis("ellipsoid", "a", a);
    checkSemiAxis("ellipsoid", "b", b);
    checkSemiAxis("ellipsoid", "c", c);
    double s2[3] = {a*a, b*b, c*c};
    double chi = 2*CarlsonIntegrals::carlsonRF(s2[0], s2[1], s2[2]);
    double alpha[3];
    for (int i = 0; i < 3; i++)
        alpha[i] = (2.0/3.0)*CarlsonIntegrals::carlsonRD(s2[(i+1)%3], s2[(i+2)%3], s2[i]);
    PrincipalFriction f;
    for (int i = 0; i < 3; i++) {
        int j = (i+1)%3, k = (i+2)%3;
        f.translation[i] = 16*M_PI/(chi+s2[i]*alpha[i]);
        f.rotation[i] = 16*M_PI*(s2[j]+s2[k])/(3*(s2[j]*alpha[j]+s2[k]*alpha[k]));
    }
    return f;
}

PrincipalFriction PerrinFriction::spheroid(double a, double b) {
    checkSemiAxis("spheroid", "a", a);
    checkSemiAxis("spheroid", "b", b);
    // The source's closed forms (prolate a > b; oblate a < b with the same formulas):
    //     Xtt_a = 16 pi (a^2-b^2) / ((2a^2-b^2) S - 2a)
    //     Xtt_b = 32 pi (a^2-b^2) / ((2a^2-3b^2) S + 2a)
    //     Xrr_a = (32 pi/3) (a^2-b^2) b^2 / (2a - b^2 S)
    //     Xrr_b = (32 pi/3) (a^4-b^4) / ((2a^2-b^2) S - 2a)
    // With b^2 = a^2 (1-eps) and S = 2g/a, every numerator carries the factor eps and every
    // denominator is 2a eps times a combination of g and q = (g-1)/eps, so the factor cancels
    // exactly and the forms below hold for prolate, oblate and (g = 1, q = 1/3) the sphere:
    // 6 pi a and 8 pi a^3.
    double eps = 1-(b/a)*(b/a);
    double g, q;
    shapeFunctions(eps, g, q);
    PrincipalFriction f;
    f.translation[0] = 8*M_PI*a/(g+q);
    f.translation[1] = f.translation[2] = 16*M_PI*a/(3*g-q);
    f.rotation[0] = (16*M_PI/3)*a*a*a*(1-eps)/(g-q);
    f.rotation[1] = f.rotation[2] = (16*M_PI/3)*a*a*a*(2-eps)/(g+q);
    return f;
}
