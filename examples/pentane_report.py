"""The banana scene's solvent report: pentane.md and density_trace.png from the study folder's
density and viscosity runs (banana_scene.py's stages), and the results the banana report builds on.

The viscosity at k = 0 is given by both common extrapolations of eta(k) (pentane_solvent: eta
linear in k^2, and 1/eta linear as GROMACS's gmx tcaf prescribes), each with its chi-squared's
verdict: the forms differ by more than the error of either, and which one is right the three
harmonics cannot say beyond those verdicts, so the banana report carries both.
"""
import math

import numpy as np

import banana_model as bm
import pentane_solvent as ps

CP = ps.AMU_PER_NM_PS_IN_CP
# The two forms of the extrapolation to k = 0, as the reports name them (pentane_solvent.extrapolations_by_shear_rate).
FORMS = {'eta': 'eta linear in k^2', 'inverse': '1/eta linear in k^2 (GROMACS\'s gmx tcaf)'}


def combine(means, errors):
    """Inverse-variance weighted mean of independent estimates, its standard error, and the
    chi-squared of their scatter about it (about n - 1 if the errors are right)."""
    means, errors = np.asarray(means, dtype=float), np.asarray(errors, dtype=float)
    weights = 1/errors**2
    mean = float(np.sum(weights*means)/np.sum(weights))
    return mean, float(1/math.sqrt(np.sum(weights))), float(np.sum(((means-mean)/errors)**2))


def density_result(stage):
    """The neat solvent's density (g/mL) from every density run: each run's settled mean volume,
    combined. Returns {'density', 'error', 'volume', 'volume_error', 'runs': [settled_mean of each]}."""
    settled = [ps.settled_mean(run['volume']) for _, run in stage.runs()]
    volume, volume_error, chi2 = combine([r['mean'] for r in settled], [r['error'] for r in settled])
    density = ps.density_from_volume(volume)
    return {'density': density, 'error': density*volume_error/volume, 'volume': volume, 'volume_error': volume_error,
            'chi2': chi2, 'runs': settled}


def scene_box_result(stage):
    settled = [ps.settled_mean(run['volume']) for _, run in stage.runs()]
    volume, error, chi2 = combine([r['mean'] for r in settled], [r['error'] for r in settled])
    return {'box': volume**(1/3), 'box_error': volume**(1/3)*error/(3*volume), 'volume': volume, 'volume_error': error, 'chi2': chi2}


def viscosity_result(stage):
    """eta (amu/(nm ps)) of one harmonic and flow speed, combined over its runs, with the
    temperature of the motion less the flow."""
    etas, errors, temperatures = [], [], []
    for _, run in stage.runs():
        flow = ps.settled_mean(run['V'])
        eta, error = ps.viscosity_from_flow(float(run['amplitude']), float(run['density']), float(run['wavenumber']), flow['mean'], flow['error'])
        etas.append(eta)
        errors.append(error)
        temperatures.append(float(np.mean(run['temperature'])))
        k = float(run['wavenumber'])
    eta, error, chi2 = combine(etas, errors)
    return {'eta': eta, 'error': error, 'wavenumber': k, 'temperature': float(np.mean(temperatures)), 'runs': len(etas), 'chi2': chi2,
            'harmonic': stage.definition['harmonic'], 'speed': stage.definition['speed'], 'run_etas': etas}


def forms(fit):
    """One shear rate's extrapolations by form: {'eta': {eta0, error, slope, slope_error, chi2,
    probability, accepted}, 'inverse': the same} (amu/(nm ps); the slopes in their own units)."""
    return {'eta': {k: v for k, v in fit.items() if k not in ('inverse', 'fitted')}, 'inverse': fit['inverse']}


def verdict(form, dof):
    if dof < 1:
        return 'not tested (no degree of freedom)'
    return f'{"accepted" if form["accepted"] else "rejected"} (probability {form["probability"]:.2f})'


