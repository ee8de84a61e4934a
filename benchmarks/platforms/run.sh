#!/usr/bin/env bash
# Run the platform benchmarks: integrator cost (1e3 to 1e6 bodies) and the rigid water box against
# LangevinMiddleIntegrator with SETTLE, and SSD/RF water against TIP3P, on every platform, and the CPU step in and out of
# the last-level cache. Tables go to stdout and to
# benchmarks/platforms/results/*.csv, plots to results/*.png; with a GPU and ncu, also the
# integrator's memory bandwidth (gpu_bandwidth.py). Takes about 30 minutes on 2 cores.
#
#   bash benchmarks/platforms/run.sh
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bash "$ROOT/scripts/setup.sh" >/dev/null
# numpy's OpenBLAS threads would compete with OpenMM's for the cores.
export OPENBLAS_NUM_THREADS=1
cd "$ROOT/benchmarks/platforms"
echo "==> integrator cost"
"$ROOT/.venv/bin/python" integrator_cost.py "$@" 2>&1 | grep -v "Using an unsupported OpenCL implementation"
echo "==> rigid water box"
"$ROOT/.venv/bin/python" water_box.py 2>&1 | grep -v "Using an unsupported OpenCL implementation"
echo "==> single-site SSD/RF water against TIP3P"
"$ROOT/.venv/bin/python" ssd_water.py 2>&1 | grep -v "Using an unsupported OpenCL implementation"
echo "==> interactions inside rigid bodies removed (villin, colloids)"
"$ROOT/.venv/bin/python" internal_interactions.py 2>&1 | grep -v "Using an unsupported OpenCL implementation"
echo "==> CPU step with its arrays in and out of the last-level cache"
"$ROOT/.venv/bin/python" cpu_cache.py
echo "==> GPU memory bandwidth (CUDA and Nsight Compute only)"
"$ROOT/.venv/bin/python" gpu_bandwidth.py
