"""The source's second scene: two banana-shaped molecules in explicit pentane against the two alone
in implicit solvent, and the viscosity at which they agree.

Sun, Lin & Gezelter (J. Chem. Phys. 128, 234107 (2008), section IV B) ran two bananas (three
Gay-Berne ellipsoids rigidly joined) among 256 pentanes at 273 K in NVE, and the two bananas alone
under their Langevin integrator at the experimental viscosity of pentane, 0.289 cP, with the
resistance tensor of a rough shell of 2266 beads; they compared the velocity autocorrelation of
the bananas' centres and the orientational autocorrelation of the middle ellipsoid's axis. This
example does the same with the model of banana_model.py (and 320 pentanes: see PENTANES) and answers what the source could not:
at which viscosity the implicit model reproduces the explicit diffusion, translational and
rotational, and how far that is from the solvent model's own viscosity. It writes, to --out:

  tensor.md           the banana's resistance tensor (shell extrapolated to zero bead size, and the
                      shell at the source's 2266 beads) beside the source's, in its frame and units
  pentane.md          the pentane model's density (NPT) and shear viscosity (periodic perturbation)
                      at 273 K, with standard errors, against experiment
  diffusion.md/.csv   D_t and D_r of the bananas, explicit against implicit (this integrator's
                      ExactFlow and BAOAB schemes at 0.289 cP, OpenMM's LangevinMiddleIntegrator
                      per particle), the tensor's prediction, the matching viscosities, ns/day
  correlations.csv/.png  velocity and orientational autocorrelations, explicit against implicit

    python examples/banana_scene.py --quick     # minutes: every stage, short
    python examples/banana_scene.py --medium    # about 45 minutes: rough numbers (examples/results/banana_scene)
    python examples/banana_scene.py             # the full study (see the README for its run time)

Every observable comes from independent replicas (rigidlangevin.ensemble: run it under mpirun to
spread them over ranks); its standard error is their spread over sqrt(replicas).
"""
import argparse
import csv
import math
import pathlib
import sys
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl
from rigidlangevin.ensemble import broadcast, run_ensemble
from rigidlangevin import statistics
from rigidlangevin.statistics import block_error

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import banana_model as bm  # noqa: E402

TEMPERATURE = bm.SOURCE_TEMPERATURE
KT = bm.BOLTZ*TEMPERATURE  # kJ/mol
AMU_PER_NM_PS_IN_CP = 1.66053906660e-27/(1e-9*1e-12)*1e3  # amu/(nm ps) in cP
CM2_S = 1e3  # nm^2/ps in 1e-5 cm^2/s
PENTANE_VISCOSITY_273K = 0.289  # cP, as the source uses (experiment)
PENTANE_DENSITY_273K = 0.6454  # g/mL near 0 C (CRC Handbook)
CUTOFF = 1.0  # nm, the Gay-Berne force's cutoff (switched over its last 10%)
# The source's 256 pentanes make a box of about 3.7 nm, and this banana's particles span 1.9 nm,
# more than half of it (the integrator refuses a body wider than half the box: its particles'
# minimum images would not be one body). 320 pentanes make a box of about 4 nm.
PENTANES = 320

# Quick and full settings: picoseconds of each stage, replicas, sampling.
SETTINGS = {
    'quick': dict(density_ps=10, viscosity_equilibration_ps=2, viscosity_ps=10, explicit_equilibration_ps=5, explicit_ps=5,
                  implicit_equilibration_ps=5, implicit_ps=100, replicas=2, max_beads=1000),
    'medium': dict(density_ps=25, viscosity_equilibration_ps=10, viscosity_ps=25, explicit_equilibration_ps=20, explicit_ps=40,
                   implicit_equilibration_ps=5, implicit_ps=300, replicas=3, max_beads=2000),
    'full': dict(density_ps=100, viscosity_equilibration_ps=10, viscosity_ps=200, explicit_equilibration_ps=50, explicit_ps=500,
                 implicit_equilibration_ps=50, implicit_ps=5000, replicas=8, max_beads=2000),
}
SAMPLE_PS = 0.01  # every 10 fs
EXPLICIT_STEP = 0.001  # ps: flexible pentane's bonds
IMPLICIT_STEP = 0.002


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


