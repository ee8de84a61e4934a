/**
 * One step of every body: gather its force and torque, kick, then the scheme's flow. The equations
 * are those of the plugin's BodyDynamics.h (the Reference kernel's), see there and docs/physics.md
 * for why each term is there. Bodies are grouped by friction class and number of rotations, and
 * each group has its own kernel, so that a class never pays for another's work: Scalar bodies (free
 * particles) take their exact flow in the lab frame with scalar coefficients, Diagonal bodies
 * multiply by diagonals, only Coupled bodies apply the 6x6 mode matrices; and the number of
 * coordinates is a constant, so that loops unroll and per-body arrays stay in registers.
 *
 * Generalized coordinates: translation along the body axes (0-2), then rotation about the axes
 * that rotate (3 - numRotations to 2); type parameters cover the dof active ones.
 */

#define SCHEME_EXACT_FLOW 0
#define SCHEME_BAOAB 1
#define SCHEME_ORIGINAL 2
#define CLASS_SCALAR 0
#define CLASS_DIAGONAL 1
#define CLASS_COUPLED 2
#define MODE_DECAY 0
#define MODE_DRIFT 1
#define MODE_NOISE_VELOCITY 2
#define MODE_NOISE_CROSS 3
#define MODE_NOISE_DISPLACEMENT 4

/** The generalized coordinate (0-5) of active coordinate i. */
DEVICE int activeCoordinate(int i, int numRotations) {
    return (i < 3 ? i : i+3-numRotations);
}

/** y = A x on the active coordinates; non-coupled classes multiply by the diagonal alone. */
DEVICE void multiplyActive(GLOBAL const mixed* RESTRICT a, int dof, int frictionClass, const mixed* x, mixed* y) {
    if (frictionClass == CLASS_COUPLED)
        for (int i = 0; i < dof; i++) {
            mixed sum = 0;
            for (int j = 0; j < dof; j++)
                sum += a[6*i+j]*x[j];
            y[i] = sum;
        }
    else
        for (int i = 0; i < dof; i++)
            y[i] = a[7*i]*x[i];
}

/**
 * A body as the step works on it: state in private memory, type parameters in global memory. The
 * number of rotations is passed beside it, not kept in it: a constant in each kernel, it lets every
 * loop over coordinates unroll, so that the body's arrays stay in registers (with a field read back
 * from the struct, they went to local memory, which moved more bytes than the step needs).
 */
typedef struct {
    mixed q[9], position[3], velocity[3], angularMomentum[3];
    mixed mass, inertia[3];
} Body;

/** The generalized velocity (Q V, omega) on the active coordinates. */
DEVICE void generalizedVelocity(const Body* b, int numRotations, mixed* u) {
    mixed vb[3];
    vectorToBodyFrame(b->q, b->velocity, vb);
    for (int i = 0; i < 3+numRotations; i++) {
        int k = activeCoordinate(i, numRotations);
        u[i] = (k < 3 ? vb[k] : b->angularMomentum[k-3]/b->inertia[k-3]);
    }
}

/** Add dt*force/m to the velocity and dt*torque to the angular momentum about the axes that rotate. */
DEVICE void kickBody(Body* b, int numRotations, const mixed* force, const mixed* torque, mixed dt) {
    mixed scale = dt/b->mass;
    for (int i = 0; i < 3; i++) {
        b->velocity[i] += force[i]*scale;
        if (i >= 3-numRotations)
            b->angularMomentum[i] += dt*torque[i];
    }
}

/** The free drift over dt: translation and free rotation (BAOAB's A, velocity Verlet's drift). */
DEVICE void driftBody(Body* b, int numRotations, mixed dt) {
    for (int i = 0; i < 3; i++)
        b->position[i] += b->velocity[i]*dt;
    if (numRotations > 0)
        freeRotorRotation(b->q, numRotations, b->inertia, dt, b->angularMomentum, 1);
}

/**
 * ExactFlow: the exact flow of the free body under friction and noise over h, taken as two exact
 * halves for bodies that rotate, plus the frame-rotation terms of second order (BodyDynamics::exactFlow).
 * Uses 2 (one flow) or 4 (two halves) normal random numbers per active coordinate.
 */
