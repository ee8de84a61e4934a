"""SSD/E and SSD/RF liquid water at 298 K and 1 atm against the published density and diffusion.

Fennell & Gezelter (J. Chem. Phys. 120, 9175 (2004), the table of liquid properties at ambient
conditions, reproduced in Fennell's dissertation, waterChapter.tex) give for their two models:

    SSD/E    density 0.996(1) g/cm^3   self-diffusion 2.51(18) 1e-5 cm^2/s
    SSD/RF   density 0.997(1) g/cm^3   self-diffusion 2.32(6)  1e-5 cm^2/s

The set-up is the one the authors' code ran these models with (OOPSE, in the OpenMD/OpenMD
repository): 256 molecules, 9 A cutoff, SSD/E without a reaction field and SSD/RF with one of
dielectric 80; dipole only (OOPSE's 2004 force field gives these types no quadrupole); the pair
energy switched by a cubic to zero at the cutoff. Where the switch starts the paper does not say:
OOPSE 2.0's samples set 7.7 A, and its set-up chose 0.95 of the cutoff (8.55 A) for a
reaction-field run that set none; SSD/RF is run with both (CASES). As in the paper the diffusion
constant is the average of five NVE runs, from the mean-square displacement of the molecules'
centres, without a finite-size correction (so it is that of a 256-molecule box).

Per model:
1. The lattice is minimised, melted at 400 K and brought to 298 K at constant volume, then run at
   298 K and 1 atm: LangevinMiddleIntegrator (1/ps, 2 fs) with the molecules' constraints and a
   MonteCarloBarostat. The density is a property of the force, not of the integrator; this is
   OpenMM's own NPT machinery. Mean density and potential energy per molecule, with standard errors
   from block averages.
2. The box is scaled (molecule centres) to the mean density. Five NVE runs under
   RigidLangevinIntegrator at zero viscosity (velocity Verlet with the symplectic rotation the paper
   used), each after its own thermalisation at 298 K under the same integrator at 0.01 P. D is the
   slope of the mean-square displacement of the molecules' centres relative to the box's centre of
   mass over lags 2-10 ps (/6); its standard error is over the five runs. Energy drift of each NVE
   run is reported.

Writes table.md and properties.csv to --out.

    python examples/ssd_properties.py              # about 27 minutes on 2 cores (9 per row)
    python examples/ssd_properties.py --quick      # a minute: the machinery, not the numbers
"""
import sys
import argparse
import csv
import math
import pathlib
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl
from rigidlangevin import statistics
from rigidlangevin.statistics import block_error, standard_error

#: Fennell & Gezelter 2004: model -> (density g/cm^3, its error, D 1e-5 cm^2/s, its error).
PUBLISHED = {'SSD/E': (0.996, 0.001, 2.51, 0.18), 'SSD/RF': (0.997, 0.001, 2.32, 0.06)}
REACTION_FIELD = {'SSD/E': 1.0, 'SSD/RF': 80.0}  # dielectric 1: no reaction field
MOLECULES = 256
CUTOFF = 0.9  # nm
#: (model, switching distance in A). 7.7 A is what the authors' OOPSE 2.0 samples set
#: (samples/water/ssde/ssde.md, ssdrf/ssdrf.md); 8.55 A (0.95 of the cutoff) is what OOPSE's set-up
#: (SimSetup.cpp, 2004) chose for a reaction-field run that set none. The paper does not say which
#: its runs had; SSD/RF is run with both.
CASES = [('SSD/E', 7.7), ('SSD/RF', 8.55), ('SSD/RF', 7.7)]
TEMPERATURE, PRESSURE = 298.0, 1.01325  # K, bar
STEP = 0.002  # ps
AVOGADRO = 6.02214076e23
MSD_LAGS_PS = (2.0, 10.0)
SAMPLE_PS = 0.1  # between samples of centres


def grams(system):
    """The System's mass in g."""
    return sum(system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles()))/AVOGADRO


def density(mass_g, box_volume_nm3):
    """g/cm^3 (1 nm^3 = 1e-21 cm^3)."""
    return mass_g/(box_volume_nm3*1e-21)


