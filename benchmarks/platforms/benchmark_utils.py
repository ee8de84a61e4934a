"""Helpers shared by the platform benchmarks: platforms, timing, tables and plots."""
import csv
import math
import os
import time

import numpy as np
import openmm as mm

KERNEL = 'IntegrateRigidLangevinStep'
RESULTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'results')


def platform_status(name):
    """None if the plugin can run on the named platform here, else why it cannot."""
    try:
        platform = mm.Platform.getPlatformByName(name)
    except Exception:
        library = f'libOpenMM{name}.so'
        failures = [f for f in mm.Platform.getPluginLoadFailures() if library in f]
        if failures:
            reason = failures[0].split(library+': ', 1)[-1].strip()
            return f'not available on this machine: {library} does not load ({reason}); no GPU here'
        return 'not available on this machine: OpenMM has no such platform here'
    if not platform.supportsKernels([KERNEL]):
        return 'plugin kernels not registered'
    return None


GPU_PLATFORMS = ('OpenCL', 'CUDA')


def platform_properties(name, precision):
    """The Context properties of a platform at a precision: the GPU platforms take one; the host
    platforms compute in double precision and take none."""
    return {'Precision': precision} if name in GPU_PLATFORMS else {}


def running_context(system, integrator, positions, platform_name, properties, warmup_steps=0):
    """A Context on the named platform, at the positions, with velocities at 300 K (seed 1), after
    warmup_steps steps (so that kernels are compiled and neighbour lists built before timing)."""
    import openmm.unit as unit
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform_name), properties)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300*unit.kelvin, 1)
    if warmup_steps:
        integrator.step(warmup_steps)
    return context


def time_per_step(integrator, context, steps, repeats=3, min_seconds=0.2, subtract_sync=True):
    """Time per step (seconds). Each block of steps ends with a State (the sync). With subtract_sync,
    the difference between the best block of 2*steps and the best block of steps, which cancels the
    State's own cost: at 1e6 bodies (a copy of every position) it outweighs many GPU steps; steps
    grow until the difference is at least min_seconds, so that timer noise is small beside it.
    Without, the best block divided by steps (for small systems, where the State costs little and
    a difference of two blocks would only add noise)."""
    integrator.step(5)
    context.getState(getPositions=True)

    def best_block(n):
        best = float('inf')
        for _ in range(repeats):
            start = time.perf_counter()
            integrator.step(n)
            context.getState(getPositions=True)
            best = min(best, time.perf_counter()-start)
        return best

    if not subtract_sync:
        return best_block(steps)/steps
    while True:
        difference = best_block(2*steps)-best_block(steps)
        if difference >= min_seconds or steps >= 1000000:
            return difference/steps
        steps *= 4


def calibrated_steps(integrator, context, steps, min_seconds=0.3):
    """Steps per timing block: `steps`, grown fourfold until one block (less its closing State)
    takes at least min_seconds, so that timer noise and the State's cost are small beside it."""
    sync = sync_seconds(context)
    while steps < 1000000:
        start = time.perf_counter()
        integrator.step(steps)
        context.getState(getPositions=True)
        if time.perf_counter()-start-sync >= min_seconds:
            break
        steps *= 4
    return steps


def sync_seconds(context, repeats=3):
    """The cost of the State that closes each timing block, taken with nothing queued (best of
    repeats): at 1e6 bodies on a GPU it is a copy of every position, worth many steps."""
    context.getState(getPositions=True)
    best = float('inf')
    for _ in range(repeats):
        start = time.perf_counter()
        context.getState(getPositions=True)
        best = min(best, time.perf_counter()-start)
    return best


def paired_times(contexts, steps, pairs=5, prepare=None):
    """Time per step (s) of each of several {key: (integrator, context)}: {key: [one per pair]}.
    In each pair every context runs one block of `steps` steps (or steps[key], for contexts whose
    steps differ by orders of magnitude in cost) closed by a State, in turn, so that
    all see the same machine load; the order is reversed every other pair so that none always
    follows another; each block's State is timed alone beforehand and subtracted. Ratios taken
    pair by pair cancel the load the pair saw; mean_and_error gives their standard error.
    prepare: optionally {key: function}, called before each of that context's blocks (to set what
    the context reads as it steps, such as an environment variable)."""
    sync = {key: sync_seconds(context) for key, (integrator, context) in contexts.items()}
    times = {key: [] for key in contexts}
    keys = list(contexts)
    for pair in range(pairs):
        for key in (keys if pair % 2 == 0 else keys[::-1]):
            integrator, context = contexts[key]
            block = steps[key] if isinstance(steps, dict) else steps
            if prepare and key in prepare:
                prepare[key]()
            start = time.perf_counter()
            integrator.step(block)
            context.getState(getPositions=True)
            times[key].append(max(time.perf_counter()-start-sync[key], 0.0)/block)
    return times


def mean_and_error(values):
    """Mean and its standard error (sample standard deviation / sqrt(n))."""
    values = np.asarray(values, dtype=float)
    return values.mean(), values.std(ddof=1)/math.sqrt(len(values))


def save_plot(fig, name):
    """Save a figure as results/<name>.png."""
    fig.tight_layout()
    path = f'{RESULTS}/{name}.png'
    fig.savefig(path, dpi=120)
    print(f'(plot: {path})')


def write_table(name, columns, rows):
    """Write rows (dicts) as results/<name>.csv and print them as an aligned table."""
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, name+'.csv')
    with open(path, 'w', newline='', encoding='utf-8') as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow({c: row.get(c, '') for c in columns})
    widths = [max(len(c), *(len(str(row.get(c, ''))) for row in rows)) for c in columns]
    print('  '.join(c.rjust(w) for c, w in zip(columns, widths)))
    for row in rows:
        print('  '.join(str(row.get(c, '')).rjust(w) for c, w in zip(columns, widths)))
    print(f'(written to {path})')
    return path
