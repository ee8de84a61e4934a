"""removeInternalInteractions: the interactions rigid bodies make constant are removed, and nothing else.

The exact claim: without friction the dynamics are deterministic, and removing interactions whose
net force and torque on every body are zero leaves the trajectory the same to round-off, while the
potential energy drops by a constant, the one the call reports. Each check has a control that
breaks the claim slightly (one pair between two bodies excluded as well) and must be seen.
"""
import os
import warnings

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit
import pytest

import rigidlangevin as rl

VILLIN = os.path.join(os.path.dirname(app.__file__), 'data', 'test.pdb')


def villin_fragment(residues, nonbondedMethod, implicit):
    """The first residues of villin HP35 (OpenMM's test.pdb, no water), amber14, every residue a rigid body."""
    pdb = app.PDBFile(VILLIN)
    modeller = app.Modeller(pdb.topology, pdb.positions)
    keep = list(modeller.topology.residues())[:residues]
    modeller.delete([r for r in modeller.topology.residues() if r not in keep])
    cap_c_terminus(modeller)
    files = ['amber14-all.xml'] + (['implicit/obc2.xml'] if implicit else [])
    forcefield = app.ForceField(*files)
    positions = modeller.positions
    if nonbondedMethod in (app.PME, app.CutoffPeriodic):
        modeller.topology.setPeriodicBoxVectors(np.eye(3)*3.5*unit.nanometer)
    system = forcefield.createSystem(modeller.topology, nonbondedMethod=nonbondedMethod, nonbondedCutoff=1.0*unit.nanometer,
                                     constraints=None, rigidWater=False)
    if nonbondedMethod in (app.PME, app.CutoffPeriodic):
        # A CustomNonbondedForce beside the NonbondedForce, with the same exclusions, as force fields make them.
        extra = mm.CustomNonbondedForce('1e-3/r^6')
        extra.setNonbondedMethod(mm.CustomNonbondedForce.CutoffPeriodic)
        extra.setCutoffDistance(1.0)
        nonbonded = next(f for f in system.getForces() if isinstance(f, mm.NonbondedForce))
        for i in range(system.getNumParticles()):
            extra.addParticle([])
        for i in range(nonbonded.getNumExceptions()):
            extra.addExclusion(*nonbonded.getExceptionParameters(i)[:2])
        system.addForce(extra)
    return modeller.topology, system, positions


def cap_c_terminus(modeller):
    """Give the cut chain's last residue its terminal oxygen, opposite CA and O about C, so that it matches a template."""
    last = list(modeller.topology.residues())[-1]
    atoms = {atom.name: atom for atom in last.atoms()}
    xyz = {name: np.array(modeller.positions[atom.index].value_in_unit(unit.nanometer)) for name, atom in atoms.items()}
    away = (xyz['C']-xyz['CA'])/np.linalg.norm(xyz['C']-xyz['CA']) + (xyz['C']-xyz['O'])/np.linalg.norm(xyz['C']-xyz['O'])
    oxt = modeller.topology.addAtom('OXT', app.element.oxygen, last)
    modeller.topology.addBond(atoms['C'], oxt)
    modeller.positions = list(modeller.positions) + [mm.Vec3(*(xyz['C'] + 0.125*away/np.linalg.norm(away)))*unit.nanometer]


def residue_bodies(topology):
    return [[atom.index for atom in residue.atoms()] for residue in topology.residues()]


def run(topology, system, positions, steps, every=50):
    """Positions and potential energies every `every` steps without friction, on Reference; each residue a body."""
    integrator = rl.RigidLangevinIntegrator(300, 0, 0.002)
    rl.addRigidBodies(integrator, topology, system, residues=lambda residue: True)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300, 5)
    trajectory, energies = [], []
    for _ in range(steps//every):
        integrator.step(every)
        state = context.getState(getPositions=True, getEnergy=True)
        trajectory.append(state.getPositions(asNumpy=True).value_in_unit(unit.nanometer))
        energies.append(state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))
    return np.array(trajectory), np.array(energies)


def exclude_one_pair_between(system, bodies):
    """The control: one pair between two different bodies excluded too, a change the trajectory must show."""
    a, b = bodies[0][0], bodies[2][0]
    for force in system.getForces():
        if isinstance(force, mm.NonbondedForce):
            force.addException(a, b, 0.0, 1.0, 0.0, True)


@pytest.mark.parametrize('method, implicit', [(app.NoCutoff, True), (app.PME, False), (app.CutoffPeriodic, False)],
                         ids=['NoCutoff-OBC2', 'PME', 'ReactionField'])
