"""What a restore takes from the file and what from the integrator, and what the integrator does
when something else moves the particles.

A State or checkpoint carries where the bodies are and how they move; the integrator the user built
defines the physics (friction, radii, blobs). Restores into bodies listed in another order put every
particle where it was saved; a refused checkpoint leaves a Context that refuses to step; positions
moved by another integrator are taken as they are. (Barostats are refused: RigidBodyModel.)
"""
import io

import numpy as np
import openmm as mm
import pytest

import rigidlangevin as rl

ANGLE = np.radians(104.52)
WATER = np.array([(0, 0, 0), (0.09572, 0, 0), (0.09572*np.cos(ANGLE), 0.09572*np.sin(ANGLE), 0)])
WATER_MASSES = (16.0, 1.0, 1.0)
LINEAR = np.array([(0, 0, 0), (0.116, 0, 0), (-0.116, 0, 0)])
LINEAR_MASSES = (12.0, 16.0, 16.0)


def molecules(order=(0, 1), reverse_particles=False, radius=0.1, viscosity=0.0, temperature=0.0, scheme=None):
    """A water-shaped and a linear molecule, 1 nm apart, as rigid bodies added in `order`; the
    first body's particles listed in reverse if reverse_particles."""
    system = mm.System()
    for m in WATER_MASSES+LINEAR_MASSES:
        system.addParticle(m)
    integrator = rl.RigidLangevinIntegrator(temperature, viscosity, 0.002)
    if scheme is not None:
        integrator.setScheme(scheme)
    bodies = ([0, 1, 2], [3, 4, 5])
    for k, b in enumerate(order):
        particles = bodies[b][::-1] if reverse_particles and k == 0 else bodies[b]
        integrator.addRigidBody(particles)
    for p in range(6):
        integrator.setParticleRadius(p, radius)
    positions = np.vstack([WATER, LINEAR+np.array([1.0, 0.2, 0.1])])
    return system, integrator, positions


def moving_context(platform, **kwargs):
    system, integrator, positions = molecules(**kwargs)
    context = platform.context(system, integrator)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300, 5)
    return context, integrator


def positions_of(context):
    return context.getState(getPositions=True).getPositions(asNumpy=True)._value


def velocities_of(context):
    return context.getState(getVelocities=True).getVelocities(asNumpy=True)._value


def checkpoint_of(context):
    return context.createCheckpoint()


def restore(context, saved, how):
    if how == 'State':
        context.setState(saved)
    else:
        context.loadCheckpoint(saved)


def save(context, how):
    if how == 'State':
        return mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(
            context.getState(getPositions=True, getVelocities=True, getIntegratorParameters=True)))
    return checkpoint_of(context)


@pytest.mark.parametrize('how', ['State', 'checkpoint'])
def test_restore_keeps_the_receiving_integrators_friction(platform, how):
    # At zero temperature a step is deterministic. Saved with radius 0.1 and read by an integrator
    # with radius 0.3 (three times each bead's Stokes friction), the step after the restore is the
    # reader's: the same as its peer given the saved particles by setPositions and setVelocities.
    writer, _ = moving_context(platform, radius=0.1, viscosity=500.0)
    saved = save(writer, how)
    particles = positions_of(writer), velocities_of(writer)
    stepped = {}
    for peer in (False, True):
        system, integrator, positions = molecules(radius=0.3, viscosity=500.0)
        context = platform.context(system, integrator)
        context.setPositions(positions)
        if peer:
            context.setPositions(particles[0])
            context.setVelocities(particles[1])
        else:
            restore(context, saved, how)
        assert np.abs(positions_of(context)-particles[0]).max() < 1e-9
        integrator.step(1)
        stepped[peer] = velocities_of(context)
    writer.getIntegrator().step(1)
    written = velocities_of(writer)
    assert np.abs(stepped[False]-stepped[True]).max() < 1e-9*np.abs(written).max()
    assert np.abs(stepped[False]-written).max() > 0.05*np.abs(written).max()


