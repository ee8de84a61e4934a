"""pip install . as a user does it: a fresh virtual environment gets OpenMM from PyPI, then this
checkout with pip (scikit-build-core builds it against that OpenMM and installs the plugin's
libraries where it loads plugins); a small simulation runs on Reference and CPU from another
directory; pip uninstall removes every file it installed.

To build in minutes the test turns the GPU platform kernels off (their build is the same CMake
code the developer build runs), optimises at -O1 rather than -O3 (a sixth less compile time for
the same packaging; the optimised build is the developer build's) and builds with all cores.
"""
import os
import pathlib
import subprocess
import sys

import openmm.version

ROOT = pathlib.Path(__file__).resolve().parent.parent

SIMULATION = '''
import openmm as mm, openmm.unit as unit, rigidlangevin as rl
for name in ("Reference", "CPU"):
    system = mm.System()
    for i in range(6):
        system.addParticle(16.0)
    integrator = rl.RigidLangevinIntegrator(300*unit.kelvin, 0.01*rl.poise, 2*unit.femtoseconds)
    integrator.setRandomNumberSeed(3)
    for b in range(2):
        integrator.addRigidBody([3*b, 3*b+1, 3*b+2])
    for i in range(6):
        integrator.setParticleRadius(i, 0.15)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(name))
    context.setPositions([mm.Vec3(b+0.1*(i % 3 == 1), 0.1*(i % 3 == 2), 0) for b in range(2) for i in range(3)])
    context.setVelocitiesToTemperature(300, 5)
    integrator.step(100)
    state = context.getState(getPositions=True)
    print(name, "ok", integrator.computeSystemTemperature())
'''


CMAKE_PROJECT = """cmake_minimum_required(VERSION 3.18)
project(UsesRigidLangevin CXX)
find_package(RigidLangevin 0.1 REQUIRED)
add_executable(quickstart {examples}/QuickStart.cpp)
target_link_libraries(quickstart RigidLangevin::Reference)
add_executable(hydrodynamics {examples}/Hydrodynamics.cpp)
target_link_libraries(hydrodynamics RigidLangevin::Hydrodynamics)
"""


def run(command, **kwargs):
    result = subprocess.run([str(c) for c in command], capture_output=True, encoding='utf-8', **kwargs)
    assert result.returncode == 0, f'{command} failed:\n{result.stdout[-3000:]}\n{result.stderr[-3000:]}'
    return result.stdout


