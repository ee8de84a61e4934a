#!/usr/bin/env bash
# Times RigidBrownianIntegrator's step against RigidMultiblobsWall's on the boomerang suspensions above
# a wall, in alternating blocks, and writes
# benchmarks/hydrodynamics/results/brownian_vs_rigid_multiblobs_wall.{json,md,png}.
#
#   bash benchmarks/peers/run_brownian_vs_rigid_multiblobs_wall.sh [--sizes 16 64 256] [--pairs 4]
#
# Needs the project's .venv (scripts/setup.sh) and the peer's folder (scripts/peers/setup_rigid_multiblobs_wall.sh;
# --peer to name another). About 15 minutes to 256 bodies on 2 cores; run it when the machine is quiet
# (the table records the load averages).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$ROOT"
OPENMM_CPU_THREADS="${OPENMM_CPU_THREADS:-2}" .venv/bin/python benchmarks/hydrodynamics/brownian_vs_rigid_multiblobs_wall.py "$@"