def pentane_density(settings, platform, seed):
    """Mean volume per pentane (nm^3) and its standard error: PENTANES pentanes, NPT at 273 K and 1 bar
    (LangevinMiddleIntegrator at 1/ps, Monte Carlo barostat), the second half of the run."""
    # Start at the experimental density.
    box = (PENTANES*bm.PENTANE_MASS/(6.02214076e23*PENTANE_DENSITY_273K)*1e21)**(1/3)
    system, positions, _, _ = bm.pentane_box(PENTANES, box, seed, cutoff=CUTOFF)
    system.addForce(mm.MonteCarloBarostat(1.0, TEMPERATURE))
    integrator = mm.LangevinMiddleIntegrator(TEMPERATURE, 1.0, EXPLICIT_STEP)
    integrator.setRandomNumberSeed(seed)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform))
    context.setPositions(positions)
    mm.LocalEnergyMinimizer.minimize(context, 10.0, 1000)
    context.setVelocitiesToTemperature(TEMPERATURE, seed)
    volumes = []
    steps = int(round(settings['density_ps']/EXPLICIT_STEP))
    for _ in range(steps//100):
        integrator.step(100)
        volumes.append(context.getState().getPeriodicBoxVolume().value_in_unit(unit.nanometer**3))
    volumes = np.array(volumes[len(volumes)//2:])/PENTANES
    state = context.getState(getPositions=True)
    return volumes.mean(), block_error(volumes), state


def cosine_acceleration_integrator(amplitude, wavenumber, friction, step):
    """Velocity Verlet with the periodic perturbation a_x = A cos(k z) (Hess, J. Chem. Phys. 116, 209
    (2002)) and a Langevin thermostat on y and z only, so that it removes the heat the flow makes
    without dragging the flow itself."""
    integrator = mm.CustomIntegrator(step)
    integrator.addGlobalVariable('A', amplitude)
    integrator.addGlobalVariable('k', wavenumber)
    integrator.addGlobalVariable('kT', KT)
    integrator.addGlobalVariable('keep', math.exp(-friction*step))
    integrator.addGlobalVariable('noise', math.sqrt(1-math.exp(-2*friction*step)))
    integrator.addUpdateContextState()
    kick = 'v + 0.5*dt*f/m + 0.5*dt*vector(A*cos(k*_z(x)), 0, 0)'
    integrator.addComputePerDof('v', kick)
    integrator.addComputePerDof('x', 'x + 0.5*dt*v')
    integrator.addComputePerDof('v', 'v*vector(1, keep, keep) + sqrt(kT/m)*vector(0, noise, noise)*gaussian')
    integrator.addComputePerDof('x', 'x + 0.5*dt*v')
    integrator.addComputePerDof('v', kick)
    return integrator


def pentane_viscosity(settings, platform, state, seed):
    """Shear viscosity (cP) of the pentane model and its standard error by periodic perturbation:
    eta = A rho / (V k^2), V the amplitude of the steady flow profile v_x(z) = V cos(k z)."""
    system, _, _, _ = bm.pentane_box(PENTANES, 4.2, seed, cutoff=CUTOFF)
    box = state.getPeriodicBoxVectors()
    system.setDefaultPeriodicBoxVectors(*box)
    length = box[2][2].value_in_unit(unit.nanometer)
    k = 2*math.pi/length
    masses = np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())])
    rho = masses.sum()/length**3  # amu/nm^3
    # A flow amplitude of about 0.05 nm/ps for pentane's viscosity: far below thermal speeds (~0.4 nm/ps).
    amplitude = 0.05*(PENTANE_VISCOSITY_273K/AMU_PER_NM_PS_IN_CP)*k*k/rho
    integrator = cosine_acceleration_integrator(amplitude, k, 5.0, EXPLICIT_STEP)
    integrator.setRandomNumberSeed(seed)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform))
    context.setPositions(state.getPositions())
    context.setVelocitiesToTemperature(TEMPERATURE, seed)
    # The profile builds up as 1 - exp(-t/tau), tau = rho/(eta k^2): 1.3 ps at the experimental
    # viscosity in this box, longer for a less viscous model; the full study waits 10 ps.
    integrator.step(int(round(settings['viscosity_equilibration_ps']/EXPLICIT_STEP)))
    profile = []
    for _ in range(int(round(settings['viscosity_ps']/SAMPLE_PS))):
        integrator.step(int(round(SAMPLE_PS/EXPLICIT_STEP)))
        s = context.getState(getPositions=True, getVelocities=True)
        x = s.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
        v = s.getVelocities(asNumpy=True).value_in_unit(unit.nanometer/unit.picosecond)
        profile.append(2*np.sum(masses*v[:, 0]*np.cos(k*x[:, 2]))/masses.sum())
    profile = np.array(profile)
    velocity, error = profile.mean(), block_error(profile)
    eta = amplitude*rho/(velocity*k*k)*AMU_PER_NM_PS_IN_CP
    return eta, eta*error/velocity, length


