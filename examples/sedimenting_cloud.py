"""A cloud of spheres settling in water, with and without hydrodynamic interactions.

N spheres of radius a, placed at random (not overlapping) in a spherical cloud of radius R, each
pulled down by the same force F, at 300 K in water (0.89 cP), BAOAB with the coupled friction
step (RigidLangevinIntegrator.setHydrodynamicInteractions). Alone, a sphere settles at Stokes's
U0 = F/(6 pi eta a); without interactions every sphere does, however many there are. With them
each sphere is carried by the flow the others make, and the cloud falls several times faster: for
point forces in a uniform spherical cloud the mean speed is U0 (1 + 6/5 (N-1) a/R) (Oseen
stokeslets averaged over the cloud: <1/r> = 6/(5R) between two points of a ball; Nitsche &
Batchelor, J. Fluid Mech. 340, 161 (1997)), which a user measures here as the centroid's speed.

The measured speed (mean of the centroid's velocity over the run, with its block standard error)
is compared with the exact expectation for the same trajectory: the spheres' RPY mobility from
rigidlangevin.hydrodynamics at each sampled configuration, times F, averaged over the samples.

    python examples/sedimenting_cloud.py [--quick] [--spheres 100] [--platform CPU] [--out DIR]

Every platform has hydrodynamic interactions (--platform Reference, CPU, OpenCL or CUDA).

Writes DIR/table.md and DIR/cloud.png (default out/sedimenting_cloud, outside version control) and
prints the table. The committed results are the full run written there on purpose:

    python examples/sedimenting_cloud.py --out examples/results/sedimenting_cloud
"""
import sys
import argparse
import math
import os

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl
import rigidlangevin.hydrodynamics as hydro
from rigidlangevin import _units
from rigidlangevin.statistics import block_error

RADIUS = 0.5            # nm
MASS = 100.0            # amu
CLOUD_FRACTION = 0.02   # N a^3 / R^3
STOKES_SPEED = 0.5      # nm/ps: U0, which sets F
TEMPERATURE = 300.0
VISCOSITY = 0.89*rl.centipoise
STEP = 0.004            # ps
SAMPLE_STEPS = 10
RELAX_PS = 0.2          # the velocities come to their settling values within about 5/gamma = 0.1 ps


def cloud(num_spheres, seed):
    """Centres of num_spheres non-overlapping spheres (at least 2.2 a apart) uniform in a ball, and its radius."""
    cloud_radius = RADIUS*(num_spheres/CLOUD_FRACTION)**(1/3)
    rng = np.random.default_rng(seed)
    centres = []
    while len(centres) < num_spheres:
        p = rng.uniform(-cloud_radius, cloud_radius, 3)
        if np.linalg.norm(p) <= cloud_radius-RADIUS and all(np.linalg.norm(p-q) >= 2.2*RADIUS for q in centres):
            centres.append(p)
    return np.array(centres), cloud_radius


def predicted_speed(positions, force, viscosity):
    """The spheres' mean downward speed (nm/ps) at these centres: their RPY mobility (one blob each,
    translation only: the translational blocks of the coupled resistance are M^-1) times the force."""
    n = len(positions)
    resistance = hydro.coupledResistance([([p], [RADIUS], p) for p in positions])
    translation = np.concatenate([np.arange(6*i, 6*i+3) for i in range(n)])
    forces = np.tile([0.0, 0.0, -force], n)
    velocities = np.linalg.solve(resistance[np.ix_(translation, translation)], forces)/viscosity
    return -velocities[2::3].mean()