DEVICE void exactFlow(Body* b, int numRotations, int halfSteps, GLOBAL const mixed* RESTRICT tp, int frictionClass, mixed h, const float* rnd) {
    const int dof = 3+numRotations;
    mixed u[6], a[6], mid[6], y[6], displacement[6];
    generalizedVelocity(b, numRotations, u);
    multiplyActive(&tp[TP_TO_MODES], dof, frictionClass, u, a);
    for (int i = 0; i < dof; i++) {
        GLOBAL const mixed* m = &tp[TP_MODES+5*i];
        if (halfSteps) {
            mixed n1 = rnd[4*i], n2 = rnd[4*i+1], n3 = rnd[4*i+2], n4 = rnd[4*i+3];
            y[i] = m[MODE_DRIFT]*a[i]+m[MODE_NOISE_CROSS]*n1+m[MODE_NOISE_DISPLACEMENT]*n2;
            a[i] = m[MODE_DECAY]*a[i]+m[MODE_NOISE_VELOCITY]*n1;
            mid[i] = a[i];
            y[i] += m[MODE_DRIFT]*a[i]+m[MODE_NOISE_CROSS]*n3+m[MODE_NOISE_DISPLACEMENT]*n4;
            a[i] = m[MODE_DECAY]*a[i]+m[MODE_NOISE_VELOCITY]*n3;
        }
        else {
            mixed n1 = rnd[2*i], n2 = rnd[2*i+1];
            y[i] = m[MODE_DRIFT]*a[i]+m[MODE_NOISE_CROSS]*n1+m[MODE_NOISE_DISPLACEMENT]*n2;
            a[i] = m[MODE_DECAY]*a[i]+m[MODE_NOISE_VELOCITY]*n1;
        }
    }
    multiplyActive(&tp[TP_FROM_MODES], dof, frictionClass, a, u);
    multiplyActive(&tp[TP_FROM_MODES], dof, frictionClass, y, displacement);
    mixed dx[3] = {0, 0, 0}, vb[3] = {0, 0, 0}, j[3] = {0, 0, 0}, theta[3] = {0, 0, 0};
    for (int i = 0; i < dof; i++) {
        int k = activeCoordinate(i, numRotations);
        if (k < 3) {
            dx[k] = displacement[i];
            vb[k] = u[i];
        }
        else {
            j[k-3] = b->inertia[k-3]*u[i];
            theta[k-3] = displacement[i];
        }
    }
    if (numRotations == 0) {
        vectorToLabFrame(b->q, vb, b->velocity);
        mixed labDx[3];
        vectorToLabFrame(b->q, dx, labDx);
        for (int i = 0; i < 3; i++)
            b->position[i] += labDx[i];
        return;
    }

    // Mid-step velocities, scaled by their drive fractions.
    mixed midVelocity[6], vMid[3] = {0, 0, 0}, wMid[3] = {0, 0, 0};
    multiplyActive(&tp[TP_FROM_MODES], dof, frictionClass, mid, midVelocity);
    for (int i = 0; i < dof; i++) {
        int k = activeCoordinate(i, numRotations);
        if (k < 3)
            vMid[k] = tp[TP_DRIVE+k]*midVelocity[i];
        else
            wMid[k-3] = tp[TP_DRIVE+k]*midVelocity[i];
    }

    // Translation with the Stratonovich drift (theta x dx)/2, less the same product of mid-step velocities.
    mixed thetaCrossDx[3], wCrossV[3], step[3], labStep[3];
    crossProduct(theta, dx, thetaCrossDx);
    crossProduct(wMid, vMid, wCrossV);
    for (int i = 0; i < 3; i++)
        step[i] = dx[i]+(thetaCrossDx[i]-wCrossV[i]*(h*h))*0.5f;
    vectorToLabFrame(b->q, step, labStep);
    for (int i = 0; i < 3; i++)
        b->position[i] += labStep[i];

    // Rotation: half the rest of theta, the free rotor driven by I c w, the other half.
    mixed drive[3], rest[3];
    for (int k = 0; k < 3; k++) {
        drive[k] = b->inertia[k]*wMid[k];
        rest[k] = 0.5f*(theta[k]-h*wMid[k]);
    }
    rotateByRotationVector(b->q, rest, drive, 1);
    freeRotorRotation(b->q, numRotations, b->inertia, h, drive, 1);
    rotateByRotationVector(b->q, rest, drive, 0);

    // The end angular momentum and the end velocity turn by the free-rotor motion of the end angular
    // momentum, scaled by c, into the new body frame; not by the rest of the rotation, which is
    // correlated with the end velocity (BodyDynamics::exactFlow). A linear body's velocity keeps its
    // axial component: it turns by the same exact rotation, outside freeRotorRotation.
    mixed vectors[9];
    for (int k = 0; k < 3; k++) {
        vectors[k] = tp[TP_DRIVE+3+k]*j[k];
        vectors[3+k] = j[k];
        vectors[6+k] = vb[k];
    }
    if (numRotations == 2) {
        mixed phi[3] = {0, h*vectors[1]/b->inertia[1], h*vectors[2]/b->inertia[2]};
        rotateByRotationVector(0, phi, &vectors[6], 1);
        freeRotorRotation(0, numRotations, b->inertia, h, vectors, 2);
    }
    else
        freeRotorRotation(0, numRotations, b->inertia, h, vectors, 3);
    for (int k = 0; k < 3; k++)
        b->angularMomentum[k] = (k >= 3-numRotations ? vectors[3+k] : 0);
    vectorToLabFrame(b->q, &vectors[6], b->velocity);
}

