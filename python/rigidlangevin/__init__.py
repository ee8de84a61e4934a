"""Langevin dynamics of rigid bodies of arbitrary shape in implicit solvent, for OpenMM.

The integrator, RigidLangevinIntegrator, moves rigid bodies (and free particles) with friction and
noise from a full 6x6 hydrodynamic resistance tensor per body; ResistanceTensor builds and queries
such tensors. Viscosities may be given with the units exported here (poise, centipoise) or any
openmm.unit viscosity.
"""
import openmm  # loads OpenMM and its plugins (this one's kernels among them) before our module

from .core import RigidLangevinIntegrator, ResistanceTensor
from ._units import poise, centipoise, md_viscosity
from .topology import addRigidBodies
from .reporters import RigidBodyTemperatureReporter
from . import hydrodynamics

__all__ = ['RigidLangevinIntegrator', 'ResistanceTensor', 'poise', 'centipoise', 'md_viscosity', 'addRigidBodies',
           'RigidBodyTemperatureReporter', 'hydrodynamics']
