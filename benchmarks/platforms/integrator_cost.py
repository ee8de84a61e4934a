"""Cost of RigidLangevinIntegrator alone: force-free rigid water-shaped bodies (3 particles each),
the default ExactFlow scheme at the viscosity of water, from 1e3 to 1e6 bodies, on every platform.
Reports bodies*steps per second and time per step; the cost must grow linearly with the number of
bodies (constant bodies*steps/s once the fixed cost of a step is amortised). For scale, the same
particles with LangevinMiddleIntegrator (each particle free, no constraints) are timed as well, in
alternating pairs of blocks with it: each row has the mean time per body-step over the pairs and
the ratio to LangevinMiddle pair by pair, each with its standard error.

    python benchmarks/platforms/integrator_cost.py [--sizes 1000 10000 100000 1000000] [--pairs 5]
"""
import sys
import argparse
import math

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl
from benchmark_utils import (GPU_PLATFORMS, calibrated_steps, mean_and_error, paired_times, platform_properties, platform_status,
                             running_context, save_plot, write_table)

WATER = np.array([[0, 0, 0], [0.09572, 0, 0], [-0.02399, 0.09266, 0]])
MASSES = (15.999, 1.008, 1.008)
RADII = (0.15, 0.1, 0.1)


def build(num_bodies, rigid):
    """num_bodies water-shaped bodies on a cubic lattice of spacing 0.4 nm, and the integrator."""
    system = mm.System()
    side = math.ceil(num_bodies**(1/3))
    b = np.arange(num_bodies)
    centers = 0.4*np.stack([b % side, (b//side) % side, b//side**2], axis=1)
    positions = (centers[:, None, :]+WATER[None, :, :]).reshape(-1, 3)
    for _ in range(num_bodies):
        for m in MASSES:
            system.addParticle(m)
    if rigid:
        integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.89*rl.centipoise, 2*unit.femtoseconds)
        for i in range(num_bodies):
            integrator.addRigidBody([3*i, 3*i+1, 3*i+2])
        for p in range(3*num_bodies):
            integrator.setParticleRadius(p, RADII[p % 3])
    else:
        integrator = mm.LangevinMiddleIntegrator(300*unit.kelvin, 1/unit.picosecond, 2*unit.femtoseconds)
    integrator.setRandomNumberSeed(1)
    return system, integrator, positions


def steps_for(num_bodies):
    """Steps to start calibrating from: ~1 s on a slow platform without minutes on a fast one. A
    multiple of four: OpenMM's common platforms make LangevinMiddleIntegrator's random numbers four
    steps at a time (IntegrationUtilities::prepareRandomNumbers), so that any other block length
    holds a varying share of that cost (on PoCL at 1e6 bodies blocks of three steps ranged from
    258 to 840 ms per step)."""
    return 4*max(1, min(50, int(0.75e6/num_bodies)))


def time_against_langevin_middle(n, platform, properties, pairs):
    """RigidLangevinIntegrator on n bodies and LangevinMiddleIntegrator on the same particles, both
    Contexts alive and timed in alternating pairs (benchmark_utils.paired_times): the row of the
    table, with the mean time per step of each, and the ratio pair by pair with its standard error."""
    contexts = {}
    for rigid in (True, False):
        system, integrator, positions = build(n, rigid)
        contexts['rigid' if rigid else 'middle'] = (integrator, running_context(system, integrator, positions, platform, properties, warmup_steps=2))
    steps = calibrated_steps(*contexts['rigid'], steps_for(n))
    times = paired_times(contexts, steps, pairs)
    rigid, middle = np.array(times['rigid']), np.array(times['middle'])
    us, us_error = mean_and_error(1e6*rigid/n)
    ratio, ratio_error = mean_and_error(rigid/middle)
    return {'pairs': pairs, 'steps': steps, 'ms_per_step': f'{1e3*rigid.mean():.4g}', 'body_steps_per_s': f'{n/rigid.mean():.4g}',
            'us_per_body_step': f'{us:.4g}', 'us_per_body_step_se': f'{us_error:.2g}',
            'langevin_middle_ms_per_step': f'{1e3*middle.mean():.4g}', 'ratio': f'{ratio:.3f}', 'ratio_se': f'{ratio_error:.3f}'}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--sizes', type=int, nargs='+', default=[1000, 10000, 100000, 1000000])
    parser.add_argument('--platforms', nargs='+', default=['Reference', 'CPU', 'OpenCL', 'CUDA'])
    parser.add_argument('--precisions', nargs='+', default=None, help='GPU precisions (default: single mixed double on CUDA, single double on OpenCL)')
    parser.add_argument('--pairs', type=int, default=5, help='alternating pairs of timed blocks (RigidLangevin, LangevinMiddle) per row')
    parser.add_argument('--name', default='integrator_cost', help='results/<name>.csv and .png (e.g. integrator_cost_gpu for a GPU machine)')
    args = parser.parse_args()
    rows = []
    for name in args.platforms:
        status = platform_status(name)
        precisions = ['single', 'mixed', 'double'] if name in GPU_PLATFORMS else ['double']
        if name == 'OpenCL':
            precisions = ['single', 'double']
        if args.precisions and name in GPU_PLATFORMS:
            precisions = args.precisions
        for precision in precisions:
            if status is not None:
                rows.append({'platform': name, 'precision': '-', 'bodies': '', 'note': status})
                break
            for n in args.sizes:
                if name == 'Reference' and n > 100000:
                    continue  # single-threaded double precision: the trend is clear well before
                row = {'platform': name, 'precision': precision, 'bodies': n,
                       **time_against_langevin_middle(n, name, platform_properties(name, precision), args.pairs)}
                rows.append(row)
                print(row, flush=True)
    columns = ['platform', 'precision', 'bodies', 'pairs', 'steps', 'ms_per_step', 'body_steps_per_s', 'us_per_body_step',
               'us_per_body_step_se', 'langevin_middle_ms_per_step', 'ratio', 'ratio_se', 'note']
    write_table(args.name, columns, rows)
    plot(rows, args.name)


def plot(rows, name, title='RigidLangevinIntegrator, no forces'):
    """Time per body-step against bodies, each platform and precision beside LangevinMiddleIntegrator
    on the same particles (dashed, same colour), and the ratio of the two, with standard errors."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 5.4))
    series = {}
    for row in rows:
        if row.get('ms_per_step'):
            n = int(row['bodies'])
            series.setdefault(f"{row['platform']} ({row['precision']})", []).append(
                (n, float(row['us_per_body_step']), float(row['us_per_body_step_se']), 1e3*float(row['langevin_middle_ms_per_step'])/n,
                 float(row['ratio']), float(row['ratio_se'])))
    for label, points in series.items():
        n, rigid, rigid_error, middle, ratio, ratio_error = np.array(sorted(points)).T
        line = left.errorbar(n, rigid, rigid_error, fmt='o-', capsize=2, label=label)[0]
        left.plot(n, middle, 's--', color=line.get_color(), alpha=0.6, label=f'{label}: LangevinMiddle')
        right.errorbar(n, ratio, ratio_error, fmt='o-', capsize=2, color=line.get_color(), label=label)
    left.set_xscale('log')
    left.set_yscale('log')
    right.set_xscale('log')
    right.axhline(1, color='k', lw=0.8)
    left.set_xlabel('bodies (3 particles each)')
    left.set_ylabel('us per body-step (mean +- s.e. over pairs)')
    left.set_title(title)
    right.set_xlabel('bodies')
    right.set_ylabel('RigidLangevin / LangevinMiddle (same particles)')
    right.set_title('cost relative to LangevinMiddleIntegrator, pair by pair')
    left.yaxis.set_major_formatter(matplotlib.ticker.ScalarFormatter())
    left.yaxis.set_minor_formatter(matplotlib.ticker.ScalarFormatter())
    for ax in (left, right):
        ax.grid(True, which='both', alpha=0.3)
        ax.legend(fontsize=7, ncol=2, loc='upper center', bbox_to_anchor=(0.5, -0.16))
    save_plot(fig, name)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
