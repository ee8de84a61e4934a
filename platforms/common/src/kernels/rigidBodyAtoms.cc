/**
 * Between bodies and atoms. Each body owns a contiguous range of entries (bodyAtomStart[k] to
 * bodyAtomStart[k+1]): its particles in the body's order, each with its current index in OpenMM's
 * atom arrays (atomSlot, which the host updates whenever OpenMM reorders atoms, together with the
 * atom's periodic cell offset). Body-frame coordinates belong to the body's type, shared by all its
 * bodies: typeCoords from typeInfo[type].x, in the same order, so that a step reads them from cache
 * instead of once per particle from memory.
 *
 * Body states: position, velocity and body-frame angular momentum are mixed4. The rotation Q, whose
 * rows are orthonormal and right-handed, is kept as its first two rows, the third being their cross
 * product: bodyRotation holds (Q00, Q01, Q02, Q10), bodyVelocity.w Q11 and bodyAngularMomentum.w
 * Q12. A body that rotates reads and writes those vectors anyway, so its rotation moves one mixed4
 * each way, as a quaternion would (the step is bound by memory traffic), and the host's copy of
 * the state (two rows in double) holds the device's exactly, so checkpoints continue bit for bit.
 * Per-type parameters come from the host with the offsets TP_* into blocks of TYPE_STRIDE values.
 */

/**
 * Q (rows, 9 values) from its first row and Q10 (rows), and Q11 and Q12, made orthonormal: the
 * first row normalized, the second made orthogonal to it and normalized (Gram-Schmidt), the third
 * their cross product. Without that, rounding errors grow: a rotation mixing a stored row with
 * the derived one passes the stored rows' error in length on to both, by sin^2 of its angle each
 * step (a 0.06 rad turn per step deformed bodies after 6000 steps in double precision).
 */
DEVICE void unpackRotation(mixed4 rows, mixed q11, mixed q12, mixed* q) {
    mixed scale0 = 1/sqrt(rows.x*rows.x+rows.y*rows.y+rows.z*rows.z);
    q[0] = scale0*rows.x;
    q[1] = scale0*rows.y;
    q[2] = scale0*rows.z;
    mixed overlap = q[0]*rows.w+q[1]*q11+q[2]*q12;
    mixed r[3] = {rows.w-overlap*q[0], q11-overlap*q[1], q12-overlap*q[2]};
    mixed scale1 = 1/sqrt(r[0]*r[0]+r[1]*r[1]+r[2]*r[2]);
    q[3] = scale1*r[0];
    q[4] = scale1*r[1];
    q[5] = scale1*r[2];
    q[6] = q[1]*q[5]-q[2]*q[4];
    q[7] = q[2]*q[3]-q[0]*q[5];
    q[8] = q[0]*q[4]-q[1]*q[3];
}

