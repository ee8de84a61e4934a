"""Seconds per step of the issue's flagship suspension (issue 60's goal: 256 boomerangs x 15 blobs in
open space, a whole RigidLangevinIntegrator step, friction and noise, <= 0.5 s on 2 cores).

The scene and integrators are tolerance_error.py's (boomerang_suspension.py's bodies at 5% volume
fraction, water at 300 K, BAOAB at h = m/gamma of a lone blob and, strongly damped, at 30 times
that; the Krylov path at the default tolerance), on the CPU platform. After one untimed step, each
step is timed on its own (closed by a State); mean +- standard error over the steps, with the
Krylov iterations of the last step (getKrylovIterations(): the noise's Lanczos, 0, the friction's
conjugate gradients).

    python benchmarks/hydrodynamics/boomerang_step.py [--bodies 256] [--steps 8] [--threads 2] [--out results/boomerang_step.md]
"""
import argparse
import math
import os
import pathlib
import sys
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import boomerang_suspension  # noqa: E402
import tolerance_error  # noqa: E402


def seconds_per_step(scene, kind, steps, threads):
    default = rl.RigidLangevinIntegrator(300, 1, 1).getHydrodynamicTolerance()
    system, integrator, positions = tolerance_error.system_and_integrator(scene, kind, 'open', default)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'), {'Threads': str(threads)})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(300*unit.kelvin, 11)
    integrator.step(1)
    times = []
    for _ in range(steps):
        start = time.perf_counter()
        integrator.step(1)
        context.getState(getEnergy=True)
        times.append(time.perf_counter()-start)
    return np.mean(times), np.std(times, ddof=1)/math.sqrt(steps), list(integrator.getKrylovIterations())


def main():
    sys.stdout.reconfigure(encoding='utf-8')
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--bodies', type=int, default=256)
    parser.add_argument('--steps', type=int, default=8)
    parser.add_argument('--threads', type=int, default=2)
    parser.add_argument('--out', default=str(HERE/'results'/'boomerang_step.md'))
    args = parser.parse_args()
    scene = boomerang_suspension.scene(args.bodies)
    lines = [f'# {args.bodies} boomerangs (15 blobs each) in open space: one RigidLangevinIntegrator step', '',
             f'Written by benchmarks/hydrodynamics/boomerang_step.py: CPU platform, {args.threads} threads, the Krylov path at the '
             f'default tolerance; {args.steps} steps after an untimed one, mean ± standard error; load averages before '
             f'{", ".join(f"{x:.2f}" for x in os.getloadavg())}; {time.strftime("%Y-%m-%d %H:%M %Z")}.', '',
             '| step | seconds a step | Krylov iterations (Lanczos, -, friction CG) |', '|---|---|---|']
    for kind in ('Langevin', tolerance_error.STIFF):
        mean, error, iterations = seconds_per_step(scene, kind, args.steps, args.threads)
        label = 'h = m/gamma' if kind == 'Langevin' else 'h = 30 m/gamma'
        lines.append(f'| {label} | {mean:.3g} ± {error:.2g} | {tuple(iterations)} |')
        print(lines[-1], flush=True)
    pathlib.Path(args.out).write_text('\n'.join(lines)+'\n', encoding='utf-8')


if __name__ == '__main__':
    main()
