"""Remove from a System the interactions that rigid bodies make constant.

Particles of one rigid body never move relative to each other, so every interaction among them
alone (a bond, an angle or torsion, a nonbonded pair) has a constant energy and forces that add up
to zero force and zero torque on the body: computing them changes nothing in the trajectory. For a
protein held rigid they are nearly all of the cost of a step. `removeInternalInteractions` takes
them out of the System, which then gives the same trajectory (to round-off) with its potential
energy lower by a constant, which the call reports.

What is removed, force by force:

- A force that is wholly inside one body (every particle it can act on belongs to that body, and
  it uses no periodic boundary conditions, so its energy depends only on the body's shape) is
  removed from the System: NonbondedForce, CustomNonbondedForce, GBSAOBCForce, CustomGBForce and
  the bonded forces below. This is what makes a lone protein with implicit solvent (GB) cheap.
- NonbondedForce: each pair inside a body becomes an exception with no charge product and no
  epsilon (an existing exception, 1-4 pairs included, is set so, and its parameter offsets to
  zero). OpenMM treats such a pair as excluded: under PME and Ewald the pair's reciprocal-space
  part is subtracted with it, so its whole Coulomb energy goes, a constant; under a cutoff with
  reaction field the pair's term depends only on its fixed distance.
- CustomNonbondedForce: each pair inside a body becomes an exclusion. The same pairs are added to
  every nonbonded force, so forces that had identical exclusions (as OpenMM's GPU platforms
  require) still have.
- HarmonicBondForce, HarmonicAngleForce, PeriodicTorsionForce, RBTorsionForce, CMAPTorsionForce:
  each term whose particles all lie in one body gets zero force constants (OpenMM cannot delete a
  term; a zero term costs almost nothing, and Python references to the forces stay valid).
- Anything else (GB forces that reach outside a body, custom bonded forces with terms inside a
  body, forces unknown to this call) is left as it is and named in a warning: it stays exact, only
  not faster.

Where one body is larger than half a periodic box, its pairs' nearest images change as it turns,
and this is refused.
"""
import itertools
import warnings
from dataclasses import dataclass, field

import numpy as np
import openmm as mm
import openmm.unit as unit

from .hydrodynamics import _vectors

__all__ = ['removeInternalInteractions', 'InternalInteractions']

# Bonded forces: (particles per term, the name of the term count, the name of the term getter).
# Their energies depend only on distances and angles among a term's particles.
_BONDED = {
    mm.HarmonicBondForce: (2, 'getNumBonds', 'getBondParameters'),
    mm.HarmonicAngleForce: (3, 'getNumAngles', 'getAngleParameters'),
    mm.PeriodicTorsionForce: (4, 'getNumTorsions', 'getTorsionParameters'),
    mm.RBTorsionForce: (4, 'getNumTorsions', 'getTorsionParameters'),
    mm.CMAPTorsionForce: (8, 'getNumTorsions', 'getTorsionParameters'),
    mm.CustomBondForce: (2, 'getNumBonds', 'getBondParameters'),
    mm.CustomAngleForce: (3, 'getNumAngles', 'getAngleParameters'),
    mm.CustomTorsionForce: (4, 'getNumTorsions', 'getTorsionParameters'),
}
_CUSTOM_BONDED = (mm.CustomBondForce, mm.CustomAngleForce, mm.CustomTorsionForce)
_PAIR_FORCES = (mm.NonbondedForce, mm.CustomNonbondedForce)
_GB_FORCES = (mm.GBSAOBCForce, mm.CustomGBForce)
# Forces that act on no particle of their own: nothing inside a body to remove.
_GLOBAL_FORCES = (mm.CMMotionRemover, mm.MonteCarloBarostat, mm.MonteCarloAnisotropicBarostat,
                  mm.MonteCarloMembraneBarostat, mm.MonteCarloFlexibleBarostat, mm.AndersenThermostat)


@dataclass
class InternalInteractions:
    """What removeInternalInteractions() did.

    energyOffset: the energy removed (a Quantity in kJ/mol, or None without positions): the new
        System's potential energy plus energyOffset is the old one's, wherever the bodies are.
    removedForces: names of the forces taken out of the System whole.
    excludedPairs: pairs inside bodies made exclusions (per nonbonded force).
    zeroedTerms: bonded terms inside bodies given zero force constants, per force name.
    leftAlone: names of forces that may hold interactions inside a body and were kept as they are.
    """
    energyOffset: object = None
    removedForces: list = field(default_factory=list)
    excludedPairs: dict = field(default_factory=dict)
    zeroedTerms: dict = field(default_factory=dict)
    leftAlone: list = field(default_factory=list)


