"""The banana scene's runs, one replica each: the scene's box under a barostat, two bananas among
pentanes in NVE (explicit solvent), and two bananas alone in implicit solvent; and the observables
every one of them records.

Observables of a replica (curves on fixed lag grids, so that replicas add up):
- vacf: the velocity autocorrelation of the bananas' centres of mass, every SAMPLE_PS to VACF_PS;
- msd: the mean-square displacement of the bananas' centres of diffusion (the point of the body
  where the tensor's long-time translational diffusion is defined; the centre of mass wobbles
  about it as the body turns), every COARSE_PS to the run's longest lag;
- cu: <u(0).u(t)> of the middle ellipsoid's long axis u, on the same lags;
averaged over both bananas and every time origin.
"""
import math
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import banana_model as bm
import pentane_solvent as ps
import rigidlangevin as rl

TEMPERATURE = ps.TEMPERATURE
KT = ps.KT
# The implicit runs: this integrator's two schemes with the tensor, OpenMM's integrator per particle.
IMPLICIT_SCHEMES = ('ExactFlow', 'BAOAB', 'LangevinMiddle')
SAMPLE_PS = 0.01  # every 10 fs: the velocity autocorrelation
COARSE_PS = 0.1  # the lags of msd and cu
VACF_PS = 2.0
CHECKPOINT_SECONDS = 300.0  # how often (wall clock) a run with somewhere to keep its progress saves it
EXPLICIT_STEP = ps.STEP
IMPLICIT_STEP = 0.002
SITE_RADIUS = 0.19  # nm: a pentane site's Stokes radius during the thermostatted equilibration
MELT_VISCOSITY, EQUILIBRATION_VISCOSITY = 1.0, 0.01  # cP
NVE_START_ROUNDS, NVE_START_TOLERANCE = 20, 1e-3  # kJ/mol: the NVE start's total energy against its target
EXPLICIT_SETTINGS = {'step': EXPLICIT_STEP, 'sample_ps': SAMPLE_PS, 'site_radius': SITE_RADIUS, 'melt_viscosity': MELT_VISCOSITY,
                     'equilibration_viscosity': EQUILIBRATION_VISCOSITY, 'nve_start': 'the integrator\'s kinetic energy'}


def center_weights(point):
    """Weights w (9) with sum w = 1 and sum w_i b_i = point for the banana's nine particles b_i
    (banana_positions()): the banana is flat, so any point in its plane is an affine combination of
    its particles, which rigid motions carry exactly (the minimum-norm one is taken). A point off
    the plane by up to 0.001 nm (the shell tensor's centres come 1e-4 nm off it, its beads being
    not exactly symmetric) is taken at its projection."""
    b = bm.banana_positions()
    if abs(point[2]) > 1e-3:
        raise ValueError(f'the point {point} is not in the banana\'s plane (z = 0)')
    system = np.vstack([b[:, :2].T, np.ones(len(b))])
    return np.linalg.lstsq(system, np.array([point[0], point[1], 1.0]), rcond=None)[0]


def correlation(series, lags):
    """<a(0).a(t)> over time origins and bananas for t = lags (samples); series (T, B, 3)."""
    n = len(series)
    return np.array([np.mean(np.sum(series[:n-lag]*series[lag:], axis=2)) for lag in lags])


def displacement(series, lags):
    """<|a(t)-a(0)|^2> over time origins and bananas; series (T, B, 3), unwrapped."""
    n = len(series)
    return np.array([np.mean(np.sum((series[lag:]-series[:n-lag])**2, axis=2)) for lag in lags])


