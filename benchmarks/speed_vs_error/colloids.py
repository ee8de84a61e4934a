"""Speed against error for colloids (part S3 of the speed-against-error study): RigidBrownianIntegrator's
weak accuracy against its time step, where the truth is exact.

Scene: a sphere of radius a = 1 um (one blob) sedimented above a no-slip wall at z = 0 in water
(0.89 cP, 300 K), pulled down by its weight W = 4 kT/a and pushed off the wall by 4 kT exp(-(z - a)/(0.1 a)),
both CustomExternalForces on its particle; hydrodynamic interactions on, so that its mobility is
Rotne-Prager-Blake's and depends on its height (which is what the stochastic drift is for). The
Gibbs-Boltzmann density of its height is exp(-U(z)/kT) whatever the mobility: its mean and standard
deviation, by quadrature, are the exact truth.

Each time step runs REPLICAS independent spheres (a Context each, seeds 1..REPLICAS) for the same
simulated time after an equilibration of EQUILIBRATION seconds, sampling the height every SAMPLE
seconds; an error is the replicas' mean against the truth, with the standard error of the spread over
replicas. The scheme (Euler-Maruyama with the drift by random finite differences) is weakly first order:
its errors should shrink in proportion to the step. Cost: wall seconds per simulated second on the CPU
platform, one thread (a lone sphere's step is a 3x3 dense solve; what a many-body step costs is in
benchmarks/hydrodynamics). RigidLangevinIntegrator would need steps of about m/gamma = 2.6e-7 s here
(a polystyrene sphere of 1 um): 4e4 times more steps than the Brownian one at 0.01 s for the same time.

    python benchmarks/speed_vs_error/colloids.py [--out benchmarks/speed_vs_error/results] [--quick]
    python benchmarks/speed_vs_error/colloids.py --append [--chunks 2]   # more chunks, added to what is on disk

Each replica runs in chunks of SIMULATED_S seconds, each from a fresh start with its own seed, so that
runs appended one after another give the same records (bar wall times) as one run of as many chunks.
Writes colloids.json (every chunk's sums), colloids.md (the table) and colloids.png (error against cost).
"""
import argparse
import json
import math
import pathlib
import sys
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl

KT = (unit.BOLTZMANN_CONSTANT_kB*unit.AVOGADRO_CONSTANT_NA*300*unit.kelvin).value_in_unit(unit.kilojoule_per_mole)
RADIUS = 1000.0  # nm
WEIGHT, REPULSION, DECAY = 4*KT/RADIUS, 4*KT, 0.1*RADIUS
STEPS_S = [0.005, 0.01, 0.02, 0.04, 0.08, 0.16]
REPLICAS = 16
SIMULATED_S = 500.0  # per replica and chunk
EQUILIBRATION_S = 5.0
SAMPLE_S = 0.16
PS_PER_S = 1e12


def truth():
    """The Gibbs-Boltzmann mean and standard deviation of the height (nm), by quadrature."""
    z = np.linspace(1e-3, RADIUS+40*KT/WEIGHT, 2000001)
    density = np.exp(-(WEIGHT*z+REPULSION*np.exp(-(z-RADIUS)/DECAY))/KT)
    norm = np.trapezoid(density, z)
    mean = np.trapezoid(z*density, z)/norm
    return mean, math.sqrt(np.trapezoid((z-mean)**2*density, z)/norm)


def sphere(step_s, seed):
    """(System, integrator) of one sedimented sphere above the wall."""
    system = mm.System()
    system.addParticle(1.0)
    force = mm.CustomExternalForce('weight*z+repulsion*exp(-(z-radius)/decay)')
    for name, value in [('weight', WEIGHT), ('repulsion', REPULSION), ('radius', RADIUS), ('decay', DECAY)]:
        force.addGlobalParameter(name, value)
    force.addParticle(0, [])
    system.addForce(force)
    integrator = rl.RigidBrownianIntegrator(300*unit.kelvin, 0.89*rl.centipoise, step_s*PS_PER_S*unit.picoseconds)
    integrator.addRigidBody([0])
    integrator.setParticleRadius(0, RADIUS*unit.nanometer)
    integrator.setHydrodynamicInteractions(True)
    integrator.setWall(0.0)
    integrator.setRandomNumberSeed(seed)
    return system, integrator


