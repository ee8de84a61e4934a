"""Times RigidMultiblobsWall (the hydrodynamic-interaction benchmarks' peer) on the boomerang
suspensions of benchmarks/hydrodynamics/boomerang_suspension.py, with its own code paths.

Run with the peer's Python (scripts/peers/setup_rigid_multiblobs_wall.sh makes it), not the
project's; benchmarks/peers/run_rigid_multiblobs_wall.sh runs every step:

    build-peers/rigid-multiblobs-wall/venv/bin/python benchmarks/peers/rigid_multiblobs_wall_driver.py \
        --peer build-peers/rigid-multiblobs-wall --scenes build-peers/boomerang_suspension.json --out results.json

For each number of bodies, in open space and above a no-slip wall at z = 0:
- one blob mobility product M f, its numba functions (no_wall_ / single_wall_mobility_trans_times_force_numba);
- one mobility solve: its GMRES (general_application_utils.gmres through QuaternionIntegrator.
  solve_mobility_problem: right preconditioning, restart 60, the right-hand side scaled to norm 1)
  to a relative residual of 1e-8 with its block-diagonal preconditioner (multi_bodies.
  build_block_diagonal_preconditioner: each body's own problem solved exactly); the preconditioner's
  construction is timed on its own;
- above the wall, one Brownian step of the scheme its documentation recommends for many rigid
  multiblobs, stochastic_Slip_Trapz (3 mobility solves, 1 Lanczos, 2 extra products), at the
  solver tolerance of its boomerang input files (1e-3, GMRES and Lanczos alike), dt = 0.01 s and
  rf_delta = 1e-6 (its documentation's value for products in double precision, as numba's are).
Forces are its defaults: gravity and the wall's repulsion per blob (multi_bodies_functions), the
blob-blob Yukawa repulsion (forces_numba), with the parameters of its boomerang input files (um, s).
Each time is wall-clock and process CPU time (all threads) of repeats, with mean and standard error.
For 16 bodies it also writes M f for a fixed random f (free space and wall) and the bodies'
velocities for a fixed random force-torque from a solve to 1e-12 (free space), so that the project
can check its own products and mobility against them (tests/test_rigid_multiblobs_wall_peer.py).
"""
import os

# Its thread count (numba's; 2 unless NUMBA_NUM_THREADS says otherwise) and the BLAS's the same,
# before numpy and numba load.
for _name in ('NUMBA_NUM_THREADS', 'OMP_NUM_THREADS', 'OPENBLAS_NUM_THREADS', 'MKL_NUM_THREADS'):
    os.environ.setdefault(_name, os.environ.get('NUMBA_NUM_THREADS', '2'))

import argparse  # noqa: E402
import functools  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import types  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

# The peer's boomerang input files (multi_bodies/examples/boomerang_suspension), units um, s, mg.
PHYSICS = {'eta': 8.9e-4, 'g': 0.0001539384, 'kT': 0.0041419464,
           'repulsion_strength_wall': 0.095713728509, 'debye_length_wall': 0.162278695459,
           'repulsion_strength': 0.095713728509, 'debye_length': 0.162278695459}
SOLVE_TOLERANCE = 1e-8
REFERENCE_SOLVE_TOLERANCE = 1e-12
STEP = {'scheme': 'stochastic_Slip_Trapz', 'tolerance': 1e-3, 'dt': 0.01, 'rf_delta': 1e-6, 'update_PC': 1}
NO_PERIODS = np.zeros(3)
DOMAINS = {'open': {'product': 'numba_no_wall', 'blobs': 'python_no_wall', 'domain': 'no_wall'},
           'wall': {'product': 'numba', 'blobs': 'python', 'domain': 'single_wall'}}


def load_peer(src):
    """The peer's modules, imported from its source folder with a scratch folder as the working
    directory (its force module reads user overrides from there: none, so its defaults hold)."""
    sys.path[:0] = [os.path.join(src, 'multi_bodies'), src]
    os.chdir(tempfile.mkdtemp(prefix='rmw-'))
    warnings.simplefilter('ignore', DeprecationWarning)
    import multi_bodies
    import multi_bodies_functions
    from body import body
    from mobility import mobility
    from quaternion_integrator.quaternion import Quaternion
    from quaternion_integrator.quaternion_integrator_multi_bodies import QuaternionIntegrator
    multi_bodies_functions.calc_blob_blob_forces = multi_bodies_functions.set_blob_blob_forces('numba')
    multi_bodies_functions.calc_body_body_forces_torques = multi_bodies_functions.set_body_body_forces_torques('None')
    return types.SimpleNamespace(mb=multi_bodies, functions=multi_bodies_functions, Body=body.Body,
                                 mobility=mobility, Quaternion=Quaternion, Integrator=QuaternionIntegrator)


