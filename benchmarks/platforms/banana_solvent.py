"""The banana scene's cost: the explicit step with the pentane sites' Lennard-Jones in a
NonbondedForce (only pairs with an ellipsoid in the GayBerneForce) against the same System with every
particle in one GayBerneForce, at the same 1.4 nm cutoff (the energies are the same: tests/test_banana.py);
and explicit solvent against implicit, per nanosecond. Each pair of Contexts is timed in alternating
pairs of blocks (benchmark_utils.paired_times): the ratios carry standard errors.

Explicit: two bananas (bodies) among 320 pentanes under RigidLangevinIntegrator at zero viscosity,
1 fs (the scene's NVE runs). Implicit: the two bananas alone under its ExactFlow scheme at 0.289 cP,
2 fs. Writes results/banana_solvent.csv and .png, and where the split explicit step's time goes:
each force alone (its own force group, evaluated in rounds that alternate the forces) against the
whole step, results/banana_solvent_forces.csv.

    python benchmarks/platforms/banana_solvent.py [--platform CPU] [--pairs 6]
"""
import argparse
import pathlib
import sys
import time

import numpy as np
import openmm as mm

import rigidlangevin as rl
from benchmark_utils import calibrated_steps, mean_and_error, paired_times, save_plot, write_table

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2]/'examples'))
import banana_model as bm  # noqa: E402
import banana_runs as runs  # noqa: E402

BOX = 4.07  # nm: about the scene's


def scene_context(all_in_gayberne, xi, platform, properties):
    """The explicit scene's Context, relaxed from its lattice."""
    system, positions, bodies, _ = bm.pentane_box(320, BOX, 1, bananas=2, all_in_gayberne=all_in_gayberne)
    integrator = runs.explicit_integrator(system, bodies, xi, 1.0)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform), properties)
    context.setPositions(positions)
    integrator.step(500)  # relaxes the lattice's close contacts at 1 cP
    integrator.setViscosity(0.0)
    return integrator, context


def force_costs(platform, properties, rounds=12, evaluations=20):
    """Milliseconds per evaluation (mean and standard error over rounds) of each force of the split
    explicit System alone, of all of them together, and of no force (a State's own cost, which
    every other row includes)."""
    system, positions, _, _ = bm.pentane_box(320, BOX, 1, bananas=2)
    for group, force in enumerate(system.getForces()):
        force.setForceGroup(group)
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName(platform), properties)
    context.setPositions(positions)
    names = [f'{force.__class__.__name__} ({force.getName()})' if force.getName() != force.__class__.__name__ else force.__class__.__name__
             for force in system.getForces()]
    groups = {name: {group} for group, name in enumerate(names)}
    groups['all forces'] = set(range(len(names)))
    groups['none (the State\'s own cost)'] = {31}
    times = {name: [] for name in groups}
    for _ in range(rounds):
        for name, group in groups.items():
            context.getState(getForces=True, groups=group)
            start = time.perf_counter()
            for _ in range(evaluations):
                context.getState(getForces=True, groups=group)
            times[name].append((time.perf_counter()-start)/evaluations*1e3)
    return {name: mean_and_error(np.array(t)) for name, t in times.items()}


def implicit_context(xi, platform, properties):
    system, positions, bodies, _ = bm.pentane_box(0, BOX, 1, bananas=2)
    integrator = rl.RigidLangevinIntegrator(runs.TEMPERATURE, bm.SOURCE_VISCOSITY*rl.poise, runs.IMPLICIT_STEP)
    runs.add_bodies(integrator, bodies, xi)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform), properties)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(runs.TEMPERATURE, 1)
    integrator.step(100)
    return integrator, context


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--platform', default='CPU')
    parser.add_argument('--pairs', type=int, default=6)
    args = parser.parse_args()
    properties = {}
    xi = bm.resistance_tensor(1000)
    contexts = {'split': scene_context(False, xi, args.platform, properties), 'one GayBerneForce': scene_context(True, xi, args.platform, properties),
                'implicit': implicit_context(xi, args.platform, properties)}
    steps = {key: calibrated_steps(integrator, context, 20) for key, (integrator, context) in contexts.items()}
    times = paired_times(contexts, steps, args.pairs)
    per_ns = {key: np.array(times[key])/(runs.IMPLICIT_STEP if key == 'implicit' else runs.EXPLICIT_STEP)*1e3 for key in times}  # s per ns
    rows = []
    for key in contexts:
        mean, error = mean_and_error(np.array(times[key])*1e3)
        rows.append({'run': key, 'ms per step': f'{mean:.4f} ± {error:.4f}', 'ns/day': f'{86400/np.mean(per_ns[key]):.1f}'})
    old, old_error = mean_and_error(np.array(times['one GayBerneForce'])/np.array(times['split']))
    ratio, ratio_error = mean_and_error(per_ns['split']/per_ns['implicit'])
    rows.append({'run': 'one GayBerneForce / split (per step)', 'ratio': f'{old:.2f} ± {old_error:.2f}'})
    rows.append({'run': 'explicit (split) / implicit (per ns)', 'ratio': f'{ratio:.1f} ± {ratio_error:.1f}'})
    write_table('banana_solvent', ['run', 'ms per step', 'ns/day', 'ratio'], rows)
    step, _ = mean_and_error(np.array(times['split'])*1e3)
    costs = force_costs(args.platform, properties)
    write_table('banana_solvent_forces', ['force', 'ms per evaluation', 'share of the split step'],
                [{'force': name, 'ms per evaluation': f'{mean:.4f} ± {error:.4f}', 'share of the split step': f'{100*mean/step:.0f}%'}
                 for name, (mean, error) in costs.items()])
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 3.5))
    keys = list(contexts)
    means = [86400/np.mean(per_ns[k]) for k in keys]
    errors = [86400*np.std(1/per_ns[k], ddof=1)/np.sqrt(len(per_ns[k])) for k in keys]
    ax.bar(keys, means, yerr=errors, capsize=4)
    ax.set_yscale('log')
    ax.set_ylabel('ns/day (integrator steps alone)')
    ax.set_title(f'banana scene on {args.platform}: explicit {ratio:.0f}x slower per ns than implicit')
    save_plot(fig, 'banana_solvent')


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
