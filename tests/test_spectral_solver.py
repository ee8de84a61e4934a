"""The spectral solver (setHydrodynamicSolver(SpectralSolver)): the matrix-free coupled step in a
periodic box with the positively split Ewald (PSE) products of the blobs' mobility, at linear cost.
Its step equals the dense Ewald sum's to the tolerance; it keeps the Maxwell distribution; a
suspension of thousands of spheres sediments at the model's first-order speed; and what it cannot
do is refused naming the setting to change."""
import math
import re

import numpy as np
import openmm as mm
import pytest

import rigidlangevin as rl
from conftest import PlatformChoice
from test_hydrodynamics import assert_first_order_sedimentation

KB = 0.0083144626181532


@pytest.fixture(autouse=True)
def no_solver_override(monkeypatch):
    # The environment variable is for the other tests' runners; these choose the solver themselves.
    monkeypatch.delenv('RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER', raising=False)


def random_spheres(count, volume_fraction, radius, rng):
    """The side of the cube holding count spheres at the volume fraction, and their centres at random without overlap."""
    side = (count*4/3*math.pi*radius**3/volume_fraction)**(1/3)
    centres = np.empty((0, 3))
    while len(centres) < count:
        p = rng.uniform(0, side, 3)
        d = centres-p
        d -= side*np.round(d/side)
        if np.all(np.einsum('ij,ij->i', d, d) >= (2*radius)**2):
            centres = np.vstack([centres, p])
    return side, centres


def periodic_spheres(integrator, count, side, radius, mass=40.0):
    """A periodic System of count one-blob spheres (a periodic force of zero makes it periodic)."""
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(side, 0, 0), mm.Vec3(0, side, 0), mm.Vec3(0, 0, side))
    periodic = mm.CustomNonbondedForce('0')
    periodic.setNonbondedMethod(mm.CustomNonbondedForce.CutoffPeriodic)
    periodic.setCutoffDistance(min(1.0, 0.4*side))
    integrator.setHydrodynamicInteractions(True)
    integrator.setRandomNumberSeed(11)
    for i in range(count):
        system.addParticle(mass)
        periodic.addParticle([])
        integrator.addRigidBody([i])
        integrator.setParticleRadius(i, radius)
    system.addForce(periodic)
    return system


def langevin(temperature=300, viscosity=500.0):
    integrator = rl.RigidLangevinIntegrator(temperature, viscosity, 0.002)
    integrator.setScheme(rl.RigidLangevinIntegrator.BAOAB)
    return integrator


def one_step(platform, make_integrator, solver, tolerance, count=60, radii=(0.5,)):
    """The displacements and velocities of one step of count spheres (placed as radius 0.5 nm at 5%
    volume fraction; sphere i of radius radii[i % len(radii)]), each pulled by a force of its own
    (random, fixed)."""
    side, centres = random_spheres(count, 0.05, 0.5, np.random.default_rng(3))
    integrator = make_integrator()
    system = periodic_spheres(integrator, count, side, 0.5)
    for i in range(count):
        integrator.setParticleRadius(i, radii[i % len(radii)])
    pull = mm.CustomExternalForce('-(fx*x+fy*y+fz*z)')
    for name in ('fx', 'fy', 'fz'):
        pull.addPerParticleParameter(name)
    for i, f in enumerate(np.random.default_rng(4).normal(0, 10, (count, 3))):
        pull.addParticle(i, list(f))
    system.addForce(pull)
    integrator.setHydrodynamicSolver(solver)
    integrator.setHydrodynamicTolerance(tolerance)
    context = platform.context(system, integrator)
    context.setPositions(centres)
    context.setVelocitiesToTemperature(300, 1)
    integrator.step(1)
    state = context.getState(getPositions=True, getVelocities=True)
    return state.getPositions(asNumpy=True)._value-centres, state.getVelocities(asNumpy=True)._value, list(integrator.getKrylovIterations())


def brownian_at_zero_temperature():
    return rl.RigidBrownianIntegrator(0, 1.0, 0.002)


# Either integrator's step: Langevin's at 300 K, Brownian's at zero temperature (with the spectral
# products its noise is the PSE's own, exact through the split, not the Lanczos noise of the dense
# sum; TestSpectralBlobMobility checks its covariance against the dense Ewald sum's M).
BOTH_STEPS = pytest.mark.parametrize('make_integrator', [langevin, brownian_at_zero_temperature], ids=['langevin', 'brownian'])