def run(num_spheres, interactions, picoseconds, seed, platform='CPU'):
    """The centroid's speed (mean, block standard error), the prediction's mean, and the centroid's height against time."""
    centres, _ = cloud(num_spheres, seed)
    viscosity = _units.viscosity_value(VISCOSITY)
    force = STOKES_SPEED*6*math.pi*viscosity*RADIUS
    system = mm.System()
    pull = mm.CustomExternalForce(f'{force}*z')
    system.addForce(pull)
    integrator = rl.RigidLangevinIntegrator(TEMPERATURE*unit.kelvin, VISCOSITY, STEP*unit.picoseconds)
    integrator.setScheme(rl.RigidLangevinIntegrator.BAOAB)
    integrator.setHydrodynamicInteractions(interactions)
    integrator.setRandomNumberSeed(seed)
    for i in range(num_spheres):
        system.addParticle(MASS)
        pull.addParticle(i)
        integrator.setParticleRadius(i, RADIUS*unit.nanometer)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform))
    context.setPositions([mm.Vec3(*p) for p in centres])
    context.setVelocitiesToTemperature(TEMPERATURE*unit.kelvin, seed)
    integrator.step(int(round(RELAX_PS/STEP)))
    times, heights, predictions = [], [], []
    for k in range(int(round(picoseconds/(STEP*SAMPLE_STEPS)))+1):
        if k > 0:
            integrator.step(SAMPLE_STEPS)
        positions = context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(unit.nanometer)
        times.append(k*SAMPLE_STEPS*STEP)
        heights.append(positions[:, 2].mean())
        if interactions and k < int(round(picoseconds/(STEP*SAMPLE_STEPS))):
            predictions.append(predicted_speed(positions, force, viscosity))
    speeds = -np.diff(heights)/(SAMPLE_STEPS*STEP)
    expected = np.mean(predictions) if interactions else STOKES_SPEED
    return speeds.mean(), block_error(speeds), expected, np.array(times), np.array(heights)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--quick', action='store_true', help='30 spheres, 1 ps (seconds)')
    parser.add_argument('--spheres', type=int, help='spheres in the cloud (default 100, 30 with --quick)')
    parser.add_argument('--picoseconds', type=float, help='the measured run (default 4, 1 with --quick)')
    parser.add_argument('--seed', type=int, default=3)
    parser.add_argument('--platform', default='CPU', help='the OpenMM platform (default CPU)')
    parser.add_argument('--out', help='output folder (default out/sedimenting_cloud; the committed results: examples/results/sedimenting_cloud)')
    args = parser.parse_args()
    num_spheres = args.spheres or (30 if args.quick else 100)
    picoseconds = args.picoseconds or (1.0 if args.quick else 4.0)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = args.out or os.path.join(root, 'out', 'sedimenting_cloud')
    os.makedirs(out, exist_ok=True)
    _, cloud_radius = cloud(num_spheres, args.seed)
    oseen = 1+6/5*(num_spheres-1)*RADIUS/cloud_radius

    results = {}
    for interactions in (False, True):
        results[interactions] = run(num_spheres, interactions, picoseconds, args.seed, args.platform)
    lines = [f'# A settling cloud: {num_spheres} spheres of radius {RADIUS} nm in a ball of radius {cloud_radius:.2f} nm, {picoseconds:g} ps at '
             f'{TEMPERATURE:g} K, 0.89 cP; speeds in units of Stokes\'s U0 = {STOKES_SPEED} nm/ps', '',
             '| interactions | measured speed / U0 | expected / U0 | (measured - expected) / standard error |', '|---|---|---|---|']
    for interactions, label in ((False, 'off'), (True, 'on')):
        speed, error, expected, _, _ = results[interactions]
        lines.append(f'| {label} | {speed/STOKES_SPEED:.4f} ± {error/STOKES_SPEED:.4f} | {expected/STOKES_SPEED:.4f} | {(speed-expected)/error:+.2f} |')
    lines += ['', f'Expected: without interactions U0 exactly; with them the spheres\' RPY mobility times F at each sampled configuration, '
                  f'averaged. For point forces in a uniform cloud of this size, 1 + 6/5 (N-1) a/R = {oseen:.3f}.']
    text = '\n'.join(lines)+'\n'
    with open(os.path.join(out, 'table.md'), 'w', encoding='utf-8') as f:
        f.write(text)
    print(text)

    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for interactions, label in ((False, 'without interactions'), (True, 'with interactions')):
        speed, error, expected, times, heights = results[interactions]
        ax.plot(times, heights-heights[0], label=f'{label}: {speed/STOKES_SPEED:.2f} ± {error/STOKES_SPEED:.2f} U0')
        ax.plot(times, -expected*times, 'k:', lw=1)
    ax.set_xlabel('time (ps)')
    ax.set_ylabel("the cloud's centroid: height (nm)")
    ax.set_title(f'{num_spheres} spheres settling (dotted: expected)')
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, 'cloud.png'), dpi=120)
    print(f'(written to {out}/table.md and cloud.png)')


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
