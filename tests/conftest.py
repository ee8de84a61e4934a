"""Shared pytest fixtures: the platforms to run on."""
import collections

import openmm as mm
import pytest

import rigidlangevin  # noqa: F401  (importing openmm loads the plugin; this makes sure it is built)

KERNEL = 'IntegrateRigidLangevinStep'
GPU_PLATFORMS = ('OpenCL', 'CUDA', 'HIP')

PlatformChoice = collections.namedtuple('PlatformChoice', 'name platform properties')
PlatformChoice.__doc__ = 'An OpenMM platform and the properties to create a Context with (GPU platforms in double precision).'
PlatformChoice.context = lambda self, system, integrator: mm.Context(system, integrator, self.platform, self.properties)


IMPLEMENTED = ('Reference', 'CPU', 'OpenCL', 'CUDA')

# The few tests that take minutes, longest first. The test command runs two pytest-xdist workers,
# which take tests in collection order: starting these first lets the two end together.
LONG_RUNNING = ('test_water_peers.py', 'test_pip_install.py', 'test_benchmarks.py', 'test_examples.py', 'test_sedimented_boomerangs.py')


def pytest_collection_modifyitems(items):
    def rank(item):
        name = item.path.name
        return LONG_RUNNING.index(name) if name in LONG_RUNNING else len(LONG_RUNNING)
    items.sort(key=rank)  # stable: the order within a file is kept


def available_platforms():
    """Every platform this machine has on which the plugin's kernels are registered. A platform that
    OpenMM loaded and this plugin implements must have them (its kernel library failing to load is an
    error, not a platform fewer to test); CPU and OpenCL must be there (setup installs PoCL); CUDA
    may be missing only where NVIDIA's driver (libcuda.so) is."""
    names = [mm.Platform.getPlatform(i).getName() for i in range(mm.Platform.getNumPlatforms())]
    missing = [n for n in names if n in IMPLEMENTED and not mm.Platform.getPlatformByName(n).supportsKernels([KERNEL])]
    missing += [f'{n} (OpenMM could not load its platform; setup installs PoCL for OpenCL)' for n in ('CPU', 'OpenCL') if n not in names]
    cuda_failures = [f for f in mm.Platform.getPluginLoadFailures() if f.split(':')[0].endswith('/libOpenMMCUDA.so') and 'libcuda.so' not in f]
    # The CPU platform derives from Reference and would fall back to the Reference kernels: its own
    # kernel library failing to load must still be seen. The CUDA one may fail where OpenMM's does.
    missing += [f'{f} (this plugin failed to load)' for f in mm.Platform.getPluginLoadFailures()
                if 'libRigidLangevin' in f and not ('libRigidLangevinCUDA' in f and 'CUDA' not in names)]
    if 'CUDA' not in names and cuda_failures:
        missing.append('CUDA (it failed to load for another reason than a missing driver)')
    if missing:
        raise pytest.UsageError(f"the plugin's kernels are missing on {missing}; plugin load failures: {mm.Platform.getPluginLoadFailures()}")
    return [n for n in names if n in IMPLEMENTED]


def _choice(name):
    properties = {'Precision': 'double'} if name in GPU_PLATFORMS else {}
    return PlatformChoice(name, mm.Platform.getPlatformByName(name), properties)


@pytest.fixture(params=available_platforms())
def platform(request):
    """Parametrizes a test over every available platform: a PlatformChoice (use .context(system,
    integrator) to create a Context). GPU platforms run in double precision."""
    return _choice(request.param)


#: The platforms with a kernel for StickyDipoleForce: Reference and CPU (which runs the Reference
#: kernel); the OpenCL and CUDA kernels are not written yet.
STICKY_DIPOLE_PLATFORMS = ('Reference', 'CPU', 'OpenCL', 'CUDA')


@pytest.fixture(params=[n for n in available_platforms() if n in STICKY_DIPOLE_PLATFORMS])
def sticky_dipole_platform(request):
    """Like `platform`, over the platforms that have StickyDipoleForce's kernel. The list is fixed
    here rather than read from the platforms, so a platform losing the kernel fails a test."""
    return _choice(request.param)
