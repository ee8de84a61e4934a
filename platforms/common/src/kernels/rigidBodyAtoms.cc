/**
 * Between bodies and atoms. Each body owns a contiguous range of entries (bodyAtomStart[k] to
 * bodyAtomStart[k+1]): its particles in the body's order, each with its body-frame coordinates and
 * its current index in OpenMM's atom arrays (atomSlot, which the host updates whenever OpenMM
 * reorders atoms, together with the atom's periodic cell offset).
 *
 * Body states: position, velocity and body-frame angular momentum are mixed4 (w unused), the
 * rotation Q three mixed4 per body (its rows). Per-type parameters come from the host with the
 * offsets TP_* into blocks of TYPE_STRIDE values.
 */

DEVICE void loadRotation(GLOBAL const mixed4* RESTRICT rotation, int body, mixed* q) {
    for (int i = 0; i < 3; i++) {
        mixed4 row = rotation[3*body+i];
        q[3*i] = row.x;
        q[3*i+1] = row.y;
        q[3*i+2] = row.z;
    }
}

DEVICE void storeRotation(GLOBAL mixed4* RESTRICT rotation, int body, const mixed* q) {
    for (int i = 0; i < 3; i++)
        rotation[3*body+i] = make_mixed4(q[3*i], q[3*i+1], q[3*i+2], 0);
}

DEVICE void loadVector(GLOBAL const mixed4* RESTRICT array, int index, mixed* v) {
    mixed4 value = array[index];
    v[0] = value.x;
    v[1] = value.y;
    v[2] = value.z;
}

DEVICE void storeVector(GLOBAL mixed4* RESTRICT array, int index, const mixed* v) {
    array[index] = make_mixed4(v[0], v[1], v[2], 0);
}

/**
 * The total force on body k (lab frame) and the torque about its centre of mass (body frame),
 * from OpenMM's fixed-point force buffer, summed over the body's particles in their order, each
 * weighted by atomCoords.w: 0 for a virtual site, whose force OpenMM has already handed to its
 * parents, 1 otherwise.
 */
DEVICE void loadBodyForce(int body, int numRotations, const mixed* q, GLOBAL const int* RESTRICT bodyAtomStart,
        GLOBAL const int* RESTRICT atomSlot, GLOBAL const mixed4* RESTRICT atomCoords, GLOBAL const mm_long* RESTRICT force,
        mixed* totalForce, mixed* torque) {
    const mixed scale = 1/(mixed) 0x100000000;
    for (int i = 0; i < 3; i++)
        totalForce[i] = torque[i] = 0;
    int end = bodyAtomStart[body+1];
    for (int entry = bodyAtomStart[body]; entry < end; entry++) {
        int slot = atomSlot[entry];
        mixed4 coords = atomCoords[entry];
        mixed weight = scale*coords.w;
        mixed f[3] = {weight*force[slot], weight*force[slot+PADDED_NUM_ATOMS], weight*force[slot+2*PADDED_NUM_ATOMS]};
        for (int i = 0; i < 3; i++)
            totalForce[i] += f[i];
        if (numRotations > 0) {
            mixed fb[3], c[3] = {coords.x, coords.y, coords.z}, t[3];
            vectorToBodyFrame(q, f, fb);
            crossProduct(c, fb, t);
            for (int i = 0; i < 3; i++)
                torque[i] += t[i];
        }
    }
}

/**
 * Keep a body's centre in the periodic box, counting the boxes it has left in bodyImage, so that
 * single precision resolves it as well after any diffusion as at the start: its true position is
 * the stored one plus image.x a + image.y b + image.z c (OpenMM's reduced box vectors a, b, c).
 * The image is read and written only when the centre leaves the box.
 */
DEVICE void keepInBox(mixed* r, int body, GLOBAL int4* RESTRICT bodyImage, mixed4 boxVecX, mixed4 boxVecY, mixed4 boxVecZ) {
    int sz = (int) floor(r[2]/boxVecZ.z);
    r[0] -= sz*boxVecZ.x;
    r[1] -= sz*boxVecZ.y;
    r[2] -= sz*boxVecZ.z;
    int sy = (int) floor(r[1]/boxVecY.y);
    r[0] -= sy*boxVecY.x;
    r[1] -= sy*boxVecY.y;
    int sx = (int) floor(r[0]/boxVecX.x);
    r[0] -= sx*boxVecX.x;
    if (sx != 0 || sy != 0 || sz != 0) {
        int4 image = bodyImage[body];
        bodyImage[body] = make_int4(image.x+sx, image.y+sy, image.z+sz, 0);
    }
}

