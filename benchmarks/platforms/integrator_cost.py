"""Cost of RigidLangevinIntegrator alone: force-free rigid water-shaped bodies (3 particles each),
the default ExactFlow scheme at the viscosity of water, from 1e3 to 1e6 bodies, on every platform.
Reports bodies*steps per second and time per step; the cost must grow linearly with the number of
bodies (constant bodies*steps/s once the fixed cost of a step is amortised). For scale, the same
particles with LangevinMiddleIntegrator (each particle free, no constraints) are timed as well.

    python benchmarks/platforms/integrator_cost.py [--sizes 1000 10000 100000 1000000]
"""
import argparse
import math

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl
from benchmark_utils import platform_status, time_per_step, write_table, save_plot, running_context

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
    """Enough steps to take ~1 s on a slow platform without taking minutes on a fast one."""
    return max(3, min(200, int(3e6/num_bodies)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--sizes', type=int, nargs='+', default=[1000, 10000, 100000, 1000000])
    parser.add_argument('--platforms', nargs='+', default=['Reference', 'CPU', 'OpenCL', 'CUDA'])
    parser.add_argument('--precisions', nargs='+', default=None, help='GPU precisions (default: single mixed double on CUDA, single double on OpenCL)')
    parser.add_argument('--name', default='integrator_cost', help='results/<name>.csv and .png (e.g. integrator_cost_gpu for a GPU machine)')
    args = parser.parse_args()
    rows = []
    for name in args.platforms:
        status = platform_status(name)
        precisions = ['single', 'mixed', 'double'] if name in ('OpenCL', 'CUDA') else ['double']
        if name == 'OpenCL':
            precisions = ['single', 'double']
        if args.precisions and name in ('OpenCL', 'CUDA'):
            precisions = args.precisions
        for precision in precisions:
            if status is not None:
                rows.append({'platform': name, 'precision': '-', 'bodies': '', 'note': status})
                break
            for n in args.sizes:
                if name == 'Reference' and n > 100000:
                    continue  # single-threaded double precision: the trend is clear well before
                properties = {'Precision': precision} if name in ('OpenCL', 'CUDA') else {}
                row = {'platform': name, 'precision': precision, 'bodies': n}
                for rigid in (True, False):
                    system, integrator, positions = build(n, rigid)
                    context = running_context(system, integrator, positions, name, properties)
                    seconds = time_per_step(integrator, context, steps_for(n))
                    if rigid:
                        row['ms_per_step'] = f'{1e3*seconds:.4g}'
                        row['body_steps_per_s'] = f'{n/seconds:.4g}'
                        row['us_per_body_step'] = f'{1e6*seconds/n:.4g}'
                    else:
                        row['langevin_middle_ms_per_step'] = f'{1e3*seconds:.4g}'
                    del context, integrator
                rows.append(row)
                print(row, flush=True)
    columns = ['platform', 'precision', 'bodies', 'ms_per_step', 'body_steps_per_s', 'us_per_body_step', 'langevin_middle_ms_per_step', 'note']
    write_table(args.name, columns, rows)
    plot(rows, args.name)


def plot(rows, name, title='RigidLangevinIntegrator, no forces'):
    """Time per body-step against bodies, each platform and precision beside LangevinMiddleIntegrator
    on the same particles (dashed, same colour), and the ratio of the two."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    series = {}
    for row in rows:
        if row.get('ms_per_step'):
            n = int(row['bodies'])
            series.setdefault(f"{row['platform']} ({row['precision']})", []).append(
                (n, 1e3*float(row['ms_per_step'])/n, 1e3*float(row['langevin_middle_ms_per_step'])/n))
    for label, points in series.items():
        points.sort()
        n = np.array([p[0] for p in points])
        rigid, middle = np.array([p[1] for p in points]), np.array([p[2] for p in points])
        line, = left.loglog(n, rigid, 'o-', label=label)
        left.loglog(n, middle, 's--', color=line.get_color(), alpha=0.6, label=f'{label}: LangevinMiddle')
        right.semilogx(n, rigid/middle, 'o-', color=line.get_color(), label=label)
    right.axhline(1, color='k', lw=0.8)
    left.set_xlabel('bodies (3 particles each)')
    left.set_ylabel('us per body-step')
    left.set_title(title)
    right.set_xlabel('bodies')
    right.set_ylabel('RigidLangevin / LangevinMiddle (same particles)')
    right.set_title('cost relative to LangevinMiddleIntegrator')
    for ax in (left, right):
        ax.grid(True, which='both', alpha=0.3)
        ax.legend(fontsize=7)
    save_plot(fig, name)


if __name__ == '__main__':
    main()
