/*
 * StickyDipoleForce's pair term, inserted into OpenMM's nonbonded kernel (NonbondedUtilities), the
 * same expressions as pairEnergy() on the host (StickyDipoleInteraction.h). Site a is atom1, b is
 * atom2, d = delta = r_b - r_a. The kernel gives atoms 0 for their type (x.w) if they are no site.
 * The energy goes to tempEnergy; per site, the force on it (F_a = dU/dd, F_b = -dU/dd) and T, the
 * derivative of the energy under a rotation of its frame (sum over axes of axis x dU/daxis), go to
 * GRADIENTS with atomics, scaled by interactionScale (1/2 where the kernel visits a pair twice).
 */
{
    int typeA = (int) SITE_X1.w, typeB = (int) SITE_X2.w;
#ifdef USE_CUTOFF
    bool includePair = (typeA != 0 && typeB != 0 && atom1 != atom2 && !IS_EXCLUDED && r2 < CUTOFF_SQUARED);
#else
    bool includePair = (typeA != 0 && typeB != 0 && atom1 != atom2 && !IS_EXCLUDED);
#endif
    if (includePair) {
        const int pa = (typeA-1)*TYPE_STRIDE, pb = (typeB-1)*TYPE_STRIDE;
        real3 d = make_real3(delta.x, delta.y, delta.z);
        real3 xa = make_real3(SITE_X1.x, SITE_X1.y, SITE_X1.z), ya = make_real3(SITE_Y1.x, SITE_Y1.y, SITE_Y1.z), za = cross(xa, ya);
        real3 xb = make_real3(SITE_X2.x, SITE_X2.y, SITE_X2.z), yb = make_real3(SITE_Y2.x, SITE_Y2.y, SITE_Y2.z), zb = cross(xb, yb);
        real r2Inv = invR*invR;
        // Lennard-Jones with Lorentz-Berthelot combination.
        real sigma = 0.5f*(TYPE_PARAMS[pa]+TYPE_PARAMS[pb]), epsilon = SQRT(TYPE_PARAMS[pa+1]*TYPE_PARAMS[pb+1]);
        real sr2 = sigma*sigma*r2Inv, sr6 = sr2*sr2*sr2;
        real lj = 4*epsilon*(sr6*sr6-sr6);
        real ljDerivative = 4*epsilon*(-12*sr6*sr6+6*sr6)*invR;
        // Point dipoles along the z axes, with the reaction field.
        real dipoleA = TYPE_PARAMS[pa+2], dipoleB = TYPE_PARAMS[pb+2];
        real3 ma = za*dipoleA, mb = zb*dipoleB;
        real mamb = dot(ma, mb), mad = dot(ma, d), mbd = dot(mb, d);
        real r3Inv = r2Inv*invR, r5Inv = r3Inv*r2Inv, r7Inv = r5Inv*r2Inv;
        real dipole = COULOMB*(mamb*r3Inv-3*mad*mbd*r5Inv-2*KAPPA*mamb);
        real3 dipoleGradient = (d*(-3*mamb*r5Inv+15*mad*mbd*r7Inv)-(ma*mbd+mb*mad)*(3*r5Inv))*COULOMB;
        real3 gma = (mb*(r3Inv-2*KAPPA)-d*(3*mbd*r5Inv))*COULOMB;
        real3 gmb = (ma*(r3Inv-2*KAPPA)-d*(3*mad*r5Inv))*COULOMB;
        // The cubic switch of both from SWITCH_LOWER to SWITCH_UPPER.
        real switchFactor = 1, switchDerivative = 0;
        if (USE_SWITCH && r > SWITCH_LOWER) {
            real width = SWITCH_UPPER-SWITCH_LOWER, width3 = width*width*width;
            switchFactor = (SWITCH_UPPER-r)*(SWITCH_UPPER-r)*(SWITCH_UPPER+2*r-3*SWITCH_LOWER)/width3;
            switchDerivative = -6*(SWITCH_UPPER-r)*(r-SWITCH_LOWER)/width3;
        }
        real unswitched = lj+dipole;
        real pairEnergy = switchFactor*unswitched;
        real3 gd = (d*(ljDerivative*invR)+dipoleGradient)*switchFactor+d*(unswitched*switchDerivative*invR);
        real3 torqueA = cross(za, gma*(dipoleA*switchFactor)), torqueB = cross(zb, gmb*(dipoleB*switchFactor));
        // Each site's sticky term, with (x, y, z) the other site's position in its frame.
        for (int side = 0; side < 2; side++) {
            int p = (side == 0 ? pa : pb);
            real sign = (side == 0 ? 1 : -1);
            real3 ax = (side == 0 ? xa : xb), ay = (side == 0 ? ya : yb), az = (side == 0 ? za : zb);
            real nu0 = TYPE_PARAMS[p+3], rL = TYPE_PARAMS[p+4], rU = TYPE_PARAMS[p+5];
            real nu0Prime = TYPE_PARAMS[p+6], rLPrime = TYPE_PARAMS[p+7], rUPrime = TYPE_PARAMS[p+8], w0 = TYPE_PARAMS[p+9];
            if (r >= rU && r >= rUPrime)
                continue;
            real s = 1, ds = 0, sPrime = 1, dsPrime = 0;
            if (r >= rU)
                s = 0;
            else if (r > rL) {
                real width = rU-rL, width3 = width*width*width;
                s = (rU-r)*(rU-r)*(rU+2*r-3*rL)/width3;
                ds = -6*(rU-r)*(r-rL)/width3;
            }
            if (r >= rUPrime)
                sPrime = 0;
            else if (r > rLPrime) {
                real width = rUPrime-rLPrime, width3 = width*width*width;
                sPrime = (rUPrime-r)*(rUPrime-r)*(rUPrime+2*r-3*rLPrime)/width3;
                dsPrime = -6*(rUPrime-r)*(r-rLPrime)/width3;
            }
            real x = sign*dot(ax, d), y = sign*dot(ay, d), z = sign*dot(az, d);
            real c = z*invR;
            real w = 2*(x*x-y*y)*z*r3Inv;
            real f = (c-THREE_FIFTHS)*(c-THREE_FIFTHS)*(c+FOUR_FIFTHS)*(c+FOUR_FIFTHS);
            real df = 2*(c-THREE_FIFTHS)*(c+FOUR_FIFTHS)*(2*c+ONE_FIFTH);
            real wPrime = f-w0;
            real tx = 2*nu0*s*x*z*r3Inv;
            real ty = -2*nu0*s*y*z*r3Inv;
            real tz = 0.5f*(nu0*s*2*(x*x-y*y)*r3Inv+nu0Prime*sPrime*df*invR);
            real tr = 0.5f*(nu0*(ds*w-3*s*w*invR)+nu0Prime*(dsPrime*wPrime-sPrime*df*z*r2Inv));
            gd += (ax*tx+ay*ty+az*tz)*sign+d*(tr*invR);
            real3 t = (cross(ax, d)*tx+cross(ay, d)*ty+cross(az, d)*tz)*sign;
            if (side == 0)
                torqueA += t;
            else
                torqueB += t;
            pairEnergy += 0.5f*(nu0*s*w+nu0Prime*sPrime*wPrime);
        }
        tempEnergy += pairEnergy;
#ifdef INCLUDE_FORCES
        gd *= interactionScale;
        torqueA *= interactionScale;
        torqueB *= interactionScale;
        ATOMIC_ADD(&GRADIENTS[atom1], (mm_ulong) realToFixedPoint(gd.x));
        ATOMIC_ADD(&GRADIENTS[atom1+PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(gd.y));
        ATOMIC_ADD(&GRADIENTS[atom1+2*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(gd.z));
        ATOMIC_ADD(&GRADIENTS[atom1+3*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(torqueA.x));
        ATOMIC_ADD(&GRADIENTS[atom1+4*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(torqueA.y));
        ATOMIC_ADD(&GRADIENTS[atom1+5*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(torqueA.z));
        ATOMIC_ADD(&GRADIENTS[atom2], (mm_ulong) realToFixedPoint(-gd.x));
        ATOMIC_ADD(&GRADIENTS[atom2+PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(-gd.y));
        ATOMIC_ADD(&GRADIENTS[atom2+2*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(-gd.z));
        ATOMIC_ADD(&GRADIENTS[atom2+3*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(torqueB.x));
        ATOMIC_ADD(&GRADIENTS[atom2+4*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(torqueB.y));
        ATOMIC_ADD(&GRADIENTS[atom2+5*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(torqueB.z));
#endif
    }
}