def box_volume(state):
    a, b, c = state.getPeriodicBoxVectors(asNumpy=True).value_in_unit(unit.nanometer)
    return float(np.dot(a, np.cross(b, c)))


def unwrapped(frames, box):
    """Positions (frames x molecules x 3, nm) followed through periodic wrapping: each step is the
    minimum image of the displacement between consecutive frames (frames close enough in time that
    no molecule moves half a box between them)."""
    frames = np.asarray(frames, dtype=float)
    steps = np.diff(frames, axis=0)
    steps -= box*np.round(steps/box)
    return np.concatenate([frames[:1], frames[:1]+np.cumsum(steps, axis=0)])


def relative_to_centre_of_mass(trajectory):
    """Positions (frames x molecules x 3) of equal-mass molecules less their centre of mass. At zero
    viscosity the total momentum is conserved, but the thermalisation before a run leaves it at a
    random value (the whole box then drifts by about 0.2 nm in 10 ps at 298 K, a tenth of the
    molecules' own mean-square displacement, quadratic in time); the paper's NVE runs had none."""
    return trajectory-trajectory.mean(axis=1, keepdims=True)


def diffusion_constant(trajectory, dt, lags):
    """D (nm^2/ps) from a trajectory (frames x molecules x 3, unwrapped) sampled every dt ps: the
    mean-square displacement's slope over lags[0]..lags[1] ps."""
    first, last = (int(round(lag/dt)) for lag in lags)
    return statistics.diffusion_constant(trajectory, dt, range(first, last+1))


def npt(system, positions, platform, args, seed):
    """Minimise, melt at 400 K and cool to 298 K at constant volume, then sample the density and the
    potential energy per molecule at 298 K and 1 atm. Returns both series and the final State."""
    integrator = mm.LangevinMiddleIntegrator(400*unit.kelvin, 1/unit.picosecond, STEP*unit.picosecond)
    integrator.setRandomNumberSeed(seed)
    context = mm.Context(system, integrator, platform)
    context.setPositions(positions)
    mm.LocalEnergyMinimizer.minimize(context, 10.0, 500)
    context.setVelocitiesToTemperature(400*unit.kelvin, seed)
    integrator.step(int(round(args.melt_ps/STEP)))
    integrator.setTemperature(TEMPERATURE*unit.kelvin)
    integrator.step(int(round(args.melt_ps/STEP)))
    melted = context.getState(getPositions=True, getVelocities=True)

    barostatted = mm.XmlSerializer.clone(system)
    barostat = mm.MonteCarloBarostat(PRESSURE*unit.bar, TEMPERATURE*unit.kelvin, 25)
    barostat.setRandomNumberSeed(seed)
    barostatted.addForce(barostat)
    integrator = mm.LangevinMiddleIntegrator(TEMPERATURE*unit.kelvin, 1/unit.picosecond, STEP*unit.picosecond)
    integrator.setRandomNumberSeed(seed+1)
    context = mm.Context(barostatted, integrator, platform)
    context.setState(melted)
    integrator.step(int(round(args.npt_equilibrate_ps/STEP)))
    mass, densities, energies = grams(system), [], []
    every = int(round(args.npt_sample_ps/STEP))
    for _ in range(int(round(args.npt_ps/args.npt_sample_ps))):
        integrator.step(every)
        state = context.getState(getEnergy=True)
        densities.append(density(mass, box_volume(state)))
        energies.append(state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)/MOLECULES)
    return np.array(densities), np.array(energies), context.getState(getPositions=True)


def at_density(topology, system, state, target):
    """The System (a copy) and positions with the box scaled to `target` g/cm^3: each molecule moved
    rigidly with its centre (the site M, at the centre of mass)."""
    positions = state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)
    volume = box_volume(state)
    scale = (density(grams(system), volume)/target)**(1/3)
    scaled = positions.copy()
    for residue in topology.residues():
        atoms = [a.index for a in residue.atoms()]
        scaled[atoms] += (scale-1)*positions[atoms[-1]]
    system = mm.XmlSerializer.clone(system)
    edge = (volume*scale**3)**(1/3)
    system.setDefaultPeriodicBoxVectors(mm.Vec3(edge, 0, 0), mm.Vec3(0, edge, 0), mm.Vec3(0, 0, edge))
    return system, scaled, edge


