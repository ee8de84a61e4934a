"""The MPI ensemble runner: replicas with their own seeds, reduced to mean and standard error."""
import shutil
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from rigidlangevin.ensemble import broadcast, run_ensemble

# A replica: free Stokes particles at 300 K; returns the mean kinetic temperature and the mean
# square displacement at three lags, from its own seed.
REPLICA = textwrap.dedent('''
    import numpy as np, openmm as mm, rigidlangevin as rl
    def replica(index, seed):
        system = mm.System()
        integrator = rl.RigidLangevinIntegrator(300, 500.0, 0.002)
        integrator.setRandomNumberSeed(seed)
        for i in range(50):
            system.addParticle(18.0)
            integrator.setParticleRadius(i, 0.15)
        context = mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))
        context.setPositions([mm.Vec3(i, 0, 0) for i in range(50)])
        context.setVelocitiesToTemperature(300, seed)
        start = context.getState(getPositions=True).getPositions(asNumpy=True)._value
        msd = []
        for lag in range(3):
            integrator.step(100)
            x = context.getState(getPositions=True).getPositions(asNumpy=True)._value
            msd.append(((x-start)**2).sum(axis=1).mean())
        return {'temperature': integrator.computeSystemTemperature()._value, 'msd': np.array(msd), 'seed': seed}
''')


def test_serial_ensemble():
    namespace = {}
    exec(REPLICA, namespace)
    result = run_ensemble(namespace['replica'], replicas=4, base_seed=10, progress=False)
    assert result.replicas == 4 and result.seeds == [10, 11, 12, 13]
    mean, error = result['msd']
    assert mean.shape == (3,) and np.all(error > 0) and np.all(np.diff(mean) > 0)
    assert result['seed'][0] == pytest.approx(11.5)
    # Different seeds give different replicas.
    assert len({v['temperature'] for v in result.values}) == 4
    # Without MPI, broadcast hands the value back.
    assert broadcast([1, 2]) == [1, 2]


def test_mpi_ensemble_on_two_ranks(tmp_path):
    script = tmp_path/'ensemble.py'
    script.write_text(REPLICA+textwrap.dedent('''
        from mpi4py import MPI
        from rigidlangevin.ensemble import broadcast, run_ensemble
        # Rank 0's value reaches every rank.
        shared = broadcast({'start': 42} if MPI.COMM_WORLD.Get_rank() == 0 else None)
        # Rank 0 prints what every rank received: two ranks printing at once can interleave one line.
        received = MPI.COMM_WORLD.gather(shared['start'])
        if received is not None:
            print('shared', received)
        result = run_ensemble(replica, replicas=4, base_seed=10)
        if result is not None:
            print('seeds', result.seeds, 'temperature', result['temperature'][0], result['temperature'][1])
    '''), encoding='utf-8')
    # scripts/setup.sh installs Open MPI, so mpirun is expected: its absence fails here.
    assert shutil.which('mpirun'), 'mpirun not found: run scripts/setup.sh (it installs openmpi-bin)'
    command = ['mpirun', '--oversubscribe', '-np', '2', sys.executable, str(script)]
    import os
    if os.geteuid() == 0:
        command.insert(1, '--allow-run-as-root')
    result = subprocess.run(command, capture_output=True, encoding='utf-8', timeout=300)
    assert result.returncode == 0, result.stderr
    line = [l for l in result.stdout.splitlines() if l.startswith('seeds')]
    assert len(line) == 1 and 'seeds [10, 11, 12, 13]' in line[0]
    assert [l for l in result.stdout.splitlines() if l.startswith('shared')] == ['shared [42, 42]']
    # The same replicas run serially give the same reduced result.
    namespace = {}
    exec(REPLICA, namespace)
    serial = run_ensemble(namespace['replica'], replicas=4, base_seed=10, progress=False)
    assert float(line[0].split()[-2]) == pytest.approx(serial['temperature'][0], rel=1e-12)
