"""The banana scene's answer: diffusion.md/.csv and correlations.csv/.png from the study folder's
explicit and implicit runs (banana_scene.py's stages), with the solvent's viscosity from
pentane_report.py.

D_t is the long-time diffusion of the bananas' centres of diffusion; D_r the tumbling of the middle
ellipsoid's long axis, <u(0).u(t)> = exp(-2 D_r t) (rotation about that axis leaves u alone).
Everything that uses the solvent model's own viscosity (the finite-size correction of the explicit
D_t, the matching viscosities over the solvent's) is given for both of its extrapolations to k = 0
(pentane_report.FORMS), whose spread is larger than either's error.
"""
import csv
import math

import numpy as np

import banana_model as bm
import banana_runs as runs
import pentane_report as pr
import pentane_solvent as ps

CM2_S = 1e3  # nm^2/ps in 1e-5 cm^2/s
# The relative standard errors of D_t and D_r the full study is to reach (the explicit one's D_t
# finite-size corrected); the report says which are reached and how many replicas the spread so
# far asks for.
TARGET_ERRORS = {'explicit': 0.05, 'implicit': 0.03}
# The lags (ps) at which diffusion.md compares the normalised velocity autocorrelations, and the
# range over which it gives their smallest difference in standard errors.
VACF_LAGS = (0.05, 0.1, 0.2, 0.5, 1.0)
VACF_RANGE = (0.02, 1.0)


def fit_slope(t, y, window):
    inside = (t >= window[0]-1e-9) & (t <= window[1]+1e-9)
    return float(np.polyfit(t[inside], y[inside], 1)[0])


def replica_constants(stage, window):
    """Per replica: D_t (nm^2/ps) from the slope of the mean-square displacement of the centres of
    diffusion over window (ps), D_r (1/ps) from that of -log <u(0).u(t)> / 2."""
    d_t, d_r = [], []
    for _, run in stage.runs():
        t = np.arange(len(run['msd']))*runs.COARSE_PS
        d_t.append(fit_slope(t, run['msd'], window)/6)
        d_r.append(-fit_slope(t, np.log(np.clip(run['cu'], 1e-12, None)), window)/2)
    return np.array(d_t), np.array(d_r)


def jackknife_error(statistic, *samples):
    """The standard error of statistic(*samples) by the delete-one jackknife over the samples'
    common index (the replicas): for a statistic of several quantities of the same replicas, whose
    correlation the errors of each alone leave out."""
    n = len(samples[0])
    left_out = np.array([statistic(*(np.delete(s, i) for s in samples)) for i in range(n)])
    return math.sqrt((n-1)/n*np.sum((left_out-left_out.mean())**2))


def mean_error(values):
    values = np.asarray(values, dtype=float)
    return float(values.mean()), float(values.std(ddof=1)/math.sqrt(len(values))) if len(values) > 1 else float('nan')


def curves(stage, key):
    values = np.array([run[key]/(run[key][0] if key == 'vacf' else 1) for _, run in stage.runs()])
    return values.mean(axis=0), (values.std(axis=0, ddof=1)/math.sqrt(len(values)) if len(values) > 1 else np.zeros(values.shape[1]))


def platform_counts(stages):
    """'explicit: CPU 8; ExactFlow: CPU 6, CUDA 2; ...' (runs saved before platforms were kept ran on the CPU)."""
    def count(stage):
        platforms = [str(run['platform']) if 'platform' in run else 'CPU' for _, run in stage.runs()]
        return ', '.join(f'{p} {platforms.count(p)}' for p in sorted(set(platforms)))
    return '; '.join(f'{stage.name}: {count(stage)}' for stage in stages)


