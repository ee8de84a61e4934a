"""RigidLangevinIntegrator in openmm.app: Simulation, reporters, checkpoints, States, force-field water."""
import io
import os
import pathlib

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit
import pytest

import rigidlangevin as rl
from rigidlangevin.statistics import agreement_threshold, block_error

# block_error's 10 blocks leave 9 degrees of freedom: the window is their t quantile (4.8), not 4.
WINDOW = agreement_threshold(9)

WATER_MODELS = {'tip3p': 'tip3p.xml', 'spce': 'spce.xml', 'tip4pew': 'tip4pew.xml'}


def water_simulation(model='tip3p', waters=64, rigid_water=True, constrain_bodies=True, platform='CPU', viscosity=0.89*rl.centipoise,
                     minimize=True, properties=None):
    """A box of force-field water with one rigid body per molecule, minimized (Modeller's small boxes
    have overlapping molecules)."""
    forcefield = app.ForceField(WATER_MODELS[model])
    modeller = app.Modeller(app.Topology(), [])
    modeller.addSolvent(forcefield, model=model, numAdded=waters)
    system = forcefield.createSystem(modeller.topology, nonbondedMethod=app.PME, nonbondedCutoff=0.6*unit.nanometer, rigidWater=rigid_water,
                                     removeCMMotion=False)
    integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, viscosity, 2*unit.femtoseconds)
    integrator.setRandomNumberSeed(3)
    bodies = rl.addRigidBodies(integrator, modeller.topology, system, positions=modeller.positions if constrain_bodies else None)
    assert len(bodies) == waters
    simulation = app.Simulation(modeller.topology, system, integrator, mm.Platform.getPlatformByName(platform), properties)
    simulation.context.setPositions(modeller.positions)
    if minimize:
        simulation.minimizeEnergy(maxIterations=100)
    return simulation


