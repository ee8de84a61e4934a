"""Run independent replicas of a simulation over MPI ranks and reduce their observables.

Each replica gets its own seed and Context; observables (numbers or numpy arrays) come back as the
mean over replicas and its standard error (replicas are independent, so the error of the mean is
their spread over sqrt(R)). Without MPI, or with one rank, the replicas run one after another.

    from rigidlangevin.ensemble import run_ensemble

    def replica(index, seed):
        ... build a Context with seed, run it ...
        return {'temperature': t, 'msd': msd_array}

    result = run_ensemble(replica, replicas=8, label='water')   # mean and error on rank 0, None elsewhere

Run it on several processes with `mpirun -np 4 python script.py` (Open MPI; add
`--allow-run-as-root` as root). On a cluster, launch the same script with the site's MPI launcher
(srun, mpiexec) and one rank per core or per GPU; ranks take replicas index = rank, rank + size, ...
"""
import math
import os

import numpy as np
from tqdm import tqdm

# Variables MPI launchers (Open MPI, MPICH/Hydra, PMIx, Slurm's PMI) set in each rank's environment.
_LAUNCHER_VARIABLES = ('OMPI_COMM_WORLD_SIZE', 'PMI_SIZE', 'PMIX_RANK', 'MPI_LOCALNRANKS')


def _communicator():
    """MPI.COMM_WORLD when launched by an MPI launcher, else None: importing mpi4py in a plain
    process would start MPI as a singleton, which then stops that process from launching mpirun."""
    if not any(v in os.environ for v in _LAUNCHER_VARIABLES):
        return None
    try:
        from mpi4py import MPI
    except ImportError:
        return None
    return MPI.COMM_WORLD


def broadcast(value, comm=None):
    """Rank 0's `value` on every rank (the value itself without MPI): for inputs that one rank
    prepares and every replica needs, such as equilibrated starting configurations."""
    comm = comm if comm is not None else _communicator()
    return comm.bcast(value, root=0) if comm is not None else value


class EnsembleResult(dict):
    """Observable name -> (mean, standard error) for every numeric observable; also the number of
    replicas, their seeds and every replica's own values (in `values`, anything they returned)."""

    def __init__(self, values, seeds):
        super().__init__()
        self.replicas = len(seeds)
        self.seeds = seeds
        self.values = values
        for name in values[0]:
            try:
                stacked = np.array([v[name] for v in values], dtype=float)
            except (TypeError, ValueError):
                continue
            mean = stacked.mean(axis=0)
            error = stacked.std(axis=0, ddof=1)/math.sqrt(len(values)) if len(values) > 1 else np.full_like(mean, np.nan)
            self[name] = (mean, error)


def run_ensemble(replica, replicas, base_seed=1, label='ensemble', comm=None, progress=True):
    """Run `replicas` independent replicas spread over the ranks of an MPI communicator.

    Parameters
    ----------
    replica : callable(index, seed) -> dict
        Runs one replica and returns its observables, each a number or a numpy array (the same
        shape in every replica).
    replicas : int
        How many replicas.
    base_seed : int
        Replica i gets seed base_seed + i (never 0, which OpenMM takes as "pick one").
    label : str
        A name for the progress line.
    comm : mpi4py communicator, optional
        Defaults to MPI.COMM_WORLD when the process was started by an MPI launcher.
    progress : bool
        Show a progress line on rank 0's standard error.

    Returns
    -------
    EnsembleResult on rank 0 (the mean and standard error of every observable), None on other ranks.
    """
    comm = comm if comm is not None else _communicator()
    rank = comm.Get_rank() if comm is not None else 0
    size = comm.Get_size() if comm is not None else 1
    mine = list(range(rank, replicas, size))
    results = []
    # Ranks run in step, so rank 0's share tells how far the whole ensemble is. tqdm draws a bar
    # on a terminal and keeps quiet when stderr is a file or a pipe.
    for index in tqdm(mine, desc=f'{label} ({size} rank(s))', unit='replica', unit_scale=size,
                      disable=None if (progress and rank == 0) else True, leave=False):
        seed = base_seed+index
        results.append((index, seed, replica(index, seed)))
    gathered = comm.gather(results, root=0) if comm is not None else [results]
    if rank != 0:
        return None
    everything = sorted((item for part in gathered for item in part), key=lambda item: item[0])
    return EnsembleResult([item[2] for item in everything], [item[1] for item in everything])