@BOTH_STEPS
def test_the_spectral_step_is_the_dense_ewald_step_to_the_tolerance(platform, make_integrator):
    # Same seed, same normals (three per blob, the Lanczos noise of the Langevin step on either
    # product): the two steps differ only by the products' and solves' errors. Measured 1e-11 to
    # 2e-10 of the largest displacement or velocity at tolerance 1e-9 (the PSE's epsilon); a PSE
    # product wrong by 1e-6 (an epsilon a thousand times the tolerance, a part of the split
    # missing) fails.
    tolerance = 1e-9
    spectral = one_step(platform, make_integrator, rl.RigidLangevinIntegrator.SpectralSolver, tolerance)
    dense = one_step(platform, make_integrator, rl.RigidLangevinIntegrator.KrylovSolver, tolerance)
    # The Langevin noise takes no solve ([1] may be 0); at zero temperature there is no noise ([0] is 0).
    assert spectral[2] == dense[2] and spectral[2][2] > 0 and (spectral[2][0] > 0 or make_integrator is brownian_at_zero_temperature)
    for s, d in zip(spectral[:2], dense[:2]):
        assert np.abs(s-d).max() < tolerance*np.abs(d).max()


@BOTH_STEPS
def test_the_device_spectral_step_in_mixed_precision_is_the_dense_ewald_step_to_the_tolerance(make_integrator):
    # On OpenCL in mixed precision at a tolerance of 1e-4 the spectral products run on the device with
    # the grid and FFTs in float (CommonPseMobility); the step still equals the dense Ewald sum's
    # (the matrix-free step's products, the tiled kernel's) to the tolerance. A PSE product off by
    # 1e-3 (a Fourier factor ten times the tolerance) fails.
    choice = PlatformChoice('OpenCL', mm.Platform.getPlatformByName('OpenCL'), {'Precision': 'mixed'})
    tolerance = 1e-4
    spectral = one_step(choice, make_integrator, rl.RigidLangevinIntegrator.SpectralSolver, tolerance)
    dense = one_step(choice, make_integrator, rl.RigidLangevinIntegrator.KrylovSolver, tolerance)
    for s, d in zip(spectral[:2], dense[:2]):
        print(f'\nlargest difference over largest value: {np.abs(s-d).max()/np.abs(d).max():.2g}')
        assert np.abs(s-d).max() < tolerance*np.abs(d).max()


def test_the_spectral_step_keeps_the_maxwell_distribution():
    """1000 spheres (5% volume fraction, mass 5: gamma h 1.9, so successive steps' velocities are nearly
    independent) in a periodic box, stepped with the PSE products at tolerance 1e-4. The midpoint
    friction step keeps the Maxwell distribution exactly when its noise's covariance is its friction's
    (fluctuation-dissipation), for any positive definite friction: so the kinetic temperature is 300 K
    to within the run's statistics if and only if the noise and the friction use the same PSE
    operator, correctly scaled. BAOAB's configurational distribution depends on the friction step
    only through that property, so this is what keeps the statics unchanged with the PSE on (a
    configurational histogram would take 10^4 steps here to decorrelate). Ten steps of 3000 degrees
    of freedom: standard error about 0.6% (measured 299.6 +- 1.6 K); 5% fails by eight errors, and a
    noise variance off by a factor 2 by far more."""
    count, mass, temperature = 1000, 5.0, 300
    side, centres = random_spheres(count, 0.05, 0.5, np.random.default_rng(1))
    integrator = langevin(temperature)
    system = periodic_spheres(integrator, count, side, 0.5, mass)
    integrator.setHydrodynamicSolver(integrator.SpectralSolver)
    integrator.setHydrodynamicTolerance(1e-4)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'))
    context.setPositions(centres)
    context.setVelocitiesToTemperature(temperature, 2)
    integrator.step(2)
    temperatures = []
    for _ in range(10):
        integrator.step(1)
        v = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
        temperatures.append(mass*np.einsum('ij,ij', v, v)/(3*count*KB))
    assert integrator.getKrylovIterations()[0] > 0 and integrator.getKrylovIterations()[2] > 0
    mean, error = np.mean(temperatures), np.std(temperatures, ddof=1)/math.sqrt(len(temperatures))
    print(f'\nkinetic temperature with the spectral solver: {mean:.1f} +- {error:.1f} K')
    assert error < 0.01*temperature
    assert abs(mean-temperature) < 4*error


