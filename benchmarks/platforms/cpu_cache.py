"""Is the CPU step bound by memory? RigidLangevinIntegrator's time per body-step on the CPU platform,
one thread, with the step's arrays inside the last-level cache against far outside it: force-free
water-shaped bodies (integrator_cost.build), 2e4 of them (about 10 MB by traffic.py's model of the
CPU kernel, 524 bytes per body-step) against 1e6 (about 500 MB), timed in alternating pairs so
that both see the same machine load, in CPU time (this VM's wall clock scatters by a factor of two
when the host takes its core away). A step bound by memory would be slower out of cache by up to
the ratio of the bandwidths; one bound by arithmetic takes the same time. This decides whether
moving fewer bytes (traffic.md's excess over the minimum on the CPU) can make the CPU step faster.

Out of cache the step writes particle positions and velocities with streaming stores, which do not
read the lines they fill (RigidBodyModel::chooseParticleStores); the same large system is timed with
ordinary stores too (RIGIDLANGEVIN_HOST_PARTICLE_STORES=cached), in the same pairs, to show what
streaming costs or saves in time (it saves 144 of 668 bytes per body-step by the model).

    python benchmarks/platforms/cpu_cache.py [--pairs 6] [--small 20000] [--large 1000000]

Writes results/cpu_cache.csv (one row per pair) and results/cpu_cache.png, and prints the mean
ratios (large/small, streaming/ordinary stores) with their standard errors over the pairs.
"""
import sys
import argparse
import os
import time

import numpy as np

from benchmark_utils import mean_and_error, running_context, save_plot, write_table
from integrator_cost import build
from traffic import cpu_current


def last_level_cache_mib():
    """This machine's largest CPU cache in MiB (Linux sysfs), or None."""
    import glob
    sizes = []
    for path in glob.glob('/sys/devices/system/cpu/cpu0/cache/index*/size'):
        text = open(path, encoding='utf-8').read().strip()
        sizes.append(int(text[:-1])/(1024 if text.endswith('K') else 1) if text[-1] in 'KM' else int(text)/2**20)
    return max(sizes) if sizes else None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--pairs', type=int, default=6)
    parser.add_argument('--small', type=int, default=20000, help='bodies whose arrays fit in the last-level cache')
    parser.add_argument('--large', type=int, default=1000000, help='bodies whose arrays do not')
    args = parser.parse_args()
    # (label, bodies, stores): the stores are read when the Context is made.
    runs = [('small', args.small, 'auto'), ('large', args.large, 'streaming'), ('large_cached', args.large, 'cached')]
    contexts = {}
    for label, n, stores in runs:
        os.environ['RIGIDLANGEVIN_HOST_PARTICLE_STORES'] = stores
        system, integrator, positions = build(n, True)
        contexts[label] = (integrator, running_context(system, integrator, positions, 'CPU', {'Threads': '1'}, warmup_steps=2))
    del os.environ['RIGIDLANGEVIN_HOST_PARTICLE_STORES']

    def cpu_time_per_body_step(label, n, steps, repeats=3):
        """Best of `repeats` blocks of `steps` steps, in the process's CPU time (the CPU platform
        steps synchronously), per body-step."""
        integrator = contexts[label][0]
        best = float('inf')
        for _ in range(repeats):
            start = time.process_time()
            integrator.step(steps)
            best = min(best, time.process_time()-start)
        return best/(steps*n)

    rows = []
    for pair in range(args.pairs):
        row = {'pair': pair+1}
        order = runs if pair % 2 == 0 else runs[::-1]  # neither large run always follows the other
        for label, n, stores in order:
            row[f'{label}_us_per_body_step'] = 1e6*cpu_time_per_body_step(label, n, max(2, int(2e6/n)))
        row['large_over_small'] = row['large_us_per_body_step']/row['small_us_per_body_step']
        row['streaming_over_cached'] = row['large_us_per_body_step']/row['large_cached_us_per_body_step']
        rows.append(row)
        print(row, flush=True)
    small = np.array([r['small_us_per_body_step'] for r in rows])
    large = np.array([r['large_us_per_body_step'] for r in rows])
    large_cached = np.array([r['large_cached_us_per_body_step'] for r in rows])
    ratios, streaming = large/small, large/large_cached
    mean, error = mean_and_error(ratios)
    cache = last_level_cache_mib()
    mib_per_step = lambda bodies: bodies*cpu_current(3)/2**20  # traffic.py's model of the CPU kernel
    print(f'last-level cache {cache} MiB; the step moves {mib_per_step(args.small):.0f} MiB ({args.small} bodies) '
          f'and {mib_per_step(args.large):.0f} MiB ({args.large}) by the model')
    print(f'time per body-step out of cache / in cache: {mean:.3f} +- {error:.3f} ({len(ratios)} alternating pairs)')
    print('out of cache, streaming stores / ordinary stores: %.3f +- %.3f' % mean_and_error(streaming))
    write_table('cpu_cache', ['pair', 'small_us_per_body_step', 'large_us_per_body_step', 'large_cached_us_per_body_step',
                              'large_over_small', 'streaming_over_cached'],
                [{'pair': r['pair'], **{key: f'{value:.4g}' for key, value in r.items() if key != 'pair'}} for r in rows])

    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.8))
    pairs = [r['pair'] for r in rows]
    left.plot(pairs, small, 'o-', label=f'{args.small} bodies ({mib_per_step(args.small):.0f} MiB per step)')
    left.plot(pairs, large, 's-', label=f'{args.large} bodies, streaming stores ({mib_per_step(args.large):.0f} MiB per step)')
    left.plot(pairs, large_cached, '^-', label=f'{args.large} bodies, ordinary stores')
    left.set_xlabel('pair (timed alternately)')
    left.set_ylabel('us per body-step (CPU, one thread)')
    left.set_title(f'last-level cache {cache:.0f} MiB' if cache else 'CPU platform, one thread')
    left.set_ylim(bottom=0)
    left.legend(fontsize=8)
    for values, marker, color, label in ((ratios, 'o', 'C0', 'out of cache / in cache'),
                                         (streaming, '^', 'C2', 'out of cache: streaming / ordinary stores')):
        m, e = mean_and_error(values)
        right.plot(pairs, values, marker, color=color)
        right.axhline(m, color=color, lw=0.8)
        right.axhspan(m-e, m+e, color=color, alpha=0.15, label=f'{label}: {m:.2f} +- {e:.2f}')
    right.axhline(1, color='r', lw=0.8, ls='--')
    right.set_xlabel('pair')
    right.set_ylabel('ratio')
    right.set_title('time per body-step')
    right.legend(fontsize=7, loc='lower left')
    save_plot(fig, 'cpu_cache')


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
