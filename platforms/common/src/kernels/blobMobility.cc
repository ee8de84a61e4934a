/**
 * The blobs' generalised Rotne-Prager-Yamakawa mobility applied to forces, matrix-free: velocity =
 * M force per unit viscosity, for the Krylov solves of bodies coupled through the solvent
 * (CommonBlobMobility; the same M as RotnePragerYamakawa::mobilityBlock on the host, written out
 * again here in OpenMM's common dialect). Always in double precision, whatever the platform's
 * precision: conjugate gradients asked for a relative residual of 1e-10 cannot reach it with products
 * rounded to single precision.
 *
 * One work item per blob i sums over all blobs j, which pass through local memory a tile of
 * BLOB_TILE at a time (each is read from global memory once per work group, not once per item).
 * blob: x, y, z, radius per blob; force and velocity: 3 per blob.
 */
#if defined(cl_khr_fp64)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#define BLOB_PI 3.141592653589793

KERNEL void multiplyBlobMobility(int numBlobs, GLOBAL const double* RESTRICT blob, GLOBAL const double* RESTRICT force,
                                 GLOBAL double* RESTRICT velocity) {
    LOCAL double tileBlob[4*BLOB_TILE];
    LOCAL double tileForce[3*BLOB_TILE];
    // The same number of passes for every item of a group, so that all reach each barrier.
    for (int first = GROUP_ID*BLOB_TILE; first < numBlobs; first += NUM_GROUPS*BLOB_TILE) {
        const int i = first+LOCAL_ID;
        const bool active = (i < numBlobs);
        double xi = 0, yi = 0, zi = 0, ai = 1;
        if (active) {
            xi = blob[4*i];
            yi = blob[4*i+1];
            zi = blob[4*i+2];
            ai = blob[4*i+3];
        }
        double vx = 0, vy = 0, vz = 0;
        for (int tile = 0; tile < numBlobs; tile += BLOB_TILE) {
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
            velocity[3*i] = vx;
            velocity[3*i+1] = vy;
            velocity[3*i+2] = vz;
        }
    }
}
