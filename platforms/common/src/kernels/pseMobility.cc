/**
 * The positively split Ewald product of the blobs' mobility in a periodic box, velocity = M force
 * per unit viscosity, on the device (CommonPseMobility): the same operator as the host's
 * PositivelySplitEwald, whose setBlobs() prepares what these kernels apply (the real-space pairs,
 * each blob's Gaussian factors, the Fourier factors), so that a product here and there differ by
 * rounding only.
 *
 * Real space: rows of pairs in the cells' order (pseGatherForces, pseRealSpaceRows), the pair terms
 * in pse_pair_real (double if PSE_DOUBLE_PAIRS; float from epsilon 1e-4 up, as the host stores them), each row summed in
 * double. Wave space: each blob's Gaussian spread onto the grid by 64-bit fixed-point atomic adds
 * (pseSpread: exact integer sums, so the grid does not depend on the order the adds come in; the
 * scale is a power of two chosen per product so that no point can overflow), converted to the
 * FFT's real type (pseGridToReal, which clears the accumulator for the next product), transformed
 * by OpenMM's FFT3D, multiplied by D(k) (I - k k) mode by mode (pseApplyFactors), transformed back
 * and interpolated (pseInterpolate, which adds to the real-space velocity). Several radius groups
 * are spread and transformed one by one and summed with sinc(k a_g) (pseScaleSpectrum).
 * Grid arrays: component c of point (i0, i1, i2) at (i0 M1 + i1) M2 + i2, one array per component.
 */
#if defined(cl_khr_fp64)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#if PSE_DOUBLE_PAIRS
typedef double pse_pair_real;
#else
typedef float pse_pair_real;
#endif

/** One real-space pair, laid out as the host's PseRealSpace::Pair. */
typedef struct {
    int j;
    pse_pair_real isotropic, dyadicPerR2, d[3];
} PsePair;

KERNEL void pseGatherForces(int numBlobs, GLOBAL const int* RESTRICT order, GLOBAL const double* RESTRICT force, GLOBAL double* RESTRICT sorted) {
    for (int i = GLOBAL_ID; i < numBlobs; i += GLOBAL_SIZE) {
        const int from = order[i];
        for (int c = 0; c < 3; c++)
            sorted[3*i+c] = force[3*from+c];
    }
}

/** velocity of blob order[i] = self_i f_i + sum over row i's pairs of F_ij f_j. */
KERNEL void pseRealSpaceRows(int numBlobs, GLOBAL const int* RESTRICT order, GLOBAL const mm_long* RESTRICT rowStart,
        GLOBAL const PsePair* RESTRICT pairs, GLOBAL const double* RESTRICT self, GLOBAL const double* RESTRICT sorted,
        GLOBAL double* RESTRICT velocity) {
    for (int i = GLOBAL_ID; i < numBlobs; i += GLOBAL_SIZE) {
        double u[3];
        for (int c = 0; c < 3; c++)
            u[c] = self[i]*sorted[3*i+c];
        for (mm_long k = rowStart[i]; k < rowStart[i+1]; k++) {
            const PsePair pair = pairs[k];
            const double f0 = sorted[3*pair.j], f1 = sorted[3*pair.j+1], f2 = sorted[3*pair.j+2];
            const double projection = pair.dyadicPerR2*(pair.d[0]*f0+pair.d[1]*f1+pair.d[2]*f2);
            u[0] += pair.isotropic*f0+projection*pair.d[0];
            u[1] += pair.isotropic*f1+projection*pair.d[1];
            u[2] += pair.isotropic*f2+projection*pair.d[2];
        }
        const int to = order[i];
        for (int c = 0; c < 3; c++)
            velocity[3*to+c] = u[c];
    }
}

/** The grid index of support point n along an axis of m points from first (wrapped). */
DEVICE int pseWrap(int first, int n, int m) {
    return (first+n >= m ? first+n-m : first+n);
}

/**
 * The blobs groupBlobs[first ... first+count) spread, one work item per (blob, n0, n1) line of the
 * support: grid += g(x - r_i) f_i scale, in fixed point.
 */
KERNEL void pseSpread(int first, int count, int p, int m0, int m1, int m2, GLOBAL const int* RESTRICT groupBlobs,
        GLOBAL const int* RESTRICT base, GLOBAL const real* RESTRICT factors, GLOBAL const real* RESTRICT cross, int triclinic,
        GLOBAL const double* RESTRICT force, double scale, GLOBAL mm_ulong* RESTRICT grid) {
    const int lines = p*p;
    const int points = m0*m1*m2;
    for (int index = GLOBAL_ID; index < count*lines; index += GLOBAL_SIZE) {
        const int i = groupBlobs[first+index/lines];
        const int n0 = (index%lines)/p, n1 = index%p;
        GLOBAL const real* w = factors+3*p*i;
        const real w01 = w[n0]*w[p+n1];
        const real f[3] = {(real) (force[3*i]*scale), (real) (force[3*i+1]*scale), (real) (force[3*i+2]*scale)};
        const int row = (pseWrap(base[3*i], n0, m0)*m1+pseWrap(base[3*i+1], n1, m1))*m2;
        for (int n2 = 0; n2 < p; n2++) {
            const real weight = w01*w[2*p+n2]*(triclinic ? cross[(n0*p+n1)*p+n2] : (real) 1);
            const int point = row+pseWrap(base[3*i+2], n2, m2);
            for (int c = 0; c < 3; c++)
                ATOMIC_ADD(&grid[c*points+point], (mm_ulong) ((mm_long) (weight*f[c])));
        }
    }
}

