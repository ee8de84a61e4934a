"""Tables, plots and the verdict on the targets of the speed-against-error study.

Errors come with a standard error ('error X +-': measurement and truth combined). A difference
between two integrators counts only when it exceeds the 95% two-sided Student-t quantile times the
standard error of the difference, with the degrees of freedom of the standard errors (replicas - 1
in S2, where three replicas, the default, give 2 and the quantile is 4.3; groups of bodies or blocks - 1 = 9 in
S1): below that the study cannot tell them apart, and says so rather than ranking noise.
"""
import csv
import math

import numpy as np

from rigidlangevin.statistics import standard_error

DYNAMICAL = ['D translational (nm^2/ps)', 'orientational time (ps)', 'VACF']
CONFIGURATIONAL = ['T translational (K)', 'T rotational (K)', 'potential per molecule (kJ/mol)', 'T configurational (K)', 'O-O RDF']
DEFAULT, ORIGINAL = 'ExactFlow', 'Original'
ABSOLUTE = ('VACF', 'O-O RDF')  # root-mean-square differences, not relative errors
# 95% two-sided Student-t quantiles by degrees of freedom (2.0 beyond the table).
T_QUANTILE = {1: 12.71, 2: 4.30, 3: 3.18, 4: 2.78, 5: 2.57, 6: 2.45, 7: 2.36, 8: 2.31, 9: 2.26, 10: 2.23,
              15: 2.13, 20: 2.09, 30: 2.04}


def write_csv(path, rows):
    """Rows (dicts) as CSV, with the union of their keys as columns in first-seen order."""
    fields = []
    for r in rows:
        fields += [k for k in r if k not in fields]
    with open(path, 'w', newline='', encoding='utf-8') as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        writer.writerows(rows)


def read_csv(path):
    """Rows written by write_csv, numbers as numbers and empty cells left out."""
    with open(path, encoding='utf-8') as f:
        return [{k: number(v) for k, v in r.items() if v != ''} for r in csv.DictReader(f)]


def number(text):
    try:
        value = float(text)
    except ValueError:
        return text
    return int(value) if text.lstrip('-').isdigit() else value


def write(out, rows, stability):
    out.mkdir(parents=True, exist_ok=True)
    write_csv(out/'results.csv', rows)
    if stability:
        write_csv(out/'stability.csv', stability)
    table = markdown(rows, stability)+'\n'+targets(rows, stability)
    (out/'table.md').write_text(table, encoding='utf-8')
    print(table)
    plot(out, rows)


def cell(r, observable):
    if 'error '+observable not in r:
        return ''
    e, s = r['error '+observable], r.get('error '+observable+' +-')
    if observable in ABSOLUTE:
        return f'{e:.4f}'+(f' ± {s:.4f}' if s else '')
    return f'{100*e:.2f}'+(f' ± {100*s:.2f}' if s else '')+' %'


def markdown(rows, stability):
    observables = [o for o in DYNAMICAL+CONFIGURATIONAL if any('error '+o in r for r in rows)]
    counts = sorted({int(r['replicas']) for r in rows if r['scene'].startswith('S2') and 'replicas' in r}) or [3]
    replicas = counts[0]
    lines = ['Errors against the truth (exact for S1, the 0.5 fs reference for S2), ± one standard error;',
             'VACF and O-O RDF: root-mean-square difference of the normalized function. Standard errors: over',
             f'{"-".join(str(c) for c in sorted({counts[0], counts[-1]}))} replicas in S2 (each row\'s count is '
             'in results.csv; at least '
             f'{replicas-1} degrees of freedom, so the verdicts below take differences beyond '
             f'{quantile({"replicas": replicas})} of',
             'them as real), over 10 groups of bodies (or blocks) in S1. S2\'s errors of D and of the orientational',
             'time compare each replica with the reference run from the same start (paired by start).', '',
             '| scene | viscosity (P) | integrator | step (fs) | ns/day | '+' | '.join('error '+o for o in observables)+' |',
             '|'+'---|'*(5+len(observables))]
    for r in rows:
        if r['status'] != 'ok':
            cells = [r['status']]+['']*(len(observables))
        else:
            cells = [f"{r.get('ns/day', float('nan')):.1f}"]+[cell(r, o) for o in observables]
        lines.append(f"| {r['scene']} | {r['viscosity (P)']} | {r['integrator']} | {r['step (fs)']} | "+' | '.join(cells)+' |')
    if stability:
        lines += ['', '| viscosity (P) | integrator | largest stable step (fs) |', '|---|---|---|']
        for s in stability:
            lines.append(f"| {s['viscosity (P)']} | {s['integrator']} | {s['largest stable step (fs)']} |")
    return '\n'.join(lines)+'\n'


def _error(r, observable):
    return r['error '+observable], r.get('error '+observable+' +-', 0.0) or 0.0


