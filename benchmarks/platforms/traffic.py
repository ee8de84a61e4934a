"""Memory traffic of one RigidLangevinIntegrator step, per body: the minimum a step must move against
what each kernel moves today, for the common (OpenCL/CUDA) kernels and the CPU kernel, bodies of
1, 3 and 10 particles, single, mixed and double precision, with the measured bytes and times
beside them where there are measurements.

The counts are a model of the kernels as written (rigidBodyStep.cc, rigidBodyAtoms.cc,
HostRigidLangevinStepKernel.h): every per-body or per-particle array element a kernel touches
counts once per kernel per step, whole (a mixed4 counts 4 values even where w is unused); per-type
data (coefficients, body-frame coordinates shared by a type) stay in cache and count nothing. On
the CPU an ordinary store to a line not in cache reads it first (write-allocate), so particle
positions and velocities counted twice there until the kernel wrote them with streaming stores
(which it does where a System's arrays exceed the last-level cache; one that fits moves them to
memory not at all). The minimum keeps only what a step cannot avoid: the body state in
and out (position, velocity, and for bodies that rotate the angular momentum and the orientation as
a quaternion), the particles' forces in (OpenMM's 64-bit fixed-point buffer on GPUs), each
particle's slot in OpenMM's reordered arrays, and its position out (posq, and posqCorrection in
mixed precision); random numbers generated where they are used; particle velocities (needed only
when a State asks for them) are listed apart.

Measured: per-kernel DRAM bytes on an H100 and an H200 (Nsight Compute, 1e6 water-shaped bodies;
PROFILES below: on the H100 before the kernels were rewritten, after each step of the rewrite and
those of 2715354, on the H200 the kernels of b9f060f, 07d6a90 and 84c33cd, the last in double precision
too) and the time per body-step of
integrator_cost.py (results/integrator_cost.csv, results/*/integrator_cost*.csv) divided into
the modelled bytes: the bandwidth a kernel achieves.

    python benchmarks/platforms/traffic.py       # writes results/traffic.md and results/traffic.csv

It also measures this machine's memory bandwidth (a numpy copy of 400 MB, one thread, bytes read and
written), as the CPU kernels' peak; run it on a quiet machine, or pass --host-bandwidth GB/s.
"""
import sys
import argparse
import csv
import math
import os

from benchmark_utils import RESULTS

PRECISIONS = {'single': (4, 4), 'mixed': (8, 4), 'double': (8, 8)}  # bytes of (mixed, real)
PARTICLES = [1, 3, 10]
FORCE = 24      # three 64-bit fixed-point components (OpenMM's long force buffer)
INT, INT4 = 4, 16


def rotations(n):
    """Rotating axes of an n-particle body of the benchmarks (1: a point; 3 and 10: not collinear)."""
    return 0 if n == 1 else 3


def random_float4(n):
    """float4s of normal random numbers per body and ExactFlow step (randomFloat4PerBody): two per
    coordinate, for each half of the flow of a body that rotates."""
    return math.ceil((2 if rotations(n) == 0 else 4)*(3+rotations(n))/4)


def _particle_placement(n, precision, reads_velm, reads_cell_offsets):
    """Per particle, what placing it moves beyond what the force gather reads: its periodic cell
    offset (the kernels up to those profiled on the H200 read it in any box; later ones only in a
    periodic box), posq in (for its charge) and out, posqCorrection out in mixed precision, velm out,
    and velm in where the kernel reads the inverse mass back from it (the kernels up to the profiled
    fused ones; today's take it from the type's coordinates)."""
    m, r = PRECISIONS[precision]
    return n*((INT4 if reads_cell_offsets else 0)+2*4*r+(4*r if precision == 'mixed' else 0)+(2 if reads_velm else 1)*4*m)


def _body_state(n, precision, points_move_angular_momentum, rotation_mixed4):
    """Position, velocity, angular momentum (mixed4 each) and the rotation (rotation_mixed4 mixed4:
    3 for the matrix's rows, 1 where two rows are packed into it and the other vectors' w), in and
    out; a body that does not rotate has no rotation, and no angular momentum where the kernel skips it."""
    m, r = PRECISIONS[precision]
    vectors = 3 if rotations(n) > 0 or points_move_angular_momentum else 2
    return 2*vectors*4*m+(2*rotation_mixed4*4*m if rotations(n) > 0 else 0)


