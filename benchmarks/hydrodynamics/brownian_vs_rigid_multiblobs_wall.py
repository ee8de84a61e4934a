"""The Brownian step above a no-slip wall: RigidBrownianIntegrator against RigidMultiblobsWall's
recommended scheme, on the same boomerang suspensions, in alternating blocks (issue 61, item 5).

    bash benchmarks/peers/run_brownian_vs_rigid_multiblobs_wall.sh [--sizes 16 64 256] [--pairs 4]

The scenes are boomerang_suspension.py's (seed 1; 16, 64, 256 boomerangs of 15 blobs at 5% volume
fraction, every blob above the wall z = 0), with the peer's boomerang input files' forces on both
sides: gravity and the wall's repulsion per blob, and the blob-blob repulsion between bodies
(e exp(-(r - 2a)/b), linear below 2a), water at 8.9e-4 Pa s, 300 K, steps of 0.01 s. The peer sums
the repulsion over every pair; ours is a CustomNonbondedForce cut off at 2a + 20 b (3.9 um), where
the force has fallen to e^-20 = 2e-9 of its value at contact (7e-6 of a blob's weight), as an
OpenMM user would write it, and for comparison also summed over every pair at 1e-3.

- The peer: stochastic_Slip_Trapz (three mobility solves, one Lanczos, two more products a step) at
  its boomerang files' tolerance 1e-3 for GMRES and Lanczos, its numba products on 2 threads, the
  preconditioner rebuilt every step (rigid_multiblobs_wall_steps.py, in the peer's own Python, kept
  alive and asked for blocks of steps).
- Ours: RigidBrownianIntegrator with hydrodynamic interactions and the wall, each body its rigid
  multiblob tensor about its corner (so far from others it is exactly the peer's body), the Krylov
  path (Lanczos, GMRES on the saddle-point problem), CPU platform on 2 threads, at the Krylov
  tolerance 1e-3 (the peer's) and at the integrator's default (1e-4). Euler-Maruyama with the drift
  by random finite differences in the traction form: one Lanczos, two GMRES solves and two more
  products a step.

In each pair of blocks every contender runs a block of steps in turn (the order reversed every other
pair), so that all see the same machine load; the ratio of the peer's seconds per step to ours is
taken pair by pair and given as mean +- standard error over the pairs. Writes
results/brownian_vs_rigid_multiblobs_wall.{json,md,png}: seconds per step against the number of
bodies, the ratios, the iterations and the machine's load averages before and after.
"""
import argparse
import json
import math
import os
import pathlib
import platform as host
import subprocess
import sys
import tempfile
import time

import numpy as np
import openmm as mm

import rigidlangevin as rl

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path[:0] = [str(HERE), str(ROOT/'examples')]
import boomerang_suspension as scenes  # noqa: E402
import sedimented_boomerangs as boomerangs  # noqa: E402  (the forces, the body's tensor, units)

RESULTS = HERE/'results'
# Our contenders: label -> (Krylov tolerance or None for the default, the repulsion cut off).
CONTENDERS = {'1e-3': (1e-3, True), 'default': (None, True), '1e-3, all pairs': (1e-3, False)}
DEFAULT_TOLERANCE = f"{rl.RigidBrownianIntegrator(300, 1, 1).getHydrodynamicTolerance():g}"
PEER_STEPS = 2          # steps in each of the peer's blocks
MIN_BLOCK_S = 1.0       # our blocks: enough steps to take about this long


def blob_repulsion(num_bodies, cut_off):
    """The peer's blob-blob repulsion between blobs of different bodies (kJ/mol, nm), cut off at
    2a + 20 b or summed over every pair."""
    forces = boomerangs.Forces()
    kt, nm = boomerangs.KT, boomerangs.NM_PER_UM
    force = mm.CustomNonbondedForce('select(step(r-2*radius), repulsion*exp(-(r-2*radius)/decay), repulsion*(1+(2*radius-r)/decay))')
    for name, value in [('repulsion', forces.repulsion*kt), ('radius', forces.radius*nm), ('decay', forces.decay*nm)]:
        force.addGlobalParameter(name, value)
    force.setNonbondedMethod(mm.CustomNonbondedForce.CutoffNonPeriodic if cut_off else mm.CustomNonbondedForce.NoCutoff)
    force.setCutoffDistance((2*forces.radius+20*forces.decay)*nm)
    blobs = len(boomerangs.BLOBS_UM)
    for _ in range(num_bodies*blobs):
        force.addParticle([])
    for b in range(num_bodies):
        for i in range(b*blobs, (b+1)*blobs):
            for j in range(i+1, (b+1)*blobs):
                force.addExclusion(i, j)
    return force


