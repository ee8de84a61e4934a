#ifndef RIGIDLANGEVIN_STICKY_DIPOLE_INTERACTION_H_
#define RIGIDLANGEVIN_STICKY_DIPOLE_INTERACTION_H_

/*
 * StickyDipoleForce's pair energy and its gradient on the host, in double precision (the form is
 * written out in StickyDipoleForce.h). The energy of a pair depends on the separation d = r_j - r_i
 * and on the two sites' frames (x, y, z axes); the gradient is returned with respect to d and to
 * each axis, and SiteFrame::addForces() carries the axes' part to the site and its reference
 * particles through the frame's construction. Every force is thus the exact gradient of the
 * energy, and a rigid molecule feels the right force and torque.
 */

#include "StickyDipoleForce.h"
#include "openmm/Vec3.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <algorithm>
#include <cmath>

namespace RigidLangevinPlugin {

/** A site's frame and what its gradient needs. */
struct SiteFrame {
    OpenMM::Vec3 x, y, z;
    OpenMM::Vec3 v;            // reference1 - reference2
    double uLength, wLength;   // |midpoint - site|, |v made perpendicular to z|

    SiteFrame(const OpenMM::Vec3& site, const OpenMM::Vec3& reference1, const OpenMM::Vec3& reference2) {
        OpenMM::Vec3 u = (reference1+reference2)*0.5-site;
        uLength = std::sqrt(u.dot(u));
        z = u/uLength;
        v = reference1-reference2;
        OpenMM::Vec3 w = v-z*v.dot(z);
        wLength = std::sqrt(w.dot(w));
        y = w/wLength;
        x = y.cross(z);
    }

