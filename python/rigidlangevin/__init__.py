"""Langevin dynamics of rigid bodies of arbitrary shape in implicit solvent, for OpenMM.

The integrators move rigid bodies (and free particles) with friction and noise from a full 6x6
hydrodynamic resistance tensor per body: RigidLangevinIntegrator with inertia, RigidBrownianIntegrator
overdamped (colloids), both with hydrodynamic interactions and a no-slip wall (RigidBodyIntegrator
holds what they share); ResistanceTensor builds and queries
such tensors; StickyDipoleForce is the soft sticky dipole family of single-site water models. Viscosities may be given with the units exported here (poise, centipoise) or any
openmm.unit viscosity.
"""
import openmm  # loads OpenMM and its plugins (this one's kernels among them) before our module
import openmm.version

from ._build_info import OPENMM_VERSION as _BUILT_AGAINST

# The OpenMM release series this package supports, as pyproject.toml, recipe/meta.yaml and
# CMakeLists.txt declare it (tests/test_versions.py holds them to agree): the plugin is compiled
# against one series, its wrapper needs the SWIG runtime of 8.6's own, and the reporters the dict
# form of describeNextReport (8.2 and later).
_OPENMM_SERIES = '8.6'
if openmm.version.short_version.split('.')[:2] != _OPENMM_SERIES.split('.'):
    raise ImportError(f'rigidlangevin needs OpenMM {_OPENMM_SERIES}.x, but this environment has OpenMM {openmm.version.short_version}: '
                      f'install openmm=={_OPENMM_SERIES}.* (then rigidlangevin against it)')

# A plugin is compiled against one OpenMM release series: refuse another, rather than crash in it.
if _BUILT_AGAINST and openmm.version.short_version.split('.')[:2] != _BUILT_AGAINST.split('.')[:2]:
    raise ImportError(f'rigidlangevin was built against OpenMM {_BUILT_AGAINST}, but this environment has OpenMM '
                      f'{openmm.version.short_version}: reinstall it (pip install --force-reinstall --no-cache-dir openmm-rigid-langevin, '
                      f'or rebuild from the source) against this OpenMM')

from .core import RigidBodyIntegrator, RigidLangevinIntegrator, RigidBrownianIntegrator, ResistanceTensor, StickyDipoleForce
from ._units import poise, centipoise, md_viscosity
from .topology import addRigidBodies
from .internal import removeInternalInteractions
from .reporters import RigidBodyStateReporter, RigidBodyTemperatureReporter
from . import hydrodynamics
from . import ssd
from . import forcefield as _forcefield  # registers <StickyDipoleForce> with openmm.app.ForceField

__all__ = ['RigidBodyIntegrator', 'RigidLangevinIntegrator', 'RigidBrownianIntegrator', 'ResistanceTensor', 'StickyDipoleForce', 'poise', 'centipoise', 'md_viscosity', 'addRigidBodies', 'removeInternalInteractions',
           'RigidBodyTemperatureReporter', 'RigidBodyStateReporter', 'castForce', 'hydrodynamics', 'ssd']


def castForce(force):
    """A Force as this plugin's class if it is one (a StickyDipoleForce), else the Force itself.

    OpenMM's Python wrapper gives System.getForce() and XmlSerializer.deserialize() the class of a
    force only for its own Force classes (a list fixed when OpenMM is built), so a plugin's force
    comes back as a plain openmm.Force. `[rl.castForce(f) for f in system.getForces()]` gives every
    force its class; `StickyDipoleForce.cast(force)` does it for one known to be a StickyDipoleForce.
    The result keeps the original object alive."""
    return StickyDipoleForce.cast(force) if StickyDipoleForce.isinstance(force) else force