/** The fixed-point grid to the FFT's real input (packed reals), times inverseScale; clears grid. */
KERNEL void pseGridToReal(int points, GLOBAL mm_long* RESTRICT grid, double inverseScale, GLOBAL real* RESTRICT out0,
        GLOBAL real* RESTRICT out1, GLOBAL real* RESTRICT out2) {
    for (int k = GLOBAL_ID; k < points; k += GLOBAL_SIZE) {
        out0[k] = (real) (grid[k]*inverseScale);
        out1[k] = (real) (grid[points+k]*inverseScale);
        out2[k] = (real) (grid[2*points+k]*inverseScale);
        grid[k] = grid[points+k] = grid[2*points+k] = 0;
    }
}

/** to_c = sinc_g(k) from_c (or to_c += that if add) for the modes of the half spectrum; sincs holds each group's in turn. */
KERNEL void pseScaleSpectrum(int modes, GLOBAL const double* RESTRICT sincs, int g, int add, GLOBAL const real2* RESTRICT from0,
        GLOBAL const real2* RESTRICT from1, GLOBAL const real2* RESTRICT from2, GLOBAL real2* RESTRICT to0, GLOBAL real2* RESTRICT to1,
        GLOBAL real2* RESTRICT to2) {
    for (int k = GLOBAL_ID; k < modes; k += GLOBAL_SIZE) {
        const real s = (real) sincs[(mm_long) g*modes+k];
        const real2 zero = make_real2(0, 0);
        to0[k] = (add ? to0[k] : zero)+from0[k]*s;
        to1[k] = (add ? to1[k] : zero)+from1[k]*s;
        to2[k] = (add ? to2[k] : zero)+from2[k]*s;
    }
}

/** u(k) = D(k) (I - k k/k^2) u(k) for every mode (i0, i1, i2) of the M0 x M1 x half spectrum. */
KERNEL void pseApplyFactors(int m0, int m1, int halfLength, GLOBAL const double* RESTRICT factor, double r00, double r01, double r02,
        double r10, double r11, double r12, double r20, double r21, double r22, GLOBAL real2* RESTRICT u0, GLOBAL real2* RESTRICT u1,
        GLOBAL real2* RESTRICT u2) {
    const int modes = m0*m1*halfLength;
    for (int index = GLOBAL_ID; index < modes; index += GLOBAL_SIZE) {
        const double d = factor[index];
        if (d == 0) {
            u0[index] = u1[index] = u2[index] = make_real2(0, 0);
            continue;
        }
        const int i0 = index/(m1*halfLength), i1 = (index/halfLength)%m1, i2 = index%halfLength;
        const int n0 = (i0 > m0/2 ? i0-m0 : i0), n1 = (i1 > m1/2 ? i1-m1 : i1);
        double k0 = r00*n0+r10*n1+r20*i2, k1 = r01*n0+r11*n1+r21*i2, k2 = r02*n0+r12*n1+r22*i2;
        const double inverseLength = 1/sqrt(k0*k0+k1*k1+k2*k2);
        k0 *= inverseLength;
        k1 *= inverseLength;
        k2 *= inverseLength;
        const real2 a = u0[index], b = u1[index], c = u2[index];
        const double alongX = k0*a.x+k1*b.x+k2*c.x, alongY = k0*a.y+k1*b.y+k2*c.y;
        u0[index] = make_real2((real) (d*(a.x-k0*alongX)), (real) (d*(a.y-k0*alongY)));
        u1[index] = make_real2((real) (d*(b.x-k1*alongX)), (real) (d*(b.y-k1*alongY)));
        u2[index] = make_real2((real) (d*(c.x-k2*alongX)), (real) (d*(c.y-k2*alongY)));
    }
}

/** velocity_i += sum over blob i's support of g(x_m - r_i) grid_m, for the blobs groupBlobs[first ... first+count). */
KERNEL void pseInterpolate(int first, int count, int p, int m0, int m1, int m2, GLOBAL const int* RESTRICT groupBlobs,
        GLOBAL const int* RESTRICT base, GLOBAL const real* RESTRICT factors, GLOBAL const real* RESTRICT cross, int triclinic,
        GLOBAL const real* RESTRICT grid0, GLOBAL const real* RESTRICT grid1, GLOBAL const real* RESTRICT grid2,
        GLOBAL double* RESTRICT velocity) {
    for (int k = GLOBAL_ID; k < count; k += GLOBAL_SIZE) {
        const int i = groupBlobs[first+k];
        GLOBAL const real* w = factors+3*p*i;
        double u[3] = {0, 0, 0};
        for (int n0 = 0; n0 < p; n0++)
            for (int n1 = 0; n1 < p; n1++) {
                const real w01 = w[n0]*w[p+n1];
                const int row = (pseWrap(base[3*i], n0, m0)*m1+pseWrap(base[3*i+1], n1, m1))*m2;
                real sums[3] = {0, 0, 0};
                for (int n2 = 0; n2 < p; n2++) {
                    const real weight = w[2*p+n2]*(triclinic ? cross[(n0*p+n1)*p+n2] : (real) 1);
                    const int point = row+pseWrap(base[3*i+2], n2, m2);
                    sums[0] += weight*grid0[point];
                    sums[1] += weight*grid1[point];
                    sums[2] += weight*grid2[point];
                }
                for (int c = 0; c < 3; c++)
                    u[c] += w01*sums[c];
            }
        for (int c = 0; c < 3; c++)
            velocity[3*i+c] += u[c];
    }
}
