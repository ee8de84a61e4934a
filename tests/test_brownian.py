"""RigidBrownianIntegrator against exact answers: a free body's step covariance and drift, a sphere's
diffusion beside a no-slip wall, a sedimented sphere's height distribution (the drift's test), and
what it refuses.

Each statistical check states the error it catches: the covariance tests fail at 5% in a variance,
the drift test without the random finite difference, the equilibrium test without the drift.
"""
import math

import numpy as np
import openmm as mm
import pytest
import rigidlangevin as rl
from scipy.spatial.transform import Rotation

KT = 2.494338785  # kJ/mol at 300 K
PLATFORMS = ['Reference', 'CPU']


def platform(name):
    return mm.Platform.getPlatformByName(name)


def rotation_vector(a_new, a_old):
    """The lab-frame rotation vector that turns orientation a_old into a_new."""
    return Rotation.from_matrix(a_new @ a_old.T).as_rotvec()


# --- A free body: its step is exactly Gaussian with covariance 2 kT h N, its mean kT h div N ---

BODY = np.array([[0.0, 0.0, 0.0], [0.6, 0.1, 0.0], [0.2, 0.5, 0.3]])  # nm
MASSES = [1.0, 2.0, 3.0]


def coupled_tensor():
    """A positive definite 6x6 resistance (per unit viscosity) whose translation-rotation block is not
    symmetric: about the centre of mass this body drifts as it turns (its centre of mass is not its
    centre of mobility)."""
    rng = np.random.default_rng(3)
    b = rng.normal(size=(6, 6))
    xi = b @ b.T + 3*np.eye(6)
    xi[:3, 3:] += np.array([[0, 1.5, -0.8], [-1.5, 0, 0.6], [0.8, -0.6, 0]])
    xi[3:, :3] = xi[:3, 3:].T
    assert np.all(np.linalg.eigvalsh(xi) > 0)
    return xi


def expected_drift(mobility):
    """kT div N in the lab frame at the reference orientation, by central differences of the rotated
    mobility over lab-frame rotation vectors (the translation rows; the rotation rows vanish)."""
    drift = np.zeros(6)
    for j in range(3):
        step = np.zeros(3)
        step[j] = 1e-5
        turned = []
        for sign in (1, -1):
            r = Rotation.from_rotvec(sign*step).as_matrix()
            g = np.kron(np.eye(2), r)
            turned.append(g @ mobility @ g.T)
        drift += (turned[0]-turned[1])[:, 3+j]/2e-5
    return KT*drift


def free_bodies(count, viscosity, step):
    system = mm.System()
    integrator = rl.RigidBrownianIntegrator(300, viscosity, step)
    integrator.setRandomNumberSeed(11)
    centre = np.average(BODY, axis=0, weights=MASSES)
    positions = []
    for b in range(count):
        first = system.getNumParticles()
        for m in MASSES:
            system.addParticle(m)
        integrator.addRigidBody([first, first+1, first+2])
        integrator.setBodyResistance(b, list(coupled_tensor().flat), mm.Vec3(*centre), [mm.Vec3(*p) for p in BODY])
        positions += [mm.Vec3(*(p+[30.0*b, 0, 0])) for p in BODY]
    return system, integrator, positions


