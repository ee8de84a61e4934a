"""The source's second scene: two banana-shaped molecules in explicit pentane against the two alone
in implicit solvent, and the viscosity at which they agree.

Sun, Lin & Gezelter (J. Chem. Phys. 128, 234107 (2008), section IV B) ran two bananas (three
Gay-Berne ellipsoids rigidly joined) among 256 pentanes at 273 K in NVE, and the two bananas alone
under their Langevin integrator at the experimental viscosity of pentane, 0.289 cP, with the
resistance tensor of a rough shell of 2266 beads; they compared the velocity autocorrelation of
the bananas' centres and the orientational autocorrelation of the middle ellipsoid's axis. This
study does the same with the model of banana_model.py (320 pentanes: see PENTANES) and answers what
the source could not: at which viscosity the implicit model reproduces the explicit diffusion,
translational and rotational, and how far that is from the solvent model's own viscosity.

Stages, each a folder of runs under OUT/runs/ (study_folder.py: a run is kept as soon as it ends,
runs are appended to what is on disk, and a folder made with another model or other settings is
refused):
  density            the neat solvent under a barostat (pentane_solvent.npt_run)
  viscosity_n*_v*    periodic perturbation at harmonic n of the box and flow speed v (nm/ps),
                     at the mean density of the density runs when this stage began
  scene_box          the scene (bananas held rigid by constraints) under a barostat: its box edge
  explicit           two bananas among the pentanes: thermostatted equilibration, then NVE
  ExactFlow, BAOAB, LangevinMiddle
                     the two bananas alone at 0.289 cP (this integrator's two schemes with the
                     tensor; OpenMM's integrator per particle, rigid through constraints)
Then it writes, to OUT: tensor.md (the tensor beside the source's), pentane.md and
density_trace.png and viscosity.png (the solvent model against experiment), diffusion.md/.csv (D_t,
D_r, the matching viscosities, the explicit runs' temperature and energy drift) and
correlations.csv/.png (velocity and orientational autocorrelations, explicit against implicit).

    python examples/banana_scene.py --quick                    # every stage, short: minutes (tested)
    python examples/banana_scene.py                            # the full study, into examples/results/banana_scene:
                                                               # runs only what is not on disk yet
    python examples/banana_scene.py --stages explicit --add 4  # 4 more explicit replicas
    mpirun --allow-run-as-root --mca mpi_yield_when_idle 1 -np 2 .venv/bin/python examples/banana_scene.py --threads 1
        # runs spread over ranks; a rank left without a run waits without holding its core
    python examples/banana_scene.py --stages implicit --platform CUDA --part 0/4 --no-report &  # ... to --part 3/4:
        # the same without MPI (a GPU machine: scripts/gpu/run.sh banana); then --report-only
        # (the scene with pentanes runs on Reference and CPU only: banana_model.scene_context)

An explicit or implicit replica under way saves its progress (every --save-every seconds); a run
stopped carries on from there when the study is run again.

Standard errors: of a time series from its statistical inefficiency, of replicas from their
spread over sqrt(replicas).
"""
import argparse
import csv
import math
import pathlib
import sys
import time
import zlib

import numpy as np
import openmm.unit as unit

import rigidlangevin as rl
from rigidlangevin.ensemble import _communicator

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import banana_model as bm  # noqa: E402
import banana_runs as runs  # noqa: E402
import pentane_solvent as ps  # noqa: E402
from study_folder import StudyFolder, StudyMismatch, system_fingerprint  # noqa: E402

TEMPERATURE = ps.TEMPERATURE
CM2_S = 1e3  # nm^2/ps in 1e-5 cm^2/s
# The source's 256 pentanes make a box of about 3.7 nm, and this banana's particles span 1.9 nm,
# more than half of it (the integrator refuses a body wider than half the box: its particles'
# minimum images would not be one body). 320 pentanes make a box of about 4 nm.
PENTANES = ps.PENTANES
CANONICAL_BOX = 4.0  # nm: the box of the Systems whose fingerprints identify the model
IMPLICIT_SCHEMES = ('ExactFlow', 'BAOAB', 'LangevinMiddle')
# The relative standard errors of D_t and D_r the full study is to reach (the explicit one's D_t
# finite-size corrected); the report says which are reached and how many replicas the spread so
# far asks for.
TARGET_ERRORS = {'explicit': 0.05, 'implicit': 0.03}
# Flow speeds at harmonics 1, 2, 3 of the box, two series of equal shear rates k V (n V = 0.05 and
# 0.025 nm/ps): each series extrapolates to k = 0 on its own, and the lower rate's stands for the
# Newtonian viscosity (pentane_solvent.newtonian_rate), the two together showing shear thinning.
VISCOSITY_SERIES = ((1, 0.05), (1, 0.025), (2, 0.025), (3, 0.05/3), (2, 0.0125), (3, 0.025/3))

