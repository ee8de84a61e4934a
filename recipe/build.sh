#!/bin/bash
# conda build: pip builds with scikit-build-core against the host environment's OpenMM, which
# lives in $PREFIX (cmake/InstallLayout.cmake installs the plugin libraries into $PREFIX/lib).
set -euxo pipefail
export CMAKE_BUILD_PARALLEL_LEVEL=${CPU_COUNT}
${PYTHON} -m pip install . -vv --no-deps --no-build-isolation
