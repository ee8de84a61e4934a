#!/usr/bin/env bash
# Set up (idempotent) and run the main job: the flagship, the source's SSD water scene replayed
# (examples/ssd_scene.py: 256 SSD waters, 60 ps at each of 1, 0.1 and 0.01 P, and the heating curves;
# about 5 minutes on 2 cores; --full for the source's 1 ns runs, about 75 minutes). Results go to
# out/ssd_scene/.
# Extra arguments go to the scene (see python examples/ssd_scene.py --help).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT"
exec "$ROOT/.venv/bin/python" "$ROOT/examples/ssd_scene.py" --out "$ROOT/out/ssd_scene" "$@"
