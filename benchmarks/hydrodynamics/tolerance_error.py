"""What the Krylov tolerance costs and what it buys (issue 60: the tolerance chosen from the error it
causes, not from round-off).

The boomerang suspensions of boomerang_suspension.py (15-blob bodies at 5% volume fraction; lengths
in um taken as 1000 nm), in water at 300 K, on the CPU platform with hydrodynamic interactions solved
matrix-free (KrylovSolver). For each integrator and tolerance, one step from the same state with the
same random numbers (the same seed), against the same step at the reference tolerance 1e-12:

  - RigidBrownianIntegrator, dt = 0.01 s, above a no-slip wall at z = 0 (the colloid scene) and in
    open space: the error is |dx - dx_ref| / |dx_ref| over all particles' displacements dx;
  - RigidLangevinIntegrator (BAOAB, the coupled midpoint friction step), blobs of water's density,
    h = m/gamma of a lone blob and, strongly damped, 30 times that, open space, velocities drawn at
    300 K from one seed: the error is |v - v_ref| / |v_ref - v_0| over all particles' velocity
    changes in the step.

The step's error bounds what the tolerance does to what users measure: a mean or a covariance of
the motion (drift, diffusion, a distribution sampled) is off by at most about the step's relative
error (twice it for a covariance), whatever the run's length, since every step errs alike. Also the
Krylov iterations of the step (integrator.getKrylovIterations()) and its wall-clock seconds (one step
after one untimed step; taken on a shared machine, so the iterations are the robust measure).

    python benchmarks/hydrodynamics/tolerance_error.py [--sizes 16 64 256] [--out benchmarks/hydrodynamics/results]

Writes tolerance_error.csv, .md (the table) and .png (error and seconds against tolerance).
"""
import argparse
import csv
import os
import pathlib
import sys
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import boomerang_suspension  # noqa: E402

TOLERANCES = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6]
REFERENCE_TOLERANCE = 1e-8
VISCOSITY = 0.89*rl.centipoise
BROWNIAN_STEP = 0.01*unit.second
WATER_AMU_PER_NM3 = 602.214  # 1 g/cm^3
STIFF = 'Langevin, h = 30 m/gamma'
CASES = [('Brownian', 'wall'), ('Brownian', 'open'), ('Langevin', 'open'), (STIFF, 'open')]


def blob_mass_amu(radius_nm):
    return WATER_AMU_PER_NM3*4/3*np.pi*radius_nm**3


def langevin_step(radius_nm):
    """m/gamma of a lone blob of water's density (ps)."""
    viscosity = VISCOSITY.value_in_unit(rl.centipoise)*1e-2*60221.4  # amu/(nm ps)
    return blob_mass_amu(radius_nm)/(6*np.pi*viscosity*radius_nm)


def system_and_integrator(scene, kind, where, tolerance):
    """The scene's bodies as a System (one particle per blob) and an integrator with interactions."""
    radius = 1000*scene['blob_radius_um']
    positions = 1000*np.array(scene['blob_positions_um'])
    if kind == 'Brownian':
        integrator = rl.RigidBrownianIntegrator(300*unit.kelvin, VISCOSITY, BROWNIAN_STEP)
    else:
        h = langevin_step(radius)*(30 if kind == STIFF else 1)
        integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, VISCOSITY, h*unit.picoseconds)
        integrator.setScheme(rl.RigidLangevinIntegrator.BAOAB)
    system = mm.System()
    offsets = scene['body_blob_offsets']
    for start, end in zip(offsets[:-1], offsets[1:]):
        particles = [system.addParticle(blob_mass_amu(radius)) for _ in range(start, end)]
        integrator.addRigidBody(particles)
        for p in particles:
            integrator.setParticleRadius(p, radius*unit.nanometer)
    integrator.setHydrodynamicInteractions(True)
    integrator.setHydrodynamicSolver(integrator.KrylovSolver)
    integrator.setHydrodynamicTolerance(tolerance)
    if where == 'wall':
        integrator.setWall(0.0)
    integrator.setRandomNumberSeed(7)
    return system, integrator, positions