def sampled_temperatures(simulation, discard, steps, every=10):
    """computeSystemTemperature() every `every` steps over `steps` steps, after `discard` steps."""
    simulation.step(discard)
    temperatures = []
    for _ in range(steps//every):
        simulation.step(every)
        temperatures.append(simulation.integrator.computeSystemTemperature().value_in_unit(unit.kelvin))
    return np.array(temperatures)


def assert_bath_temperature(temperatures, what, bath=300.0):
    """The mean within WINDOW block standard errors of the bath's, with 6 standard errors below 5% of it
    (a 5% error would lie at least 2 standard errors beyond the window)."""
    mean, error = np.mean(temperatures), block_error(temperatures)
    assert abs(mean-bath) < WINDOW*error, f'{what}: {mean:.2f} +- {error:.2f} K, bath {bath} K'
    assert 6*error < 0.05*bath, f'{what}: standard error {error:.2f} K is too large to see a 5% error'


def positions_of(simulation):
    return simulation.context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(unit.nanometer)


def body_shapes(simulation):
    """Sorted intramolecular distances of every water (massive particles only)."""
    x = positions_of(simulation)
    shapes = []
    for residue in simulation.topology.residues():
        atoms = [a.index for a in residue.atoms() if a.element is not None]
        shapes.append(sorted(np.linalg.norm(x[a]-x[b]) for i, a in enumerate(atoms) for b in atoms[i+1:]))
    return np.array(shapes)


@pytest.mark.parametrize('model', ['tip3p', 'spce', 'tip4pew'])
@pytest.mark.parametrize('rigid_water', [True, False])
def test_force_field_water_minimize_and_run(model, rigid_water):
    # The force fields' rigid water works as bodies with or without the System's water constraints;
    # minimizeEnergy keeps them rigid (addRigidBodies adds constraints where there are none).
    simulation = water_simulation(model, rigid_water=rigid_water, minimize=False)
    simulation.minimizeEnergy(maxIterations=100)
    shapes = body_shapes(simulation)
    simulation.context.setVelocitiesToTemperature(300*unit.kelvin, 5)
    simulation.step(200)
    # Identical molecules (within 1e-3 nm) share one body type and take its exact shape, that of the
    # first water, and keep it.
    after = body_shapes(simulation)
    assert np.abs(after-after[0]).max() < 1e-9
    assert np.abs(after-shapes).max() < 1e-3
    integrator = simulation.integrator
    assert integrator.getNumDegreesOfFreedom() == 6*64
    if model == 'tip4pew':
        # The M site sits exactly on its virtual-site definition: the body's shape was made from it.
        x = positions_of(simulation)
        for residue in simulation.topology.residues():
            o, h1, h2, m = [a.index for a in residue.atoms()]
            site = simulation.system.getVirtualSite(m)
            expected = sum(site.getWeight(k)*x[site.getParticle(k)] for k in range(3))
            assert np.linalg.norm(x[m]-expected) < 1e-12
    assert_bath_temperature(sampled_temperatures(simulation, 500, 3000), f'{model}, rigidWater={rigid_water}')


def test_state_data_reporter_reports_rigid_body_temperature():
    simulation = water_simulation(viscosity=10*rl.centipoise)
    simulation.context.setVelocitiesToTemperature(300*unit.kelvin, 1)
    out = io.StringIO()
    simulation.reporters.append(app.StateDataReporter(out, 10, step=True, temperature=True))
    temperatures = io.StringIO()
    simulation.reporters.append(rl.RigidBodyTemperatureReporter(temperatures, 10))
    simulation.step(6000)
    reported = np.array([float(line.split(',')[1]) for line in out.getvalue().splitlines()[1:]])
    # 384 degrees of freedom: fluctuations of ~7% a sample.
    assert len(reported) == 600
    assert_bath_temperature(reported[100:], 'StateDataReporter temperature')
    rows = np.array([[float(v) for v in line.split(',')] for line in temperatures.getvalue().splitlines()[1:]])
    assert len(rows) == 600
    assert rows[-1, 4] == pytest.approx(reported[-1], rel=1e-6)
    for column, what in ((2, 'translational'), (3, 'rotational')):
        mean, error = np.mean(rows[100:, column]), block_error(rows[100:, column])
        assert abs(mean-300) < WINDOW*error and 6*error < 0.05*300, f'{what} temperature {mean:.2f} +- {error:.2f} K'



def test_dcd_reporter_writes_frames(tmp_path):
    simulation = water_simulation()
    path = str(tmp_path/'traj.dcd')
    simulation.reporters.append(app.DCDReporter(path, 10))
    simulation.step(50)
    del simulation.reporters[:]
    with open(path, 'rb') as f:
        header = f.read(12)
    # First Fortran record: length 84, 'CORD', then the number of frames.
    assert np.frombuffer(header[:4], dtype=np.int32)[0] == 84 and header[4:8] == b'CORD'
    assert np.frombuffer(header[8:12], dtype=np.int32)[0] == 5


def test_checkpoints_continue_bit_identically(tmp_path):
    # On the Reference platform: OpenMM's CPU platform sums forces in a thread-dependent order, so
    # there even its own integrators continue from a checkpoint only to ~1e-8.
    simulation = water_simulation(platform='Reference')
    simulation.context.setVelocitiesToTemperature(300*unit.kelvin, 2)
    simulation.step(20)
    path = str(tmp_path/'sim.chk')
    simulation.saveCheckpoint(path)
    simulation.step(30)
    first = positions_of(simulation)
    simulation.loadCheckpoint(path)
    simulation.step(30)
    assert np.array_equal(first, positions_of(simulation))
    # The CheckpointReporter writes the same kind of file.
    reporter_path = str(tmp_path/'reporter.chk')
    simulation.reporters.append(app.CheckpointReporter(reporter_path, 10))
    simulation.step(10)
    assert os.path.getsize(reporter_path) > 0


def test_states_and_reinitialize_preserve_bodies(tmp_path):
    simulation = water_simulation()
    simulation.context.setVelocitiesToTemperature(300*unit.kelvin, 4)
    simulation.step(20)
    path = str(tmp_path/'state.xml')
    simulation.saveState(path)
    saved = simulation.context.getState(getPositions=True, getVelocities=True)
    simulation.step(20)
    simulation.loadState(path)
    def difference(a, b):
        return np.abs(np.array(a._value)-np.array(b._value)).max()
    state = simulation.context.getState(getPositions=True, getVelocities=True)
    assert difference(state.getPositions(), saved.getPositions()) < 1e-12
    assert difference(state.getVelocities(), saved.getVelocities()) < 1e-9
    simulation.context.reinitialize(preserveState=True)
    state = simulation.context.getState(getPositions=True)
    assert difference(state.getPositions(), saved.getPositions()) < 1e-12
    simulation.step(20)


def test_selecting_residues_and_radii():
    forcefield = app.ForceField('tip3p.xml')
    modeller = app.Modeller(app.Topology(), [])
    modeller.addSolvent(forcefield, model='tip3p', numAdded=10)
    system = forcefield.createSystem(modeller.topology, nonbondedMethod=app.NoCutoff, rigidWater=True, removeCMMotion=False)
    integrator = rl.RigidLangevinIntegrator(300, 100, 0.002)
    first = lambda residue: residue.index < 4
    assert rl.addRigidBodies(integrator, modeller.topology, system, residues=first) == [0, 1, 2, 3]
    assert integrator.getNumRigidBodies() == 4
    # Hydrogens (epsilon 0) get the van der Waals radius of hydrogen; oxygens keep sigma/2.
    assert integrator.getParticleRadius(1).value_in_unit(unit.nanometer) == pytest.approx(0.12)
    assert integrator.getParticleRadius(0) is None
    integrator2 = rl.RigidLangevinIntegrator(300, 100, 0.002)
    assert len(rl.addRigidBodies(integrator2, modeller.topology, system, residues=['HOH'])) == 10


@pytest.mark.parametrize('model', ['tip3p', 'spce'])
def test_water_without_any_constraints_runs_as_bodies(model):
    # A flexible-water System (bonds and angles, no constraints) moved as rigid bodies: the
    # intramolecular forces cancel within each body, which keeps its shape.
    pdb = app.PDBFile(str(pathlib.Path(__file__).resolve().parents[1]/'examples'/'data'/'water256.pdb'))
    forcefield = app.ForceField(WATER_MODELS[model])
    system = forcefield.createSystem(pdb.topology, nonbondedMethod=app.PME, nonbondedCutoff=0.9*unit.nanometer, rigidWater=False,
                                     removeCMMotion=False)
    assert system.getNumConstraints() == 0
    integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.1*rl.poise, 2*unit.femtoseconds)
    rl.addRigidBodies(integrator, pdb.topology, system)
    simulation = app.Simulation(pdb.topology, system, integrator, mm.Platform.getPlatformByName('CPU'))
    simulation.context.setPositions(pdb.positions)
    simulation.context.setVelocitiesToTemperature(300*unit.kelvin, 1)
    shapes = body_shapes(simulation)
    temperatures = sampled_temperatures(simulation, 200, 2000)
    assert np.abs(body_shapes(simulation)-shapes).max() < 1e-3
    assert_bath_temperature(temperatures, f'{model} without constraints')