def common_current(n, precision, periodic=False):
    """Bytes per body-step of the common step kernel as written (ExactFlow): one pass per body that
    steps it and places its particles, making its random numbers itself (rigidBodyRandom.cc).
    Body-frame coordinates, with the inverse masses written to velm.w, are read per type (from
    cache); the body's periodic image and its particles' cell offsets only in a periodic box
    (integrator_cost.py's bodies are not in one); a body that does not rotate neither reads nor
    writes an angular momentum; the rotation's first two rows fill one mixed4 and the w of velocity
    and angular momentum."""
    m, r = PRECISIONS[precision]
    step = (INT+INT+(INT4 if periodic else 0)         # bodyType, bodyAtomStart, bodyImage
            + _body_state(n, precision, points_move_angular_momentum=False, rotation_mixed4=1)
            + n*(INT+FORCE)                           # atomSlot, force
            + _particle_placement(n, precision, reads_velm=False, reads_cell_offsets=periodic))
    return {'step': step}


def common_h200(n, precision):
    """The kernels as profiled on the H200 (commit b9f060f): the cell offsets read in any box."""
    return {'step': common_current(n, precision)['step']+n*INT4}


def common_fused(n, precision):
    """The kernels as profiled on the H100 after the step and the placement were fused (commit
    3ed7dd0): body-frame coordinates read per particle, the image read in any box, velm read back for
    the inverse masses, every body's angular momentum moved, and the random numbers OpenMM's
    generateRandomNumbers kernel wrote read back."""
    m, r = PRECISIONS[precision]
    random = 16*random_float4(n)
    step = (INT+INT+INT4+_body_state(n, precision, points_move_angular_momentum=True, rotation_mixed4=3)
            + n*(INT+FORCE+4*m)                       # atomSlot, force, atomCoords
            + _particle_placement(n, precision, reads_velm=True, reads_cell_offsets=True)+random)
    return {'generateRandomNumbers': random, 'step': step}


def common_before(n, precision):
    """The same before the step and the placement were fused (commit 61978fa): a step kernel, then a
    placement kernel with one work item per particle that read the body state and the entries again."""
    m, r = PRECISIONS[precision]
    rotating = rotations(n) > 0
    random = 16*random_float4(n)
    step = INT+INT+_body_state(n, precision, points_move_angular_momentum=True, rotation_mixed4=3)+n*(INT+4*m+FORCE)+random
    place = (INT+12*m+4*m+4*m+(4*m if rotating else 0)+INT4  # per body: type, rotation, position, velocity, angular momentum, image
             + n*(INT+INT+4*m)                        # per particle: atomBody, atomSlot, atomCoords
             + _particle_placement(n, precision, reads_velm=True, reads_cell_offsets=True))
    return {'generateRandomNumbers': random, 'step': step, 'placeBodyAtoms': place}


def common_minimum(n, precision):
    """Bytes per body-step a step cannot avoid on the common platforms; and particle velocities apart."""
    m, r = PRECISIONS[precision]
    state = 2*(4*m+4*m+(4*m+4*m if rotations(n) else 0))  # position, velocity (+ angular momentum, quaternion) in and out
    particles = n*(INT+FORCE+4*r+(4*r if precision == 'mixed' else 0))
    return state+particles, n*4*m


def common_layout_minimum(n, precision, periodic=False):
    """The minimum within OpenMM's arrays: particle velocities written (a State reads velm, and OpenMM
    gives an integrator no hook to make them on demand); posq read, since its w holds the charge,
    which other forces own and may change (NonbondedForce's parameter offsets do every step; writing
    x, y and z alone would leave a partial sector, which memory with ECC reads to update its check
    bits); and in a periodic box each particle's cell offset, which OpenMM sets per molecule (atoms
    linked by bonds, constraints or virtual sites), not per body."""
    m, r = PRECISIONS[precision]
    minimum, velocities = common_minimum(n, precision)
    return minimum+velocities+n*4*r+(n*INT4 if periodic else 0)


def cpu_current(n):
    """Bytes per body-step of the CPU (and Reference) kernel as written, for a System whose arrays
    exceed the last-level cache (RigidBodyModel::chooseParticleStores; 1e6 three-particle bodies on
    this machine): one pass per body in double; a body that does not rotate moves only its position
    and velocity (HostBodyStates::loadPoint); every body's particle indices in one array
    (BodyParticleLists); particle positions and velocities written with streaming stores, which do
    not read the lines they fill."""
    d = 8
    state = 2*(3*d+3*d+(3*d+9*d if rotations(n) else 0))   # position, velocity (+ angular momentum, rotation matrix) in and out
    return (state
            + INT+INT+n*INT                           # body type, start of its particle list, particle indices
            + n*3*d                                   # forces
            + 2*n*3*d)                                # positions and velocities out, written once