def our_context(scene, tolerance, threads, cut_off=True):
    """RigidBrownianIntegrator on a scene above the wall z = 0: (integrator, context)."""
    nm = boomerangs.NM_PER_UM
    blobs_nm, tensor = boomerangs.BLOBS_UM*nm, boomerangs.body_tensor()
    radius = scene['blob_radius_um']*nm
    system = mm.System()
    integrator = rl.RigidBrownianIntegrator(boomerangs.TEMPERATURE, boomerangs.VISCOSITY, boomerangs.STEP_PS[True])
    integrator.setRandomNumberSeed(1)
    external = boomerangs.Forces().openmm_force()
    offsets = scene['body_blob_offsets']
    for b in range(scene['num_bodies']):
        particles = list(range(offsets[b], offsets[b+1]))
        for p in particles:
            system.addParticle(1.0)
            external.addParticle(p)
            integrator.setParticleRadius(p, radius)
        integrator.addRigidBody(particles)
        integrator.setBodyResistance(b, list(tensor.flat), mm.Vec3(*blobs_nm[boomerangs.CROSS_POINT]), [mm.Vec3(*p) for p in blobs_nm])
    system.addForce(external)
    system.addForce(blob_repulsion(scene['num_bodies'], cut_off))
    integrator.setHydrodynamicInteractions(True)
    integrator.setWall(0.0)
    integrator.setHydrodynamicSolver(rl.RigidBrownianIntegrator.KrylovSolver)
    if tolerance is not None:
        integrator.setHydrodynamicTolerance(tolerance)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'), {'Threads': str(threads)})
    context.setPositions([mm.Vec3(*p) for p in nm*np.array(scene['blob_positions_um'])])
    return integrator, context


class Peer:
    """RigidMultiblobsWall's step server (rigid_multiblobs_wall_steps.py) in the peer's Python."""

    def __init__(self, folder, scenes_file, threads):
        env = dict(os.environ, NUMBA_NUM_THREADS=str(threads))
        self.process = subprocess.Popen([os.path.join(folder, 'venv', 'bin', 'python'), str(ROOT/'benchmarks'/'peers'/'rigid_multiblobs_wall_steps.py'),
                                         '--peer', folder, '--scenes', scenes_file], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                        encoding='utf-8', env=env)

    def steps(self, num_bodies, steps):
        self.process.stdin.write(json.dumps({'num_bodies': num_bodies, 'steps': steps})+'\n')
        self.process.stdin.flush()
        while True:
            line = self.process.stdout.readline()
            if not line:
                raise RuntimeError('the peer stopped: see its error output above')
            if line.startswith('{'):  # its imports may print warnings on stdout
                return json.loads(line)

    def close(self):
        self.process.stdin.close()
        self.process.wait(timeout=60)


def timed_block(integrator, context, steps):
    """Wall-clock and process CPU seconds per step over a block (closed by a State)."""
    start, cpu = time.perf_counter(), time.process_time()
    integrator.step(steps)
    context.getState(getPositions=True)
    return (time.perf_counter()-start)/steps, (time.process_time()-cpu)/steps


def mean_and_error(values):
    values = np.asarray(values, dtype=float)
    return float(values.mean()), float(values.std(ddof=1)/math.sqrt(len(values))) if len(values) > 1 else float('nan')


