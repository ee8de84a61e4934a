#include "internal/HasimotoSplit.h"
#include "internal/RotnePragerYamakawa.h"
#include <cmath>

using namespace RigidLangevinPlugin;
using OpenMM::Vec3;

namespace {

const double SqrtPi = 1.77245385090551602730;

/** Below this X = xi r the Taylor series replaces the closed form, whose three terms cancel there
 *  as (xi (a_i + a_j)/X)^2. */
const double SeriesBelow = 0.5;

/** The series' terms: n = 3, 5, ..., 2 NumSeriesTerms + 1; at X = 0.5 the first omitted one is
 *  below 1e-16 of the sum (the terms fall as (X^2)^j/j!). */
const int NumSeriesTerms = 14;

/** h and its first two antiderivatives from 0 (HasimotoSplit.h), at x. */
void kernelAndAntiderivatives(double x, double& h, double& h1, double& h2) {
    const double e = std::exp(-x*x), erfx = std::erf(x), x2 = x*x;
    h = x2*erfx+x*e/SqrtPi;
    h1 = x2*x*erfx/3+((2*x2-1)*e+1)/(6*SqrtPi);
    h2 = x2*x2*erfx/12-erfx/16+(x+(2*x2-1)*x*e/4)/(6*SqrtPi);
}

/**
 * h', h''', ..., h^(2 NumSeriesTerms - 1) at x. h''' = (2/sqrt(pi)) (3 - 2x^2) e^{-x^2} =
 * (2/sqrt(pi)) (2 H_0 - H_2/2) e^{-x^2}, and d^k/dx^k (H_j e^{-x^2}) = (-1)^k H_{j+k} e^{-x^2}
 * (Hermite polynomials, by their stable recurrence H_{n+1} = 2x H_n - 2n H_{n-1}).
 */
void oddDerivatives(double x, double out[NumSeriesTerms]) {
    const int numHermite = 2*NumSeriesTerms;
    double hermite[numHermite+1];
    hermite[0] = 1;
    hermite[1] = 2*x;
    for (int n = 1; n < numHermite; n++)
        hermite[n+1] = 2*x*hermite[n]-2*n*hermite[n-1];
    const double e = std::exp(-x*x);
    out[0] = 2*x*std::erf(x)+e/SqrtPi;
    for (int m = 3; m < 2*NumSeriesTerms; m += 2) {
        const int k = m-3;
        out[(m-1)/2] = 2/SqrtPi*(k%2 == 0 ? 1 : -1)*(2*hermite[k]-hermite[k+2]/2)*e;
    }
}

/** G's coefficients times 32 pi alpha beta/xi by the Taylor series in X (HasimotoSplit.h). */
void smoothPartSeries(double x, double alpha, double beta, double& isotropic, double& dyadic) {
    double t[NumSeriesTerms] = {0}, derivatives[NumSeriesTerms];
    for (int s = -1; s <= 1; s += 2)
        for (int u = -1; u <= 1; u += 2) {
            oddDerivatives(s*alpha+u*beta, derivatives);
            for (int k = 0; k < NumSeriesTerms; k++)
                t[k] += s*u*derivatives[k];
        }
    // T_n = t[(n-3)/2]; A ~ sum (n-1)^2 T_n X^(n-3)/n!, B ~ -sum (n-1)(n-3) T_n X^(n-3)/n!.
    isotropic = 0;
    dyadic = 0;
    double power = 1, factorial = 6;
    for (int k = 0; k < NumSeriesTerms; k++) {
        const int n = 2*k+3;
        isotropic += (n-1)*(n-1)*t[k]*power/factorial;
        dyadic -= (n-1)*(n-3)*t[k]*power/factorial;
        power *= x*x;
        factorial *= (n+1)*(n+2);
    }
}

} // namespace

double HasimotoSplit::weight(double k2, double xi) {
    const double x = k2/(4*xi*xi);
    return (1+x)*std::exp(-x);
}

void HasimotoSplit::smoothPart(double r, double ai, double aj, double xi, double& isotropic, double& dyadic) {
    const double x = xi*r, alpha = xi*ai, beta = xi*aj;
    if (x < SeriesBelow)
        smoothPartSeries(x, alpha, beta, isotropic, dyadic);
    else {
        double sumH = 0, sumH1 = 0, sumH2 = 0;
        for (int s = -1; s <= 1; s += 2)
            for (int u = -1; u <= 1; u += 2) {
                double h, h1, h2;
                kernelAndAntiderivatives(x+s*alpha+u*beta, h, h1, h2);
                sumH += s*u*h;
                sumH1 += s*u*h1;
                sumH2 += s*u*h2;
            }
        isotropic = sumH/x-sumH1/(x*x)+sumH2/(x*x*x);
        dyadic = -(sumH/x-3*sumH1/(x*x)+3*sumH2/(x*x*x));
    }
    const double scale = xi/(32*M_PI*alpha*beta);
    isotropic *= scale;
    dyadic *= scale;
}

void HasimotoSplit::realSpaceCoefficients(double r, double ai, double aj, double xi, double& isotropic, double& dyadicPerR2) {
    double dyadic, smoothIsotropic, smoothDyadic;
    RotnePragerYamakawa::mobilityCoefficients(r, ai, aj, isotropic, dyadic);
    smoothPart(r, ai, aj, xi, smoothIsotropic, smoothDyadic);
    isotropic -= smoothIsotropic;
    dyadicPerR2 = (r > 0 ? (dyadic-smoothDyadic)/(r*r) : 0.0);
}

void HasimotoSplit::realSpaceBlock(const Vec3& d, double ai, double aj, double xi, double block[9]) {
    double isotropic, dyadicPerR2;
    realSpaceCoefficients(std::sqrt(d.dot(d)), ai, aj, xi, isotropic, dyadicPerR2);
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++)
            block[3*k+l] = dyadicPerR2*d[k]*d[l]+(k == l ? isotropic : 0.0);
}
