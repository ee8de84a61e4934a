/*
 * StickyDipoleForce around OpenMM's nonbonded kernel (CommonCalcStickyDipoleForceKernel): the
 * sites' frames before it, and after it the forces that come through the frames. A site's frame:
 * z from the site to the midpoint of its reference particles, y along reference1 - reference2
 * made perpendicular to z, x = y cross z (as SiteFrame on the host).
 */

/** Store each site's x and y axes at the site's atom (x.w: 1 + its type), for the pair loop. */
KERNEL void computeStickyDipoleFrames(int numSites, GLOBAL const real4* RESTRICT posq, GLOBAL const int4* RESTRICT siteAtoms,
        GLOBAL real4* RESTRICT xAxis, GLOBAL real4* RESTRICT yAxis) {
    for (int site = GLOBAL_ID; site < numSites; site += GLOBAL_SIZE) {
        int4 atoms = siteAtoms[site];
        real3 position = trimTo3(posq[atoms.x]), reference1 = trimTo3(posq[atoms.y]), reference2 = trimTo3(posq[atoms.z]);
        real3 u = (reference1+reference2)*0.5f-position;
        real3 z = u*RSQRT(dot(u, u));
        real3 v = reference1-reference2;
        real3 w = v-z*dot(v, z);
        real3 y = w*RSQRT(dot(w, w));
        real3 x = cross(y, z);
        xAxis[atoms.x] = make_real4(x.x, x.y, x.z, (real) atoms.w);
        yAxis[atoms.x] = make_real4(y.x, y.y, y.z, 0);
    }
}

/**
 * Add the forces of the pair loop: on each site the force accumulated there, and the part that
 * comes through its frame, from T = dU/d(rotation of the frame) = sum over axes a of a x dU/da.
 * Any dU/da with that T gives the same forces, because the frame's construction only rotates it:
 * dU/da = T x a / 2 is one. The chain rule through the construction is SiteFrame::addForces().
 */
KERNEL void applyStickyDipoleForces(int numSites, GLOBAL const real4* RESTRICT posq, GLOBAL const int4* RESTRICT siteAtoms,
        GLOBAL const mm_long* RESTRICT gradients, GLOBAL mm_ulong* RESTRICT forceBuffers) {
    const real scale = 1/(real) 0x100000000;
    for (int site = GLOBAL_ID; site < numSites; site += GLOBAL_SIZE) {
        int4 atoms = siteAtoms[site];
        real3 position = trimTo3(posq[atoms.x]), reference1 = trimTo3(posq[atoms.y]), reference2 = trimTo3(posq[atoms.z]);
        real3 u = (reference1+reference2)*0.5f-position;
        real uLength = SQRT(dot(u, u));
        real3 z = u/uLength;
        real3 v = reference1-reference2;
        real3 w = v-z*dot(v, z);
        real wLength = SQRT(dot(w, w));
        real3 y = w/wLength;
        real3 x = cross(y, z);
        real3 force = make_real3((real) gradients[atoms.x], (real) gradients[atoms.x+PADDED_NUM_ATOMS], (real) gradients[atoms.x+2*PADDED_NUM_ATOMS])*scale;
        real3 torque = make_real3((real) gradients[atoms.x+3*PADDED_NUM_ATOMS], (real) gradients[atoms.x+4*PADDED_NUM_ATOMS],
                (real) gradients[atoms.x+5*PADDED_NUM_ATOMS])*scale;
        real3 gx = cross(torque, x)*0.5f, gy = cross(torque, y)*0.5f, gz = cross(torque, z)*0.5f;
        // x = y cross z
        gy += cross(z, gx);
        gz += cross(gx, y);
        // y = w/|w|, w = v - (v.z) z
        real3 gw = (gy-y*dot(gy, y))/wLength;
        real3 gv = gw-z*dot(gw, z);
        gz -= v*dot(gw, z)+gw*dot(v, z);
        // z = u/|u|, u = (reference1+reference2)/2 - site
        real3 gu = (gz-z*dot(gz, z))/uLength;
        force += gu;
        real3 force1 = -(gu*0.5f+gv), force2 = -(gu*0.5f-gv);
        ATOMIC_ADD(&forceBuffers[atoms.x], (mm_ulong) realToFixedPoint(force.x));
        ATOMIC_ADD(&forceBuffers[atoms.x+PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(force.y));
        ATOMIC_ADD(&forceBuffers[atoms.x+2*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(force.z));
        ATOMIC_ADD(&forceBuffers[atoms.y], (mm_ulong) realToFixedPoint(force1.x));
        ATOMIC_ADD(&forceBuffers[atoms.y+PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(force1.y));
        ATOMIC_ADD(&forceBuffers[atoms.y+2*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(force1.z));
        ATOMIC_ADD(&forceBuffers[atoms.z], (mm_ulong) realToFixedPoint(force2.x));
        ATOMIC_ADD(&forceBuffers[atoms.z+PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(force2.y));
        ATOMIC_ADD(&forceBuffers[atoms.z+2*PADDED_NUM_ATOMS], (mm_ulong) realToFixedPoint(force2.z));
    }
}
