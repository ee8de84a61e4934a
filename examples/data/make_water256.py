"""Make water256.pdb: 256 TIP3P waters equilibrated at 300 K in a cubic box of 1.97166 nm, the
configuration of the source's temperature-control experiment (Sun, Lin & Gezelter 2008), and
water64.pdb, 64 waters at the same density (box 1.24208 nm) for the stability study.

    python examples/data/make_water256.py      # writes examples/data/water256.pdb and water64.pdb

Modeller cannot put exactly 256 waters into a given box, so it makes 256 in its own box, the box
is scaled to 1.97166 nm moving whole molecules, and the result is minimized and equilibrated for
50 ps with RigidLangevinIntegrator at 300 K.
"""
import pathlib

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit

import rigidlangevin as rl

def make(waters, BOX, cutoff):
    forcefield = app.ForceField('tip3p.xml')
    modeller = app.Modeller(app.Topology(), [])
    modeller.addSolvent(forcefield, model='tip3p', numAdded=waters)
    old = modeller.topology.getPeriodicBoxVectors()[0][0].value_in_unit(unit.nanometer)
    x = np.array(modeller.positions.value_in_unit(unit.nanometer))
    for residue in modeller.topology.residues():
        atoms = [a.index for a in residue.atoms()]
        centre = x[atoms].mean(axis=0)
        x[atoms] += centre*(BOX/old-1)
    modeller.topology.setPeriodicBoxVectors([mm.Vec3(BOX, 0, 0), mm.Vec3(0, BOX, 0), mm.Vec3(0, 0, BOX)]*unit.nanometer)
    system = forcefield.createSystem(modeller.topology, nonbondedMethod=app.PME, nonbondedCutoff=cutoff*unit.nanometer, rigidWater=True)
    integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.1*rl.poise, 2*unit.femtoseconds)
    integrator.setRandomNumberSeed(2026)
    rl.addRigidBodies(integrator, modeller.topology, system)
    simulation = app.Simulation(modeller.topology, system, integrator, mm.Platform.getPlatformByName('CPU'))
    simulation.context.setPositions([mm.Vec3(*p) for p in x]*unit.nanometer)
    simulation.minimizeEnergy()
    simulation.context.setVelocitiesToTemperature(300*unit.kelvin, 2026)
    simulation.step(25000)
    positions = simulation.context.getState(getPositions=True, enforcePeriodicBox=True).getPositions()
    path = pathlib.Path(__file__).with_name(f'water{waters}.pdb')
    with open(path, 'w', encoding='utf-8') as f:
        app.PDBFile.writeFile(modeller.topology, positions, f)
    print(f'wrote {path}: {modeller.topology.getNumResidues()} waters, box {BOX} nm')


def main():
    make(256, 1.97166, 0.9)
    make(64, 1.97166*(64/256)**(1/3), 0.6)


if __name__ == '__main__':
    main()
