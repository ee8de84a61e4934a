#!/usr/bin/env bash
# Packs .gpu/ (ignored by git): what a GPU machine that has NVIDIA's driver, the CUDA toolkit's
# libraries and a Python 3 with numpy, but neither OpenMM nor this project's build, needs to run
# the CUDA C++ runners, the Python tests' CUDA cases and the GPU benchmarks (scripts/gpu/run.sh).
# Run on the development machine after scripts/setup.sh; takes a minute.
#
#   bash scripts/gpu/bundle.sh [python version of the GPU machine, default 3.12]
#
# The CUDA runners are built only where a driver is found (platforms/cuda/tests/CMakeLists.txt):
# here the build is configured for a while with RIGIDLANGEVIN_CUDA_DRIVER at a link to the toolkit's
# stub (outside a stubs/ folder), so that they link libcuda.so.1 and load the GPU machine's driver,
# then configured back. The runners keep this machine's paths (the build, OpenMM's plugins): run.sh
# recreates them there from .gpu/paths.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
PYVERSION="${1:-3.12}"
BUILD="$ROOT/build"
G="$ROOT/.gpu"
PY="$ROOT/.venv/bin/python"
SITE="$("$PY" -c 'import openmm, os; print(os.path.dirname(os.path.dirname(openmm.__file__)))')"
OPENMM_VERSION="$("$PY" -c 'import openmm; print(openmm.__version__)')"
STUB="$(find /usr/local/cuda*/ -path '*stubs/libcuda.so' 2>/dev/null | head -1)"
[ -n "$STUB" ] || { echo "no CUDA toolkit driver stub (stubs/libcuda.so) found" >&2; exit 1; }
grep -qx '/.gpu/' "$ROOT/.git/info/exclude" 2>/dev/null || echo '/.gpu/' >> "$ROOT/.git/info/exclude"

LINK_DIR=/tmp/rigidlangevin-cuda-driver
mkdir -p "$LINK_DIR" && ln -sf "$STUB" "$LINK_DIR/libcuda.so"
cmake -DRIGIDLANGEVIN_CUDA_DRIVER="$LINK_DIR/libcuda.so" "$BUILD" >/dev/null
trap 'cmake -DRIGIDLANGEVIN_CUDA_DRIVER=RIGIDLANGEVIN_CUDA_DRIVER-NOTFOUND "$BUILD" >/dev/null' EXIT
cmake --build "$BUILD" -j "$(nproc)" >/dev/null
cmake --install "$BUILD" >/dev/null

rm -rf "$G" && mkdir -p "$G"/{whl,lib/plugins,buildlibs,bin,pkg/rigidlangevin,ocl}
for name in openmm OpenMM-CUDA-13; do
    for tag in 34 28 17 35 31; do
        python3 -m pip download -q --no-deps --only-binary=:all: --python-version "$PYVERSION" --implementation cp \
            --platform manylinux_2_${tag}_x86_64 -d "$G/whl" "$name==$OPENMM_VERSION" 2>/dev/null && break
    done
done
[ "$(ls "$G/whl" | wc -l)" = 2 ] || { echo "could not download OpenMM $OPENMM_VERSION's wheels for Python $PYVERSION" >&2; exit 1; }
cp "$BUILD"/*.so "$G/buildlibs/"
cp "$SITE"/OpenMM.libs/lib/libRigidLangevin*.so "$G/lib/"
cp "$SITE"/OpenMM.libs/lib/plugins/libRigidLangevin*.so "$G/lib/plugins/"
cp "$BUILD"/TestCuda* "$BUILD"/TestOpenCL* "$G/bin/"
cp "$BUILD/python/RigidLangevinPythonWrapper.cpp" "$G/"
cp "$BUILD"/python/rigidlangevin/*.py "$G/pkg/rigidlangevin/"
# Debian's OpenCL ICD loader, for a machine whose driver brings NVIDIA's OpenCL library but no loader.
cp /usr/lib/x86_64-linux-gnu/libOpenCL.so.1* "$G/ocl/"
printf 'BUILD=%s\nOPENMM_LIBS=%s\n' "$BUILD" "$SITE/OpenMM.libs" > "$G/paths"
echo "packed $(du -sh "$G" | cut -f1) into $G"
