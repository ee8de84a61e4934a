"""RigidMultiblobsWall's Brownian step above the wall, timed on request: the peer's half of
benchmarks/hydrodynamics/brownian_vs_rigid_multiblobs_wall.py, which starts this in the peer's
Python and alternates blocks of its steps with blocks of the project's.

    build-peers/rigid-multiblobs-wall/venv/bin/python benchmarks/peers/rigid_multiblobs_wall_steps.py \
        --peer build-peers/rigid-multiblobs-wall --scenes SCENES.json

Reads one JSON request a line on stdin, {"num_bodies": N, "steps": k}, and answers each with one
JSON line: the wall-clock and process CPU seconds of each of k steps of its recommended scheme
(stochastic_Slip_Trapz, the settings of rigid_multiblobs_wall_driver.STEP: tolerance 1e-3, dt 0.01 s,
the preconditioner rebuilt every step) and their GMRES and Lanczos iterations. The first request
for a size builds its bodies (the scene's) and takes one untimed step. Stops at end of input.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rigid_multiblobs_wall_driver as driver  # noqa: E402  (sets the thread counts before numpy loads)
import numpy as np  # noqa: E402


def main():
    import argparse
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--peer', required=True)
    parser.add_argument('--scenes', required=True)
    args = parser.parse_args()
    peer_folder = os.path.abspath(args.peer)
    with open(args.scenes, encoding='utf-8') as f:
        scenes = {s['num_bodies']: s for s in json.load(f)['scenes']}
    peer = driver.load_peer(os.path.join(peer_folder, 'src'))
    integrators, steps_taken = {}, {}
    for line in sys.stdin:
        request = json.loads(line)
        n = request['num_bodies']
        if n not in integrators:
            bodies = driver.make_bodies(peer, scenes[n], 'wall')
            integrators[n] = driver.make_integrator(peer, bodies, 'wall', driver.STEP['tolerance'], driver.STEP['scheme'])
            np.random.seed(1)
            integrators[n].advance_time_step(driver.STEP['dt'], step=0)
            steps_taken[n] = 1
        integrator = integrators[n]
        wall, cpu, gmres, lanczos = [], [], [], []
        for _ in range(request['steps']):
            before = integrator.det_iterations_count, integrator.stoch_iterations_count
            start = driver.clock()
            integrator.advance_time_step(driver.STEP['dt'], step=steps_taken[n])
            end = driver.clock()
            steps_taken[n] += 1
            wall.append(end[0]-start[0])
            cpu.append(end[1]-start[1])
            gmres.append(integrator.det_iterations_count-before[0])
            lanczos.append(integrator.stoch_iterations_count-before[1])
        print(json.dumps({'seconds': wall, 'cpu_seconds': cpu, 'gmres': gmres, 'lanczos': lanczos,
                          'invalid_configurations': integrator.invalid_configuration_count}), flush=True)


if __name__ == '__main__':
    main()