def target_errors(rows):
    """The sentence that says, for each run of the diffusion table (rows as in diffusion.csv; the
    explicit one by its finite-size corrected D_t), whether its relative standard errors reach
    TARGET_ERRORS, and for those that do not, the replicas that the spread so far asks for (the
    error falls as one over the square root of the count)."""
    short = []
    for row in rows:
        if row['run'] == 'explicit':
            continue
        kind = 'explicit' if row['run'].startswith('explicit') else 'implicit'
        for quantity, column in (('D_t', 'D_t (1e-5 cm^2/s)'), ('D_r', 'D_r (1/ns)')):
            relative = row[f'{quantity} error']/row[column]
            if not relative <= TARGET_ERRORS[kind]:
                needed = math.ceil(row['replicas']*(relative/TARGET_ERRORS[kind])**2) if math.isfinite(relative) else 2
                entry = f'{row["run"].split(",")[0]} {quantity} {100*relative:.1f}% (about {needed} replicas at this spread)'
                short += [entry] if entry not in short else []  # the explicit D_r once, whichever correction
    reached = (f'Relative standard errors to reach: {100*TARGET_ERRORS["explicit"]:g}% explicit (D_t finite-size corrected), '
               f'{100*TARGET_ERRORS["implicit"]:g}% implicit. ')
    return reached+('Every one reached.' if not short else 'Not reached: '+'; '.join(short)+
                    '. More replicas: --stages explicit (or implicit) --add N.')


def finite_size_correction(eta, box):
    """What a periodic box of edge box (nm) takes from a body's translational diffusion in a fluid of
    viscosity eta (amu/(nm ps)): xi_EW kT/(6 pi eta L) (nm^2/ps; Yeh & Hummer, J. Phys. Chem. B 108,
    15873 (2004)). Rotation's correction is of order the body's volume over the box's, left out."""
    return 2.837297*ps.KT/(6*math.pi*eta*box)


def ratio(a, a_error, b, b_error):
    """a/b and its standard error, the two relative errors combined as independent."""
    return a/b, abs(a/b)*math.hypot(a_error/a, b_error/b)


def diffusion_rows(settings, explicit_stage, implicit_stages, solvent, box):
    """The rows of diffusion.csv (D_t, D_r, their errors and speed per run; the explicit D_t also
    finite-size corrected with each form's eta_0), and the explicit replicas' (D_t, D_r) arrays."""
    rows, replicas = [], {}
    for name, stage in [('explicit', explicit_stage)]+list(zip(runs.IMPLICIT_SCHEMES, implicit_stages)):
        replicas[name] = replica_constants(stage, settings['window_ps'])
        (d_t, d_t_err), (d_r, d_r_err) = (mean_error(v) for v in replicas[name])
        speed = [(settings['production_ps'] if name == 'explicit' else settings['implicit_ps'])*1e-3/float(run['seconds'])*86400
                 for _, run in stage.runs()]
        rows.append({'run': name, 'replicas': len(replicas[name][0]), 'D_t (1e-5 cm^2/s)': d_t*CM2_S, 'D_t error': d_t_err*CM2_S,
                     'D_r (1/ns)': d_r*1e3, 'D_r error': d_r_err*1e3, 'ns/day': float(np.median(speed))})
    d_t_box, d_t_box_err = mean_error(replicas['explicit'][0])
    for i, (key, form) in enumerate(solvent.items()):
        correction = finite_size_correction(form['eta0'], box)
        d_t, d_t_err = d_t_box+correction, math.hypot(d_t_box_err, correction*form['error']/form['eta0'])
        rows.insert(1+i, dict(rows[0], run=f'explicit, finite-size corrected ({pr.FORMS[key].split(" (")[0]})',
                              **{'D_t (1e-5 cm^2/s)': d_t*CM2_S, 'D_t error': d_t_err*CM2_S}))
    return rows, replicas['explicit']