def run_replica(step_s, seed, simulated_s):
    """Sums of the sampled heights and their squares, the sample count, and the wall seconds of the
    sampled part."""
    system, integrator = sphere(step_s, seed)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'), {'Threads': '1'})
    context.setPositions([mm.Vec3(0, 0, 1.3*RADIUS)])
    integrator.step(int(round(EQUILIBRATION_S/step_s)))
    stride = max(1, int(round(SAMPLE_S/step_s)))
    samples = int(simulated_s/(stride*step_s))
    heights = np.empty(samples)
    start = time.perf_counter()
    for i in range(samples):
        integrator.step(stride)
        heights[i] = context.getState(getPositions=True).getPositions(asNumpy=True)._value[0, 2]
    seconds = time.perf_counter()-start
    return {'sum': float(heights.sum()), 'sum2': float((heights**2).sum()), 'count': samples, 'seconds': seconds,
            'simulated_s': samples*stride*step_s}


def measure(records, chunks, simulated_s, steps=STEPS_S, replicas=REPLICAS):
    """Add `chunks` chunks of simulated_s to every replica of every step in records (step -> chunks).
    A chunk's seed follows from its replica and its number alone, so that runs appended one after
    another give the records of one run of as many chunks."""
    for step_s in steps:
        mine = records.setdefault(str(step_s), [])
        first = 1+max((c['chunk'] for c in mine), default=-1)
        for chunk in range(first, first+chunks):
            for replica in range(replicas):
                result = run_replica(step_s, 1+replica+REPLICAS*chunk, simulated_s)
                mine.append(dict(result, replica=replica, chunk=chunk))
        print(f'step {step_s} s: {len(mine)//replicas} chunks of {replicas} replicas', flush=True)


def merge(chunks):
    """Each replica's chunks summed (a replica's chunks start afresh, so replicas stay independent)."""
    by_replica = {}
    for c in chunks:
        total = by_replica.setdefault(c['replica'], dict.fromkeys(('sum', 'sum2', 'count', 'seconds', 'simulated_s'), 0))
        for key in total:
            total[key] += c[key]
    return list(by_replica.values())


def table_rows(records):
    mean_true, std_true = truth()
    rows = []
    for step_s in sorted(float(step) for step in records):
        replicas = merge(records[str(step_s)])
        means = np.array([r['sum']/r['count'] for r in replicas])
        stds = np.array([math.sqrt(r['sum2']/r['count']-(r['sum']/r['count'])**2) for r in replicas])
        cost = sum(r['seconds'] for r in replicas)/sum(r['simulated_s'] for r in replicas)
        rows.append({'step_s': step_s, 'replicas': len(replicas), 'simulated_s': sum(r['simulated_s'] for r in replicas),
                     'wall_s_per_simulated_s': cost,
                     'mean_error_nm': means.mean()-mean_true, 'mean_se_nm': means.std(ddof=1)/math.sqrt(len(means)),
                     'std_error_nm': stds.mean()-std_true, 'std_se_nm': stds.std(ddof=1)/math.sqrt(len(stds))})
    return rows, mean_true, std_true


def first_order_fit(rows, key):
    """The weighted least-squares slope C of error = C step over every step but the largest, its
    standard error and the fit's chi^2 (degrees of freedom: the steps used less one)."""
    used = sorted(rows, key=lambda r: r['step_s'])[:-1]
    dt = np.array([r['step_s'] for r in used])
    error = np.array([r[f'{key}_error_nm'] for r in used])
    weight = 1/np.array([r[f'{key}_se_nm'] for r in used])**2
    slope = float((weight*dt*error).sum()/(weight*dt*dt).sum())
    return slope, float(1/math.sqrt((weight*dt*dt).sum())), float((weight*(error-slope*dt)**2).sum()), len(used)-1