def sample_bananas(context, integrator, bodies, masses, weights, steps_per_sample, samples, max_lag_ps, on_coarse=None,
                   progress=None, saved=None, keep=None):
    """Run samples x steps_per_sample steps, recording every SAMPLE_PS the centres-of-mass velocity,
    and every COARSE_PS the centre of diffusion (weights on the first nine particles of each banana)
    and the middle ellipsoid's axis, to lags of max_lag_ps at most. on_coarse(state), called at
    each coarse sample, returns numbers to record there (a series of each comes back). With
    progress (a study folder's RunProgress), at the start and every CHECKPOINT_SECONDS of wall time
    at a coarse sample, the Context's checkpoint, the series so far and keep (the caller's numbers)
    are saved there; saved (what progress.load() gave, the Context already restored from its 'checkpoint')
    carries the run on from there. Returns the observables (see the module's text), the series of
    on_coarse's numbers, and the sampling's wall-clock seconds (over every sitting)."""
    members = np.array(bodies)
    nine = members[:, :9]
    m = masses[members][:, :, None]
    total = m.sum(axis=1)
    per_coarse = int(round(COARSE_PS/SAMPLE_PS))
    series = {'velocities': [], 'centers': [], 'axes': []}
    first, earlier_seconds = 0, 0.0
    if saved is not None:
        first, earlier_seconds = int(saved['samples_done']), float(saved['sampling_seconds'])
        series = {name: list(saved['series_'+name]) for name in saved['series_names']}
    start = last_save = time.time()

    def save(done):
        progress.save(checkpoint=np.frombuffer(context.createCheckpoint(), dtype=np.uint8), platform=context.getPlatform().getName(),
                      samples_done=done, sampling_seconds=earlier_seconds+time.time()-start, series_names=np.array(list(series)),
                      **{'series_'+name: np.array(values) for name, values in series.items()}, **(keep or {}))
    if progress is not None and saved is None:
        save(0)  # the equilibration before this is a run's longest stretch without a save
    for sample in range(first, samples):
        integrator.step(steps_per_sample)
        coarse = sample % per_coarse == per_coarse-1
        state = context.getState(getPositions=coarse, getVelocities=True, getEnergy=coarse and on_coarse is not None)
        v = state.getVelocities(asNumpy=True).value_in_unit(unit.nanometer/unit.picosecond)
        series['velocities'].append((m*v[members]).sum(axis=1)/total)
        if not coarse:
            continue
        x = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
        series['centers'].append(np.einsum('k,bkj->bj', weights, x[nine]))
        u = x[nine[:, 4]]-x[nine[:, 3]]
        series['axes'].append(u/np.linalg.norm(u, axis=1, keepdims=True))
        for name, value in (on_coarse(state) if on_coarse is not None else {}).items():
            series.setdefault(name, []).append(value)
        if progress is not None and time.time()-last_save >= CHECKPOINT_SECONDS and sample+1 < samples:
            save(sample+1)
            last_save = time.time()
    velocities, centers, axes = (np.array(series.pop(name)) for name in ('velocities', 'centers', 'axes'))
    vacf_lags = np.arange(min(len(velocities)//2, int(round(VACF_PS/SAMPLE_PS))+1))
    coarse_lags = np.arange(min(len(centers)//3, int(round(max_lag_ps/COARSE_PS)))+1)
    return dict({'vacf': correlation(velocities, vacf_lags), 'msd': displacement(centers, coarse_lags), 'cu': correlation(axes, coarse_lags),
                 'seconds': earlier_seconds+time.time()-start}, **{name: np.array(values) for name, values in series.items()})


def resume(context, progress):
    """What progress (a RunProgress, or None) saved, the Context restored from its checkpoint; or
    None. Progress saved on another platform, whose checkpoint only that platform can load, is
    left (said, not silently): the run starts over, and its new progress replaces it."""
    saved = progress.load() if progress is not None else None
    if saved is None:
        return None
    here = context.getPlatform().getName()
    if str(saved['platform']) != here:
        print(f'{progress.path}: progress saved on {saved["platform"]}, whose checkpoints only that platform loads; this run starts '
              f'over on {here} (to carry it on instead, run it with --platform {saved["platform"]})', flush=True)
        return None
    context.loadCheckpoint(saved['checkpoint'].tobytes())
    return saved


def particle_masses(system):
    return np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())])


def add_bodies(integrator, bodies, xi):
    reference = [mm.Vec3(*p) for p in bm.banana_positions()]
    for members in bodies:
        integrator.setBodyHydrodynamics(integrator.addRigidBody(members), xi, reference)


def scene_box_run(pentanes, picoseconds, seed, platform, properties=None, sample_ps=ps.SAMPLE_PS):
    """The scene (two bananas, held rigid by constraints, among pentanes) at 273.15 K and 1 bar:
    its volume (nm^3) every sample_ps, from a lattice at the experimental density of the pentanes
    plus a guess of the bananas' volume (three ellipsoids' volume over a packing fraction of one
    half). LangevinMiddleIntegrator (1/ps) with a Monte Carlo barostat, as for the neat solvent."""
    banana_volume = 3*4/3*math.pi*(bm.GB_LENGTH/2)*(bm.GB_BREADTH/2)**2/0.5
    box = (ps.box_edge(ps.EXPERIMENT_DENSITY, pentanes)**3+2*banana_volume)**(1/3)
    system, positions, _, _ = bm.pentane_box(pentanes, box, seed, bananas=2, constrained=True)
    system.addForce(ps.barostat(seed))
    integrator = mm.LangevinMiddleIntegrator(TEMPERATURE, ps.NPT_FRICTION, ps.STEP)
    integrator.setRandomNumberSeed(seed)
    context = bm.scene_context(system, integrator, platform, properties)
    context.setPositions(positions)
    mm.LocalEnergyMinimizer.minimize(context, 10.0, 1000)
    context.setVelocitiesToTemperature(TEMPERATURE, seed)
    every = int(round(sample_ps/ps.STEP))
    volumes = []
    for _ in range(int(round(picoseconds/sample_ps))):
        integrator.step(every)
        volumes.append(context.getState().getPeriodicBoxVolume().value_in_unit(unit.nanometer**3))
    return np.array(volumes)


def explicit_integrator(system, bodies, xi, viscosity_cp):
    """This integrator for the explicit scene at viscosity_cp: the bananas bodies with their tensor,
    the pentane sites free particles of Stokes radius SITE_RADIUS (friction only while thermostatted)."""
    integrator = rl.RigidLangevinIntegrator(TEMPERATURE, viscosity_cp*rl.centipoise, EXPLICIT_STEP)
    add_bodies(integrator, bodies, xi)
    masses = particle_masses(system)
    in_body = np.zeros(len(masses), dtype=bool)
    in_body[np.array(bodies).ravel()] = True
    for i in np.flatnonzero((masses > 0) & ~in_body):
        integrator.setParticleRadius(int(i), SITE_RADIUS)
    return integrator


def explicit_replica(settings, box, xi, weights, seed, platform, properties=None, progress=None):
    """Two bananas among settings['pentanes'] pentanes in a cubic box (nm), from a lattice: melted
    for melt_ps at 1 cP and equilibrated for equilibration_ps at 0.01 cP under this integrator
    (bananas as bodies with their tensor, pentane sites as free particles with Stokes friction);
    then NVE (zero viscosity: velocity Verlet with the bodies' symplectic rotation) for
    production_ps, started at the energy whose microcanonical temperature is the bath's:
    E = <U> over the equilibration's second half + (N_f - 3) kT / 2, N_f the integrator's degrees of
    freedom less the total momentum, which is removed (a uniform velocity is a rigid motion,
    which bodies take exactly). With progress (a RunProgress), the production saves its progress
    and a run cut short carries on from it. Returns the observables, the temperature and total
    energy every COARSE_PS, the target energy, and the run's speed."""
    system, positions, bodies, _ = bm.pentane_box(settings['pentanes'], box, seed, bananas=2)
    integrator = explicit_integrator(system, bodies, xi, MELT_VISCOSITY)
    integrator.setRandomNumberSeed(seed)
    masses = particle_masses(system)
    context = bm.scene_context(system, integrator, platform, properties)
    saved = resume(context, progress)
    if saved is None:
        context.setPositions(positions)
    dof = integrator.getNumDegreesOfFreedom()-3
    target = equilibrated_nve_start(settings, context, integrator, masses, dof, seed) if saved is None else float(saved['target_energy'])
    integrator.setViscosity(0.0)  # the production is NVE

    def record(state):
        kinetic = state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
        return {'temperature': 2*kinetic/(dof*bm.BOLTZ), 'energy': kinetic+state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)}
    result = sample_bananas(context, integrator, bodies, masses, weights, int(round(SAMPLE_PS/EXPLICIT_STEP)),
                            int(round(settings['production_ps']/SAMPLE_PS)), settings['max_lag_ps'], on_coarse=record,
                            progress=progress, saved=saved, keep={'target_energy': target})
    result.update(target_energy=target, degrees_of_freedom=dof)
    return result