SETTINGS = {
    'quick': dict(density_runs=1, density_ps=10, viscosity_runs=1, viscosity_ps=5, build_up_ps=2, scene_box_runs=1, scene_box_ps=5,
                  replicas=2, melt_ps=1, equilibration_ps=4, production_ps=6, implicit_replicas=2, implicit_equilibration_ps=5,
                  implicit_ps=30, max_lag_ps=2.0, window_ps=(0.5, 2.0), max_beads=1000),
    'full': dict(density_runs=2, density_ps=1000, viscosity_runs=1, viscosity_ps=500, build_up_ps=20, scene_box_runs=1, scene_box_ps=400,
                 replicas=8, melt_ps=5, equilibration_ps=95, production_ps=500, implicit_replicas=8, implicit_equilibration_ps=50,
                 implicit_ps=5000, max_lag_ps=150.0, window_ps=(10.0, 50.0), max_beads=2000),
}
STAGE_SETTINGS = {  # the settings that define each kind of stage (beside its model)
    'density': ('density_ps',),
    'viscosity': ('viscosity_ps', 'build_up_ps'),
    'scene_box': ('scene_box_ps',),
    'explicit': ('melt_ps', 'equilibration_ps', 'production_ps', 'max_lag_ps', 'max_beads'),
    'implicit': ('implicit_equilibration_ps', 'implicit_ps', 'max_lag_ps', 'max_beads'),
}


def source_frame(matrix):
    """A 6x6 tensor turned from the banana's frame (x long, y bend, z normal) into the source's
    (z long, y bend, x normal: smallest translational and rotational resistance along z, the
    centre of resistance displaced along y): a turn by -90 degrees about y."""
    turn = np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]], dtype=float)
    t = np.zeros((6, 6))
    t[:3, :3] = t[3:, 3:] = turn
    return t@matrix@t.T, turn


def tensor_comparison(settings, out):
    """tensor.md: our tensor in the source's frame and units (amu/fs, amu A/fs, amu A^2/fs at 0.289 cP)."""
    start = time.time()
    xi = bm.resistance_tensor(settings['max_beads'])
    extrapolated_seconds = time.time()-start
    radius, count, shell = bm.source_size_shell()
    eta = bm.viscosity_md_units(bm.SOURCE_VISCOSITY)  # amu/(nm ps)
    # amu/(nm ps) x nm = amu/ps = 1e-3 amu/fs; x nm^2 (coupling) -> amu A/fs x 10; x nm^3 -> amu A^2/fs x 100.
    scale = np.ones((6, 6))*1e-3*eta
    scale[:3, 3:] *= 10
    scale[3:, :3] *= 10
    scale[3:, 3:] *= 100
    center = xi.getCenterOfResistance()
    ours, turn = source_frame(np.array(xi.getMatrix(center))*scale)
    shell_ours, _ = source_frame(np.array(shell.getMatrix(center))*scale)
    cor = turn@(np.array(center.value_in_unit(unit.nanometer))*10)  # A, relative to the centre of mass
    fmt = lambda m: '\n'.join('    '+' '.join(f'{v:9.4f}' for v in row) for row in m)
    eig = lambda m: np.linalg.eigvalsh(m)
    lines = ['# The banana\'s resistance tensor at 0.289 cP beside the source\'s', '',
             'Frame: the source\'s, as its numbers show it (smallest translational and rotational resistance along z, the long axis;',
             'the centre of resistance displaced along y, toward the bend; x normal to the banana\'s plane); origin at the centre of',
             'resistance. Units: amu/fs (translation), amu A/fs (coupling), amu A^2/fs (rotation), the units of the source\'s code',
             '(amu, A, fs), in which its translational block is what Stokes\'s law gives for an object of a few A at 0.289 cP.', '',
             f'This work, rough shells of the three ellipsoids extrapolated to zero bead size ({settings["max_beads"]} beads at the finest, '
             f'{extrapolated_seconds:.1f} s):', '', fmt(ours), '',
             f'Rough shell at the source\'s resolution ({count} beads of radius {radius*10:.3f} A; the source: {bm.SOURCE_SHELL_BEADS} beads '
             f'of size 0.3 A):', '', fmt(shell_ours), '', 'The source:', '', fmt(bm.SOURCE_TENSOR), '',
             '| | this work (extrapolated) | this work (2266-bead shell) | source |', '|---|---|---|---|',
             f'| centre of resistance from the centre of mass (A) | {np.array2string(cor, precision=4)} | | {bm.SOURCE_CENTER_OF_RESISTANCE} |',
             f'| translational eigenvalues (amu/fs) | {np.array2string(eig(ours[:3, :3]), precision=4)} | '
             f'{np.array2string(eig(shell_ours[:3, :3]), precision=4)} | {np.array2string(eig(bm.SOURCE_TENSOR[:3, :3]), precision=4)} |',
             f'| rotational eigenvalues (amu A^2/fs) | {np.array2string(eig(ours[3:, 3:]), precision=2)} | '
             f'{np.array2string(eig(shell_ours[3:, 3:]), precision=2)} | {np.array2string(eig(bm.SOURCE_TENSOR[3:, 3:]), precision=2)} |', '']
    single = np.array(rl.hydrodynamics.spheroid(bm.GB_LENGTH/2, bm.GB_BREADTH/2).getMatrix())*scale
    lines += [f'One of the banana\'s ellipsoids alone (Perrin): translation {np.array2string(np.diag(single)[:3], precision=4)} amu/fs, '
              f'rotation {np.array2string(np.diag(single)[3:], precision=2)} amu A^2/fs. The source\'s translational block is that of one '
              'ellipsoid to 3%, while its rotational block is 3-4 times one ellipsoid\'s: no rigid union of these ellipsoids has both, '
              'so the source\'s tensor is not reproducible from its description; the ratio of its smallest to largest rotational '
              'resistance (0.18) is what set our bend.', '']
    (out/'tensor.md').write_text('\n'.join(lines))
    return xi


