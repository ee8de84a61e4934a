"""Speed against error: which integrator to use for rigid bodies in implicit solvent.

For each scene, integrator and step size, measures the cost (ns/day, wall seconds per body per
step) and the error of configurational and dynamical observables, and plots error against ns/day.

Scenes
  S1  free asymmetric bodies with a coupled 6x6 tensor about a point off the centre of mass: the
      truth is exact (kinetic temperatures, kT (eta Xi)^-1 diffusion, Favro's orientational times);
      with them, in a Context of their own, free isotropic helicoids (coupled, rotation-invariant
      6x6 tensor) whose velocity autocorrelation exp(-M^-1 eta Xi t) kT M^-1 is exact.
  S2  the flagship's 256 rigid TIP3P waters (PME 0.9 nm, LJ switched from 0.8 nm) at 0.01, 0.1 and
      1 poise: the truth is small-step (0.5 fs) ExactFlow reference runs. Every run starts from one
      of a few configurations equilibrated at 0.01 P (the configurational equilibrium does not
      depend on the viscosity; at 1 P reaching it would take nanoseconds), replica r of every
      integrator from start r; the configurational truth pools the references of all viscosities.
Every measured value carries a standard error: over replicas (S2) or over groups of independent
bodies (S1); errors are given with the standard error of measurement and truth combined.
Integrators: RigidLangevinIntegrator's ExactFlow, BAOAB and Original schemes, and OpenMM's
LangevinMiddleIntegrator with SETTLE and per-atom friction giving the same translational friction.
Also the largest stable step of each integrator per viscosity (1e5 steps of 64 rigid waters without
blowing up), and (part tconf) the configurational temperature at 1 P and 4 fs from 32 replicas,
against its exact value and against 1 fs runs from the same starts.

    python benchmarks/speed_vs_error/study.py                    # everything, on one rank
    mpirun -np 2 python benchmarks/speed_vs_error/study.py       # the same over 2 ranks (about 2 hours on 2 cores)
    ... study.py --parts s2                                      # one part; the other parts' rows are kept
    ... study.py --parts s2 --replicas 4 --s2-append             # 4 more S2 replicas, new starts (about 40 min on 2 cores)
    ... study.py --parts s2 --replicas 8 --s2-append --s2-rows 0.01:BAOAB:1,1.0:BAOAB:4   # 8 more of two rows only
    python benchmarks/speed_vs_error/study.py --quick            # a few ps per run, to check it works (5 min)

Writes results to --out (default out/speed_vs_error): results.csv, stability.csv, table.md,
error_vs_speed_*.png, and s2_replicas.json (every S2 run's observables, which --s2-append adds to).

The water System has no CMMotionRemover, which RigidLangevinIntegrator refuses with friction. The
committed S2 replicas (made before that rule) had one: it took the 256 waters' total momentum out
every step, slowing every run's diffusion alike by about 1/256 (0.4%, below each D's standard error
of 0.6-1.9%); an error compares a replica with its reference from the same start under the same
System, so the errors are unaffected, and replicas appended since are comparable with them.
"""
import argparse
import csv
import json
import math
import os
import pathlib
import sys
import time

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit

import rigidlangevin as rl
from rigidlangevin.ensemble import broadcast, run_ensemble
from rigidlangevin.statistics import block_error, standard_error

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import observables as obs  # noqa: E402
import report  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
TEMPERATURE = 300.0
SCHEMES = {'ExactFlow': rl.RigidLangevinIntegrator.ExactFlow, 'BAOAB': rl.RigidLangevinIntegrator.BAOAB,
           'Original': rl.RigidLangevinIntegrator.Original}
INTEGRATORS = ['ExactFlow', 'BAOAB', 'Original', 'LangevinMiddle+SETTLE']
WATER_STEPS = [1.0, 2.0, 4.0]  # fs, S2
WATER_SWITCH, WATER_CUTOFF = 0.8, 0.9
S2_REPLICAS = 's2_replicas.json'  # every S2 run's observables, for --s2-append


# ---------------------------------------------------------------------------- scene S2: water
def new_context(system, integrator, args, threads=None):
    """A Context on args.platform: CPU with `threads` (default args.threads) threads, OpenCL or CUDA
    in args.precision."""
    if args.platform == 'CPU':
        properties = {'Threads': str(threads or args.threads)}
    else:
        properties = {'Precision': args.precision}
    return mm.Context(system, integrator, mm.Platform.getPlatformByName(args.platform), properties)