def make_bodies(peer, scene, domain):
    """The peer's bodies of a scene; checks that they put their blobs where the scene has them."""
    reference = np.array(scene['body_frame_blobs_um'])
    a = scene['blob_radius_um']
    bodies = []
    for location, q in zip(scene['locations_um'], scene['quaternions']):
        b = peer.Body(np.array(location), peer.Quaternion(q), reference, a)
        b.mobility_blobs = peer.mb.set_mobility_blobs(DOMAINS[domain]['blobs'])
        b.ID = 'boomerang'
        bodies.append(b)
    bodies = np.array(bodies)
    r = peer.mb.get_blobs_r_vectors(bodies, len(scene['blob_positions_um']))
    gap = np.abs(r-np.array(scene['blob_positions_um'])).max()
    if gap > 1e-12:
        raise RuntimeError(f'the peer places the blobs {gap} um from the scene (quaternion convention?)')
    return bodies


def make_integrator(peer, bodies, domain, tolerance, scheme='deterministic_forward_euler'):
    """A QuaternionIntegrator wired as the peer's multi_bodies.py wires it for rigid bodies."""
    mb, num_blobs = peer.mb, sum(b.Nblobs for b in bodies)
    product = mb.set_mobility_vector_prod(DOMAINS[domain]['product'])
    mb.mobility_vector_prod = product  # its linear operator and preconditioners read this global
    wall = domain == 'wall'
    forces = dict(PHYSICS, repulsion_strength_wall=PHYSICS['repulsion_strength_wall'] if wall else 0.0)
    del forces['eta'], forces['kT']
    integrator = peer.Integrator(bodies, num_blobs, scheme, tolerance=tolerance, domain=DOMAINS[domain]['domain'])
    settings = {
        'first_guess': np.zeros(3*num_blobs+6*len(bodies)), 'n_save': 1, 'get_blobs_r_vectors': mb.get_blobs_r_vectors,
        'calc_slip': functools.partial(mb.calc_slip, implementation=DOMAINS[domain]['product'], blob_radius=bodies[0].blob_radius,
                                       eta=PHYSICS['eta'], g=PHYSICS['g'], Laplace_flag=None, domain=DOMAINS[domain]['domain']),
        'mobility_blobs': mb.set_mobility_blobs(DOMAINS[domain]['blobs']),
        'mobility_vector_prod': product, 'calc_K_matrix_bodies': mb.calc_K_matrix_bodies, 'calc_K_matrix': mb.calc_K_matrix,
        'force_torque_calculator': lambda bodies, r: peer.functions.force_torque_calculator_sort_by_bodies(
            bodies, r, periodic_length=NO_PERIODS, omega_one_roller=None, **forces),
        'linear_operator': mb.linear_operator_rigid, 'build_block_diagonal_preconditioner': mb.build_block_diagonal_preconditioner,
        'build_block_diagonal_preconditioners_det_stoch': mb.build_block_diagonal_preconditioners_det_stoch,
        'eta': PHYSICS['eta'], 'a': bodies[0].blob_radius, 'kT': PHYSICS['kT'],
        'K_matrix_T_vector_prod': mb.K_matrix_T_vector_prod, 'K_matrix_vector_prod': mb.K_matrix_vector_prod,
        'preprocess': peer.functions.preprocess, 'postprocess': peer.functions.postprocess, 'periodic_length': NO_PERIODS,
        'update_PC': STEP['update_PC'], 'print_residual': False, 'rf_delta': STEP['rf_delta'], 'constraints': [],
        'articulated': [], 'calc_C_matrix_constraints': mb.calc_C_matrix_constraints}
    for name, value in settings.items():
        setattr(integrator, name, value)
    return integrator


def clock():
    return time.perf_counter(), time.process_time()