# --- Stages -----------------------------------------------------------------------------------


def definition(kind, settings, model, **extra):
    """What makes a stage's runs comparable: its model's fingerprint, the temperature, the settings
    of its kind, and extra."""
    d = {'model': model, 'temperature': TEMPERATURE, 'pentanes': PENTANES}
    d.update({k: settings[k] for k in STAGE_SETTINGS[kind]})
    d.update(extra)
    return d


def neat_model():
    return system_fingerprint(ps.pentane_system(CANONICAL_BOX, 1)[0])


def scene_model(**kwargs):
    return system_fingerprint(bm.pentane_box(kwargs.pop('pentanes', PENTANES), CANONICAL_BOX, 1, bananas=2, **kwargs)[0])


def tensor_fingerprint(xi):
    return [round(float(v), 9) for v in np.array(xi.getMatrix()).ravel()]


def viscosity_stage_name(harmonic, speed):
    return f'viscosity_n{harmonic}_v{speed:.4f}'


class Study:
    """The stages of one study folder, their runs spread over MPI ranks, or over processes started
    apart with --part I/K (each takes the runs rank I of K would)."""

    def __init__(self, args, settings, xi, requested):
        self.args, self.settings, self.xi, self.requested = args, settings, xi, requested
        self.folder = StudyFolder(args.out)
        self.comm = _communicator()
        self.rank, self.size = (self.comm.Get_rank(), self.comm.Get_size()) if self.comm is not None else args.part
        self.properties = {'Threads': str(args.threads)} if args.threads and args.platform == 'CPU' else {}
        center = np.array(xi.getCenterOfDiffusion().value_in_unit(unit.nanometer))
        self.weights = runs.center_weights(center)

    def barrier(self):
        if self.comm is not None:
            self.comm.Barrier()

    def open(self, name, kind, model, inputs, **extra):
        """The stage on disk; or, if there is none and this stage is to run, a new one started
        with inputs() (evaluated on rank 0, shared with the others; by every process started apart,
        alike); else None."""
        d = definition(kind, self.settings, model, **extra)
        exists = self.folder.has(name)
        if self.comm is not None:
            exists = self.comm.bcast(exists, root=0)  # rank 0 may start it before another rank looks
        if exists:
            return self.folder.stage(name, d)
        if not self.wanted(kind):
            return None
        if self.rank == 0 or self.comm is None:
            self.folder.stage(name, d, inputs())
        self.barrier()
        return self.folder.stage(name, d)

    def run(self, stage, total, label, work):
        return self.run_all([(stage, total, label, work)])[0]

    def run_all(self, jobs):
        """For each (stage, total, label, work): the runs of stage up to total, plus --add more;
        work(index, seed, progress) returns a run's arrays (progress: the run's RunProgress, where
        work that can carry on a run cut short keeps it). All the jobs' runs are dealt out to the ranks
        together, in turn; processes started apart (--part), which share no moment at which they
        all look at the disk, take each run by its stage and index alone. Only stages asked for
        run. Returns the stages."""
        todo = []
        for stage, total, label, work in jobs:
            if stage is None or not self.wanted(self.kind(stage.name)):
                continue
            indices = stage.missing(total)
            if self.args.add:
                indices += [i for i in stage.next_indices(self.args.add+len(indices)) if i not in indices][:self.args.add]
            if self.rank == 0 and indices:
                print(f'{label}: {len(indices)} run(s) to do ({self.size} rank(s))', flush=True)
            todo += [(stage, index, label, work) for index in indices]
        if self.comm is None:
            todo = [job for job in todo if (zlib.crc32(job[0].name.encode())+job[1]) % self.size == self.rank]
        else:
            todo = todo[self.rank::self.size]
        for stage, index, label, work in todo:
            seed = self.seed_base(stage.name)+index
            start = time.time()
            arrays = work(index, seed, stage.progress(index, seed))
            stage.save(index, seed=seed, wall_seconds=time.time()-start, platform=self.args.platform, **arrays)
            print(f'  {label}: run {index} (seed {seed}) done in {time.time()-start:.0f} s', flush=True)
        self.barrier()
        return [job[0] for job in jobs]

    def wanted(self, kind):
        return kind in self.requested

    @staticmethod
    def kind(name):
        return 'viscosity' if name.startswith('viscosity') else 'implicit' if name in IMPLICIT_SCHEMES else name

    @staticmethod
    def seed_base(name):
        """Each stage its own seeds, fixed by its name: run i has seed_base + i."""
        return 1+1000*(zlib.crc32(name.encode()) % 100000)

    # The stages, in order.

    def density(self):
        s = self.settings
        stage = self.open('density', 'density', neat_model(), lambda: {}, **ps.NPT_SETTINGS)

        def work(index, seed, _progress):
            volumes, state = ps.npt_run(s['density_ps'], seed, self.args.platform, self.properties)
            return {'volume': volumes, 'positions': state.getPositions(asNumpy=True).value_in_unit(unit.nanometer),
                    'velocities': state.getVelocities(asNumpy=True).value_in_unit(unit.nanometer/unit.picosecond),
                    'box': np.array(state.getPeriodicBoxVectors().value_in_unit(unit.nanometer))}
        return self.run(stage, s['density_runs'], 'pentane NPT', work)

    def viscosity(self, density_stage):
        s = self.settings
        jobs = []
        for harmonic, speed in VISCOSITY_SERIES:
            def inputs():
                result = density_result(require(density_stage, 'density', 'the viscosity runs'))
                return {'box': ps.box_edge(result['density']), 'density': result['density']}
            stage = self.open(viscosity_stage_name(harmonic, speed), 'viscosity', neat_model(), inputs, harmonic=harmonic, speed=speed,
                              **ps.FLOW_SETTINGS)

            def work(index, seed, _progress, harmonic=harmonic, speed=speed, box=stage and stage.inputs['box']):
                starts = require(density_stage, 'density', 'the viscosity runs').indices()
                start = density_stage.load(starts[index % len(starts)])
                return ps.flow_run(scaled_positions(start, box), start['velocities'], box, harmonic, speed, s['viscosity_ps'], seed,
                                   self.args.platform, self.properties, build_up_ps=s['build_up_ps'])
            jobs.append((stage, s['viscosity_runs'], f'viscosity n={harmonic} v={speed:.4f}', work))
        return self.run_all(jobs)

    def scene_box(self):
        s = self.settings
        stage = self.open('scene_box', 'scene_box', scene_model(constrained=True), lambda: {}, **ps.NPT_SETTINGS)
        return self.run(stage, s['scene_box_runs'], 'scene NPT',
                        lambda index, seed, _progress: {'volume': runs.scene_box_run(PENTANES, s['scene_box_ps'], seed, self.args.platform, self.properties)})

    def explicit(self, box_stage):
        s = dict(self.settings, pentanes=PENTANES)
        stage = self.open('explicit', 'explicit', scene_model(),
                          lambda: {'box': scene_box_result(require(box_stage, 'scene_box', 'the explicit runs'))['box']},
                          **runs.EXPLICIT_SETTINGS, tensor=tensor_fingerprint(self.xi))
        return self.run(stage, s['replicas'], 'explicit pentane', lambda index, seed, progress: runs.explicit_replica(
            s, stage.inputs['box'], self.xi, self.weights, seed, self.args.platform, self.properties, progress))

    def implicit(self, explicit_stage, box_stage):
        """The implicit runs in the explicit runs' box (the bananas meet each other as often), or
        the scene's if there are no explicit runs yet."""
        s = self.settings
        jobs = []
        for scheme in IMPLICIT_SCHEMES:
            model = scene_model(pentanes=0, constrained=scheme == 'LangevinMiddle')
            inputs = lambda: {'box': explicit_stage.inputs['box'] if explicit_stage is not None else
                              scene_box_result(require(box_stage, 'scene_box', 'the implicit runs'))['box']}
            stage = self.open(scheme, 'implicit', model, inputs, scheme=scheme, viscosity=bm.SOURCE_VISCOSITY, tensor=tensor_fingerprint(self.xi),
                              step=runs.IMPLICIT_STEP, sample_ps=runs.SAMPLE_PS)
            jobs.append((stage, s['implicit_replicas'], f'implicit {scheme}',
                         lambda index, seed, progress, scheme=scheme, stage=stage: runs.implicit_replica(
                             s, stage.inputs['box'], self.xi, self.weights, scheme, bm.SOURCE_VISCOSITY, seed, self.args.platform,
                             {'Threads': '1'} if self.args.platform == 'CPU' else {}, progress)))
        return self.run_all(jobs)


