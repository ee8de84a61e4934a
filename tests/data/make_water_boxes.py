"""Writes the equilibrated water boxes that tests/test_water_peers.py starts from: for each model,
a 2 nm box from Modeller.addSolvent, minimized, then 100 ps of LangevinMiddleIntegrator + SETTLE
(300 K, 1/ps, 2 fs, PME 0.9 nm) on the CPU platform. A box cut from Modeller's water relaxes for
tens of picoseconds (the potential energy per molecule moves by 0.5 kJ/mol between 10 and 20 ps),
longer than a test can afford to wait.

    .venv/bin/python tests/data/make_water_boxes.py [model ...]
"""
import pathlib
import sys

import openmm as mm
import openmm.app as app
import openmm.unit as unit

MODELS = ['tip3p', 'spce', 'tip4pew', 'opc', 'tip5p']
HERE = pathlib.Path(__file__).parent


def main(models):
    for model in models:
        forcefield = app.ForceField(f'{model}.xml')
        modeller = app.Modeller(app.Topology(), [])
        # Modeller has no box of OPC; TIP4P-Ew's has the same atoms, and the force field places the site.
        modeller.addSolvent(forcefield, model='tip4pew' if model == 'opc' else model, boxSize=mm.Vec3(2, 2, 2)*unit.nanometer)
        system = forcefield.createSystem(modeller.topology, nonbondedMethod=app.PME, nonbondedCutoff=0.9*unit.nanometer, rigidWater=True)
        integrator = mm.LangevinMiddleIntegrator(300, 1.0, 0.002)
        integrator.setRandomNumberSeed(1)
        simulation = app.Simulation(modeller.topology, system, integrator, mm.Platform.getPlatformByName('CPU'))
        simulation.context.setPositions(modeller.positions)
        simulation.minimizeEnergy()
        simulation.context.setVelocitiesToTemperature(300, 1)
        simulation.step(50000)
        state = simulation.context.getState(getPositions=True, enforcePeriodicBox=True)
        with open(HERE/f'water_{model}.pdb', 'w', encoding='utf-8') as out:
            app.PDBFile.writeFile(modeller.topology, state.getPositions(), out)
        print(model, modeller.topology.getNumResidues(), 'waters written', flush=True)


if __name__ == '__main__':
    main(sys.argv[1:] or MODELS)