def _force_name(index, force):
    name = force.getName()
    return f'{name} (force {index})' if name == type(force).__name__ else f'{name} ({type(force).__name__}, force {index})'


def _body_particles(bodies):
    if hasattr(bodies, 'getNumRigidBodies'):
        bodies = [list(bodies.getRigidBodyParticles(b)) for b in range(bodies.getNumRigidBodies())]
    return [list(b) for b in bodies]


def _keep_default_radii(integrator, force):
    """The integrator takes a particle's default hydrodynamic radius from a NonbondedForce (sigma/2
    where epsilon is nonzero): before that force goes, make those radii explicit."""
    for p in range(force.getNumParticles()):
        charge, sigma, epsilon = force.getParticleParameters(p)
        sigma, epsilon = sigma.value_in_unit(unit.nanometer), epsilon.value_in_unit(unit.kilojoule_per_mole)
        if integrator.getParticleRadius(p) is None and epsilon != 0 and sigma > 0:
            integrator.setParticleRadius(p, 0.5*sigma)


def _check_size(system, bodies, positions):
    """A body wider than half the box would see its pairs' nearest images change as it turns."""
    if positions is None or not system.usesPeriodicBoundaryConditions():
        return
    box = system.getDefaultPeriodicBoxVectors()
    half = 0.5*min(box[0][0], box[1][1], box[2][2]).value_in_unit(unit.nanometer)
    for index, particles in enumerate(bodies):
        xyz = np.array([positions[p] for p in particles])
        # Twice the largest distance from the centroid bounds the width: only a body that bound does
        # not clear needs its pairs measured (a protein has 1e5 of them).
        if 2*np.max(np.linalg.norm(xyz-xyz.mean(axis=0), axis=1)) < half:
            continue
        widest = max(np.max(np.linalg.norm(xyz[i+1:]-xyz[i], axis=1)) for i in range(len(xyz)-1))
        if widest >= half:
            raise ValueError(f'body {index} is {widest:.3f} nm across, more than half the periodic box ({half:.3f} nm): '
                             f'its internal pairs would change images as it turns; use a larger box')


def _term_particles(force):
    """The particles of each term of a bonded force."""
    count, number, get = _BONDED[type(force)]
    first = 1 if isinstance(force, mm.CMAPTorsionForce) else 0  # a CMAP term starts with its map
    return [tuple(getattr(force, get)(i)[first:first+count]) for i in range(getattr(force, number)())]


def _terms_inside(force, body_of):
    """Indices of the bonded force's terms whose particles all lie in one body."""
    inside = []
    for i, particles in enumerate(_term_particles(force)):
        body = body_of.get(particles[0])
        if body is not None and all(body_of.get(p) == body for p in particles):
            inside.append(i)
    return inside


def _zero_terms(force, terms):
    if isinstance(force, mm.HarmonicBondForce):
        for i in terms:
            a, b, length, k = force.getBondParameters(i)
            force.setBondParameters(i, a, b, length, 0)
    elif isinstance(force, mm.HarmonicAngleForce):
        for i in terms:
            a, b, c, angle, k = force.getAngleParameters(i)
            force.setAngleParameters(i, a, b, c, angle, 0)
    elif isinstance(force, mm.PeriodicTorsionForce):
        for i in terms:
            a, b, c, d, periodicity, phase, k = force.getTorsionParameters(i)
            force.setTorsionParameters(i, a, b, c, d, periodicity, phase, 0)
    elif isinstance(force, mm.RBTorsionForce):
        for i in terms:
            a, b, c, d = force.getTorsionParameters(i)[:4]
            force.setTorsionParameters(i, a, b, c, d, 0, 0, 0, 0, 0, 0)
    elif isinstance(force, mm.CMAPTorsionForce):
        zero_map = None
        for i in terms:
            params = force.getTorsionParameters(i)
            if zero_map is None:
                size = force.getMapParameters(params[0])[0]
                zero_map = force.addMap(size, [0.0]*(size*size))
            force.setTorsionParameters(i, zero_map, *params[1:])


def _pairs_inside(bodies):
    for particles in bodies:
        yield from itertools.combinations(sorted(particles), 2)


def _exclude_nonbonded(force, bodies):
    existing = {}
    for i in range(force.getNumExceptions()):
        a, b = force.getExceptionParameters(i)[:2]
        existing[(min(a, b), max(a, b))] = i
    zeroed = set()
    count = 0
    for pair in _pairs_inside(bodies):
        index = existing.get(pair)
        if index is None:
            force.addException(pair[0], pair[1], 0.0, 1.0, 0.0)
        else:
            force.setExceptionParameters(index, pair[0], pair[1], 0.0, 1.0, 0.0)
            zeroed.add(index)
        count += 1
    for i in range(force.getNumExceptionParameterOffsets()):
        parameter, exception, charge, sigma, epsilon = force.getExceptionParameterOffset(i)
        if exception in zeroed:
            force.setExceptionParameterOffset(i, parameter, exception, 0.0, 0.0, 0.0)
    return count


