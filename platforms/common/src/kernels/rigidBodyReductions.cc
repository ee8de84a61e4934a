/**
 * Sums over all bodies: the total momentum (to remove the centre-of-mass motion) and the kinetic
 * energies. Work groups have REDUCTION_GROUP_SIZE work items and reduce in local memory.
 */

/** Sum the three values of every work item of the group into sums[0..2]; all items must call it. */
DEVICE void reduceThree(LOCAL_ARG mixed* sums, mixed a, mixed b, mixed c) {
    sums[3*LOCAL_ID] = a;
    sums[3*LOCAL_ID+1] = b;
    sums[3*LOCAL_ID+2] = c;
    SYNC_THREADS;
    for (int offset = REDUCTION_GROUP_SIZE/2; offset > 0; offset /= 2) {
        if (LOCAL_ID < offset)
            for (int i = 0; i < 3; i++)
                sums[3*LOCAL_ID+i] += sums[3*(LOCAL_ID+offset)+i];
        SYNC_THREADS;
    }
}

/**
 * The velocity of the centre of mass of all bodies, into centerOfMassVelocity[0]. Run as a single
 * work group.
 */
KERNEL void computeCenterOfMassVelocity(int numBodies, mixed inverseTotalMass, GLOBAL const mixed4* RESTRICT bodyVelocity,
        GLOBAL const int* RESTRICT bodyType, GLOBAL const mixed* RESTRICT typeParams, GLOBAL mixed4* RESTRICT centerOfMassVelocity) {
    LOCAL mixed sums[3*REDUCTION_GROUP_SIZE];
    mixed p[3] = {0, 0, 0};
    for (int body = LOCAL_ID; body < numBodies; body += LOCAL_SIZE) {
        mixed mass = typeParams[bodyType[body]*TYPE_STRIDE+TP_MASS];
        mixed4 v = bodyVelocity[body];
        p[0] += mass*v.x;
        p[1] += mass*v.y;
        p[2] += mass*v.z;
    }
    reduceThree(sums, p[0], p[1], p[2]);
    if (LOCAL_ID == 0)
        centerOfMassVelocity[0] = make_mixed4(sums[0]*inverseTotalMass, sums[1]*inverseTotalMass, sums[2]*inverseTotalMass, 0);
}

/**
 * Per work group: the sums of 1/2 m V^2 and of 1/2 j_k^2/I_k over the rotating axes (energy[2*group]
 * .x and .y) and of the momentum (energy[2*group+1]), with each body's velocities first kicked
 * forward by timeShift with its force and torque.
 */
KERNEL void computeBodyKineticEnergies(int numBodies, mixed timeShift, GLOBAL const mixed4* RESTRICT bodyVelocity,
        GLOBAL const mixed4* RESTRICT bodyAngularMomentum, GLOBAL const mixed4* RESTRICT bodyRotation,
        GLOBAL const int* RESTRICT bodyType, GLOBAL const int* RESTRICT bodyAtomStart, GLOBAL const int* RESTRICT atomSlot,
        GLOBAL const mixed4* RESTRICT typeCoords, GLOBAL const mm_long* RESTRICT force, GLOBAL const mixed* RESTRICT typeParams,
        GLOBAL const int4* RESTRICT typeInfo, GLOBAL mixed4* RESTRICT energy) {
    LOCAL mixed sums[3*REDUCTION_GROUP_SIZE];
    mixed translational = 0, rotational = 0, p[3] = {0, 0, 0};
    for (int body = GLOBAL_ID; body < numBodies; body += GLOBAL_SIZE) {
        int type = bodyType[body];
        GLOBAL const mixed* tp = &typeParams[type*TYPE_STRIDE];
        int4 info = typeInfo[type];
        int numRotations = info.y;
        mixed mass = tp[TP_MASS];
        mixed v[3], j[3];
        loadVector(bodyVelocity, body, v);
        loadVector(bodyAngularMomentum, body, j);
        if (timeShift != 0) {
            mixed q[9], f[3], torque[3];
            loadRotation(bodyRotation, bodyVelocity, bodyAngularMomentum, body, q);
            loadBodyForce(body, numRotations, q, bodyAtomStart, atomSlot, &typeCoords[info.x], force, f, torque);
            for (int i = 0; i < 3; i++) {
                v[i] += f[i]*(timeShift/mass);
                j[i] += timeShift*torque[i];
            }
        }
        translational += 0.5f*mass*(v[0]*v[0]+v[1]*v[1]+v[2]*v[2]);
        for (int k = 3-numRotations; k < 3; k++)
            rotational += 0.5f*j[k]*j[k]/tp[TP_MASS+1+k];
        for (int i = 0; i < 3; i++)
            p[i] += mass*v[i];
    }
    reduceThree(sums, translational, rotational, 0);
    mixed2 energies = make_mixed2(sums[0], sums[1]);
    SYNC_THREADS;
    reduceThree(sums, p[0], p[1], p[2]);
    if (LOCAL_ID == 0) {
        energy[2*GROUP_ID] = make_mixed4(energies.x, energies.y, 0, 0);
        energy[2*GROUP_ID+1] = make_mixed4(sums[0], sums[1], sums[2], 0);
    }
}
