"""A State saved in one process and restored into a fresh Context in another continues the same
trajectory, as users restart runs: System, integrator and State through XmlSerializer files.

Every kind of body whose frame a fresh Context could choose differently: spherical tops
(degenerate moments: any axes are principal), symmetric tops, linear bodies, asymmetric bodies,
and bodies holding virtual sites. Without friction the run is deterministic, so 200 steps after
the restore must equal the uninterrupted run to round-off on Reference, whether the new Context
starts from the original positions, from the saved frame, or from the whole system rotated.
"""
import subprocess
import sys
import textwrap

import numpy as np
import openmm as mm
import pytest

import rigidlangevin as rl

# Body kinds: particle masses and positions (nm) about the body's own origin; virtual sites as
# (index, parents, weights) of a ThreeParticleAverageSite.
ANGLE = np.radians(104.52)
WATER = [(0, 0, 0), (0.09572, 0, 0), (0.09572*np.cos(ANGLE), 0.09572*np.sin(ANGLE), 0)]
KINDS = {
    'spherical_top': ([12.0]*4, [(0.1, 0.1, 0.1), (0.1, -0.1, -0.1), (-0.1, 0.1, -0.1), (-0.1, -0.1, 0.1)], []),
    'symmetric_top': ([14.0, 1.0, 1.0, 1.0], [(0, 0, 0.038), (0.094, 0, 0), (-0.047, 0.0814, 0), (-0.047, -0.0814, 0)], []),
    'linear': ([12.0, 16.0, 16.0], [(0, 0, 0), (0.116, 0, 0), (-0.116, 0, 0)], []),
    'asymmetric': ([16.0, 1.0, 1.0], WATER, []),
    'virtual_site': ([16.0, 1.0, 1.0, 0.0], WATER+[(0, 0, 0)], [(3, (0, 1, 2), (0.786646558, 0.106676721, 0.106676721))]),
}
STARTS = ('original', 'saved_frame', 'rotated')


def build(kind, n=8, seed=2):
    """n interacting bodies of one kind (Lennard-Jones and charges, no cutoff), without friction."""
    masses, shape, sites = KINDS[kind]
    rng = np.random.default_rng(seed)
    system = mm.System()
    nonbonded = mm.NonbondedForce()
    integrator = rl.RigidLangevinIntegrator(300, 0, 0.001)
    positions = []
    for b in range(n):
        first = system.getNumParticles()
        for i, m in enumerate(masses):
            system.addParticle(m)
            charge = 0.4*(-1)**i if kind != 'virtual_site' else (0, 0.52, 0.52, -1.04)[i]
            nonbonded.addParticle(charge, 0.3 if m > 1.5 else 0.1, 0.5 if m > 1.5 else 0.0)
        for site, parents, weights in sites:
            system.setVirtualSite(first+site, mm.ThreeParticleAverageSite(*(first+p for p in parents), *weights))
        particles = list(range(first, first+len(masses)))
        for i in particles:
            for j in particles:
                if i < j:
                    nonbonded.addException(i, j, 0, 1, 0)
        integrator.addRigidBody(particles)
        for p, m in zip(particles, masses):
            if m > 0:
                integrator.setParticleRadius(p, 0.15)
        rotation = np.linalg.qr(rng.normal(size=(3, 3)))[0]
        centre = 0.45*np.array([b % 2, (b//2) % 2, b//4])
        positions += [centre+rotation@np.array(p) for p in shape]
    system.addForce(nonbonded)
    return system, integrator, np.array(positions)


RESTORE = textwrap.dedent('''
    import sys
    import numpy as np
    import openmm as mm
    import rigidlangevin as rl
    folder, start = sys.argv[1], sys.argv[2]
    read = lambda name: open(f"{folder}/{name}", encoding='utf-8').read()
    system = mm.XmlSerializer.deserialize(read("system.xml"))
    integrator = rl.RigidLangevinIntegrator.cast(mm.XmlSerializer.deserialize(read("integrator.xml")))
    state = mm.XmlSerializer.deserialize(read("state.xml"))
    positions = np.load(f"{folder}/start_{start}.npy")
    properties = {"Precision": "double"} if sys.argv[3] in ("OpenCL", "CUDA") else {}
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(sys.argv[3]), properties)
    context.setPositions(positions)
    context.setState(state)
    restored = context.getState(getPositions=True).getPositions(asNumpy=True)._value
    integrator.step(200)
    after = context.getState(getPositions=True).getPositions(asNumpy=True)._value
    np.save(f"{folder}/restored_{start}.npy", restored)
    np.save(f"{folder}/after_{start}.npy", after)
''')


@pytest.mark.parametrize('kind', sorted(KINDS))
def test_state_restored_in_another_process_continues_the_trajectory(kind, tmp_path, platform):
    system, integrator, positions = build(kind)
    context = platform.context(system, integrator)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300, 7)
    integrator.step(100)
    state = context.getState(getPositions=True, getVelocities=True, getIntegratorParameters=True)
    saved = state.getPositions(asNumpy=True)._value
    (tmp_path/'system.xml').write_text(mm.XmlSerializer.serialize(system), encoding='utf-8')
    (tmp_path/'integrator.xml').write_text(mm.XmlSerializer.serialize(integrator), encoding='utf-8')
    (tmp_path/'state.xml').write_text(mm.XmlSerializer.serialize(state), encoding='utf-8')
    integrator.step(200)
    uninterrupted = context.getState(getPositions=True).getPositions(asNumpy=True)._value
    rotation = np.linalg.qr(np.random.default_rng(3).normal(size=(3, 3)))[0]
    np.save(tmp_path/'start_original.npy', positions)
    np.save(tmp_path/'start_saved_frame.npy', saved)
    np.save(tmp_path/'start_rotated.npy', positions@rotation.T+np.array([0.3, -0.2, 0.1]))
    # Reference is the definition: round-off. Other platforms compute forces in their own order
    # and precision, so 200 chaotic steps amplify their round-off; the restored frame is still exact.
    continued = 1e-9 if platform.name == 'Reference' else 1e-3
    for start in STARTS:
        subprocess.run([sys.executable, '-c', RESTORE, str(tmp_path), start, platform.name], check=True)
        restored = np.load(tmp_path/f'restored_{start}.npy')
        after = np.load(tmp_path/f'after_{start}.npy')
        assert np.abs(restored-saved).max() < 1e-12, f'{kind}, start {start}: restored particles off the saved ones'
        assert np.abs(after-uninterrupted).max() < continued, f'{kind}, start {start}: the restored run left the trajectory'
