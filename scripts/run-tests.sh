#!/usr/bin/env bash
# Set up (idempotent), build, and run every test: the C++ tests through ctest, the Python tests
# through pytest. This is the README's test command and what CI runs.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT/build"
status=0
echo "==> C++ tests (ctest)"
ctest --output-on-failure -j "${JOBS:-$(nproc)}" || status=1
if ls "$ROOT"/tests/test_*.py >/dev/null 2>&1; then
    echo "==> Python tests (pytest)"
    cd "$ROOT"
    "$ROOT/.venv/bin/python" -m pytest -q "$ROOT/tests" || status=1
fi
exit $status
