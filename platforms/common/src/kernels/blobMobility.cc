/**
 * The blobs' generalised Rotne-Prager-Yamakawa mobility applied to forces, matrix-free: velocity =
 * M force per unit viscosity, for the Krylov solves of bodies coupled through the solvent
 * (CommonBlobMobility; the same M as RotnePragerYamakawa::mobilityBlock on the host, written out
 * again here in OpenMM's common dialect).
 *
 * The pair terms are in PAIR_REAL: double, or float where the solves' tolerance allows it
 * (CommonBlobMobility::setTolerance(), as the host's TiledBlobProduct). In float, lengths are in
 * units of lengthScale (a power of two near the largest radius) and forces in units of forceScale
 * (one above the largest component), so that every term lies well inside float's range; each
 * position is held as two floats, its rounding and what that left (high + low), so that a
 * difference of positions, (high_j - high_i) + (low_j - low_i), is good to float's precision
 * relative to the distance, not to the distance from the origin, without a double operation per
 * pair (GPUs without fast double precision); each tile's terms are summed in PAIR_REAL and the
 * tiles' sums in double, and the row is scaled back (times forceScale/lengthScale: M goes as one
 * over length) at the end. With the scales 1 and PAIR_REAL double (the low parts zero) it is the
 * double product.
 *
 * One work item per blob i sums over the blobs j of one part of the tiles, which pass through local
 * memory a tile of BLOB_TILE at a time (each is read from global memory once per work group, not
 * once per item). A work group is one (tile of i, part of j) task: with numParts parts the i blobs'
 * sums are split numParts ways, so that a few thousand blobs still fill a GPU (one item per blob
 * left it mostly idle: an H200 reached 1.5e9 blob pairs a second at 1e3 blobs). Part p writes its
 * sums to out[3*numBlobs*p...]; sumBlobMobilityParts adds the parts in order (the same sum on every
 * run), or with one part out is the velocity itself.
 * blob: x, y, z, radius per blob; force: 3 per blob; out: 3 per blob per part.
 */
#if defined(cl_khr_fp64)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#define BLOB_PI 3.141592653589793

#if PAIR_SINGLE
typedef float pair_real;
#else
typedef double pair_real;
#endif

/** The (scaled) pair block's isotropic and dyadic parts, mu = isotropic I + dyadic d d^T / r^2. */
DEVICE void blobPairBlock(pair_real r2, pair_real ai, pair_real aj, pair_real* isotropic, pair_real* dyadic) {
    const pair_real r = sqrt(r2);
    const pair_real pi = (pair_real) BLOB_PI;
    if (r > ai+aj) {
        const pair_real sigma2 = (ai*ai+aj*aj)/r2;
        *isotropic = (1+sigma2/3)/(8*pi*r);
        *dyadic = (1-sigma2)/(8*pi*r);
    }
    else if (r > fabs(ai-aj) && r2 > (pair_real) 1e-24*ai*aj) {
        const pair_real d2 = (ai-aj)*(ai-aj);
        const pair_real r3 = r2*r;
        const pair_real scale = 1/(6*pi*ai*aj*32*r3);
        const pair_real s = d2+3*r2;
        const pair_real q = d2-r2;
        *isotropic = (16*r3*(ai+aj)-s*s)*scale;
        *dyadic = 3*q*q*scale;
    }
    else {
        // One inside the other (r = 0 with unequal radii included, and equal radii at r -> 0, the
        // overlap's limit): the smaller moves with the larger.
        *isotropic = 1/(6*pi*fmax(ai, aj));
        *dyadic = 0;
    }
}

/** What rounding x to PAIR_REAL left (zero in double): x = (pair_real) x + lowPart(x) to float's precision squared. */
DEVICE pair_real lowPart(double x) {
    return (pair_real) (x-(pair_real) x);
}