def cpu_84c33cd(n):
    """The CPU kernel from aef7a69 to 84c33cd: a vector of
    particle indices per body (its header and indices read) and ordinary stores, which read each
    line of particle positions and velocities before writing it (write-allocate)."""
    return cpu_before(n)-(2*(3*8+9*8) if rotations(n) == 0 else 0)


def cpu_before(n):
    """The CPU kernel until aef7a69: every body's whole state in and out."""
    d = 8
    return (2*(3*d+3*d+3*d+9*d)                       # position, velocity, angular momentum, rotation matrix in and out
            + INT+24+n*INT                            # body type, the body's particle list (vector header and indices)
            + n*3*d                                   # forces
            + 2*n*3*d+2*n*3*d)                        # positions and velocities out, each read first (write-allocate)


def cpu_minimum(n):
    d = 8
    state = 2*(3*d+3*d+(3*d+4*d if rotations(n) else 0))
    return state+n*(INT+3*d+3*d), n*3*d   # positions written once (streaming stores), velocities likewise, apart


def read_csv(name):
    path = os.path.join(RESULTS, name)
    if not os.path.exists(path):
        return []
    with open(path, encoding='utf-8') as f:
        return list(csv.DictReader(f))


def measured_time(path, platform, precision, bodies=1000000):
    """us per body-step of the integrator alone at 1e6 water-shaped bodies, from a table of
    integrator_cost.py (results/path), and its standard error where the table has one (tables
    written before integrator_cost.py timed pairs of blocks hold one block each): (us, error or None)."""
    for row in read_csv(path):
        if row['platform'] == platform and row['precision'] == precision and row['bodies'] == str(bodies):
            return float(row['us_per_body_step']), float(row['us_per_body_step_se']) if row.get('us_per_body_step_se') else None
    return None, None