/** BAOAB's O: the exact Ornstein-Uhlenbeck step of the velocities over h (dof random numbers). */
DEVICE void ornsteinUhlenbeck(Body* b, int numRotations, GLOBAL const mixed* RESTRICT tp, int frictionClass, const float* rnd) {
    const int dof = 3+numRotations;
    mixed u[6], a[6];
    generalizedVelocity(b, numRotations, u);
    multiplyActive(&tp[TP_TO_MODES], dof, frictionClass, u, a);
    for (int i = 0; i < dof; i++)
        a[i] = tp[TP_MODES+5*i+MODE_DECAY]*a[i]+tp[TP_MODES+5*i+MODE_NOISE_VELOCITY]*rnd[i];
    multiplyActive(&tp[TP_FROM_MODES], dof, frictionClass, a, u);
    mixed vb[3];
    for (int i = 0; i < dof; i++) {
        int k = activeCoordinate(i, numRotations);
        if (k < 3)
            vb[k] = u[i];
        else
            b->angularMomentum[k-3] = b->inertia[k-3]*u[i];
    }
    vectorToLabFrame(b->q, vb, b->velocity);
}

/**
 * The Original scheme (Sun, Lin and Gezelter): finish the previous step with the friction of the
 * second half kick by fixed-point iteration and a fresh random force, then half kick, drift and
 * rotate (BodyDynamics::originalStep). Uses dof random numbers. ORIGINAL_MAX_ITERATIONS and
 * ORIGINAL_TOLERANCE come from the host (BodyDynamics.h).
 */
