/**
 * Rotations of rigid bodies, in the conventions of the plugin's BodyDynamics.h (which the Reference
 * and CPU kernels use): Q maps lab vectors to body vectors and is held as 9 values, row by row (its
 * rows are the body axes in the lab frame); a free rotation about body axis k by angle a maps
 * Q -> R_k(a)^T Q and every body-frame vector v -> R_k(a)^T v. Vectors are arrays of 3 values, so
 * that components can be picked by index. Q may be passed as 0 where only vectors turn.
 */

/** Q v: a lab vector in the body frame. */
DEVICE void vectorToBodyFrame(const mixed* q, const mixed* v, mixed* result) {
    for (int i = 0; i < 3; i++)
        result[i] = q[3*i]*v[0]+q[3*i+1]*v[1]+q[3*i+2]*v[2];
}

/** Q^T v: a body vector in the lab frame. */
DEVICE void vectorToLabFrame(const mixed* q, const mixed* v, mixed* result) {
    for (int k = 0; k < 3; k++)
        result[k] = q[k]*v[0]+q[3+k]*v[1]+q[6+k]*v[2];
}

/** a x b */
DEVICE void crossProduct(const mixed* a, const mixed* b, mixed* result) {
    result[0] = a[1]*b[2]-a[2]*b[1];
    result[1] = a[2]*b[0]-a[0]*b[2];
    result[2] = a[0]*b[1]-a[1]*b[0];
}

/**
 * The sine and cosine of an angle. Trigonometry dominates the cost of rotations, and the angles a
 * body turns by in a step are small (thermal rotation: ~0.01 rad), so below 0.1 rad their Taylor
 * series are summed, as polynomials in x^2 by Estrin's scheme (pairs of terms, then powers of x^2),
 * whose dependency chain is half as long as Horner's (BodyDynamics.h does the same on the host).
 * With mixed in double precision to the x^11 and x^10 terms (the first left out is below 2e-21
 * relative); in single precision to x^5 and x^4 (the first left out is below 2e-10 relative, under
 * float's rounding of 6e-8). Larger angles take the library's sincos.
 */
DEVICE void sineAndCosine(mixed angle, mixed* sn, mixed* cs) {
    mixed x2 = angle*angle;
    if (x2 < (mixed) 0.01f) {
        // sin(x)/x = s0 + s1 x^2 + ... and cos(x) = c0 + c1 x^2 + ..., sk = (-1)^k/(2k+1)!, ck = (-1)^k/(2k)!.
        const mixed one = 1;
        mixed x4 = x2*x2;
#if defined(USE_MIXED_PRECISION) || defined(USE_DOUBLE_PRECISION)
        mixed x8 = x4*x4;
        mixed s01 = one-x2*(one/6), s23 = one/120-x2*(one/5040), s45 = one/362880-x2*(one/39916800);
        mixed c01 = one-x2*(one/2), c23 = one/24-x2*(one/720), c45 = one/40320-x2*(one/3628800);
        *sn = angle*(s01+(x4*s23+x8*s45));
        *cs = c01+(x4*c23+x8*c45);
#else
        *sn = angle*((one-x2*(one/6))+x4*(one/120));
        *cs = (one-x2*(one/2))+x4*(one/24);
#endif
        return;
    }
#ifdef __OPENCL_VERSION__
    *sn = sincos(angle, cs);
#else
    sincos(angle, sn, cs);
#endif
}

/** Rotate about body axis `axis` by `angle`: Q -> R^T Q and each of the vectors v -> R^T v. */
DEVICE void rotateAboutBodyAxis(mixed* q, int axis, mixed angle, mixed* vectors, int numVectors) {
    int b = (axis+1)%3, c = (axis+2)%3;
    mixed cs, sn;
    sineAndCosine(angle, &sn, &cs);
    if (q != 0)
        for (int k = 0; k < 3; k++) {
            mixed qb = q[3*b+k], qc = q[3*c+k];
            q[3*b+k] = cs*qb+sn*qc;
            q[3*c+k] = cs*qc-sn*qb;
        }
    for (int i = 0; i < numVectors; i++) {
        mixed vb = vectors[3*i+b], vc = vectors[3*i+c];
        vectors[3*i+b] = cs*vb+sn*vc;
        vectors[3*i+c] = cs*vc-sn*vb;
    }
}

/** R^T v for the rotation by angle (cosine cs, sine sn) about the unit vector n, in place. */
DEVICE void applyInverseRotation(const mixed* n, mixed cs, mixed sn, mixed* v) {
    mixed nxv[3];
    crossProduct(n, v, nxv);
    mixed projection = (1-cs)*(n[0]*v[0]+n[1]*v[1]+n[2]*v[2]);
    for (int i = 0; i < 3; i++)
        v[i] = v[i]*cs-nxv[i]*sn+n[i]*projection;
}

/**
 * Rotate by the rotation vector phi (body frame): Q -> R^T Q and each of the vectors v -> R^T v,
 * with R = exp(skew(phi)) (Rodrigues' formula).
 */
DEVICE void rotateByRotationVector(mixed* q, const mixed* phi, mixed* vectors, int numVectors) {
    mixed angle = sqrt(phi[0]*phi[0]+phi[1]*phi[1]+phi[2]*phi[2]);
    if (angle == 0)
        return;
    mixed n[3] = {phi[0]/angle, phi[1]/angle, phi[2]/angle};
    mixed cs, sn;
    sineAndCosine(angle, &sn, &cs);
    if (q != 0)
        for (int k = 0; k < 3; k++) {
            mixed column[3] = {q[k], q[3+k], q[6+k]};
            applyInverseRotation(n, cs, sn, column);
            q[k] = column[0];
            q[3+k] = column[1];
            q[6+k] = column[2];
        }
    for (int i = 0; i < numVectors; i++)
        applyInverseRotation(n, cs, sn, &vectors[3*i]);
}

/**
 * The free rotation over dt driven by the body-frame angular momentum vectors[0..2], which turns
 * along with the other vectors. Three moments: the symmetric DLM splitting
 * x(dt/2) y(dt/2) z(dt) y(dt/2) x(dt/2), each sub-rotation by the angle that the current momentum
 * gives. Linear bodies (rotating about axes 1 and 2 only) turn exactly about their angular
 * velocity, and components along the axis are removed from the vectors.
 */
DEVICE void freeRotorRotation(mixed* q, int numRotations, const mixed* inertia, mixed dt, mixed* vectors, int numVectors) {
    if (numRotations == 2) {
        mixed phi[3] = {0, dt*vectors[1]/inertia[1], dt*vectors[2]/inertia[2]};
        rotateByRotationVector(q, phi, vectors, numVectors);
        for (int i = 0; i < numVectors; i++)
            vectors[3*i] = 0;
    }
    else {
        // The rates before the chain: each sub-rotation then waits on a multiplication, not a division.
        mixed rate0 = 0.5f*dt/inertia[0], rate1 = 0.5f*dt/inertia[1], rate2 = dt/inertia[2];
        rotateAboutBodyAxis(q, 0, rate0*vectors[0], vectors, numVectors);
        rotateAboutBodyAxis(q, 1, rate1*vectors[1], vectors, numVectors);
        rotateAboutBodyAxis(q, 2, rate2*vectors[2], vectors, numVectors);
        rotateAboutBodyAxis(q, 1, rate1*vectors[1], vectors, numVectors);
        rotateAboutBodyAxis(q, 0, rate0*vectors[0], vectors, numVectors);
    }
}