def answer_table(rows, explicit_replicas, solvent, box, xi):
    """The answer by form of the solvent's eta_0: the matching viscosities, the factors by which a
    tensor at the solvent's viscosity is too slow, and the explicit diffusion over this project's
    tensor's and the source's own at 0.289 cP (markdown table lines)."""
    cp = pr.CP
    ours = runs.predicted_diffusion(xi, bm.SOURCE_VISCOSITY)
    source = runs.predicted_diffusion(bm.source_resistance_tensor(), bm.SOURCE_VISCOSITY)
    row = {r['run']: r for r in rows}
    d_r = (row['explicit']['D_r (1/ns)']*1e-3, row['explicit']['D_r error']*1e-3)
    matching = lambda predicted, d: bm.SOURCE_VISCOSITY*100*predicted/d  # cP: D scales as 1/eta
    fmt = lambda value, error, digits: f'{value:.{digits}f} ± {error:.{digits}f}'
    columns = []
    for i, (key, form) in enumerate(solvent.items()):
        corrected = row[f'explicit, finite-size corrected ({pr.FORMS[key].split(" (")[0]})']
        d_t = (corrected['D_t (1e-5 cm^2/s)']/CM2_S, corrected['D_t error']/CM2_S)
        eta0 = (form['eta0']*cp, form['error']*cp)
        eta_t = (matching(ours[0], d_t[0]), matching(ours[0], d_t[0])*d_t[1]/d_t[0])
        eta_r = (matching(ours[1], d_r[0]), matching(ours[1], d_r[0])*d_r[1]/d_r[0])
        correction = finite_size_correction(form['eta0'], box)
        difference = jackknife_error(lambda t, r: matching(ours[1], r.mean())-matching(ours[0], t.mean()+correction), *explicit_replicas)
        over_t, over_r = ratio(*eta_t, *eta0), ratio(*eta_r, *eta0)
        columns.append([
            f'{fmt(*eta0, 4)}, {"accepted" if form["accepted"] else "rejected"} by its chi-squared',
            f'{fmt(correction*CM2_S, correction*CM2_S*form["error"]/form["eta0"], 3)}',
            fmt(d_t[0]*CM2_S, d_t[1]*CM2_S, 3), fmt(*eta_t, 4), fmt(*eta_r, 4), fmt(eta_r[0]-eta_t[0], difference, 4),
            fmt(*over_t, 3), fmt(*over_r, 3), fmt(1/over_t[0], over_t[1]/over_t[0]**2, 2), fmt(1/over_r[0], over_r[1]/over_r[0]**2, 2),
            fmt(d_t[0]/ours[0], d_t[1]/ours[0], 3), fmt(d_r[0]/ours[1], d_r[1]/ours[1], 3),
            fmt(*ratio(ps.EXPERIMENT_VISCOSITY, 0.0, *eta0), 3),
            fmt(d_t[0]/source[0], d_t[1]/source[0], 3), fmt(d_r[0]/source[1], d_r[1]/source[1], 3)])
    labels = ['the solvent model\'s eta_0 (cP)', 'finite-size correction of the explicit D_t (1e-5 cm^2/s)',
              'explicit D_t, finite-size corrected (1e-5 cm^2/s)', 'matching viscosity, translation (cP)',
              'matching viscosity, rotation (cP)', 'rotation\'s less translation\'s (cP; delete-one jackknife over the explicit replicas, '
              'whose D_t and D_r correlate)', 'matching viscosity over eta_0, translation', 'matching viscosity over eta_0, rotation',
              'the tensor at eta_0 predicts diffusion too slow by, translation', 'the same, rotation',
              'explicit diffusion over this project\'s tensor\'s at 0.289 cP, translation', 'the same, rotation',
              'of which 0.289 cP over eta_0 (the model pentane thinner than real pentane)',
              'explicit diffusion over the source\'s own tensor\'s at 0.289 cP, translation', 'the same, rotation']
    header = '| | '+' | '.join(f'eta_0 from {pr.FORMS[key]}' for key in solvent)+' |'
    lines = [header, '|---'*(1+len(solvent))+'|']
    lines += [f'| {label} | '+' | '.join(column[i] for column in columns)+' |' for i, label in enumerate(labels)]
    return lines, ours, source


