"""Boomerang colloids above a no-slip wall under RigidBrownianIntegrator (examples/sedimented_boomerangs.py):
the example's quick run on every platform against the Gibbs-Boltzmann density, one boomerang's
cross-point height (the stochastic drift's test), and the Krylov step in colloid units against the
dense one."""
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
    # that do not move; a missing drift acts too slowly for it (see the test below).
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


# --- One boomerang: the drift keeps the Gibbs-Boltzmann heights ---

WEIGHT_SCALE = 4  # the anchors' weight four times over: the heights decorrelate within 2 s (200 steps)


def test_one_boomerang_samples_gibbs_boltzmann_cross_point_heights():
    # Sixteen boomerangs, each alone in a Context (independent), each from a Gibbs-Boltzmann sample,
    # 20000 steps of 0.01 s (200 s, about 100 correlation times) on Reference (dense, exact). The
    # density's mean cross-point height is 2.025 um; each replica's time mean is an independent
    # estimate, standard error about 0.026 um (1.3%). Without the stochastic drift kT div N (the
    # wall's, and the cross point's being off the centre of mobility) the mean is 1.913 +- 0.026 um
    # (a scratch build with the drift switched off), 5.5% low, 4.4 standard errors: the test fails
    # at its threshold (4.07 standard errors, 0.104 um), but only just. It cannot see an error under about 5% in the mean height,
    # nor one that leaves the mean alone; the sphere's test (test_brownian.py) checks the height
    # histogram bin by bin.
    forces = sb.Forces(WEIGHT_SCALE)
    expected = sb.GibbsBoltzmann(forces).mean
    starts = sb.sample_bodies(forces, 16, np.random.default_rng(5))
    means = []
    for replica, start in enumerate(starts):
        integrator, context = sb.build(forces, [start], True, 'Reference', seed=100+replica)
        means.append(sb.cross_point_heights(integrator, context, 20000, 50).mean())
    error = standard_error(means)
    assert error < 0.04, error
    assert abs(np.mean(means)-expected) < agreement_threshold(len(means)-1)*error, (np.mean(means), error, expected)


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