def nve_runs(topology, system, positions, edge, platform, args, seed):
    """args.nve_runs NVE runs under RigidLangevinIntegrator at zero viscosity, each after its own
    thermalisation at 298 K and 0.01 P. Returns per run D (nm^2/ps), mean temperature (K) and the
    drift of the total energy (kJ/mol per ns per molecule)."""
    integrator = rl.RigidLangevinIntegrator(TEMPERATURE*unit.kelvin, 0.01*rl.poise, STEP*unit.picosecond)
    integrator.setRandomNumberSeed(seed)
    rl.addRigidBodies(integrator, topology, system, residues='water', positions=positions)
    context = mm.Context(system, integrator, platform)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(TEMPERATURE*unit.kelvin, seed)
    sites = [list(r.atoms())[-1].index for r in topology.residues()]
    dof = 6*MOLECULES-3  # the total momentum is conserved at zero viscosity
    boltzmann = unit.MOLAR_GAS_CONSTANT_R.value_in_unit(unit.kilojoule_per_mole/unit.kelvin)
    every = int(round(SAMPLE_PS/STEP))
    runs = []
    for _ in range(args.nve_runs):
        integrator.setViscosity(0.01*rl.poise)
        integrator.step(int(round(args.thermalise_ps/STEP)))
        integrator.setViscosity(0.0)
        frames, kinetic, total = [], [], []
        for _ in range(int(round(args.nve_ps/SAMPLE_PS))+1):
            state = context.getState(getPositions=True, getEnergy=True)
            frames.append(state.getPositions(asNumpy=True).value_in_unit(unit.nanometer)[sites])
            k = state.getKineticEnergy().value_in_unit(unit.kilojoule_per_mole)
            kinetic.append(k)
            total.append(k+state.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))
            integrator.step(every)
        times = SAMPLE_PS*np.arange(len(total))
        runs.append({'D': diffusion_constant(relative_to_centre_of_mass(unwrapped(frames, edge)), SAMPLE_PS, args.msd_lags),
                     'T': float(np.mean(kinetic))*2/(dof*boltzmann),
                     'drift': float(np.polyfit(times, total, 1)[0])*1000/MOLECULES})
    return runs


def measure(model, switch, platform, args, seed):
    """One row of the table: model and switching distance (A) -> density, energy, D and their errors."""
    start = time.perf_counter()
    topology, system, positions = rl.ssd.waterBox(MOLECULES, model=model, cutoff=CUTOFF*unit.nanometer,
                                                  switchingDistance=switch*unit.angstrom,
                                                  reactionFieldDielectric=REACTION_FIELD[model])
    densities, energies, state = npt(system, positions, platform, args, seed)
    rho, rho_error = float(np.mean(densities)), block_error(densities)
    nve_system, scaled, edge = at_density(topology, system, state, rho)
    runs = nve_runs(topology, nve_system, scaled, edge, platform, args, seed+12)
    d = [r['D']*1000 for r in runs]  # nm^2/ps = 1e-2 cm^2/s = 1000 x 1e-5 cm^2/s
    published = PUBLISHED[model]
    row = {'model': model, 'switching distance (A)': switch, 'density (g/cm^3)': rho, 'density +-': rho_error,
           'potential per molecule (kJ/mol)': float(np.mean(energies)), 'potential per molecule +-': block_error(energies),
           'D (1e-5 cm^2/s)': float(np.mean(d)), 'D +-': standard_error(d),
           'NVE T (K)': float(np.mean([r['T'] for r in runs])), 'NVE T +-': standard_error([r['T'] for r in runs]),
           'largest NVE drift (kJ/mol/ns per molecule)': max(abs(r['drift']) for r in runs),
           'published density': published[0], 'published density +-': published[1],
           'published D': published[2], 'published D +-': published[3],
           'box edge at the mean density (nm)': edge, 'minutes': (time.perf_counter()-start)/60}
    for key, value, error in (('density', rho, rho_error), ('D', row['D (1e-5 cm^2/s)'], row['D +-'])):
        row[key+' minus published, in standard errors'] = (value-row['published '+key])/math.hypot(error, row['published '+key+' +-'])
    return row


