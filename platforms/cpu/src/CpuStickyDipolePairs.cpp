#include "CpuStickyDipolePairs.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <cmath>

using namespace RigidLangevinPlugin;

// The helpers below pass vectors by value only to each other, inlined into the one exported function.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace {

#define LANES_INLINE inline __attribute__((always_inline))

// Four doubles as one value (GCC's and Clang's vector extensions: AVX2 registers where the clone is
// compiled for AVX2, pairs of SSE2 registers otherwise).
typedef double vd __attribute__((vector_size(32)));
typedef long long vm __attribute__((vector_size(32)));

LANES_INLINE vd splat(double x) {
    return vd{x, x, x, x};
}

LANES_INLINE vd load(const double* p) {
    return vd{p[0], p[1], p[2], p[3]};
}

LANES_INLINE void store(double* p, vd v) {
    for (int k = 0; k < 4; k++)
        p[k] = v[k];
}

LANES_INLINE vd vsqrt(vd x) {
    return vd{std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3])};
}

/** Round to the nearest integer (|x| < 2^51): adding and subtracting 1.5 * 2^52 leaves no fraction. */
LANES_INLINE vd vround(vd x) {
    const vd shift = splat(6755399441055744.0);
    return (x+shift)-shift;
}

LANES_INLINE vd vmin(vd a, vd b) {
    return (a < b) ? a : b;
}

LANES_INLINE vd vmax(vd a, vd b) {
    return (a > b) ? a : b;
}

struct V3 {
    vd x, y, z;
};

LANES_INLINE V3 operator+(V3 a, V3 b) {
    return {a.x+b.x, a.y+b.y, a.z+b.z};
}

LANES_INLINE V3 operator-(V3 a, V3 b) {
    return {a.x-b.x, a.y-b.y, a.z-b.z};
}

LANES_INLINE V3 operator*(V3 a, vd s) {
    return {a.x*s, a.y*s, a.z*s};
}

LANES_INLINE vd dot(V3 a, V3 b) {
    return a.x*b.x+a.y*b.y+a.z*b.z;
}

LANES_INLINE V3 cross(V3 a, V3 b) {
    return {a.y*b.z-a.z*b.y, a.z*b.x-a.x*b.z, a.x*b.y-a.y*b.x};
}

LANES_INLINE V3 load3(const double (*p)[StickyPairBlock::Lanes]) {
    return {load(p[0]), load(p[1]), load(p[2])};
}

/** The cubic switch from 1 at lower to 0 at upper, as a clamped polynomial, and its derivative. */
LANES_INLINE vd cubicSwitch(vd r, vd lower, vd upper, vd& derivative) {
    vd width = upper-lower;
    vd t = vmin(vmax((r-lower)/width, splat(0.0)), splat(1.0));
    derivative = -6*t*(1-t)/width;
    return 1-t*t*(3-2*t);
}

/** One site's sticky term (stickyTerm() on the host), adding to the force on i and the site's T. */
LANES_INLINE vd stickySide(const double (*p)[StickyPairBlock::Lanes], V3 ax, V3 ay, V3 az, double sign, V3 d, vd r, vd invR, vd r2Inv, vd r3Inv,
                     V3& gd, V3& torque) {
    vd nu0 = load(p[3]), rL = load(p[4]), rU = load(p[5]), nu0Prime = load(p[6]), rLPrime = load(p[7]), rUPrime = load(p[8]), w0 = load(p[9]);
    vd ds, dsPrime;
    vd s = cubicSwitch(r, rL, rU, ds), sPrime = cubicSwitch(r, rLPrime, rUPrime, dsPrime);
    vd x = sign*dot(ax, d), y = sign*dot(ay, d), z = sign*dot(az, d);
    vd c = z*invR;
    vd w = 2*(x*x-y*y)*z*r3Inv;
    vd f = (c-0.6)*(c-0.6)*(c+0.8)*(c+0.8), df = 2*(c-0.6)*(c+0.8)*(2*c+0.2);
    vd wPrime = f-w0;
    vd tx = 2*nu0*s*x*z*r3Inv;
    vd ty = -2*nu0*s*y*z*r3Inv;
    vd tz = 0.5*(nu0*s*2*(x*x-y*y)*r3Inv+nu0Prime*sPrime*df*invR);
    vd tr = 0.5*(nu0*(ds*w-3*s*w*invR)+nu0Prime*(dsPrime*wPrime-sPrime*df*z*r2Inv));
    gd = gd+(ax*tx+ay*ty+az*tz)*splat(sign)+d*(tr*invR);
    torque = torque+(cross(ax, d)*tx+cross(ay, d)*ty+cross(az, d)*tz)*splat(sign);
    return 0.5*(nu0*s*w+nu0Prime*sPrime*wPrime);
}

} // namespace