DEVICE void originalStep(Body* b, int numRotations, GLOBAL const mixed* RESTRICT tp, const mixed* force, const mixed* torque, mixed h, const float* rnd) {
    const int dof = 3+numRotations;
    mixed uHalf[6], u[6], g[6], fb[3];
    generalizedVelocity(b, numRotations, uHalf);
    vectorToBodyFrame(b->q, force, fb);
    for (int i = 0; i < dof; i++) {
        int k = activeCoordinate(i, numRotations);
        g[i] = (k < 3 ? fb[k] : torque[k-3]);
    }
    for (int i = 0; i < dof; i++)
        for (int j = 0; j <= i; j++)
            g[i] += tp[TP_RANDOM_FORCE+6*i+j]*rnd[j];
    for (int i = 0; i < dof; i++)
        u[i] = uHalf[i];
    for (int iteration = 0; iteration < ORIGINAL_MAX_ITERATIONS; iteration++) {
        mixed change = 0, size = 0, next[6];
        for (int i = 0; i < dof; i++) {
            mixed friction = 0;
            for (int j = 0; j < dof; j++)
                friction += tp[TP_FRICTION+6*i+j]*u[j];
            next[i] = uHalf[i]+0.5f*h*tp[TP_INVERSE_MASS+i]*(g[i]-friction);
            change = max(change, fabs(next[i]-u[i]));
            size = max(size, fabs(next[i]));
        }
        for (int i = 0; i < dof; i++)
            u[i] = next[i];
        if (change <= ORIGINAL_TOLERANCE*size)
            break;
    }
    mixed vb[3], totalForce[3];
    for (int i = 0; i < dof; i++) {
        mixed friction = 0;
        for (int j = 0; j < dof; j++)
            friction += tp[TP_FRICTION+6*i+j]*u[j];
        mixed total = g[i]-friction;
        int k = activeCoordinate(i, numRotations);
        if (k < 3) {
            vb[k] = u[i];
            totalForce[k] = total;
        }
        else
            b->angularMomentum[k-3] = b->inertia[k-3]*u[i]+0.5f*h*total;
    }
    mixed kicked[3];
    mixed scale = 0.5f*h/b->mass;
    for (int i = 0; i < 3; i++)
        kicked[i] = vb[i]+totalForce[i]*scale;
    vectorToLabFrame(b->q, kicked, b->velocity);
    driftBody(b, numRotations, h);
}

/**
 * Free particles and single-particle bodies: isotropic friction on translation alone, so the exact
 * flow (or the O step) acts on each lab-frame component with the same scalar coefficients, with no
 * rotation matrix at all. Returns with the position and velocity updated.
 */
DEVICE void scalarFlow(Body* b, GLOBAL const mixed* RESTRICT tp, int scheme, mixed h, const float* rnd) {
    GLOBAL const mixed* m = &tp[TP_MODES];
    mixed sqrtMass = tp[TP_TO_MODES], invSqrtMass = tp[TP_FROM_MODES];
    if (scheme == SCHEME_EXACT_FLOW)
        for (int i = 0; i < 3; i++) {
            mixed a = sqrtMass*b->velocity[i];
            mixed y = m[MODE_DRIFT]*a+m[MODE_NOISE_CROSS]*rnd[2*i]+m[MODE_NOISE_DISPLACEMENT]*rnd[2*i+1];
            a = m[MODE_DECAY]*a+m[MODE_NOISE_VELOCITY]*rnd[2*i];
            b->velocity[i] = invSqrtMass*a;
            b->position[i] += invSqrtMass*y;
        }
    else {
        for (int i = 0; i < 3; i++)
            b->position[i] += 0.5f*h*b->velocity[i];
        for (int i = 0; i < 3; i++)
            b->velocity[i] = invSqrtMass*(m[MODE_DECAY]*sqrtMass*b->velocity[i]+m[MODE_NOISE_VELOCITY]*rnd[i]);
        for (int i = 0; i < 3; i++)
            b->position[i] += 0.5f*h*b->velocity[i];
    }
}

/**
 * Advance body k by one step and place its particles. frictionClass and numRotations are constants
 * in each kernel that calls this, and the scheme is STEP_SCHEME, fixed when the program is compiled
 * (the host compiles one program per scheme it uses): the compiler drops the other groups' and
 * schemes' code, unrolls the loops over coordinates and needs fewer registers (166 instead of 238
 * for coupled bodies on sm_90, in mixed precision), so that more bodies are in flight.
 *
 * Placing the particles here rather than in a pass of its own saves reading the body state and the
 * particle entries a second time: the step is bound by memory traffic.
 */