class MissingRuns(Exception):
    """A stage needs the runs of an earlier one, and there are none."""


def require(stage, name, needed_by):
    if stage is None or not stage.indices():
        raise MissingRuns(f'{needed_by} need the {name} stage\'s runs first: run --stages {name}')
    return stage


def scaled_positions(run, box):
    """A density run's final positions (nm) in a cubic box of edge box (nm): each pentane moved
    with its centre (as the barostat moves molecules), its shape kept."""
    molecules = run['positions'].reshape(-1, 5, 3)
    centers = molecules.mean(axis=1, keepdims=True)
    return (molecules+centers*(box/run['box'][0][0]-1)).reshape(-1, 3)


# --- Results ----------------------------------------------------------------------------------


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
            'harmonic': stage.definition['harmonic'], 'speed': stage.definition['speed']}


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


def has_runs(*stages):
    return all(stage is not None and stage.indices() for stage in stages)


def write_report(out, settings, xi, density_stage, viscosity_stages, box_stage, explicit_stage, implicit_stages):
    """Every table and plot that the runs on disk allow; returns the names of the tables written."""
    import matplotlib
    matplotlib.use('Agg')
    written = ['tensor.md']
    measured = [stage for stage in viscosity_stages if has_runs(stage)]
    viscosities = [viscosity_result(stage) for stage in measured]
    if not has_runs(density_stage) or not ps.extrapolations_by_shear_rate(viscosities):
        return written
    eta0, eta0_error = solvent_report(out, settings, density_stage, measured, viscosities)
    written.append('pentane.md')
    if has_runs(box_stage, explicit_stage, *implicit_stages):
        banana_report(out, settings, xi, eta0, eta0_error, box_stage, explicit_stage, implicit_stages)
        written.append('diffusion.md')
    return written