def test_lone_body_from_create_system_diffuses_and_a_motion_remover_is_refused():
    # The user guide's protein recipe with one body: createSystem's default CMMotionRemover would hold
    # it still (translational temperature 0 K, no diffusion); with friction it is refused, naming
    # the fix, and with removeCMMotion=False the body's translation is the bath's.
    pdb = app.PDBFile(io.StringIO(
        'HETATM    1  O   HOH A   1       0.000   0.000   0.000  1.00  0.00           O\n'
        'HETATM    2  H1  HOH A   1       0.957   0.000   0.000  1.00  0.00           H\n'
        'HETATM    3  H2  HOH A   1      -0.240   0.927   0.000  1.00  0.00           H\n'
        'END\n'))
    forcefield = app.ForceField('amber14/tip3p.xml')
    for remove in (True, False):
        system = forcefield.createSystem(pdb.topology, nonbondedMethod=app.NoCutoff, rigidWater=False, removeCMMotion=remove)
        integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.89*rl.centipoise, 2*unit.femtoseconds)
        integrator.setRandomNumberSeed(2)
        rl.addRigidBodies(integrator, pdb.topology, system)
        if remove:
            with pytest.raises(mm.OpenMMException, match=r'CMMotionRemover \(force \d\).*removeCMMotion=False'):
                mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))
            continue
        context = mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))
        context.setPositions(pdb.positions)
        temperatures = []
        for _ in range(4000):
            integrator.step(5)
            temperatures.append(integrator.computeTranslationalTemperature().value_in_unit(unit.kelvin))
        # 3 degrees of freedom: each sample's temperature scatters by sqrt(2/3); friction this stiff
        # renews the velocity within a few steps, so samples 5 steps apart are nearly independent.
        mean, error = np.mean(temperatures), block_error(temperatures)
        assert abs(mean-300) < WINDOW*error and WINDOW*error < 0.1*300, (mean, error)