def water_setup(waters_pdb, viscosity_poise, integrator_name, step_fs, seed, args, start=None, threads=None):
    """A Context of rigid TIP3P water under the named integrator, and the molecule layout; from the
    PDB's positions at T0, or from start = (positions, velocities) in nm and nm/ps."""
    pdb = app.PDBFile(str(waters_pdb))
    forcefield = app.ForceField('tip3p.xml')
    # The 64-water box of the stability study is too small for the 0.9 nm cutoff.
    switch, cutoff = (WATER_SWITCH, WATER_CUTOFF) if waters_pdb.name == 'water256.pdb' else (0.5, 0.6)
    system = forcefield.createSystem(pdb.topology, nonbondedMethod=app.PME, nonbondedCutoff=cutoff*unit.nanometer,
                                     switchDistance=switch*unit.nanometer, rigidWater=True, removeCMMotion=False)
    box = pdb.topology.getPeriodicBoxVectors()
    if waters_pdb.name == 'water256.pdb':
        box = [mm.Vec3(1.97166, 0, 0), mm.Vec3(0, 1.97166, 0), mm.Vec3(0, 0, 1.97166)]*unit.nanometer
    system.setDefaultPeriodicBoxVectors(*box)
    indices = [[a.index for a in r.atoms()] for r in pdb.topology.residues()]
    molecules = obs.Molecules(indices, [system.getParticleMass(i)._value for i in indices[0]])
    h = step_fs*1e-3
    if integrator_name == 'LangevinMiddle+SETTLE':
        # The same translational friction as the rigid body's: per-atom gamma = xi_t/M.
        friction = translational_friction(pdb, system, indices[0], viscosity_poise)/molecules.mass
        integrator = mm.LangevinMiddleIntegrator(TEMPERATURE, friction, h)
    else:
        integrator = rl.RigidLangevinIntegrator(TEMPERATURE*unit.kelvin, viscosity_poise*rl.poise, h*unit.picoseconds)
        integrator.setScheme(SCHEMES[integrator_name])
        rl.addRigidBodies(integrator, pdb.topology, system)
    integrator.setRandomNumberSeed(seed)
    context = new_context(system, integrator, args, threads)
    if start is None:
        context.setPositions(pdb.positions)
        context.applyConstraints(1e-10)
        context.setVelocitiesToTemperature(TEMPERATURE, seed)
    else:
        context.setPositions(start[0])
        context.setVelocities(start[1])
    nonbonded = [f for f in system.getForces() if isinstance(f, mm.NonbondedForce)][0]
    charge, sigma, epsilon = nonbonded.getParticleParameters(indices[0][0])
    return context, integrator, molecules, (sigma._value, epsilon._value), np.array([box[i][i].value_in_unit(unit.nanometer) for i in range(3)])


def md_viscosity(viscosity_poise):
    """A viscosity in poise in OpenMM's units, amu/(nm ps), as the integrator converts it."""
    return (viscosity_poise*rl.poise).value_in_unit(rl.md_viscosity)


def translational_friction(pdb, system, atoms, viscosity_poise):
    """eta * tr(Xi_tt)/3 (amu/ps) of one water body: the integrator's default bead model, with the
    radii addRigidBodies gives the body (Lennard-Jones sigma/2, else the element's radius)."""
    integrator = rl.RigidLangevinIntegrator(TEMPERATURE*unit.kelvin, viscosity_poise*rl.poise, 0.001*unit.picoseconds)
    rl.addRigidBodies(integrator, pdb.topology, system, residues=lambda residue: residue.index == 0)
    nonbonded = [f for f in system.getForces() if isinstance(f, mm.NonbondedForce)][0]
    positions = [pdb.positions[a] for a in atoms]
    radii = [integrator.getParticleRadius(a) or 0.5*nonbonded.getParticleParameters(a)[1] for a in atoms]
    tensor = rl.hydrodynamics.beads(positions, radii, rl.hydrodynamics.unionVolume(positions, radii)).getMatrix()
    return md_viscosity(viscosity_poise)*np.trace(tensor[:3, :3])/3


def refusal(error):
    text = str(error)
    if 'Original scheme cannot integrate' in text:
        return 'refused: friction too stiff for the fixed-point iteration'
    return 'blew up: '+text[:80]


def prepare_starts(args, count, seed, spacing_ps=None):
    """`count` equilibrated starting configurations (positions, velocities): the PDB's box relaxed
    at 0.01 P, where rotation decorrelates in picoseconds, then one snapshot every spacing_ps
    (default start_spacing_ps), all at 1 fs."""
    context, integrator, _, _, _ = water_setup(ROOT/'examples'/'data'/'water256.pdb', 0.01, 'ExactFlow', 1.0, seed, args)
    integrator.step(int(round(args.start_equilibration_ps/0.001)))
    starts = []
    for _ in range(count):
        integrator.step(int(round((spacing_ps or args.start_spacing_ps)/0.001)))
        state = context.getState(getPositions=True, getVelocities=True)
        starts.append((state.getPositions(asNumpy=True)._value, state.getVelocities(asNumpy=True)._value))
    return starts