DEVICE void stepBody(int body, int frictionClass, int numRotations, int frictionless, mixed h, int removeMotion,
        GLOBAL mixed4* RESTRICT bodyPosition, GLOBAL mixed4* RESTRICT bodyVelocity, GLOBAL mixed4* RESTRICT bodyAngularMomentum,
        GLOBAL mixed4* RESTRICT bodyRotation, GLOBAL const int* RESTRICT bodyType, GLOBAL const int* RESTRICT bodyAtomStart,
        GLOBAL const int* RESTRICT atomSlot, GLOBAL const mixed4* RESTRICT typeCoords, GLOBAL const int4* RESTRICT atomCellOffset,
        GLOBAL const mm_long* RESTRICT force, GLOBAL const mixed* RESTRICT typeParams, GLOBAL const int4* RESTRICT typeInfo,
        unsigned int seed, mm_ulong randomStep, int randomPerBody, GLOBAL const mixed4* RESTRICT centerOfMassVelocity,
        int periodic, mixed4 boxVecX, mixed4 boxVecY, mixed4 boxVecZ, GLOBAL int4* RESTRICT bodyImage,
        GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection, GLOBAL mixed4* RESTRICT velm) {
    const int scheme = STEP_SCHEME;
    // The Original scheme turns every body. The constant goes left of ||: clang warns, on every
    // build of the program, about || with a constant right operand.
    const int haveRotation = (scheme == SCHEME_ORIGINAL || frictionClass != CLASS_SCALAR);
    int type = bodyType[body];
    GLOBAL const mixed* tp = &typeParams[type*TYPE_STRIDE];
    int4 info = typeInfo[type];
    Body b;
    b.mass = tp[TP_MASS];
    for (int i = 0; i < 3; i++)
        b.inertia[i] = tp[TP_MASS+1+i];
    // The w of velocity and angular momentum: the rotation's Q11 and Q12 (rigidBodyAtoms.cc). A body
    // that does not rotate keeps a zero angular momentum, read only for its (fixed) rotation and
    // written only where the rotation is.
    const int storesRotation = (frictionClass != CLASS_SCALAR);
    loadVector(bodyPosition, body, b.position);
    mixed4 velocity4 = bodyVelocity[body];
    mixed4 angular4 = make_mixed4(0, 0, 0, 0);
    if (haveRotation || numRotations > 0)
        angular4 = bodyAngularMomentum[body];
    b.velocity[0] = velocity4.x;
    b.velocity[1] = velocity4.y;
    b.velocity[2] = velocity4.z;
    b.angularMomentum[0] = (numRotations > 0 ? angular4.x : 0);
    b.angularMomentum[1] = (numRotations > 0 ? angular4.y : 0);
    b.angularMomentum[2] = (numRotations > 0 ? angular4.z : 0);
    if (haveRotation)
        unpackRotation(bodyRotation[body], velocity4.w, angular4.w, b.q);
    if (removeMotion) {
        mixed4 v = centerOfMassVelocity[0];
        b.velocity[0] -= v.x;
        b.velocity[1] -= v.y;
        b.velocity[2] -= v.z;
    }
    mixed totalForce[3], torque[3];
    GLOBAL const mixed4* RESTRICT bodyCoords = &typeCoords[info.x];
    loadBodyForce(body, numRotations, b.q, bodyAtomStart, atomSlot, bodyCoords, force, totalForce, torque);

    // This body's normal random numbers, made here (rigidBodyRandom.cc). The loop has a constant
    // bound so that it unrolls and rnd stays in registers: with a runtime bound rnd lives in local
    // memory, which moves more bytes than the whole step needs.
    float rnd[4*MAX_RANDOM_FLOAT4_PER_BODY];
    for (int i = 0; i < MAX_RANDOM_FLOAT4_PER_BODY; i++) {
        if (i < randomPerBody)
            normalFloat4(seed, body, i, randomStep, &rnd[4*i]);
        else
            rnd[4*i] = rnd[4*i+1] = rnd[4*i+2] = rnd[4*i+3] = 0;
    }
    if (scheme == SCHEME_ORIGINAL)
        originalStep(&b, numRotations, tp, totalForce, torque, h, rnd);
    else {
        // Velocities are kept between flow and kick: the half kicks of consecutive steps are one.
        kickBody(&b, numRotations, totalForce, torque, h);
        if (frictionless) {
            if (scheme == SCHEME_EXACT_FLOW)
                driftBody(&b, numRotations, h);
            else {
                driftBody(&b, numRotations, 0.5f*h);
                driftBody(&b, numRotations, 0.5f*h);
            }
        }
        else if (frictionClass == CLASS_SCALAR)
            scalarFlow(&b, tp, scheme, h, rnd);
        else if (scheme == SCHEME_EXACT_FLOW)
            exactFlow(&b, numRotations, info.z, tp, frictionClass, h, rnd);
        else {
            driftBody(&b, numRotations, 0.5f*h);
            ornsteinUhlenbeck(&b, numRotations, tp, frictionClass, rnd);
            driftBody(&b, numRotations, 0.5f*h);
        }
    }
    // Without a periodic box a body never leaves it: its image stays zero, and is not read.
    int4 image = (periodic ? bodyImage[body] : make_int4(0, 0, 0, 0));
    if (periodic && keepInBox(b.position, &image, boxVecX, boxVecY, boxVecZ))
        bodyImage[body] = image;
    mixed q11 = velocity4.w, q12 = angular4.w;
    if (storesRotation) {
        bodyRotation[body] = make_mixed4(b.q[0], b.q[1], b.q[2], b.q[3]);
        q11 = b.q[4];
        q12 = b.q[5];
    }
    storeVector(bodyPosition, body, b.position);
    bodyVelocity[body] = make_mixed4(b.velocity[0], b.velocity[1], b.velocity[2], q11);
    if (numRotations > 0 || storesRotation)
        bodyAngularMomentum[body] = make_mixed4(b.angularMomentum[0], b.angularMomentum[1], b.angularMomentum[2], q12);
    mixed omega[3];
    angularVelocity(numRotations, b.angularMomentum, b.inertia, omega);
    placeBodyParticles(body, numRotations, haveRotation, periodic, b.q, b.position, b.velocity, omega, image, bodyRotation, bodyVelocity,
            bodyAngularMomentum, bodyAtomStart,
            atomSlot, bodyCoords, atomCellOffset, posq, posqCorrection, velm, boxVecX, boxVecY, boxVecZ);
}

