#!/usr/bin/env bash
# Times RigidMultiblobsWall on the boomerang suspensions and writes
# benchmarks/hydrodynamics/results/rigid_multiblobs_wall.{json,md,png}.
#
#   bash benchmarks/peers/run_rigid_multiblobs_wall.sh [driver options, e.g. --sizes 16 64 256]
#   NUMBA_NUM_THREADS=1 OUT=benchmarks/hydrodynamics/results/rigid_multiblobs_wall_one_thread.json bash ...
#
# Needs the project's .venv (scripts/setup.sh) for the scenes and the table, and the peer's folder
# (scripts/peers/setup_rigid_multiblobs_wall.sh; PEER= to name another). 20 minutes with 1024 bodies
# (products and solves) at niceness 10 under load 6; run it when the machine is quiet (the table records
# the load averages).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
PEER="${PEER:-$ROOT/build-peers/rigid-multiblobs-wall}"
SCENES="$ROOT/build-peers/boomerang_suspension.json"
OUT="${OUT:-$ROOT/benchmarks/hydrodynamics/results/rigid_multiblobs_wall.json}"
[ -x "$PEER/venv/bin/python" ] || { echo "no peer in $PEER: run scripts/peers/setup_rigid_multiblobs_wall.sh first" >&2; exit 1; }
cd "$ROOT"
.venv/bin/python benchmarks/hydrodynamics/boomerang_suspension.py --out "$SCENES"
NUMBA_NUM_THREADS="${NUMBA_NUM_THREADS:-2}" "$PEER/venv/bin/python" benchmarks/peers/rigid_multiblobs_wall_driver.py \
    --peer "$PEER" --scenes "$SCENES" --out "$OUT" "$@"
.venv/bin/python benchmarks/peers/rigid_multiblobs_wall_report.py "$OUT"
