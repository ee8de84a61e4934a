"""What coupling bodies through the solvent costs (RigidLangevinIntegrator.setHydrodynamicInteractions).

Rigid bodies of 1, 4 or 12 blobs (a sphere, a tetrahedron, an icosahedron of spheres of radius
0.1 nm), randomly turned on a cubic lattice 1 nm apart, open boundaries, no forces, at 300 K in
water (0.89 cP), BAOAB with a 2 fs step, on the CPU platform (or --platform). Each size is timed without
interactions and with them, dense (Cholesky) where that fits and matrix-free (Krylov), in
alternating pairs of blocks in one run (benchmark_utils.paired_times; the solver chosen with
RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER before each block).

    python benchmarks/platforms/hydrodynamic_interactions.py [--quick | --large] [--name hydrodynamic_interactions]
        [--platform CPU] [--precision mixed] [--max-dense-blobs 1200] [--sizes N ...]

--large times 1000, 3000 and 10000 single spheres (Krylov with matrix-free products against no
interactions; two pairs, two steps for the iterations; about 20 minutes on 2 cores) into
results/hydrodynamic_interactions_large.csv and .png; --sizes gives other numbers of spheres
(on a GPU, 10^5 and beyond).

On OpenCL and CUDA (--platform) the Krylov solves' products run on the device (tiled, matrix-free,
double precision) and the rest of the coupled step on the host; the dense step is the host's.
--max-dense-blobs bounds the systems given a dense step (its Cholesky's cost grows as the cube).
The table is written again after each system, so that a run cut short keeps what it measured;
--replot draws the plot of such a table.

Writes results/<name>.csv and .png: ms per step (mean of the pairs +- its standard error), the
ratio to the same bodies without interactions, the simulated time per day, and for Krylov the
iterations of its three solves (RigidLangevinIntegrator.getKrylovIterations(): the noise's Lanczos,
the noise's and the friction's conjugate gradients; the noise's are 0 since it is taken by one
preconditioned Lanczos, and the committed tables' figures predate that), mean and range over
ITERATION_STEPS steps after the timing.
"""
import sys
import argparse
import csv
import os
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl
import benchmark_utils
from benchmark_utils import mean_and_error, paired_times, platform_properties, platform_status, running_context, save_plot, write_table

STEP_PS = 0.002
SHAPES = {
    1: np.zeros((1, 3)),
    4: 0.15*np.array([(1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1)], float),
    12: 0.2*np.array([(0, s1, s2*(1+5**0.5)/2) for s1 in (-1, 1) for s2 in (-1, 1)]
                     + [(s1, s2*(1+5**0.5)/2, 0) for s1 in (-1, 1) for s2 in (-1, 1)]
                     + [(s2*(1+5**0.5)/2, 0, s1) for s1 in (-1, 1) for s2 in (-1, 1)], float),
}
# Steps whose Krylov iterations are recorded.
ITERATION_STEPS = 5
# Dense coupled steps beyond this many blobs take seconds each (the Cholesky's cost grows as the cube).
MAX_DENSE_BLOBS = 1200


