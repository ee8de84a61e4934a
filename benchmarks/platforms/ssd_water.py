"""Single-site against three-site water: SSD/RF waters (StickyDipoleForce, reaction field, each
water a rigid body under RigidLangevinIntegrator at 0.01 P) against TIP3P with PME under
LangevinMiddleIntegrator + SETTLE, in the same cubic box (same edge, each model's own liquid
density), on the same platform, 2 fs steps, timed in alternating pairs of blocks. Reports ns/day
of each (from the mean time per step) and their ratio pair by pair with its standard error.

    python benchmarks/platforms/ssd_water.py [--boxes 1.97166 4.0] [--platforms CPU OpenCL CUDA] [--pairs 6]

The default boxes are the source's scene (19.7166 A, 256 SSD waters, 9 A cutoff) and a 4 nm box
(about 2100 waters); cutoffs are 0.9 nm for both models.
"""
import sys
import argparse

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit

import rigidlangevin as rl
from benchmark_utils import calibrated_steps, mean_and_error, paired_times, platform_status, running_context, save_plot, write_table

STICKY_KERNEL = 'CalcStickyDipoleForce'


def ssd_box(edge):
    """SSD/RF waters at the liquid's density (the source's 256 in 19.7166 A), minimised, and their integrator."""
    n = int(round(256*(edge/1.97166)**3))
    topology, system, positions = rl.ssd.waterBox(n, model='SSD/RF', boxSize=edge*unit.nanometer)
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName('CPU'))
    context.setPositions(positions)
    mm.LocalEnergyMinimizer.minimize(context, 10.0, 200)
    positions = context.getState(getPositions=True).getPositions()

    def integrator():
        rigid = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.01*rl.poise, 2*unit.femtoseconds)
        rl.addRigidBodies(rigid, topology, system, residues='water', positions=positions)
        return rigid
    return n, system, positions, integrator


def tip3p_box(edge):
    """TIP3P water filling the same box (Modeller's equilibrated water), PME with a 0.9 nm cutoff."""
    forcefield = app.ForceField('amber14/tip3p.xml')
    modeller = app.Modeller(app.Topology(), [])
    modeller.addSolvent(forcefield, boxSize=mm.Vec3(edge, edge, edge)*unit.nanometer)
    system = forcefield.createSystem(modeller.topology, nonbondedMethod=app.PME, nonbondedCutoff=0.9*unit.nanometer,
                                     constraints=app.HBonds, rigidWater=True, removeCMMotion=False)
    n = modeller.topology.getNumResidues()
    return n, system, modeller.positions, lambda: mm.LangevinMiddleIntegrator(300*unit.kelvin, 1/unit.picosecond, 2*unit.femtoseconds)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--boxes', type=float, nargs='+', default=[1.97166, 4.0], help='box edges in nm')
    parser.add_argument('--platforms', nargs='+', default=['CPU', 'OpenCL', 'CUDA'])
    parser.add_argument('--steps', type=int, default=48, help='steps per timing block to start calibrating from (a multiple of four, as integrator_cost.steps_for says why)')
    parser.add_argument('--pairs', type=int, default=6, help='alternating pairs of timed blocks (SSD/RF, TIP3P)')
    parser.add_argument('--name', default='ssd_water', help='results/<name>.csv and .png')
    args = parser.parse_args()
    rows = []
    for edge in args.boxes:
        models = {'ssd': ssd_box(edge), 'tip3p': tip3p_box(edge)}
        for name in args.platforms:
            status = platform_status(name)
            if status is None and not mm.Platform.getPlatformByName(name).supportsKernels([STICKY_KERNEL]):
                status = 'no StickyDipoleForce kernel for this platform yet'
            if status is not None:
                rows.append({'box_nm': edge, 'platform': name, 'note': status})
                continue
            properties = {'Precision': 'mixed'} if name in ('OpenCL', 'CUDA') else {}
            contexts = {}
            for model, (n, system, positions, make_integrator) in models.items():
                integrator = make_integrator()
                contexts[model] = (integrator, running_context(system, integrator, positions, name, properties, warmup_steps=10))
            # Blocks of the faster model calibrated to last 0.3 s, fourfold at a time (still a multiple of four).
            times = paired_times(contexts, calibrated_steps(*contexts['ssd'], args.steps), args.pairs)
            del contexts
            ssd, tip3p = np.mean(times['ssd']), np.mean(times['tip3p'])
            speedup, speedup_error = mean_and_error(np.array(times['tip3p'])/np.array(times['ssd']))
            row = {'box_nm': edge, 'platform': name, 'precision': properties.get('Precision', 'CPU platform'),
                   'ssd_waters': models['ssd'][0], 'tip3p_waters': models['tip3p'][0], 'pairs': args.pairs,
                   'ssd_ns_per_day': f'{0.002*86400/ssd/1e3:.3g}', 'tip3p_ns_per_day': f'{0.002*86400/tip3p/1e3:.3g}',
                   'speedup': f'{speedup:.2f}', 'speedup_se': f'{speedup_error:.2f}'}
            rows.append(row)
            print(row, flush=True)
    columns = ['box_nm', 'platform', 'precision', 'ssd_waters', 'tip3p_waters', 'pairs', 'ssd_ns_per_day', 'tip3p_ns_per_day', 'speedup',
               'speedup_se', 'note']
    write_table(args.name, columns, rows)
    plot(rows, args.name)


def plot(rows, name):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    measured = [r for r in rows if r.get('speedup')]
    labels = [f"{r['platform']}\n{r['box_nm']} nm" for r in measured]
    x = np.arange(len(measured))
    fig, ax = plt.subplots(figsize=(max(5, 1.8*len(measured)+2), 4))
    ax.bar(x-0.2, [float(r['ssd_ns_per_day']) for r in measured], 0.4, label='SSD/RF, RigidLangevinIntegrator')
    ax.bar(x+0.2, [float(r['tip3p_ns_per_day']) for r in measured], 0.4, label='TIP3P PME, LangevinMiddle + SETTLE')
    for i, r in enumerate(measured):
        ax.text(i, max(float(r['ssd_ns_per_day']), float(r['tip3p_ns_per_day']))*1.02, f"{r['speedup']} +- {r['speedup_se']}x", ha='center', fontsize=9)
    if measured:  # room above the tallest bar for its speed-up
        ax.set_ylim(top=1.12*max(max(float(r['ssd_ns_per_day']), float(r['tip3p_ns_per_day'])) for r in measured))
    ax.set_xticks(x, labels)
    ax.set_ylabel('ns/day (from the mean time per step)')
    missing = sorted({r['platform'] for r in rows if not r.get('speedup')})
    title = 'single-site SSD/RF against TIP3P water, same box'
    if missing:
        title += f" ({', '.join(missing)}: not measured)"
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8)
    save_plot(fig, name)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
