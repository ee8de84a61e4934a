"""The plugin's part of an OpenMM checkpoint is framed with a CRC-32: any damage is refused with a
clear message, never loaded; and a checkpoint of the previous format (3, no frame) is still read
correctly."""
import pathlib

import numpy as np
import openmm as mm
import pytest

DATA = pathlib.Path(__file__).resolve().parent/'data'


def scene(platform):
    """Eight asymmetric bodies with friction, 20 steps in: (context, integrator)."""
    import rigidlangevin as rl
    from test_state_restore import build
    system, integrator, positions = build('asymmetric')
    integrator.setViscosity(0.89*rl.centipoise)
    integrator.setRandomNumberSeed(17)
    context = platform.context(system, integrator)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300, 5)
    integrator.step(20)
    return context, integrator


def positions_after(context, integrator, steps):
    integrator.step(steps)
    return context.getState(getPositions=True).getPositions(asNumpy=True)._value


def test_damaged_checkpoints_are_refused(platform):
    # The plugin's section is the checkpoint's tail, from its magic bytes. Every byte of it changed
    # alone, and 200 random sets of 1 to 64 changed bytes, must be refused with an OpenMMException
    # that says the checkpoint is damaged (or, for the magic bytes, not the plugin's); the intact
    # checkpoint loads and continues the run exactly.
    context, integrator = scene(platform)
    checkpoint = context.createCheckpoint()
    expected = positions_after(context, integrator, 10)
    start = checkpoint.rfind(b'RLck')
    assert start > 0 and len(checkpoint)-start > 400
    fresh, fresh_integrator = scene(platform)

    def refused(data):
        with pytest.raises(mm.OpenMMException) as error:
            fresh.loadCheckpoint(data)
        message = str(error.value)
        assert 'checkpoint is damaged' in message or "rigid-body part is not one this plugin reads" in message, message
    rng = np.random.default_rng(1)
    for position in range(start, len(checkpoint)):
        damaged = bytearray(checkpoint)
        damaged[position] ^= int(rng.integers(1, 256))
        refused(bytes(damaged))
    for _ in range(200):
        damaged = bytearray(checkpoint)
        for position in rng.choice(np.arange(start, len(checkpoint)), size=int(rng.integers(1, 65)), replace=False):
            damaged[position] ^= int(rng.integers(1, 256))
        refused(bytes(damaged))
    refused(checkpoint[:-1])  # truncated
    fresh.loadCheckpoint(checkpoint)
    assert np.array_equal(positions_after(fresh, fresh_integrator, 10), expected)


def test_checkpoint_of_the_previous_format_is_read():
    # data/checkpoint_v3.chk was written by the plugin at 4add0d7 (format 3, no frame) on the
    # Reference platform (data/make_checkpoint_v3.py): loaded now, the run continues exactly as it
    # did then.
    import rigidlangevin as rl
    from test_state_restore import build
    system, integrator, positions = build('asymmetric')
    integrator.setViscosity(0.89*rl.centipoise)
    integrator.setRandomNumberSeed(17)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))
    context.setPositions(positions)
    old = (DATA/'checkpoint_v3.chk').read_bytes()
    assert b'RLck' not in old
    context.loadCheckpoint(old)
    assert np.array_equal(positions_after(context, integrator, 10), np.load(DATA/'checkpoint_v3_after.npy'))
    # Format 2, which this plugin no longer reads, is refused by its version: OpenMM's part of the
    # checkpoint is as long as in a checkpoint of today, so the plugin's starts at the same place.
    start = context.createCheckpoint().rfind(b'RLck')
    assert old[start:start+4] == np.int32(3).tobytes()
    with pytest.raises(mm.OpenMMException, match='not one this plugin reads'):
        context.loadCheckpoint(old[:start]+np.int32(2).tobytes()+old[start+4:])


def triatomics(count, make_context):
    """count free triatomic bodies (the default bead model, radii 0.15 nm) on a grid 1 nm apart, in a
    new Context from make_context(system, integrator) at their starting positions: (context, integrator)."""
    import rigidlangevin as rl
    system, positions = mm.System(), []
    integrator = rl.RigidLangevinIntegrator(300, 0.89*rl.centipoise, 0.002)
    integrator.setRandomNumberSeed(29)
    for b in range(count):
        origin = np.array([1.0*(b % 16), 1.0*(b//16), 0.0])
        members = [system.addParticle(mass) for mass in (16.0, 1.0, 1.0)]
        positions += [origin, origin+[0.1, 0, 0], origin+[-0.03, 0.095, 0]]
        integrator.addRigidBody(members)
        for p in members:
            integrator.setParticleRadius(p, 0.15)
    context = make_context(system, integrator)
    context.setPositions(positions)
    return context, integrator


def test_cpu_checkpoint_continues_alike_on_any_number_of_threads():
    # The CPU platform draws each chunk of bodies' normals from a stream of its own, as many streams
    # as chunks whatever the number of threads (a trajectory does not depend on them): a checkpoint
    # written by a Context on two threads, loaded into one on one thread, continues exactly as the
    # two-thread run does. 256 free triatomic bodies, enough for the step to use its threads.
    def on_threads(threads):
        return lambda system, integrator: mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'), {'Threads': str(threads)})
    two, two_integrator = triatomics(256, on_threads(2))
    two.setVelocitiesToTemperature(300, 3)
    two_integrator.step(10)
    checkpoint = two.createCheckpoint()
    expected = positions_after(two, two_integrator, 10)
    one, one_integrator = triatomics(256, on_threads(1))
    one.loadCheckpoint(checkpoint)
    assert one.getPlatform().getPropertyValue(one, 'Threads') == '1'
    assert np.array_equal(positions_after(one, one_integrator, 10), expected)


def test_checkpoint_continues_exactly_whichever_way_a_fresh_context_fits_the_body(platform):
    # A fresh Context fits its bodies to the checkpoint's particles, and a fit may turn a body's
    # principal axes the other way round from the run that wrote it; the checkpoint's own frame and
    # friction must be taken over exactly. This triatomic's friction (the default bead model, whose
    # volume correction integrates on a grid along the frame's axes) differed by 2e-7 when computed in
    # the turned frame, and runs loaded after 6 or 26 of the first 30 steps (Reference; 13 to 15, 22,
    # 25 and 26 on the CPU platform) continued with other friction and other random numbers: every
    # one of them must continue exactly.
    run, run_integrator = triatomics(1, platform.context)
    run.setVelocitiesToTemperature(300, 3)
    for steps in range(30):
        checkpoint = run.createCheckpoint()
        fresh, fresh_integrator = triatomics(1, platform.context)
        fresh.loadCheckpoint(checkpoint)
        expected = positions_after(run, run_integrator, 3)
        assert np.array_equal(positions_after(fresh, fresh_integrator, 3), expected), f'loaded after {steps} steps'
        run.loadCheckpoint(checkpoint)
        run_integrator.step(1)
