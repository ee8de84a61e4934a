"""The source's first scene replayed: 256 SSD (or SSD/RF) waters under RigidLangevinIntegrator.

Sun, Lin & Gezelter (J. Chem. Phys. 128, 234107 (2008)) ran 256 SSD waters in a 19.7166 A box,
9 A cutoff, 2 fs, 300 K, 1 ns at each of 1, 0.1 and 0.01 poise, from an equilibrated NVT
configuration, and reported the mean and rms temperature; then the configuration cooled to 173 K
heated under their Langevin integrator at 0.1 P, Nose-Hoover (5 ps) and NVE. This example does
the same and writes, to --out:

  temperatures.csv, table.md   mean and rms temperature at each viscosity, with standard errors
                                (block averages), beside the source's numbers
  heating.csv, heating.png     temperature against time from 173 K: this integrator at 0.1 P,
                                OpenMM's NoseHooverIntegrator (5 ps), and NVE (velocity Verlet)

    python examples/ssd_scene.py                   # about 8 minutes on 2 cores: 3 x 60 ps, 3 heating runs of 40 ps
    python examples/ssd_scene.py --full            # the source's lengths: 3 x 1 ns, 3 x 100 ps (about 75 minutes;
                                                   # the committed examples/results/ssd_scene)
    python examples/ssd_scene.py --quick           # seconds: a few ps of each (for tests)

60 ps per viscosity tells the source's 303 K at 0.01 P from 300 K: the temperature decorrelates within
tens of fs at these viscosities, so its mean carries a standard error of about 0.3 K.

The temperature is that of the bodies' 6 degrees of freedom each (6 x 256 = 1536; no centre of
mass constraint, as in the source); an ideal canonical sample has rms fluctuation 300 K sqrt(2/1536)
= 10.8 K.
"""
import sys
import argparse
import csv
import math
import pathlib
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl
from rigidlangevin.statistics import block_error

#: The source's table (its Table 1): viscosity (poise) -> (mean T, rms T) in K.
SOURCE = {1.0: (300.47, 10.99), 0.1: (301.19, 11.136), 0.01: (303.04, 11.796)}
BOLTZ = unit.MOLAR_GAS_CONSTANT_R.value_in_unit(unit.kilojoule_per_mole/unit.kelvin)
STEP = 0.002  # ps


def temperature(context, dof):
    """Instantaneous temperature (K) from the kinetic energy OpenMM reports (for rigid bodies: theirs)."""
    kinetic = context.getState(getEnergy=True).getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
    return 2*kinetic/(dof*BOLTZ)


def sample(integrator, context, dof, picoseconds, every=10):
    """Temperatures every `every` steps over a run."""
    values = []
    for _ in range(int(round(picoseconds/STEP/every))):
        integrator.step(every)
        values.append(temperature(context, dof))
    return np.array(values)


