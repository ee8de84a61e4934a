#!/usr/bin/env bash
# Sets up RigidMultiblobsWall (stochasticHydroTools; GPL-3, Python + numba), the peer of the
# hydrodynamic-interaction benchmarks, in a folder and a virtual environment of its own, outside the
# project's dependencies. Nothing of its code enters this repository: the script extracts a source
# snapshot that the caller provides into a git-ignored folder, and installs what it needs from PyPI.
#
#   bash scripts/peers/setup_rigid_multiblobs_wall.sh [--snapshot PATH] [--dest DIR]
#
#   --snapshot  the peer's source: a git repository (bare or not; its HEAD is extracted) or a folder
#               holding its files (default: $RMW_SNAPSHOT, else the mirror at
#               /work/.mirror/stochasticHydroTools+RigidMultiblobsWall/repo)
#   --dest      where to put it (default: build-peers/rigid-multiblobs-wall in this checkout)
#
# Afterwards DEST/src holds the peer's files, DEST/venv its Python (numpy, scipy and numba pinned to
# versions its code runs on: it uses the module imp, gone in Python 3.12, and scipy's gmres(tol=),
# gone in scipy 1.14), DEST/SNAPSHOT the snapshot's commit. benchmarks/peers/run_rigid_multiblobs_wall.sh
# runs the benchmark with it. Safe to run again: the source is extracted afresh, the venv kept.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
SNAPSHOT="${RMW_SNAPSHOT:-/work/.mirror/stochasticHydroTools+RigidMultiblobsWall/repo}"
DEST="$ROOT/build-peers/rigid-multiblobs-wall"
PYTHON="${PYTHON:-python3}"
PEER_PACKAGES=(numpy==1.24.4 scipy==1.10.1 numba==0.58.1)

fail() { echo "setup_rigid_multiblobs_wall.sh: $1" >&2; exit 1; }
while [ $# -gt 0 ]; do
    case "$1" in
        --snapshot) SNAPSHOT="${2:?--snapshot needs a path}"; shift 2 ;;
        --dest) DEST="${2:?--dest needs a folder}"; shift 2 ;;
        -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
        *) fail "unknown argument '$1' (see --help)" ;;
    esac
done

[ -e "$SNAPSHOT" ] || fail "the snapshot $SNAPSHOT is absent: RigidMultiblobsWall is not a dependency of this
project and is not shipped with it (GPL-3). Give a clone of it with --snapshot PATH (or RMW_SNAPSHOT)."

echo "==> extracting $SNAPSHOT into $DEST/src"
rm -rf "$DEST/src"
mkdir -p "$DEST/src"
if git -C "$SNAPSHOT" rev-parse --verify -q HEAD >/dev/null 2>&1; then
    COMMIT="$(git -C "$SNAPSHOT" rev-parse HEAD)"
    git -C "$SNAPSHOT" archive HEAD | tar -x -C "$DEST/src"
elif [ -f "$SNAPSHOT/multi_bodies/multi_bodies.py" ]; then
    COMMIT="unknown (a folder, not a git repository)"
    cp -r "$SNAPSHOT/." "$DEST/src/"
else
    fail "$SNAPSHOT is neither a git repository nor a folder holding multi_bodies/multi_bodies.py"
fi
[ -f "$DEST/src/multi_bodies/multi_bodies.py" ] || fail "$SNAPSHOT has no multi_bodies/multi_bodies.py: not RigidMultiblobsWall?"
echo "$COMMIT" > "$DEST/SNAPSHOT"

"$PYTHON" -c 'import sys; sys.exit(sys.version_info[:2] >= (3, 12))' \
    || fail "$PYTHON is Python 3.12 or newer; the peer imports the module imp, which 3.12 removed: set PYTHON to a Python 3.8-3.11"
if [ ! -x "$DEST/venv/bin/python" ]; then
    echo "==> creating its virtual environment $DEST/venv"
    "$PYTHON" -m venv "$DEST/venv" || fail "could not create a venv with $PYTHON (is python3-venv installed?)"
fi
echo "==> installing ${PEER_PACKAGES[*]}"
"$DEST/venv/bin/python" -m pip install -q "${PEER_PACKAGES[@]}" || fail "pip install ${PEER_PACKAGES[*]} failed (is PyPI reachable?)"

echo "==> checking that its modules import"
(cd "$DEST" && "$DEST/venv/bin/python" - "$DEST/src" <<'EOF') || fail "the peer's modules do not import (see above)"
import os, sys, warnings
warnings.simplefilter('ignore', DeprecationWarning)
src = sys.argv[1]
sys.path[:0] = [os.path.join(src, 'multi_bodies'), src]
import multi_bodies                                   # noqa: E402  (its solver, preconditioners, K products)
from mobility import mobility                         # noqa: E402
from quaternion_integrator.quaternion_integrator_multi_bodies import QuaternionIntegrator  # noqa: E402,F401
assert mobility.found_numba, 'numba was not found by the peer'
import numba, numpy, scipy                            # noqa: E402
print(f'    numpy {numpy.__version__}, scipy {scipy.__version__}, numba {numba.__version__}')
EOF
echo "RigidMultiblobsWall commit $COMMIT is set up in $DEST"