def banana_observables(context, bodies, masses, steps_per_sample, samples, integrator):
    """Centre-of-mass positions (unwrapped) and velocities of the bananas and the middle ellipsoid's
    axis, every steps_per_sample steps: arrays (samples, bananas, 3)."""
    members = np.array(bodies)
    m = masses[members][:, :, None]
    total = m.sum(axis=1)
    com, vel, axis = [], [], []
    for _ in range(samples):
        integrator.step(steps_per_sample)
        s = context.getState(getPositions=True, getVelocities=True)
        x = s.getPositions(asNumpy=True).value_in_unit(unit.nanometer)[members]
        v = s.getVelocities(asNumpy=True).value_in_unit(unit.nanometer/unit.picosecond)[members]
        com.append((m*x).sum(axis=1)/total)
        vel.append((m*v).sum(axis=1)/total)
        u = x[:, 4]-x[:, 3]  # middle ellipsoid: its first mass particle minus its centre
        axis.append(u/np.linalg.norm(u, axis=1, keepdims=True))
    return np.array(com), np.array(vel), np.array(axis)


def correlation(series, lags):
    """<a(0).a(t)> over time origins and bananas for t = 0..lags-1 samples; series (T, B, 3)."""
    n = len(series)
    out = np.zeros(lags)
    for lag in range(lags):
        out[lag] = np.mean(np.sum(series[:n-lag]*series[lag:], axis=2))
    return out