class _StateRecorder:
    """Keeps the positions, velocities and forces of the State at each report (step -> (x, v, f))."""

    def __init__(self, interval):
        self.interval, self.states = interval, {}

    def describeNextReport(self, simulation):
        return {'steps': self.interval-simulation.currentStep % self.interval, 'periodic': False,
                'include': ['positions', 'velocities', 'forces']}

    def report(self, simulation, state):
        self.states[simulation.currentStep] = (state.getPositions(asNumpy=True).value_in_unit(unit.nanometer),
                                               state.getVelocities(asNumpy=True).value_in_unit(unit.nanometer/unit.picosecond),
                                               state.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole/unit.nanometer))


def _half_kick(masses, arms, forces, step):
    """The centre's and the angular velocity's change (lab frame) of a rigid body in half a kick."""
    inertia = sum(m*(a@a*np.eye(3)-np.outer(a, a)) for m, a in zip(masses, arms))
    torque = sum(np.cross(a, f) for a, f in zip(arms, forces))
    return 0.5*step*forces.sum(axis=0)/masses.sum(), 0.5*step*np.linalg.solve(inertia, torque)


def test_reporters_write_the_time_to_the_step():
    # At 10000 ps one 2 fs step is the eighth significant digit: both reporters must write 10000.002
    # ('%g' wrote 10000), and a second report one step later must differ from the first.
    system = mm.System()
    for _ in range(3):
        system.addParticle(16.0)
    integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.89*rl.centipoise, 2*unit.femtoseconds)
    integrator.addRigidBody([0, 1, 2])
    for i in range(3):
        integrator.setParticleRadius(i, 0.15)
    simulation = app.Simulation(app.Topology(), system, integrator, mm.Platform.getPlatformByName('Reference'))
    simulation.context.setPositions([mm.Vec3(0, 0, 0), mm.Vec3(0.1, 0, 0), mm.Vec3(0, 0.1, 0)])
    simulation.context.setTime(10000*unit.picosecond)
    temperatures, states = io.StringIO(), io.StringIO()
    simulation.reporters += [rl.RigidBodyTemperatureReporter(temperatures, 1), rl.RigidBodyStateReporter(states, 1)]
    simulation.step(2)
    for out in (temperatures, states):
        times = [line.split(',')[1] for line in out.getvalue().splitlines()[1:]]
        assert times == ['10000.002', '10000.004'], out.getvalue()