def solvent_report(out, settings, density_stage, viscosity_stages, viscosities):
    """pentane.md and density_trace.png from the density runs and the viscosity stages with runs
    (viscosities: their viscosity_result()); returns the model's viscosity at k = 0 by each form
    at the rate taken (forms())."""
    density = density_result(density_stage)
    fits = ps.extrapolations_by_shear_rate(viscosities)
    rate = ps.newtonian_rate(fits)
    taken = forms(fits[rate])
    dof = len(fits[rate]['fitted'])-2
    box = viscosity_stages[0].inputs['box']
    deviation = density['density']/ps.EXPERIMENT_DENSITY-1
    lines = ['# The pentane model at 273.15 K and 1 bar', '',
             f'TraPPE-UA (Martin & Siepmann 1998; harmonic bonds, see banana_model.py), {ps.PENTANES} molecules, Lennard-Jones cut at '
             f'{bm.CUTOFF} nm with the analytic tail correction (TraPPE\'s own treatment).', '',
             '| | this model | experiment |', '|---|---|---|',
             f'| density (g/mL), NPT at 1 bar | {density["density"]:.4f} ± {density["error"]:.4f} ({100*density["error"]/density["density"]:.2f}%) | '
             f'{ps.EXPERIMENT_DENSITY} (model {100*deviation:+.2f}%) |']
    for key, form in taken.items():
        lines.append(f'| shear viscosity (cP), periodic perturbation extrapolated to k = 0, {FORMS[key]} | {form["eta0"]*CP:.4f} ± '
                     f'{form["error"]*CP:.4f} ({100*form["error"]/form["eta0"]:.1f}%), its chi-squared {form["chi2"]:.2f} for {dof} '
                     f'degree(s) of freedom: {verdict(form, dof)} | {ps.EXPERIMENT_VISCOSITY} '
                     f'(model {100*(form["eta0"]*CP/ps.EXPERIMENT_VISCOSITY-1):+.0f}%) |')
    lines += ['', density_text(settings, density), '']
    lines += viscosity_text(settings, viscosity_stages, viscosities, fits, rate, box)
    spread = taken['inverse']['eta0']-taken['eta']['eta0']
    lines += ['', f'At the rate taken the two forms\' eta_0 differ by {spread*CP:+.4f} cP ({100*spread/taken["eta"]["eta0"]:+.1f}%), '
              'more than either\'s standard error; the chi-squared verdicts above are all the three harmonics say about which form is '
              'right, so the banana report (diffusion.md) carries both.', '',
              'Published: no TraPPE-UA shear viscosity of n-pentane near 273 K was found in the sources reachable when this was '
              'written. Dysthe, Fuchs & Rousseau (J. Chem. Phys. 112, 7581 (2000)), comparing seven united-atom alkane models, '
              'found their viscosities underestimated the more the denser and colder the liquid (by up to 80%), the sign of '
              'this model\'s '+' and '.join(f'{100*(form["eta0"]*CP/ps.EXPERIMENT_VISCOSITY-1):+.0f}% ({FORMS[key].split(" (")[0]})'
                                            for key, form in taken.items())+'.', '']
    (out/'pentane.md').write_text('\n'.join(lines), encoding='utf-8')
    density_plot(out, density_stage, density, viscosities, fits, box)
    return taken


def density_text(settings, density):
    lines = [f'Density: {len(density["runs"])} NPT run(s) of {settings["density_ps"]:g} ps from a lattice at the experimental density '
             f'(LangevinMiddleIntegrator 1/ps, Monte Carlo barostat); each run\'s start before it settled is dropped (Chodera\'s '
             'equilibration detection), its error from the statistical inefficiency of the rest; runs combined by inverse variance '
             f'(chi-squared {density["chi2"]:.2f} for {len(density["runs"])-1} degree(s) of freedom).', '',
             '| run | settled after (ps) | statistical inefficiency (samples of 0.1 ps) | density (g/mL) |', '|---|---|---|---|']
    for i, r in enumerate(density['runs']):
        d = ps.density_from_volume(r['mean'])
        lines.append(f'| {i} | {r["start"]*0.1:.1f} | {r["inefficiency"]:.1f} | {d:.4f} ± {d*r["error"]/r["mean"]:.4f} |')
    return '\n'.join(lines)


