"""Helpers shared by the platform benchmarks: platforms, timing, tables and plots."""
import csv
import os
import time

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


def time_per_step(integrator, context, steps, repeats=3):
    """Best time per step (seconds) over a few blocks of steps, each ended by a State (a sync)."""
    integrator.step(5)
    context.getState(getPositions=True)
    best = float('inf')
    for _ in range(repeats):
        start = time.perf_counter()
        integrator.step(steps)
        context.getState(getPositions=True)
        best = min(best, (time.perf_counter()-start)/steps)
    return best


def write_table(name, columns, rows):
    """Write rows (dicts) as results/<name>.csv and print them as an aligned table."""
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, name+'.csv')
    with open(path, 'w', newline='') as f:
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