def summary(wall, cpu, **extra):
    """Repeats of a time, with their mean and standard error (sample deviation / sqrt(n))."""
    def stats(values):
        values = np.asarray(values)
        error = values.std(ddof=1)/math.sqrt(len(values)) if len(values) > 1 else float('nan')
        return float(values.mean()), float(error)
    (mean, error), (cpu_mean, cpu_error) = stats(wall), stats(cpu)
    return dict({'seconds': [float(t) for t in wall], 'cpu_seconds': [float(t) for t in cpu], 'mean_s': mean,
                 'standard_error_s': error, 'min_s': float(min(wall)), 'cpu_mean_s': cpu_mean, 'cpu_standard_error_s': cpu_error}, **extra)


def time_product(peer, scene, domain, repeats, min_block_s=0.2):
    """One M f: blocks of products (grown until a block takes min_block_s), time per product."""
    function = peer.mb.set_mobility_vector_prod(DOMAINS[domain]['product'])
    r = np.array(scene['blob_positions_um'])
    f = np.random.default_rng(0).normal(size=r.size)
    product = lambda: function(r, f, PHYSICS['eta'], scene['blob_radius_um'], periodic_length=NO_PERIODS)  # noqa: E731
    product()  # compiles
    block = 1
    while True:
        start = clock()
        for _ in range(block):
            product()
        if time.perf_counter()-start[0] >= min_block_s or block >= 4096:
            break
        block *= 4
    wall, cpu = [], []
    for _ in range(repeats):
        start = clock()
        for _ in range(block):
            product()
        end = clock()
        wall.append((end[0]-start[0])/block)
        cpu.append((end[1]-start[1])/block)
    return summary(wall, cpu, products_per_block=block)


def force_torque_rhs(integrator, bodies, force_torque=None):
    """The mobility problem's right-hand side [slip = 0, -(forces, torques)]: the scene's own forces
    (gravity, the wall, blob-blob repulsion) unless force_torque (6 per body) is given."""
    num_blobs = integrator.Nblobs
    if force_torque is None:
        force_torque = integrator.force_torque_calculator(bodies, integrator.get_blobs_r_vectors(bodies, num_blobs))
    return np.concatenate([np.zeros(3*num_blobs), -np.ravel(force_torque)])


def solve(peer, integrator, bodies, rhs, preconditioner):
    """One solve of the peer's (solution, iterations, achieved relative residual); the residual
    takes one more application of its operator, outside any timing."""
    before = integrator.det_iterations_count
    solution = integrator.solve_mobility_problem(RHS=rhs.copy(), PC_partial=preconditioner)
    iterations = integrator.det_iterations_count-before
    r = integrator.get_blobs_r_vectors(bodies, integrator.Nblobs)
    applied = peer.mb.linear_operator_rigid(solution, bodies, [], r, integrator.eta, integrator.a,
                                            K_bodies=integrator.calc_K_matrix_bodies(bodies, integrator.Nblobs),
                                            periodic_length=NO_PERIODS)
    return solution, iterations, float(np.linalg.norm(applied-rhs)/np.linalg.norm(rhs))


def build_preconditioner(peer, integrator, bodies):
    r = integrator.get_blobs_r_vectors(bodies, integrator.Nblobs)
    return peer.mb.build_block_diagonal_preconditioner(bodies, [], r, integrator.Nblobs, integrator.eta, integrator.a,
                                                       periodic_length=NO_PERIODS, step=0, update_PC=1)


def time_solve(peer, scene, domain, repeats):
    """One mobility solve with the scene's forces to SOLVE_TOLERANCE, from a zero first guess, its
    block-diagonal preconditioner built beforehand (and timed on its own)."""
    bodies = make_bodies(peer, scene, domain)
    integrator = make_integrator(peer, bodies, domain, SOLVE_TOLERANCE)
    rhs = force_torque_rhs(integrator, bodies)
    solve(peer, integrator, bodies, rhs, build_preconditioner(peer, integrator, bodies))  # compiles
    build_wall, build_cpu, wall, cpu, iterations, residuals = [], [], [], [], [], []
    for _ in range(repeats):
        start = clock()
        preconditioner = build_preconditioner(peer, integrator, bodies)
        middle = clock()
        before = integrator.det_iterations_count
        integrator.solve_mobility_problem(RHS=rhs.copy(), PC_partial=preconditioner)
        end = clock()
        iterations.append(integrator.det_iterations_count-before)
        build_wall.append(middle[0]-start[0])
        build_cpu.append(middle[1]-start[1])
        wall.append(end[0]-middle[0])
        cpu.append(end[1]-middle[1])
    _, _, residual = solve(peer, integrator, bodies, rhs, preconditioner)
    return summary(wall, cpu, iterations=iterations, relative_residual=residual), summary(build_wall, build_cpu)


