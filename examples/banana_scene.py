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
density_trace.png (the solvent model against experiment, its viscosity by both extrapolations to
k = 0: pentane_report.py), diffusion.md/.csv (D_t, D_r, the matching viscosities by either
extrapolation, this project's tensor and the source's own at 0.289 cP, the explicit runs'
temperature and energy drift, the velocity autocorrelations compared) and correlations.csv/.png
(velocity and orientational autocorrelations, explicit against implicit: banana_report.py).

    python examples/banana_scene.py --quick                    # every stage, short: minutes (tested)
    python examples/banana_scene.py                            # the full study, into examples/results/banana_scene:
                                                               # runs only what is not on disk yet
    python examples/banana_scene.py --stages explicit --add 4  # 4 more explicit replicas
    python examples/banana_scene.py --report-only              # the tables and plots from the runs on disk (minutes)
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
import banana_report as br  # noqa: E402
import banana_runs as runs  # noqa: E402
import pentane_report as pr  # noqa: E402
import pentane_solvent as ps  # noqa: E402
from study_folder import StudyFolder, StudyMismatch, system_fingerprint  # noqa: E402

TEMPERATURE = ps.TEMPERATURE
# The source's 256 pentanes make a box of about 3.7 nm, and this banana's particles span 1.9 nm,
# more than half of it (the integrator refuses a body wider than half the box: its particles'
# minimum images would not be one body). 320 pentanes make a box of about 4 nm.
PENTANES = ps.PENTANES
CANONICAL_BOX = 4.0  # nm: the box of the Systems whose fingerprints identify the model
IMPLICIT_SCHEMES = runs.IMPLICIT_SCHEMES
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


def tensor_comparison(settings, out):
    """tensor.md: our tensor in the source's frame and units (amu/fs, amu A/fs, amu A^2/fs at 0.289 cP)."""
    start = time.time()
    xi = bm.resistance_tensor(settings['max_beads'])
    extrapolated_seconds = time.time()-start
    radius, count, shell = bm.source_size_shell()
    scale = bm.source_units()
    center = xi.getCenterOfResistance()
    ours, turn = bm.source_frame(np.array(xi.getMatrix(center))*scale)
    shell_ours, _ = bm.source_frame(np.array(shell.getMatrix(center))*scale)
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
    (out/'tensor.md').write_text('\n'.join(lines), encoding='utf-8')
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
                result = pr.density_result(require(density_stage, 'density', 'the viscosity runs'))
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
                          lambda: {'box': pr.scene_box_result(require(box_stage, 'scene_box', 'the explicit runs'))['box']},
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
                              pr.scene_box_result(require(box_stage, 'scene_box', 'the implicit runs'))['box']}
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


def has_runs(*stages):
    return all(stage is not None and stage.indices() for stage in stages)


def write_report(out, settings, xi, density_stage, viscosity_stages, box_stage, explicit_stage, implicit_stages):
    """Every table and plot that the runs on disk allow (pentane_report.py, banana_report.py); returns
    the names of the tables written."""
    written = ['tensor.md']
    measured = [stage for stage in viscosity_stages if has_runs(stage)]
    viscosities = [pr.viscosity_result(stage) for stage in measured]
    if not has_runs(density_stage) or not ps.extrapolations_by_shear_rate(viscosities):
        return written
    solvent = pr.solvent_report(out, settings, density_stage, measured, viscosities)
    written.append('pentane.md')
    if has_runs(box_stage, explicit_stage, *implicit_stages):
        br.banana_report(out, settings, xi, solvent, box_stage, explicit_stage, implicit_stages)
        written.append('diffusion.md')
    return written


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
            print((out/name).read_text(encoding='utf-8'), flush=True)
        print(f'total {time.time()-started:.0f} s', flush=True)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