@pytest.mark.parametrize('how', ['State', 'checkpoint'])
def test_explicit_tensor_of_the_receiving_integrator_is_used(platform, how):
    # The water body with an explicit diagonal tensor; the reader's is 6.3 times the writer's in
    # translation. Its centre's velocity along x decays by exp(-viscosity xi_xx h / m) in one step.
    def context_with(scale):
        system, integrator, positions = molecules(viscosity=100.0)
        tensor = np.diag([0.05, 0.05, 0.05, 1e-4, 1e-4, 1e-4])*np.array([scale]*3+[1]*3)
        centre = (np.array(WATER_MASSES)[:, None]*WATER).sum(0)/sum(WATER_MASSES)
        integrator.setBodyResistance(0, tensor.flatten().tolist(), mm.Vec3(*centre), [mm.Vec3(*p) for p in WATER])
        context = platform.context(system, integrator)
        context.setPositions(positions)
        velocities = np.zeros((6, 3))
        velocities[:3] = (1.0, 0, 0)
        context.setVelocities(velocities)
        return context, integrator
    writer, _ = context_with(1.0)
    saved = save(writer, how)
    reader, integrator = context_with(6.3)
    reader.setVelocities(np.zeros((6, 3)))
    restore(reader, saved, how)
    integrator.step(1)
    vx = velocities_of(reader)[:3, 0]
    mass, h = sum(WATER_MASSES), 0.002
    assert np.allclose(vx, np.exp(-100.0*0.05*6.3*h/mass), rtol=1e-9)


@pytest.mark.parametrize('how', ['State', 'checkpoint'])
@pytest.mark.parametrize('change', ['bodies_reordered', 'particles_reordered'])
def test_restore_into_bodies_listed_in_another_order_puts_every_particle_where_it_was_saved(platform, how, change):
    writer, writer_integrator = moving_context(platform)
    writer_integrator.step(5)
    saved = save(writer, how)
    expected = positions_of(writer)
    writer_integrator.step(20)
    continued = positions_of(writer)
    kwargs = {'order': (1, 0)} if change == 'bodies_reordered' else {'reverse_particles': True}
    system, integrator, positions = molecules(**kwargs)
    context = platform.context(system, integrator)
    context.setPositions(positions)
    restore(context, saved, how)
    assert np.abs(positions_of(context)-expected).max() < 1e-9
    integrator.step(20)
    assert np.abs(positions_of(context)-continued).max() < 1e-6


def test_a_refused_checkpoint_leaves_a_context_that_refuses_to_step(platform):
    context, integrator = moving_context(platform)
    good = checkpoint_of(context)
    integrator.step(3)
    damaged = bytearray(good)
    damaged[-20] ^= 0xFF  # inside the plugin's part, which ends the checkpoint
    with pytest.raises(mm.OpenMMException, match='damaged'):
        context.loadCheckpoint(bytes(damaged))
    with pytest.raises(mm.OpenMMException, match='last checkpoint was refused'):
        integrator.step(1)
    context.loadCheckpoint(good)
    integrator.step(1)
    with pytest.raises(mm.OpenMMException, match='damaged'):
        context.loadCheckpoint(bytes(damaged))
    context.setPositions(positions_of(context))
    integrator.step(1)


def test_reinitialize_preserving_the_state_after_a_mass_change(platform):
    context, integrator = moving_context(platform)
    integrator.step(3)
    before = positions_of(context)
    velocities = velocities_of(context)
    context.getSystem().setParticleMass(0, 18.0)
    context.reinitialize(preserveState=True)
    assert np.abs(positions_of(context)-before).max() < 1e-9
    # The bodies were fitted to the restored particles: rigid velocities survive a new mass.
    assert np.abs(velocities_of(context)-velocities).max() < 1e-9
    integrator.step(1)


def test_another_integrator_in_a_compound_integrator_moves_the_bodies(platform):
    # 100 Verlet steps carry a free molecule from x = 0.07 nm to 11 nm; the rigid-body integrator
    # goes on from there (it used to put it back where its last own step had left it).
    system, rigid, positions = molecules()
    compound = mm.CompoundIntegrator()
    compound.addIntegrator(rigid)
    compound.addIntegrator(mm.VerletIntegrator(0.002))
    context = platform.context(system, compound)
    positions = positions+np.array([0.07, 0, 0])
    context.setPositions(positions)
    context.setVelocities(np.tile([54.65, 0.0, 0.0], (6, 1)))
    compound.setCurrentIntegrator(0)
    compound.step(1)
    compound.setCurrentIntegrator(1)
    compound.step(100)
    moved = positions_of(context)
    compound.setCurrentIntegrator(0)
    compound.step(1)
    after = positions_of(context)
    assert moved[0, 0] > 11.0
    assert np.allclose(after, moved+np.array([54.65*0.002, 0, 0]), atol=1e-9, rtol=0)