def measure_size(scene, peer, pairs, threads):
    """Alternating blocks of the peer's steps and ours (each tolerance) for one scene."""
    n = scene['num_bodies']
    ours = {label: our_context(scene, tolerance, threads, cut_off) for label, (tolerance, cut_off) in CONTENDERS.items()}
    block = {}
    for label, (integrator, context) in ours.items():
        start = time.perf_counter()
        integrator.step(1)  # untimed: builds what the first step builds
        block[label] = max(1, int(round(MIN_BLOCK_S/(time.perf_counter()-start))))
    peer.steps(n, 0)  # builds the peer's bodies and takes its untimed step
    result = {'num_bodies': n, 'num_blobs': len(scene['blob_positions_um']), 'ours': {k: {'seconds': [], 'cpu_seconds': []} for k in ours},
              'peer': {'seconds': [], 'cpu_seconds': [], 'gmres': [], 'lanczos': []}, 'our_block_steps': block, 'peer_block_steps': PEER_STEPS}
    contenders = ['peer', *ours]
    for pair in range(pairs):
        for who in (contenders if pair % 2 == 0 else contenders[::-1]):
            if who == 'peer':
                answer = peer.steps(n, PEER_STEPS)
                for key in ('gmres', 'lanczos'):
                    result['peer'][key] += answer[key]
                result['peer']['seconds'].append(float(np.mean(answer['seconds'])))
                result['peer']['cpu_seconds'].append(float(np.mean(answer['cpu_seconds'])))
            else:
                wall, cpu = timed_block(*ours[who], block[who])
                result['ours'][who]['seconds'].append(wall)
                result['ours'][who]['cpu_seconds'].append(cpu)
    for label, (integrator, _) in ours.items():
        entry = result['ours'][label]
        entry['krylov_iterations_last_step'] = list(integrator.getKrylovIterations())
        entry['mean_s'], entry['standard_error_s'] = mean_and_error(entry['seconds'])
        ratios = np.array(result['peer']['seconds'])/np.array(entry['seconds'])
        entry['peer_over_ours'], entry['peer_over_ours_error'] = mean_and_error(ratios)
    result['peer']['mean_s'], result['peer']['standard_error_s'] = mean_and_error(result['peer']['seconds'])
    print(f"{n} bodies: peer {result['peer']['mean_s']:.3g} s, " + ', '.join(
        f"ours ({k}) {v['mean_s']:.3g} s, peer/ours {v['peer_over_ours']:.3g} +- {v['peer_over_ours_error']:.2g}" for k, v in result['ours'].items()), flush=True)
    return result


def machine(threads):
    model = next((line.split(':', 1)[1].strip() for line in open('/proc/cpuinfo', encoding='utf-8') if line.startswith('model name')), host.processor())
    return {'processor': model, 'cores': os.cpu_count(), 'threads_each': threads, 'niceness': os.nice(0), 'load_averages_before': list(os.getloadavg()),
            'openmm': mm.__version__, 'python': host.python_version()}


def markdown(report):
    lines = ['# The Brownian step above a wall: RigidBrownianIntegrator against RigidMultiblobsWall', '',
             'Written by benchmarks/hydrodynamics/brownian_vs_rigid_multiblobs_wall.py. Seconds per step (wall clock), mean over the '
             'pairs of alternating blocks ± standard error; the ratio (the peer\'s time over ours) taken pair by pair. Ours: the '
             'blob-blob repulsion cut off at 2a + 20 b unless "all pairs".', '',
             '| bodies (blobs) | RigidMultiblobsWall, Slip_Trapz 1e-3 (s) | ' + ' | '.join(f'ours, {contender_name(k)} (s) | peer / ours' for k in CONTENDERS) +
             ' | peer iterations a step | ours a step (Lanczos, GMRES drift, GMRES step) ' + '; '.join(contender_name(k) for k in CONTENDERS) + ' |',
             '|---|---|' + '---|---|'*len(CONTENDERS) + '---|---|']
    for r in report['sizes']:
        p = r['peer']
        cells = [f"{r['num_bodies']} ({r['num_blobs']})", f"{p['mean_s']:.3g} ± {p['standard_error_s']:.1g}"]
        for k in CONTENDERS:
            o = r['ours'][k]
            cells += [f"{o['mean_s']:.3g} ± {o['standard_error_s']:.1g}", f"{o['peer_over_ours']:.3g} ± {o['peer_over_ours_error']:.2g}"]
        cells.append(f"GMRES {min(p['gmres'])}–{max(p['gmres'])}, Lanczos {min(p['lanczos'])}–{max(p['lanczos'])}")
        cells.append('; '.join(str(tuple(r['ours'][k]['krylov_iterations_last_step'])) for k in CONTENDERS))
        lines.append('| ' + ' | '.join(cells) + ' |')
    m = report['machine']
    pairs = ', '.join(f"{len(r['peer']['seconds'])} at {r['num_bodies']} bodies" for r in report['sizes'])
    lines += ['', f"Machine: {m['processor']}, {m['cores']} cores, {m['threads_each']} threads each, niceness {m['niceness']}; load averages (1, 5, 15 min) "
                  f"{', '.join(f'{x:.2f}' for x in m['load_averages_before'])} before and {', '.join(f'{x:.2f}' for x in m['load_averages_after'])} after; "
                  f"{report['started']}. Pairs of blocks: {pairs}."]
    return '\n'.join(lines)+'\n'