DEVICE void loadRotation(GLOBAL const mixed4* RESTRICT rotation, GLOBAL const mixed4* RESTRICT velocity,
        GLOBAL const mixed4* RESTRICT angularMomentum, int body, mixed* q) {
    unpackRotation(rotation[body], velocity[body].w, angularMomentum[body].w, q);
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
 * from OpenMM's fixed-point force buffer, summed over the body's particles in their order, leaving
 * out virtual sites (coords[i].w < 0 in the body's type's coordinates), whose force OpenMM has
 * already handed to their parents.
 */
DEVICE void loadBodyForce(int body, int numRotations, const mixed* q, GLOBAL const int* RESTRICT bodyAtomStart,
        GLOBAL const int* RESTRICT atomSlot, GLOBAL const mixed4* RESTRICT bodyCoords, GLOBAL const mm_long* RESTRICT force,
        mixed* totalForce, mixed* torque) {
    const mixed scale = 1/(mixed) 0x100000000;
    for (int i = 0; i < 3; i++)
        totalForce[i] = torque[i] = 0;
    int start = bodyAtomStart[body], end = bodyAtomStart[body+1];
    for (int entry = start; entry < end; entry++) {
        int slot = atomSlot[entry];
        mixed4 coords = bodyCoords[entry-start];
        mixed weight = (coords.w < 0 ? 0 : scale);
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
 * Keep a body's centre in the periodic box, counting the boxes it has left in image, so that single
 * precision resolves it as well after any diffusion as at the start: its true position is r plus
 * image.x a + image.y b + image.z c (OpenMM's reduced box vectors a, b, c). Returns whether the
 * image changed (the caller writes it back only then).
 */
DEVICE bool keepInBox(mixed* r, int4* image, mixed4 boxVecX, mixed4 boxVecY, mixed4 boxVecZ) {
    int sz = (int) floor(r[2]/boxVecZ.z);
    r[0] -= sz*boxVecZ.x;
    r[1] -= sz*boxVecZ.y;
    r[2] -= sz*boxVecZ.z;
    int sy = (int) floor(r[1]/boxVecY.y);
    r[0] -= sy*boxVecY.x;
    r[1] -= sy*boxVecY.y;
    int sx = (int) floor(r[0]/boxVecX.x);
    r[0] -= sx*boxVecX.x;
    if (sx == 0 && sy == 0 && sz == 0)
        return false;
    *image = make_int4(image->x+sx, image->y+sy, image->z+sz, 0);
    return true;
}

/**
 * Place the particles of one body from its state: r = R + Q^T c and v = V + Q^T (omega x c), with
 * omega the body-frame angular velocity (zero for a body that does not rotate). Positions are
 * stored shifted by the atom's periodic cell offset, as OpenMM keeps them, and by the boxes the
 * body has left (image): both are whole boxes, added before they meet the coordinates. Charges
 * (posq.w) are left alone; inverse masses (velm.w) are written, as OpenMM set them, from the
 * type's coordinates (their w, where a virtual site's -1 stands for 0), so that velm is not read:
 * the step is bound by memory traffic. q holds the rotation if haveRotation; a
 * body that does not rotate may skip loading it, and it is read here only for a particle off the
 * centre (a massless site of a point body), from the body state as stored. bodyCoords: the body's
 * type's coordinates. periodic: whether the System has a periodic box (without one the cell offsets
 * are all zero and are not read).
 */
DEVICE void placeBodyParticles(int body, int numRotations, int haveRotation, int periodic, const mixed* q, const mixed* position,
        const mixed* velocity, const mixed* omega, int4 image, GLOBAL const mixed4* RESTRICT bodyRotation,
        GLOBAL const mixed4* RESTRICT bodyVelocity, GLOBAL const mixed4* RESTRICT bodyAngularMomentum,
        GLOBAL const int* RESTRICT bodyAtomStart, GLOBAL const int* RESTRICT atomSlot, GLOBAL const mixed4* RESTRICT bodyCoords,
        GLOBAL const int4* RESTRICT atomCellOffset, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL mixed4* RESTRICT velm, mixed4 boxVecX, mixed4 boxVecY, mixed4 boxVecZ) {
    int start = bodyAtomStart[body], end = bodyAtomStart[body+1];
    for (int entry = start; entry < end; entry++) {
        mixed c[3], offset[3] = {0, 0, 0};
        loadVector(bodyCoords, entry-start, c);
        if (haveRotation)
            vectorToLabFrame(q, c, offset);
        else if (c[0] != 0 || c[1] != 0 || c[2] != 0) {
            mixed rotation[9];
            loadRotation(bodyRotation, bodyVelocity, bodyAngularMomentum, body, rotation);
            vectorToLabFrame(rotation, c, offset);
        }
        int slot = atomSlot[entry];
        // Without a periodic box OpenMM never wraps atoms: their cell offsets are zero, and are not read.
        int4 cell = (periodic ? atomCellOffset[entry] : make_int4(0, 0, 0, 0));
        cell = make_int4(cell.x+image.x, cell.y+image.y, cell.z+image.z, 0);
        mixed3 shift = make_mixed3(cell.x*boxVecX.x+cell.y*boxVecY.x+cell.z*boxVecZ.x,
                                   cell.y*boxVecY.y+cell.z*boxVecZ.y,
                                   cell.z*boxVecZ.z);
        mixed3 pos = make_mixed3(position[0]+offset[0]+shift.x, position[1]+offset[1]+shift.y, position[2]+offset[2]+shift.z);
        real4 stored = posq[slot];
#ifdef USE_MIXED_PRECISION
        posq[slot] = make_real4((real) pos.x, (real) pos.y, (real) pos.z, stored.w);
        posqCorrection[slot] = make_real4(pos.x-(real) pos.x, pos.y-(real) pos.y, pos.z-(real) pos.z, 0);
#else
        posq[slot] = make_real4(pos.x, pos.y, pos.z, stored.w);
#endif
        mixed inverseMass = bodyCoords[entry-start].w;
        mixed4 v = make_mixed4(velocity[0], velocity[1], velocity[2], inverseMass < 0 ? 0 : inverseMass);
        if (numRotations > 0) {
            mixed w[3], labW[3];
            crossProduct(omega, c, w);
            vectorToLabFrame(q, w, labW);
            v.x += labW[0];
            v.y += labW[1];
            v.z += labW[2];
        }
        velm[slot] = v;
    }
}

/** The body-frame angular velocity from the angular momentum about the axes that rotate. */
DEVICE void angularVelocity(int numRotations, const mixed* angularMomentum, const mixed* inertia, mixed* omega) {
    omega[0] = (numRotations == 3 ? angularMomentum[0]/inertia[0] : 0);
    omega[1] = (numRotations > 0 ? angularMomentum[1]/inertia[1] : 0);
    omega[2] = (numRotations > 0 ? angularMomentum[2]/inertia[2] : 0);
}

/**
 * Place every particle of every body from the body states, one work item per body (the step kernels
 * place their bodies' particles themselves; this is for states set from the host).
 */
KERNEL void placeBodyAtoms(int numBodies, GLOBAL const mixed4* RESTRICT bodyPosition, GLOBAL const mixed4* RESTRICT bodyVelocity,
        GLOBAL const mixed4* RESTRICT bodyAngularMomentum, GLOBAL const mixed4* RESTRICT bodyRotation,
        GLOBAL const int* RESTRICT bodyType, GLOBAL const mixed* RESTRICT typeParams, GLOBAL const int4* RESTRICT typeInfo,
        GLOBAL const int4* RESTRICT bodyImage, GLOBAL const int* RESTRICT bodyAtomStart, GLOBAL const int* RESTRICT atomSlot,
        GLOBAL const mixed4* RESTRICT typeCoords, GLOBAL const int4* RESTRICT atomCellOffset,
        GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection, GLOBAL mixed4* RESTRICT velm,
        mixed4 boxVecX, mixed4 boxVecY, mixed4 boxVecZ) {
    for (int body = GLOBAL_ID; body < numBodies; body += GLOBAL_SIZE) {
        int type = bodyType[body];
        int4 info = typeInfo[type];
        int numRotations = info.y;
        mixed q[9], position[3], velocity[3], angularMomentum[3], inertia[3], omega[3];
        for (int i = 0; i < 3; i++)
            inertia[i] = typeParams[type*TYPE_STRIDE+TP_MASS+1+i];
        loadRotation(bodyRotation, bodyVelocity, bodyAngularMomentum, body, q);
        loadVector(bodyPosition, body, position);
        loadVector(bodyVelocity, body, velocity);
        loadVector(bodyAngularMomentum, body, angularMomentum);
        angularVelocity(numRotations, angularMomentum, inertia, omega);
        placeBodyParticles(body, numRotations, 1, 1, q, position, velocity, omega, bodyImage[body], bodyRotation, bodyVelocity,
                bodyAngularMomentum, bodyAtomStart,
                atomSlot, &typeCoords[info.x], atomCellOffset, posq, posqCorrection, velm, boxVecX, boxVecY, boxVecZ);
    }
}
