#!/usr/bin/env bash
# On a GPU machine, from the repository's root, with .gpu/ packed by scripts/gpu/bundle.sh: installs
# OpenMM's wheels and this build into /tmp, builds the Python extension for the machine's python3,
# then runs the phases asked for (default: tests bench large pse), each under a time limit, writing
# logs and tables to $OUT (default /tmp/out):
#   tests  every CUDA and OpenCL C++ runner (the hydrodynamic-interaction runner split by test, and
#          again with RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER=krylov), 8 at a time; pytest -k CUDA
#   bench  benchmarks/platforms/hydrodynamic_interactions.py on CUDA (bodies of 1-12 blobs)
#   large  the same, single spheres, 10^3 to 10^5
#   pse    benchmarks/platforms/periodic_hydrodynamics.py on CUDA, mixed precision: the spectral step
#          (its products on the device) at tolerance 1e-3, 10^3 to 10^5 blobs, with blob products/s
#   banana the banana study's missing implicit replicas on CUDA (8 processes sharing the GPU) and
#          explicit ones on the CPU platform (8 more, one core each: OpenMM's CUDA Gay-Berne kernel
#          drops the scene's exceptions across the box's edge, banana_model.scene_context), for
#          BANANA_SECONDS (default 480), saving progress every minute; brings back
#          $OUT/banana_runs.tar.gz.NN: finished runs and the explicit runs' progress (CPU checkpoints,
#          carried on here; the implicit runs' progress, 24 MB a run, stays behind). Here, unpack with
#          cat banana_runs.tar.gz.* | tar xz -C examples/results/banana_scene
# A 2026-11-28 H200 took 220 s for tests (without the split), 90 s for bench, and 170 s reached 3e4 in large.
#
#   bash scripts/gpu/run.sh [tests] [bench] [large] [pse] [banana]
set -u
R="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
G="$R/.gpu"; O="${OUT:-/tmp/out}"; mkdir -p "$O"
PHASES="${*:-tests bench large pse}"
exec > >(tee "$O/run.log") 2>&1
echo "root: $R  phases: $PHASES"; date
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
case "$(nvidia-smi --query-gpu=name --format=csv,noheader | head -1)" in
    *H200*) TAG=gpu_h200;; *H100*) TAG=gpu_h100;; *) TAG=gpu_other;; esac