def vacf_lines(stages):
    """The normalised velocity autocorrelations of the bananas' centres at VACF_LAGS, per run (mean ±
    standard error over replicas), and the smallest difference between the explicit and each
    implicit run over VACF_RANGE in their combined standard errors (markdown lines)."""
    means = {name: curves(stage, 'vacf') for name, stage in stages.items()}
    index = lambda t: int(round(t/runs.SAMPLE_PS))
    lines = ['| t (ps) | '+' | '.join(stages)+' |', '|---'*(1+len(stages))+'|']
    length = min(len(m) for m, _ in means.values())  # short runs (--quick) reach fewer lags
    for t in (t for t in VACF_LAGS if index(t) < length):
        lines.append(f'| {t:g} | '+' | '.join(f'{m[index(t)]:.4f} ± {e[index(t)]:.4f}' for m, e in means.values())+' |')
    window = slice(index(VACF_RANGE[0]), min(index(VACF_RANGE[1])+1, length))
    explicit_mean, explicit_error = (v[window] for v in means['explicit'])
    apart = []
    for name, (mean, error) in means.items():
        if name != 'explicit':
            z = np.abs(explicit_mean-mean[window])/np.hypot(explicit_error, error[window])
            apart.append(f'{name} {z.min():.1f}' if len(z) else f'{name}: no lags')
    last = (window.stop-1)*runs.SAMPLE_PS
    lines += ['', f'Smallest difference from the explicit curve at any lag from {VACF_RANGE[0]:g} to {last:g} ps, in combined '
              'standard errors: '+', '.join(apart)+'.']
    return lines


