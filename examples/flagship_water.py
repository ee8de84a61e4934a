"""The second example: the source's temperature-control experiment with rigid TIP3P water (the
flagship, examples/ssd_scene.py, replays it with the source's own SSD water).

Sun, Lin & Gezelter (J. Chem. Phys. 128, 234107, 2008) ran 256 SSD waters in a cubic box of
19.7166 A with a 9 A cutoff and 2 fs steps at 300 K under their rigid-body Langevin integrator.
This study runs the same experiment with 256 rigid TIP3P waters (PME, 0.9 nm cutoff) under
RigidLangevinIntegrator's default scheme:

 1. Temperature control: mean and rms temperature at 1, 0.1 and 0.01 poise, beside the source's
    table (300.47, 301.19, 303.04 K), with the standard error of each mean, and the translational
    and rotational temperatures separately.
 2. Heating curve: from a configuration cooled to 173 K, temperature against time under the rigid
    Langevin integrator (0.1 poise), OpenMM's NoseHooverIntegrator (5 ps coupling, SETTLE) and
    zero viscosity (NVE); a CSV and a PNG plot.
 3. The speed of every run in ns/day.

    python examples/flagship_water.py                       # 100 ps per viscosity, 20 ps heating
    python examples/flagship_water.py --control-ps 1000     # the source's 1 ns runs
    python examples/flagship_water.py --control-ps 2 --heating-ps 1 --equilibration-ps 0.2   # a quick check

Results go to --out (default out/flagship): temperature_control.csv and .md, heating_curve.csv
and .png, timings.csv.
"""
import argparse
import csv
import pathlib
import sys
import time

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit
from tqdm import tqdm

import rigidlangevin as rl
from rigidlangevin.statistics import block_error

HERE = pathlib.Path(__file__).resolve().parent
BOX = 1.97166  # nm
STEP = 0.002  # ps
SOURCE_TABLE = {1.0: (300.47, 10.99), 0.1: (301.19, 11.136), 0.01: (303.04, 11.796)}  # poise: (T_avg, T_rms) for SSD


def water_system(pdb):
    forcefield = app.ForceField('tip3p.xml')
    system = forcefield.createSystem(pdb.topology, nonbondedMethod=app.PME, nonbondedCutoff=0.9*unit.nanometer, rigidWater=True,
                                     removeCMMotion=False)  # the bath does not conserve momentum: see docs/user-guide.md
    box = [mm.Vec3(BOX, 0, 0), mm.Vec3(0, BOX, 0), mm.Vec3(0, 0, BOX)]*unit.nanometer
    system.setDefaultPeriodicBoxVectors(*box)
    return system


def rigid_context(pdb, viscosity_poise, temperature, platform, seed):
    """A Context of the water box under RigidLangevinIntegrator (one body per water)."""
    system = water_system(pdb)
    integrator = rl.RigidLangevinIntegrator(temperature*unit.kelvin, viscosity_poise*rl.poise, STEP*unit.picoseconds)
    integrator.setRandomNumberSeed(seed)
    rl.addRigidBodies(integrator, pdb.topology, system)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform))
    return context, integrator


def start(context, pdb, temperature, seed):
    context.setPositions(pdb.positions)
    # The water geometry of the force field (the PDB's is rounded): bodies take it from here.
    context.applyConstraints(1e-10)
    context.setVelocitiesToTemperature(temperature*unit.kelvin, seed)