def one_step(scene, kind, where, tolerance, threads):
    """(the change the second step makes to the particles' positions or velocities, its Krylov
    iterations, its seconds): one untimed step first, from the same state and seed every time."""
    system, integrator, positions = system_and_integrator(scene, kind, where, tolerance)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'), {'Threads': str(threads)})
    context.setPositions(positions)
    if kind != 'Brownian':
        context.setVelocitiesToTemperature(300*unit.kelvin, 11)
    integrator.step(1)
    quantity = 'getPositions' if kind == 'Brownian' else 'getVelocities'
    before = getattr(context.getState(**{quantity: True}), quantity)(asNumpy=True)._value
    start = time.perf_counter()
    integrator.step(1)
    context.getState(getEnergy=True)
    seconds = time.perf_counter()-start
    after = getattr(context.getState(**{quantity: True}), quantity)(asNumpy=True)._value
    return after-before, list(integrator.getKrylovIterations()), seconds


def measure(sizes, threads):
    rows = []
    for size in sizes:
        scene = boomerang_suspension.scene(size)
        for kind, where in CASES:
            reference, _, _ = one_step(scene, kind, where, REFERENCE_TOLERANCE, threads)
            for tolerance in TOLERANCES+[REFERENCE_TOLERANCE]:
                change, iterations, seconds = one_step(scene, kind, where, tolerance, threads)
                error = np.linalg.norm(change-reference)/np.linalg.norm(reference)
                rows.append({'bodies': size, 'integrator': kind, 'solvent': where, 'tolerance': tolerance,
                             'step_error': f'{error:.3g}', 'iterations': '/'.join(map(str, iterations)),
                             'products': sum(iterations), 'seconds': f'{seconds:.3g}'})
                print(rows[-1], flush=True)
    return rows


def write(rows, out):
    out.mkdir(parents=True, exist_ok=True)
    with open(out/'tolerance_error.csv', 'w', encoding='utf-8', newline='') as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    lines = ['| bodies | integrator | solvent | tolerance | step error | iterations | products | seconds |', '|---|---|---|---|---|---|---|---|']
    lines += [f"| {r['bodies']} | {r['integrator']} | {r['solvent']} | {r['tolerance']:g} | {r['step_error']} | {r['iterations']} | "
              f"{r['products']} | {r['seconds']} |" for r in rows]
    (out/'tolerance_error.md').write_text('\n'.join(lines)+'\n', encoding='utf-8')


def plot(rows, out):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for kind, where in CASES:
        for size in sorted({r['bodies'] for r in rows}):
            mine = [r for r in rows if (r['integrator'], r['solvent'], r['bodies']) == (kind, where, size) and r['tolerance'] > REFERENCE_TOLERANCE]
            if not mine:
                continue
            x = [r['tolerance'] for r in mine]
            label = f'{kind}, {where}, {size} bodies'
            left.loglog(x, [max(float(r['step_error']), 1e-16) for r in mine], 'o-', label=label)
            right.loglog(x, [r['products'] for r in mine], 'o-', label=label)
    left.set_xlabel('Krylov tolerance')
    left.set_ylabel('relative error of one step')
    right.set_xlabel('Krylov tolerance')
    right.set_ylabel('mobility products in the step')
    left.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out/'tolerance_error.png', dpi=120)


def main():
    sys.stdout.reconfigure(encoding='utf-8')
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--sizes', type=int, nargs='+', default=[16, 64, 256])
    parser.add_argument('--threads', type=int, default=os.cpu_count())
    parser.add_argument('--out', default=str(pathlib.Path(__file__).resolve().parent/'results'))
    args = parser.parse_args()
    rows = measure(args.sizes, args.threads)
    write(rows, pathlib.Path(args.out))
    plot(rows, pathlib.Path(args.out))


if __name__ == '__main__':
    main()