def _exclude_custom_nonbonded(force, bodies):
    existing = set()
    for i in range(force.getNumExclusions()):
        a, b = force.getExclusionParticles(i)
        existing.add((min(a, b), max(a, b)))
    count = 0
    for pair in _pairs_inside(bodies):
        if pair not in existing:
            force.addExclusion(*pair)
        count += 1
    return count


def _particles_of(force):
    """The particles a force can act on, for the forces whose energy depends only on distances among them."""
    if isinstance(force, _PAIR_FORCES+_GB_FORCES):
        return range(force.getNumParticles())
    if type(force) in _BONDED:
        return {p for particles in _term_particles(force) for p in particles}
    return None


def _energy(system, positions):
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName('Reference'))
    context.setPositions(positions)
    return context.getState(getEnergy=True).getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole)


def removeInternalInteractions(system, bodies, positions=None):
    """Remove from `system` the interactions among particles of the same rigid body (see the module's text).

    Parameters
    ----------
    system : openmm.System
        Changed in place, before a Context is made of it. Forces removed whole are deleted: do not use
        Python references to them afterwards.
    bodies : RigidLangevinIntegrator, or list of lists of particle indices
        The rigid bodies: an integrator's (after addRigidBody / addRigidBodies), or the particles of each.
        The integrator takes default hydrodynamic radii from a NonbondedForce; given the integrator, the
        call makes those radii explicit before it removes such a force whole (given lists, set them with
        setParticleRadius, as the Context's error will say).
    positions : list of Vec3 or Quantity, optional
        Any positions of the System with the bodies in their shapes. With them, the removed energy is
        reported (computed on the Reference platform) and bodies wider than half a periodic box are refused.

    Returns
    -------
    InternalInteractions
    """
    integrator = bodies if hasattr(bodies, 'getNumRigidBodies') else None
    bodies = _body_particles(bodies)
    body_of = {}
    for index, particles in enumerate(bodies):
        for p in particles:
            if p in body_of:
                raise ValueError(f'particle {p} is in body {body_of[p]} and body {index}: a particle can belong to one body only')
            if not 0 <= p < system.getNumParticles():
                raise ValueError(f'body {index} holds particle {p}, but the System has {system.getNumParticles()} particles')
            body_of[p] = index
    if positions is not None:
        positions = _vectors(positions)
        if len(positions) != system.getNumParticles():
            raise ValueError(f'{len(positions)} positions for a System of {system.getNumParticles()} particles')
    _check_size(system, bodies, positions)
    before = _energy(system, positions) if positions is not None else None

    report = InternalInteractions()
    multi = [b for b in bodies if len(b) > 1]
    removable = []
    for index, force in enumerate(system.getForces()):
        name = _force_name(index, force)
        if isinstance(force, _GLOBAL_FORCES):
            continue
        particles = _particles_of(force)
        if particles is not None and not force.usesPeriodicBoundaryConditions():
            owners = {body_of.get(p) for p in particles}
            if len(owners) == 1 and None not in owners:
                removable.append(index)
                report.removedForces.append(name)
                continue
        if isinstance(force, mm.NonbondedForce):
            report.excludedPairs[name] = _exclude_nonbonded(force, multi)
        elif isinstance(force, mm.CustomNonbondedForce):
            report.excludedPairs[name] = _exclude_custom_nonbonded(force, multi)
        elif isinstance(force, _CUSTOM_BONDED):
            if _terms_inside(force, body_of):
                report.leftAlone.append(name)
        elif type(force) in _BONDED:
            terms = _terms_inside(force, body_of)
            _zero_terms(force, terms)
            if terms:
                report.zeroedTerms[name] = len(terms)
        elif isinstance(force, _GB_FORCES):
            if multi:
                report.leftAlone.append(name)
        else:
            report.leftAlone.append(name)
    for index in reversed(removable):
        if integrator is not None and isinstance(system.getForce(index), mm.NonbondedForce):
            _keep_default_radii(integrator, system.getForce(index))
        system.removeForce(index)
    if report.leftAlone:
        warnings.warn('removeInternalInteractions left these forces as they are (their interactions inside bodies are still '
                      'computed, exactly): ' + ', '.join(report.leftAlone), RuntimeWarning, stacklevel=2)
    if before is not None:
        report.energyOffset = (before - _energy(system, positions))*unit.kilojoule_per_mole
    return report
