"""Rigid proteins diffusing in implicit solvent: measured diffusion against their tensor's prediction.

A protein user's path through the plugin, for each PDB file given (default: villin HP35, OpenMM's
test.pdb):

1. its System from a force field (amber14-all with OBC2 implicit solvent, no cutoff), the protein
   one rigid body, and removeInternalInteractions(): every force acts inside the body, so all go
   (the trajectory is the same; the step costs microseconds instead of milliseconds);
2. its resistance tensor the HYDROPRO way (hydrodynamics.protein(): 2.9 A spheres on the heavy
   atoms, shell extrapolated to zero bead size) in water at 20 C;
3. many copies, far apart (infinite dilution), under RigidLangevinIntegrator; the translational and
   rotational diffusion constants measured from their trajectories against the tensor's:
   D_t from the mean-square displacement of the centres of mass over lags of 10-100 ps (past the
   inertial time, about 0.3 ps), D_r from the three body axes, whose mean 1 - <u(0).u(t)> grows as
   2 D_r t at short times for any shape (D_r a third of the rotational block's trace).
   Standard errors from the spread over groups of copies.

    python examples/protein_diffusion.py [file.pdb ...] [--copies 64] [--time 1000] [--quick]
"""
import sys
import argparse
import os
import time

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit

import rigidlangevin as rl
import rigidlangevin.hydrodynamics as hydro
from rigidlangevin import statistics

TEMPERATURE = 293.15*unit.kelvin
VISCOSITY = 1.002*rl.centipoise   # water at 20 C
VILLIN = os.path.join(os.path.dirname(app.__file__), 'data', 'test.pdb')


def protein_only(path):
    """The protein of a PDB file (residues with an alpha carbon), with hydrogens added where missing."""
    pdb = app.PDBFile(path)
    modeller = app.Modeller(pdb.topology, pdb.positions)
    modeller.delete([r for r in modeller.topology.residues() if not any(a.name == 'CA' for a in r.atoms())])
    forcefield = app.ForceField('amber14-all.xml', 'implicit/obc2.xml')
    modeller.addHydrogens(forcefield)
    return modeller.topology, modeller.positions, forcefield


def one_protein(path):
    """Steps 1 and 2 for one copy: the System with what the body makes constant removed, and the tensor."""
    topology, positions, forcefield = protein_only(path)
    system = forcefield.createSystem(topology, nonbondedMethod=app.NoCutoff)
    integrator = rl.RigidLangevinIntegrator(TEMPERATURE, VISCOSITY, 10*unit.femtoseconds)
    integrator.addRigidBody(list(range(system.getNumParticles())))
    report = rl.removeInternalInteractions(system, integrator, positions)
    tensor = hydro.protein(topology, positions)
    return topology, positions, system, report, tensor


def frame(xyz, atoms):
    """Three orthonormal axes fixed in each body, from three of its atoms (bodies x 3 axes x 3)."""
    a, b, c = (xyz[:, i] for i in atoms)
    e1 = (b-a)/np.linalg.norm(b-a, axis=1)[:, None]
    v = c-a
    e2 = v-np.sum(v*e1, axis=1)[:, None]*e1
    e2 /= np.linalg.norm(e2, axis=1)[:, None]
    return np.stack([e1, e2, np.cross(e1, e2)], axis=1)


