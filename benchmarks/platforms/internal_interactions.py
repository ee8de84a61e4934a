"""What removing the interactions inside rigid bodies saves (rigidlangevin.removeInternalInteractions).

Two scenes, each timed with and without the removal on the same platform, in alternating pairs of
blocks in one run (the speed-up taken pair by pair, with its standard error):

- villin: villin HP35 (OpenMM's test.pdb, protein only, 582 atoms), amber14-all with implicit/obc2,
  no cutoff, as one rigid body at 20 C in water. Every force is inside the body, so all go.
- colloids: 50 rigid colloids of 92 Lennard-Jones beads each (an icosphere of radius 1.5 nm),
  CutoffPeriodic 1.2 nm, volume fraction 0.1. Pairs within a colloid become exclusions.

    python benchmarks/platforms/internal_interactions.py [--platforms CPU OpenCL] [--name internal_interactions]

Writes results/<name>.csv and .png: mean ms per step with and without, and their ratio +- its standard error.
"""
import sys
import argparse
import os

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit

import rigidlangevin as rl
from benchmark_utils import (calibrated_steps, mean_and_error, paired_times, platform_properties, platform_status, running_context,
                             save_plot, write_table)

VILLIN = os.path.join(os.path.dirname(app.__file__), 'data', 'test.pdb')


def villin():
    """Villin HP35 in implicit solvent: (System, positions, particles of the one body)."""
    pdb = app.PDBFile(VILLIN)
    modeller = app.Modeller(pdb.topology, pdb.positions)
    modeller.delete([r for r in modeller.topology.residues() if r.name.upper() in ('HOH', 'CL', 'NA')])
    system = app.ForceField('amber14-all.xml', 'implicit/obc2.xml').createSystem(modeller.topology, nonbondedMethod=app.NoCutoff, removeCMMotion=False)
    return system, modeller.positions, [list(range(system.getNumParticles()))]


def icosphere(radius, subdivisions=2):
    """Points on a sphere: an icosahedron's vertices with each edge split `subdivisions` times (92 for 2)."""
    t = (1+5**0.5)/2
    vertices = [np.array(v, float) for v in [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                                                (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
             (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    points = {tuple(np.round(v/np.linalg.norm(v), 9)) for v in vertices}
    n = subdivisions+1
    for a, b, c in faces:
        for i in range(n+1):
            for j in range(n+1-i):
                p = (vertices[a]*(n-i-j) + vertices[b]*i + vertices[c]*j)/n
                points.add(tuple(np.round(p/np.linalg.norm(p), 9)))
    return radius*np.array(sorted(points))


def colloids(count=50, radius=1.5, fraction=0.1, seed=1):
    """Rigid Lennard-Jones colloids on a cubic lattice, randomly turned: (System, positions, bodies)."""
    shell = icosphere(radius)
    edge = (count*4/3*np.pi*(radius+0.2)**3/fraction)**(1/3)
    side = int(np.ceil(count**(1/3)))
    rng = np.random.default_rng(seed)
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(edge, 0, 0), mm.Vec3(0, edge, 0), mm.Vec3(0, 0, edge))
    nonbonded = mm.NonbondedForce()
    nonbonded.setNonbondedMethod(mm.NonbondedForce.CutoffPeriodic)
    nonbonded.setCutoffDistance(1.2)
    positions, bodies = [], []
    for k in range(count):
        centre = (np.array([k % side, (k//side) % side, k//side**2])+0.5)*edge/side
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        bodies.append([])
        for point in shell:
            bodies[-1].append(system.addParticle(20.0))
            nonbonded.addParticle(0.0, 0.4, 1.0)
            positions.append(mm.Vec3(*(centre+q@point)))
    system.addForce(nonbonded)
    return system, positions*unit.nanometer, bodies


def contexts(system, positions, bodies, platform, properties):
    """Two running Contexts of the scene: as built, and with the interactions inside bodies removed."""
    made = {}
    for removed in (False, True):
        copy = mm.XmlSerializer.clone(system)
        integrator = rl.RigidLangevinIntegrator(293*unit.kelvin, 1*rl.centipoise, 2*unit.femtoseconds)
        for particles in bodies:
            integrator.addRigidBody(particles)
        for p in range(copy.getNumParticles()):
            integrator.setParticleRadius(p, 0.15)  # hydrodynamics is not what is timed: the same for both
        if removed:
            report = rl.removeInternalInteractions(copy, integrator, positions)
        made[removed] = (integrator, running_context(copy, integrator, positions, platform, properties, warmup_steps=5))
    return made, report


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--platforms', nargs='+', default=['CPU', 'OpenCL'])
    parser.add_argument('--steps', type=int, default=20, help='steps per timing block to start calibrating from')
    parser.add_argument('--pairs', type=int, default=5, help='alternating pairs of timed blocks (with and without the removal)')
    parser.add_argument('--name', default='internal_interactions', help='results/<name>.csv and .png')
    args = parser.parse_args()
    rows = []
    for scene, build in (('villin HP35, one body, OBC2', villin), ('50 colloids of 92 beads', colloids)):
        system, positions, bodies = build()
        for platform in args.platforms:
            why = platform_status(platform)
            if why:
                print(f'{platform}: {why}')
                continue
            made, report = contexts(system, positions, bodies, platform, platform_properties(platform, 'mixed'))
            # In turn over several pairs, so that both see the same machine load; each one's blocks
            # calibrated to last 0.3 s (a step without forces takes microseconds).
            steps = {key: calibrated_steps(integrator, context, args.steps) for key, (integrator, context) in made.items()}
            times = paired_times(made, steps, args.pairs)
            speedup, speedup_error = mean_and_error(np.array(times[False])/np.array(times[True]))
            rows.append({'scene': scene, 'platform': platform, 'particles': system.getNumParticles(), 'bodies': len(bodies),
                         'pairs': args.pairs, 'ms_per_step_all': f'{1e3*np.mean(times[False]):.4f}',
                         'ms_per_step_removed': f'{1e3*np.mean(times[True]):.4f}',
                         'speedup': f'{speedup:.3g}', 'speedup_se': f'{speedup_error:.2g}',
                         'removed_forces': len(report.removedForces), 'excluded_pairs': sum(report.excludedPairs.values()),
                         'energy_offset_kJ_per_mol': f'{report.energyOffset.value_in_unit(unit.kilojoule_per_mole):.2f}'})
    write_table(args.name, ['scene', 'platform', 'particles', 'bodies', 'pairs', 'ms_per_step_all', 'ms_per_step_removed', 'speedup',
                            'speedup_se', 'removed_forces', 'excluded_pairs', 'energy_offset_kJ_per_mol'], rows)
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 3.5))
    labels = [f"{r['scene']}\n{r['platform']}" for r in rows]
    y = np.arange(len(rows))
    ax.barh(y+0.2, [float(r['ms_per_step_all']) for r in rows], 0.4, label='all interactions')
    ax.barh(y-0.2, [float(r['ms_per_step_removed']) for r in rows], 0.4, label='inside bodies removed')
    ax.set_yticks(y, labels)
    ax.set_xscale('log')
    ax.set_xlabel('ms per step (2 fs)')
    ax.legend()
    save_plot(fig, args.name)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