source "$G/paths"
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --target /tmp/site "$G"/whl/*.whl || exit 1
L=/tmp/site/OpenMM.libs/lib
cp "$G"/lib/*.so "$L/"; cp "$G"/lib/plugins/*.so "$L/plugins/"
# The runners' compiled-in paths (this project's build and OpenMM's libraries where they were built).
if [ -d "$OPENMM_LIBS" ] && [ ! -L "$OPENMM_LIBS" ]; then echo "$OPENMM_LIBS exists here: this is the development machine"; exit 1; fi
mkdir -p "$(dirname "$OPENMM_LIBS")" "$BUILD"
ln -sfn /tmp/site/OpenMM.libs "$OPENMM_LIBS"
cp "$G"/buildlibs/*.so "$BUILD/"
NVRTC=$(find /usr/local /opt -name 'libnvrtc.so.13*' 2>/dev/null | head -1)
CUFFT=$(find /usr/local /opt -name 'libcufft.so.12*' 2>/dev/null | head -1)
mkdir -p /tmp/ocl /etc/OpenCL/vendors
ldconfig -p | grep -q libOpenCL.so.1 || cp -a "$G"/ocl/* /tmp/ocl/
[ -n "$(ls /etc/OpenCL/vendors)" ] || echo libnvidia-opencl.so.1 > /etc/OpenCL/vendors/nvidia.icd
export LD_LIBRARY_PATH="$(dirname "$NVRTC"):$(dirname "$CUFFT"):/tmp/ocl:$L:$BUILD"
ldd "$L/plugins/libOpenMMCUDA.so" | grep "not found"
PY=python3
EXT=$($PY -c "import sysconfig; print(sysconfig.get_config_var('EXT_SUFFIX'))")
PYINC=$($PY -c "import sysconfig; print(sysconfig.get_paths()['include'])")
NPINC=$($PY -c "import numpy; print(numpy.get_include())")
mkdir -p /tmp/pkg && cp -r "$G/pkg/rigidlangevin" /tmp/pkg/
c++ -O1 -fPIC -w -std=gnu++17 -shared -I"$NPINC" -I"$R/openmmapi/include" -I"$R/model/include" -I"$R/platforms/shared/include" \
    -I"$R/serialization/include" -I"$R/hydrodynamics/include" -isystem "$PYINC" -isystem /tmp/site/OpenMM.libs/include \
    "$G/RigidLangevinPythonWrapper.cpp" -o "/tmp/pkg/rigidlangevin/_core$EXT" -L"$L" -lRigidLangevin -lRigidLangevinHydrodynamics \
    -lOpenMM -Wl,-rpath,"$L" || exit 1
export PYTHONPATH=/tmp/pkg:/tmp/site PYTHONUNBUFFERED=1 OPENBLAS_NUM_THREADS=1
$PY -c "import openmm as mm, rigidlangevin; print([mm.Platform.getPlatform(i).getName() for i in range(mm.Platform.getNumPlatforms())], mm.Platform.getPluginLoadFailures())"

if [[ " $PHASES " == *" tests "* ]]; then
    T=/tmp/testlogs; mkdir -p $T; cd /tmp; start=$(date +%s)
    LONG="*Temperatures*:*BoundPairs*:*NoiseCovariance*"
    {
        for t in "$G"/bin/Test*; do
            case "$(basename "$t")" in *HydrodynamicInteractions) ;; *) echo "$(basename "$t") $t";; esac
        done
        for p in Cuda OpenCL; do
            H="$G/bin/Test${p}HydrodynamicInteractions"
            echo "${p}HI $H --gtest_filter=-$LONG"
            for f in Temperatures BoundPairs NoiseCovariance; do echo "${p}HI_$f $H --gtest_filter=*$f*"; done
            echo "${p}HI_krylov env RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER=krylov $H --gtest_filter=-$LONG"
        done
        echo "CudaHI_krylov_NoiseCovariance env RIGIDLANGEVIN_HYDRODYNAMIC_SOLVER=krylov $G/bin/TestCudaHydrodynamicInteractions --gtest_filter=*NoiseCovariance*"
    } > /tmp/testlist
    (cd "$R" && timeout 200 $PY -m pytest -q -p no:cacheprovider -k CUDA tests > $T/pytest_cuda.log 2>&1; echo "pytest -k CUDA rc=$?" >> $T/pytest_cuda.log) &
    PYTEST=$!
    xargs -P 8 -L 1 bash -c 'name=$0; s=$(date +%s); timeout 200 "$@" > /tmp/testlogs/$name.log 2>&1; echo "$name rc=$? $(( $(date +%s)-s )) s"' < /tmp/testlist
    wait $PYTEST
    tail -2 $T/pytest_cuda.log
    echo "tests took $(( $(date +%s)-start )) s"
    grep -h -E "FAILED|Failure|Expected|Which is" $T/*.log | head -60
    tar czf "$O/testlogs.tar.gz" -C /tmp testlogs
fi
cd "$R/benchmarks/platforms"
if [[ " $PHASES " == *" bench "* ]]; then
    timeout 150 $PY hydrodynamic_interactions.py --platform CUDA --max-dense-blobs 400 --name $TAG/hydrodynamic_interactions
    cp results/$TAG/hydrodynamic_interactions.* "$O/" 2>/dev/null
fi
if [[ " $PHASES " == *" large "* ]]; then
    timeout 200 $PY hydrodynamic_interactions.py --platform CUDA --large --max-dense-blobs 0 --sizes 1000 10000 30000 100000 \
        --name $TAG/hydrodynamic_interactions_large
    cp results/$TAG/hydrodynamic_interactions_large.* "$O/" 2>/dev/null
fi
if [[ " $PHASES " == *" pse "* ]]; then
    timeout 200 $PY periodic_hydrodynamics.py --platform CUDA --precision mixed --sizes 1000 10000 100000 --tolerances 1e-3 \
        --max-dense-blobs 0 --name $TAG/periodic_hydrodynamics
    cp results/$TAG/periodic_hydrodynamics.* "$O/" 2>/dev/null
fi
if [[ " $PHASES " == *" banana "* ]]; then
    cd "$R"; S=examples/results/banana_scene; B="${BANANA_SECONDS:-480}"; start=$(date +%s); PIDS=""
    (cd $S && find runs -name 'run_*.npz' | sort) > /tmp/banana_before
    for i in 0 1 2 3 4 5 6 7; do
        timeout "$B" $PY examples/banana_scene.py --threads 1 --stages explicit --part $i/8 --save-every 60 --no-report \
            > "/tmp/banana_explicit_$i.log" 2>&1 &
        PIDS="$PIDS $!"
        timeout "$B" $PY examples/banana_scene.py --platform CUDA --stages implicit --part $i/8 --save-every 60 --no-report \
            > "/tmp/banana_implicit_$i.log" 2>&1 &
        PIDS="$PIDS $!"
    done
    wait $PIDS
    echo "banana took $(( $(date +%s)-start )) s"; tail -n 3 /tmp/banana_*.log
    # New runs, the stages' manifests and the explicit runs' progress.
    (cd $S && { find runs -name 'run_*.npz' | sort | comm -13 /tmp/banana_before -; find runs -name stage.json;
                find runs/explicit -name '.progress_*.npz'; }) | tar czf - -C $S -T - | split -b 15M -d - "$O/banana_runs.tar.gz."
    (cd /tmp && tar czf "$O/banana_logs.tar.gz" banana_*.log)
fi
date
