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


def available_platforms():
    """Every platform this machine has on which the plugin's kernels are registered."""
    names = []
    for i in range(mm.Platform.getNumPlatforms()):
        platform = mm.Platform.getPlatform(i)
        if platform.supportsKernels([KERNEL]):
            names.append(platform.getName())
    return names


@pytest.fixture(params=available_platforms())
def platform(request):
    """Parametrizes a test over every available platform: a PlatformChoice (use .context(system,
    integrator) to create a Context). GPU platforms run in double precision."""
    name = request.param
    properties = {'Precision': 'double'} if name in GPU_PLATFORMS else {}
    return PlatformChoice(name, mm.Platform.getPlatformByName(name), properties)