def starts_per_rank(args, count, ranks, seed, spacing_ps, label):
    """`count` starting configurations from one chain per rank (chain k seeded seed+k), on every rank."""
    chains = [{'count': -(-count//ranks), 'seed': seed+k} for k in range(ranks)]
    starts = distribute(lambda task: prepare_starts(args, task['count'], task['seed'], spacing_ps), chains, label)
    return broadcast([s for chain in starts for s in chain][:count] if starts is not None else None)


def run_water(task):
    """One S2 run: equilibrate, then sample every `sample_fs` (positions and velocities) and every
    tenth sample the forces and energy; returns observables and the cost of the steps alone."""
    viscosity, name, step_fs, seed, args = task['viscosity'], task['integrator'], task['step_fs'], task['seed'], task['args']
    context, integrator, molecules, (sigma, epsilon), box = water_setup(ROOT/'examples'/'data'/'water256.pdb', viscosity, name, step_fs, seed,
                                                                        args, args.starts[task['replica']])
    every = max(1, int(round(args.sample_fs/step_fs)))
    dt = every*step_fs*1e-3
    try:
        integrator.step(int(round(args.equilibration_ps/(step_fs*1e-3))))
        samples = int(round(args.production_ps/dt))
        centers, directions, velocities = [], [], []
        t_trans, t_rot, potential, force_sq, laplacian = [], [], [], [], []
        rdf = 0
        stepping = 0.0
        for s in range(samples):
            start = time.time()
            integrator.step(every)
            stepping += time.time()-start
            heavy = (s % 10 == 0)
            state = context.getState(getPositions=True, getVelocities=True, getForces=heavy, getEnergy=heavy)
            x = state.getPositions(asNumpy=True)._value
            v = state.getVelocities(asNumpy=True)._value
            if not np.all(np.isfinite(x)):
                return {'status': 'blew up'}
            tt, tr = obs.kinetic_temperatures(molecules, x, v)
            t_trans.append(tt)
            t_rot.append(tr)
            centers.append(molecules.centers(x))
            directions.append(obs.dipole_directions(x, molecules))
            velocities.append(molecules.rigid_motion(x, v)[0])
            if heavy:
                potential.append(state.getPotentialEnergy()._value/len(molecules.indices))
                oxygens = x[molecules.indices[:, 0]]
                a, b = obs.configurational_temperature_terms(molecules, state.getForces(asNumpy=True)._value, oxygens, box,
                                                             sigma, epsilon, WATER_SWITCH, WATER_CUTOFF)
                force_sq.append(a)
                laplacian.append(b)
                rdf = rdf+obs.radial_distribution(oxygens, box, 0.95, 95)
    except mm.OpenMMException as e:
        return {'status': refusal(e)}
    lag1, lag2 = int(round(2.0/dt)), int(round(min(8.0, 0.5*args.production_ps)/dt))
    conf = np.array(force_sq)/np.mean(laplacian)/obs.KB
    return {'status': 'ok',
            'T translational (K)': np.mean(t_trans), 'T translational (K) +-': block_error(t_trans),
            'T rotational (K)': np.mean(t_rot), 'T rotational (K) +-': block_error(t_rot),
            'potential per molecule (kJ/mol)': np.mean(potential), 'potential per molecule (kJ/mol) +-': block_error(potential),
            'T configurational (K)': np.mean(force_sq)/np.mean(laplacian)/obs.KB, 'T configurational (K) +-': block_error(conf),
            'O-O RDF': rdf/len(potential),
            'D translational (nm^2/ps)': obs.diffusion_from_msd(centers, dt, lag1, max(lag2, lag1+1)),
            'orientational time (ps)': obs.correlation_time(directions, dt, int(round(5.0/dt))),
            'VACF': obs.velocity_autocorrelation(velocities, [1, 2, 4, 8]),
            'ns/day': samples*every*step_fs*1e-6/(stepping/86400),
            's per body-step': stepping/(samples*every*len(molecules.indices))}


# ---------------------------------------------------------------------------- scene S1: free coupled bodies
def coupled_tensor():
    a = np.array([[1.0, 0.3, -0.2, 0.5, -0.1, 0.2], [0.1, 0.9, 0.4, -0.3, 0.6, 0.1], [-0.2, 0.2, 1.1, 0.2, 0.1, -0.5],
                  [0.3, -0.4, 0.1, 1.2, 0.2, 0.3], [0.2, 0.1, -0.3, 0.1, 0.8, -0.2], [-0.1, 0.3, 0.2, -0.2, 0.3, 1.0]])
    s = np.diag([2.5, 2.5, 2.5, 0.3, 0.3, 0.3])
    return s@(a@a.T+0.5*np.eye(6))@s


BODY_SHAPE = np.array([[0, 0, 0], [0.12, 0, 0], [0.02, 0.09, 0], [0.03, 0.02, 0.07]])
BODY_MASSES = np.array([4.0, 3.0, 3.5, 7.5])  # 18 amu, water-sized inertia
BODY_OFFSET = np.array([0.05, 0.03, 0.01])  # tensor origin relative to the centre of mass
S1_GROUPS = 10  # groups of bodies for standard errors
S1_VISCOSITY = 0.003  # poise: mode rates lambda h from 0.05 to 2.7 at 2 fs, orientational time 4.5 ps


def s1_truth():
    """Exact answers for S1: diffusion kT (eta Xi)^-1 at the centre of diffusion, Favro's times, the
    helicoids' velocity autocorrelation."""
    kt = obs.KB*TEMPERATURE
    eta = md_viscosity(S1_VISCOSITY)
    def skew(r):
        return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])
    def move(mu, r):
        b = np.eye(6)
        b[:3, 3:] = -skew(r)
        return b@mu@b.T
    d = move(kt*np.linalg.inv(eta*coupled_tensor()), -BODY_OFFSET)
    trace = lambda r: np.trace(move(d, r)[:3, :3])
    # Minimum of a quadratic: solve the gradient from finite differences.
    e, g, hmat = 1e-3, np.zeros(3), np.zeros((3, 3))
    for i in range(3):
        ei = np.eye(3)[i]*e
        g[i] = (trace(ei)-trace(-ei))/(2*e)
        for j in range(3):
            ej = np.eye(3)[j]*e
            hmat[i, j] = (trace(ei+ej)-trace(ei-ej)-trace(-ei+ej)+trace(-ei-ej))/(4*e*e)
    center = -np.linalg.solve(hmat, g)
    rotational = np.linalg.eigvalsh(d[3:, 3:])
    return {'T translational (K)': TEMPERATURE, 'T rotational (K)': TEMPERATURE,
            'D translational (nm^2/ps)': trace(center)/3,
            'orientational time (ps)': np.mean([1/(rotational.sum()-rotational[k]) for k in range(3)]),
            'VACF': helicoid_vacf_truth(),
            'center': center, 'axes': np.linalg.eigh(d[3:, 3:])[1]}


# S1's velocity autocorrelation: the lab-frame velocities of the asymmetric body above turn with it
# (its friction in the lab frame depends on its orientation), so their autocorrelation has no closed
# form. Kelvin's isotropic helicoid has one: its 6x6 tensor about the centre of mass couples
# translation and rotation (Xi_tr = c 1) yet is unchanged by rotation, and with isotropic inertia
# nothing turns the lab-frame velocities (V, omega) but friction and noise, an Ornstein-Uhlenbeck
# process: <u(t) u(0)^T> = exp(-M^-1 eta Xi t) kT M^-1 exactly.
HELICOID_SHAPE = 0.06/math.sqrt(3)*np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]])  # regular tetrahedron
HELICOID_MASSES = np.full(4, 4.5)  # 18 amu, inertia 0.0432 amu nm^2 about every axis
HELICOID_RESISTANCE = (1.0, 0.0048, 0.045)  # nm, nm^3, nm^2: rates 4.6 and 25.6 /ps at 0.003 P, coupling c^2/(ab) = 0.42
VACF_STRIDE_FS = 32.0  # velocity samples (a multiple of every step); the VACF at 1, 2, 4, 8 strides
VACF_LAGS = [1, 2, 4, 8]


