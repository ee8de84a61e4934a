"""The Python module: units, OpenMM interoperability, copying, errors."""
import copy
import pickle

import numpy as np
import openmm as mm
import openmm.unit as unit
import pytest

import rigidlangevin as rl


def water_like_body_system(n=3):
    """n rigid three-site bodies (water-like geometry) with radii, no forces."""
    system = mm.System()
    integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.89*rl.centipoise, 2*unit.femtoseconds)
    positions = []
    for b in range(n):
        first = system.getNumParticles()
        for mass in (15.999, 1.008, 1.008):
            system.addParticle(mass)
        positions += [mm.Vec3(b, 0, 0), mm.Vec3(b+0.09572, 0, 0), mm.Vec3(b-0.024, 0.0927, 0)]
        integrator.addRigidBody([first, first+1, first+2])
        for p in range(first, first+3):
            integrator.setParticleRadius(p, 0.1*unit.nanometer)
    return system, integrator, positions


def test_viscosity_units_and_avogadro():
    # 0.89 cP is 535.97 amu/(nm ps): openmm.unit's own MD form of Pa*s lacks Avogadro's number.
    i = rl.RigidLangevinIntegrator(300, 0.89*rl.centipoise, 0.002)
    assert i.getViscosity().value_in_unit(rl.md_viscosity) == pytest.approx(535.97, rel=1e-4)
    assert i.getViscosity().value_in_unit(rl.centipoise) == pytest.approx(0.89)
    i.setViscosity(1*rl.poise)
    assert i.getViscosity()._value == pytest.approx(60221.4076)
    i.setViscosity(1e-3*unit.pascal*unit.second)
    assert i.getViscosity()._value == pytest.approx(602.214076)
    i.setViscosity(8.9e-22*unit.mole*unit.dalton/(unit.nanometer*unit.picosecond))
    assert i.getViscosity()._value == pytest.approx(535.97, rel=1e-4)
    i.setViscosity(123.0)
    assert i.getViscosity()._value == 123.0
    i.setViscosity(5.0*unit.dalton/(unit.nanometer*unit.picosecond))
    assert i.getViscosity()._value == pytest.approx(5.0)
    with pytest.raises(TypeError):
        i.setViscosity(1*unit.nanometer)


def test_quantities_in_and_out():
    i = rl.RigidLangevinIntegrator(310*unit.kelvin, 100, 1.5*unit.femtoseconds)
    assert i.getTemperature() == 310*unit.kelvin
    assert i.getStepSize().value_in_unit(unit.femtoseconds) == pytest.approx(1.5)
    i.setTemperature(20*unit.kelvin)
    assert i.getTemperature() == 20*unit.kelvin
    i.setParticleRadius(3, 2*unit.angstrom)
    assert i.getParticleRadius(3).value_in_unit(unit.nanometer) == pytest.approx(0.2)
    assert i.getParticleRadius(4) is None


def test_bodies_and_tensors_from_numpy():
    i = rl.RigidLangevinIntegrator(300, 100, 0.002)
    assert i.addRigidBody(np.arange(3)) == 0
    assert i.getRigidBodyParticles(0) == (0, 1, 2)
    tensor = np.diag([1., 2, 3, 4, 5, 6])
    reference = np.array([[0, 0, 0], [0.9572, 0, 0], [-0.24, 0.927, 0]])*unit.angstrom
    i.setBodyResistance(0, tensor, mm.Vec3(1, 2, 3)*unit.angstrom, reference)
    matrix, origin, positions = i.getBodyResistance(0)
    assert np.array_equal(matrix, tensor)
    assert origin.value_in_unit(unit.nanometer) == pytest.approx(mm.Vec3(0.1, 0.2, 0.3))
    assert positions.value_in_unit(unit.nanometer) == pytest.approx(reference.value_in_unit(unit.nanometer))
    assert i.getNumRigidBodies() == 1
    with pytest.raises(ValueError):
        i.setBodyResistance(0, np.ones(5), (0, 0, 0), reference)