def quantile(*points):
    """The t quantile for a difference of these points' errors: the fewest degrees of freedom
    (paired replicas - 1, else replicas - 1, in S2; 10 groups of bodies or blocks - 1 in S1)."""
    dof = min(int(p.get('paired replicas', p.get('replicas', 10)))-1 for p in points)
    return T_QUANTILE.get(dof) or T_QUANTILE[max(k for k in T_QUANTILE if k <= dof)]


def targets(rows, stability):
    """The issue's targets, checked on these results, one line per target and viscosity."""
    lines = ['## Targets', '', 'A difference counts where it exceeds the 95% Student-t quantile times its standard error.', '']
    groups = sorted({(r['scene'], r['viscosity (P)']) for r in rows if 'reference' not in r['scene']})
    for scene, viscosity in groups:
        selected = [r for r in rows if (r['scene'], r['viscosity (P)']) == (scene, viscosity) and r['status'] == 'ok']
        default = [r for r in selected if r['integrator'] == DEFAULT]
        others = [r for r in selected if r['integrator'] != DEFAULT]
        # Dynamical: every competitor point must be matched by a default point at least as fast
        # (within 10% timing noise) and no worse beyond the noise of the difference.
        for observable in [o for o in DYNAMICAL if any('error '+o in r for r in selected)]:
            beaten = []
            for other in (r for r in others if 'error '+observable in r):
                e, s = _error(other, observable)
                matched = any(_error(d, observable)[0] <= e+quantile(d, other)*math.hypot(s, _error(d, observable)[1])
                              for d in default if 'error '+observable in d and d['ns/day'] >= 0.9*other['ns/day'])
                if not matched:
                    beaten.append(f"{other['integrator']} {other['step (fs)']} fs")
            verdict = 'met' if not beaten else 'NOT met: below it '+', '.join(beaten)
            lines.append(f'- {scene}, {viscosity} P, {observable}: {DEFAULT} front on or below every competitor: {verdict}')
        # Configurational: within 1.5 times the best at the same step, beyond the noise.
        for observable in [o for o in CONFIGURATIONAL if any('error '+o in r for r in selected)]:
            worse = []
            for d in (r for r in default if 'error '+observable in r):
                same = [r for r in others if r['step (fs)'] == d['step (fs)'] and 'error '+observable in r]
                if not same:
                    continue
                best = min(same, key=lambda r: _error(r, observable)[0])
                e, s = _error(d, observable)
                eb, sb = _error(best, observable)
                if e > 1.5*eb+quantile(d, best)*math.hypot(s, 1.5*sb):
                    worse.append(f"{d['step (fs)']} fs ({cell(d, observable)} vs {best['integrator']} {cell(best, observable)})")
            verdict = 'met' if not worse else 'NOT met at '+'; '.join(worse)
            lines.append(f'- {scene}, {viscosity} P, {observable}: {DEFAULT} within 1.5x of the best: {verdict}')
        # Temperature at 2 fs: the mean of the translational and rotational kinetic temperatures
        # (three degrees of freedom each per body).
        at2 = [d for d in default if d['step (fs)'] == 2.0 and 'T translational (K)' in d and 'T rotational (K)' in d]
        for d in at2:
            t = 0.5*(d['T translational (K)']+d['T rotational (K)'])
            s = 0.5*math.hypot(d.get('T translational (K) +-', 0.0), d.get('T rotational (K) +-', 0.0))
            deviation = abs(t-300.0)/300.0
            lines.append(f"- {scene}, {viscosity} P: |<T> - T0| at 2 fs = {100*deviation:.3f} % (<T> = {t:.2f} ± {s:.2f} K; "
                         f"target below 0.2 %): {'met' if deviation < 0.002 else 'NOT met'}")
    if stability:
        by = {(float(s['viscosity (P)']), s['integrator']): float(s['largest stable step (fs)']) for s in stability}
        for viscosity in sorted({v for v, _ in by}):
            d, o = by.get((viscosity, DEFAULT)), by.get((viscosity, ORIGINAL))
            if d is None or o is None:
                continue
            ok = d >= 2*o
            lines.append(f"- stability, {viscosity} P: {DEFAULT} {d:g} fs, {ORIGINAL} {o:g} fs"
                         f"{' (refused at every step)' if o == 0 else ''}: at least twice: {'met' if ok else 'NOT met'}")
    return '\n'.join(lines)+'\n'