def equilibrated_nve_start(settings, context, integrator, masses, dof, seed):
    """Melt and equilibrate the explicit scene (the Context at its start), then leave it at zero
    viscosity with the velocities that give the target energy (explicit_replica()); returns it."""
    context.setVelocitiesToTemperature(TEMPERATURE, seed)
    integrator.step(int(round(settings['melt_ps']/EXPLICIT_STEP)))
    integrator.setViscosity(EQUILIBRATION_VISCOSITY*rl.centipoise)
    steps = int(round(settings['equilibration_ps']/EXPLICIT_STEP))
    every = int(round(COARSE_PS/EXPLICIT_STEP))
    integrator.step(steps//2)
    potential = []
    for _ in range((steps-steps//2)//every):
        integrator.step(every)
        potential.append(context.getState(getEnergy=True).getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))
    target = float(np.mean(potential))+0.5*dof*KT
    integrator.setViscosity(0.0)
    state = context.getState(getVelocities=True, getEnergy=True)
    v = state.getVelocities(asNumpy=True).value_in_unit(unit.nanometer/unit.picosecond)
    v = (v-masses@v/masses.sum())*(masses > 0)[:, None]
    kinetic = 0.5*np.sum(masses[:, None]*v*v)
    headroom = target-state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)
    if headroom <= 0:
        raise RuntimeError(f'seed {seed}: the potential energy at the end of the equilibration is above the target total energy')
    # At zero viscosity the stored velocities lag the positions by half a kick (velocity Verlet),
    # and the integrator reports the kinetic energy at the positions' time: that of the velocities
    # set differs by (dt/2) sum v.F, tens of kJ/mol here (a temperature off by a kelvin). The scale
    # is refined on the integrator's own report until the total energy is the target.
    scale = math.sqrt(headroom/kinetic)
    for _ in range(NVE_START_ROUNDS):
        context.setVelocities(v*scale)
        reported = context.getState(getEnergy=True).getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
        if abs(reported-headroom) < NVE_START_TOLERANCE:
            return target
        scale *= math.sqrt(headroom/reported)
    raise RuntimeError(f'seed {seed}: the kinetic energy the integrator reports did not reach {headroom:.3f} kJ/mol in {NVE_START_ROUNDS} '
                       f'rounds (last {reported:.3f})')


def predicted_diffusion(xi, viscosity_poise):
    """The tensor's long-time D_t (nm^2/ps: a third of the trace of the translational block of
    kT (eta Xi)^-1 at the centre of diffusion) and D_r across the middle ellipsoid's axis (1/ps:
    half the sum of the rotational diffusion about the banana's y and z axes)."""
    d = np.array(xi.getDiffusionTensor(TEMPERATURE*unit.kelvin, viscosity_poise*rl.poise, xi.getCenterOfDiffusion()))
    return np.trace(d[:3, :3])/3, (d[4, 4]+d[5, 5])/2


def implicit_replica(settings, box, xi, weights, scheme, viscosity_poise, seed, platform, properties=None, progress=None):
    """The two bananas alone at viscosity_poise in the scene's box, interacting only with each other:
    under this integrator with their tensor (scheme 'ExactFlow' or 'BAOAB'), or ('LangevinMiddle')
    under OpenMM's LangevinMiddleIntegrator, rigid through constraints (add_constrained_banana())
    with the per-particle friction that gives the tensor's translational diffusion (a per-particle
    friction cannot also give its rotation). equilibration_ps, then production_ps sampled (with
    progress, a RunProgress, saving its progress and carrying on from it)."""
    constrained = scheme == 'LangevinMiddle'
    system, positions, bodies, _ = bm.pentane_box(0, box, seed, bananas=2, constrained=constrained)
    if constrained:
        # Friction gamma m on every particle is gamma M on the centre of mass: D_t = kT/(gamma M).
        friction = KT/(3*bm.GB_MASS*predicted_diffusion(xi, viscosity_poise)[0])
        integrator = mm.LangevinMiddleIntegrator(TEMPERATURE, friction, IMPLICIT_STEP)
    else:
        integrator = rl.RigidLangevinIntegrator(TEMPERATURE, viscosity_poise*rl.poise, IMPLICIT_STEP)
        integrator.setScheme(getattr(rl.RigidLangevinIntegrator, scheme))
        add_bodies(integrator, bodies, xi)
    integrator.setRandomNumberSeed(seed)
    context = bm.scene_context(system, integrator, platform, properties)
    saved = resume(context, progress)
    if saved is None:
        context.setPositions(positions)
        context.setVelocitiesToTemperature(TEMPERATURE, seed)
        integrator.step(int(round(settings['implicit_equilibration_ps']/IMPLICIT_STEP)))
    return sample_bananas(context, integrator, bodies, particle_masses(system), weights, int(round(SAMPLE_PS/IMPLICIT_STEP)),
                          int(round(settings['implicit_ps']/SAMPLE_PS)), settings['max_lag_ps'], progress=progress, saved=saved)