def scene(num_bodies, blobs_per_body, seed=1):
    """(System, integrator factory, positions): bodies of the shape on a cubic lattice 1 nm apart."""
    shape = SHAPES[blobs_per_body]
    side = int(np.ceil(num_bodies**(1/3)))
    rng = np.random.default_rng(seed)
    system = mm.System()
    positions, bodies = [], []
    for b in range(num_bodies):
        centre = np.array([b % side, (b//side) % side, b//side**2], float)
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        w, x, y, z = q
        rotation = np.array([[1-2*(y*y+z*z), 2*(x*y-w*z), 2*(x*z+w*y)], [2*(x*y+w*z), 1-2*(x*x+z*z), 2*(y*z-w*x)],
                             [2*(x*z-w*y), 2*(y*z+w*x), 1-2*(x*x+y*y)]])
        particles = []
        for p in shape:
            particles.append(system.addParticle(10.0))
            positions.append(mm.Vec3(*(centre+rotation@p)))
        bodies.append(particles)

    def integrator(interactions):
        result = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.89*rl.centipoise, STEP_PS*unit.picoseconds)
        result.setScheme(rl.RigidLangevinIntegrator.BAOAB)
        result.setHydrodynamicInteractions(interactions)
        for particles in bodies:
            result.addRigidBody(particles)
            for p in particles:
                result.setParticleRadius(p, 0.1*unit.nanometer)
        return result
    return system, integrator, positions


def solver(name):
    def set_environment():
        os.environ['RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER'] = name
    return set_environment


def measure(num_bodies, blobs_per_body, pairs, iteration_steps=ITERATION_STEPS, probe_steps=2, platform='CPU', properties=None,
            max_dense_blobs=MAX_DENSE_BLOBS):
    """Rows of the table for one system: each mode's ms per step and its ratio to no interactions.
    probe_steps: the warm-up steps of each Context, and the steps that size its blocks."""
    system, make_integrator, positions = scene(num_bodies, blobs_per_body)
    blobs = num_bodies*blobs_per_body
    modes = ['off']+(['dense'] if blobs <= max_dense_blobs else [])+['krylov']
    contexts, prepare = {}, {}
    for mode in modes:
        integrator = make_integrator(mode != 'off')
        if mode != 'off':
            prepare[mode] = solver(mode)
            prepare[mode]()
        contexts[mode] = (integrator, running_context(system, integrator, positions, platform, properties or {}, warmup_steps=probe_steps))
    # Blocks of about a tenth of a second or more each (the coupled steps cost up to seconds).
    steps = {}
    for mode, (integrator, context) in contexts.items():
        if mode in prepare:
            prepare[mode]()
        start = time.perf_counter()
        integrator.step(probe_steps)
        per_step = (time.perf_counter()-start)/probe_steps
        steps[mode] = int(np.clip(0.1/per_step, 1, 20000))
    times = paired_times(contexts, steps, pairs=pairs, prepare=prepare)
    integrator, context = contexts['krylov']
    prepare['krylov']()
    iterations = []
    for _ in range(iteration_steps):
        integrator.step(1)
        iterations.append(integrator.getKrylovIterations())
    iterations = np.array(iterations)
    os.environ.pop('RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER', None)
    rows = []
    for mode in modes:
        mean, error = mean_and_error(np.array(times[mode])*1e3)
        ratio, ratio_error = mean_and_error(np.array(times[mode])/np.array(times['off']))
        rows.append({'platform': platform, 'bodies': num_bodies, 'blobs_per_body': blobs_per_body, 'blobs': blobs, 'solver': mode,
                     'ms_per_step': f'{mean:.4g}', 'ms_error': f'{error:.2g}', 'ratio_to_off': f'{ratio:.4g}', 'ratio_error': f'{ratio_error:.2g}',
                     'ns_per_day': f'{STEP_PS*1e-3*86400/(mean*1e-3):.4g}'})
        for k, solve in enumerate(('lanczos', 'noise_cg', 'friction_cg')):
            rows[-1][solve] = (f'{iterations[:, k].mean():.3g} ({iterations[:, k].min()}-{iterations[:, k].max()})' if mode == 'krylov' else '')
    return rows


COLUMNS = ['platform', 'bodies', 'blobs_per_body', 'blobs', 'solver', 'ms_per_step', 'ms_error', 'ratio_to_off', 'ratio_error',
           'ns_per_day', 'lanczos', 'noise_cg', 'friction_cg']


def plot(rows, name):
    """results/<name>.png: ms per step against blobs, each solver (rows as measure() gives them, or read back from the table)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for mode, marker in (('off', 'o'), ('dense', 's'), ('krylov', '^')):
        points = sorted((int(r['blobs']), float(r['ms_per_step']), float(r['ms_error'])) for r in rows if r['solver'] == mode)
        if points:
            x, y, e = zip(*points)
            ax.errorbar(x, y, yerr=e, marker=marker, label={'off': 'without interactions', 'dense': 'dense (Cholesky)', 'krylov': 'Krylov'}[mode])
    ax.set_xscale('log')
    ax.set_yscale('log')
    ax.set_xlabel('blobs (all bodies)')
    ax.set_ylabel(f"ms per step ({rows[0].get('platform') or 'CPU'} platform)")
    ax.set_title('Hydrodynamic interactions: cost per step')
    ax.legend()
    save_plot(fig, name)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sizes = parser.add_mutually_exclusive_group()
    sizes.add_argument('--quick', action='store_true', help='two small systems, two pairs (seconds)')
    sizes.add_argument('--large', action='store_true', help='1000 to 10000 single spheres, Krylov only (about 20 minutes)')
    parser.add_argument('--sizes', type=int, nargs='+', help='with --large: the numbers of single spheres')
    parser.add_argument('--name', default=None, help='results/<name>.csv and .png (e.g. gpu_h200/hydrodynamic_interactions on a GPU machine)')
    parser.add_argument('--platform', default='CPU', choices=('Reference', 'CPU', 'OpenCL', 'CUDA'))
    parser.add_argument('--precision', default='mixed', choices=('single', 'mixed', 'double'), help='on OpenCL and CUDA')
    parser.add_argument('--max-dense-blobs', type=int, default=MAX_DENSE_BLOBS, help='largest system given a dense step')
    parser.add_argument('--replot', action='store_true', help='only draw results/<name>.png again from results/<name>.csv')
    args = parser.parse_args()
    args.name = args.name or ('hydrodynamic_interactions_large' if args.large else 'hydrodynamic_interactions')
    if args.replot:
        with open(os.path.join(benchmark_utils.RESULTS, args.name+'.csv'), encoding='utf-8') as f:
            plot(list(csv.DictReader(f)), args.name)
        return
    status = platform_status(args.platform)
    if status is not None:
        parser.error(f'{args.platform}: {status}')
    options = {'platform': args.platform, 'max_dense_blobs': args.max_dense_blobs,
               'properties': platform_properties(args.platform, args.precision)}
    if args.quick:
        systems, pairs = [(5, 4), (10, 1)], 2
    elif args.large:
        systems, pairs = [(n, 1) for n in (args.sizes or (1000, 3000, 10000))], 2
        options.update(iteration_steps=2, probe_steps=1)
    else:
        systems = [(n, 4) for n in (10, 30, 100, 300, 600)]+[(50, 1), (50, 12), (300, 1)]
        pairs = 3
    rows = []
    for num_bodies, blobs_per_body in systems:
        print(f'{num_bodies} bodies of {blobs_per_body} blob(s)...', flush=True)
        rows += measure(num_bodies, blobs_per_body, pairs, **options)
        write_table(args.name, COLUMNS, rows)

    plot(rows, args.name)

if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