def rms_and_error(values, blocks=10):
    """The rms deviation of a series from its mean, and its standard error from block estimates."""
    n = len(values)//blocks
    per_block = [np.std(values[i*n:(i+1)*n]) for i in range(blocks)]
    return float(np.std(values)), float(np.std(per_block, ddof=1)/math.sqrt(blocks))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--model', default='SSD', choices=['SSD', 'SSD1', 'SSD/E', 'SSD/RF'])
    parser.add_argument('--platform', default='CPU')
    parser.add_argument('--quick', action='store_true', help='a few ps of each run (seconds; for tests)')
    parser.add_argument('--full', action='store_true', help="the source's lengths: 1 ns per viscosity, 100 ps heating runs")
    parser.add_argument('--run-ps', type=float, help='length of each viscosity run (default 60; quick 4, full 1000)')
    parser.add_argument('--equilibrate-ps', type=float, help='equilibration at 300 K (default 20; quick 2, full 100)')
    parser.add_argument('--heating-ps', type=float, help='length of each heating run (default 40; quick 2, full 100)')
    parser.add_argument('--out', default='ssd_scene', help='directory for the results')
    args = parser.parse_args()
    if args.quick and args.full:
        parser.error('choose --quick or --full')
    lengths = {'quick': (4.0, 2.0, 2.0), 'full': (1000.0, 100.0, 100.0), 'default': (60.0, 20.0, 40.0)}
    run_ps, equilibrate_ps, heating_ps = lengths['quick' if args.quick else 'full' if args.full else 'default']
    run_ps, equilibrate_ps, heating_ps = args.run_ps or run_ps, args.equilibrate_ps or equilibrate_ps, args.heating_ps or heating_ps
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    platform = mm.Platform.getPlatformByName(args.platform)

    topology, system, positions = rl.ssd.waterBox(256, model=args.model)
    n = topology.getNumResidues()
    dof = 6*n

    def bodies(temperature_k, viscosity_poise):
        integrator = rl.RigidLangevinIntegrator(temperature_k*unit.kelvin, viscosity_poise*rl.poise, STEP*unit.picosecond)
        integrator.setRandomNumberSeed(2008)
        rl.addRigidBodies(integrator, topology, system, residues='water', positions=positions)
        context = mm.Context(system, integrator, platform)
        return integrator, context

    # Minimise the lattice, then equilibrate at 300 K to an NVT configuration. At 0.01 P the bodies'
    # velocities relax in about 10 fs and their positions nearly as fast as in water; at 1 P (110
    # times water's viscosity) the motion is overdamped and the configuration would lag behind.
    integrator, context = bodies(300, 0.01)
    context.setPositions(positions)
    mm.LocalEnergyMinimizer.minimize(context, 10.0, 500)
    context.setVelocitiesToTemperature(300*unit.kelvin, 1)
    start = time.perf_counter()
    integrator.step(int(round(equilibrate_ps/STEP)))
    equilibrated = context.getState(getPositions=True, getVelocities=True)
    print(f'{n} {args.model} waters equilibrated for {equilibrate_ps:g} ps ({time.perf_counter()-start:.0f} s)', flush=True)

    rows = []
    for viscosity in (1.0, 0.1, 0.01):
        integrator, context = bodies(300, viscosity)
        context.setState(equilibrated)
        start = time.perf_counter()
        values = sample(integrator, context, dof, run_ps)
        seconds = time.perf_counter()-start
        mean, mean_error = float(np.mean(values)), block_error(values)
        rms, rms_error = rms_and_error(values)
        rows.append({'viscosity_poise': viscosity, 'run_ps': run_ps, 'mean_T': f'{mean:.2f}', 'mean_T_error': f'{mean_error:.2f}',
                     'rms_T': f'{rms:.2f}', 'rms_T_error': f'{rms_error:.2f}', 'source_mean_T': SOURCE[viscosity][0],
                     'source_rms_T': SOURCE[viscosity][1], 'ns_per_day': f'{run_ps*1e-3*86400/seconds:.3g}'})
        print(f'  {viscosity:g} P: mean {mean:.2f} ± {mean_error:.2f} K, rms {rms:.2f} ± {rms_error:.2f} K '
              f'({run_ps:g} ps, {seconds:.0f} s)', flush=True)
    with open(out/'temperatures.csv', 'w', newline='', encoding='utf-8') as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    lines = [f'{n} {args.model} waters, 19.7166 A box, 9 A cutoff, 2 fs, 300 K, {run_ps:g} ps per viscosity '
             f'(standard errors from 10 blocks). An ideal canonical sample: mean 300 K, rms {300*math.sqrt(2/dof):.2f} K.', '',
             '| viscosity (P) | mean T (K) | rms T (K) | source mean T | source rms T |', '|---|---|---|---|---|']
    lines += [f"| {r['viscosity_poise']} | {r['mean_T']} ± {r['mean_T_error']} | {r['rms_T']} ± {r['rms_T_error']} | "
              f"{r['source_mean_T']} | {r['source_rms_T']} |" for r in rows]
    (out/'table.md').write_text('\n'.join(lines)+'\n', encoding='utf-8')
    print('\n'+'\n'.join(lines)+'\n', flush=True)

    # Heating from 173 K: cool the equilibrated configuration (at 0.01 P, for the reason above), then heat.
    integrator, context = bodies(173, 0.01)
    context.setState(equilibrated)
    integrator.step(int(round(max(2.0, equilibrate_ps/4)/STEP)))
    cold = context.getState(getPositions=True, getVelocities=True)
    curves = {}
    integrator, context = bodies(300, 0.1)
    context.setState(cold)
    curves['RigidLangevin 0.1 P'] = sample(integrator, context, dof, heating_ps)
    for label, make in (('Nose-Hoover 5 ps', lambda: mm.NoseHooverIntegrator(300*unit.kelvin, 0.2/unit.picosecond, STEP*unit.picosecond)),
                        ('NVE', lambda: mm.VerletIntegrator(STEP*unit.picosecond))):
        integrator = make()
        context = mm.Context(system, integrator, platform)
        context.setPositions(cold.getPositions())
        context.setVelocities(cold.getVelocities())
        context.applyConstraints(1e-8)
        context.applyVelocityConstraints(1e-8)
        curves[label] = sample(integrator, context, dof, heating_ps)
    times = np.arange(1, len(curves['NVE'])+1)*10*STEP
    with open(out/'heating.csv', 'w', newline='', encoding='utf-8') as f:
        writer = csv.writer(f)
        writer.writerow(['time_ps']+list(curves))
        writer.writerows(zip(times, *curves.values()))
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for label, values in curves.items():
        ax.plot(times, values, label=label, lw=1)
    ax.axhline(300, color='gray', lw=0.5)
    ax.set_xlabel('time (ps)')
    ax.set_ylabel('temperature (K)')
    ax.set_title(f'{n} {args.model} waters heated from 173 K', fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out/'heating.png', dpi=120)
    # The heating curves on screen: each run's temperature at a few times.
    marks = [t for t in (1, 5, 10, 20, 40, 100) if t <= times[-1]+1e-9]
    print('Heating from 173 K toward 300 K (temperature in K, each a mean over 1 ps):')
    print('| run | '+' | '.join(f'{t:g} ps' for t in marks)+' |')
    for label, values in curves.items():
        means = [np.mean(values[max(0, int(round(t/(10*STEP)))-50):int(round(t/(10*STEP)))]) for t in marks]
        print(f'| {label} | '+' | '.join(f'{m:.0f}' for m in means)+' |')
    print(f'\nresults in {out}/: table.md, temperatures.csv, heating.csv, heating.png', flush=True)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