def solvent_report(out, settings, density_stage, viscosity_stages, viscosities):
    """pentane.md and density_trace.png from the density runs and the viscosity stages with runs
    (viscosities: their viscosity_result()); returns the model's viscosity at k = 0 and its error
    (amu/(nm ps))."""
    import matplotlib.pyplot as plt
    density = density_result(density_stage)
    fits = ps.extrapolations_by_shear_rate(viscosities)
    rate = ps.newtonian_rate(fits)
    eta0, eta0_error = fits[rate]['eta0'], fits[rate]['error']
    box = viscosity_stages[0].inputs['box']
    cp = ps.AMU_PER_NM_PS_IN_CP
    deviation = density['density']/ps.EXPERIMENT_DENSITY-1
    lines = ['# The pentane model at 273.15 K and 1 bar', '',
             f'TraPPE-UA (Martin & Siepmann 1998; harmonic bonds, see banana_model.py), {PENTANES} molecules, Lennard-Jones cut at '
             f'{bm.CUTOFF} nm with the analytic tail correction (TraPPE\'s own treatment).', '',
             '| | this model | experiment |', '|---|---|---|',
             f'| density (g/mL), NPT at 1 bar | {density["density"]:.4f} ± {density["error"]:.4f} ({100*density["error"]/density["density"]:.2f}%) | '
             f'{ps.EXPERIMENT_DENSITY} (model {100*deviation:+.2f}%) |',
             f'| shear viscosity (cP), periodic perturbation extrapolated to k = 0 | {eta0*cp:.3f} ± {eta0_error*cp:.3f} '
             f'({100*eta0_error/eta0:.1f}%) | {ps.EXPERIMENT_VISCOSITY} |', '',
             f'Density: {len(density["runs"])} NPT run(s) of {settings["density_ps"]:g} ps from a lattice at the experimental density '
             f'(LangevinMiddleIntegrator 1/ps, Monte Carlo barostat); each run\'s start before it settled is dropped (Chodera\'s '
             'equilibration detection), its error from the statistical inefficiency of the rest; runs combined by inverse variance '
             f'(chi-squared {density["chi2"]:.2f} for {len(density["runs"])-1} degree(s) of freedom).', '',
             '| run | settled after (ps) | statistical inefficiency (samples of 0.1 ps) | density (g/mL) |', '|---|---|---|---|']
    for i, r in enumerate(density['runs']):
        d = ps.density_from_volume(r['mean'])
        lines.append(f'| {i} | {r["start"]*0.1:.1f} | {r["inefficiency"]:.1f} | {d:.4f} ± {d*r["error"]/r["mean"]:.4f} |')
    lines += ['', f'Viscosity: velocity Verlet with a periodic acceleration A cos(kz) along x and stochastic velocity rescaling of the '
              f'motion less the flow (pentane_solvent.py), at the density above as it was when the viscosity runs began '
              f'({viscosity_stages[0].inputs["density"]:.4f} g/mL, box {viscosity_stages[0].inputs["box"]:.4f} nm); '
              f'{settings["viscosity_ps"]:g} ps per run after {settings["build_up_ps"]:g} ps of build-up.', '',
              '| harmonic n | k (1/nm) | flow speed (nm/ps) | runs | temperature less the flow (K) | eta (cP) |', '|---|---|---|---|---|---|']
    for v in viscosities:
        lines.append(f'| {v["harmonic"]} | {v["wavenumber"]:.4f} | {v["speed"]:.4f} | {v["runs"]} | {v["temperature"]:.2f} | '
                     f'{v["eta"]*cp:.4f} ± {v["error"]*cp:.4f} |')
    lines += ['', 'Extrapolations eta(k) = eta_0 + c k^2, one per shear rate (the harmonics of one series share k V); eta_0 above is '
              'the lowest rate\'s with three harmonics (the least shear thinning; pentane_solvent.newtonian_rate):', '',
              '| shear rate k V (1/ps) | harmonics | eta_0 (cP) | c (cP nm^2) | chi-squared (degrees of freedom) |', '|---|---|---|---|---|']
    for r, fit in fits.items():
        lines.append(f'| {r*2*math.pi/box:.3f}{" (taken)" if r == rate else ""} | {", ".join(str(v["harmonic"]) for v in fit["fitted"])} | '
                     f'{fit["eta0"]*cp:.4f} ± {fit["error"]*cp:.4f} | {fit["slope"]*cp:.5f} ± {fit["slope_error"]*cp:.5f} | '
                     f'{fit["chi2"]:.2f} ({len(fit["fitted"])-2}) |')
    lines += ['',
              'Published: no TraPPE-UA shear viscosity of n-pentane near 273 K was found in the sources reachable when this was '
              'written. Dysthe, Fuchs & Rousseau (J. Chem. Phys. 112, 7581 (2000)), comparing seven united-atom alkane models, '
              'found their viscosities underestimated the more the denser and colder the liquid (by up to 80%), the sign of '
              f'this model\'s {100*(eta0*cp/ps.EXPERIMENT_VISCOSITY-1):+.0f}%.', '']
    (out/'pentane.md').write_text('\n'.join(lines))

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
        points = right.errorbar([v['wavenumber']**2 for v in group], [v['eta']*cp for v in group], yerr=[v['error']*cp for v in group],
                                fmt='o', capsize=3)
        right.plot(grid, (fit['eta0']+fit['slope']*grid)*cp, '-', lw=1, color=points[0].get_color(),
                   label=f'k V = {r*2*math.pi/box:.3f}/ps: eta_0 = {fit["eta0"]*cp:.3f} ± {fit["error"]*cp:.3f} cP')
    for v in viscosities:
        right.annotate(f'n={v["harmonic"]}, V={v["speed"]:.3f}', (v['wavenumber']**2, v['eta']*cp), fontsize=7, xytext=(4, 4), textcoords='offset points')
    right.axhline(ps.EXPERIMENT_VISCOSITY, color='r', ls='--', label='experiment')
    right.set_xlabel('k^2 (1/nm^2)')
    right.set_ylabel('eta (cP)')
    right.set_title('periodic perturbation')
    right.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out/'density_trace.png', dpi=120)
    plt.close(fig)
    return eta0, eta0_error


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
                short.append(f'{row["run"].split(",")[0]} {quantity} {100*relative:.1f}% (about {needed} replicas at this spread)')
    reached = (f'Relative standard errors to reach: {100*TARGET_ERRORS["explicit"]:g}% explicit (D_t finite-size corrected), '
               f'{100*TARGET_ERRORS["implicit"]:g}% implicit. ')
    return reached+('Every one reached.' if not short else 'Not reached: '+'; '.join(short)+
                    '. More replicas: --stages explicit (or implicit) --add N.')