#define STEP_KERNEL(name, frictionClass, numRotations) \
KERNEL void name(int first, int last, int frictionless, mixed h, int removeMotion, \
        GLOBAL mixed4* RESTRICT bodyPosition, GLOBAL mixed4* RESTRICT bodyVelocity, GLOBAL mixed4* RESTRICT bodyAngularMomentum, \
        GLOBAL mixed4* RESTRICT bodyRotation, GLOBAL const int* RESTRICT bodyType, GLOBAL const int* RESTRICT bodyAtomStart, \
        GLOBAL const int* RESTRICT atomSlot, GLOBAL const mixed4* RESTRICT typeCoords, GLOBAL const int4* RESTRICT atomCellOffset, \
        GLOBAL const mm_long* RESTRICT force, GLOBAL const mixed* RESTRICT typeParams, GLOBAL const int4* RESTRICT typeInfo, \
        unsigned int seed, mm_ulong randomStep, int randomPerBody, GLOBAL const mixed4* RESTRICT centerOfMassVelocity, \
        int periodic, mixed4 boxVecX, mixed4 boxVecY, mixed4 boxVecZ, GLOBAL int4* RESTRICT bodyImage, \
        GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection, GLOBAL mixed4* RESTRICT velm) { \
    for (int body = first+GLOBAL_ID; body < last; body += GLOBAL_SIZE) \
        stepBody(body, frictionClass, numRotations, frictionless, h, removeMotion, bodyPosition, bodyVelocity, \
                bodyAngularMomentum, bodyRotation, bodyType, bodyAtomStart, atomSlot, typeCoords, atomCellOffset, force, typeParams, \
                typeInfo, seed, randomStep, randomPerBody, centerOfMassVelocity, periodic, boxVecX, boxVecY, \
                boxVecZ, bodyImage, posq, posqCorrection, velm); \
}

STEP_KERNEL(stepScalarBodies, CLASS_SCALAR, 0)
STEP_KERNEL(stepDiagonalBodies0, CLASS_DIAGONAL, 0)
STEP_KERNEL(stepDiagonalBodies2, CLASS_DIAGONAL, 2)
STEP_KERNEL(stepDiagonalBodies3, CLASS_DIAGONAL, 3)
STEP_KERNEL(stepCoupledBodies0, CLASS_COUPLED, 0)
STEP_KERNEL(stepCoupledBodies2, CLASS_COUPLED, 2)
STEP_KERNEL(stepCoupledBodies3, CLASS_COUPLED, 3)