def write(rows, mean_true, std_true, out):
    lines = [f'Sphere (a = 1 um) sedimented above a no-slip wall, RigidBrownianIntegrator with hydrodynamic interactions; '
             f'exact Gibbs-Boltzmann height: mean {mean_true:.2f} nm, standard deviation {std_true:.2f} nm. '
             'Errors: replicas\' mean minus the truth, +- one standard error over replicas.', '',
             '| step (s) | replicas | simulated s | wall s per simulated s | error of mean height (nm) | error of height s.d. (nm) |',
             '|---|---|---|---|---|---|']
    for r in rows:
        lines.append(f"| {r['step_s']:g} | {r['replicas']} | {r['simulated_s']:.0f} | {r['wall_s_per_simulated_s']:.3g} | "
                     f"{r['mean_error_nm']:.2f} +- {r['mean_se_nm']:.2f} | {r['std_error_nm']:.2f} +- {r['std_se_nm']:.2f} |")
    if len(rows) > 2:
        lines.append('')
        lines.append(f"Weakly first order: a fit error = C step over the steps up to {sorted(r['step_s'] for r in rows)[-2]:g} s gives")
        for key, name in [('mean', 'mean height'), ('std', 'height s.d.')]:
            slope, se, chi2, dof = first_order_fit(rows, key)
            lines.append(f'- {name}: C = {slope:.0f} +- {se:.0f} nm/s (chi^2 {chi2:.1f} for {dof} degrees of freedom)')
    (out/'colloids.md').write_text('\n'.join(lines)+'\n', encoding='utf-8')


def plot(rows, out):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4.2))
    cost = [r['wall_s_per_simulated_s'] for r in rows]
    for key, label in [('mean', 'mean height'), ('std', 'height s.d.')]:
        ax.errorbar(cost, [r[f'{key}_error_nm'] for r in rows], yerr=[r[f'{key}_se_nm'] for r in rows], fmt='o-', capsize=3, label=label)
    for r in rows:
        ax.annotate(f"{r['step_s']:g} s", (r['wall_s_per_simulated_s'], r['mean_error_nm']), fontsize=7, xytext=(3, 3), textcoords='offset points')
    ax.axhline(0, color='grey', lw=0.8)
    ax.set_xscale('log')
    ax.set_xlabel('wall seconds per simulated second (CPU, 1 thread)')
    ax.set_ylabel('error against Gibbs-Boltzmann (nm)')
    ax.set_title('Sedimented sphere above a wall: RigidBrownianIntegrator', fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out/'colloids.png', dpi=120)


def main(argv=None):
    sys.stdout.reconfigure(encoding='utf-8')
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--out', default=str(pathlib.Path(__file__).resolve().parent/'results'))
    parser.add_argument('--append', action='store_true', help='add chunks to those in colloids.json')
    parser.add_argument('--chunks', type=int, default=1, help=f'chunks of {SIMULATED_S:g} simulated s per replica to run (default 1)')
    parser.add_argument('--quick', action='store_true', help='a few simulated seconds: checks the machinery, not the numbers')
    parser.add_argument('--steps', type=float, nargs='+', default=STEPS_S, help='time steps (s)')
    parser.add_argument('--replicas', type=int, default=REPLICAS)
    args = parser.parse_args(argv)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = out/'colloids.json'
    records = json.loads(path.read_text(encoding='utf-8')) if args.append and path.exists() else {}
    measure(records, args.chunks, 10*SAMPLE_S if args.quick else SIMULATED_S, args.steps, args.replicas)
    path.write_text(json.dumps(records), encoding='utf-8')
    rows, mean_true, std_true = table_rows(records)
    write(rows, mean_true, std_true, out)
    plot(rows, out)
    print((out/'colloids.md').read_text(encoding='utf-8'))


if __name__ == '__main__':
    main()