def run(context, integrator, steps, every, label, sample):
    """Take steps, calling sample() every `every` steps; return the speed in ns/day."""
    begin = time.time()
    # tqdm draws a bar on a terminal and keeps quiet when stderr is a file or a pipe.
    for _ in tqdm(range(steps//every), desc=label, unit_scale=every, unit='step', disable=None, leave=False):
        integrator.step(every)
        sample()
    return steps*STEP*1e-3/((time.time()-begin)/86400)


def temperature_control(pdb, args):
    rows = []
    for viscosity in (1.0, 0.1, 0.01):
        context, integrator = rigid_context(pdb, viscosity, 300.0, args.platform, args.seed)
        start(context, pdb, 300.0, args.seed)
        run(context, integrator, int(args.equilibration_ps/STEP), 50, f'{viscosity} P equilibration', lambda: None)
        total, translational, rotational = [], [], []
        def sample():
            total.append(integrator.computeSystemTemperature().value_in_unit(unit.kelvin))
            translational.append(integrator.computeTranslationalTemperature().value_in_unit(unit.kelvin))
            rotational.append(integrator.computeRotationalTemperature().value_in_unit(unit.kelvin))
        speed = run(context, integrator, int(args.control_ps/STEP), 10, f'{viscosity} P', sample)
        source_mean, source_rms = SOURCE_TABLE[viscosity]
        rows.append({'viscosity (P)': viscosity, 'source <T> (K)': source_mean, 'source T rms (K)': source_rms,
                     '<T> (K)': np.mean(total), 'standard error (K)': block_error(total, 20), 'T rms (K)': np.std(total),
                     '<T translational> (K)': np.mean(translational), '<T rotational> (K)': np.mean(rotational),
                     'ns/day': speed})
    return rows


def heating_curves(pdb, args):
    """Cool to 173 K, then heat under three thermostats; temperature against time."""
    context, integrator = rigid_context(pdb, 1.0, 173.0, args.platform, args.seed)
    start(context, pdb, 173.0, args.seed)
    run(context, integrator, int(args.equilibration_ps/STEP), 50, 'cooling to 173 K', lambda: None)
    cold = context.getState(getPositions=True, getVelocities=True)
    steps, every = int(args.heating_ps/STEP), max(1, int(round(0.05/STEP)))
    curves, speeds = {}, {}

    # RigidLangevinIntegrator at 0.1 poise, and at zero viscosity (NVE).
    for label, viscosity in (('RigidLangevin 0.1 P', 0.1), ('NVE (zero viscosity)', 0.0)):
        context, integrator = rigid_context(pdb, viscosity, 300.0, args.platform, args.seed)
        context.setPositions(cold.getPositions())
        context.setVelocities(cold.getVelocities())
        temperatures = [integrator.computeSystemTemperature().value_in_unit(unit.kelvin)]
        speeds[label] = run(context, integrator, steps, every, label,
                            lambda: temperatures.append(integrator.computeSystemTemperature().value_in_unit(unit.kelvin)))
        curves[label] = temperatures

    # OpenMM's Nose-Hoover thermostat with SETTLE on the same System.
    system = water_system(pdb)
    nose_hoover = mm.NoseHooverIntegrator(300*unit.kelvin, 0.2/unit.picosecond, STEP*unit.picoseconds)
    context = mm.Context(system, nose_hoover, mm.Platform.getPlatformByName(args.platform))
    context.setPositions(cold.getPositions())
    context.setVelocities(cold.getVelocities())
    context.applyConstraints(1e-10)
    context.applyVelocityConstraints(1e-10)
    dof = 3*system.getNumParticles()-system.getNumConstraints()-3
    def temperature():
        return (2*context.getState(getEnergy=True).getKineticEnergy()/(dof*unit.MOLAR_GAS_CONSTANT_R)).value_in_unit(unit.kelvin)
    temperatures = [temperature()]
    label = 'Nose-Hoover 5 ps'
    speeds[label] = run(context, nose_hoover, steps, every, label, lambda: temperatures.append(temperature()))
    curves[label] = temperatures
    times = [i*every*STEP for i in range(len(temperatures))]
    return times, curves, speeds


def write_outputs(out, control, times, curves, heating_speeds):
    out.mkdir(parents=True, exist_ok=True)
    with open(out/'temperature_control.csv', 'w', newline='', encoding='utf-8') as f:
        writer = csv.DictWriter(f, fieldnames=list(control[0]))
        writer.writeheader()
        writer.writerows(control)
    lines = ['| viscosity (P) | source <T> (K) | source T rms (K) | <T> (K) | T rms (K) | <T trans> (K) | <T rot> (K) | ns/day |',
             '|---|---|---|---|---|---|---|---|']
    for r in control:
        lines.append(f"| {r['viscosity (P)']} | {r['source <T> (K)']} | {r['source T rms (K)']} | "
                     f"{r['<T> (K)']:.2f} ± {r['standard error (K)']:.2f} | {r['T rms (K)']:.2f} | "
                     f"{r['<T translational> (K)']:.2f} | {r['<T rotational> (K)']:.2f} | {r['ns/day']:.1f} |")
    (out/'temperature_control.md').write_text('\n'.join(lines)+'\n', encoding='utf-8')
    with open(out/'heating_curve.csv', 'w', newline='', encoding='utf-8') as f:
        writer = csv.writer(f)
        writer.writerow(['time (ps)']+[f'{label} T (K)' for label in curves])
        for i, t in enumerate(times):
            writer.writerow([f'{t:.3f}']+[f'{curves[label][i]:.3f}' for label in curves])
    with open(out/'timings.csv', 'w', newline='', encoding='utf-8') as f:
        writer = csv.writer(f)
        writer.writerow(['run', 'ns/day'])
        for r in control:
            writer.writerow([f"temperature control {r['viscosity (P)']} P", f"{r['ns/day']:.2f}"])
        for label, speed in heating_speeds.items():
            writer.writerow([f'heating: {label}', f'{speed:.2f}'])
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for label, temperatures in curves.items():
        ax.plot(times, temperatures, label=label)
    ax.axhline(300, color='gray', lw=0.8, ls='--')
    ax.set_xlabel('time (ps)')
    ax.set_ylabel('temperature (K)')
    ax.set_title('256 rigid TIP3P waters heated from 173 K to a 300 K bath')
    ax.legend()
    fig.tight_layout()
    fig.savefig(out/'heating_curve.png', dpi=120)
    return '\n'.join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description='The source\'s temperature-control experiment with rigid water.')
    parser.add_argument('--control-ps', type=float, default=100.0, help='length of each temperature-control run (ps, default 100; the source used 1000)')
    parser.add_argument('--heating-ps', type=float, default=20.0, help='length of each heating run (ps, default 20)')
    parser.add_argument('--equilibration-ps', type=float, default=10.0, help='equilibration before each run (ps, default 10)')
    parser.add_argument('--platform', default='CPU', help='OpenMM platform (default CPU)')
    parser.add_argument('--seed', type=int, default=1, help='random seed (default 1)')
    parser.add_argument('--out', default='out/flagship', help='output directory (default out/flagship)')
    args = parser.parse_args(argv)
    pdb = app.PDBFile(str(HERE/'data'/'water256.pdb'))
    print(f'256 rigid TIP3P waters, box {BOX} nm, PME 0.9 nm, 2 fs, platform {args.platform}')
    print('1. Temperature control at 300 K')
    control = temperature_control(pdb, args)
    print('2. Heating curves from 173 K')
    times, curves, speeds = heating_curves(pdb, args)
    table = write_outputs(pathlib.Path(args.out), control, times, curves, speeds)
    print(table)
    print('Heating (mean temperature over the last quarter of each run):')
    for label, temperatures in curves.items():
        print(f'  {label:22s} {np.mean(temperatures[-max(1, len(temperatures)//4):]):7.1f} K   {speeds[label]:.1f} ns/day')
    print(f'Results in {args.out}/: temperature_control.csv/.md, heating_curve.csv/.png, timings.csv')
    return 0


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    sys.exit(main())
