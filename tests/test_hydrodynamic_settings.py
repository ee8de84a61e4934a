"""The hydrodynamic solver's settings: dense or matrix-free, its tolerance and the size from which it
is matrix-free are integrator settings (C++, Python, XML), each able to change what a step does."""
import re

import numpy as np
import openmm as mm
import pytest

import rigidlangevin as rl


@pytest.fixture(autouse=True)
def no_solver_override(monkeypatch):
    # The environment variable is for the other tests' runners; these test the settings themselves.
    monkeypatch.delenv('RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER', raising=False)


def spheres(count=24, seed=3):
    """count spheres with hydrodynamic interactions, 0.6 nm apart on average, under no force."""
    rng = np.random.default_rng(seed)
    system = mm.System()
    integrator = rl.RigidLangevinIntegrator(300, 500.0, 0.002)
    integrator.setScheme(rl.RigidLangevinIntegrator.BAOAB)
    integrator.setHydrodynamicInteractions(True)
    integrator.setRandomNumberSeed(5)
    for i in range(count):
        system.addParticle(40.0)
        integrator.addRigidBody([i])
        integrator.setParticleRadius(i, 0.15)
    positions = rng.uniform(0, 0.6*count**(1/3), size=(count, 3))
    return system, integrator, positions


def stepped(platform, configure, steps=3):
    system, integrator, positions = spheres()
    configure(integrator)
    context = platform.context(system, integrator)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300, 1)
    integrator.step(steps)
    return context.getState(getVelocities=True).getVelocities(asNumpy=True)._value, list(integrator.getKrylovIterations())


def matrix_free(iterations):
    """Whether a step's Krylov iterations (the noise's Lanczos, 0, the friction's conjugate gradients) say it was matrix-free."""
    return iterations[0] > 0 and iterations[1] == 0 and iterations[2] > 0


def test_dense_and_matrix_free_solvers_take_the_same_step(platform):
    dense, dense_iterations = stepped(platform, lambda i: i.setHydrodynamicSolver(i.DenseSolver))
    krylov, krylov_iterations = stepped(platform, lambda i: i.setHydrodynamicSolver(i.KrylovSolver))
    assert dense_iterations == [0, 0, 0] and matrix_free(krylov_iterations)
    # The two draw their normal numbers differently, so only at zero temperature do they coincide.
    cold = lambda solver: stepped(platform, lambda i: (i.setHydrodynamicSolver(solver), i.setTemperature(0), i.setHydrodynamicTolerance(1e-10)))[0]
    assert np.abs(cold(rl.RigidLangevinIntegrator.DenseSolver)-cold(rl.RigidLangevinIntegrator.KrylovSolver)).max() < 1e-8*np.abs(dense).max()


def test_the_size_from_which_the_solve_is_matrix_free(platform):
    # 24 blobs: matrix-free from 24, dense from 25; the platform's default is dense on Reference
    # and matrix-free from 100 blobs elsewhere.
    assert matrix_free(stepped(platform, lambda i: i.setKrylovMinBlobs(24))[1])
    assert stepped(platform, lambda i: i.setKrylovMinBlobs(25))[1] == [0, 0, 0]
    assert stepped(platform, lambda i: None)[1] == [0, 0, 0]


def test_a_looser_tolerance_takes_fewer_iterations(platform):
    tight = stepped(platform, lambda i: i.setHydrodynamicSolver(i.KrylovSolver))[1]
    loose = stepped(platform, lambda i: (i.setHydrodynamicSolver(i.KrylovSolver), i.setHydrodynamicTolerance(1e-3)))[1]
    assert loose[0] < tight[0] and loose[2] < tight[2], (loose, tight)


def test_settings_survive_serialization_and_bad_values_are_refused():
    integrator = rl.RigidLangevinIntegrator(300, 500.0, 0.002)
    assert (integrator.getHydrodynamicSolver(), integrator.getHydrodynamicTolerance(), integrator.getKrylovMinBlobs()) == \
        (integrator.AutomaticSolver, 1e-4, -1)
    integrator.setHydrodynamicSolver(integrator.KrylovSolver)
    integrator.setHydrodynamicTolerance(3e-6)
    integrator.setKrylovMinBlobs(250)
    copy = rl.RigidLangevinIntegrator.cast(mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(integrator)))
    assert (copy.getHydrodynamicSolver(), copy.getHydrodynamicTolerance(), copy.getKrylovMinBlobs()) == (integrator.KrylovSolver, 3e-6, 250)
    for bad in (0.0, 1e-13, 0.5, float('nan')):
        with pytest.raises(mm.OpenMMException, match='setHydrodynamicTolerance'):
            integrator.setHydrodynamicTolerance(bad)
    with pytest.raises(mm.OpenMMException, match='setKrylovMinBlobs'):
        integrator.setKrylovMinBlobs(-2)
    with pytest.raises(mm.OpenMMException, match='unknown solver'):
        integrator.setHydrodynamicSolver(7)


def test_version_3_xml_reads_with_the_default_settings():
    integrator = rl.RigidLangevinIntegrator(300, 500.0, 0.002)
    integrator.setHydrodynamicSolver(integrator.DenseSolver)
    xml = mm.XmlSerializer.serialize(integrator)
    assert 'version="5"' in xml
    xml = re.sub(r' (hydrodynamicSolver|hydrodynamicTolerance|krylovMinBlobs|wall|wallHeight)="[^"]*"', '', xml.replace('version="5"', 'version="3"'))
    copy = rl.RigidLangevinIntegrator.cast(mm.XmlSerializer.deserialize(xml))
    assert (copy.getHydrodynamicSolver(), copy.getHydrodynamicTolerance(), copy.getKrylovMinBlobs()) == (integrator.AutomaticSolver, 1e-4, -1)
