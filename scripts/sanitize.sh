#!/usr/bin/env bash
# Builds the C++ tests with AddressSanitizer and UndefinedBehaviorSanitizer (build-sanitize/) and
# runs them on the Reference and CPU platforms: out-of-bounds and use-after-free accesses, leaks of
# the plugin's own memory, uninitialised reads made visible by UBSan's checks, integer overflow,
# invalid shifts and casts. Any report fails the run. The OpenCL and CUDA platforms are not built:
# their kernels are not host code (PoCL compiles them with its own LLVM at run time), and their
# runners that reach into OpenMM's OpenCLContext do not link under UBSan's vptr check (the OpenMM
# wheel exports no typeinfo for it). Nor are the host code's baseline builds run under QEMU
# (TestCpu*Baseline): an AddressSanitizer build of a test did not finish under it in 120 s.
#
#   bash scripts/sanitize.sh        # after scripts/setup.sh (uses its virtual environment's OpenMM)
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="$ROOT/build-sanitize"
JOBS="${JOBS:-$(nproc)}"
OPENMM_DIR="$("$ROOT/.venv/bin/python" -c "import os, openmm.version as v; print(os.path.dirname(v.openmm_library_path))")"
FLAGS="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
echo "==> configuring $BUILD"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DOPENMM_DIR="$OPENMM_DIR" \
      -DCMAKE_CXX_FLAGS="$FLAGS" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
      -DCMAKE_DISABLE_FIND_PACKAGE_SWIG=ON -DRIGIDLANGEVIN_BUILD_OPENCL=OFF -DRIGIDLANGEVIN_BUILD_CUDA=OFF -DRIGIDLANGEVIN_TEST_BASELINE_CLONE=OFF >"$BUILD.log" 2>&1 \
    || { tail -30 "$BUILD.log"; exit 1; }
echo "==> building (make -j$JOBS)"
cmake --build "$BUILD" -j "$JOBS" >>"$BUILD.log" 2>&1 || { grep -E "error" "$BUILD.log" | head -30; exit 1; }
echo "==> running the C++ tests on Reference and CPU under the sanitizers"
cd "$BUILD"
# Leaks are checked, except the registries that live as long as the process: OpenMM's own, and the
# serialization proxy this plugin registers with it (as OpenMM's plugins do).
printf 'leak:registerRigidLangevinSerializationProxies\nleak:libOpenMM\nleak:libOpenMMCPU\nleak:libOpenMMPME\nleak:libOpenMMOpenCL\nleak:libpocl\nleak:libLLVM\n' > lsan.supp
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1"
export LSAN_OPTIONS="suppressions=$BUILD/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
ctest --output-on-failure -j "$JOBS"