def test_a_suspension_of_4000_spheres_sediments_at_the_models_first_order_speed():
    """The periodic sedimentation test of test_hydrodynamics.py (its derivation there) through the
    integrator, at a size the dense Ewald path cannot reach in the suite's time (4000 blobs: 1.1 GiB and
    minutes to form the matrix each step): one-blob spheres (radius a) at random without overlap,
    each pulled by the same force F along z, one step of RigidBrownianIntegrator at zero temperature
    with the spectral solver; their mean displacement over the step is the suspension's sedimentation
    velocity, which for the Rotne-Prager-Yamakawa level averages over configurations to

        U/U0 = 1 - 2.837297 (a/L) (1 - 8 phi) - 5 phi,   phi = (N-1) (4/3) pi a^3 / L^3.

    At phi = 0.02 the pair term 5 phi is 0.10 and Hasimoto's 0.030; twelve configurations give a
    standard error near 0.006 (each configuration's mean scatters by about 0.02 with the density's
    longest waves): a factor 2 in the pair term fails by some 15 errors, Hasimoto's term left out by 5."""
    count, a, phi, viscosity, h, force = 4000, 0.1, 0.02, 1.0, 0.001, 10.0
    rng = np.random.default_rng(7)
    context = integrator = None
    velocities = []
    for _ in range(12):
        side, centres = random_spheres(count, phi, a, rng)
        if context is None:
            integrator = rl.RigidBrownianIntegrator(0, viscosity, h)
            system = periodic_spheres(integrator, count, side, a, 1.0)
            pull = mm.CustomExternalForce(f'-{force}*z')
            for i in range(count):
                pull.addParticle(i, [])
            system.addForce(pull)
            integrator.setHydrodynamicSolver(integrator.SpectralSolver)
            integrator.setHydrodynamicTolerance(1e-5)
            context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'))
        context.setPositions(centres)
        integrator.step(1)
        moved = context.getState(getPositions=True).getPositions(asNumpy=True)._value-centres
        velocities.append(moved[:, 2].mean()/h/(force/(6*math.pi*viscosity*a)))
    assert integrator.getKrylovIterations()[2] > 0
    assert_first_order_sedimentation(velocities, count, a, side)