def test_errors_are_openmm_exceptions():
    i = rl.RigidLangevinIntegrator(300, 100, 0.002)
    i.addRigidBody([0, 1])
    with pytest.raises(mm.OpenMMException, match='particle 1 is already in rigid body 0'):
        i.addRigidBody([1, 2])
    with pytest.raises(mm.OpenMMException, match='not symmetric'):
        bad = np.eye(6)
        bad[0, 1] = 1
        i.setBodyResistance(0, bad, (0, 0, 0), [(0, 0, 0), (0.1, 0, 0)])
    with pytest.raises(mm.OpenMMException, match='temperature'):
        rl.RigidLangevinIntegrator(-1, 1, 0.002)


def test_context_state_and_temperatures(platform):
    system, integrator, positions = water_like_body_system()
    context = platform.context(system, integrator)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300*unit.kelvin, 1)
    integrator.step(10)
    assert integrator.getNumDegreesOfFreedom() == 18
    temperatures = (integrator.computeSystemTemperature(), integrator.computeTranslationalTemperature(), integrator.computeRotationalTemperature())
    for t in temperatures:
        assert unit.is_quantity(t) and t.unit == unit.kelvin
    # Exact identities: the temperature is the State's kinetic energy over 18 degrees of freedom
    # (no CMMotionRemover), and the degree-of-freedom-weighted mean of its 9 + 9 parts.
    kinetic = context.getState(getEnergy=True).getKineticEnergy()
    boltzmann = unit.MOLAR_GAS_CONSTANT_R.value_in_unit(unit.kilojoule_per_mole/unit.kelvin)
    total, translational, rotational = (t.value_in_unit(unit.kelvin) for t in temperatures)
    assert total == pytest.approx(2*kinetic.value_in_unit(unit.kilojoule_per_mole)/(18*boltzmann), rel=1e-9)
    assert total == pytest.approx((translational+rotational)/2, rel=1e-12)
    assert rl.RigidLangevinIntegrator.isinstance(context.getIntegrator())
    assert context.getIntegrator().getViscosity() == integrator.getViscosity()


def test_xml_serializer_copy_and_pickle():
    integrator = rl.RigidLangevinIntegrator(300, 536.0, 0.002)
    integrator.setScheme(rl.RigidLangevinIntegrator.BAOAB)
    integrator.addRigidBody([0, 1, 2])
    integrator.setBodyResistance(0, np.diag([1., 1, 1, 2, 2, 2]), (0.1, 0, 0), [(0, 0, 0), (0.1, 0, 0), (0, 0.1, 0)])
    integrator.setParticleRadius(1, 0.12)
    integrator.setRandomNumberSeed(9)
    xml = mm.XmlSerializer.serialize(integrator)
    assert 'RigidLangevinIntegrator' in xml
    restored = rl.RigidLangevinIntegrator.cast(mm.XmlSerializer.deserialize(xml))
    for other in (restored, copy.deepcopy(integrator), copy.copy(integrator), pickle.loads(pickle.dumps(integrator))):
        assert isinstance(other, rl.RigidLangevinIntegrator)
        assert mm.XmlSerializer.serialize(other) == xml
        assert other.getScheme() == rl.RigidLangevinIntegrator.BAOAB
    with pytest.raises(mm.OpenMMException, match='not a RigidLangevinIntegrator'):
        rl.RigidLangevinIntegrator.cast(mm.VerletIntegrator(0.001))


def test_resistance_tensor_values():
    sphere = rl.ResistanceTensor.sphere(0.2)
    m = sphere.getMatrix()
    assert m.shape == (6, 6)
    assert m[0, 0] == pytest.approx(6*np.pi*0.2)
    assert m[5, 5] == pytest.approx(8*np.pi*0.2**3)
    # About another point the coupling appears, and the centre of resistance is the sphere's centre.
    moved = sphere.getMatrix(mm.Vec3(0.1, 0, 0))
    assert abs(moved[1, 5]) > 0
    explicit = rl.ResistanceTensor.explicit(moved, mm.Vec3(0.1, 0, 0))
    assert explicit.getCenterOfResistance().value_in_unit(unit.nanometer) == pytest.approx(mm.Vec3(0, 0, 0), abs=1e-12)


