"""Boomerang colloids above a no-slip wall (examples/sedimented_boomerangs.py): the example's quick run
on every platform against the Gibbs-Boltzmann density; one boomerang's cross-point and lowest-blob
heights against it under RigidBrownianIntegrator (the stochastic drift's test) and under
RigidLangevinIntegrator (the wall's friction and noise); and the Krylov step in colloid units
against the dense one."""
import functools
import math
import pathlib
import subprocess
import sys

import numpy as np
import openmm as mm
import pytest
import rigidlangevin as rl
from rigidlangevin.statistics import agreement_threshold, standard_error

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT/'examples'))
import sedimented_boomerangs as sb  # noqa: E402


def table_rows(path):
    """The example's table: {label: (mean, block error, bodies' spread, Gibbs-Boltzmann mean)}."""
    rows = {}
    for line in path.read_text(encoding='utf-8').splitlines():
        cells = [c.strip() for c in line.strip('|').split('|')]
        if cells[0] in ('with (wall)', 'without'):
            mean, block = (float(v) for v in cells[1].split('±'))
            rows[cells[0]] = (mean, block, float(cells[2].strip('± ')), float(cells[3]))
    return rows


def test_sedimented_boomerangs_example(tmp_path, platform):
    # The quick run (9 bodies, 4 s) starts every body from a Gibbs-Boltzmann sample, so each body's
    # own mean height is an unbiased and independent estimate of the density's mean at any run
    # length: the spread over the bodies is the standard error (blocks of 0.4 s are far shorter than
    # the heights' correlation time here, so the block error is not used). It catches a wrong
    # force, noise or mobility that moves the suspension away from equilibrium within seconds (the
    # 0.01 s step without the wall's hydrodynamics lifts it by 3.1 um, 4.7 errors, in 4 s), and bodies
    # that do not move; a missing drift acts too slowly for it (see the tests below).
    result = subprocess.run([sys.executable, str(ROOT/'examples'/'sedimented_boomerangs.py'), '--quick', '--platform', platform.name,
                             '--out', str(tmp_path)], capture_output=True, encoding='utf-8', timeout=300)
    assert result.returncode == 0, result.stderr
    rows = table_rows(tmp_path/'table.md')
    window = agreement_threshold(8)
    for label, (mean, _, spread, expected) in rows.items():
        assert abs(mean-expected) < window*spread, (label, mean, spread, expected)
    heights = np.load(tmp_path/'heights.npz')
    for name in ('with_interactions', 'without'):
        moved = np.sqrt(np.mean((heights[name][-1]-heights[name][0])**2))
        assert moved > 0.3, (name, moved)  # um; diffusion alone gives about 1 um in 4 s
    assert (tmp_path/'boomerangs.png').exists()


# --- One boomerang above the wall: the Gibbs-Boltzmann heights under both integrators ---

WEIGHT_SCALE = 4  # the anchors' weight four times over: the heights decorrelate within 2 s
FRACTIONS = np.arange(1, 8)/8  # eight bins of equal Gibbs-Boltzmann probability


@functools.lru_cache(maxsize=None)
def gibbs_boltzmann():
    # 48 points over orientations: the lowest blob's bin probabilities to about 1e-4 (the lowest of
    # the blobs is a kinked function of the orientation, so the quadrature converges only as 1/n^2;
    # 32 points are 2e-4 off), a twentieth of their standard errors below.
    return sb.GibbsBoltzmann(sb.Forces(WEIGHT_SCALE), points=48)


