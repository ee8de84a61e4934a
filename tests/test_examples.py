"""The examples stay runnable: each is run briefly."""
import csv
import pathlib
import shutil
import subprocess
import sys

import numpy as np

from rigidlangevin.statistics import agreement_threshold, block_error

# block_error's 10 blocks leave 9 degrees of freedom: the window is their t quantile (4.8), not 4.
WINDOW = agreement_threshold(9)

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_bent_trimers_example(platform):
    result = subprocess.run([sys.executable, str(ROOT/'examples'/'bent_trimers.py'), '--bodies', '60', '--steps', '8000', '--report', '20',
                             '--platform', platform.name], capture_output=True, encoding='utf-8', timeout=300)
    assert result.returncode == 0, result.stderr
    def numbers(line):
        try:
            return [float(v) for v in line.split()]
        except ValueError:
            return None
    # Report lines: time, T_trans, T_rot, T, potential, kinetic, ns/day.
    rows = np.array([numbers(l) for l in result.stdout.splitlines() if numbers(l) is not None and len(l.split()) == 7])
    assert len(rows) == 400
    # The example's claim: both temperatures come to the bath's (within WINDOW block standard errors,
    # after 1 ps), each measured well enough to see a 5% error.
    for column, what in ((1, 'translational'), (2, 'rotational'), (3, 'total')):
        mean, error = np.mean(rows[25:, column]), block_error(rows[25:, column])
        assert abs(mean-300) < WINDOW*error, f'{what} temperature {mean:.1f} +- {error:.1f} K'
        assert 6*error < 0.05*300, f'{what} temperature: standard error {error:.1f} K'


def test_flagship_study_short_form(tmp_path):
    # A few picoseconds of every run: the table, the heating curve (CSV and PNG) and timings appear.
    result = subprocess.run([sys.executable, str(ROOT/'examples'/'flagship_water.py'), '--control-ps', '1', '--heating-ps', '0.4',
                             '--equilibration-ps', '0.2', '--out', str(tmp_path)], capture_output=True, encoding='utf-8', timeout=600)
    assert result.returncode == 0, result.stderr
    table = (tmp_path/'temperature_control.md').read_text(encoding='utf-8').splitlines()
    assert len(table) == 5 and '300.47' in table[2] and '303.04' in table[4]
    rows = list(csv.DictReader(open(tmp_path/'temperature_control.csv', encoding='utf-8')))
    assert len(rows) == 3
    for row in rows:
        mean, error = float(row['<T> (K)']), float(row['standard error (K)'])
        assert error > 0
        # At 1 and 0.1 P the bath holds the water within 1 ps of the start; at 0.01 P it takes about
        # that long to relax, longer than the short form's run.
        if float(row['viscosity (P)']) >= 0.1:
            assert abs(mean-300) < agreement_threshold(19)*error, f"{row['viscosity (P)']} P: {mean:.2f} +- {error:.2f} K"
    heating = list(csv.reader(open(tmp_path/'heating_curve.csv', encoding='utf-8')))
    assert heating[0][1:] == ['RigidLangevin 0.1 P T (K)', 'NVE (zero viscosity) T (K)', 'Nose-Hoover 5 ps T (K)']
    assert len(heating) == 10  # header, t = 0, then every 0.05 ps
    assert (tmp_path/'heating_curve.png').stat().st_size > 10000
    timings = list(csv.reader(open(tmp_path/'timings.csv', encoding='utf-8')))
    assert len(timings) == 7 and all(float(t[1]) > 0 for t in timings[1:])


