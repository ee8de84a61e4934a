#!/usr/bin/env bash
# Set up (idempotent) and run the main example: bent three-bead rigid bodies in implicit water.
# Extra arguments go to the example (see python examples/bent_trimers.py --help).
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
exec "$ROOT/.venv/bin/python" "$ROOT/examples/bent_trimers.py" "$@"