def banana_report(out, settings, xi, solvent, box_stage, explicit_stage, implicit_stages):
    """diffusion.md/.csv and correlations.csv/.png; solvent: the solvent's eta_0 by form
    (pentane_report.forms() of the rate taken)."""
    box = explicit_stage.inputs['box']
    scene = pr.scene_box_result(box_stage)
    rows, explicit_replicas = diffusion_rows(settings, explicit_stage, implicit_stages, solvent, box)
    with open(out/'diffusion.csv', 'w', newline='', encoding='utf-8') as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    answer, ours, source = answer_table(rows, explicit_replicas, solvent, box, xi)
    explicit_runs = [run for _, run in explicit_stage.runs()]
    temperatures = [float(np.mean(run['temperature'])) for run in explicit_runs]
    drifts = [np.polyfit(np.arange(len(run['energy']))*runs.COARSE_PS*1e-3, run['energy'], 1)[0]/(ps.PENTANES+2) for run in explicit_runs]
    (t_mean, t_err), (drift, drift_err) = mean_error(temperatures), mean_error(drifts)
    window = settings['window_ps']
    lines = ['# Bananas in explicit pentane against implicit solvent at 273.15 K', '',
             f'Replicas of each run are independent (their own starts and seeds); standard errors from their spread. Box {box:.4f} nm '
             f'(the scene\'s mean volume under a barostat, {scene["box"]:.4f} ± {scene["box_error"]:.4f} nm now).',
             f'Explicit runs: {settings["melt_ps"]:g} ps at 1 cP and {settings["equilibration_ps"]:g} ps at 0.01 cP under this integrator, then '
             f'{settings["production_ps"]:g} ps of NVE at the total energy of 273.15 K. Their mean temperature {t_mean:.2f} ± {t_err:.2f} K; '
             f'energy drift {drift:+.4f} ± {drift_err:.4f} kJ/mol/ns per molecule. D_t from the mean-square displacement of the '
             f'centres of diffusion and D_r, the tumbling of the middle ellipsoid\'s long axis u, from <u(0).u(t)> = exp(-2 D_r t), '
             f'both fitted over lags of {window[0]:g}-{window[1]:g} ps. The explicit D_t finite-size corrected (Yeh-Hummer) with the '
             f'solvent model\'s own viscosity, by each of its two extrapolations (pentane.md). '
             f'Runs by platform: {platform_counts([explicit_stage]+list(implicit_stages))}.', '',
             '| run | replicas | D_t (1e-5 cm^2/s) | D_r, tumbling of the middle axis (1/ns) | ns/day (median replica) |', '|---|---|---|---|---|']
    for row in rows:
        lines.append(f"| {row['run']} | {row['replicas']} | {row['D_t (1e-5 cm^2/s)']:.3f} ± {row['D_t error']:.3f} "
                     f"({100*row['D_t error']/row['D_t (1e-5 cm^2/s)']:.1f}%) | {row['D_r (1/ns)']:.3f} ± {row['D_r error']:.3f} "
                     f"({100*row['D_r error']/row['D_r (1/ns)']:.1f}%) | {row['ns/day']:.1f} |")
    lines += [f'| this project\'s tensor at 0.289 cP (exact, long time) | | {ours[0]*CM2_S:.3f} | {ours[1]*1e3:.3f} | |',
              f'| the source\'s own tensor at 0.289 cP (exact, long time; banana_model.source_resistance_tensor) | | '
              f'{source[0]*CM2_S:.3f} | {source[1]*1e3:.3f} | |', '', target_errors(rows), '',
              'Explicit replicas one by one (D_t of the periodic box, uncorrected):', '',
              '| replica | seed | mean temperature (K) | energy drift (kJ/mol/ns per molecule) | D_t (1e-5 cm^2/s) | D_r (1/ns) |',
              '|---|---|---|---|---|---|']
    lines += [f'| {index} | {int(run["seed"])} | {temperature:.2f} | {d:+.4f} | {t*CM2_S:.3f} | {r*1e3:.3f} |'
              for (index, run), temperature, d, t, r in zip(explicit_stage.runs(), temperatures, drifts, *explicit_replicas)]
    d_t_box, d_t_box_err = mean_error(explicit_replicas[0])
    uncorrected = bm.SOURCE_VISCOSITY*100*ours[0]/d_t_box
    lines += ['', 'The viscosity at which the implicit model reproduces the explicit diffusion (the matching viscosity: D scales as '
              f'1/eta), by the solvent\'s eta_0 of each form (from the periodic box\'s D_t without the correction: '
              f'{uncorrected:.4f} ± {uncorrected*d_t_box_err/d_t_box:.4f} cP):', '', *answer, '',
              'Velocity autocorrelation of the bananas\' centres of mass, normalised (explicit against implicit at 0.289 cP):', '',
              *vacf_lines(dict([('explicit', explicit_stage)]+list(zip(runs.IMPLICIT_SCHEMES, implicit_stages)))), '']
    (out/'diffusion.md').write_text('\n'.join(lines), encoding='utf-8')
    correlations_report(out, explicit_stage, implicit_stages)


def correlations_report(out, explicit_stage, implicit_stages):
    """correlations.csv and correlations.png: the velocity and orientational autocorrelations."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    with open(out/'correlations.csv', 'w', newline='', encoding='utf-8') as f:
        writer = csv.writer(f)
        writer.writerow(['run', 'quantity', 't (ps)', 'mean', 'standard error'])
        for name, stage in [('explicit', explicit_stage)]+list(zip(runs.IMPLICIT_SCHEMES, implicit_stages)):
            for key, axes, dt in (('vacf', left, runs.SAMPLE_PS), ('cu', right, runs.COARSE_PS)):
                mean, error = curves(stage, key)
                t = np.arange(len(mean))*dt
                axes.plot(t, mean, label=name)
                axes.fill_between(t, mean-error, mean+error, alpha=0.3)
                writer.writerows([name, key, f'{ti:.3f}', f'{m:.6g}', f'{e:.3g}'] for ti, m, e in zip(t, mean, error))
    left.set_xlim(0, runs.VACF_PS)
    left.set_xlabel('t (ps)')
    left.set_title('VACF of the centres of mass (normalised)')
    right.set_xlabel('t (ps)')
    right.set_yscale('log')
    right.set_title('<u(0).u(t)>, middle ellipsoid\'s axis')
    left.legend()
    fig.tight_layout()
    fig.savefig(out/'correlations.png', dpi=120)
    plt.close(fig)