def test_ssd_scene_quick(tmp_path):
    # The source's SSD scene in its quick form: the table beside the source's numbers and the heating
    # curves are written; at each viscosity the mean temperature is the bath's within the statistics
    # of the run, and the heating runs start cold and the thermostatted ones approach 300 K.
    result = subprocess.run([sys.executable, str(ROOT/'examples'/'ssd_scene.py'), '--quick', '--out', str(tmp_path)],
                            capture_output=True, encoding='utf-8', timeout=900)
    assert result.returncode == 0, result.stderr
    with open(tmp_path/'temperatures.csv', encoding='utf-8') as f:
        rows = list(csv.DictReader(f))
    assert [float(r['viscosity_poise']) for r in rows] == [1.0, 0.1, 0.01]
    for r in rows:
        assert abs(float(r['mean_T'])-300) < WINDOW*float(r['mean_T_error']), r
    assert '| 0.1 |' in (tmp_path/'table.md').read_text(encoding='utf-8')
    # The table is printed as it is written, and the heating curves are summarised on screen.
    assert (tmp_path/'table.md').read_text(encoding='utf-8').strip() in result.stdout and '| Nose-Hoover 5 ps |' in result.stdout
    with open(tmp_path/'heating.csv', encoding='utf-8') as f:
        heating = list(csv.DictReader(f))
    # The heating runs start cold: their first samples (after 20 fs, in which the quick form's briefly
    # cooled configuration already releases some potential energy) lie more than 5 rms fluctuations
    # (10.8 K each at 300 K) below the bath, where a warm start would almost never be.
    assert float(heating[0]['NVE']) < 300-5*10.8 and float(heating[0]['Nose-Hoover 5 ps']) < 300-5*10.8
    assert float(heating[-1]['RigidLangevin 0.1 P']) > 250  # 0.1 P relaxes the temperature within femtoseconds
    assert (tmp_path/'heating.png').stat().st_size > 10000


def test_banana_scene_short_form_and_appending(tmp_path):
    # Every stage of the banana scene, very short: the tables and plots appear, the tensor table
    # carries the source's numbers beside ours, and the implicit runs are far faster than the
    # explicit ones (the point of implicit solvent). Then the study in parts: one replica of each
    # run, then one more appended, gives the tables of both run at once (replica i is seeded from i;
    # one thread, so each run repeats bit for bit); and a folder made with other settings is
    # refused, naming them, rather than mixed. And the study run by processes started apart.
    scene = [sys.executable, str(ROOT/'examples'/'banana_scene.py'), '--quick', '--ps-scale', '0.1', '--threads', '1']

    def run(*extra):
        return subprocess.run(scene+list(extra), capture_output=True, encoding='utf-8', timeout=900)
    whole, parts = tmp_path/'whole', tmp_path/'parts'
    result = run('--out', str(whole))
    assert result.returncode == 0, result.stderr
    for name in ('tensor.md', 'pentane.md', 'density_trace.png', 'diffusion.md', 'diffusion.csv', 'correlations.csv', 'correlations.png'):
        assert (whole/name).stat().st_size > 0, name
    assert '58.64' in (whole/'tensor.md').read_text(encoding='utf-8')
    rows = {row['run']: row for row in csv.DictReader(open(whole/'diffusion.csv', encoding='utf-8'))}
    corrected = ['explicit, finite-size corrected (eta linear in k^2)', 'explicit, finite-size corrected (1/eta linear in k^2)']
    assert set(rows) == {'explicit', *corrected, 'ExactFlow', 'BAOAB', 'LangevinMiddle'}
    # The Yeh-Hummer correction only adds to the periodic box's D_t, with the solvent's viscosity by
    # either extrapolation to k = 0.
    for name in corrected:
        assert float(rows[name]['D_t (1e-5 cm^2/s)']) > float(rows['explicit']['D_t (1e-5 cm^2/s)'])
    for name in ('ExactFlow', 'BAOAB', 'LangevinMiddle'):
        assert float(rows[name]['ns/day']) > 5*float(rows['explicit']['ns/day'])
        assert float(rows[name]['D_t error']) > 0 and rows[name]['replicas'] == '2'

    # The stages before them (density, viscosities, the scene's box: one run each) are the whole
    # study's, copied: rerunning them repeated about 60 s of the test's 245 s for no new check.
    def copy_earlier_stages(folder):
        for name in ('density', 'scene_box') + tuple(p.name for p in (whole/'runs').glob('viscosity_*')):
            shutil.copytree(whole/'runs'/name, folder/'runs'/name)
    copy_earlier_stages(parts)
    result = run('--out', str(parts), '--replicas', '1', '--stages', 'explicit,implicit')
    assert result.returncode == 0, result.stderr
    assert {row['replicas'] for row in csv.DictReader(open(parts/'diffusion.csv', encoding='utf-8'))} == {'1'}
    result = run('--out', str(parts), '--replicas', '1', '--stages', 'explicit,implicit', '--add', '1')
    assert result.returncode == 0, result.stderr

    def without_speed(folder):
        return [{k: v for k, v in row.items() if k != 'ns/day'} for row in csv.DictReader(open(folder/'diffusion.csv', encoding='utf-8'))]
    assert without_speed(parts) == without_speed(whole)
    for name in ('pentane.md', 'correlations.csv'):
        assert (parts/name).read_text(encoding='utf-8') == (whole/name).read_text(encoding='utf-8'), name

    # The explicit and implicit stages run by two processes started apart (--part, as on a machine
    # without MPI), on a folder holding only the earlier stages' runs: the same tables again, each
    # run once (a run taken by both parts, or by neither, would change the replica count).
    split = tmp_path/'split'
    copy_earlier_stages(split)
    both = [subprocess.Popen(scene+['--out', str(split), '--stages', 'explicit,implicit', '--part', f'{i}/2', '--no-report'],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, encoding='utf-8') for i in range(2)]
    for process in both:
        _, error = process.communicate(timeout=900)
        assert process.returncode == 0, error
    assert not (split/'diffusion.csv').exists()
    result = run('--out', str(split), '--report-only')
    assert result.returncode == 0, result.stderr
    assert without_speed(split) == without_speed(whole)
    assert (split/'correlations.csv').read_text(encoding='utf-8') == (whole/'correlations.csv').read_text(encoding='utf-8')

    result = run('--out', str(parts), '--ps-scale', '0.2')
    assert result.returncode != 0
    assert 'holds runs of another density stage' in result.stderr and 'density_ps' in result.stderr