def analyse(com, vel, axis):
    """Observables of one run: VACF, C_u, MSD and the diffusion constants fitted from them."""
    samples = len(com)
    lags = max(4, samples//4)
    vacf, cu = correlation(vel, min(lags, int(2/SAMPLE_PS))), correlation(axis, lags)
    msd = statistics.mean_square_displacement(com, range(lags))
    t = np.arange(lags)*SAMPLE_PS
    window = slice(lags//2, lags)
    d_t = np.polyfit(t[window], msd[window], 1)[0]/6
    # <u(0).u(t)> = exp(-2 D_r t) for rotation about the axes across u: the slope of its logarithm.
    positive = cu[window] > 0
    d_r = -np.polyfit(t[window][positive], np.log(cu[window][positive]), 1)[0]/2 if positive.sum() > 2 else float('nan')
    return {'vacf': vacf/vacf[0], 'vacf0': vacf[0], 'cu': cu, 'msd': msd, 'D_t': d_t, 'D_r': d_r}


def explicit_replica(settings, platform, box, xi, seed):
    """Two bananas among PENTANES pentanes in a box of side box: equilibrated under this integrator
    with friction (bananas as bodies with their tensor, pentane sites with Stokes friction), then
    NVE (zero viscosity) as in the source. Returns the observables and the temperature at the end."""
    system, positions, bodies, _ = bm.pentane_box(PENTANES, box, seed, bananas=2, cutoff=CUTOFF)
    integrator = rl.RigidLangevinIntegrator(TEMPERATURE, 1.0*rl.centipoise, EXPLICIT_STEP)
    integrator.setRandomNumberSeed(seed)
    reference = [mm.Vec3(*p) for p in bm.banana_positions()]
    for members in bodies:
        integrator.setBodyHydrodynamics(integrator.addRigidBody(members), xi, reference)
    for i in range(system.getNumParticles()):
        if system.getParticleMass(i).value_in_unit(unit.dalton) > 0 and not any(i in members for members in bodies):
            integrator.setParticleRadius(i, 0.19)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(TEMPERATURE, seed)
    # Half the equilibration at 1 cP relaxes the starting lattice fast; at that friction (gamma h =
    # 0.15 for a pentane site) the configurations come out measurably cold (NVE from them settles
    # several kelvin lower), so the second half runs at 0.01 cP (gamma h = 0.0015).
    steps = int(round(settings['explicit_equilibration_ps']/EXPLICIT_STEP))
    integrator.step(steps//2)
    integrator.setViscosity(0.01*rl.centipoise)
    integrator.step(steps-steps//2)
    integrator.setViscosity(0.0)
    # NVE keeps the total momentum the bath left (a centre-of-mass drift of about 0.01 nm/ps, which
    # over tens of ps would add as much to the bananas' mean-square displacement as their own
    # diffusion): remove it. A uniform velocity is a rigid motion, so bodies take it exactly.
    masses = np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())])
    velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(unit.nanometer/unit.picosecond)
    context.setVelocities((velocities-masses@velocities/masses.sum())*(masses > 0)[:, None])
    start = time.time()
    every = int(round(SAMPLE_PS/EXPLICIT_STEP))
    samples = int(round(settings['explicit_ps']/SAMPLE_PS))
    com, vel, axis = banana_observables(context, bodies, masses, every, samples, integrator)
    seconds = time.time()-start
    result = analyse(com, vel, axis)
    result['ns_per_day'] = settings['explicit_ps']*1e-3/seconds*86400
    result['temperature'] = integrator.computeSystemTemperature().value_in_unit(unit.kelvin)
    return result


def implicit_replica(settings, platform, box, xi, scheme, viscosity, seed):
    """The two bananas alone at viscosity (poise): under this integrator with their tensor
    (scheme ExactFlow or BAOAB), or (scheme 'LangevinMiddle') under OpenMM's
    LangevinMiddleIntegrator, rigid through constraints (add_constrained_banana()), with the
    per-particle friction that gives the tensor's translational diffusion."""
    constrained = scheme == 'LangevinMiddle'
    system, positions, bodies, _ = bm.pentane_box(0, box, 1, bananas=2, cutoff=CUTOFF, constrained=constrained)
    if constrained:
        # Friction gamma m on every particle is gamma M on the centre of mass: D_t = kT/(gamma M).
        friction = KT/(3*bm.GB_MASS*predicted_diffusion(xi, viscosity)[0])
        integrator = mm.LangevinMiddleIntegrator(TEMPERATURE, friction, IMPLICIT_STEP)
    else:
        integrator = rl.RigidLangevinIntegrator(TEMPERATURE, viscosity*rl.poise, IMPLICIT_STEP)
        integrator.setScheme(scheme)
        reference = [mm.Vec3(*p) for p in bm.banana_positions()]
        for members in bodies:
            integrator.setBodyHydrodynamics(integrator.addRigidBody(members), xi, reference)
    integrator.setRandomNumberSeed(seed)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(TEMPERATURE, seed)
    integrator.step(int(round(settings['implicit_equilibration_ps']/IMPLICIT_STEP)))
    masses = np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())])
    start = time.time()
    com, vel, axis = banana_observables(context, bodies, masses, int(round(SAMPLE_PS/IMPLICIT_STEP)),
                                        int(round(settings['implicit_ps']/SAMPLE_PS)), integrator)
    seconds = time.time()-start
    result = analyse(com, vel, axis)
    result['ns_per_day'] = settings['implicit_ps']*1e-3/seconds*86400
    return result