def contender_name(label):
    tolerance, cut_off = CONTENDERS[label]
    return ('Krylov 1e-3' if tolerance else f'Krylov {DEFAULT_TOLERANCE} (default)') + ('' if cut_off else ', repulsion over all pairs')


def plot(report, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    n = [r['num_bodies'] for r in report['sizes']]
    curves = [('RigidMultiblobsWall, Slip_Trapz 1e-3', lambda r: r['peer'], 'k-o')]
    curves += [(f'ours, {contender_name(k)}', lambda r, k=k: r['ours'][k], style) for k, style in zip(CONTENDERS, ('C0-s', 'C1-^', 'C2--v'))]
    for label, pick, style in curves:
        ax.errorbar(n, [pick(r)['mean_s'] for r in report['sizes']], [pick(r)['standard_error_s'] for r in report['sizes']], fmt=style, label=label, capsize=3)
    ax.set_xscale('log')
    ax.set_yscale('log')
    ax.set_xticks(n, [str(k) for k in n])
    ax.minorticks_off()
    ax.set_xlabel('boomerangs (15 blobs each) above the wall')
    ax.set_ylabel('seconds per Brownian step (2 threads)')
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--sizes', type=int, nargs='+', default=[16, 64, 256])
    parser.add_argument('--pairs', type=int, default=4)
    parser.add_argument('--large-pairs', type=int, default=2, help='pairs from 256 bodies, where a pair of blocks takes about a minute')
    parser.add_argument('--threads', type=int, default=2)
    parser.add_argument('--peer', default=str(ROOT/'build-peers'/'rigid-multiblobs-wall'))
    parser.add_argument('--name', default='brownian_vs_rigid_multiblobs_wall', help='results/<name>.{json,md,png}')
    args = parser.parse_args()
    if not os.path.exists(os.path.join(args.peer, 'venv', 'bin', 'python')):
        sys.exit(f'no peer in {args.peer}: run scripts/peers/setup_rigid_multiblobs_wall.sh first')
    the_scenes = [scenes.scene(n) for n in args.sizes]
    scenes_file = os.path.join(tempfile.mkdtemp(prefix='boomerangs-'), 'scenes.json')
    with open(scenes_file, 'w', encoding='utf-8') as f:
        json.dump({'scenes': the_scenes}, f)
    report = {'machine': machine(args.threads), 'started': time.strftime('%Y-%m-%d %H:%M %Z'), 'command': ' '.join(sys.argv), 'sizes': []}
    peer = Peer(args.peer, scenes_file, args.threads)
    try:
        for scene in the_scenes:
            pairs = args.pairs if scene['num_bodies'] < 256 else args.large_pairs
            report['sizes'].append(measure_size(scene, peer, pairs, args.threads))
    finally:
        peer.close()
    report['machine']['load_averages_after'] = list(os.getloadavg())
    RESULTS.mkdir(exist_ok=True)
    with open(RESULTS/f'{args.name}.json', 'w', encoding='utf-8') as f:
        json.dump(report, f, indent=1)
    text = markdown(report)
    (RESULTS/f'{args.name}.md').write_text(text, encoding='utf-8')
    plot(report, RESULTS/f'{args.name}.png')
    print(text)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its table carries ±
    main()