def helicoid_tensor():
    a, b, c = HELICOID_RESISTANCE
    return np.block([[a*np.eye(3), c*np.eye(3)], [c*np.eye(3), b*np.eye(3)]])


def helicoid_vacf_truth():
    """Normalized <V(t).V(0)> of the helicoids at the VACF lags: tr_tt exp(-K t)/3 with
    K = M^-1/2 eta Xi M^-1/2 (the translational block of M^1/2 is a multiple of 1)."""
    inertia = np.einsum('s,sk,sk->', HELICOID_MASSES, HELICOID_SHAPE, HELICOID_SHAPE)*2/3
    scale = np.repeat([HELICOID_MASSES.sum()**-0.5, inertia**-0.5], 3)
    rates, modes = np.linalg.eigh(scale[:, None]*md_viscosity(S1_VISCOSITY)*helicoid_tensor()*scale[None, :])
    lags = VACF_STRIDE_FS*1e-3*np.array(VACF_LAGS)
    return np.array([np.trace(((modes*np.exp(-rates*t))@modes.T)[:3, :3])/3 for t in lags])


def free_bodies(name, step_fs, seed, args, shape, masses, tensor, origin):
    """args.free_bodies force-free copies of a body (sites `shape` about its centre of mass, 3 nm
    apart) with the resistance `tensor` about `origin` (relative to the centre of mass), at S1's
    viscosity: the integrator, a CPU Context at temperature and the bodies as Molecules."""
    n = args.free_bodies
    system = mm.System()
    integrator = rl.RigidLangevinIntegrator(TEMPERATURE*unit.kelvin, S1_VISCOSITY*rl.poise, step_fs*1e-3*unit.picoseconds)
    integrator.setScheme(SCHEMES[name])
    integrator.setRandomNumberSeed(seed)
    positions = []
    sites = len(masses)
    for b in range(n):
        # Bodies along the line y = 3 nm. Where a body's moments are equal (the helicoid) its principal
        # axes, and so which random number drives which axis, follow the last bits of the positions:
        # the place keeps the recorded runs reproducible (the statistics do not depend on it).
        place = np.array([3.0*b, 3.0, 0])
        for m, p in zip(masses, shape):
            system.addParticle(m)
            positions.append(mm.Vec3(*(p+place)))
        integrator.addRigidBody(list(range(sites*b, sites*b+sites)))
        integrator.setBodyResistance(b, tensor, mm.Vec3(*(origin+place)), positions[-sites:])
    context = new_context(system, integrator, args)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(TEMPERATURE, seed)
    return integrator, context, obs.Molecules([list(range(sites*b, sites*b+sites)) for b in range(n)], masses)


def run_helicoids(name, step_fs, seed, args):
    """S1's velocity autocorrelation: free helicoids sampled every VACF_STRIDE_FS; the normalized
    VACF at VACF_LAGS, its mean and standard error over groups of helicoids."""
    n = args.free_bodies
    integrator, context, molecules = free_bodies(name, step_fs, seed, args, HELICOID_SHAPE, HELICOID_MASSES,
                                                 helicoid_tensor(), np.zeros(3))
    stride = int(round(VACF_STRIDE_FS/step_fs))
    integrator.step(int(round(2.0/(step_fs*1e-3))))  # 2 ps: 9 velocity relaxation times of the slowest mode
    velocities = []
    for s in range(int(round(args.helicoid_ps/(VACF_STRIDE_FS*1e-3)))):
        integrator.step(stride)
        state = context.getState(getPositions=True, getVelocities=True)
        velocities.append(molecules.rigid_motion(state.getPositions(asNumpy=True)._value, state.getVelocities(asNumpy=True)._value)[0])
    velocities = np.array(velocities)
    vacf = [obs.velocity_autocorrelation(velocities[:, g], VACF_LAGS) for g in np.array_split(np.arange(n), S1_GROUPS)]
    return np.mean(vacf, axis=0), standard_error(vacf)


