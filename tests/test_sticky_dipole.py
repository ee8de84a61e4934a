"""StickyDipoleForce from Python: parameters with units, named models, XmlSerializer and copies,
and the SSD water box builder (geometry, inertia, a short run of rigid bodies). The force's
physics is tested in C++ (tests/TestStickyDipoleForce.h) against a direct sum and finite
differences; here the wrapper must pass the same numbers through."""
import copy
import io

import numpy as np
import openmm as mm
import openmm.unit as unit
import pytest

import rigidlangevin as rl

DEBYE = 0.0208194  # e*nm


def test_named_models_have_the_published_parameters():
    # Fennell & Gezelter, J. Chem. Phys. 120, 9175 (2004): SSD/RF sigma 3.019 A, epsilon 0.152 kcal/mol,
    # dipole 2.48 D, nu0 3.90 kcal/mol, rL 2.40, rU 3.80, rL' 2.75, rU' 3.35 A, w0 0.07715.
    p = rl.StickyDipoleForce.getModelParameters('SSD/RF')
    assert p['sigma'].value_in_unit(unit.angstrom) == pytest.approx(3.019, rel=1e-12)
    assert p['epsilon'].value_in_unit(unit.kilocalorie_per_mole) == pytest.approx(0.152, rel=1e-12)
    assert p['dipole'].value_in_unit(unit.elementary_charge*unit.nanometer) == pytest.approx(2.48*DEBYE, rel=1e-12)
    assert p['nu0'].value_in_unit(unit.kilocalorie_per_mole) == pytest.approx(3.90, rel=1e-12)
    assert p['nu0Prime'] == p['nu0']
    assert [p[k].value_in_unit(unit.angstrom) for k in ('rL', 'rU', 'rLPrime', 'rUPrime')] == pytest.approx([2.40, 3.80, 2.75, 3.35])
    assert p['w0'] == 0.07715
    with pytest.raises(mm.OpenMMException, match='SSD, SSD1'):
        rl.StickyDipoleForce.getModelParameters('TIP3P')


def test_sites_take_quantities_and_keywords():
    force = rl.StickyDipoleForce()
    force.addSite(3, 1, 2, 'SSD', dipole=2.2*DEBYE*unit.elementary_charge*unit.nanometer, rU=0.34*unit.nanometer, w0=0.05)
    force.addSite(7, 5, 6, sigma=3.0*unit.angstrom, epsilon=0.5)
    particle, r1, r2, p = force.getSiteParameters(0)
    assert (particle, r1, r2) == (3, 1, 2)
    assert p['dipole'].value_in_unit(unit.elementary_charge*unit.nanometer) == pytest.approx(2.2*DEBYE)
    assert p['rU'].value_in_unit(unit.nanometer) == pytest.approx(0.34)
    assert p['w0'] == 0.05
    assert p['sigma'] == rl.StickyDipoleForce.getModelParameters('SSD')['sigma']
    q = force.getSiteParameters(1)[3]
    assert q['sigma'].value_in_unit(unit.nanometer) == pytest.approx(0.3)
    assert q['nu0'].value_in_unit(unit.kilojoule_per_mole) == 0
    with pytest.raises(TypeError, match='unknown site parameters'):
        force.addSite(0, 1, 2, 'SSD', radius=1.0)
    force.setCutoffDistance(9*unit.angstrom)
    assert force.getCutoffDistance() == 0.9*unit.nanometer


def test_molecule_has_the_ssd_inertia():
    # OpenMD's forceFields/Water.frc: I_xx, I_yy, I_zz = 1.7696, 0.6145, 1.1550 amu A^2 for the SSD family.
    geometry = rl.ssd.moleculeGeometry()*10  # A
    masses = np.array([rl.ssd.OXYGEN_MASS, rl.ssd.HYDROGEN_MASS, rl.ssd.HYDROGEN_MASS, 0.0])
    assert masses.sum() == pytest.approx(18.0153, abs=1e-4)
    assert np.allclose(masses@geometry, 0, atol=1e-12)
    inertia = [sum(m*(r@r-r[k]**2) for m, r in zip(masses, geometry)) for k in range(3)]
    assert inertia == pytest.approx([1.7696, 0.6145, 1.1550], abs=2e-4)


def test_xml_round_trip_and_copies(sticky_dipole_platform):
    platform = sticky_dipole_platform
    topology, system, positions = rl.ssd.waterBox(27, boxSize=0.93*unit.nanometer, cutoff=0.45*unit.nanometer)
    copied = mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(system))
    force = rl.StickyDipoleForce.cast(copied.getForce(0))
    assert force.getNumSites() == 27
    assert force.getSwitchingDistance().value_in_unit(unit.nanometer) == pytest.approx(0.85*0.45)
    clone = copy.deepcopy(rl.StickyDipoleForce.cast(system.getForce(0)))
    assert clone.getSiteParameters(5) == force.getSiteParameters(5)
    energies = []
    for s in (system, copied):
        context = platform.context(s, mm.VerletIntegrator(0.001))
        context.setPositions(positions)
        energies.append(context.getState(getEnergy=True).getPotentialEnergy())
    assert energies[0] == energies[1]


