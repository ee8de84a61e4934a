"""Bent three-bead rigid bodies with Lennard-Jones interactions in implicit water.

A few hundred rigid 'bent trimers' (three beads at 120 degrees, like a coarse-grained banana) move
as rigid bodies under RigidLangevinIntegrator: their friction is the 6x6 resistance tensor of
their three beads at the viscosity of water, their noise is the matching random force and torque.
The run prints the translational and rotational temperatures (which must both come to the bath
temperature) and the energies as it goes.

    python examples/bent_trimers.py                  # 20 ps on the CPU platform
    python examples/bent_trimers.py --steps 200 --report 50 --platform Reference
"""
import argparse
import math
import sys
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl


def build(num_bodies, box, seed):
    """System, body definitions and positions of num_bodies bent trimers on a lattice."""
    bead_mass, sigma, epsilon, arm = 40.0, 0.35, 1.0, 0.38
    angle = math.radians(120)
    shape = np.array([[arm*math.cos(angle/2), arm*math.sin(angle/2), 0],
                      [0, 0, 0],
                      [arm*math.cos(angle/2), -arm*math.sin(angle/2), 0]])
    shape -= shape.mean(axis=0)
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(box, 0, 0), mm.Vec3(0, box, 0), mm.Vec3(0, 0, box))
    nonbonded = mm.NonbondedForce()
    nonbonded.setNonbondedMethod(mm.NonbondedForce.CutoffPeriodic)
    nonbonded.setCutoffDistance(1.0)
    nonbonded.setUseDispersionCorrection(False)
    rng = np.random.default_rng(seed)
    per_side = math.ceil(num_bodies**(1/3))
    spacing = box/per_side
    bodies, positions = [], []
    for b in range(num_bodies):
        cell = np.array([b % per_side, (b//per_side) % per_side, b//per_side**2])
        rotation, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        members = []
        for bead in shape:
            members.append(system.addParticle(bead_mass))
            nonbonded.addParticle(0.0, sigma, epsilon)
            positions.append(mm.Vec3(*((cell+0.5)*spacing+rotation@bead)))
        for i in range(3):
            for j in range(i+1, 3):
                nonbonded.addException(members[i], members[j], 0.0, 1.0, 0.0)
        bodies.append(members)
    system.addForce(nonbonded)
    return system, bodies, positions


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--bodies', type=int, default=300, help='number of rigid bodies (default 300)')
    parser.add_argument('--steps', type=int, default=10000, help='number of 2 fs steps (default 10000 = 20 ps)')
    parser.add_argument('--report', type=int, default=1000, help='steps between reports (default 1000)')
    parser.add_argument('--platform', default='CPU', help='OpenMM platform (default CPU)')
    parser.add_argument('--viscosity', type=float, default=0.89, help='solvent viscosity in centipoise (default 0.89, water)')
    parser.add_argument('--temperature', type=float, default=300.0, help='bath temperature in K (default 300)')
    parser.add_argument('--seed', type=int, default=1, help='random seed (default 1)')
    args = parser.parse_args(argv)

    system, bodies, positions = build(args.bodies, box=7.0, seed=args.seed)
    integrator = rl.RigidLangevinIntegrator(args.temperature*unit.kelvin, args.viscosity*rl.centipoise, 2*unit.femtoseconds)
    integrator.setRandomNumberSeed(args.seed)
    for members in bodies:
        integrator.addRigidBody(members)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(args.platform))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(args.temperature*unit.kelvin, args.seed)

    print(f'{args.bodies} bent trimers, {integrator.getNumDegreesOfFreedom()} degrees of freedom, '
          f'{args.viscosity} cP, {args.temperature} K, 2 fs steps, platform {args.platform}')
    print(f'{"time (ps)":>10} {"T_trans (K)":>12} {"T_rot (K)":>10} {"T (K)":>8} {"potential (kJ/mol)":>19} {"kinetic (kJ/mol)":>17} {"ns/day":>8}')
    done = 0
    start = time.time()
    while done < args.steps:
        n = min(args.report, args.steps-done)
        integrator.step(n)
        done += n
        state = context.getState(getEnergy=True)
        elapsed = time.time()-start
        print(f'{done*0.002:10.2f} {integrator.computeTranslationalTemperature()._value:12.1f} '
              f'{integrator.computeRotationalTemperature()._value:10.1f} {integrator.computeSystemTemperature()._value:8.1f} '
              f'{state.getPotentialEnergy()._value:19.1f} {state.getKineticEnergy()._value:17.1f} '
              f'{done*0.002e-3/(elapsed/86400):8.2f}', flush=True)
    return 0


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')  # its tables carry ± and units: an ASCII locale must not stop it
    sys.exit(main())