def time_steps(peer, scene, steps, seed=1):
    """Brownian steps of the recommended scheme above the wall (STEP), after one untimed step."""
    bodies = make_bodies(peer, scene, 'wall')
    integrator = make_integrator(peer, bodies, 'wall', STEP['tolerance'], STEP['scheme'])
    np.random.seed(seed)
    integrator.advance_time_step(STEP['dt'], step=0)
    wall, cpu, gmres, lanczos = [], [], [], []
    for step in range(1, steps+1):
        before = integrator.det_iterations_count, integrator.stoch_iterations_count
        start = clock()
        integrator.advance_time_step(STEP['dt'], step=step)
        end = clock()
        wall.append(end[0]-start[0])
        cpu.append(end[1]-start[1])
        gmres.append(integrator.det_iterations_count-before[0])
        lanczos.append(integrator.stoch_iterations_count-before[1])
    return summary(wall, cpu, gmres_iterations_per_step=gmres, lanczos_iterations_per_step=lanczos,
                   invalid_configurations=integrator.invalid_configuration_count)


def reference_values(peer, scene, seed=2026):
    """For the project's tests: M f (open and wall) for a fixed random f, and the bodies' velocities
    and angular velocities (open space) for fixed random forces and torques, solved to
    REFERENCE_SOLVE_TOLERANCE."""
    rng = np.random.default_rng(seed)
    r = np.array(scene['blob_positions_um'])
    a, eta = scene['blob_radius_um'], PHYSICS['eta']
    f = rng.normal(size=r.size)
    products = {d: peer.mb.set_mobility_vector_prod(DOMAINS[d]['product'])(r, f, eta, a, periodic_length=NO_PERIODS)
                for d in DOMAINS}
    force_torque = rng.normal(size=6*scene['num_bodies'])
    bodies = make_bodies(peer, scene, 'open')
    integrator = make_integrator(peer, bodies, 'open', REFERENCE_SOLVE_TOLERANCE)
    rhs = force_torque_rhs(integrator, bodies, force_torque)
    solution, iterations, residual = solve(peer, integrator, bodies, rhs, build_preconditioner(peer, integrator, bodies))
    return {'num_bodies': scene['num_bodies'], 'eta': eta, 'blob_radius_um': a, 'blob_positions_um': r.tolist(),
            'body_locations_um': scene['locations_um'], 'body_blob_offsets': scene['body_blob_offsets'],
            'blob_forces': f.tolist(), 'blob_velocities_open': products['open'].tolist(),
            'blob_velocities_wall': products['wall'].tolist(), 'body_forces_torques': force_torque.tolist(),
            'body_velocities_open': solution[r.size:].tolist(), 'solve_tolerance': REFERENCE_SOLVE_TOLERANCE,
            'solve_iterations': iterations, 'solve_relative_residual': residual}


def machine():
    """What the times were taken on: processor, cores, load averages (1, 5, 15 min), niceness, the
    thread and BLAS settings, Python and package versions."""
    import numba
    import scipy
    model = next((line.split(':', 1)[1].strip() for line in open('/proc/cpuinfo', encoding='utf-8') if line.startswith('model name')), platform.processor())
    environment = {k: v for k, v in os.environ.items() if k.startswith(('NUMBA_', 'OMP_', 'OPENBLAS_', 'MKL_'))}
    return {'processor': model, 'cores': os.cpu_count(), 'load_averages_before': list(os.getloadavg()), 'niceness': os.nice(0),
            'environment': environment, 'numba_threads': numba.config.NUMBA_NUM_THREADS, 'python': platform.python_version(),
            'numpy': np.__version__, 'scipy': scipy.__version__, 'numba': numba.__version__, 'platform': platform.platform()}