def test_water_box_runs_as_rigid_bodies(sticky_dipole_platform):
    platform = sticky_dipole_platform
    # 27 SSD/RF waters as bodies at zero viscosity: the molecules stay rigid and the total energy stays
    # within a small fraction of the kinetic energy over 2 ps.
    topology, system, positions = rl.ssd.waterBox(27, boxSize=0.93*unit.nanometer, cutoff=0.45*unit.nanometer)
    # Minimised on Reference: OpenMM 8.6's minimizer kernel crashes on PoCL's OpenCL for any System.
    minimizer = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName('Reference'))
    minimizer.setPositions(positions)
    mm.LocalEnergyMinimizer.minimize(minimizer, 1.0, 500)
    positions = minimizer.getState(getPositions=True).getPositions()
    integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, 0, 0.001*unit.picosecond)
    rl.addRigidBodies(integrator, topology, system, residues='water', positions=positions)
    assert integrator.getNumRigidBodies() == 27
    context = platform.context(system, integrator)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300*unit.kelvin, 3)
    energies, kinetic = [], []
    for _ in range(100):
        integrator.step(20)
        state = context.getState(getEnergy=True, getPositions=True)
        kinetic.append(state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole))
        energies.append(kinetic[-1]+state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))
    xyz = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
    oh = np.linalg.norm(xyz[1::4]-xyz[0::4], axis=1)
    assert np.allclose(oh, rl.ssd.OH_LENGTH, atol=1e-9)
    assert np.std(energies) < 0.01*np.mean(kinetic), (np.std(energies), np.mean(kinetic))


@pytest.mark.parametrize('model', ['SSD', 'SSD1', 'SSD/E', 'SSD/RF'])
def test_force_field_builds_the_same_system(model):
    # openmm.app.ForceField with the <StickyDipoleForce> generator gives the System waterBox builds.
    topology, system, positions = rl.ssd.waterBox(27, model=model, boxSize=0.93*unit.nanometer, cutoff=0.45*unit.nanometer)
    built = rl.ssd.forceField(model).createSystem(topology, nonbondedMethod=mm.app.CutoffPeriodic,
                                                  nonbondedCutoff=0.45*unit.nanometer, removeCMMotion=False)
    assert built.getNumConstraints() == 3*27
    assert all(built.isVirtualSite(4*i+3) for i in range(27))
    forces = [f for f in built.getForces() if rl.StickyDipoleForce.isinstance(f)]
    assert len(forces) == 1
    force = rl.StickyDipoleForce.cast(forces[0])
    assert force.getSwitchingDistance().value_in_unit(unit.nanometer) == pytest.approx(0.85*0.45)
    assert force.getSiteParameters(4) == rl.StickyDipoleForce.cast(system.getForce(0)).getSiteParameters(4)
    platform = mm.Platform.getPlatformByName('Reference')
    energies = []
    for s in (system, built):
        context = mm.Context(s, mm.VerletIntegrator(0.001), platform)
        context.setPositions(positions)
        energies.append(context.getState(getEnergy=True).getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))
    assert energies[1] == pytest.approx(energies[0], rel=1e-12)
    with pytest.raises(ValueError, match='no Ewald sum'):
        rl.ssd.forceField(model).createSystem(topology, nonbondedMethod=mm.app.PME, nonbondedCutoff=0.45*unit.nanometer)


def test_force_field_sites_take_attributes_and_switch_distance():
    xml = rl.ssd.forceFieldXml('SSD').replace('model="SSD"/>', 'model="SSD" w0="0.05" dipole="0.05"/>')
    topology, system, positions = rl.ssd.waterBox(8, boxSize=0.62*unit.nanometer, cutoff=0.3*unit.nanometer)
    built = mm.app.ForceField(io.StringIO(xml)).createSystem(topology, nonbondedMethod=mm.app.CutoffPeriodic,
                                                              nonbondedCutoff=0.3*unit.nanometer, switchDistance=0.25*unit.nanometer)
    force = rl.StickyDipoleForce.cast([f for f in built.getForces() if rl.StickyDipoleForce.isinstance(f)][0])
    assert force.getSwitchingDistance() == 0.25*unit.nanometer
    parameters = force.getSiteParameters(0)[3]
    assert parameters['w0'] == 0.05
    assert parameters['dipole'].value_in_unit(unit.elementary_charge*unit.nanometer) == 0.05
    assert parameters['sigma'] == rl.StickyDipoleForce.getModelParameters('SSD')['sigma']


def test_cast_force_gives_plugin_forces_their_class():
    # System.getForce() returns a plain openmm.Force for a plugin's force; castForce gives it its
    # class (the same C++ object: a change through it shows in the System) and leaves OpenMM's own.
    topology, system, positions = rl.ssd.waterBox(8, model='SSD/RF', boxSize=1.0*unit.nanometer, cutoff=0.45*unit.nanometer)
    forces = [rl.castForce(f) for f in system.getForces()]
    sticky = [f for f in forces if isinstance(f, rl.StickyDipoleForce)]
    assert len(sticky) == 1 and type(system.getForce(forces.index(sticky[0]))) is mm.Force
    assert all(type(f) is type(system.getForce(i)) for i, f in enumerate(forces) if f is not sticky[0])
    sticky[0].setReactionFieldDielectric(33.0)
    assert rl.StickyDipoleForce.cast(system.getForce(forces.index(sticky[0]))).getReactionFieldDielectric() == 33.0