/**
 * Place every particle of every body from the body states, one work item per particle:
 * r = R + Q^T b and v = V + Q^T (omega x b), with omega the body-frame angular velocity. Positions
 * are stored shifted by the atom's periodic cell offset, as OpenMM keeps them, and by the boxes its
 * body has left (bodyImage): both are whole boxes, added before they meet the coordinates. Charges
 * (posq.w) and inverse masses (velm.w) are left alone.
 */
KERNEL void placeBodyAtoms(int numEntries, GLOBAL const int* RESTRICT atomBody, GLOBAL const int* RESTRICT atomSlot,
        GLOBAL const mixed4* RESTRICT atomCoords, GLOBAL const int4* RESTRICT atomCellOffset,
        GLOBAL const mixed4* RESTRICT bodyPosition, GLOBAL const mixed4* RESTRICT bodyVelocity,
        GLOBAL const mixed4* RESTRICT bodyAngularMomentum, GLOBAL const mixed4* RESTRICT bodyRotation,
        GLOBAL const int* RESTRICT bodyType, GLOBAL const mixed* RESTRICT typeParams, GLOBAL const int4* RESTRICT typeInfo,
        GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection, GLOBAL mixed4* RESTRICT velm,
        mixed4 boxVecX, mixed4 boxVecY, mixed4 boxVecZ, GLOBAL const int4* RESTRICT bodyImage) {
    for (int entry = GLOBAL_ID; entry < numEntries; entry += GLOBAL_SIZE) {
        int body = atomBody[entry];
        int type = bodyType[body];
        int numRotations = typeInfo[type].y;
        mixed q[9], c[3], offset[3], position[3], velocity[3];
        loadRotation(bodyRotation, body, q);
        loadVector(atomCoords, entry, c);
        loadVector(bodyPosition, body, position);
        loadVector(bodyVelocity, body, velocity);
        vectorToLabFrame(q, c, offset);
        int slot = atomSlot[entry];
        int4 cell = atomCellOffset[entry];
        int4 image = bodyImage[body];
        cell = make_int4(cell.x+image.x, cell.y+image.y, cell.z+image.z, 0);
        mixed3 shift = make_mixed3(cell.x*boxVecX.x+cell.y*boxVecY.x+cell.z*boxVecZ.x,
                                   cell.y*boxVecY.y+cell.z*boxVecZ.y,
                                   cell.z*boxVecZ.z);
        mixed3 pos = make_mixed3(position[0]+offset[0]+shift.x, position[1]+offset[1]+shift.y, position[2]+offset[2]+shift.z);
#ifdef USE_MIXED_PRECISION
        real4 stored = posq[slot];
        posq[slot] = make_real4((real) pos.x, (real) pos.y, (real) pos.z, stored.w);
        posqCorrection[slot] = make_real4(pos.x-(real) pos.x, pos.y-(real) pos.y, pos.z-(real) pos.z, 0);
#else
        real4 stored = posq[slot];
        posq[slot] = make_real4(pos.x, pos.y, pos.z, stored.w);
#endif
        mixed4 v = velm[slot];
        if (numRotations > 0) {
            GLOBAL const mixed* inertia = &typeParams[type*TYPE_STRIDE+TP_MASS+1];
            mixed4 j = bodyAngularMomentum[body];
            mixed omega[3] = {(numRotations == 3 ? j.x/inertia[0] : 0), j.y/inertia[1], j.z/inertia[2]};
            mixed w[3], labW[3];
            crossProduct(omega, c, w);
            vectorToLabFrame(q, w, labW);
            v.x = velocity[0]+labW[0];
            v.y = velocity[1]+labW[1];
            v.z = velocity[2]+labW[2];
        }
        else {
            v.x = velocity[0];
            v.y = velocity[1];
            v.z = velocity[2];
        }
        velm[slot] = v;
    }
}