def banana_report(out, settings, xi, eta0, eta0_error, box_stage, explicit_stage, implicit_stages):
    """diffusion.md/.csv and correlations.csv/.png."""
    import matplotlib.pyplot as plt
    cp = ps.AMU_PER_NM_PS_IN_CP
    window = settings['window_ps']
    scene = scene_box_result(box_stage)
    box = explicit_stage.inputs['box']
    predicted_t, predicted_r = runs.predicted_diffusion(xi, bm.SOURCE_VISCOSITY)
    rows = []
    constants = {}
    for name, stage in [('explicit', explicit_stage)]+list(zip(IMPLICIT_SCHEMES, implicit_stages)):
        d_t, d_r = replica_constants(stage, window)
        if name == 'explicit':
            explicit_replicas = (d_t, d_r)
        constants[name] = (mean_error(d_t), mean_error(d_r))
        speed = [(settings['production_ps'] if name == 'explicit' else settings['implicit_ps'])*1e-3/float(run['seconds'])*86400
                 for _, run in stage.runs()]
        rows.append({'run': name, 'replicas': len(d_t), 'D_t (1e-5 cm^2/s)': constants[name][0][0]*CM2_S, 'D_t error': constants[name][0][1]*CM2_S,
                     'D_r (1/ns)': constants[name][1][0]*1e3, 'D_r error': constants[name][1][1]*1e3, 'ns/day': float(np.median(speed))})
    # The explicit bananas diffuse in a periodic box, which slows translation by
    # xi_EW kT/(6 pi eta L) (Yeh & Hummer, J. Phys. Chem. B 108, 15873 (2004)), eta the solvent
    # model's own viscosity; rotation's correction is of order the banana's volume over the box's.
    (d_t_box, d_t_box_err), (d_r, d_r_err) = constants['explicit']
    finite_size = 2.837297*ps.KT/(6*math.pi*eta0*box)  # nm^2/ps
    d_t = d_t_box+finite_size
    d_t_err = math.hypot(d_t_box_err, finite_size*eta0_error/eta0)
    rows.insert(1, dict(rows[0], run='explicit, finite-size corrected', **{'D_t (1e-5 cm^2/s)': d_t*CM2_S, 'D_t error': d_t_err*CM2_S}))
    with open(out/'diffusion.csv', 'w', newline='') as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    # Long-time diffusion under this integrator is kT (eta Xi)^-1 whatever the mass, so D scales as
    # 1/eta: the viscosity at which the implicit model diffuses as the explicit bananas do.
    def matching_viscosity(predicted, measured):  # cP
        return bm.SOURCE_VISCOSITY*predicted/measured*100
    eta_t, eta_r = matching_viscosity(predicted_t, d_t), matching_viscosity(predicted_r, d_r)

    def rotation_less_translation(d_t_box, d_r):  # cP, from the explicit replicas' constants
        return matching_viscosity(predicted_r, d_r.mean())-matching_viscosity(predicted_t, d_t_box.mean()+finite_size)
    explicit_runs = [run for _, run in explicit_stage.runs()]
    temperatures = [float(np.mean(run['temperature'])) for run in explicit_runs]
    t_mean, t_err = mean_error(temperatures)
    drifts = [np.polyfit(np.arange(len(run['energy']))*runs.COARSE_PS*1e-3, run['energy'], 1)[0]/(PENTANES+2) for run in explicit_runs]
    drift, drift_err = mean_error(drifts)
    lines = ['# Bananas in explicit pentane against implicit solvent at 273.15 K', '',
             f'Replicas of each run are independent (their own starts and seeds); standard errors from their spread. Box {box:.4f} nm '
             f'(the scene\'s mean volume under a barostat, {scene["box"]:.4f} ± {scene["box_error"]:.4f} nm now).',
             f'Explicit runs: {settings["melt_ps"]:g} ps at 1 cP and {settings["equilibration_ps"]:g} ps at 0.01 cP under this integrator, then '
             f'{settings["production_ps"]:g} ps of NVE at the total energy of 273.15 K. Their mean temperature {t_mean:.2f} ± {t_err:.2f} K; '
             f'energy drift {drift:+.4f} ± {drift_err:.4f} kJ/mol/ns per molecule. D_t from the mean-square displacement of the '
             f'centres of diffusion and D_r from <u(0).u(t)> = exp(-2 D_r t), both fitted over lags of {window[0]:g}-{window[1]:g} ps. '
             f'Finite-size correction of D_t +{finite_size*CM2_S:.3f} 1e-5 cm^2/s (Yeh-Hummer, with the model\'s own viscosity). '
             f'Runs by platform: {platform_counts([explicit_stage]+list(implicit_stages))}.', '',
             '| run | replicas | D_t (1e-5 cm^2/s) | D_r across the middle axis (1/ns) | ns/day (median replica) |', '|---|---|---|---|---|']
    for row in rows:
        lines.append(f"| {row['run']} | {row['replicas']} | {row['D_t (1e-5 cm^2/s)']:.3f} ± {row['D_t error']:.3f} "
                     f"({100*row['D_t error']/row['D_t (1e-5 cm^2/s)']:.1f}%) | {row['D_r (1/ns)']:.3f} ± {row['D_r error']:.3f} "
                     f"({100*row['D_r error']/row['D_r (1/ns)']:.1f}%) | {row['ns/day']:.1f} |")
    lines += [f'| the tensor at 0.289 cP (exact, long time) | | {predicted_t*CM2_S:.3f} | {predicted_r*1e3:.3f} | |', '',
              target_errors(rows), '',
              'Explicit replicas one by one (D_t of the periodic box, uncorrected):', '',
              '| replica | seed | mean temperature (K) | energy drift (kJ/mol/ns per molecule) | D_t (1e-5 cm^2/s) | D_r (1/ns) |',
              '|---|---|---|---|---|---|']
    lines += [f'| {index} | {int(run["seed"])} | {temperature:.2f} | {d:+.4f} | {t*CM2_S:.3f} | {r*1e3:.3f} |'
              for (index, run), temperature, d, t, r in zip(explicit_stage.runs(), temperatures, drifts, *explicit_replicas)]
    lines += ['',
              'Viscosity at which the implicit model reproduces the explicit diffusion (D scales as 1/eta):', '',
              f'- translational: {eta_t:.4f} ± {eta_t*d_t_err/d_t:.4f} cP (from the periodic box\'s D_t without the correction: '
              f'{eta_t*d_t/d_t_box:.4f} ± {eta_t*d_t/d_t_box*d_t_box_err/d_t_box:.4f} cP)',
              f'- rotational: {eta_r:.4f} ± {eta_r*d_r_err/d_r:.4f} cP',
              f'- rotational less translational: {eta_r-eta_t:+.4f} ± {jackknife_error(rotation_less_translation, *explicit_replicas):.4f} cP '
              '(delete-one jackknife over the explicit replicas, whose D_t and D_r correlate)',
              f'- the pentane model\'s own shear viscosity: {eta0*cp:.4f} ± {eta0_error*cp:.4f} cP; experiment {ps.EXPERIMENT_VISCOSITY} cP',
              '- over the model\'s own viscosity (the tensor at the solvent\'s own viscosity predicts diffusion its inverse times too '
              f'slow): translational {eta_t/(eta0*cp):.3f} ± {eta_t/(eta0*cp)*math.hypot(d_t_err/d_t, eta0_error/eta0):.3f}, '
              f'rotational {eta_r/(eta0*cp):.3f} ± {eta_r/(eta0*cp)*math.hypot(d_r_err/d_r, eta0_error/eta0):.3f}',
              f'- the explicit diffusion over the tensor\'s at 0.289 cP: translational {d_t/predicted_t:.3f} ± {d_t_err/predicted_t:.3f}, '
              f'rotational {d_r/predicted_r:.3f} ± {d_r_err/predicted_r:.3f}', '']
    (out/'diffusion.md').write_text('\n'.join(lines))

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    with open(out/'correlations.csv', 'w', newline='') as f:
        writer = csv.writer(f)
        writer.writerow(['run', 'quantity', 't (ps)', 'mean', 'standard error'])
        for name, stage in [('explicit', explicit_stage)]+list(zip(IMPLICIT_SCHEMES, implicit_stages)):
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
    right.set_title('<u(0).u(t)>, middle ellipsoid')
    left.legend()
    fig.tight_layout()
    fig.savefig(out/'correlations.png', dpi=120)
    plt.close(fig)