def write(out, rows, args):
    """properties.csv and table.md."""
    with open(out/'properties.csv', 'w', newline='', encoding='utf-8') as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    lines = [f'{MOLECULES} molecules, {TEMPERATURE:g} K, 1 atm, {CUTOFF*10:g} A cutoff. '
             f'Density: {args.npt_ps:g} ps of LangevinMiddleIntegrator + MonteCarloBarostat (block standard errors). '
             f'D: {args.nve_runs} NVE runs of {args.nve_ps:g} ps under RigidLangevinIntegrator at zero viscosity at the mean density, '
             f'MSD slope over {args.msd_lags[0]:g}-{args.msd_lags[1]:g} ps (standard error over runs). '
             'Published: Fennell & Gezelter, J. Chem. Phys. 120, 9175 (2004). Differences in combined standard errors.', '',
             '| model | switched from (A) | density (g/cm³) | published | difference (SE) | D (1e-5 cm²/s) | published | difference (SE) | '
             'potential per molecule (kJ/mol) | NVE T (K) | largest NVE drift (kJ/mol/ns per molecule) |',
             '|---|---|---|---|---|---|---|---|---|---|---|']
    for r in rows:
        lines.append(f"| {r['model']} | {r['switching distance (A)']:g} | {r['density (g/cm^3)']:.4f} ± {r['density +-']:.4f} | "
                     f"{r['published density']} ± {r['published density +-']} | "
                     f"{r['density minus published, in standard errors']:+.1f} | {r['D (1e-5 cm^2/s)']:.2f} ± {r['D +-']:.2f} | "
                     f"{r['published D']} ± {r['published D +-']} | {r['D minus published, in standard errors']:+.1f} | "
                     f"{r['potential per molecule (kJ/mol)']:.2f} ± {r['potential per molecule +-']:.2f} | "
                     f"{r['NVE T (K)']:.1f} ± {r['NVE T +-']:.1f} | {r['largest NVE drift (kJ/mol/ns per molecule)']:.2g} |")
    (out/'table.md').write_text('\n'.join(lines)+'\n', encoding='utf-8')
    print('\n'.join(lines))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--models', default='SSD/E,SSD/RF', help='which models of CASES to run (default both)')
    parser.add_argument('--switch', type=float, help='one switching distance (A) for every model instead of CASES')
    parser.add_argument('--platform', default='CPU')
    parser.add_argument('--quick', action='store_true', help='short runs of the same steps: the machinery, not the numbers')
    parser.add_argument('--out', default='ssd_properties', help='directory for the results')
    args = parser.parse_args(argv)
    if args.quick:
        args.melt_ps, args.npt_equilibrate_ps, args.npt_ps, args.npt_sample_ps = 1.0, 1.0, 4.0, 0.1
        args.nve_runs, args.thermalise_ps, args.nve_ps, args.msd_lags = 2, 0.4, 2.0, (0.4, 1.0)
    else:
        args.melt_ps, args.npt_equilibrate_ps, args.npt_ps, args.npt_sample_ps = 20.0, 100.0, 600.0, 0.2
        args.nve_runs, args.thermalise_ps, args.nve_ps, args.msd_lags = 5, 10.0, 50.0, MSD_LAGS_PS
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    platform = mm.Platform.getPlatformByName(args.platform)
    models = args.models.split(',')
    cases = [(m, s) for m, s in CASES if m in models] if args.switch is None else [(m, args.switch) for m in models]
    rows = []
    for n, (model, switch) in enumerate(cases):
        rows.append(measure(model, switch, platform, args, seed=17+n))
        print(rows[-1], flush=True)
    write(out, rows, args)
    return 0


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    raise SystemExit(main())