def test_same_trajectory_constant_energy_shift(method, implicit):
    topology, system, positions = villin_fragment(8, method, implicit)
    bodies = residue_bodies(topology)
    reference = mm.XmlSerializer.clone(system)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always')
        report = rl.removeInternalInteractions(system, bodies, positions)
    # The GB force couples the bodies: kept, and said so; nothing else is left alone.
    assert report.leftAlone == (['CustomGBForce (force 5)'] if implicit else []), report
    assert [str(w.message) for w in caught if 'left these forces' in str(w.message)] == \
        ([f'removeInternalInteractions left these forces as they are (their interactions inside bodies are still computed, exactly): '
          f'CustomGBForce (force 5)'] if implicit else [])
    pairs = sum(len(b)*(len(b)-1)//2 for b in bodies)
    assert set(report.excludedPairs.values()) == {pairs}
    assert report.zeroedTerms and report.removedForces == []
    offset = report.energyOffset.value_in_unit(unit.kilojoule_per_mole)

    steps = 1000
    x0, e0 = run(topology, reference, positions, steps)
    x1, e1 = run(topology, system, positions, steps)
    # Round-off: the removed forces cancel in each body's force and torque only to the last bits, and
    # 1000 steps amplify that little (measured: at most 8e-14 nm). The bound is a thousand times that;
    # the control below moves particles by 5e-3 nm or more.
    assert np.max(np.abs(x1-x0)) < 1e-10, np.max(np.abs(x1-x0))
    # The energy shift is the reported constant at every sample, to the round-off of energies of this
    # size (measured: at most 3e-11 kJ/mol of 1e3).
    scale = 1e-12*max(np.max(np.abs(e0)), abs(offset))
    assert np.max(np.abs((e0-e1)-offset)) < 100*scale, (e0-e1-offset)
    # ...and the bodies did move (a shift equal only because nothing moved would prove nothing).
    assert np.max(np.abs(x0[-1]-x0[0])) > 0.1

    # The control: one more excluded pair, between two bodies, and the trajectory must differ.
    exclude_one_pair_between(system, bodies)
    x2, _ = run(topology, system, positions, steps)
    assert np.max(np.abs(x2-x0)) > 1e-4, np.max(np.abs(x2-x0))


def test_lone_protein_loses_every_force():
    """Villin HP35 as one body in implicit solvent: every force is inside the body, so all go, and
    the energy they leave behind is the whole potential energy."""
    pdb = app.PDBFile(VILLIN)
    modeller = app.Modeller(pdb.topology, pdb.positions)
    modeller.deleteWater()
    modeller.delete([r for r in modeller.topology.residues() if r.name.upper() in ('CL', 'NA')])
    system = app.ForceField('amber14-all.xml', 'implicit/obc2.xml').createSystem(modeller.topology, nonbondedMethod=app.NoCutoff)
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName('Reference'))
    context.setPositions(modeller.positions)
    energy = context.getState(getEnergy=True).getPotentialEnergy()
    integrator = rl.RigidLangevinIntegrator(293, 1*rl.centipoise, 0.002)
    bodies = rl.addRigidBodies(integrator, modeller.topology, system, residues=lambda r: True, positions=None)
    assert len(bodies) == 35 and bodies.internalInteractions is None
    one = rl.RigidLangevinIntegrator(293, 1*rl.centipoise, 0.002)
    one.addRigidBody(list(range(system.getNumParticles())))
    report = rl.removeInternalInteractions(system, one, modeller.positions)
    names = {type(f).__name__ for f in system.getForces()}
    assert names <= {'CMMotionRemover'}, names
    assert {'NonbondedForce', 'CustomGBForce', 'PeriodicTorsionForce', 'HarmonicBondForce', 'HarmonicAngleForce'} <= \
        {name.split(' ')[0] for name in report.removedForces}
    assert report.energyOffset.value_in_unit(unit.kilojoule_per_mole) == pytest.approx(energy.value_in_unit(unit.kilojoule_per_mole), rel=1e-12)


def test_add_rigid_bodies_option_matches_the_call():
    """addRigidBodies(..., removeInternalInteractions=True) does what the call does for its new bodies."""
    topology, system, positions = villin_fragment(4, app.NoCutoff, False)
    direct = mm.XmlSerializer.clone(system)
    integrator = rl.RigidLangevinIntegrator(300, 0, 0.002)
    bodies = rl.addRigidBodies(integrator, topology, system, residues=lambda r: True, positions=positions, removeInternalInteractions=True)
    report = rl.removeInternalInteractions(direct, residue_bodies(topology), positions)
    assert bodies.internalInteractions.energyOffset.value_in_unit(unit.kilojoule_per_mole) == \
        pytest.approx(report.energyOffset.value_in_unit(unit.kilojoule_per_mole), rel=1e-12)
    assert bodies.internalInteractions.excludedPairs == report.excludedPairs


def test_bad_input_is_named():
    topology, system, positions = villin_fragment(3, app.PME, False)
    bodies = residue_bodies(topology)
    with pytest.raises(ValueError, match='particle 0 is in body 0 and body 1'):
        rl.removeInternalInteractions(system, [bodies[0], bodies[0]], positions)
    with pytest.raises(ValueError, match='holds particle 99999'):
        rl.removeInternalInteractions(system, [[0, 99999]], positions)
    small = mm.XmlSerializer.clone(system)
    small.setDefaultPeriodicBoxVectors(*(np.eye(3)*0.3))
    with pytest.raises(ValueError, match='body 0 is .* nm across, more than half the periodic box'):
        rl.removeInternalInteractions(small, bodies, positions)