def predicted_diffusion(xi, viscosity_poise):
    """The tensor's long-time D_t (nm^2/ps: a third of the trace of the translational block of
    kT (eta Xi)^-1 at the centre of diffusion) and D_r across the middle ellipsoid's axis (1/ps:
    half the sum of the rotational diffusion about the banana's y and z axes)."""
    d = np.array(xi.getDiffusionTensor(TEMPERATURE*unit.kelvin, viscosity_poise*rl.poise, xi.getCenterOfDiffusion()))
    return np.trace(d[:3, :3])/3, (d[4, 4]+d[5, 5])/2


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--quick', action='store_true', help='every stage, short (minutes)')
    parser.add_argument('--medium', action='store_true', help='every stage, long enough for rough numbers (about 40 minutes on 2 cores)')
    parser.add_argument('--out', default='out/banana_scene', help='output directory')
    parser.add_argument('--platform', default='CPU')
    parser.add_argument('--replicas', type=int, help='independent replicas of every run (default 2 quick, 8 full)')
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--ps-scale', type=float, default=1.0, help='scale every run length by this (for tests)')
    args = parser.parse_args(argv)
    settings = dict(SETTINGS['quick' if args.quick else 'medium' if args.medium else 'full'])
    for key in settings:
        if key.endswith('_ps'):
            settings[key] *= args.ps_scale
    if args.replicas:
        settings['replicas'] = args.replicas
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    started = time.time()

    xi = tensor_comparison(settings, out)
    print((out/'tensor.md').read_text().split('\n\n')[-2], flush=True)

    # The solvent model on its own: density under a barostat, then shear viscosity at that density.
    density_runs = run_ensemble(lambda i, seed: dict(zip(('volume', 'error', 'state'), pentane_density(settings, args.platform, seed))),
                                settings['replicas'], args.seed, 'pentane NPT')
    density_runs = broadcast(density_runs)
    volume, volume_error = density_runs['volume']
    grams = lambda v: bm.PENTANE_MASS/(6.02214076e23*v*1e-21)
    density, density_error = grams(volume), grams(volume)*volume_error/volume
    states = [v['state'] for v in density_runs.values]
    viscosity_runs = run_ensemble(lambda i, seed: dict(zip(('eta', 'error', 'length'), pentane_viscosity(settings, args.platform, states[i], seed))),
                                  settings['replicas'], args.seed+100, 'pentane viscosity')
    eta_pentane, eta_pentane_error = viscosity_runs['eta']
    (out/'pentane.md').write_text('\n'.join([
        '# The pentane model at 273 K', '',
        'TraPPE-UA (harmonic bonds, see banana_model.py), Gay-Berne cutoff 1.0 nm switched from 0.9 nm, no tail correction.', '',
        '| | this model | experiment |', '|---|---|---|',
        f'| density (g/mL), NPT at 1 bar | {density:.4f} +- {density_error:.4f} | {PENTANE_DENSITY_273K} |',
        f'| shear viscosity (cP), periodic perturbation | {eta_pentane:.3f} +- {eta_pentane_error:.3f} | {PENTANE_VISCOSITY_273K} |', '',
        f'{settings["replicas"]} replicas of {settings["density_ps"]} ps NPT (from the experimental density; the second half averaged) and '
        f'{settings["viscosity_ps"]} ps of periodic perturbation after {settings["viscosity_equilibration_ps"]} ps of build-up '
        f'(flow amplitude about 0.05 nm/ps, wavelength the box, {np.mean([v["length"] for v in viscosity_runs.values]):.3f} nm).', '']))
    print((out/'pentane.md').read_text(), flush=True)

    # The scene's box: the pentanes at the model's own density, plus the bananas' volume (three
    # ellipsoids each, over a packing fraction of one half: 0.4% of the box, an estimate).
    banana_volume = 3*4/3*math.pi*(bm.GB_LENGTH/2)*(bm.GB_BREADTH/2)**2/0.5
    box = (PENTANES*volume+2*banana_volume)**(1/3)

    runs = {}
    runs['explicit'] = run_ensemble(lambda i, seed: explicit_replica(settings, args.platform, box, xi, seed), settings['replicas'],
                                    args.seed+200, 'explicit pentane')
    for name, scheme in (('ExactFlow', rl.RigidLangevinIntegrator.ExactFlow), ('BAOAB', rl.RigidLangevinIntegrator.BAOAB),
                         ('LangevinMiddle', 'LangevinMiddle')):
        runs[name] = run_ensemble(lambda i, seed: implicit_replica(settings, args.platform, box, xi, scheme, bm.SOURCE_VISCOSITY, seed),
                                  settings['replicas'], args.seed+300, f'implicit {name}')
    write_results(out, settings, runs, xi, eta_pentane, eta_pentane_error, box)
    print(f'total {time.time()-started:.0f} s', flush=True)


