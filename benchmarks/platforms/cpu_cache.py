"""Is the CPU step bound by memory? RigidLangevinIntegrator's time per body-step on the CPU platform,
one thread, with the step's arrays inside the last-level cache against far outside it: force-free
water-shaped bodies (integrator_cost.build), 2e4 of them (about 14 MB by traffic.py's model of the
CPU kernel, 688 bytes per body-step) against 1e6 (about 690 MB), timed in alternating pairs so
that both see the same machine load, in CPU time (this VM's wall clock scatters by a factor of two
when the host takes its core away). A step bound by memory would be slower out of cache by up to
the ratio of the bandwidths; one bound by arithmetic takes the same time. This decides whether
moving fewer bytes (traffic.md's excess over the minimum on the CPU) can make the CPU step faster.

    python benchmarks/platforms/cpu_cache.py [--pairs 6] [--small 20000] [--large 1000000]

Writes results/cpu_cache.csv (one row per pair) and results/cpu_cache.png, and prints the mean
ratio (large/small) with its standard error over the pairs.
"""
import argparse
import math
import time

import numpy as np

from benchmark_utils import running_context, save_plot, write_table
from integrator_cost import build
from traffic import cpu_current


def last_level_cache_mib():
    """This machine's largest CPU cache in MiB (Linux sysfs), or None."""
    import glob
    sizes = []
    for path in glob.glob('/sys/devices/system/cpu/cpu0/cache/index*/size'):
        text = open(path).read().strip()
        sizes.append(int(text[:-1])/(1024 if text.endswith('K') else 1) if text[-1] in 'KM' else int(text)/2**20)
    return max(sizes) if sizes else None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--pairs', type=int, default=6)
    parser.add_argument('--small', type=int, default=20000, help='bodies whose arrays fit in the last-level cache')
    parser.add_argument('--large', type=int, default=1000000, help='bodies whose arrays do not')
    args = parser.parse_args()
    contexts = {}
    for n in (args.small, args.large):
        system, integrator, positions = build(n, True)
        contexts[n] = (integrator, running_context(system, integrator, positions, 'CPU', {'Threads': '1'}, warmup_steps=2))

    def cpu_time_per_body_step(n, steps, repeats=3):
        """Best of `repeats` blocks of `steps` steps, in the process's CPU time (the CPU platform
        steps synchronously), per body-step."""
        integrator = contexts[n][0]
        best = float('inf')
        for _ in range(repeats):
            start = time.process_time()
            integrator.step(steps)
            best = min(best, time.process_time()-start)
        return best/(steps*n)

    rows = []
    for pair in range(args.pairs):
        row = {'pair': pair+1}
        for n, label in ((args.small, 'small'), (args.large, 'large')):
            row[f'{label}_us_per_body_step'] = 1e6*cpu_time_per_body_step(n, max(2, int(2e6/n)))
        row['large_over_small'] = row['large_us_per_body_step']/row['small_us_per_body_step']
        rows.append(row)
        print(row, flush=True)
    small = np.array([r['small_us_per_body_step'] for r in rows])
    large = np.array([r['large_us_per_body_step'] for r in rows])
    ratios = large/small
    mean, error = ratios.mean(), ratios.std(ddof=1)/math.sqrt(len(ratios))
    cache = last_level_cache_mib()
    mib_per_step = lambda bodies: bodies*cpu_current(3)/2**20  # traffic.py's model of the CPU kernel
    print(f'last-level cache {cache} MiB; the step moves {mib_per_step(args.small):.0f} MiB ({args.small} bodies) '
          f'and {mib_per_step(args.large):.0f} MiB ({args.large}) by the model')
    print(f'time per body-step out of cache / in cache: {mean:.3f} +- {error:.3f} ({len(ratios)} alternating pairs)')
    write_table('cpu_cache', ['pair', 'small_us_per_body_step', 'large_us_per_body_step', 'large_over_small'],
                [{'pair': r['pair'], **{key: f'{value:.4g}' for key, value in r.items() if key != 'pair'}} for r in rows])

    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.8))
    pairs = [r['pair'] for r in rows]
    left.plot(pairs, small, 'o-', label=f'{args.small} bodies ({mib_per_step(args.small):.0f} MiB per step)')
    left.plot(pairs, large, 's-', label=f'{args.large} bodies ({mib_per_step(args.large):.0f} MiB per step)')
    left.set_xlabel('pair (timed alternately)')
    left.set_ylabel('us per body-step (CPU, one thread)')
    left.set_title(f'last-level cache {cache:.0f} MiB' if cache else 'CPU platform, one thread')
    left.set_ylim(bottom=0)
    left.legend(fontsize=8)
    right.plot(pairs, ratios, 'o')
    right.axhline(mean, color='k', lw=0.8)
    right.axhspan(mean-error, mean+error, color='k', alpha=0.15, label=f'mean {mean:.2f} +- {error:.2f}')
    right.axhline(1, color='r', lw=0.8, ls='--')
    right.set_xlabel('pair')
    right.set_ylabel('out of cache / in cache')
    right.set_title('time per body-step')
    right.legend(fontsize=8)
    save_plot(fig, 'cpu_cache')


if __name__ == '__main__':
    main()
