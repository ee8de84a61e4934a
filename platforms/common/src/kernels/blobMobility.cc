/**
 * The blobs' generalised Rotne-Prager-Yamakawa mobility applied to forces, matrix-free: velocity =
 * M force per unit viscosity, for the Krylov solves of bodies coupled through the solvent
 * (CommonBlobMobility; the same M as RotnePragerYamakawa::mobilityBlock on the host, written out
 * again here in OpenMM's common dialect). Always in double precision, whatever the platform's
 * precision: conjugate gradients asked for a relative residual of 1e-10 cannot reach it with products
 * rounded to single precision.
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

KERNEL void multiplyBlobMobility(int numBlobs, int numParts, int tilesPerPart, GLOBAL const double* RESTRICT blob,
                                 GLOBAL const double* RESTRICT force, GLOBAL double* RESTRICT out) {
    LOCAL double tileBlob[4*BLOB_TILE];
    LOCAL double tileForce[3*BLOB_TILE];
    const int numTiles = (numBlobs+BLOB_TILE-1)/BLOB_TILE;
    // The same number of passes for every item of a group, so that all reach each barrier.
    for (int task = GROUP_ID; task < numTiles*numParts; task += NUM_GROUPS) {
        const int part = task/numTiles;
        const int i = (task-part*numTiles)*BLOB_TILE+LOCAL_ID;
        const bool active = (i < numBlobs);
        double xi = 0, yi = 0, zi = 0, ai = 1;
        if (active) {
            xi = blob[4*i];
            yi = blob[4*i+1];
            zi = blob[4*i+2];
            ai = blob[4*i+3];
        }
        double vx = 0, vy = 0, vz = 0;
        const int lastTile = min(numBlobs, (part+1)*tilesPerPart*BLOB_TILE);
        for (int tile = part*tilesPerPart*BLOB_TILE; tile < lastTile; tile += BLOB_TILE) {
            const int j = tile+LOCAL_ID;
            if (j < numBlobs) {
                for (int k = 0; k < 4; k++)
                    tileBlob[4*LOCAL_ID+k] = blob[4*j+k];
                for (int k = 0; k < 3; k++)
                    tileForce[3*LOCAL_ID+k] = force[3*j+k];
            }
            SYNC_THREADS;
            const int count = min(BLOB_TILE, numBlobs-tile);
            if (active) {
                for (int t = 0; t < count; t++) {
                    const double fx = tileForce[3*t], fy = tileForce[3*t+1], fz = tileForce[3*t+2];
                    const double aj = tileBlob[4*t+3];
                    if (tile+t == i) {
                        const double self = 1/(6*BLOB_PI*ai);
                        vx += self*fx;
                        vy += self*fy;
                        vz += self*fz;
                        continue;
                    }
                    const double dx = tileBlob[4*t]-xi, dy = tileBlob[4*t+1]-yi, dz = tileBlob[4*t+2]-zi;
                    const double r2 = dx*dx+dy*dy+dz*dz;
                    const double r = sqrt(r2);
                    double isotropic, dyadic;  // the block is isotropic I + dyadic d d^T / r^2
                    if (r > ai+aj) {
                        const double sigma2 = (ai*ai+aj*aj)/r2;
                        isotropic = (1+sigma2/3)/(8*BLOB_PI*r);
                        dyadic = (1-sigma2)/(8*BLOB_PI*r);
                    }
                    else if (r > fabs(ai-aj)) {
                        const double d2 = (ai-aj)*(ai-aj);
                        const double r3 = r2*r;
                        const double scale = 1/(6*BLOB_PI*ai*aj*32*r3);
                        const double s = d2+3*r2;
                        const double q = d2-r2;
                        isotropic = (16*r3*(ai+aj)-s*s)*scale;
                        dyadic = 3*q*q*scale;
                    }
                    else {
                        // One inside the other (r = 0 with unequal radii included): the smaller moves with the larger.
                        isotropic = 1/(6*BLOB_PI*fmax(ai, aj));
                        dyadic = 0;
                    }
                    const double projection = (r2 > 0 ? dyadic*(dx*fx+dy*fy+dz*fz)/r2 : 0.0);
                    vx += isotropic*fx+projection*dx;
                    vy += isotropic*fy+projection*dy;
                    vz += isotropic*fz+projection*dz;
                }
            }
            SYNC_THREADS;
        }
        if (active) {
            GLOBAL double* partOut = out+3*numBlobs*part;
            partOut[3*i] = vx;
            partOut[3*i+1] = vy;
            partOut[3*i+2] = vz;
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