__attribute__((target_clones("avx2", "default")))
void RigidLangevinPlugin::computeStickyPairBlock(const StickyPairBlock& block, const StickyPairSettings& settings, StickyPairResults& results) {
    const double COULOMB = ONE_4PI_EPS0;
    V3 d = load3(block.d);
    if (settings.box != nullptr) {
        // The nearest image, for any triclinic box in OpenMM's reduced form.
        const double* b = settings.box;
        for (int axis = 2; axis >= 0; axis--) {
            vd component = (axis == 0 ? d.x : axis == 1 ? d.y : d.z);
            vd n = vround(component/b[4*axis]);
            d = d-V3{splat(b[3*axis]), splat(b[3*axis+1]), splat(b[3*axis+2])}*n;
        }
    }
    vd r2 = dot(d, d), r = vsqrt(r2), invR = 1/r, r2Inv = invR*invR, r3Inv = r2Inv*invR, r5Inv = r3Inv*r2Inv, r7Inv = r5Inv*r2Inv;
    // Lennard-Jones with Lorentz-Berthelot combination.
    vd sigma = 0.5*(load(block.pi[0])+load(block.pj[0])), epsilon = vsqrt(load(block.pi[1])*load(block.pj[1]));
    vd sr2 = sigma*sigma*r2Inv, sr6 = sr2*sr2*sr2;
    vd lj = 4*epsilon*(sr6*sr6-sr6);
    vd ljDerivative = 4*epsilon*(-12*sr6*sr6+6*sr6)*invR;
    // Point dipoles along the z axes, with the reaction field.
    V3 xi = load3(block.xi), yi = load3(block.yi), zi = load3(block.zi), xj = load3(block.xj), yj = load3(block.yj), zj = load3(block.zj);
    vd dipoleI = load(block.pi[2]), dipoleJ = load(block.pj[2]);
    V3 mi = zi*dipoleI, mj = zj*dipoleJ;
    vd mimj = dot(mi, mj), mid = dot(mi, d), mjd = dot(mj, d);
    vd kappa = splat(settings.kappa);
    vd dipole = COULOMB*(mimj*r3Inv-3*mid*mjd*r5Inv-2*kappa*mimj);
    V3 dipoleGradient = (d*(-3*mimj*r5Inv+15*mid*mjd*r7Inv)-(mi*mjd+mj*mid)*(3*r5Inv))*splat(COULOMB);
    V3 gmi = (mj*(r3Inv-2*kappa)-d*(3*mjd*r5Inv))*splat(COULOMB);
    V3 gmj = (mi*(r3Inv-2*kappa)-d*(3*mid*r5Inv))*splat(COULOMB);
    vd switchFactor = splat(1.0), switchDerivative = splat(0.0);
    if (settings.useSwitching)
        switchFactor = cubicSwitch(r, splat(settings.switchingDistance), splat(settings.cutoff), switchDerivative);
    vd unswitched = lj+dipole;
    vd energy = switchFactor*unswitched;
    V3 gd = (d*(ljDerivative*invR)+dipoleGradient)*switchFactor+d*(unswitched*switchDerivative*invR);
    V3 torqueI = cross(zi, gmi*(dipoleI*switchFactor)), torqueJ = cross(zj, gmj*(dipoleJ*switchFactor));
    // The sticky terms vanish beyond their switches' upper ends: most blocks have no pair within them.
    vd range = vmax(vmax(load(block.pi[5]), load(block.pi[8])), vmax(load(block.pj[5]), load(block.pj[8])));
    vm near = (r < range);
    if ((near[0] | near[1] | near[2] | near[3]) != 0) {
        energy += stickySide(block.pi, xi, yi, zi, 1.0, d, r, invR, r2Inv, r3Inv, gd, torqueI);
        energy += stickySide(block.pj, xj, yj, zj, -1.0, d, r, invR, r2Inv, r3Inv, gd, torqueJ);
    }
    // Lanes beyond the cutoff or unused give nothing (selected, so that no NaN of theirs survives).
    vm include = (load(block.used) != splat(0.0));
    if (settings.useCutoff)
        include = include & (r < splat(settings.cutoff));
    vd zero = splat(0.0);
    store(results.energy, include ? energy : zero);
    store(results.force[0], include ? gd.x : zero);
    store(results.force[1], include ? gd.y : zero);
    store(results.force[2], include ? gd.z : zero);
    store(results.torqueI[0], include ? torqueI.x : zero);
    store(results.torqueI[1], include ? torqueI.y : zero);
    store(results.torqueI[2], include ? torqueI.z : zero);
    store(results.torqueJ[0], include ? torqueJ.x : zero);
    store(results.torqueJ[1], include ? torqueJ.y : zero);
    store(results.torqueJ[2], include ? torqueJ.z : zero);
}
