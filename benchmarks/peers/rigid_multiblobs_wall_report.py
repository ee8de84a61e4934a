"""The table (markdown) and plot of rigid_multiblobs_wall_driver.py's results.

    python benchmarks/peers/rigid_multiblobs_wall_report.py benchmarks/hydrodynamics/results/rigid_multiblobs_wall.json

writes rigid_multiblobs_wall.md and .png beside the JSON: seconds per blob mobility product, per
mobility solve (and its preconditioner) and per Brownian step against the number of bodies, each
the mean of the repeats +- its standard error, with the iterations and the machine's load.
"""
import json
import os
import sys

ROWS = [('product', 'open', 'M f, open space'), ('product', 'wall', 'M f, above the wall'),
        ('solve', 'open', 'solve to 1e-8, open space'), ('preconditioner', 'open', 'its preconditioner, open space'),
        ('solve', 'wall', 'solve to 1e-8, above the wall'), ('preconditioner', 'wall', 'its preconditioner, above the wall'),
        ('brownian_step', 'wall', 'Brownian step (Slip_Trapz, 1e-3), above the wall')]


def cell(entry):
    """'mean +- error' in seconds, with CPU time (all threads) after it."""
    if entry is None:
        return '—'
    return f"{entry['mean_s']:.3g} ± {entry['standard_error_s']:.1g} (CPU {entry['cpu_mean_s']:.3g})"


def span(values):
    """'a' where every value is a, else 'min–max'."""
    low, high = min(values), max(values)
    return f'{low}' if low == high else f'{low}–{high}'


def iterations(entry):
    if entry is None:
        return ''
    if 'iterations' in entry:
        return f"GMRES {span(entry['iterations'])}"
    if 'gmres_iterations_per_step' in entry:
        return f"GMRES {span(entry['gmres_iterations_per_step'])}, Lanczos {span(entry['lanczos_iterations_per_step'])} per step"
    return ''


def table(report):
    sizes = report['sizes']
    lines = ['| what | ' + ' | '.join(f"{s['num_bodies']} bodies ({s['num_blobs']} blobs)" for s in sizes) + ' |',
             '|---|' + '---|'*len(sizes)]
    for key, domain, label in ROWS:
        entries = [s[domain].get(key) for s in sizes]
        if any(entries):
            lines.append(f'| {label}, s | ' + ' | '.join(cell(e) for e in entries) + ' |')
            counts = [iterations(e) for e in entries]
            if any(counts):
                lines.append('| iterations | ' + ' | '.join(counts) + ' |')
    return '\n'.join(lines)


def machine_lines(report):
    m = report['machine']
    return [f"Peer: RigidMultiblobsWall at commit {report['peer']['commit']}; Python {m['python']}, numpy {m['numpy']}, "
            f"scipy {m['scipy']}, numba {m['numba']} ({m['numba_threads']} threads, threading layer "
            f"{m.get('numba_threading_layer', '?')}); started {report['started']}.",
            f"Machine: {m['processor']}, {m['cores']} cores, {m['platform']}; niceness {m['niceness']}; "
            f"load averages (1, 5, 15 min) {', '.join(f'{x:.2f}' for x in m['load_averages_before'])} before and "
            f"{', '.join(f'{x:.2f}' for x in m['load_averages_after'])} after; environment {m['environment']}."]


def code_paths(report):
    """Which of the peer's functions each row timed, from the settings the driver recorded."""
    s = report['settings']
    step = s['brownian_step']
    return ['Code paths (the peer\'s own): M f by its numba kernels mobility.' + ' and mobility.'.join(
                f"{name}_mobility_trans_times_force_numba" for name in ('no_wall', 'single_wall')) + '; the solve by '
            'QuaternionIntegrator.solve_mobility_problem (its GMRES, right-preconditioned, restart '
            f"{s['solve']['gmres_restart']}, relative residual {s['solve']['tolerance']:g}, zero first guess) with "
            f"{s['solve']['preconditioner']} (each body's own problem solved exactly), built beforehand and timed on its own "
            f"row; the Brownian step by QuaternionIntegrator.{step['scheme']} (its recommended scheme) at tolerance "
            f"{step['tolerance']:g} (GMRES and Lanczos), dt {step['dt']:g} s, rf_delta {step['rf_delta']:g}, "
            f"the preconditioner rebuilt every step; forces: {s['forces']}."]


def plot(report, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for key, domain, label in ROWS:
        points = [(s['num_bodies'], s[domain][key]) for s in report['sizes'] if key in s[domain]]
        if points and key != 'preconditioner':
            n = [p[0] for p in points]
            ax.errorbar(n, [p[1]['mean_s'] for p in points], yerr=[p[1]['standard_error_s'] for p in points],
                        marker='o', capsize=3, label=label)
    ax.set_xscale('log')
    ax.set_yscale('log')
    ax.set_xlabel('boomerangs (15 blobs each)')
    ax.set_ylabel('seconds')
    threads = report['machine']['numba_threads']
    ax.set_title(f"RigidMultiblobsWall (numba, {threads} thread{'s' if threads > 1 else ''})")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    path = sys.argv[1]
    with open(path, encoding='utf-8') as f:
        report = json.load(f)
    stem = os.path.splitext(path)[0]
    with open(stem+'.md', 'w', encoding='utf-8') as f:
        f.write('\n'.join(['# RigidMultiblobsWall on the boomerang suspensions', '',
                           'Written by benchmarks/peers/rigid_multiblobs_wall_report.py from '
                           f'{os.path.basename(path)}. Each cell: wall-clock seconds, mean of the repeats ± its '
                           'standard error, and the mean process CPU time of all threads.', '',
                           table(report), ''] + code_paths(report) + [''] + machine_lines(report) + ['']))
    plot(report, stem+'.png')
    print(f'(written to {stem}.md and {stem}.png)')


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