def settings():
    return {'physics_um_s_mg': PHYSICS, 'solve': {'tolerance': SOLVE_TOLERANCE, 'gmres_restart': 60, 'gmres_maxiter': 1000,
                                                  'first_guess': 'zero', 'preconditioner': 'multi_bodies.build_block_diagonal_preconditioner'},
            'brownian_step': dict(STEP, domain='single_wall', periodic_length=[0, 0, 0],
                                  preconditioner='multi_bodies.build_block_diagonal_preconditioners_det_stoch, rebuilt every step'),
            'blob_mobility_for_preconditioners': {d: DOMAINS[d]['blobs'] for d in DOMAINS},
            'products': {d: DOMAINS[d]['product'] for d in DOMAINS}, 'forces': 'multi_bodies_functions defaults, forces_numba blob-blob',
            'time': 'wall-clock (perf_counter) and process CPU time of all threads (process_time), per repeat'}


def measure_scene(peer, scene, args):
    """Every measurement of one number of bodies: {domain: {what: summary}}."""
    n = scene['num_bodies']
    result = {'num_bodies': n, 'num_blobs': len(scene['blob_positions_um']), 'box_side_um': scene['box_side_um']}
    for domain in DOMAINS:
        entry = {'product': time_product(peer, scene, domain, args.product_repeats)}
        if n <= args.solve_max_bodies:
            entry['solve'], entry['preconditioner'] = time_solve(peer, scene, domain, args.solve_repeats if n < 1024 else 3)
        if domain == 'wall' and n <= args.step_max_bodies:
            entry['brownian_step'] = time_steps(peer, scene, args.steps)
        result[domain] = entry
        print(f'{n} bodies, {domain}: ' + ', '.join(f"{k} {v['mean_s']:.4g} +- {v['standard_error_s']:.2g} s" for k, v in entry.items()),
              flush=True)
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--peer', default='build-peers/rigid-multiblobs-wall', help='the folder setup_rigid_multiblobs_wall.sh made')
    parser.add_argument('--scenes', default='build-peers/boomerang_suspension.json', help='boomerang_suspension.py\'s output')
    parser.add_argument('--out', required=True, help='the JSON file to write (rewritten after each size)')
    parser.add_argument('--sizes', type=int, nargs='+', help='numbers of bodies (default: every scene of the file)')
    parser.add_argument('--solve-max-bodies', type=int, default=1024)
    parser.add_argument('--step-max-bodies', type=int, default=256)
    parser.add_argument('--product-repeats', type=int, default=7)
    parser.add_argument('--solve-repeats', type=int, default=5)
    parser.add_argument('--steps', type=int, default=5, help='timed Brownian steps per size (after one untimed)')
    parser.add_argument('--reference-only', action='store_true', help='write the 16 bodies\' reference values only, no times')
    args = parser.parse_args()
    peer_folder, out = os.path.abspath(args.peer), os.path.abspath(args.out)
    with open(args.scenes, encoding='utf-8') as f:
        scenes = [s for s in json.load(f)['scenes'] if args.sizes is None or s['num_bodies'] in args.sizes]
    with open(os.path.join(peer_folder, 'SNAPSHOT'), encoding='utf-8') as f:
        commit = f.read().strip()
    peer = load_peer(os.path.join(peer_folder, 'src'))
    import numba
    report = {'peer': {'name': 'RigidMultiblobsWall', 'commit': commit}, 'machine': machine(), 'settings': settings(),
              'command': ' '.join(sys.argv), 'started': time.strftime('%Y-%m-%d %H:%M:%S %Z'), 'sizes': []}
    for scene in scenes:
        if scene['num_bodies'] == 16:
            report['reference_16_bodies'] = reference_values(peer, scene)
        if not args.reference_only:
            report['sizes'].append(measure_scene(peer, scene, args))
            report['machine']['numba_threading_layer'] = numba.threading_layer()  # known once a parallel function ran
            report['machine']['load_averages_after'] = list(os.getloadavg())
            report['machine']['uptime_after'] = subprocess.run(['uptime'], capture_output=True, encoding='utf-8').stdout.strip()
        with open(out, 'w', encoding='utf-8') as f:
            json.dump(report, f, indent=1)
    print(f'(written to {out})')


if __name__ == '__main__':
    main()