def viscosity_text(settings, viscosity_stages, viscosities, fits, rate, box):
    lines = [f'Viscosity: velocity Verlet with a periodic acceleration A cos(kz) along x and stochastic velocity rescaling of the '
             f'motion less the flow (pentane_solvent.py), at the density above as it was when the viscosity runs began '
             f'({viscosity_stages[0].inputs["density"]:.4f} g/mL, box {viscosity_stages[0].inputs["box"]:.4f} nm); '
             f'{settings["viscosity_ps"]:g} ps per run after {settings["build_up_ps"]:g} ps of build-up.', '',
             '| harmonic n | k (1/nm) | flow speed (nm/ps) | runs | temperature less the flow (K) | eta (cP) '
             '| each run (cP; chi-squared of their scatter) |',
             '|---|---|---|---|---|---|---|']
    for v in viscosities:
        each = ', '.join(f'{eta*CP:.4f}' for eta in v['run_etas'])+(f' ({v["chi2"]:.2f} for {v["runs"]-1})' if v['runs'] > 1 else '')
        lines.append(f'| {v["harmonic"]} | {v["wavenumber"]:.4f} | {v["speed"]:.4f} | {v["runs"]} | {v["temperature"]:.2f} | '
                     f'{v["eta"]*CP:.4f} ± {v["error"]*CP:.4f} | {each} |')
    lines += ['', 'Extrapolations to k = 0, one per shear rate (the harmonics of one series share k V), in both common forms: '
              'eta(k) = eta_0 + c k^2, and 1/eta(k) = 1/eta_0 + a k^2 (GROMACS\'s gmx tcaf: eta(k) = eta_0 (1 - a eta(k) k^2)); '
              'the rate taken is the lowest with three harmonics (the least shear thinning; pentane_solvent.newtonian_rate). '
              'A form is rejected where a chi-squared as large as its own would come by chance less than 5% of the time '
              '(pentane_solvent.fit_accepted).', '',
              '| shear rate k V (1/ps) | harmonics | form | eta_0 (cP) | slope: c (cP nm^2) or a (1/(cP nm^2)) '
              '| chi-squared (degrees of freedom) | verdict |',
              '|---|---|---|---|---|---|---|']
    for r, fit in fits.items():
        dof = len(fit['fitted'])-2
        for key, form in forms(fit).items():
            unit = CP if key == 'eta' else 1/CP
            lines.append(f'| {r*2*math.pi/box:.3f}{" (taken)" if r == rate else ""} | {", ".join(str(v["harmonic"]) for v in fit["fitted"])} | '
                         f'{FORMS[key]} | {form["eta0"]*CP:.4f} ± {form["error"]*CP:.4f} | '
                         f'{form["slope"]*unit:.5g} ± {form["slope_error"]*unit:.2g} | '
                         f'{form["chi2"]:.2f} ({dof}) | {verdict(form, dof)} |')
    taken = forms(fits[rate])
    for r in fits:
        if r != rate:  # another rate's runs are independent of the taken one's
            other = forms(fits[r])
            lines += ['', f'eta_0 at k V = {rate*2*math.pi/box:.3f}/ps less eta_0 at {r*2*math.pi/box:.3f}/ps (shear thinning shows as a '
                      'positive difference): '+'; '.join(
                          f'{FORMS[key].split(" (")[0]} {(taken[key]["eta0"]-other[key]["eta0"])*CP:+.4f} ± '
                          f'{math.hypot(taken[key]["error"], other[key]["error"])*CP:.4f} cP '
                          f'({abs(taken[key]["eta0"]-other[key]["eta0"])/math.hypot(taken[key]["error"], other[key]["error"]):.1f} standard errors)'
                          for key in taken)+'.']
    return lines


def density_plot(out, density_stage, density, viscosities, fits, box):
    """density_trace.png: the NPT runs' density traces, and eta(k^2) with both forms' lines."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    for i, (_, run) in enumerate(density_stage.runs()):
        t = (np.arange(len(run['volume']))+1)*0.1
        left.plot(t, ps.density_from_volume(run['volume']), lw=0.6, label=f'run {i}')
        r = density['runs'][i]
        left.axvline(r['start']*0.1, color=left.lines[-1].get_color(), ls=':', lw=1)
    left.axhspan(density['density']-density['error'], density['density']+density['error'], color='k', alpha=0.3, label='settled mean ± SE')
    left.axhline(ps.EXPERIMENT_DENSITY, color='r', ls='--', label='experiment')
    left.set_xlabel('t (ps)')
    left.set_ylabel('density (g/mL)')
    left.set_title('pentane NPT, 273.15 K, 1 bar (dotted: settled from)')
    left.legend(fontsize=8)
    grid = np.linspace(0, max(v['wavenumber'] for v in viscosities)**2*1.05, 50)
    for r, fit in fits.items():
        group = fit['fitted']
        points = right.errorbar([v['wavenumber']**2 for v in group], [v['eta']*CP for v in group], yerr=[v['error']*CP for v in group],
                                fmt='o', capsize=3)
        color = points[0].get_color()
        inverse = fit['inverse']
        right.plot(grid, (fit['eta0']+fit['slope']*grid)*CP, '-', lw=1, color=color,
                   label=f'k V = {r*2*math.pi/box:.3f}/ps, eta linear: {fit["eta0"]*CP:.4f} ± {fit["error"]*CP:.4f} cP')
        right.plot(grid, CP/(1/inverse['eta0']+inverse['slope']*grid), '--', lw=1, color=color,
                   label=f'k V = {r*2*math.pi/box:.3f}/ps, 1/eta linear: {inverse["eta0"]*CP:.4f} ± {inverse["error"]*CP:.4f} cP')
    for v in viscosities:
        right.annotate(f'n={v["harmonic"]}, V={v["speed"]:.3f}', (v['wavenumber']**2, v['eta']*CP), fontsize=7, xytext=(4, 4),
                       textcoords='offset points')
    right.axhline(ps.EXPERIMENT_VISCOSITY, color='r', ls=':', label='experiment')
    right.set_xlabel('k^2 (1/nm^2)')
    right.set_ylabel('eta (cP)')
    right.set_title('periodic perturbation')
    right.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out/'density_trace.png', dpi=120)
    plt.close(fig)
