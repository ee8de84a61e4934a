#!/usr/bin/env bash
# Set up (idempotent), build, and run every test: the C++ tests through ctest, the Python tests
# through pytest. This is the README's test command and what CI runs.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$ROOT/scripts/setup.sh"
cd "$ROOT/build"
status=0
# Each test job (ctest -j, pytest-xdist's workers) runs on one core: PoCL, the OpenCL platform on the
# host's cores, would otherwise start a thread per core in each, and two tests side by side then
# spend their time switching (TestOpenCLSinglePrecision alone: 111 s of CPU with two threads, 73 s
# with one, and it ends sooner). A GPU's OpenCL driver does not read this variable.
export POCL_MAX_PTHREAD_COUNT="${POCL_MAX_PTHREAD_COUNT:-1}"
# ctest starts the tests it knows to be long first (its cost data, kept in the build tree): a fresh
# clone has none and would start them in the order they were declared, leaving one core busy at the
# end with the last long test. tests/ctest-costs.txt holds their seconds on 2 cores (2026-12-02).
costs="$ROOT/build/Testing/Temporary/CTestCostData.txt"
[ -f "$costs" ] || { mkdir -p "$(dirname "$costs")" && cp "$ROOT/tests/ctest-costs.txt" "$costs"; }
echo "==> C++ tests (ctest)"
ctest --output-on-failure -j "${JOBS:-$(nproc)}" || status=1
if ls "$ROOT"/tests/test_*.py >/dev/null 2>&1; then
    echo "==> Python tests (pytest)"
    cd "$ROOT"
    # One worker (pytest-xdist) per core, each with one CPU-platform thread: most of the time goes
    # to OpenMM's CPU platform on small water boxes, which keeps two threads only ~75% busy; two
    # single-threaded runs side by side take ~30% less time than one after another on two threads.
    # The long tests are collected first (conftest.py) and handed out one at a time (by default
    # xdist gives each worker a contiguous batch first, which put every long test on one worker),
    # so that the workers end together.
    OPENMM_CPU_THREADS=1 "$ROOT/.venv/bin/python" -m pytest -q -n "${JOBS:-$(nproc)}" --maxschedchunk 1 "$ROOT/tests" || status=1
fi
exit $status