def host_bandwidth(megabytes=400, repeats=5):
    """GB/s of a one-thread copy of a large array, counting the bytes read and written."""
    import time
    import numpy as np
    a = np.ones(megabytes*2**20//8)
    b = np.empty_like(a)
    best = float('inf')
    for _ in range(repeats):
        start = time.perf_counter()
        np.copyto(b, a)
        best = min(best, time.perf_counter()-start)
    return 2*a.nbytes/best*1e-9


def profile_rows(path):
    """Per-kernel DRAM bytes per body-step of a GPU profile (gpu_bandwidth.py), by kernel name."""
    return {row['kernel']: row for row in read_csv(path)}


# The GPU profiles (CUDA, 1e6 three-particle bodies), each with the model of the kernels profiled: on
# the H100 before any change, after the step kernels kept their arrays in registers (97e1b74), with
# the step and the placement fused into one pass (3ed7dd0), and those of 2715354; on the H200 those of
# b9f060f (cell offsets read in any box), of 07d6a90 and of 84c33cd (today's: mixed and double), which
# the model of today's kernels describes (the step's bytes did not change after 07d6a90).
PROFILES = [('H100, before (61978fa)', 'gpu_h100/gpu_bandwidth_before.csv', 'mixed', common_before),
            ('H100, registers (97e1b74)', 'gpu_h100/gpu_bandwidth_registers.csv', 'mixed', common_before),
            ('H100, fused (3ed7dd0), mixed', 'gpu_h100/gpu_bandwidth_3ed7dd0.csv', 'mixed', common_fused),
            ('H100, fused (3ed7dd0), single', 'gpu_h100/gpu_bandwidth_single_3ed7dd0.csv', 'single', common_fused),
            ('H100, 2715354, mixed', 'gpu_h100/gpu_bandwidth.csv', 'mixed', common_current),
            ('H100, 2715354, single', 'gpu_h100/gpu_bandwidth_single.csv', 'single', common_current),
            ('H200, b9f060f, mixed', 'gpu_h200/gpu_bandwidth_b9f060f.csv', 'mixed', common_h200),
            ('H200, b9f060f, single', 'gpu_h200/gpu_bandwidth_single_b9f060f.csv', 'single', common_h200),
            ('H200, 07d6a90, mixed', 'gpu_h200/gpu_bandwidth_07d6a90.csv', 'mixed', common_current),
            ('H200, 07d6a90, single', 'gpu_h200/gpu_bandwidth_single_07d6a90.csv', 'single', common_current),
            ('H200, 84c33cd (today), mixed', 'gpu_h200/gpu_bandwidth.csv', 'mixed', common_current),
            ('H200, 84c33cd (today), double', 'gpu_h200/gpu_bandwidth_double.csv', 'double', common_current)]

# Where each machine's integrator_cost.py times are, and the model of the kernels they timed.
# (machine, table, (platform, precision) runs, model of the common kernels, model of the CPU kernel)
TIMED = [('this machine (CPU and PoCL; kernels of 6d356da)', 'integrator_cost.csv',
          [('CPU', 'double'), ('OpenCL', 'single'), ('OpenCL', 'double')], common_current, cpu_current),
         ('H100 (kernels of 3ed7dd0)', 'gpu_h100/integrator_cost_3ed7dd0.csv', [('CUDA', 'single'), ('CUDA', 'mixed')], common_fused, None),
         ('H100 (kernels of 2715354)', 'gpu_h100/integrator_cost.csv', [('CUDA', 'single'), ('CUDA', 'mixed')], common_current, None),
         ('H200 (kernels of b9f060f)', 'gpu_h200/integrator_cost_b9f060f.csv', [('CUDA', 'single'), ('CUDA', 'mixed')], common_h200, None),
         ('H200 (kernels of 84c33cd, today; OpenCL is NVIDIA\'s)', 'gpu_h200/integrator_cost.csv',
          [('CUDA', 'single'), ('CUDA', 'mixed'), ('CUDA', 'double'), ('OpenCL', 'single'), ('OpenCL', 'double')], common_current, None)]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('--host-bandwidth', type=float, help='GB/s measured earlier on a quiet machine, for when this one is busy')
    args = parser.parse_args(argv)
    rows = []
    for precision in PRECISIONS:
        for n in PARTICLES:
            minimum, velocities = common_minimum(n, precision)
            rows.append({'platform': 'OpenCL/CUDA', 'precision': precision, 'particles': n, 'minimum': minimum,
                         'particle velocities': velocities, 'layout minimum': common_layout_minimum(n, precision),
                         'before': sum(common_before(n, precision).values()), 'current': sum(common_current(n, precision).values()),
                         'current, periodic': sum(common_current(n, precision, periodic=True).values()),
                         'layout minimum, periodic': common_layout_minimum(n, precision, periodic=True)})
    for n in PARTICLES:
        minimum, velocities = cpu_minimum(n)
        layout = minimum+velocities  # on the CPU a periodic box changes neither (the kernel reads no cell offsets)
        rows.append({'platform': 'CPU', 'precision': 'double', 'particles': n, 'minimum': minimum, 'particle velocities': velocities,
                     'layout minimum': layout, 'before': cpu_before(n), 'current': cpu_current(n),
                     'current, periodic': cpu_current(n), 'layout minimum, periodic': layout})
    for r in rows:
        r['current/minimum'] = r['current']/r['minimum']
        r['current/layout minimum'] = r['current']/r['layout minimum']
        r['current, periodic/minimum'] = r['current, periodic']/r['minimum']
        r['current, periodic/layout minimum'] = r['current, periodic']/r['layout minimum, periodic']
    fields = ['platform', 'precision', 'particles', 'minimum', 'particle velocities', 'layout minimum', 'before', 'current',
              'current/minimum', 'current/layout minimum', 'current, periodic', 'layout minimum, periodic', 'current, periodic/minimum',
              'current, periodic/layout minimum']
    with open(os.path.join(RESULTS, 'traffic.csv'), 'w', newline='', encoding='utf-8') as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)

    lines = ['# Bytes per body-step: minimum against today (model)', '',
             'ExactFlow; 1-particle bodies are points (no rotation), 3 and 10 particles rotate about three axes. '
             '"minimum": body state in and out, forces, slots and positions of the particles; "particle velocities": '
             'what writing them every step adds; "OpenMM\'s layout": the minimum with particle velocities written (a State '
             'reads them from OpenMM\'s array, and OpenMM gives an integrator no hook to make them on demand) and, on the '
             'common platforms, posq read as well as written (its w is the charge, which other forces own and may change '
             'at any step) and, in a periodic box, each particle\'s cell offset (OpenMM wraps molecules, not bodies). '
             '"before": the kernels of commit 61978fa on the common platforms (a step kernel, then a particle '
             'placement kernel) and of aef7a69 on the CPU; "today": what the step kernel moves as written now (common: one '
             'pass per body that steps it, places its particles and makes its random numbers; body-frame coordinates per '
             'type, with the inverse masses it writes to velm.w; the rotation\'s first two rows in one mixed4 and the w of '
             'velocity and angular momentum; no angular momentum for a body that does not rotate; no periodic box, as in '
             'integrator_cost.py; CPU: no rotation or angular momentum for a body that does not rotate, every body\'s particle '
             'indices in one array, particle positions and velocities written with streaming stores, as for arrays larger '
             'than the last-level cache). "periodic box": '
             'the same in a periodic box, where a step also reads the body\'s image and each particle\'s cell offset '
             '(16 bytes each).', '',
             '| platform | precision | particles | minimum | + particle velocities | OpenMM\'s layout | before | today | '
             'today / minimum | today / layout | periodic box | periodic / minimum | periodic / layout |',
             '|---|---|---|---|---|---|---|---|---|---|---|---|---|']
    for r in rows:
        lines.append(f"| {r['platform']} | {r['precision']} | {r['particles']} | {r['minimum']} | {r['particle velocities']} | "
                     f"{r['layout minimum']} | {r['before']} | {r['current']} | {r['current/minimum']:.2f} | "
                     f"{r['current/layout minimum']:.2f} | {r['current, periodic']} | "
                     f"{r['current, periodic/minimum']:.2f} | {r['current, periodic/layout minimum']:.2f} |")

    measured = [(label, profile_rows(path), precision, kernels) for label, path, precision, kernels in PROFILES]
    measured = [m for m in measured if m[1]]
    if measured:
        lines += ['', '## Measured on GPUs (CUDA, 1e6 three-particle bodies, Nsight Compute DRAM bytes per body-step)', '',
                  'clearTwoBuffers is OpenMM\'s clearing of the force buffers, which every integrator\'s step has; it is not modelled.', '',
                  '| kernels | kernel | model | measured | measured / model | DRAM % of peak | us per step |', '|---|---|---|---|---|---|---|']
        for label, profile, precision, kernels in measured:
            model = kernels(3, precision)
            for kernel, row in profile.items():
                key = 'step' if kernel.startswith('step') else kernel
                bytes_ = float(row['bytes_per_body_step'])
                ratio = f'{bytes_/model[key]:.2f}' if key in model else ''
                lines.append(f"| {label} | {kernel} | {model.get(key, '')} | {bytes_:.0f} | {ratio} | {row['dram_pct_of_peak']} | {row['us_per_step']} |")
        lines.append('')
        for label, profile, precision, kernels in measured:
            minimum, velocities = common_minimum(3, precision)
            whole = float(profile['all kernels of a step (profiled)']['bytes_per_body_step'])
            step = sum(float(row['bytes_per_body_step']) for kernel, row in profile.items() if kernel.startswith('step'))
            wall = profile['whole step, unprofiled wall time']
            lines.append(f'- {label}: the step kernel moves {step:.0f} bytes per body-step, {step/minimum:.2f} times the minimum; '
                         f'the whole step {whole:.0f}, {whole/minimum:.2f} times the minimum '
                         f'({minimum}), {whole/(minimum+velocities):.2f} times with particle velocities ({minimum+velocities}); '
                         f'{wall["us_per_step"]} us per step, {wall["dram_pct_of_peak"]}% of peak DRAM bandwidth.')
    peak = args.host_bandwidth or host_bandwidth()
    lines += ['', '## Achieved bandwidth (model bytes / measured time per body-step, 1e6 bodies, integrator_cost.py)', '',
              f'This machine copies memory at {peak:.1f} GB/s (one thread, read and write counted): the CPU and PoCL rows '
              'are far below it, so there the step is bound by arithmetic, not by memory. This machine\'s times are the mean of '
              'five alternating pairs of blocks, +- its standard error (GB/s +- the same relative error); the GPU machines\' '
              'are one timed block each (on the H200, four repeats of the 1e6 rows scattered by 1-3%: '
              'gpu_h200/integrator_cost_1e6_repeats.csv).', '',
              '| machine | platform | precision | us per body-step | model bytes | GB/s |', '|---|---|---|---|---|---|']
    for machine, path, runs, kernels, cpu_kernel in TIMED:
        for platform, precision in runs:
            t, error = measured_time(path, platform, precision)
            model = cpu_kernel(3) if platform == 'CPU' else sum(kernels(3, precision).values())
            if t is not None:
                time_text, bandwidth_text = f'{t:.4g}', f'{model/t*1e-3:.3g}'
                if error is not None:
                    time_text += f' +- {error:.2g}'
                    bandwidth_text += f' +- {model/t*1e-3*error/t:.2g}'
                lines.append(f'| {machine} | {platform} | {precision} | {time_text} | {model} | {bandwidth_text} |')
    text = '\n'.join(lines)+'\n'
    with open(os.path.join(RESULTS, 'traffic.md'), 'w', encoding='utf-8') as f:
        f.write(text)
    print(text)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