KERNEL void multiplyBlobMobility(int numBlobs, int numParts, int tilesPerPart, double lengthScale, double forceScale,
                                 GLOBAL const double* RESTRICT blob, GLOBAL const double* RESTRICT force, GLOBAL double* RESTRICT out) {
    LOCAL pair_real tileHigh[3*BLOB_TILE];
    LOCAL pair_real tileLow[3*BLOB_TILE];
    LOCAL pair_real tileRadius[BLOB_TILE];
    LOCAL pair_real tileForce[3*BLOB_TILE];
    const int numTiles = (numBlobs+BLOB_TILE-1)/BLOB_TILE;
    const double perLength = 1/lengthScale, perForce = 1/forceScale;
    // The same number of passes for every item of a group, so that all reach each barrier.
    for (int task = GROUP_ID; task < numTiles*numParts; task += NUM_GROUPS) {
        const int part = task/numTiles;
        const int i = (task-part*numTiles)*BLOB_TILE+LOCAL_ID;
        const bool active = (i < numBlobs);
        pair_real high[3] = {0, 0, 0}, low[3] = {0, 0, 0}, ai = 1;
        if (active) {
            for (int k = 0; k < 3; k++) {
                high[k] = (pair_real) (blob[4*i+k]*perLength);
                low[k] = lowPart(blob[4*i+k]*perLength);
            }
            ai = (pair_real) (blob[4*i+3]*perLength);
        }
        double vx = 0, vy = 0, vz = 0;
        const int lastTile = min(numBlobs, (part+1)*tilesPerPart*BLOB_TILE);
        for (int tile = part*tilesPerPart*BLOB_TILE; tile < lastTile; tile += BLOB_TILE) {
            const int j = tile+LOCAL_ID;
            if (j < numBlobs) {
                for (int k = 0; k < 3; k++) {
                    tileHigh[3*LOCAL_ID+k] = (pair_real) (blob[4*j+k]*perLength);
                    tileLow[3*LOCAL_ID+k] = lowPart(blob[4*j+k]*perLength);
                    tileForce[3*LOCAL_ID+k] = (pair_real) (force[3*j+k]*perForce);
                }
                tileRadius[LOCAL_ID] = (pair_real) (blob[4*j+3]*perLength);
            }
            SYNC_THREADS;
            const int count = min(BLOB_TILE, numBlobs-tile);
            if (active) {
                pair_real tx = 0, ty = 0, tz = 0;  // this tile's sum
                for (int t = 0; t < count; t++) {
                    const pair_real fx = tileForce[3*t], fy = tileForce[3*t+1], fz = tileForce[3*t+2];
                    if (tile+t == i) {
                        const pair_real self = 1/(6*(pair_real) BLOB_PI*ai);
                        tx += self*fx;
                        ty += self*fy;
                        tz += self*fz;
                        continue;
                    }
                    const pair_real dx = (tileHigh[3*t]-high[0])+(tileLow[3*t]-low[0]);
                    const pair_real dy = (tileHigh[3*t+1]-high[1])+(tileLow[3*t+1]-low[1]);
                    const pair_real dz = (tileHigh[3*t+2]-high[2])+(tileLow[3*t+2]-low[2]);
                    const pair_real r2 = dx*dx+dy*dy+dz*dz;
                    pair_real isotropic, dyadic;
                    blobPairBlock(r2, ai, tileRadius[t], &isotropic, &dyadic);
                    const pair_real projection = (r2 > 0 ? dyadic*(dx*fx+dy*fy+dz*fz)/r2 : (pair_real) 0);
                    tx += isotropic*fx+projection*dx;
                    ty += isotropic*fy+projection*dy;
                    tz += isotropic*fz+projection*dz;
                }
                vx += tx;
                vy += ty;
                vz += tz;
            }
            SYNC_THREADS;
        }
        if (active) {
            const double back = forceScale*perLength;
            GLOBAL double* partOut = out+3*numBlobs*part;
            partOut[3*i] = vx*back;
            partOut[3*i+1] = vy*back;
            partOut[3*i+2] = vz*back;
        }
    }
}

/** velocity = the sum of multiplyBlobMobility's numParts parts, in order. */
KERNEL void sumBlobMobilityParts(int numBlobs, int numParts, GLOBAL const double* RESTRICT parts, GLOBAL double* RESTRICT velocity) {
    for (int k = GLOBAL_ID; k < 3*numBlobs; k += GLOBAL_SIZE) {
        double sum = 0;
        for (int part = 0; part < numParts; part++)
            sum += parts[3*numBlobs*part+k];
        velocity[k] = sum;
    }
}
