"""End to end: a box of rigid TIP3P water (about 4000 molecules, PME) with RigidLangevinIntegrator
(each water one rigid body; the water constraints of the System are inside bodies and ignored)
against LangevinMiddleIntegrator with SETTLE, on the same platform and the same System, timed in
alternating pairs of blocks. Reports the mean time per step of each and their ratio pair by pair,
with its standard error.

    python benchmarks/platforms/water_box.py [--box 5.0] [--platforms CPU OpenCL CUDA] [--pairs 6]
"""
import sys
import argparse

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit

import rigidlangevin as rl
from benchmark_utils import mean_and_error, paired_times, platform_status, running_context, save_plot, write_table


def build_water_box(box):
    """A System of rigid TIP3P water in a cubic box (nm) with PME, and exactly rigid positions."""
    forcefield = app.ForceField('amber14/tip3p.xml')
    modeller = app.Modeller(app.Topology(), [])
    modeller.addSolvent(forcefield, boxSize=mm.Vec3(box, box, box)*unit.nanometer)
    system = forcefield.createSystem(modeller.topology, nonbondedMethod=app.PME, nonbondedCutoff=0.9*unit.nanometer,
                                     constraints=None, rigidWater=True, removeCMMotion=False)
    # Make the waters exactly rigid (the pre-equilibrated box is written to 1e-4 nm), so that they
    # are all one body type, and relax the packing briefly.
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName('CPU'))
    context.setPositions(modeller.positions)
    context.applyConstraints(1e-10)
    mm.LocalEnergyMinimizer.minimize(context, 10.0, 50)
    context.applyConstraints(1e-10)
    positions = context.getState(getPositions=True).getPositions(asNumpy=True)
    waters = [[atom.index for atom in residue.atoms()] for residue in modeller.topology.residues()]
    return system, positions, waters


def rigid_integrator(system, waters):
    integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.89*rl.centipoise, 2*unit.femtoseconds)
    for atoms in waters:
        integrator.addRigidBody(atoms)
        for atom in atoms:
            if system.getParticleMass(atom).value_in_unit(unit.dalton) < 2:
                integrator.setParticleRadius(atom, 0.1*unit.nanometer)  # hydrogens: TIP3P gives them no LJ radius
    return integrator


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--box', type=float, default=5.0, help='box edge in nm (5 nm: about 4100 waters)')
    parser.add_argument('--platforms', nargs='+', default=['CPU', 'OpenCL', 'CUDA'])
    parser.add_argument('--steps', type=int, default=0, help='steps per timing block (default: by platform; a multiple of four, as integrator_cost.steps_for says why)')
    parser.add_argument('--pairs', type=int, default=6, help='alternating pairs of timed blocks (RigidLangevin, LangevinMiddle)')
    parser.add_argument('--precisions', nargs='+', default=['single', 'mixed'], help='GPU precisions (double too on a GPU machine)')
    parser.add_argument('--name', default='water_box', help='results/<name>.csv and .png (e.g. water_box_gpu for a GPU machine)')
    args = parser.parse_args()
    system, positions, waters = build_water_box(args.box)
    print(f'{len(waters)} waters, {system.getNumParticles()} particles, PME, cutoff 0.9 nm, 2 fs', flush=True)
    rows = []
    for name in args.platforms:
        status = platform_status(name)
        if status is not None:
            rows.append({'platform': name, 'precision': '-', 'note': status})
            continue
        precisions = args.precisions if name in ('OpenCL', 'CUDA') else ['']
        for precision in precisions:
            properties = {'Precision': precision} if precision else {}
            steps = args.steps or (100 if name == 'CUDA' else 40)
            # Alternate the two integrators so that both see the same machine load.
            contexts = {}
            for kind in ('rigid', 'middle'):
                if kind == 'rigid':
                    integrator = rigid_integrator(system, waters)
                else:
                    integrator = mm.LangevinMiddleIntegrator(300*unit.kelvin, 1/unit.picosecond, 2*unit.femtoseconds)
                contexts[kind] = (integrator, running_context(system, integrator, positions, name, properties, warmup_steps=10))
            times = paired_times(contexts, steps, args.pairs)
            rigid, middle = np.mean(times['rigid']), np.mean(times['middle'])
            ratio, ratio_error = mean_and_error(np.array(times['rigid'])/np.array(times['middle']))
            row = {'platform': name, 'precision': precision or 'double/single (CPU platform)', 'waters': len(waters),
                   'pairs': args.pairs, 'steps': steps, 'rigid_langevin_ms_per_step': f'{1e3*rigid:.4g}',
                   'langevin_middle_settle_ms_per_step': f'{1e3*middle:.4g}', 'ratio': f'{ratio:.3f}', 'ratio_se': f'{ratio_error:.3f}',
                   'rigid_ns_per_day': f'{0.002*86400/rigid/1e3:.3g}', 'middle_ns_per_day': f'{0.002*86400/middle/1e3:.3g}'}
            rows.append(row)
            print(row, flush=True)
            del contexts
    columns = ['platform', 'precision', 'waters', 'pairs', 'steps', 'rigid_langevin_ms_per_step', 'langevin_middle_settle_ms_per_step',
               'ratio', 'ratio_se', 'rigid_ns_per_day', 'middle_ns_per_day', 'note']
    write_table(args.name, columns, rows)
    plot(rows, args.name)


def plot(rows, name):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    measured = [r for r in rows if r.get('ratio')]
    labels = [f"{r['platform']}\n{r['precision'].split()[0]}" for r in measured]
    x = np.arange(len(measured))
    fig, ax = plt.subplots(figsize=(max(5, 1.8*len(measured)+2), 4))
    ax.bar(x-0.2, [float(r['rigid_langevin_ms_per_step']) for r in measured], 0.4, label='RigidLangevinIntegrator (rigid bodies)')
    ax.bar(x+0.2, [float(r['langevin_middle_settle_ms_per_step']) for r in measured], 0.4, label='LangevinMiddleIntegrator + SETTLE')
    for i, r in enumerate(measured):
        ax.text(i, max(float(r['rigid_langevin_ms_per_step']), float(r['langevin_middle_settle_ms_per_step']))*1.02,
                f"ratio {r['ratio']}" + (f" +- {r['ratio_se']}" if r.get('ratio_se') else ''), ha='center', fontsize=9)
    if measured:  # room above the tallest bar for its ratio
        ax.set_ylim(top=1.12*max(max(float(r['rigid_langevin_ms_per_step']), float(r['langevin_middle_settle_ms_per_step'])) for r in measured))
    ax.set_xticks(x, labels)
    ax.set_ylabel('time per step (ms, mean over pairs)')
    missing = [r['platform'] for r in rows if not r.get('ratio')]
    title = f"{measured[0]['waters'] if measured else ''} rigid TIP3P waters, PME"
    if missing:
        title += f" ({', '.join(missing)}: not available here)"
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc='lower right')
    save_plot(fig, name)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