@pytest.mark.parametrize('name', PLATFORMS)
def test_free_body_steps_have_the_tensor_covariance_and_drift(name):
    viscosity, h, count, steps = 1.0, 0.004, 500, 120
    system, integrator, positions = free_bodies(count, viscosity, h)
    context = mm.Context(system, integrator, platform(name))
    context.setPositions(positions)
    start = integrator.getRigidBodyStates()
    reference = start.orientations.copy()  # the frame of the tensor: the body as placed
    samples = []
    before = start
    for _ in range(steps):
        integrator.step(1)
        after = integrator.getRigidBodyStates()
        for b in range(count):
            turn = before.orientations[b] @ reference[b].T  # reference frame -> lab at the step's start
            dx = after.centers[b].value_in_unit(mm.unit.nanometer)-before.centers[b].value_in_unit(mm.unit.nanometer)
            dtheta = rotation_vector(after.orientations[b], before.orientations[b])
            samples.append(np.concatenate([turn.T @ dx, turn.T @ dtheta]))
        before = after
    samples = np.array(samples)
    mobility = np.linalg.inv(viscosity*coupled_tensor())
    # Whitened by the exact covariance, the steps' covariance is the identity: diagonal standard error
    # sqrt(2/n), off-diagonal sqrt(1/n). A 5% error in any variance is 10 standard errors.
    n = len(samples)
    root = np.linalg.cholesky(2*KT*h*mobility)
    white = np.linalg.solve(root, (samples-samples.mean(axis=0)).T).T
    covariance = white.T @ white/(n-1)
    se = np.where(np.eye(6) > 0, math.sqrt(2/n), math.sqrt(1/n))
    assert np.all(np.abs(covariance-np.eye(6)) < 5*se), (covariance-np.eye(6))/se
    # The mean step is the drift kT h div N (zero without the random finite difference).
    drift = expected_drift(mobility)*h
    mean_se = np.sqrt(np.diag(2*KT*h*mobility)/n)
    assert np.max(np.abs(drift[:3])/mean_se[:3]) > 8, 'the drift must be large enough to be seen'
    assert np.all(np.abs(samples.mean(axis=0)-drift) < 4.5*mean_se), (samples.mean(axis=0)-drift)/mean_se
    assert context.getState(getEnergy=True).getKineticEnergy().value_in_unit(mm.unit.kilojoule_per_mole) == 0


# --- A sphere beside a no-slip wall: Rotne-Prager-Blake rates parallel and perpendicular ---

def blake_self_mobility(radius, height):
    """The Rotne-Prager-Blake self-mobility of a sphere at height over the wall (Swan & Brady's closed
    forms), parallel and perpendicular, in units of 1/(6 pi a)."""
    x = radius/height
    return 1-9*x/16+x**3/8-x**5/16, 1-9*x/8+x**3/2-x**5/8