def test_protein_diffusion_example():
    """villin HP35 as rigid copies: all five force-field forces removed, and the measured diffusion
    within the t window of its 8 groups' standard error of the tensor's prediction. (The quick run's
    standard errors are about 12%; tests/test_banana.py checks the same prediction to 1%.)"""
    result = subprocess.run([sys.executable, str(ROOT/'examples'/'protein_diffusion.py'), '--quick'], capture_output=True, encoding='utf-8', timeout=600)
    assert result.returncode == 0, result.stderr
    line = next(l for l in result.stdout.splitlines() if l.startswith('test.pdb'))
    values = line.replace('+-', ' ').split()
    removed, predicted_t, measured_t, error_t, predicted_r, measured_r, error_r = (float(values[i]) for i in (1, 3, 4, 5, 6, 7, 8))
    assert removed == 5
    window = agreement_threshold(7)
    for predicted, measured, error, what in ((predicted_t, measured_t, error_t, 'D_t'), (predicted_r, measured_r, error_r, 'D_r')):
        assert abs(measured-predicted) < window*error, f'{what}: {measured} +- {error} against {predicted}'
        assert error < 0.25*predicted, f'{what}: standard error {error} is too large to mean anything'


def test_ssd_properties_quick(tmp_path):
    # The published-property comparison in its quick form: the table carries the published numbers
    # beside ours, and the NVE runs are at the mean NPT density (the box is scaled to exactly it).
    result = subprocess.run([sys.executable, str(ROOT/'examples'/'ssd_properties.py'), '--quick', '--models', 'SSD/RF', '--out', str(tmp_path)],
                            capture_output=True, encoding='utf-8', timeout=600)
    assert result.returncode == 0, result.stderr
    with open(tmp_path/'properties.csv', encoding='utf-8') as f:
        rows = list(csv.DictReader(f))
    assert [float(r['switching distance (A)']) for r in rows] == [8.55, 7.7]  # SSD/RF with both switches
    mass = 256*18.0153/6.02214076e23  # g
    for row in rows:
        assert abs(mass/(float(row['box edge at the mean density (nm)'])*1e-7)**3/float(row['density (g/cm^3)'])-1) < 1e-9
    table = (tmp_path/'table.md').read_text(encoding='utf-8')
    assert '| SSD/RF | 8.55 |' in table and '| 0.997 ± 0.001 |' in table