    /**
     * Add to the forces on the site and its reference particles the part of -grad U that comes
     * through the frame, given gx, gy, gz = dU/dx, dU/dy, dU/dz (x, y, z the axes).
     */
    void addForces(OpenMM::Vec3 gx, OpenMM::Vec3 gy, OpenMM::Vec3 gz, OpenMM::Vec3& siteForce, OpenMM::Vec3& force1, OpenMM::Vec3& force2) const {
        // x = y cross z
        gy += z.cross(gx);
        gz += gx.cross(y);
        // y = w/|w|, w = v - (v.z) z
        OpenMM::Vec3 gw = (gy-y*gy.dot(y))/wLength;
        OpenMM::Vec3 gv = gw-z*gw.dot(z);
        gz -= v*gw.dot(z)+gw*v.dot(z);
        // z = u/|u|, u = (r1+r2)/2 - r_site
        OpenMM::Vec3 gu = (gz-z*gz.dot(z))/uLength;
        siteForce += gu;
        force1 -= gu*0.5+gv;
        force2 -= gu*0.5-gv;
    }
};

/** The gradient of a pair energy: with respect to d = r_j - r_i and to the axes of i and j. */
struct PairGradient {
    OpenMM::Vec3 d, xi, yi, zi, xj, yj, zj;
};

/** The cubic switch from 1 at lower to 0 at upper, and its derivative. */
inline double cubicSwitch(double r, double lower, double upper, double& derivative) {
    if (r <= lower) {
        derivative = 0;
        return 1;
    }
    if (r >= upper) {
        derivative = 0;
        return 0;
    }
    double width = upper-lower, width3 = width*width*width;
    derivative = -6*(upper-r)*(r-lower)/width3;
    return (upper-r)*(upper-r)*(upper+2*r-3*lower)/width3;
}

/**
 * One site's sticky term, 1/2 [nu0 s(r) w + nu0' s'(r) w'], with (x, y, z) = sign * (axes . d).
 * Adds its gradient to g (d and this site's axes) and returns its energy.
 */
inline double stickyTerm(const StickyDipoleForce::SiteParameters& p, const SiteFrame& frame, double sign, const OpenMM::Vec3& d, double r,
                         OpenMM::Vec3& gd, OpenMM::Vec3& gx, OpenMM::Vec3& gy, OpenMM::Vec3& gz) {
    double ds, dsPrime;
    double s = cubicSwitch(r, p.rL, p.rU, ds), sPrime = cubicSwitch(r, p.rLPrime, p.rUPrime, dsPrime);
    if (s == 0 && sPrime == 0 && ds == 0 && dsPrime == 0)
        return 0;
    double x = sign*frame.x.dot(d), y = sign*frame.y.dot(d), z = sign*frame.z.dot(d);
    double r3 = r*r*r, c = z/r;
    double w = 2*(x*x-y*y)*z/r3;
    double f = (c-0.6)*(c-0.6)*(c+0.8)*(c+0.8), df = 2*(c-0.6)*(c+0.8)*(2*c+0.2);
    double wPrime = f-p.w0;
    // Partial derivatives of the term at fixed r, then of r explicitly.
    double tx = 0.5*p.nu0*s*4*x*z/r3;
    double ty = -0.5*p.nu0*s*4*y*z/r3;
    double tz = 0.5*(p.nu0*s*2*(x*x-y*y)/r3+p.nu0Prime*sPrime*df/r);
    double tr = 0.5*(p.nu0*(ds*w-3*s*w/r)+p.nu0Prime*(dsPrime*wPrime-sPrime*df*z/(r*r)));
    gd += (frame.x*tx+frame.y*ty+frame.z*tz)*sign+d*(tr/r);
    gx += d*(sign*tx);
    gy += d*(sign*ty);
    gz += d*(sign*tz);
    return 0.5*(p.nu0*s*w+p.nu0Prime*sPrime*wPrime);
}

/**
 * The energy of a pair of sites and its gradient (added to g). switchFactor, switchDerivative:
 * S(r) and dS/dr for the Lennard-Jones and dipole terms; kappa: the reaction field constant.
 */
inline double pairEnergy(const StickyDipoleForce::SiteParameters& pi, const StickyDipoleForce::SiteParameters& pj, const SiteFrame& fi,
                         const SiteFrame& fj, const OpenMM::Vec3& d, double switchFactor, double switchDerivative, double kappa, PairGradient& g) {
    const double COULOMB = ONE_4PI_EPS0;  // kJ nm/(mol e^2)
    double r2 = d.dot(d), r = std::sqrt(r2), rInv = 1/r, r2Inv = rInv*rInv;
    // Lennard-Jones with Lorentz-Berthelot combination.
    double sigma = 0.5*(pi.sigma+pj.sigma), epsilon = std::sqrt(pi.epsilon*pj.epsilon);
    double sr2 = sigma*sigma*r2Inv, sr6 = sr2*sr2*sr2;
    double lj = 4*epsilon*(sr6*sr6-sr6);
    double ljDerivative = 4*epsilon*(-12*sr6*sr6+6*sr6)*rInv;  // dU/dr
    // Point dipoles along the z axes.
    OpenMM::Vec3 mi = fi.z*pi.dipole, mj = fj.z*pj.dipole;
    double mimj = mi.dot(mj), mid = mi.dot(d), mjd = mj.dot(d);
    double r3Inv = r2Inv*rInv, r5Inv = r3Inv*r2Inv, r7Inv = r5Inv*r2Inv;
    double dipole = COULOMB*(mimj*r3Inv-3*mid*mjd*r5Inv-2*kappa*mimj);
    OpenMM::Vec3 dipoleGradient = (d*(-3*mimj*r5Inv+15*mid*mjd*r7Inv)-(mi*mjd+mj*mid)*(3*r5Inv))*COULOMB;
    OpenMM::Vec3 gmi = (mj*(r3Inv-2*kappa)-d*(3*mjd*r5Inv))*COULOMB;
    OpenMM::Vec3 gmj = (mi*(r3Inv-2*kappa)-d*(3*mid*r5Inv))*COULOMB;
    double unswitched = lj+dipole;
    g.d += (d*(ljDerivative*rInv)+dipoleGradient)*switchFactor+d*(unswitched*switchDerivative*rInv);
    g.zi += gmi*(pi.dipole*switchFactor);
    g.zj += gmj*(pj.dipole*switchFactor);
    double energy = switchFactor*unswitched;
    energy += stickyTerm(pi, fi, 1.0, d, r, g.d, g.xi, g.yi, g.zi);
    energy += stickyTerm(pj, fj, -1.0, d, r, g.d, g.xj, g.yj, g.zj);
    return energy;
}

} // namespace RigidLangevinPlugin

#endif /*RIGIDLANGEVIN_STICKY_DIPOLE_INTERACTION_H_*/
