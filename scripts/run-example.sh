#!/usr/bin/env bash
# Set up (idempotent) and run the main job: the flagship study, the source's temperature-control
# experiment with 256 rigid waters (examples/flagship_water.py; about 7 minutes on 2 cores).
# Extra arguments go to the study (see python examples/flagship_water.py --help).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT"
exec "$ROOT/.venv/bin/python" "$ROOT/examples/flagship_water.py" "$@"