def test_ssd_properties_diffusion_from_wrapped_drifting_walks():
    # The estimator of D: Brownian walkers with a known D, all carried along by one velocity (the
    # random total momentum a thermostat leaves before an NVE run) and wrapped into a periodic box as
    # a Context reports them, give D back within the spread of independent walks (a 5 % error fails:
    # the standard error is about 0.3 %, under 1 %). Following them through the wrapping and taking
    # out the common drift are each needed: without either, D is wrong by more than 20 %.
    sys.path.insert(0, str(ROOT/'examples'))
    import ssd_properties as sp
    rng = np.random.default_rng(11)
    d_true, dt, box, walkers = 2.3e-3, 0.1, 2.0, 1024  # nm^2/ps (water's), ps, nm
    drift = 0.023  # nm/ps: the centre-of-mass speed of 256 waters at 298 K
    estimates, wrapped_estimates, drifting_estimates = [], [], []
    for _ in range(16):
        walk = np.cumsum(rng.normal(scale=np.sqrt(2*d_true*dt), size=(301, walkers, 3)), axis=0)
        walk += drift*dt*np.arange(301)[:, None, None]*rng.normal(size=3)/np.sqrt(3)
        wrapped = walk-box*np.floor(walk/box)
        estimates.append(sp.diffusion_constant(sp.relative_to_centre_of_mass(sp.unwrapped(wrapped, box)), dt, sp.MSD_LAGS_PS))
        wrapped_estimates.append(sp.diffusion_constant(sp.relative_to_centre_of_mass(wrapped), dt, sp.MSD_LAGS_PS))
        drifting_estimates.append(sp.diffusion_constant(sp.unwrapped(wrapped, box), dt, sp.MSD_LAGS_PS))
    # Independent walkers' own centre of mass diffuses too: relative to it, D is (1 - 1/walkers) D.
    expected = d_true*(1-1/walkers)
    mean, error = np.mean(estimates), np.std(estimates, ddof=1)/np.sqrt(len(estimates))
    assert error < 0.01*expected
    assert abs(mean-expected) < agreement_threshold(len(estimates)-1)*error, (mean, error)
    assert abs(np.mean(wrapped_estimates)-expected) > 0.2*expected
    assert abs(np.mean(drifting_estimates)-expected) > 0.2*expected


def test_sedimenting_cloud_example(tmp_path, platform):
    # The example's claims, on its quick cloud (30 spheres, 1 ps), on every platform: without
    # interactions the cloud settles at Stokes's speed, with them at the speed its spheres' RPY
    # mobility gives for the same trajectory, each within WINDOW standard errors (of about 1% and
    # 1.5%), and the interactions make it fall several times faster: what turning them on changes
    # for a user.
    result = subprocess.run([sys.executable, str(ROOT/'examples'/'sedimenting_cloud.py'), '--quick', '--platform', platform.name, '--out', str(tmp_path)],
                            capture_output=True, encoding='utf-8', timeout=300)
    assert result.returncode == 0, result.stderr
    rows = {}
    for line in (tmp_path/'table.md').read_text(encoding='utf-8').splitlines():
        cells = [c.strip() for c in line.strip('|').split('|')]
        if cells[0] in ('off', 'on'):
            measured, error = (float(v) for v in cells[1].split('±'))
            rows[cells[0]] = (measured, error, float(cells[2]))
    assert rows['off'][2] == 1.0
    for label, (measured, error, expected) in rows.items():
        assert abs(measured-expected) < WINDOW*error, (label, measured, error, expected)
        assert error < 0.02*expected, (label, error)
    assert rows['on'][0] > 3*rows['off'][0]
    assert (tmp_path/'cloud.png').exists()