def diffuse(system, positions, tensor, copies, picoseconds, seed, platform):
    """Step 3: copies of the body 20 nm apart; centres of mass and body axes every ps."""
    n = system.getNumParticles()
    masses = np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(n)])
    xyz0 = np.array(positions.value_in_unit(unit.nanometer))
    many = mm.System()
    integrator = rl.RigidLangevinIntegrator(TEMPERATURE, VISCOSITY, 10*unit.femtoseconds)
    integrator.setRandomNumberSeed(seed)
    side = int(np.ceil(copies**(1/3)))
    all_positions = []
    for k in range(copies):
        first = many.getNumParticles()
        for m in masses:
            many.addParticle(m)
        body = integrator.addRigidBody(list(range(first, first+n)))
        integrator.setBodyHydrodynamics(body, tensor, [mm.Vec3(*p) for p in xyz0])
        offset = 20.0*np.array([k % side, (k//side) % side, k//side**2])
        all_positions += [mm.Vec3(*(p+offset)) for p in xyz0]
    context = mm.Context(many, integrator, mm.Platform.getPlatformByName(platform))
    context.setPositions(all_positions)
    context.setVelocitiesToTemperature(TEMPERATURE, seed)
    integrator.step(500)
    atoms = (0, n//2, n-1)
    centres, axes = [], []
    start = time.perf_counter()
    for _ in range(int(picoseconds)):
        integrator.step(100)
        xyz = context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(unit.nanometer).reshape(copies, n, 3)
        centres.append(np.einsum('bpi,p->bi', xyz, masses)/masses.sum())
        axes.append(frame(xyz, atoms))
    seconds = time.perf_counter()-start
    return np.array(centres), np.array(axes), 1e-3*picoseconds/seconds*86400


def measure(centres, axes, groups):
    """D_t (nm^2/ps) and D_r (1/ps) per group of copies, from slopes over lags of 10-100 ps."""
    lags = np.arange(10, min(101, len(centres)//2))
    copies = centres.shape[1]
    d_t, d_r = [], []
    for g in np.array_split(np.arange(copies), groups):
        turn = [1-np.mean(np.sum(axes[lag:, g]*axes[:-lag, g], axis=3)) for lag in lags]
        d_t.append(statistics.diffusion_constant(centres[:, g], 1.0, lags))
        d_r.append(np.polyfit(lags, turn, 1)[0]/2)
    return np.array(d_t), np.array(d_r)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('pdb', nargs='*', default=[VILLIN], help='PDB files (default: villin HP35, OpenMM test.pdb)')
    parser.add_argument('--copies', type=int, default=64)
    parser.add_argument('--time', type=float, default=1000, help='picoseconds sampled')
    parser.add_argument('--groups', type=int, default=8, help='groups of copies for the standard errors')
    parser.add_argument('--platform', default='CPU')
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--quick', action='store_true', help='16 copies, 300 ps')
    args = parser.parse_args()
    if args.quick:
        args.copies, args.time = 16, 300
    print('protein                 forces removed  energy removed (kJ/mol)  D_t predicted  D_t measured (1e-7 cm^2/s)  '
          'D_r predicted  D_r measured (1e7/s)  ns/day')
    for path in args.pdb:
        topology, positions, system, report, tensor = one_protein(path)
        d = np.array(tensor.getDiffusionTensor(TEMPERATURE, VISCOSITY, tensor.getCenterOfDiffusion()))
        predicted_t, predicted_r = np.trace(d[:3, :3])/3, np.trace(d[3:, 3:])/3
        centres, axes, speed = diffuse(system, positions, tensor, args.copies, args.time, args.seed, args.platform)
        d_t, d_r = measure(centres, axes, args.groups)
        se = lambda v: np.std(v, ddof=1)/np.sqrt(len(v))  # noqa: E731
        name = os.path.basename(path)
        # nm^2/ps to 1e-7 cm^2/s and 1/ps to 1e7/s: both a factor 1e5.
        print(f'{name:22s}  {len(report.removedForces):14d}  {report.energyOffset.value_in_unit(unit.kilojoule_per_mole):23.1f}  '
              f'{1e5*predicted_t:13.3f}  {1e5*np.mean(d_t):12.3f} +- {1e5*se(d_t):.3f}       '
              f'{1e5*predicted_r:13.3f}  {1e5*np.mean(d_r):12.3f} +- {1e5*se(d_r):.3f}  {speed:8.1f}', flush=True)


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    main()