def part(text):
    """--part's I/K as (I, K), 0 <= I < K."""
    try:
        index, count = (int(v) for v in text.split('/'))
    except ValueError:
        raise argparse.ArgumentTypeError(f'{text!r} is not I/K (two integers, such as 0/4)')
    if not 0 <= index < count:
        raise argparse.ArgumentTypeError(f'{text}: I must be 0 to K-1')
    return index, count


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--quick', action='store_true', help='every stage, short (minutes)')
    parser.add_argument('--out', help='the study folder (default examples/results/banana_scene, or out/banana_scene with --quick)')
    parser.add_argument('--stages', default='all', help='stages to run (comma-separated, of density, viscosity, scene_box, explicit, '
                        'implicit; default all); the report is written from whatever every stage has on disk')
    parser.add_argument('--replicas', type=int, help='explicit and implicit replicas to have (default 8, 2 with --quick)')
    parser.add_argument('--add', type=int, default=0, help='runs to add to each stage named by --stages beyond those the settings ask for')
    parser.add_argument('--platform', default='CPU')
    parser.add_argument('--threads', type=int, help='threads per rank on the CPU platform (default: all cores)')
    parser.add_argument('--part', type=part, default=(0, 1), metavar='I/K',
                        help='without MPI: take the runs that rank I of K would (start K processes, I = 0..K-1, on one folder)')
    parser.add_argument('--save-every', type=float, default=runs.CHECKPOINT_SECONDS, metavar='SECONDS',
                        help='how often (wall clock) a replica under way saves its progress (default %(default)g)')
    parser.add_argument('--no-report', action='store_true', help='run only; write the tables later with --report-only')
    parser.add_argument('--ps-scale', type=float, default=1.0, help='scale every run length by this (for tests)')
    parser.add_argument('--report-only', action='store_true', help='write the tables and plots from the runs on disk, run nothing')
    args = parser.parse_args(argv)
    runs.CHECKPOINT_SECONDS = args.save_every
    if args.part[1] > 1 and args.add:
        parser.error('--add with --part: the parts would each count the runs on disk at another time; set the total with --replicas')
    settings = dict(SETTINGS['quick' if args.quick else 'full'])
    for key in settings:
        if key.endswith('_ps') and not isinstance(settings[key], tuple):
            settings[key] *= args.ps_scale
    if args.ps_scale != 1.0:
        settings['window_ps'] = tuple(w*args.ps_scale for w in settings['window_ps'])
    if args.replicas:
        settings['replicas'] = settings['implicit_replicas'] = args.replicas
    out = pathlib.Path(args.out or ('out/banana_scene' if args.quick else pathlib.Path(__file__).resolve().parent/'results'/'banana_scene'))
    args.out = out
    out.mkdir(parents=True, exist_ok=True)
    kinds = ('density', 'viscosity', 'scene_box', 'explicit', 'implicit')
    requested = set(kinds) if args.stages == 'all' else set(args.stages.split(','))
    if requested-set(kinds):
        parser.error(f'unknown stage(s) {sorted(requested-set(kinds))}; the stages are {", ".join(kinds)}')
    started = time.time()
    xi = tensor_comparison(settings, out)
    study = Study(args, settings, xi, set() if args.report_only else requested)
    try:
        density = study.density()
        viscosity = study.viscosity(density)
        box = study.scene_box()
        explicit = study.explicit(box)
        implicit = study.implicit(explicit, box)
    except (StudyMismatch, MissingRuns) as error:
        sys.exit(f'banana_scene.py: {error}')
    if study.rank == 0 and not args.no_report:
        for name in write_report(out, settings, xi, density, viscosity, box, explicit, implicit):
            print((out/name).read_text(), flush=True)
        print(f'total {time.time()-started:.0f} s', flush=True)


if __name__ == '__main__':
    main()
