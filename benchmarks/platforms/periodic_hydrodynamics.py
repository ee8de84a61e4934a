"""What a periodic box costs with hydrodynamic interactions: the spectral solver (positively split
Ewald products, linear cost) against the matrix-free step with the dense Ewald sum.

Single spheres (one blob of radius 1 nm each) at random without overlap at 5% volume fraction in a
periodic cube, no forces (a periodic force of zero makes the System periodic), 300 K in water
(0.89 cP), BAOAB with a 2 fs step, on the CPU platform (or --platform). Each size is timed without interactions and
with them, matrix-free with the spectral products ('spectral', SpectralSolver) and, up to
--max-dense-blobs, with the dense Ewald sum formed every step ('dense Ewald', KrylovSolver), in
alternating pairs of blocks in one run (benchmark_utils.paired_times; the solver chosen with
RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER before each block), at each --tolerances (the Krylov solves'
tolerance and the PSE's epsilon).

    python benchmarks/platforms/periodic_hydrodynamics.py [--quick] [--sizes 100 300 1000 3000 10000]
        [--tolerances 1e-3 1e-6] [--max-dense-blobs 1000] [--pairs 2] [--name periodic_hydrodynamics] [--replot]
        [--platform CPU] [--precision mixed] [--integrator langevin|brownian]

--integrator brownian times RigidBrownianIntegrator's step instead (same scene and step size); its
iteration columns are then the noise's Lanczos (with the spectral products a Lanczos on the PSE's
sparse real-space part only: the noise is the PSE's own, exact through its split), and the GMRES
iterations of the drift's and the step's mobility solves.

On OpenCL and CUDA the spectral products run on the device (CommonPseMobility: OpenMM's FFTs; in
single and mixed precision from tolerance 1e-5 up, tighter on the host), the Krylov iterations on
the host. 'blob products/s' is the spectral step's lower bound on the products' rate: blobs times
the step's Krylov iterations (each one product) over its whole time, the host's preparation once a
step (parameters, real-space pairs) and everything else in the step included.

Memory (CPU platform only; on the others the column is empty): each mode runs once more in a child process of its own (--memory-probe: the scene, the
Context, one step); 'peak MiB' is that process's peak resident set (Linux VmHWM) above the peak of
the same probe without interactions (the PSE's grid and pairs, or the dense sum, and the solves'
vectors). Writes results/<name>.csv and .png: ms per step (mean of the pairs +- its
standard error), the ratio to no interactions, the spectral step's speed-up over the dense Ewald
one (pair by pair), peak MiB, and the Krylov iterations of the last step (Lanczos, the noise's and
the friction's conjugate gradients). The table is written again after each size.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl
import benchmark_utils
from benchmark_utils import mean_and_error, paired_times, platform_properties, platform_status, running_context, save_plot, write_table

STEP_PS = 0.002
RADIUS = 1.0
MODES = {'off': None, 'spectral': 'spectral', 'dense Ewald': 'krylov'}
COLUMNS = ['platform', 'blobs', 'tolerance', 'solver', 'ms_per_step', 'ms_error', 'ratio_to_off', 'ratio_error', 'speedup_over_dense',
           'speedup_error', 'peak_mib', 'lanczos', 'noise_cg', 'friction_cg', 'blob_products_per_s']


def scene(count, volume_fraction=0.05, seed=1, brownian=False):
    """(System, integrator factory, positions): count spheres at random without overlap in a periodic
    cube, stepped by RigidLangevinIntegrator (BAOAB) or, if brownian, RigidBrownianIntegrator."""
    side = (count*4/3*math.pi*RADIUS**3/volume_fraction)**(1/3)
    rng = np.random.default_rng(seed)
    cells = max(1, int(side/(2*RADIUS)))
    grid = {}
    positions = []
    while len(positions) < count:
        # A cell list keeps the placement linear in count (10^5 spheres in seconds).
        p = rng.uniform(0, side, 3)
        cell = tuple((p/side*cells).astype(int) % cells)
        near = [q for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                for q in grid.get(((cell[0]+dx) % cells, (cell[1]+dy) % cells, (cell[2]+dz) % cells), [])]
        d = np.array(near).reshape(-1, 3)-p
        d -= side*np.round(d/side)
        if np.all(np.einsum('ij,ij->i', d, d) >= (2*RADIUS)**2):
            grid.setdefault(cell, []).append(p)
            positions.append(p)
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(side, 0, 0), mm.Vec3(0, side, 0), mm.Vec3(0, 0, side))
    periodic = mm.CustomNonbondedForce('0')
    periodic.setNonbondedMethod(mm.CustomNonbondedForce.CutoffPeriodic)
    periodic.setCutoffDistance(min(1.0, 0.4*side))
    for _ in range(count):
        system.addParticle(10.0)
        periodic.addParticle([])
    system.addForce(periodic)

    def integrator(interactions, tolerance):
        if brownian:
            result = rl.RigidBrownianIntegrator(300*unit.kelvin, 0.89*rl.centipoise, STEP_PS*unit.picoseconds)
        else:
            result = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.89*rl.centipoise, STEP_PS*unit.picoseconds)
            result.setScheme(rl.RigidLangevinIntegrator.BAOAB)
        result.setHydrodynamicInteractions(interactions)
        result.setHydrodynamicTolerance(tolerance)
        for i in range(count):
            result.addRigidBody([i])
            result.setParticleRadius(i, RADIUS)
        return result
    return system, integrator, np.array(positions)


def peak_resident_mib():
    """This process's peak resident set (Linux VmHWM, MiB)."""
    with open('/proc/self/status', encoding='ascii') as f:
        for line in f:
            if line.startswith('VmHWM:'):
                return int(line.split()[1])/1024
    return float('nan')


