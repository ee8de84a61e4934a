"""The boomerang suspension of the hydrodynamic-interaction benchmarks (issues 60 and 61), the scene
that the project and its peer RigidMultiblobsWall are timed on side by side.

A boomerang is the anchors' (Sprinkle et al., JCP 147, 244103 (2017)): 15 blobs 0.3 um apart, two
arms of 7 along x and y meeting at a corner blob, blob radius 0.265*sqrt(1.5) um; its reference point
(where its velocity is taken and torques about) is the corner blob. N bodies, randomly placed and
turned, none overlapping another (blobs of different bodies at least two radii apart), fill a cube
of side L to a volume fraction of 5%: N * V / L^3 = 0.05, V the volume of the union of a body's
blob spheres. Every blob sphere lies inside the cube [0, L]^3: the same configuration serves in open
space and above a no-slip wall at z = 0 (each blob's centre at least a radius above it).
Deterministic from the seed (numpy's PCG64). Lengths in um.

    python benchmarks/hydrodynamics/boomerang_suspension.py --out build-peers/boomerang_suspension.json [--sizes 16 64 256 1024] [--seed 1]

writes {"scenes": [scene, ...], ...}; each scene (scene()) holds the bodies' locations and
orientations (quaternions, scalar first), their blobs' positions and radii, and each body's range
of blobs.
"""
import argparse
import json
import math
import os

import numpy as np

BLOB_SPACING_UM = 0.3
BLOB_RADIUS_UM = 0.265*math.sqrt(1.5)
VOLUME_FRACTION = 0.05
SIZES = (16, 64, 256, 1024)
# Placement tries per body before the generator gives up (at 5% none is near).
MAX_TRIES = 10000


def boomerang_blobs():
    """The 15 blob centres in the body frame (um), corner blob at the origin: the arm along x from
    its tip (2.1, 0, 0) to the corner, then the arm along y to its tip (0, 2.1, 0)."""
    steps = BLOB_SPACING_UM*np.arange(7, -1, -1)
    arm_x = np.column_stack([steps, np.zeros(8), np.zeros(8)])
    arm_y = np.column_stack([np.zeros(7), steps[-2::-1], np.zeros(7)])
    return np.vstack([arm_x, arm_y])


def union_volume(centres, radius, spacing=0.002):
    """Volume of the union of equal spheres whose centres lie in the plane z = 0: the integral over
    the plane of twice the union's half-height, max_k sqrt(a^2 - |p - c_k|^2), by the midpoint rule
    on a square grid (relative error about 1e-4 at the default spacing)."""
    low = centres[:, :2].min(axis=0)-radius
    high = centres[:, :2].max(axis=0)+radius
    xs = np.arange(low[0]+spacing/2, high[0], spacing)
    ys = np.arange(low[1]+spacing/2, high[1], spacing)
    x, y = np.meshgrid(xs, ys, indexing='ij')
    height = np.zeros_like(x)
    for c in centres:
        np.maximum(height, radius**2-(x-c[0])**2-(y-c[1])**2, out=height)
    return 2*np.sqrt(height).sum()*spacing**2


def rotation_matrix(q):
    """The rotation of a unit quaternion (s, p1, p2, p3), scalar first (RigidMultiblobsWall's order)."""
    s, p = q[0], np.asarray(q[1:])
    return 2*(np.outer(p, p)+s*np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])) \
        + (2*s*s-1)*np.eye(3)


def random_quaternion(rng):
    """A uniformly distributed rotation, its scalar part made non-negative."""
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def place_bodies(num_bodies, side, rng, reference=None, radius=BLOB_RADIUS_UM):
    """Random sequential addition in the cube [0, side]^3: (locations, quaternions, blobs per body)."""
    reference = boomerang_blobs() if reference is None else reference
    locations, quaternions, placed = [], [], []
    for body in range(num_bodies):
        for _ in range(MAX_TRIES):
            q = random_quaternion(rng)
            arm = reference@rotation_matrix(q).T
            lo, hi = radius-arm.min(axis=0), side-radius-arm.max(axis=0)
            if np.any(hi <= lo):
                raise ValueError(f'a body does not fit in a cube of side {side} um')
            location = lo+(hi-lo)*rng.random(3)
            blobs = arm+location
            if all(_separated(blobs, other, 2*radius) for other in placed):
                break
        else:
            raise RuntimeError(f'body {body}: no free place after {MAX_TRIES} tries (volume fraction too high?)')
        locations.append(location)
        quaternions.append(q)
        placed.append(blobs)
    return np.array(locations), np.array(quaternions), placed


def _separated(blobs, other, distance):
    """Whether every blob of one body is at least `distance` from every blob of another (a quick
    reject by the bodies' bounding boxes first)."""
    if np.any(blobs.min(axis=0) > other.max(axis=0)+distance) or np.any(other.min(axis=0) > blobs.max(axis=0)+distance):
        return True
    gaps = np.linalg.norm(blobs[:, None, :]-other[None, :, :], axis=2)
    return gaps.min() >= distance


def scene(num_bodies, seed=1, volume_fraction=VOLUME_FRACTION):
    """The suspension of num_bodies boomerangs (a dict of plain lists, lengths in um)."""
    reference = boomerang_blobs()
    volume = union_volume(reference, BLOB_RADIUS_UM)
    side = (num_bodies*volume/volume_fraction)**(1/3)
    rng = np.random.default_rng([seed, num_bodies])
    locations, quaternions, blobs = place_bodies(num_bodies, side, rng, reference)
    blobs_per_body = len(reference)
    return {
        'num_bodies': num_bodies,
        'seed': seed,
        'volume_fraction': volume_fraction,
        'body_volume_um3': volume,
        'box_side_um': side,
        'blob_radius_um': BLOB_RADIUS_UM,
        'body_frame_blobs_um': reference.tolist(),
        'locations_um': locations.tolist(),
        'quaternions': quaternions.tolist(),
        'blob_positions_um': np.vstack(blobs).tolist(),
        'blob_radii_um': [BLOB_RADIUS_UM]*(num_bodies*blobs_per_body),
        'body_blob_offsets': list(range(0, num_bodies*blobs_per_body+1, blobs_per_body)),
    }


def coupled_bodies(scene, scale=1000.0):
    """The scene's bodies as rigidlangevin.hydrodynamics.coupledResistance takes them: (blob
    positions, blob radii, reference point) per body, lengths times scale (1000: in nm; 1: in um)."""
    positions, radii = scale*np.array(scene['blob_positions_um']), scale*np.array(scene['blob_radii_um'])
    offsets = scene['body_blob_offsets']
    return [(positions[start:end], radii[start:end], scale*np.array(origin))
            for start, end, origin in zip(offsets[:-1], offsets[1:], scene['locations_um'])]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--out', required=True, help='the JSON file to write')
    parser.add_argument('--sizes', type=int, nargs='+', default=list(SIZES), help='numbers of bodies')
    parser.add_argument('--seed', type=int, default=1)
    args = parser.parse_args()
    scenes = [scene(n, args.seed) for n in args.sizes]
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, 'w', encoding='utf-8') as f:
        json.dump({'description': 'boomerang suspensions (benchmarks/hydrodynamics/boomerang_suspension.py); lengths in um',
                   'wall': 'a no-slip wall at z = 0 where a benchmark puts one', 'scenes': scenes}, f)
    for s in scenes:
        print(f"{s['num_bodies']} bodies: cube side {s['box_side_um']:.3f} um, body volume {s['body_volume_um3']:.4f} um^3")


if __name__ == '__main__':
    main()
