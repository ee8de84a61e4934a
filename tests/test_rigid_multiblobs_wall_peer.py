"""The project's blob mobility and coupled mobility against RigidMultiblobsWall's numbers on the
16-boomerang suspension of the hydrodynamic-interaction benchmarks (issues 60 and 61).

benchmarks/peers/rigid_multiblobs_wall_driver.py ran the peer (in a virtual environment of its own)
and saved, in benchmarks/hydrodynamics/results/rigid_multiblobs_wall.json, the product M f of its
numba Rotne-Prager-Yamakawa kernel for a fixed random f on the 240 blobs, and the bodies' velocities
from its GMRES solve (relative residual below 1e-12) for fixed random forces and torques. These
tests compare the project's dense results with those saved numbers, so they run without the peer;
the last one reruns the peer where its folder exists (not on CI) to check that the saved numbers
are still what it computes.

Lengths stay in um: the resistance per unit viscosity is homogeneous in length, so giving the
project's API numbers in um returns the mobility in um units, which the peer's divided by its
viscosity eta must equal. The blobs overlap (0.3 um apart, radius 0.325 um), so the overlap form
of RPY is compared as well as the far field.
"""
import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import rigidlangevin.hydrodynamics as hydro

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent/'benchmarks'/'hydrodynamics'))
import boomerang_suspension  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
RESULTS = ROOT/'benchmarks'/'hydrodynamics'/'results'/'rigid_multiblobs_wall.json'
PEER = ROOT/'build-peers'/'rigid-multiblobs-wall'


def saved_reference():
    with open(RESULTS, encoding='utf-8') as f:
        return json.load(f)['reference_16_bodies']


def blob_mobility(positions, radius):
    """The project's blob mobility M per unit viscosity: each blob a body of its own whose reference
    point is its centre, so the translational rows and columns of the coupled resistance are M^-1."""
    resistance = hydro.coupledResistance([([p], [radius], p) for p in positions])
    translations = np.ravel([[6*k, 6*k+1, 6*k+2] for k in range(len(positions))])
    return np.linalg.inv(resistance[np.ix_(translations, translations)])


def relative_error(computed, expected):
    return np.linalg.norm(computed-expected)/np.linalg.norm(expected)


def test_blob_mobility_product_matches_the_peer_in_open_space():
    """M f of 240 overlapping and distant blobs agrees with the peer's numba product to round-off.
    A wrong overlap branch, a factor in the far field or a radius off by 1e-6 fails it. The
    tolerance is 10 ulps times M's condition number (the inverse of an inverse loses that many)."""
    ref = saved_reference()
    positions = np.array(ref['blob_positions_um'])
    mobility = blob_mobility(positions, ref['blob_radius_um'])/ref['eta']
    velocities = mobility@np.array(ref['blob_forces'])
    tolerance = 10*np.finfo(float).eps*np.linalg.cond(mobility)
    error = relative_error(velocities, np.array(ref['blob_velocities_open']))
    assert error < tolerance, f'relative error {error:.2e} (tolerance {tolerance:.1e})'
    assert tolerance < 1e-11


def test_coupled_mobility_matches_the_peers_solve():
    """The 16 boomerangs' velocities and angular velocities (about their corner blobs) for random
    forces and torques agree with the peer's preconditioned GMRES, solved to a relative residual of
    1e-12: K, the torque's reference point and the order of (velocity, angular velocity) per body
    must be the peer's. The tolerance is the solve's residual times the mobility's condition number."""
    ref = saved_reference()
    scene = dict(ref, locations_um=ref['body_locations_um'], blob_radii_um=[ref['blob_radius_um']]*len(ref['blob_positions_um']))
    mobility = hydro.coupledMobility(boomerang_suspension.coupled_bodies(scene, scale=1.0))/ref['eta']
    velocities = mobility@np.array(ref['body_forces_torques'])
    tolerance = 10*max(ref['solve_relative_residual'], 1e-15)*np.linalg.cond(mobility)
    error = relative_error(velocities, np.array(ref['body_velocities_open']))
    assert error < tolerance, f'relative error {error:.2e} (tolerance {tolerance:.1e})'
    assert tolerance < 1e-8


def test_the_scene_generator_still_makes_the_timed_scene():
    """benchmarks/hydrodynamics/boomerang_suspension.py (the project's side of the benchmark) gives
    the blobs the peer was timed and checked on, from the same seed: the bodies are 1.4291 um^3,
    16 of them fill 5% of the cube, and none overlaps another."""
    ref = saved_reference()
    scene = boomerang_suspension.scene(16)
    assert np.abs(np.array(scene['blob_positions_um'])-np.array(ref['blob_positions_um'])).max() < 1e-12
    assert scene['body_volume_um3'] == pytest.approx(1.42915, abs=2e-5)
    assert 16*scene['body_volume_um3']/scene['box_side_um']**3 == pytest.approx(0.05, rel=1e-12)
    blobs = np.array(scene['blob_positions_um']).reshape(16, 15, 3)
    gaps = np.linalg.norm(blobs[:, None, :, None]-blobs[None, :, None, :], axis=-1)
    gaps[np.arange(16), np.arange(16)] = np.inf
    assert gaps.min() >= 2*boomerang_suspension.BLOB_RADIUS_UM


def test_peer_setup_refuses_a_missing_snapshot_clearly(tmp_path):
    """On CI the peer's source is absent: its setup script says so and stops, creating nothing."""
    result = subprocess.run(['bash', str(ROOT/'scripts'/'peers'/'setup_rigid_multiblobs_wall.sh'), '--snapshot',
                             str(tmp_path/'absent'), '--dest', str(tmp_path/'peer')], capture_output=True, encoding='utf-8')
    assert result.returncode == 1
    assert 'is absent' in result.stderr and '--snapshot' in result.stderr
    assert not (tmp_path/'peer').exists()


@pytest.mark.skipif(not (PEER/'venv'/'bin'/'python').exists(),
                    reason='RigidMultiblobsWall is not set up here (scripts/peers/setup_rigid_multiblobs_wall.sh; '
                           'it is not a dependency, so CI has no copy)')
def test_saved_peer_numbers_are_what_the_peer_computes(tmp_path):
    """The peer, run again, gives the saved products and velocities (its numba kernels run in
    parallel with fastmath, so to round-off, not bit for bit)."""
    scenes = tmp_path/'scenes.json'
    subprocess.run([sys.executable, str(ROOT/'benchmarks'/'hydrodynamics'/'boomerang_suspension.py'), '--out', str(scenes),
                    '--sizes', '16'], check=True)
    out = tmp_path/'peer.json'
    subprocess.run([str(PEER/'venv'/'bin'/'python'), str(ROOT/'benchmarks'/'peers'/'rigid_multiblobs_wall_driver.py'),
                    '--peer', str(PEER), '--scenes', str(scenes), '--out', str(out), '--reference-only'], check=True)
    fresh, saved = json.loads(out.read_text(encoding='utf-8'))['reference_16_bodies'], saved_reference()
    for key in ('blob_velocities_open', 'blob_velocities_wall'):
        assert relative_error(np.array(fresh[key]), np.array(saved[key])) < 1e-13, key
    assert relative_error(np.array(fresh['body_velocities_open']), np.array(saved['body_velocities_open'])) < 1e-10