def stepped_with(integrator, count, side, radius=0.5):
    """Step count spheres of radius in a cube of side once (positions on a grid, no overlap)."""
    system = periodic_spheres(integrator, count, side, radius)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'))
    per_side = math.ceil(count**(1/3))
    grid = np.array([(i % per_side, i//per_side % per_side, i//per_side**2) for i in range(count)])*(side/per_side)
    context.setPositions(grid)
    integrator.step(1)


def test_a_tolerance_the_spectral_products_cannot_reach_is_refused():
    integrator = langevin()
    integrator.setHydrodynamicSolver(integrator.SpectralSolver)
    integrator.setHydrodynamicTolerance(1e-11)
    with pytest.raises(mm.OpenMMException, match=r'setHydrodynamicTolerance\(\) with at least 1e-10'):
        stepped_with(integrator, 8, 6.0)
    # AutomaticSolver takes the spectral products from 500 blobs in a periodic box: refused there too.
    integrator = langevin()
    integrator.setHydrodynamicTolerance(1e-11)
    with pytest.raises(mm.OpenMMException, match='spectral solver.*setHydrodynamicTolerance'):
        stepped_with(integrator, 500, 30.0)


def test_a_box_too_small_for_the_blobs_is_refused():
    integrator = langevin()
    integrator.setHydrodynamicSolver(integrator.SpectralSolver)
    with pytest.raises(mm.OpenMMException, match='half the box'):
        stepped_with(integrator, 2, 1.8)


def test_more_radii_than_the_spectral_products_take_are_refused_naming_the_radii():
    # Polydisperse spheres, five radii: the positively split Ewald sum takes four (two FFTs per product each).
    integrator = langevin()
    integrator.setHydrodynamicSolver(integrator.SpectralSolver)
    system = periodic_spheres(integrator, 40, 12.0, 0.5)
    for i in range(40):
        integrator.setParticleRadius(i, 0.3+0.05*(i % 5))
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'))
    context.setPositions([mm.Vec3(i % 4, i//4 % 4, i//16)*3.0 for i in range(40)])
    with pytest.raises(mm.OpenMMException, match=r'5 distinct radii.*From the integrator: give the blobs at most 4 distinct radii '
                                                 r'\(setParticleRadius\(\), setBodyBlobs\(\)\), or setHydrodynamicSolver\(KrylovSolver\)') as refused:
        integrator.step(1)
    assert 'setHydrodynamicMemoryBudget' not in str(refused.value)


@pytest.mark.parametrize('radii, chosen', [((0.3, 0.35, 0.4, 0.45), rl.RigidLangevinIntegrator.SpectralSolver),
                                           ((0.3, 0.35, 0.4, 0.45, 0.5), rl.RigidLangevinIntegrator.KrylovSolver)],
                         ids=['four-radii', 'five-radii'])
def test_the_automatic_solver_takes_the_spectral_products_only_for_radii_they_take(radii, chosen):
    # At 500 blobs in a periodic box AutomaticSolver takes the positively split Ewald products, which
    # take at most four distinct radii; with five it keeps the dense Ewald sum (it chose the spectral
    # products and the step was refused). Same seed: the step is, bit for bit, the chosen solver's.
    cpu = PlatformChoice('CPU', mm.Platform.getPlatformByName('CPU'), {})
    automatic = one_step(cpu, langevin, rl.RigidLangevinIntegrator.AutomaticSolver, 1e-4, count=500, radii=radii)
    peer = one_step(cpu, langevin, chosen, 1e-4, count=500, radii=radii)
    for a, p in zip(automatic, peer):
        assert np.array_equal(a, p)


def test_a_step_beyond_the_memory_budget_is_refused():
    # 7800 blobs: 72 B^2 = 4.1 GiB for the matrix-free step's dense Ewald sum; refused before anything is formed.
    integrator = langevin()
    integrator.setHydrodynamicSolver(integrator.KrylovSolver)
    with pytest.raises(mm.OpenMMException, match=r'more than the budget of 4096 MiB \(setHydrodynamicMemoryBudget\(\)\): call '
                                                 r'setHydrodynamicSolver\(SpectralSolver\)'):
        stepped_with(integrator, 7800, 40.0)
    # A budget set lower: 100 blobs' 0.7 MB refused under 0.5 MB; the spectral solver's grid likewise.
    integrator = langevin()
    integrator.setHydrodynamicSolver(integrator.KrylovSolver)
    integrator.setHydrodynamicMemoryBudget(5e5)
    with pytest.raises(mm.OpenMMException, match='more than the budget of 0 MiB'):
        stepped_with(integrator, 100, 12.0)
    integrator = langevin()
    integrator.setHydrodynamicSolver(integrator.SpectralSolver)
    integrator.setHydrodynamicMemoryBudget(1e5)
    with pytest.raises(mm.OpenMMException, match=r'memory budget.*raise setHydrodynamicMemoryBudget\(\)'):
        stepped_with(integrator, 100, 12.0)


def test_the_memory_budget_is_a_serialized_setting():
    integrator = rl.RigidBrownianIntegrator(300, 1.0, 0.002)
    assert integrator.getHydrodynamicMemoryBudget() == 4*2**30
    integrator.setHydrodynamicMemoryBudget(2.5e9)
    xml = mm.XmlSerializer.serialize(integrator)
    assert rl.RigidBrownianIntegrator.cast(mm.XmlSerializer.deserialize(xml)).getHydrodynamicMemoryBudget() == 2.5e9
    # Written before the setting existed (the same version): read with the default.
    older = re.sub(r' hydrodynamicMemoryBudget="[^"]*"', '', xml)
    assert older != xml and rl.RigidBrownianIntegrator.cast(mm.XmlSerializer.deserialize(older)).getHydrodynamicMemoryBudget() == 4*2**30
    for bad in (0.0, -1.0, float('inf'), float('nan')):
        with pytest.raises(mm.OpenMMException, match='setHydrodynamicMemoryBudget'):
            integrator.setHydrodynamicMemoryBudget(bad)