def memory_probe(count, tolerance, mode, brownian=False):
    """In this process: the scene, mode's Context and one step; print the peak resident MiB."""
    solver(MODES[mode])()
    system, make_integrator, positions = scene(count, brownian=brownian)
    integrator = make_integrator(mode != 'off', tolerance)
    running_context(system, integrator, positions, 'CPU', {}, warmup_steps=1)
    print(f'peak {peak_resident_mib():.6g}')


def probed_peak_mib(count, tolerance, mode, brownian=False):
    """The peak resident MiB of memory_probe() in a child process."""
    result = subprocess.run([sys.executable, os.path.abspath(__file__), '--memory-probe', str(count), repr(tolerance), mode]+
                            (['--integrator', 'brownian'] if brownian else []),
                            capture_output=True, encoding='utf-8', check=True)
    return float(result.stdout.split('peak ')[-1])


def solver(name):
    def set_environment():
        if name is None:
            os.environ.pop('RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER', None)
        else:
            os.environ['RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER'] = name
    return set_environment


def measure(count, tolerance, pairs, max_dense_blobs, platform='CPU', properties=None, brownian=False):
    """The rows of one size and tolerance on the platform (with its Context properties), of
    RigidBrownianIntegrator's step if brownian, else RigidLangevinIntegrator's."""
    system, make_integrator, positions = scene(count, brownian=brownian)
    modes = [m for m in MODES if m != 'dense Ewald' or count <= max_dense_blobs]
    contexts, prepare = {}, {}
    for mode in modes:
        prepare[mode] = solver(MODES[mode])
        prepare[mode]()
        integrator = make_integrator(mode != 'off', tolerance)
        contexts[mode] = (integrator, running_context(system, integrator, positions, platform, properties or {}, warmup_steps=1))
    times = paired_times(contexts, 1, pairs=pairs, prepare=prepare)
    os.environ.pop('RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER', None)
    peak = {mode: probed_peak_mib(count, tolerance, mode, brownian) for mode in modes} if platform == 'CPU' else None
    rows = []
    for mode in modes:
        integrator = contexts[mode][0]
        iterations = integrator.getKrylovIterations() if mode != 'off' else ['', '', '']
        mean, error = mean_and_error(np.array(times[mode])*1e3)
        ratio, ratio_error = mean_and_error(np.array(times[mode])/np.array(times['off']))
        row = {'platform': platform, 'blobs': count, 'tolerance': f'{tolerance:g}', 'solver': mode, 'ms_per_step': f'{mean:.4g}',
               'ms_error': f'{error:.2g}', 'ratio_to_off': f'{ratio:.4g}', 'ratio_error': f'{ratio_error:.2g}',
               'peak_mib': f'{peak[mode]-peak["off"]:.4g}' if peak else '', 'lanczos': iterations[0], 'noise_cg': iterations[1],
               'friction_cg': iterations[2]}
        if mode == 'spectral':
            row['blob_products_per_s'] = f'{count*sum(iterations)/(mean/1e3):.3g}'
        if mode == 'spectral' and 'dense Ewald' in times:
            speedup, speedup_error = mean_and_error(np.array(times['dense Ewald'])/np.array(times['spectral']))
            row.update(speedup_over_dense=f'{speedup:.4g}', speedup_error=f'{speedup_error:.2g}')
        rows.append(row)
    return rows