def sphere_layer(count, radius, height, spacing, viscosity, step, integrator_class=rl.RigidBrownianIntegrator):
    system = mm.System()
    integrator = integrator_class(300, viscosity, step)
    integrator.setRandomNumberSeed(5)
    positions = []
    side = int(math.ceil(math.sqrt(count)))
    for i in range(count):
        system.addParticle(1.0)
        integrator.addRigidBody([i])
        integrator.setParticleRadius(i, radius)
        positions.append(mm.Vec3(spacing*(i % side), spacing*(i//side), height))
    integrator.setHydrodynamicInteractions(True)
    integrator.setWall(0.0)
    return system, integrator, positions


@pytest.mark.parametrize('name, solver', [('Reference', 'DenseSolver'), ('CPU', 'DenseSolver'), ('CPU', 'KrylovSolver'), ('OpenCL', 'KrylovSolver')])
def test_sphere_beside_the_wall_diffuses_at_the_blake_rates(name, solver):
    radius, viscosity, h, count, repeats = 1.0, 1.0, 0.002, 36, 250
    height = 1.6*radius
    system, integrator, positions = sphere_layer(count, radius, height, 40*radius, viscosity, h)
    integrator.setHydrodynamicSolver(getattr(rl.RigidBrownianIntegrator, solver))  # Krylov: Lanczos and GMRES
    context = mm.Context(system, integrator, platform(name))
    steps = []
    for _ in range(repeats):
        context.setPositions(positions)  # every step from the same height
        integrator.step(1)
        steps.append(np.array(context.getState(getPositions=True).getPositions(asNumpy=True)._value)-np.array([list(p) for p in positions]))
    steps = np.concatenate(steps)
    n = len(steps)
    mu0 = 1/(6*math.pi*viscosity*radius)
    parallel, perpendicular = blake_self_mobility(radius, height)
    expected = 2*KT*h*mu0*np.array([parallel, parallel, perpendicular])
    variance = steps.var(axis=0)
    # Each variance to sqrt(2/n) = 2.4% relative; the unbounded solvent's rates are 27% and 59% off.
    assert np.all(np.abs(variance/expected-1) < 4*math.sqrt(2/n)), variance/expected
    assert (min(integrator.getKrylovIterations()) > 0) == (solver == 'KrylovSolver'), integrator.getKrylovIterations()


# --- Bodies of several blobs coupled through the solvent above the wall: the step's covariance ---

L_SHAPE = np.array([[0, 0, 0], [0.5, 0, 0], [1.0, 0, 0], [0, 0.5, 0], [0, 1.0, 0]])  # nm, blobs of 0.3 nm


def coupled_bodies_above_wall(integrator_class, viscosity, h, scale=1.0, temperature=300):
    """Three L-shaped bodies of five blobs each, close together above the wall z = 0, each with the
    explicit tensor of its blobs alone (so the library's calibration and the integrator's agree);
    every length times scale."""
    radius = 0.3*scale
    placements = [(scale*np.array([0, 0, 0.8]), 0.0), (scale*np.array([1.4, 0.3, 1.0]), 0.9), (scale*np.array([0.2, 1.5, 1.3]), 2.1)]
    system, integrator = mm.System(), integrator_class(temperature, viscosity, h)
    integrator.setRandomNumberSeed(17)
    positions, library = [], []
    for b, (shift, angle) in enumerate(placements):
        turn = Rotation.from_rotvec([0.3*angle, angle, 0.5]).as_matrix()
        blobs = scale*L_SHAPE @ turn.T + shift
        first = system.getNumParticles()
        for i in range(len(blobs)):
            system.addParticle(1.0)
            integrator.setParticleRadius(first+i, radius)
        integrator.addRigidBody(list(range(first, first+len(blobs))))
        centre = blobs.mean(axis=0)
        alone = rl.hydrodynamics.coupledResistance([(blobs, [radius]*len(blobs), centre)])
        integrator.setBodyResistance(b, list(alone.flat), mm.Vec3(*centre), [mm.Vec3(*p) for p in blobs])
        positions += [mm.Vec3(*p) for p in blobs]
        library.append(((blobs, [radius]*len(blobs), centre), rl.hydrodynamics.explicit(alone, centre)))
    integrator.setHydrodynamicInteractions(True)
    integrator.setWall(0.0)
    mobility = rl.hydrodynamics.coupledMobility([body for body, _ in library], own=[tensor for _, tensor in library], wall=0.0)/viscosity
    return system, integrator, positions, mobility


@pytest.mark.parametrize('name, solver', [('Reference', 'DenseSolver'), ('CPU', 'KrylovSolver')])
def test_coupled_bodies_above_the_wall_step_with_their_mobility(name, solver):
    viscosity, h, repeats = 1.0, 0.002, 900
    system, integrator, positions, mobility = coupled_bodies_above_wall(rl.RigidBrownianIntegrator, viscosity, h)
    integrator.setHydrodynamicSolver(getattr(rl.RigidBrownianIntegrator, solver))
    context = mm.Context(system, integrator, platform(name))
    context.setPositions(positions)
    start = integrator.getRigidBodyStates()
    centres = start.centers.value_in_unit(mm.unit.nanometer)
    samples = []
    for _ in range(repeats):
        context.setPositions(positions)
        integrator.step(1)
        after = integrator.getRigidBodyStates()
        moved = after.centers.value_in_unit(mm.unit.nanometer)-centres
        samples.append(np.concatenate([np.concatenate([moved[b], rotation_vector(after.orientations[b], start.orientations[b])]) for b in range(3)]))
    samples = np.array(samples)
    samples -= samples.mean(axis=0)
    # Eigenmode by eigenmode of the exact covariance 2 kT h N (the library's dense mobility above the
    # wall): each mode's variance ratio has standard error sqrt(2/R) = 4.7%, their mean over the 18
    # modes 1.1%, so a 5% error anywhere in the noise, or a mode with the wrong variance, fails.
    values, vectors = np.linalg.eigh(2*KT*h*mobility)
    ratios = ((samples @ vectors)**2).mean(axis=0)/values
    se = math.sqrt(2/repeats)
    assert np.all(np.abs(ratios-1) < 4.5*se), ratios
    assert abs(ratios.mean()-1) < 4*se/math.sqrt(len(ratios)), ratios.mean()
    assert (min(integrator.getKrylovIterations()) > 0) == (solver == 'KrylovSolver')


def test_krylov_steps_of_colloids_are_right_to_the_tolerance():
    # Colloid-sized bodies (blobs of 300 nm) pushed by forces at zero temperature: a step is N F h
    # alone. The saddle-point problem mixes blob velocities (about mu0 = 1/(6 pi eta a) per unit
    # force, ~1e-4 in nm) with forces; unscaled, its residual gave the velocities almost no weight and
    # the Krylov step was 1.4e-3 off the dense one at tolerance 1e-8 (7% in the drift's solves at 1e-4).
    steps = {}
    for solver in ('DenseSolver', 'KrylovSolver'):
        system, integrator, positions, _ = coupled_bodies_above_wall(rl.RigidBrownianIntegrator, 1.0, 1e6, scale=1000.0, temperature=0)
        push = mm.CustomExternalForce('-fx*x-fy*y-fz*z')
        for name in ('fx', 'fy', 'fz'):
            push.addPerParticleParameter(name)
        for i in range(system.getNumParticles()):
            push.addParticle(i, [1.0+0.3*i, -0.5+0.1*i, 0.2*(i % 3)-0.1])
        system.addForce(push)
        integrator.setHydrodynamicSolver(getattr(rl.RigidBrownianIntegrator, solver))
        integrator.setHydrodynamicTolerance(1e-8)
        context = mm.Context(system, integrator, platform('CPU'))
        context.setPositions(positions)
        integrator.step(1)
        steps[solver] = context.getState(getPositions=True).getPositions(asNumpy=True)._value-np.array([list(p) for p in positions])
    error = np.linalg.norm(steps['KrylovSolver']-steps['DenseSolver'])/np.linalg.norm(steps['DenseSolver'])
    assert error < 1e-6, error


# --- Equilibrium above the wall: the drift keeps the Gibbs-Boltzmann heights ---

def sedimented_system(count, radius, weight, repulsion, decay):
    """Spheres (one particle each) pulled down by their weight (kJ/mol/nm) and pushed off the wall by
    repulsion*exp(-(z - radius)/decay), as CustomExternalForces on their particles."""
    system = mm.System()
    force = mm.CustomExternalForce('weight*z+repulsion*exp(-(z-radius)/decay)')
    for name, value in [('weight', weight), ('repulsion', repulsion), ('radius', radius), ('decay', decay)]:
        force.addGlobalParameter(name, value)
    for i in range(count):
        system.addParticle(1.0)
        force.addParticle(i, [])
    system.addForce(force)
    return system


def gibbs_boltzmann_heights(radius, weight, repulsion, decay, edges):
    """The probability of each height bin, by quadrature of exp(-U/kT) above the wall."""
    z = np.linspace(1e-6, edges[-1]+20*KT/weight, 400001)
    density = np.exp(-(weight*z+repulsion*np.exp(-(z-radius)/decay))/KT)
    cumulative = np.concatenate([[0], np.cumsum((density[1:]+density[:-1])/2*np.diff(z))])
    return np.diff(np.interp(edges, z, cumulative))/cumulative[-1]


def equilibrium_heights(integrator_class, spheres=16, steps=60000, h=0.01, stride=10):
    """Heights of spheres sedimented above the wall, each alone in a Context of its own (so they are
    independent samples), binned per sphere; and the Gibbs-Boltzmann probability of each bin."""
    radius, viscosity = 1.0, 1.0
    weight, repulsion, decay = 4*KT/radius, 4*KT, 0.1*radius
    edges = np.array([0.0, 1.1, 1.2, 1.3, 1.45, 1.65, 10.0])*radius
    counts = []
    for sphere in range(spheres):
        system = sedimented_system(1, radius, weight, repulsion, decay)
        _, integrator, positions = sphere_layer(1, radius, 1.5*radius, 0, viscosity, h, integrator_class)
        integrator.setRandomNumberSeed(101+sphere)
        if integrator_class is rl.RigidLangevinIntegrator:
            integrator.setScheme(rl.RigidLangevinIntegrator.BAOAB)
        context = mm.Context(system, integrator, platform('Reference'))
        context.setPositions(positions)
        integrator.step(500)
        heights = []
        for _ in range(steps//stride):
            integrator.step(stride)
            heights.append(context.getState(getPositions=True).getPositions(asNumpy=True)._value[0, 2])
        counts.append(np.histogram(heights, edges)[0])
    return np.array(counts), gibbs_boltzmann_heights(radius, weight, repulsion, decay, edges)


def assert_gibbs_boltzmann(counts, expected):
    # The spheres are independent, so the spread of each bin's fraction over them gives its standard
    # error, correlations in time included.
    fractions = counts/counts.sum(axis=1, keepdims=True)
    se = fractions.std(axis=0, ddof=1)/math.sqrt(len(fractions))
    z = (fractions.mean(axis=0)-expected)/se
    assert np.all(np.abs(z) < 4.5), (fractions.mean(axis=0), expected, z)
    chi2 = float(np.sum(z**2))
    assert chi2 < 22, chi2  # 6 bins, 5 free: p = 5e-4


def test_brownian_sphere_above_the_wall_samples_gibbs_boltzmann_heights():
    # Without the drift kT dmu_perp/dz the heights would follow exp(-U/kT)/mu_perp(z): the highest
    # bin would hold 0.106 instead of 0.145, the second 0.203 instead of 0.172 (standard errors ~0.006).
    counts, expected = equilibrium_heights(rl.RigidBrownianIntegrator)
    assert_gibbs_boltzmann(counts, expected)


def test_langevin_sphere_above_the_wall_samples_gibbs_boltzmann_heights():
    counts, expected = equilibrium_heights(rl.RigidLangevinIntegrator)
    assert_gibbs_boltzmann(counts, expected)


# --- Two bodies bound by a spring: interactions change dynamics, never statics ---

def spring_bound_pair(interactions, seed, stiffness=20.0, rest=0.5, h=0.005):
    """Two L-shaped bodies (five blobs of 0.3 nm) whose corner blobs are joined by a spring, open space."""
    system, integrator = mm.System(), rl.RigidBrownianIntegrator(300, 1.0, h)
    integrator.setRandomNumberSeed(seed)
    positions = []
    for shift, turn in [(np.zeros(3), [0.1, 0.2, 0.3]), (np.array([rest, 0.2, 0.1]), [1.0, -0.4, 2.0])]:
        first = system.getNumParticles()
        for i, p in enumerate(L_SHAPE @ Rotation.from_rotvec(turn).as_matrix().T + shift):
            system.addParticle(1.0)
            integrator.setParticleRadius(first+i, 0.3)
            positions.append(mm.Vec3(*p))
        integrator.addRigidBody(list(range(first, first+len(L_SHAPE))))
    spring = mm.HarmonicBondForce()
    spring.addBond(0, len(L_SHAPE), rest, stiffness)
    system.addForce(spring)
    integrator.setHydrodynamicInteractions(interactions)
    context = mm.Context(system, integrator, platform('CPU'))
    context.setPositions(positions)
    return context, integrator


def spring_statistics(interactions, pairs=12, steps=50000, stride=10):
    """Per pair (each in a Context of its own, so independent): the mean separation of the corner
    blobs, and the mean of cos^2 of the angle between each body's long arm and the separation, both
    bodies together."""
    separations, cosines = [], []
    for pair in range(pairs):
        context, integrator = spring_bound_pair(interactions, 31+pair)
        integrator.step(500)
        lengths, squares = [], []
        for _ in range(steps//stride):
            integrator.step(stride)
            p = context.getState(getPositions=True).getPositions(asNumpy=True)._value
            s = p[5]-p[0]
            r = np.linalg.norm(s)
            lengths.append(r)
            squares += [((p[2]-p[0])@s/np.linalg.norm(p[2]-p[0])/r)**2, ((p[7]-p[5])@s/np.linalg.norm(p[7]-p[5])/r)**2]
        separations.append(np.mean(lengths))
        cosines.append(np.mean(squares))
    return np.array(separations), np.array(cosines)


def spring_gibbs_boltzmann_separation(stiffness=20.0, rest=0.5):
    """The mean separation under exp(-U/kT): density r^2 exp(-k (r - r0)^2/(2 kT)), whatever the
    orientations (the spring acts on two body-fixed points, so they are uniform and independent of r)."""
    r = np.linspace(0, rest+20*math.sqrt(KT/stiffness), 400001)
    density = r**2*np.exp(-0.5*stiffness*(r-rest)**2/KT)
    return float(np.sum(r*density)/np.sum(density))


def test_spring_bound_pair_samples_the_same_statics_with_and_without_interactions():
    # With interactions the bodies' mobility depends on their separation and orientations, and only
    # the drift keeps the Gibbs-Boltzmann distribution: without it (checked in a scratch build, 16
    # pairs of 60000 steps) the arms lined up with the separation, <cos^2> = 0.3473 +- 0.0024 against
    # the exact 1/3 (5.8 standard errors, about 4.6 at this test's length; with it 0.3335 +- 0.0031).
    # Without interactions
    # (the peer) the mobility is constant in each body's frame. Both against the exact values, each
    # within 4 standard errors over the 12 independent pairs.
    for interactions in (True, False):
        separations, cosines = spring_statistics(interactions)
        for name, values, exact in [('separation', separations, spring_gibbs_boltzmann_separation()), ('cos^2', cosines, 1/3)]:
            se = values.std(ddof=1)/math.sqrt(len(values))
            assert abs(values.mean()-exact) < 4*se, (interactions, name, values.mean(), exact, se)


# --- States, checkpoints and the body-state reporter, as for the Langevin integrator ---

def test_checkpoints_and_states_continue_exactly_and_the_reporter_writes(tmp_path):
    from openmm import app
    system = sedimented_system(3, 1.0, 4*KT, 4*KT, 0.1)
    _, integrator, positions = sphere_layer(3, 1.0, 1.5, 5.0, 1.0, 0.01)
    integrator.setHydrodynamicSolver(integrator.KrylovSolver)
    topology = app.Topology()
    chain = topology.addChain()
    for i in range(3):
        topology.addAtom('S', app.element.carbon, topology.addResidue('S', chain))
    simulation = app.Simulation(topology, system, integrator, platform('CPU'))
    simulation.context.setPositions(positions)
    simulation.reporters.append(rl.RigidBodyStateReporter(str(tmp_path/'bodies.csv'), 5))
    simulation.step(10)
    checkpoint = simulation.context.createCheckpoint()
    state = simulation.context.getState(getPositions=True, getVelocities=True, getIntegratorParameters=True)
    simulation.step(20)
    ahead = simulation.context.getState(getPositions=True).getPositions(asNumpy=True)._value
    simulation.context.loadCheckpoint(checkpoint)
    simulation.step(20)
    assert np.array_equal(simulation.context.getState(getPositions=True).getPositions(asNumpy=True)._value, ahead)
    simulation.context.setState(state)
    assert np.array_equal(simulation.context.getState(getPositions=True).getPositions(asNumpy=True)._value,
                          state.getPositions(asNumpy=True)._value)
    rows = np.genfromtxt(tmp_path/'bodies.csv', delimiter=',', names=True)
    assert len(rows) == 3*(30//5+4) and np.all(rows['z_nm'] > 0)


# --- What it refuses ---

def test_a_wall_needs_hydrodynamic_interactions():
    system, integrator, positions = sphere_layer(1, 1.0, 2.0, 1.0, 1.0, 0.001)
    integrator.setHydrodynamicInteractions(False)
    with pytest.raises(mm.OpenMMException, match='setHydrodynamicInteractions'):
        mm.Context(system, integrator, platform('Reference'))


def test_a_body_through_the_wall_is_named():
    system, integrator, positions = sphere_layer(2, 1.0, 2.0, 10.0, 1.0, 0.001)
    context = mm.Context(system, integrator, platform('Reference'))
    positions[1] = mm.Vec3(10, 0, -0.5)
    context.setPositions(positions)
    with pytest.raises(mm.OpenMMException, match='body 1.*below the no-slip wall'):
        integrator.step(1)


def test_a_step_that_crosses_the_wall_says_so():
    # The wall's own friction slows a body that nears it, so only a step far too large for the force
    # (here 16 radii for a sphere 1.5 radii up) puts it through.
    system = sedimented_system(1, 1.0, 1e5*KT, 0.0, 0.1)
    _, integrator, positions = sphere_layer(1, 1.0, 1.5, 10.0, 1.0, 0.01)
    context = mm.Context(system, integrator, platform('Reference'))
    context.setPositions(positions)
    with pytest.raises(mm.OpenMMException, match='which moved it through: take smaller steps'):
        integrator.step(5)


def test_every_refusal_names_the_brownian_integrator():
    # The bodies' model, their blobs, the checkpoint reader and the step's checks serve both
    # integrators; a Brownian user's messages must name RigidBrownianIntegrator (they named
    # RigidLangevinIntegrator until 2026-12-02).
    def refused(action, fragment):
        with pytest.raises(mm.OpenMMException) as error:
            action()
        assert str(error.value).startswith('RigidBrownianIntegrator: ') and fragment in str(error.value), str(error.value)

    system, integrator, positions = sphere_layer(2, 1.0, 2.0, 10.0, 1.0, 0.001)
    system.setParticleMass(1, 0.0)
    refused(lambda: mm.Context(system, integrator, platform('Reference')), 'rigid body 1 has no particle with mass')  # the model
    system, integrator, positions = sphere_layer(2, 1.0, 2.0, 10.0, 1.0, 0.001)
    context = mm.Context(system, integrator, platform('Reference'))
    positions[1] = mm.Vec3(10, 0, -0.5)
    context.setPositions(positions)
    refused(lambda: integrator.step(1), 'hydrodynamic interactions')  # the blobs
    context.setPositions(sphere_layer(2, 1.0, 2.0, 10.0, 1.0, 0.001)[2])
    integrator.step(1)
    checkpoint = bytearray(context.createCheckpoint())
    checkpoint[-20] ^= 0xFF
    refused(lambda: context.loadCheckpoint(bytes(checkpoint)), 'checkpoint')  # the checkpoint reader
    system, integrator, positions = sphere_layer(2, 1.0, 2.0, 10.0, 1.0, 0.001)
    system.addForce(mm.CMMotionRemover())
    refused(lambda: mm.Context(system, integrator, platform('Reference')), 'CMMotionRemover')  # the step's checks


def test_viscosity_must_be_positive():
    with pytest.raises(mm.OpenMMException, match='set a positive viscosity'):
        rl.RigidBrownianIntegrator(300, 0.0, 0.001)
    system, integrator, positions = sphere_layer(1, 1.0, 2.0, 1.0, 1.0, 0.001)
    context = mm.Context(system, integrator, platform('Reference'))
    context.setPositions(positions)
    integrator.setViscosity(0.0)
    with pytest.raises(mm.OpenMMException, match='set a positive viscosity'):
        integrator.step(1)


def test_serialization_round_trip():
    _, integrator, _ = sphere_layer(2, 1.0, 2.0, 10.0, 1.0, 0.001)
    copy = rl.RigidBrownianIntegrator.cast(mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(integrator)))
    assert copy.getWall() == integrator.getWall() and copy.getHydrodynamicInteractions()
    assert copy.getNumRigidBodies() == 2 and copy.getStepSize() == integrator.getStepSize()
    assert copy.getViscosity() == integrator.getViscosity() and copy.getTemperature() == integrator.getTemperature()