def run_free_bodies(task):
    name, step_fs, seed, args = task['integrator'], task['step_fs'], task['seed'], task['args']
    truth = s1_truth()
    n = args.free_bodies
    com = (BODY_MASSES[:, None]*BODY_SHAPE).sum(0)/BODY_MASSES.sum()
    reference = BODY_SHAPE-com
    integrator, context, molecules = free_bodies(name, step_fs, seed, args, reference, BODY_MASSES, coupled_tensor(), BODY_OFFSET)
    tau = truth['orientational time (ps)']
    dt = tau/20
    every = max(1, int(round(dt/(step_fs*1e-3))))
    dt = every*step_fs*1e-3
    samples = int(round(args.free_body_time*tau/dt))
    try:
        integrator.step(every*20)
        centers, axes, t_trans, t_rot = [], [], [], []
        stepping = 0.0
        for s in range(samples):
            start = time.time()
            integrator.step(every)
            stepping += time.time()-start
            state = context.getState(getPositions=True, getVelocities=True)
            x = state.getPositions(asNumpy=True)._value
            v = state.getVelocities(asNumpy=True)._value
            tt, tr = obs.kinetic_temperatures(molecules, x, v, remove_com=False)
            t_trans.append(tt)
            t_rot.append(tr)
            c = molecules.centers(x)
            rotations = []
            for b in range(n):
                hmat = reference.T@(x[4*b:4*b+4]-c[b])
                u, _, vt = np.linalg.svd(hmat)
                dd = np.sign(np.linalg.det(vt.T@u.T))
                rotations.append(vt.T@np.diag([1, 1, dd])@u.T)
            rotations = np.array(rotations)
            centers.append(c+np.einsum('bij,j->bi', rotations, truth['center']))
            axes.append(np.einsum('bij,jk->bik', rotations, truth['axes']))
        vacf, vacf_error = run_helicoids(name, step_fs, seed, args)
    except mm.OpenMMException as e:
        return {'status': refusal(e)}
    # The bodies are independent: groups of them give independent estimates, hence standard errors.
    lag1, lag2 = min(int(round(2*tau/dt)), samples//4), min(int(round(6*tau/dt)), samples//2)
    groups = np.array_split(np.arange(n), S1_GROUPS)
    diffusion = [obs.diffusion_from_msd([c[g] for c in centers], dt, lag1, lag2) for g in groups]
    times = [np.mean([obs.correlation_time([a[g, :, k] for a in axes], dt, samples//2) for k in range(3)]) for g in groups]
    return {'status': 'ok', 'T translational (K)': np.mean(t_trans), 'T translational (K) +-': block_error(t_trans),
            'T rotational (K)': np.mean(t_rot), 'T rotational (K) +-': block_error(t_rot),
            'D translational (nm^2/ps)': np.mean(diffusion), 'D translational (nm^2/ps) +-': standard_error(diffusion),
            'orientational time (ps)': np.mean(times), 'orientational time (ps) +-': standard_error(times),
            'VACF': vacf, 'VACF +-': vacf_error,
            'ns/day': samples*every*step_fs*1e-6/(stepping/86400),
            's per body-step': stepping/(samples*every*n)}


# ---------------------------------------------------------------------------- stability
def stability_task(task):
    """The largest candidate step at which the integrator runs `steps` steps of the 64-water box
    without blowing up (NaN, an exception, or a temperature above 1000 K), trying steps in order."""
    viscosity, name, args = task['viscosity'], task['integrator'], task['args']
    largest = 0.0
    for step_fs in task['candidates']:
        try:
            context, integrator, molecules, lj, box = water_setup(ROOT/'examples'/'data'/'water64.pdb', viscosity, name, step_fs, 7, args)
            integrator.step(args.stability_steps)
            state = context.getState(getPositions=True, getVelocities=True)
            x = state.getPositions(asNumpy=True)._value
            tt, tr = obs.kinetic_temperatures(molecules, x, state.getVelocities(asNumpy=True)._value)
            stable = bool(np.all(np.isfinite(x)) and tt < 1000 and tr < 1000)
        except mm.OpenMMException:
            stable = False
        if not stable:
            break
        largest = step_fs
    return {'largest stable step (fs)': largest}


# ---------------------------------------------------------------------------- T configurational at 1 P
# Three replicas put ExactFlow's configurational temperature at 1 P and 4 fs 4.4 +- 1.4 % below
# 300 K. Here 32 replicas, each from its own start, also run at 1 fs from the same starts and
# compared start by start; the exact value is T0 (the translational estimator <|F|^2>/<lap U> is
# exact in the canonical ensemble). Measured (2026-11-25): ExactFlow's replicas spread by 3.8 %
# (BAOAB's, whose too-fast dynamics visit more configurations, by 0.8 %), and pairing by start
# removes little of it, so 32 replicas bound a bias by 1.5 % at two standard errors; 64 (a second
# run of 32 with --tconf-append) bound it by 0.95 %.
TCONF_VISCOSITY = 1.0
TCONF_RUNS = [('ExactFlow', 1.0), ('ExactFlow', 4.0), ('BAOAB', 4.0)]
TCONF_SPACING_PS = 10.0


def configurational_temperature(args, ranks, first_replica=0):
    """Runs TCONF_RUNS from args.tconf_replicas starts (one chain of starts per rank); returns one
    record per run on rank 0 (None elsewhere). Replicas are numbered from first_replica, and their
    chains and noise are seeded by it, so that runs appended to earlier ones are independent of them."""
    n = args.tconf_replicas
    args.starts = starts_per_rank(args, n, ranks, 50+first_replica, TCONF_SPACING_PS, 'T configurational: starting configurations (0.01 P)')
    tasks = [{'viscosity': TCONF_VISCOSITY, 'integrator': name, 'step_fs': h, 'seed': 300+first_replica+r, 'replica': r, 'args': args}
             for name, h in TCONF_RUNS for r in range(n)]
    results = distribute(run_water, tasks, f'T configurational at {TCONF_VISCOSITY} P')
    if results is None:
        return None
    keys = ['T configurational (K)', 'potential per molecule (kJ/mol)', 'T translational (K)', 'T rotational (K)']
    return [{'integrator': t['integrator'], 'step (fs)': t['step_fs'], 'replica': first_replica+t['replica'], 'status': r['status'],
             **{k: r[k] for k in keys if k in r}} for t, r in zip(tasks, results)]


# ---------------------------------------------------------------------------- driver
def distribute(function, tasks, label):
    """Run tasks over the MPI ranks (one task per replica slot); returns their results in order on rank 0."""
    result = run_ensemble(lambda index, seed: {'index': index, 'payload': function(tasks[index])}, len(tasks), label=label)
    if result is None:
        return None
    return [v['payload'] for v in result.values]


def combine(results):
    """One value per observable from replicas: the mean, with the standard error over replicas as
    'name +-' (scalars); arrays (RDF, VACF) are averaged; the speed is the fastest replica's. The
    first failure wins the status."""
    failed = [r for r in results if r.get('status') != 'ok']
    if failed:
        return {'status': failed[0].get('status', 'failed')}
    combined = {'status': 'ok', 'replicas': len(results)}
    for key, value in results[0].items():
        if key == 'status' or key.endswith(' +-'):
            continue
        values = [r[key] for r in results]
        # Speed from the least disturbed replica: replicas appended on a busy machine run slower.
        if key == 'ns/day':
            combined[key] = float(np.max(values))
        elif key == 's per body-step':
            combined[key] = float(np.min(values))
        else:
            combined[key] = np.mean(values, axis=0) if not np.isscalar(value) else float(np.mean(values))
            if len(values) > 1:
                combined[key+' +-'] = standard_error(values)
    return combined


def errors(measured, truth):
    """Relative errors of scalars (with their standard error, measurement and truth combined) and
    root-mean-square differences of arrays."""
    e = {}
    if measured.get('status') != 'ok':
        return e
    for key, value in truth.items():
        if key not in measured or key.endswith(' +-'):
            continue
        if key in ('O-O RDF', 'VACF'):
            error = float(np.sqrt(np.mean((np.asarray(measured[key])-np.asarray(value))**2)))
            # The noise floor of that difference: what it would be from the standard errors alone.
            noise = np.hypot(measured.get(key+' +-', 0.0), truth.get(key+' +-', 0.0))
            if np.any(noise > 0):
                e[key+' +-'] = float(np.sqrt(np.mean(np.square(noise))))
        elif np.isscalar(value):
            error = abs(measured[key]-value)/abs(value)
            spread = math.hypot(measured.get(key+' +-', 0.0), truth.get(key+' +-', 0.0))/abs(value)
            if np.isfinite(spread) and spread > 0:
                e[key+' +-'] = spread
        else:
            continue
        if np.isfinite(error):  # too short a run gives no diffusion, say
            e[key] = error
    return e


def main(argv=None):
    parser = argparse.ArgumentParser(description='Speed against error of integrators for rigid bodies.')
    parser.add_argument('--quick', action='store_true', help='a few ps per run: checks the machinery, not the numbers')
    parser.add_argument('--out', default='out/speed_vs_error')
    parser.add_argument('--threads', type=int, default=0, help='CPU threads per Context (default: cores / MPI ranks)')
    parser.add_argument('--platform', default='CPU', choices=['CPU', 'OpenCL', 'CUDA'])
    parser.add_argument('--precision', default='mixed', help='OpenCL and CUDA precision (default mixed)')
    parser.add_argument('--replicas', type=int, default=0, help='replicas of each S2 run (default 3)')
    parser.add_argument('--parts', default='s1,s2,stability,tconf', help='which parts to run (default all)')
    parser.add_argument('--tconf-replicas', type=int, default=0, help='replicas of part tconf (default 32)')
    parser.add_argument('--tconf-append', action='store_true',
                        help="add part tconf's replicas to those in --out's configurational.csv (new starts and seeds)")
    parser.add_argument('--s2-append', action='store_true',
                        help=f"add part s2's replicas to those in --out's {S2_REPLICAS} (new starts and seeds)")
    parser.add_argument('--s2-viscosities', default='',
                        help='the viscosities (P) part s2 runs (default all); with --s2-append, the others keep their earlier replicas')
    parser.add_argument('--s2-integrators', default=','.join(INTEGRATORS),
                        help='the integrators part s2 runs beside its references (default all); with --s2-append, the '
                             "others' rows keep their earlier replicas")
    parser.add_argument('--s2-rows', default='',
                        help='with --s2-append, only these rows, as VISCOSITY:INTEGRATOR:STEP_FS separated by commas, and no '
                             'references: for rows whose own standard error is too large (their paired errors keep the pairs '
                             'they have)')
    args = parser.parse_args(argv)
    viscosities = [0.01, 0.1, 1.0]
    args.s2_integrators = args.s2_integrators.split(',')
    if not set(args.s2_integrators) <= set(INTEGRATORS):
        parser.error(f'--s2-integrators: choose from {",".join(INTEGRATORS)}')
    args.s2_viscosities = [float(v) for v in args.s2_viscosities.split(',')] if args.s2_viscosities else viscosities
    if not set(args.s2_viscosities) <= set(viscosities):
        parser.error(f'--s2-viscosities: choose from {",".join(str(v) for v in viscosities)}')
    args.s2_rows = [parse_s2_row(text, viscosities, parser) for text in args.s2_rows.split(',')] if args.s2_rows else []
    if args.s2_rows and not args.s2_append:
        parser.error('--s2-rows adds replicas to rows that have them: use it with --s2-append')
    ranks = int(os.environ.get('OMPI_COMM_WORLD_SIZE', os.environ.get('PMI_SIZE', '1')))
    if args.threads == 0:
        args.threads = max(1, (os.cpu_count() or 1)//ranks)
    args.sample_fs = 10.0
    args.replicas = args.replicas or (2 if args.quick else 3)
    args.start_equilibration_ps, args.start_spacing_ps = (0.5, 0.5) if args.quick else (40.0, 20.0)
    args.equilibration_ps, args.production_ps, args.reference_ps = (0.2, 1.5, 2.0) if args.quick else (1.0, 15.0, 25.0)
    args.free_bodies, args.free_body_time, args.helicoid_ps = (10, 4, 5.0) if args.quick else (200, 100, 200.0)
    args.stability_steps = 200 if args.quick else 100000
    args.tconf_replicas = args.tconf_replicas or (2 if args.quick else 32)
    water_steps = WATER_STEPS
    free_steps = [1.0, 2.0, 4.0, 8.0, 16.0]
    parts = set(args.parts.split(','))
    rows, stability = [], []

    if 's1' in parts:
        # ExactFlow's step costs 1.3x BAOAB's on force-free bodies (two half flows): one more step
        # size lets its front reach the competitors' fastest point.
        tasks = [{'integrator': name, 'step_fs': h, 'seed': 11, 'args': args} for name in SCHEMES
                 for h in free_steps+([2*free_steps[-1]] if name == 'ExactFlow' else [])]
        results = distribute(run_free_bodies, tasks, 'S1 free coupled bodies')
        if results is not None:
            truth = s1_truth()
            for task, result in zip(tasks, results):
                rows.append(row('S1 free coupled bodies', S1_VISCOSITY, task, result, errors(result, truth)))

    out = pathlib.Path(args.out)
    if 's2' in parts:
        earlier = read_replicas(out/S2_REPLICAS) if args.s2_append else []
        first = 1+max((r['replica'] for r in earlier), default=-1)
        n = args.replicas
        # Seeded by the first replica: appended replicas start from configurations of their own.
        args.starts = starts_per_rank(args, n, ranks, 5+first, None, 'S2 starting configurations (0.01 P)')
        # --s2-rows: the rows' own replicas only; their references have enough.
        reference_tasks = [{'viscosity': eta, 'integrator': 'ExactFlow', 'step_fs': 0.5, 'seed': 101+first+r, 'replica': r, 'args': args}
                           for eta in args.s2_viscosities for r in range(n) if not args.s2_rows]
        saved = args.production_ps
        args.production_ps = args.reference_ps
        references = distribute(run_water, reference_tasks, 'S2 reference runs (0.5 fs)') if reference_tasks else []
        args.production_ps = saved
        runs = args.s2_rows or [(eta, name, h) for eta in args.s2_viscosities for name in args.s2_integrators for h in water_steps]
        tasks = [{'viscosity': eta, 'integrator': name, 'step_fs': h, 'seed': 7+first+r, 'replica': r, 'args': args}
                 for eta, name, h in runs for r in range(n)]
        results = distribute(run_water, tasks, 'S2 rigid water')
        if results is not None:
            records = earlier+[{'reference': reference, 'viscosity': t['viscosity'], 'integrator': t['integrator'],
                                'step (fs)': t['step_fs'], 'replica': first+t['replica'], 'result': r}
                               for reference, pairs in ((True, zip(reference_tasks, references)), (False, zip(tasks, results)))
                               for t, r in pairs]
            write_replicas(out/S2_REPLICAS, records)
            rows += s2_rows(records, viscosities, water_steps)

    if 'stability' in parts:
        candidates = [0.1, 0.2, 0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 10.0]
        # Integrator by integrator, so that ranks taking every size-th task share the costly ones
        # (the Original scheme is refused at once) evenly; the table lists them by viscosity.
        tasks = [{'viscosity': eta, 'integrator': name, 'candidates': candidates, 'args': args} for name in INTEGRATORS for eta in viscosities]
        results = distribute(stability_task, tasks, 'stability (64 waters)')
        if results is not None:
            order = sorted(range(len(tasks)), key=lambda i: (tasks[i]['viscosity'], INTEGRATORS.index(tasks[i]['integrator'])))
            for task, result in ((tasks[i], results[i]) for i in order):
                stability.append({'viscosity (P)': task['viscosity'], 'integrator': task['integrator'],
                                  'largest stable step (fs)': result['largest stable step (fs)']})

    if 'tconf' in parts:
        earlier = report.read_csv(out/'configurational.csv') if args.tconf_append else []
        records = configurational_temperature(args, ranks, first_replica=1+max((r['replica'] for r in earlier), default=-1))
        if records is not None:
            records = earlier+records
            report.write_configurational(out, records, TEMPERATURE, peer=TCONF_RUNS[0])

    if (rows or stability) and (out/'results.csv').exists():
        # A run of some parts keeps the other scenes' rows of an earlier run (S1 before S2); a run
        # of the stability part alone keeps them all.
        scenes = {r['scene'].split(' (')[0] for r in rows}
        kept = [r for r in report.read_csv(out/'results.csv') if r['scene'].split(' (')[0] not in scenes]
        rows = sorted(rows+kept, key=lambda r: r['scene'][:2])
    if rows and not stability and (out/'stability.csv').exists():
        # A run of some parts keeps the stability table of an earlier full run.
        with open(out/'stability.csv', encoding='utf-8') as f:
            stability = list(csv.DictReader(f))
    if rows or stability:
        report.write(out, rows, stability)
    return 0


def parse_s2_row(text, viscosities, parser):
    """(viscosity, integrator, step) from --s2-rows' VISCOSITY:INTEGRATOR:STEP_FS."""
    parts = text.split(':')
    try:
        row = (float(parts[0]), parts[1], float(parts[2]))
    except (ValueError, IndexError):
        parser.error(f'--s2-rows: {text!r} is not VISCOSITY:INTEGRATOR:STEP_FS (for example 0.01:BAOAB:1)')
    if len(parts) != 3 or row[0] not in viscosities or row[1] not in INTEGRATORS or row[2] not in WATER_STEPS:
        parser.error(f'--s2-rows: {text!r}: viscosity one of {viscosities}, integrator one of {INTEGRATORS}, step one of {WATER_STEPS}')
    return row


def s2_rows(records, viscosities, water_steps):
    """The S2 table's rows from every replica's record: the references' mean is the truth of the
    dynamical observables at their viscosity; the configurational truth pools every reference."""
    def results(viscosity, integrator, step_fs, reference=False):
        return [r['result'] for r in records if r['reference'] == reference and
                (r['viscosity'], r['integrator'], r['step (fs)']) == (viscosity, integrator, step_fs)]
    references = {eta: results(eta, 'ExactFlow', 0.5, reference=True) for eta in viscosities}
    # Configurational observables do not depend on the viscosity: their truth pools every reference.
    pooled = combine([r for eta in viscosities for r in references[eta]])
    rows = []
    for eta in viscosities:
        if not references[eta]:
            continue  # a viscosity none of the runs gathered (--s2-viscosities)
        reference = combine(references[eta])
        rows.append(row('S2 water (reference)', eta, {'integrator': 'ExactFlow', 'step_fs': 0.5}, reference, {}))
        exact = {'T translational (K)': TEMPERATURE, 'T rotational (K)': TEMPERATURE}  # for every integrator
        truth = {k: v for k, v in reference.items() if k.split(' +-')[0] in report.DYNAMICAL}
        truth.update({k: v for k, v in pooled.items() if k.split(' +-')[0] in report.CONFIGURATIONAL and k.split(' +-')[0] not in exact})
        truth.update(exact)
        for name in INTEGRATORS:
            for h in water_steps:
                if not results(eta, name, h):
                    continue  # an integrator none of the runs ran (--s2-integrators)
                measured = combine(results(eta, name, h))
                error = errors(measured, truth)
                paired, count = paired_dynamical_errors(records, eta, name, h) if measured.get('status') == 'ok' else ({}, 0)
                error.update(paired)
                rows.append(row('S2 water', eta, {'integrator': name, 'step_fs': h}, measured, error))
                if paired:
                    rows[-1]['paired replicas'] = count
    return rows


def paired_dynamical_errors(records, viscosity, integrator, step_fs):
    """Errors of the scalar dynamical observables against the reference runs from the same starts
    (replica r of every run starts from start r): the spread between starts, which both share
    (their diffusion constants correlate by 0.1-0.55), leaves the standard error. Replicas without
    a reference from their start (or the other way round) are left out of these errors. Returns the
    errors and the number of pairs."""
    def by_replica(reference, name, h):
        return {r['replica']: r['result'] for r in records if r['reference'] == reference and r['viscosity'] == viscosity and
                (r['integrator'], r['step (fs)']) == (name, h) and r['result'].get('status') == 'ok'}
    measured, references = by_replica(False, integrator, step_fs), by_replica(True, 'ExactFlow', 0.5)
    common = sorted(set(measured) & set(references))
    e = {}
    for key in report.DYNAMICAL:
        if len(common) < 2 or not all(np.isscalar(run[r].get(key)) and np.isfinite(run[r][key]) for run in (measured, references)
                                      for r in common):
            continue
        error, spread = report.paired_relative_error([measured[r][key] for r in common], [references[r][key] for r in common])
        e[key], e[key+' +-'] = abs(error), spread
    return e, len(common)


def write_replicas(path, records):
    """Every S2 run's own observables (JSON, arrays as lists), so that later runs can add replicas."""
    def plain(value):
        if isinstance(value, dict):
            return {k: plain(v) for k, v in value.items()}
        if isinstance(value, (np.ndarray, list, tuple)):
            return [plain(v) for v in value]
        if isinstance(value, (float, np.floating)):
            return float(f'{float(value):.10g}')
        return value.item() if isinstance(value, np.generic) else value
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps([plain(r) for r in records], separators=(',', ':')), encoding='utf-8')


def read_replicas(path):
    """Records written by write_replicas, checked: an append must not silently start over."""
    if not path.exists():
        raise SystemExit(f'--s2-append: {path} does not exist; run --parts s2 without --s2-append first')
    records = json.loads(path.read_text(encoding='utf-8'))
    needed = {'reference', 'viscosity', 'integrator', 'step (fs)', 'replica', 'result'}
    for i, r in enumerate(records):
        if not isinstance(r, dict) or not needed <= set(r) or not isinstance(r['result'], dict):
            raise SystemExit(f'{path}: record {i} is not an S2 run record (needs {sorted(needed)})')
        r['result'] = {k: np.array(v) if isinstance(v, list) else v for k, v in r['result'].items()}
    return records


def row(scene, viscosity, task, result, error):
    r = {'scene': scene, 'viscosity (P)': viscosity, 'integrator': task['integrator'], 'step (fs)': task['step_fs'],
         'status': result.get('status', 'ok')}
    for key, value in result.items():
        if key != 'status' and np.isscalar(value):
            r[key] = value
    for key, value in error.items():
        r['error '+key] = value
    return r


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    sys.exit(main())
