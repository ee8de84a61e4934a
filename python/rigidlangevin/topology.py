"""Rigid bodies from an OpenMM Topology: one body per chosen residue."""
import math

import openmm as mm
import openmm.unit as unit

from .internal import removeInternalInteractions as _remove_internal_interactions

#: Residue names OpenMM's force fields and common file formats use for water.
WATER_NAMES = frozenset(['HOH', 'WAT', 'SOL', 'H2O', 'TIP', 'TIP3', 'TIP4', 'TIP5', 'T3P', 'T4P', 'T5P', 'SPC', 'SPCE'])

#: Van der Waals radii (nm) by element symbol: Bondi, J. Phys. Chem. 68, 441 (1964), with
#: Mantina et al., J. Phys. Chem. A 113, 5806 (2009) for the elements Bondi lacks.
VAN_DER_WAALS_RADII = {
    'H': 0.120, 'C': 0.170, 'N': 0.155, 'O': 0.152, 'F': 0.147, 'P': 0.180, 'S': 0.180, 'Cl': 0.175,
    'Br': 0.185, 'I': 0.198, 'Se': 0.190, 'Si': 0.210, 'B': 0.192, 'Li': 0.182, 'Na': 0.227,
    'K': 0.275, 'Mg': 0.173, 'Ca': 0.231, 'Zn': 0.139, 'Fe': 0.194, 'Cu': 0.140,
}


def _selector(residues):
    if residues == 'water':
        return lambda residue: residue.name.upper() in WATER_NAMES
    if callable(residues):
        return residues
    names = {residues} if isinstance(residues, str) else set(residues)
    return lambda residue: residue.name in names


def _lennard_jones_particles(system):
    """Particles that get a radius from a NonbondedForce (nonzero epsilon), as the integrator does."""
    found = set()
    for force in system.getForces():
        if isinstance(force, mm.NonbondedForce):
            for i in range(force.getNumParticles()):
                charge, sigma, epsilon = force.getParticleParameters(i)
                if epsilon._value != 0 and sigma._value > 0:
                    found.add(i)
    return found


def _rigidify(system, particles, positions, existing):
    """Distance constraints that hold the massive particles of a body rigid, for OpenMM's own tools."""
    massive = [p for p in particles if system.getParticleMass(p)._value > 0]
    if len(massive) < 2:
        return
    xyz = {p: positions[p].value_in_unit(unit.nanometer) if unit.is_quantity(positions[p]) else positions[p] for p in massive}
    def distance(a, b):
        return math.dist(xyz[a], xyz[b])
    def cross_norm(a, b, c):
        u = [xyz[b][k]-xyz[a][k] for k in range(3)]
        v = [xyz[c][k]-xyz[a][k] for k in range(3)]
        w = (u[1]*v[2]-u[2]*v[1], u[2]*v[0]-u[0]*v[2], u[0]*v[1]-u[1]*v[0])
        return math.sqrt(sum(x*x for x in w))
    # Anchors: the first particle, the next one, and the first not on their line.
    anchors = massive[:2]
    for p in massive[2:]:
        if cross_norm(anchors[0], anchors[1], p) > 1e-3*distance(anchors[0], anchors[1])**2:
            anchors.append(p)
            break
    pairs = [(anchors[i], anchors[j]) for i in range(len(anchors)) for j in range(i+1, len(anchors))]
    pairs += [(p, a) for p in massive if p not in anchors for a in anchors]
    for a, b in pairs:
        if (min(a, b), max(a, b)) not in existing:
            system.addConstraint(a, b, distance(a, b))
            existing.add((min(a, b), max(a, b)))


class RigidBodies(list):
    """The indices of the bodies addRigidBodies() made; `internalInteractions` holds what
    removeInternalInteractions() removed when asked for (else None)."""
    internalInteractions = None


def addRigidBodies(integrator, topology, system, residues='water', positions=None, removeInternalInteractions=False):
    """Make a rigid body of each chosen residue of a Topology.

    Parameters
    ----------
    integrator : RigidLangevinIntegrator
        The integrator to add the bodies to (before its Context is created).
    topology : openmm.app.Topology
        The topology whose residues become bodies; its atom indices are the System's particle indices.
    system : openmm.System
        The System the Context will be made of. Particles with no Lennard-Jones sigma (zero epsilon in
        a NonbondedForce), like the hydrogens of most water models, get their element's van der Waals
        radius as hydrodynamic radius; massless particles (virtual sites, like TIP4P's M) ride along.
    residues : 'water', str, list of str, or callable
        Which residues: all water (the default), residues with these names, or those for which
        residues(residue) is true.
    positions : list of Vec3, optional
        If given, distance constraints that hold each body rigid are added to the System where it has
        none (as a force field's rigid water already has), so that OpenMM's energy minimizer keeps the
        bodies' shapes. The integrator ignores constraints inside a body.
    removeInternalInteractions : bool
        If true, remove from the System the interactions among particles of the same body (for all the
        integrator's bodies), which the bodies make constant (rigidlangevin.removeInternalInteractions):
        the same trajectories, at a fraction of the cost for large bodies. What was removed, and (with
        positions) the constant energy it took away, is in the result's `internalInteractions`.

    Returns
    -------
    RigidBodies (a list of int)
        The indices of the new bodies.
    """
    select = _selector(residues)
    lennard_jones = _lennard_jones_particles(system)
    existing = set()
    for i in range(system.getNumConstraints()):
        a, b, d = system.getConstraintParameters(i)
        existing.add((min(a, b), max(a, b)))
    bodies = RigidBodies()
    for residue in topology.residues():
        if not select(residue):
            continue
        particles = [atom.index for atom in residue.atoms()]
        for atom in residue.atoms():
            if system.getParticleMass(atom.index)._value == 0 or atom.index in lennard_jones:
                continue
            symbol = atom.element.symbol if atom.element is not None else None
            if symbol not in VAN_DER_WAALS_RADII:
                raise ValueError(f'atom {atom.index} ({atom.name} of residue {residue.name} {residue.id}) has no Lennard-Jones sigma '
                                 f'and no known van der Waals radius for element {symbol}: call integrator.setParticleRadius({atom.index}, radius)')
            integrator.setParticleRadius(atom.index, VAN_DER_WAALS_RADII[symbol])
        bodies.append(integrator.addRigidBody(particles))
        if positions is not None:
            _rigidify(system, particles, positions, existing)
    if removeInternalInteractions:
        bodies.internalInteractions = _remove_internal_interactions(system, integrator, positions)
    return bodies