def plot(rows, name):
    """results/<name>.png: seconds per step and peak memory against blobs, each solver and tolerance."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (time_axis, memory_axis) = plt.subplots(1, 2, figsize=(10, 4.5))
    for colour, tolerance in enumerate(sorted({r['tolerance'] for r in rows}, key=float)):
        for mode, marker, line in (('spectral', 'o', '-'), ('dense Ewald', 's', '--')):
            points = sorted((int(r['blobs']), float(r['ms_per_step'])/1e3, float(r['ms_error'])/1e3, float(r['peak_mib'] or 'nan'))
                            for r in rows if r['solver'] == mode and r['tolerance'] == tolerance)
            if points:
                x, y, e, m = zip(*points)
                style = dict(marker=marker, linestyle=line, color=f'C{colour}', label=f'{mode}, tolerance {tolerance}')
                time_axis.errorbar(x, y, yerr=e, **style)
                memory_axis.plot(x, m, **style)
    platform = rows[0].get('platform') or 'CPU'
    for axis, label in ((time_axis, f's per step ({platform} platform)'), (memory_axis, 'peak MiB above no interactions (a child process)')):
        axis.set_xscale('log')
        axis.set_yscale('log')
        axis.set_xlabel('blobs (one-blob spheres, 5% volume fraction)')
        axis.set_ylabel(label)
    time_axis.axhline(3, color='grey', linestyle=':', label="issue's goal at 10^4 blobs")
    memory_axis.axhline(1024, color='grey', linestyle=':', label="issue's goal at 10^4 blobs")
    time_axis.legend(fontsize=7)
    memory_axis.legend(fontsize=7)
    fig.suptitle('Periodic box with hydrodynamic interactions: spectral (PSE) against dense Ewald')
    save_plot(fig, name)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--quick', action='store_true', help='100 and 300 blobs, two pairs (seconds)')
    parser.add_argument('--sizes', type=int, nargs='+', default=[100, 300, 1000, 3000, 10000])
    parser.add_argument('--tolerances', type=float, nargs='+', default=[1e-3, 1e-6])
    parser.add_argument('--max-dense-blobs', type=int, default=1000)
    parser.add_argument('--pairs', type=int, default=2)
    parser.add_argument('--name', default='periodic_hydrodynamics')
    parser.add_argument('--replot', action='store_true', help='only draw results/<name>.png again from results/<name>.csv')
    parser.add_argument('--platform', default='CPU', choices=('Reference', 'CPU', 'OpenCL', 'CUDA'))
    parser.add_argument('--precision', default='mixed', choices=('single', 'mixed', 'double'), help='on OpenCL and CUDA')
    parser.add_argument('--integrator', default='langevin', choices=('langevin', 'brownian'),
                        help='RigidLangevinIntegrator (BAOAB) or RigidBrownianIntegrator')
    parser.add_argument('--memory-probe', nargs=3, metavar=('BLOBS', 'TOLERANCE', 'MODE'), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.memory_probe:
        memory_probe(int(args.memory_probe[0]), float(args.memory_probe[1]), args.memory_probe[2], args.integrator == 'brownian')
        return
    if args.replot:
        with open(os.path.join(benchmark_utils.RESULTS, args.name+'.csv'), encoding='utf-8') as f:
            plot(list(csv.DictReader(f)), args.name)
        return
    status = platform_status(args.platform)
    if status is not None:
        parser.error(f'{args.platform}: {status}')
    if args.quick:
        args.sizes, args.tolerances, args.pairs = [100, 300], [1e-3], 2
    rows = []
    for count in args.sizes:
        for tolerance in args.tolerances:
            print(f'{count} blobs at tolerance {tolerance:g}...', flush=True)
            start = time.perf_counter()
            rows += measure(count, tolerance, args.pairs, args.max_dense_blobs, args.platform, platform_properties(args.platform, args.precision),
                            args.integrator == 'brownian')
            print(f'({time.perf_counter()-start:.0f} s)', flush=True)
            write_table(args.name, COLUMNS, rows)
    plot(rows, args.name)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')
    main()