def plot(out, rows):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    groups = sorted({(r['scene'], r['viscosity (P)']) for r in rows if 'reference' not in r['scene']})
    for scene, viscosity in groups:
        selected = [r for r in rows if r['scene'] == scene and r['viscosity (P)'] == viscosity and r['status'] == 'ok']
        observables = [o for o in DYNAMICAL+CONFIGURATIONAL if any('error '+o in r for r in selected)]
        if not observables:
            continue
        columns = 4
        lines = (len(observables)+columns-1)//columns
        fig, axes = plt.subplots(lines, columns, figsize=(4*columns, 3.2*lines), squeeze=False)
        for ax, observable in zip(axes.flat, observables):
            for integrator in sorted({r['integrator'] for r in selected}):
                points = sorted((r['ns/day'], *_error(r, observable)) for r in selected
                                if r['integrator'] == integrator and 'error '+observable in r)
                if points:
                    x, e, s = (np.array(v) for v in zip(*points))
                    ax.errorbar(x, np.maximum(e, 1e-5), yerr=[np.minimum(s, 0.9*np.maximum(e, 1e-5)), s],
                                fmt='o-', capsize=2, label=integrator)
            ax.set_xscale('log')
            ax.set_yscale('log')
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # labels at 2x, 3x... overlap
            ax.set_xlabel('ns/day')
            ax.set_ylabel('error' if observable in ABSOLUTE else 'relative error')
            ax.set_title(observable, fontsize=9)
        for ax in list(axes.flat)[len(observables):]:
            ax.axis('off')
        axes.flat[0].legend(fontsize=7)
        fig.suptitle(f'{scene}, {viscosity} P: error against speed (step sizes along each line; bars: one standard error)')
        fig.tight_layout()
        name = scene.split()[0].lower()
        fig.savefig(out/f'error_vs_speed_{name}_{viscosity}P.png', dpi=100)
        plt.close(fig)


def paired(values, peers):
    """Mean and standard error of `values` (one per replica), and of their differences from `peers`
    run from the same starts: the difference is free of the starts' spread."""
    values, peers = np.asarray(values, float), np.asarray(peers, float)
    difference = values-peers
    return float(values.mean()), standard_error(values), float(difference.mean()), standard_error(difference)


def paired_relative_error(values, references):
    """Relative error mean(values)/mean(references) - 1 of replicas paired by start (value i and
    reference i ran from the same start), and its standard error by the ratio estimator's
    linearisation z_i = (v_i - R r_i)/mean(r): the starts' shared spread cancels, as in `paired`."""
    values, references = np.asarray(values, float), np.asarray(references, float)
    ratio = values.mean()/references.mean()
    return float(ratio-1), standard_error((values-ratio*references)/references.mean())


def write_configurational(out, records, exact, peer):
    """configurational.csv (one line per run) and configurational.md: the configurational
    temperature of each (integrator, step) against its exact value and, start by start, against the
    peer (integrator, step); likewise the potential energy per molecule against the peer."""
    out.mkdir(parents=True, exist_ok=True)
    write_csv(out/'configurational.csv', records)
    failed = [r for r in records if r['status'] != 'ok']
    runs = sorted({(r['integrator'], r['step (fs)']) for r in records}, key=lambda k: (k != tuple(peer), k))
    by = {k: {r['replica']: r for r in records if (r['integrator'], r['step (fs)']) == k and r['status'] == 'ok'} for k in runs}
    replicas = sorted(set.intersection(*(set(v) for v in by.values())))
    tc, pe = 'T configurational (K)', 'potential per molecule (kJ/mol)'
    lines = [f'Configurational temperature at 1 P from {len(replicas)} replicas (each from its own start; every '
             f'run is also compared, start by start, with {peer[0]} at {peer[1]} fs from the same start). '
             f'Exact: {exact:g} K. ± one standard error over replicas.', '',
             f'| integrator | step (fs) | T configurational (K) | minus exact (%) | minus {peer[0]} {peer[1]} fs (%) | '
             f'potential per molecule (kJ/mol) | minus {peer[0]} {peer[1]} fs (kJ/mol) |', '|---|---|---|---|---|---|---|']
    verdicts = []
    for k in runs:
        t, st, dt, sdt = paired([by[k][i][tc] for i in replicas], [by[tuple(peer)][i][tc] for i in replicas])
        p, sp, dp, sdp = paired([by[k][i][pe] for i in replicas], [by[tuple(peer)][i][pe] for i in replicas])
        off, soff = 100*(t-exact)/exact, 100*st/exact
        rel, srel = 100*dt/exact, 100*sdt/exact
        same = k == tuple(peer)
        lines.append(f'| {k[0]} | {k[1]} | {t:.1f} ± {st:.1f} | {off:+.2f} ± {soff:.2f} | '
                     f"{'' if same else f'{rel:+.2f} ± {srel:.2f}'} | {p:.3f} ± {sp:.3f} | {'' if same else f'{dp:+.4f} ± {sdp:.4f}'} |")
        verdicts.append(f"- {k[0]} {k[1]} fs: two standard errors of T configurational are {2*soff:.2f} % "
                        f"({'resolves' if 2*soff <= 1.0 else 'does NOT resolve'} 1 %); it is {abs(off)/soff:.1f} standard errors from "
                        f"{exact:g} K ({'consistent' if abs(off) <= 2*soff else 'a bias beyond 2 standard errors'})"
                        + ('' if same else f"; {abs(rel)/srel:.1f} standard errors from {peer[0]} {peer[1]} fs"))
    lines += ['', '## Verdict', ''] + verdicts
    if failed:
        lines.append(f'- {len(failed)} runs failed: '+', '.join(f"{r['integrator']} {r['step (fs)']} fs replica {r['replica']}: {r['status']}" for r in failed))
    text = '\n'.join(lines)+'\n'
    (out/'configurational.md').write_text(text, encoding='utf-8')
    print(text)