def test_pip_install_into_a_fresh_environment(tmp_path):
    venv = tmp_path/'venv'
    run([sys.executable, '-m', 'venv', venv])
    python = venv/'bin'/'python'
    run([python, '-m', 'pip', 'install', '-q', f'openmm=={openmm.version.short_version}'])
    environment = dict(os.environ, CMAKE_BUILD_PARALLEL_LEVEL=str(os.cpu_count() or 1))
    run([python, '-m', 'pip', 'install', '-q', ROOT, '--config-settings=cmake.define.RIGIDLANGEVIN_BUILD_OPENCL=OFF',
         '--config-settings=cmake.define.RIGIDLANGEVIN_BUILD_CUDA=OFF', '--config-settings=cmake.define.CMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG'],
        env=environment)

    # From another directory: nothing of the checkout is on the path.
    elsewhere = tmp_path/'elsewhere'
    elsewhere.mkdir()
    output = run([python, '-c', SIMULATION], cwd=elsewhere)
    assert 'Reference ok' in output and 'CPU ok' in output, output
    where = run([python, '-c', 'import openmm.version, rigidlangevin, os; print(os.path.dirname(openmm.version.openmm_library_path)); '
                 'print(os.path.dirname(rigidlangevin.__file__))'], cwd=elsewhere).split()
    openmm_dir, package = pathlib.Path(where[0]), pathlib.Path(where[1])
    assert package.parent.parent == venv/'lib'/package.parent.parent.name  # site-packages of the new environment
    plugins = sorted(p.name for p in (openmm_dir/'lib'/'plugins').glob('libRigidLangevin*'))
    assert plugins == ['libRigidLangevinCPU.so', 'libRigidLangevinReference.so'], plugins
    libraries = sorted((openmm_dir/'lib').glob('libRigidLangevin*'))  # the API, hydrodynamics and (x86-64) AVX2 bead-kernel libraries
    assert {'libRigidLangevin.so', 'libRigidLangevinHydrodynamics.so'} <= {library.name for library in libraries}, libraries
    assert (openmm_dir/'include'/'rigidlangevin'/'RigidLangevinIntegrator.h').exists()

    # The installed C++ headers are the public API alone (every public header, the kernel interfaces
    # not), and enough: the README's C++ quick start compiles against them with OpenMM's (no Eigen,
    # no internal headers) and runs, built from another directory with the flags
    # `python -m rigidlangevin` prints, and with CMake's find_package(RigidLangevin).
    headers = sorted(str(h.relative_to(openmm_dir/'include'/'rigidlangevin')) for h in (openmm_dir/'include'/'rigidlangevin').rglob('*.h'))
    assert headers == ['CoupledResistance.h', 'ResistanceTensor.h', 'RigidBodyIntegrator.h', 'RigidBrownianIntegrator.h', 'RigidLangevinIntegrator.h',
                       'StickyDipoleForce.h', 'internal/windowsExportHydrodynamics.h',
                       'internal/windowsExportRigidLangevin.h'], headers
    flags = lambda *which: run([python, '-m', 'rigidlangevin', *which], cwd=elsewhere).split()
    assert pathlib.Path(run([python, '-m', 'rigidlangevin', '--prefix'], cwd=elsewhere).strip()) == openmm_dir
    quickstart = tmp_path/'quickstart'
    run(['g++', ROOT/'examples'/'cpp'/'QuickStart.cpp', *flags('--cflags', '--libs'), '-o', quickstart], cwd=elsewhere)
    assert 'temperature' in run([quickstart], cwd=elsewhere)
    # The hydrodynamics library alone: its example links nothing of the integrator.
    hydrodynamics = tmp_path/'hydrodynamics'
    run(['g++', ROOT/'examples'/'cpp'/'Hydrodynamics.cpp', *flags('--cflags', '--libs-hydrodynamics'), '-o', hydrodynamics], cwd=elsewhere)
    assert 'matches Stokes-Einstein' in run([hydrodynamics], cwd=elsewhere)
    project = tmp_path/'cmake_project'
    project.mkdir()
    (project/'CMakeLists.txt').write_text(CMAKE_PROJECT.format(examples=ROOT/'examples'/'cpp'), encoding='utf-8')
    run(['cmake', '-S', project, '-B', project/'build', f'-DCMAKE_PREFIX_PATH={openmm_dir}'], cwd=elsewhere)
    run(['cmake', '--build', project/'build'], cwd=elsewhere)
    assert 'temperature' in run([project/'build'/'quickstart'], cwd=elsewhere)
    assert 'matches Stokes-Einstein' in run([project/'build'/'hydrodynamics'], cwd=elsewhere)

    # Relative RPATHs only: the environment can move.
    for library in [*libraries, *(openmm_dir/'lib'/'plugins').glob('libRigidLangevin*'), *package.glob('_core*.so')]:
        dynamic = run(['readelf', '-d', library])
        for line in dynamic.splitlines():
            if 'RPATH' in line or 'RUNPATH' in line:
                paths = line.split('[', 1)[1].rstrip(']').split(':')
                assert all(p.startswith('$ORIGIN') for p in paths), f'{library.name}: {line}'

    run([python, '-m', 'pip', 'uninstall', '-y', '-q', 'openmm-rigid-langevin'])
    assert not list((openmm_dir/'lib'/'plugins').glob('libRigidLangevin*'))
    assert not list((openmm_dir/'lib').glob('libRigidLangevin*'))
    assert not (openmm_dir/'include'/'rigidlangevin').exists()
    assert not (openmm_dir/'lib'/'cmake'/'RigidLangevin').exists()
    assert not package.exists()