def test_checkpoint_and_state_continue_on_every_platform(platform):
    # Free bodies (no forces): a checkpoint continues bit for bit, a State restores the bodies.
    system, integrator, positions = water_like_body_system(20)
    integrator.setRandomNumberSeed(5)
    context = platform.context(system, integrator)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300*unit.kelvin, 2)
    integrator.step(10)
    checkpoint = context.createCheckpoint()
    integrator.step(20)
    first = context.getState(getPositions=True, getVelocities=True)
    context.loadCheckpoint(checkpoint)
    integrator.step(20)
    second = context.getState(getPositions=True, getVelocities=True)
    assert np.array_equal(first.getPositions(asNumpy=True), second.getPositions(asNumpy=True))
    assert np.array_equal(first.getVelocities(asNumpy=True), second.getVelocities(asNumpy=True))
    # Bodies stay rigid: the distances inside each body are those set.
    end = second.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
    start = np.array([[p.x, p.y, p.z] for p in positions])
    for b in range(20):
        for i, j in ((0, 1), (0, 2), (1, 2)):
            assert np.linalg.norm(end[3*b+i]-end[3*b+j]) == pytest.approx(np.linalg.norm(start[3*b+i]-start[3*b+j]), abs=1e-9)


def test_hydrodynamic_interactions_from_python():
    # Off by default; blobs given with units come back as Quantities and through XML; with
    # interactions on, pulling one body drags its neighbour (at zero temperature, so only the
    # coupling moves it), and without them it stays put. BAOAB is required.
    system, integrator, positions = water_like_body_system(2)
    assert not integrator.getHydrodynamicInteractions()
    blobs = np.array([[0.0, 0.0, 0.0], [0.06, 0.03, 0.0], [0.0, 0.07, 0.02]])*unit.nanometer
    integrator.setBodyBlobs(0, blobs, [0.1, 0.08, 0.08]*unit.nanometer, positions[:3])
    centres, radii, reference = integrator.getBodyBlobs(0)
    assert np.allclose(centres.value_in_unit(unit.nanometer), blobs.value_in_unit(unit.nanometer))
    assert np.allclose(radii.value_in_unit(unit.angstrom), [1.0, 0.8, 0.8])
    assert integrator.getBodyBlobs(1) is None
    integrator.setHydrodynamicInteractions(True)
    xml = mm.XmlSerializer.serialize(integrator)
    restored = rl.RigidLangevinIntegrator.cast(mm.XmlSerializer.deserialize(xml))
    assert restored.getHydrodynamicInteractions() and mm.XmlSerializer.serialize(restored) == xml
    with pytest.raises(mm.OpenMMException, match='BAOAB'):
        mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))

    pull = mm.CustomExternalForce('-100*x')
    for p in range(3):
        pull.addParticle(p)
    system.addForce(pull)
    dragged = {}
    for interactions in (True, False):
        steps = copy.copy(integrator)
        steps.setTemperature(0)
        steps.setScheme(rl.RigidLangevinIntegrator.BAOAB)
        steps.setHydrodynamicInteractions(interactions)
        context = mm.Context(system, steps, mm.Platform.getPlatformByName('Reference'))
        context.setPositions(positions)
        steps.step(200)
        dragged[interactions] = steps.getRigidBodyStates().velocities[1].value_in_unit(unit.nanometer/unit.picosecond)
        puller = steps.getRigidBodyStates().velocities[0].value_in_unit(unit.nanometer/unit.picosecond)
        assert list(steps.getKrylovIterations()) == [0, 0, 0]  # Reference is dense
    assert dragged[False][0] == 0
    # Along the line of centres, Oseen's 3a/(2r) for blobs of about a = 0.13 nm 1 nm apart: 0.19
    assert 0.1*puller[0] < dragged[True][0] < 0.3*puller[0]