def one_boomerang_replicas(replicas, steps, stride, seed, make_integrator=None, blob_mass=1.0):
    """One boomerang alone in each of `replicas` Contexts (so the replicas are independent), each from
    a Gibbs-Boltzmann sample, on Reference (dense, exact): every stride steps its cross point's and
    lowest blob's heights (um), replicas x samples x 2, and under a RigidLangevinIntegrator (made by
    make_integrator(); without it the example's RigidBrownianIntegrator) the kinetic temperature
    (K), replicas x samples."""
    forces = sb.Forces(WEIGHT_SCALE)
    langevin = make_integrator is not None
    heights, temperatures = [], []
    for replica, start in enumerate(sb.sample_bodies(forces, replicas, np.random.default_rng(seed))):
        integrator, context = sb.build(forces, [start], True, 'Reference', seed=100*seed+replica,
                                       integrator=make_integrator() if langevin else None, blob_mass=blob_mass)
        if langevin:
            context.setVelocitiesToTemperature(sb.TEMPERATURE, 100*seed+replica)
        samples, kinetic = [], []
        for _ in range(steps//stride):
            integrator.step(stride)
            z = context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(mm.unit.nanometer)[:, 2]/sb.NM_PER_UM
            samples.append((z[sb.CROSS_POINT], z.min()))
            if langevin:
                kinetic.append(integrator.computeSystemTemperature().value_in_unit(mm.unit.kelvin))
        heights.append(samples)
        temperatures.append(kinetic)
    return np.array(heights), np.array(temperatures)


def height_histograms(heights):
    """Per replica, the fraction of its samples in each bin of equal Gibbs-Boltzmann probability of the
    cross point's and the lowest blob's height; and each bin's probability."""
    gb = gibbs_boltzmann()
    histograms = {}
    for column, name in enumerate(('cross point', 'lowest blob')):
        lowest = name == 'lowest blob'
        edges = np.concatenate([[0], gb.quantiles(FRACTIONS, lowest), [gb.heights[-1]]])
        fractions = np.array([np.histogram(np.clip(h[:, column], 0, edges[-1]), edges)[0]/len(h) for h in heights])
        histograms[name] = (fractions, gb.bin_probabilities(edges, lowest))
    return histograms


def hotelling(fractions, expected, false_alarm=1e-3):
    """Hotelling's T^2 of the replicas' mean bin fractions against the expected probabilities (the
    last bin left out: the fractions sum to one), with the bins' covariance from the replicas'
    spread; and the threshold it exceeds with probability false_alarm where they agree, from the F
    distribution. Per-bin z scores for the message."""
    from scipy.stats import f
    n, p = fractions.shape[0], fractions.shape[1]-1
    difference = fractions[:, :p].mean(axis=0)-expected[:p]
    t2 = float(n*difference @ np.linalg.solve(np.cov(fractions[:, :p], rowvar=False), difference))
    threshold = p*(n-1)/(n-p)*float(f.ppf(1-false_alarm, p, n-p))
    return t2, threshold, (fractions.mean(axis=0)-expected)/standard_error(fractions)


def assert_gibbs_boltzmann_heights(heights):
    for name, (fractions, expected) in height_histograms(heights).items():
        t2, threshold, z = hotelling(fractions, expected)
        assert t2 < threshold, (name, t2, threshold, np.round(z, 1))


def test_one_boomerang_under_brownian_dynamics_samples_gibbs_boltzmann_heights():
    # 32 boomerangs, each alone, from Gibbs-Boltzmann samples, 20000 steps of 0.01 s (200 s, about
    # 100 correlation times): histograms of the cross point's and the lowest blob's heights, eight
    # bins of equal Gibbs-Boltzmann probability each (the density sampled over orientations), T^2
    # 11.8 and 13.6 against the threshold 44.7. Without the stochastic drift kT div N (the wall's,
    # and the cross point's being off the centre of mobility; a scratch build with the drift
    # switched off) the body sinks towards the wall, where its mobility is low: the lowest blob's
    # lowest bin holds 0.155 +- 0.003 and its highest but one 0.100 +- 0.002 instead of 0.125 (10.3
    # and 12.8 standard errors), T^2 228 (cross point: lowest bin 0.160 +- 0.004, 8.2 standard
    # errors, T^2 91). The mean cross-point height, which this test replaces, moved by 4.7 standard
    # errors only (1.930 +- 0.020 um against 2.025).
    heights, _ = one_boomerang_replicas(32, 20000, 10, 5)
    assert_gibbs_boltzmann_heights(heights)


LANGEVIN_STEP_S, LANGEVIN_RELAXATION_S = 0.08, 0.5


def langevin_integrator():
    integrator = rl.RigidLangevinIntegrator(sb.TEMPERATURE, sb.VISCOSITY, LANGEVIN_STEP_S*1e12)
    integrator.setScheme(rl.RigidLangevinIntegrator.BAOAB)
    return integrator


def langevin_blob_mass():
    """Each blob's mass (amu) that gives the body m/gamma = LANGEVIN_RELAXATION_S, gamma the mean of
    its open-space translational friction's diagonal."""
    gamma = np.trace(sb.body_tensor()[:3, :3])/3*sb.VISCOSITY.value_in_unit(rl.md_viscosity)
    return LANGEVIN_RELAXATION_S*1e12*gamma/len(sb.BLOBS_UM)


def test_one_boomerang_under_langevin_dynamics_samples_gibbs_boltzmann_heights():
    # The same boomerang under RigidLangevinIntegrator (BAOAB with the wall's coupled friction), 48
    # replicas of 20000 steps of 0.08 s. It samples exp(-U/kT) through its friction and noise, with
    # no drift term, so the heights check that the noise matches the friction wherever the wall
    # changes it, and the kinetic temperature that it does on average. The statics do not depend on
    # the masses, so the test chooses them for speed: blobs of 3.1e17 amu give the body m/gamma =
    # 0.5 s (gamma its open-space translational friction; its six modes relax in 0.16-0.58 s, faster
    # near the wall), the step a half of the fastest, so the friction acts within a few steps, and
    # the heights decorrelate within about 2 s (25 steps) as in the overdamped limit. Lighter bodies
    # need shorter steps against the wall's stiff repulsion: at 0.16 s the lowest blob's lowest bin
    # holds 0.1216 +- 0.0007 (T^2 57 against 35; 1457 with m/gamma = 0.2 s). With the noise's
    # variance 5% high (the integrator at 315 K) the histograms give T^2 57 and 96 and the kinetic
    # temperature is 315.2 +- 0.5 K; as it is, T^2 6.7 and 14.4 (threshold 35.4), 300.2 +- 0.5 K.
    heights, temperatures = one_boomerang_replicas(48, 20000, 5, 6, langevin_integrator, langevin_blob_mass())
    assert_gibbs_boltzmann_heights(heights)
    kinetic = temperatures.mean(axis=1)
    assert abs(kinetic.mean()-sb.TEMPERATURE) < agreement_threshold(len(kinetic)-1)*standard_error(kinetic), (kinetic.mean(), standard_error(kinetic))


# --- The Krylov step in colloid units: the wall and the other bodies, at a loose tolerance ---

def colloid_step(platform, tolerance=None, interactions=True):
    """One step at zero temperature (no noise, no drift: the displacement is N F h) of two
    boomerangs 1.5 um apart near the wall, in colloid units (blobs of 325 nm, 0.01 s)."""
    from scipy.spatial.transform import Rotation
    forces = sb.Forces(WEIGHT_SCALE)
    starts = [(Rotation.from_rotvec([0.4, 0.1, 0.2]).as_matrix(), 0.8), (Rotation.from_rotvec([-0.2, 0.5, 1.0]).as_matrix(), 1.2)]
    integrator, context = sb.build(forces, starts, interactions, platform, tolerance, spacing=1.5)
    integrator.setTemperature(0)
    if interactions:
        integrator.setHydrodynamicSolver(rl.RigidBrownianIntegrator.KrylovSolver if tolerance else rl.RigidBrownianIntegrator.DenseSolver)
    before = context.getState(getPositions=True).getPositions(asNumpy=True)._value
    integrator.step(1)
    return context.getState(getPositions=True).getPositions(asNumpy=True)._value-before


def test_krylov_step_in_colloid_units_agrees_with_the_dense_one():
    # GMRES on the bodies' saddle-point problem stops on the norm of its residual: unscaled, its
    # blob rows (velocities) weigh 1/(6 pi a) = 1.6e-4 nm^-1 as much as its force rows for blobs of
    # 325 nm, and a solve to 1e-3 stopped as soon as each body's forces balanced (its own blocks,
    # the preconditioner), before the wall or the other body entered: off the dense step by 5.4
    # times its norm here at 1e-3 and 1e-6 (0.48 at 1e-8), and the drift of a boomerang near the
    # wall lost (its mean step 0.010 +- 0.008 um instead of 0.205 +- 0.009). Scaled, the step at
    # 1e-3 is within 2.4% of the dense one (a bound of 10%), at 1e-8 within 1e-7 (bound 1e-6).
    dense = colloid_step('Reference')
    open_space = colloid_step('Reference', interactions=False)
    assert np.linalg.norm(open_space-dense) > 0.2*np.linalg.norm(dense)  # the wall and the other body matter
    for tolerance, bound in ((1e-3, 0.1), (1e-8, 1e-6)):
        krylov = colloid_step('CPU', tolerance)
        assert np.linalg.norm(krylov-dense) < bound*np.linalg.norm(dense), (tolerance, np.linalg.norm(krylov-dense)/np.linalg.norm(dense))