@pytest.mark.parametrize('viscosity', [0.89*rl.centipoise, 0.0])
def test_rigid_body_states_and_their_reporter_match_the_particles(viscosity, platform):
    # getRigidBodyStates() and RigidBodyStateReporter against the particles a State reports: the
    # centre is the centre of mass, every particle is at center + A b (b its body-frame coordinates,
    # getRigidBodyCoordinates()), with A a rotation, and moves at velocity + omega x (A b). The
    # reported velocities are synchronous: without friction the State's (half a kick behind) plus
    # half a kick; with friction the shift depends on the friction's modes (test_body_velocities.py),
    # and the file must say what getRigidBodyStates() says at the same step. The file
    # reads back with numpy's header names; bodies= limits the rows. (On PoCL, OpenMM's minimizer
    # with PME crashes, under LangevinMiddleIntegrator too: there the box starts from the CPU
    # platform's minimized positions.)
    simulation = water_simulation(waters=64, viscosity=viscosity, platform=platform.name, minimize=platform.name != 'OpenCL',
                                  properties=platform.properties)
    if platform.name == 'OpenCL':
        simulation.context.setPositions(water_simulation(waters=64, viscosity=viscosity).context.getState(getPositions=True).getPositions())
    simulation.context.setVelocitiesToTemperature(300*unit.kelvin, 4)
    integrator = rl.RigidLangevinIntegrator.cast(simulation.integrator)
    out, some = io.StringIO(), io.StringIO()
    recorder = _StateRecorder(25)
    simulation.reporters += [rl.RigidBodyStateReporter(out, 25), rl.RigidBodyStateReporter(some, 25, bodies=[3, 7]), recorder]
    simulation.step(100)
    table = np.genfromtxt(io.StringIO(out.getvalue()), delimiter=',', names=True)
    assert list(table.dtype.names) == rl.RigidBodyStateReporter.COLUMNS and len(table) == 4*64
    assert sorted(set(np.genfromtxt(io.StringIO(some.getvalue()), delimiter=',', names=True)['body'])) == [3, 7]
    masses = np.array([simulation.system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(simulation.system.getNumParticles())])
    bodies = [list(integrator.getRigidBodyParticles(b)) for b in range(integrator.getNumRigidBodies())]
    frames = [integrator.getRigidBodyCoordinates(b).value_in_unit(unit.nanometer) for b in range(len(bodies))]
    last = integrator.getRigidBodyStates()
    assert np.allclose(last.centers.value_in_unit(unit.nanometer)[5], [table[table['step'] == 100][c][5] for c in ('x_nm', 'y_nm', 'z_nm')], atol=1e-9)
    step_size = integrator.getStepSize().value_in_unit(unit.picosecond)
    for step, (x, v, f) in recorder.states.items():
        rows = table[table['step'] == step]
        for b, particles in enumerate(bodies):
            row = rows[rows['body'] == b][0]
            center = np.array([row['x_nm'], row['y_nm'], row['z_nm']])
            a = np.array([row[f'a{i}{j}'] for i in (1, 2, 3) for j in (1, 2, 3)]).reshape(3, 3)
            velocity = np.array([row['vx_nm_ps'], row['vy_nm_ps'], row['vz_nm_ps']])
            omega = np.array([row['wx_rad_ps'], row['wy_rad_ps'], row['wz_rad_ps']])
            m = masses[particles]
            assert np.allclose(a@a.T, np.eye(3), atol=1e-9) and np.linalg.det(a) == pytest.approx(1, abs=1e-9)
            assert np.allclose(m@x[particles]/m.sum(), center, atol=1e-7)
            arms = frames[b]@a.T
            assert np.allclose(center+arms, x[particles], atol=1e-6)
            if viscosity == 0.0:
                dv, domega = _half_kick(m, arms, f[particles], step_size)
                assert np.allclose(velocity-dv+np.cross(omega-domega, arms), v[particles], atol=1e-5)
    velocities = last.velocities.value_in_unit(unit.nanometer/unit.picosecond)
    rows = table[table['step'] == 100]
    assert np.allclose(velocities, np.array([rows[c] for c in ('vx_nm_ps', 'vy_nm_ps', 'vz_nm_ps')]).T, atol=1e-6)