def write_results(out, settings, runs, xi, eta_pentane, eta_pentane_error, box):
    predicted_t, predicted_r = predicted_diffusion(xi, bm.SOURCE_VISCOSITY)
    rows = []
    for name, result in runs.items():
        d_t, d_t_err = result['D_t']
        d_r, d_r_err = result['D_r']
        speed, speed_err = result['ns_per_day']
        rows.append({'run': name, 'D_t (1e-5 cm^2/s)': d_t*CM2_S, 'D_t error': d_t_err*CM2_S, 'D_r (1/ns)': d_r*1e3, 'D_r error': d_r_err*1e3,
                     'ns/day': speed, 'ns/day error': speed_err})
    # The explicit bananas diffuse in a periodic box, which slows translation by
    # xi_EW kT/(6 pi eta L) (Yeh & Hummer, J. Phys. Chem. B 108, 15873 (2004)), eta the solvent
    # model's own viscosity; rotation's correction is of order the banana's volume over the box's.
    # The implicit model is an unbounded fluid: compare with the corrected D_t.
    d_t_box, d_t_box_err = runs['explicit']['D_t']
    finite_size = 2.837297*KT/(6*math.pi*eta_pentane/AMU_PER_NM_PS_IN_CP*box)  # nm^2/ps
    d_t = d_t_box+finite_size
    d_t_err = math.hypot(d_t_box_err, finite_size*eta_pentane_error/eta_pentane)
    explicit = next(row for row in rows if row['run'] == 'explicit')
    rows.insert(rows.index(explicit)+1, dict(explicit, run='explicit, finite-size corrected', **{'D_t (1e-5 cm^2/s)': d_t*CM2_S, 'D_t error': d_t_err*CM2_S}))
    # Long-time diffusion under this integrator is kT (eta Xi)^-1 whatever the mass, so D scales as
    # 1/eta: the viscosity at which the implicit model diffuses as the explicit bananas do.
    d_r, d_r_err = runs['explicit']['D_r']
    with open(out/'diffusion.csv', 'w', newline='') as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    eta_t, eta_r = bm.SOURCE_VISCOSITY*predicted_t/d_t*100, bm.SOURCE_VISCOSITY*predicted_r/d_r*100  # cP
    temperature = runs['explicit'].get('temperature', (float('nan'), float('nan')))
    lines = ['# Bananas in explicit pentane against implicit solvent at 273 K', '',
             f'{settings["replicas"]} independent replicas of each run; standard errors from their spread. Box {box:.3f} nm.',
             f'Explicit runs: NVE after {settings["explicit_equilibration_ps"]} ps under this integrator (half at 1 cP, half at 0.01 cP), total '
             f'momentum removed; '
             f'temperature at their end {temperature[0]:.1f} +- {temperature[1]:.1f} K; finite-size correction of D_t +{finite_size*CM2_S:.3f} 1e-5 cm^2/s '
             f'(Yeh-Hummer, with the model\'s own viscosity).', '',
             '| run | D_t (1e-5 cm^2/s) | D_r across the middle axis (1/ns) | ns/day |', '|---|---|---|---|']
    for row in rows:
        lines.append(f"| {row['run']} | {row['D_t (1e-5 cm^2/s)']:.3f} +- {row['D_t error']:.3f} | {row['D_r (1/ns)']:.3f} +- {row['D_r error']:.3f} | "
                     f"{row['ns/day']:.2f} |")
    lines += [f'| the tensor at 0.289 cP (exact, long time) | {predicted_t*CM2_S:.3f} | {predicted_r*1e3:.3f} | |', '',
              'Viscosity at which the implicit model reproduces the explicit diffusion (D scales as 1/eta):', '',
              f'- translational: {eta_t:.3f} +- {eta_t*d_t_err/d_t:.3f} cP (from the periodic box\'s D_t without the correction: '
              f'{eta_t*d_t/d_t_box:.3f} +- {eta_t*d_t/d_t_box*d_t_box_err/d_t_box:.3f} cP)',
              f'- rotational: {eta_r:.3f} +- {eta_r*d_r_err/d_r:.3f} cP',
              f'- the pentane model\'s own shear viscosity: {eta_pentane:.3f} +- {eta_pentane_error:.3f} cP; experiment {PENTANE_VISCOSITY_273K} cP', '']
    (out/'diffusion.md').write_text('\n'.join(lines))
    print('\n'.join(lines), flush=True)
    # Correlation functions, explicit against implicit.
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    with open(out/'correlations.csv', 'w', newline='') as f:
        writer = csv.writer(f)
        writer.writerow(['run', 'quantity', 't (ps)', 'mean', 'standard error'])
        for name, result in runs.items():
            for key, axes, label in (('vacf', left, 'VACF of the centres (normalised)'), ('cu', right, '<u(0).u(t)>, middle ellipsoid')):
                mean, error = result[key]
                t = np.arange(len(mean))*SAMPLE_PS
                axes.plot(t, mean, label=name)
                axes.fill_between(t, mean-error, mean+error, alpha=0.3)
                axes.set_xlabel('t (ps)')
                axes.set_title(label)
                writer.writerows([name, key, f'{ti:.3f}', f'{m:.6g}', f'{e:.3g}'] for ti, m, e in zip(t, mean, error))
    left.set_xlim(0, 1)
    left.legend()
    fig.tight_layout()
    fig.savefig(out/'correlations.png', dpi=120)


if __name__ == '__main__':
    main()
