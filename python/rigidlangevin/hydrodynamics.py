"""Hydrodynamic resistance tensors of rigid bodies.

Every factory returns a ResistanceTensor: the 6x6 matrix Xi per unit viscosity with
(force, torque) = -viscosity * Xi * (velocity, angular velocity) about the tensor's origin.
`t.getMatrix(origin)` gives it (numpy 6x6) about any point; `t.getCenterOfResistance()`,
`t.getCenterOfDiffusion()` and `t.getDiffusionTensor(temperature, viscosity)` (kT (eta Xi)^-1)
describe it; `integrator.setBodyHydrodynamics(index, t, positions)` gives a body that friction,
with `positions` those of the body's particles the model was computed for: the tensor then
follows the body wherever a Context places it.

Positions may be an (N, 3) numpy array or a list of Vec3 (nm), or a Quantity of either; radii a
sequence or a Quantity.

    import rigidlangevin.hydrodynamics as hydro
    xi = hydro.shellExtrapolated(atom_positions, atom_radii)         # the union of the atoms' spheres
    xi = hydro.beads(atom_positions, atom_radii, hydro.unionVolume(atom_positions, atom_radii))
    xi = hydro.ellipsoid(0.4, 0.2, 0.1)                               # Perrin, semi-axes along x, y, z
    xi = hydro.spheroidShellExtrapolated(centers, axes, a, b)          # a union of spheroids (Gay-Berne bodies)
    xi = hydro.protein(topology, positions)                           # HYDROPRO's atomic-level model of a protein
"""
import inspect

import numpy as np
import openmm as mm
import openmm.unit as unit

from .core import CoupledResistance, ResistanceTensor

__all__ = ['ResistanceTensor', 'CoupledResistance', 'coupledResistance', 'coupledMobility', 'resistanceAboveWall', 'sphere', 'ellipsoid', 'spheroid', 'beads', 'beadVolume', 'unionVolume', 'roughShell',
           'roughShellBeads', 'shellExtrapolated', 'spheroidRoughShell', 'spheroidRoughShellBeads', 'spheroidShellExtrapolated',
           'scaleBlobsToFriction', 'freeDrainingBeads', 'explicit', 'protein', 'HYDROPRO_ATOMIC_RADIUS', 'diffusionConstants']

from ._units import lengths_in_nm as _lengths


def _length(value):
    return value.value_in_unit(unit.nanometer) if unit.is_quantity(value) else float(value)


def _vectors(positions):
    if unit.is_quantity(positions):
        positions = positions.value_in_unit(unit.nanometer)
    array = np.array([[_length(c) for c in p] for p in positions], dtype=float)
    if array.ndim != 2 or array.shape[1] != 3:
        raise ValueError(f'positions must be N x 3, got shape {array.shape}')
    return [mm.Vec3(*p) for p in array]


def _point(point):
    return mm.Vec3(*(_length(c) for c in (point.value_in_unit(unit.nanometer) if unit.is_quantity(point) else point)))


def _as(function, python):
    """Give a function the documentation of the C++ function it wraps (the header's), and say how
    its Python arguments may be given."""
    def document(wrapper):
        wrapper.__doc__ = inspect.cleandoc(function.__doc__ or '')+'\n\nIn Python: '+python
        return wrapper
    return document


_LENGTHS = 'lengths in nm, or Quantities.'
_POSITIONS = 'positions an (N, 3) array, a list of Vec3 or a Quantity (nm); radii a sequence or a Quantity (nm).'
_SPHEROIDS = ('centers and axes (N, 3) arrays, lists of Vec3 or Quantities (nm); a and b sequences of N values, or single values '
              'shared by all, in nm or Quantities.')


@_as(ResistanceTensor.sphere, _LENGTHS)
def sphere(radius, center=(0, 0, 0)):
    return ResistanceTensor.sphere(_length(radius), _point(center))


@_as(ResistanceTensor.ellipsoid, _LENGTHS)
def ellipsoid(a, b, c, center=(0, 0, 0)):
    return ResistanceTensor.ellipsoid(_length(a), _length(b), _length(c), _point(center))


@_as(ResistanceTensor.spheroid, _LENGTHS)
def spheroid(a, b, center=(0, 0, 0)):
    return ResistanceTensor.spheroid(_length(a), _length(b), _point(center))


@_as(ResistanceTensor.beads, _POSITIONS+' correctionVolume in nm^3 or a Quantity.')
def beads(positions, radii, correctionVolume=0.0):
    v = correctionVolume.value_in_unit(unit.nanometer**3) if unit.is_quantity(correctionVolume) else float(correctionVolume)
    return ResistanceTensor.beads(_vectors(positions), _lengths(radii), v)


@_as(ResistanceTensor.beadVolume, 'radii a sequence or a Quantity (nm); the volume is in nm^3.')
def beadVolume(radii):
    return ResistanceTensor.beadVolume(_lengths(radii))


@_as(ResistanceTensor.unionVolume, _POSITIONS+' The volume is in nm^3.')
def unionVolume(positions, radii):
    return ResistanceTensor.unionVolume(_vectors(positions), _lengths(radii))


@_as(ResistanceTensor.roughShell, _POSITIONS+' beadRadius in nm or a Quantity.')
def roughShell(positions, radii, beadRadius):
    return ResistanceTensor.roughShell(_vectors(positions), _lengths(radii), _length(beadRadius))


@_as(ResistanceTensor.roughShellBeads, _POSITIONS+' Returns an (N, 3) Quantity in nm.')
def roughShellBeads(positions, radii, beadRadius):
    return ResistanceTensor.roughShellBeads(_vectors(positions), _lengths(radii), _length(beadRadius))


@_as(ResistanceTensor.shellExtrapolated, _POSITIONS)
def shellExtrapolated(positions, radii, maxBeads=2000, numResolutions=6):
    return ResistanceTensor.shellExtrapolated(_vectors(positions), _lengths(radii), int(maxBeads), int(numResolutions))


def _spheroids(centers, axes, a, b):
    centers = _vectors(centers)
    def per_spheroid(values):
        if unit.is_quantity(values):
            values = values.value_in_unit(unit.nanometer)
        values = np.atleast_1d(np.asarray(values, dtype=float))
        return list(values)*len(centers) if len(values) == 1 else list(values)
    return centers, _vectors(axes), per_spheroid(a), per_spheroid(b)


@_as(ResistanceTensor.spheroidRoughShell, _SPHEROIDS+' beadRadius in nm or a Quantity.')
def spheroidRoughShell(centers, axes, a, b, beadRadius):
    return ResistanceTensor.spheroidRoughShell(*_spheroids(centers, axes, a, b), _length(beadRadius))


@_as(ResistanceTensor.spheroidRoughShellBeads, _SPHEROIDS+' Returns an (N, 3) Quantity in nm.')
def spheroidRoughShellBeads(centers, axes, a, b, beadRadius):
    return ResistanceTensor.spheroidRoughShellBeads(*_spheroids(centers, axes, a, b), _length(beadRadius))


@_as(ResistanceTensor.spheroidShellExtrapolated, _SPHEROIDS)
def spheroidShellExtrapolated(centers, axes, a, b, maxBeads=2000, numResolutions=6):
    return ResistanceTensor.spheroidShellExtrapolated(*_spheroids(centers, axes, a, b), int(maxBeads), int(numResolutions))


@_as(ResistanceTensor.scaleBlobsToFriction, _POSITIONS+' center in nm or a Quantity; tensor a ResistanceTensor. Returns an (N, 3) '
     'Quantity in nm.')
def scaleBlobsToFriction(positions, radii, center, tensor):
    return ResistanceTensor.scaleBlobsToFriction(_vectors(positions), _lengths(radii), _point(center), tensor)


@_as(ResistanceTensor.freeDrainingBeads, _POSITIONS)
def freeDrainingBeads(positions, radii):
    return ResistanceTensor.freeDrainingBeads(_vectors(positions), _lengths(radii))


@_as(ResistanceTensor.explicit, 'matrix a 6x6 array (blocks per unit viscosity in nm, nm^2, nm^3); origin in nm or a Quantity.')
def explicit(matrix, origin=(0, 0, 0)):
    return ResistanceTensor.explicit(matrix, _point(origin))


def _coupled(bodies, own, box, wall):
    coupled = CoupledResistance()
    if box is not None:
        coupled.setPeriodicBox(*_vectors(box))
    if wall is not None:
        coupled.setWall(_length(wall))
    for body in bodies:
        if len(body) != 3:
            raise ValueError('each body is (blob positions, blob radii, reference point)')
        positions, radii, origin = body
        coupled.addBody(_vectors(positions), _lengths(radii), _point(origin))
    if own is not None:
        if len(own) != len(bodies):
            raise ValueError(f'own gives {len(own)} tensors for {len(bodies)} bodies (None for a body without one)')
        for body, tensor in enumerate(own):
            if tensor is not None:
                coupled.setBodyResistance(body, tensor)
    return coupled


def coupledResistance(bodies, own=None, box=None, wall=None):
    """The resistance per unit viscosity of several bodies that feel each other through the solvent
    (see CoupledResistance): a (6N, 6N) numpy array, body by body in the order given, each with its
    velocity (of its reference point) first and its angular velocity second; blocks in nm, nm^2, nm^3.

    bodies: a sequence of (blob positions, blob radii, reference point) per body, where the bodies
    are now: positions an (N, 3) array, a list of Vec3 or a Quantity (nm); radii a sequence or a
    Quantity (nm); the reference point (nm) is where the body's velocity is taken and its torque about.

        xi = hydro.coupledResistance([(blobs1, radii1, centre1), (blobs2, radii2, centre2)])
        xi[:6, 6:]    # how body 2's motion drags body 1

    own: optionally, per body, the ResistanceTensor it has alone (or None to keep its blobs'), each
    given in the frame the body is in now: the body's blocks are then calibrated to it (see
    CoupledResistance.setBodyResistance), as the integrator does with hydrodynamic interactions on.

    box: optionally, the three vectors of a periodic box (a 3x3 array, a list of Vec3 or a Quantity,
    nm): the blobs then feel every image (see CoupledResistance.setPeriodicBox).

    wall: optionally, the height z0 (nm or a Quantity) of a no-slip wall below the bodies, the plane
    z = z0: the blobs' mobility is then Rotne-Prager-Blake's (see CoupledResistance.setWall), and a
    blob whose centre is at or below the wall is refused, naming its body. Not with box.
    """
    return _coupled(bodies, own, box, wall).getResistance()


def coupledMobility(bodies, own=None, box=None, wall=None):
    """The inverse of coupledResistance(bodies, own, box, wall): (velocities, angular velocities) =
    mobility (forces, torques) / viscosity. Refused, naming the body, where a body cannot rotate about
    some axis (one blob, or blobs on one line)."""
    return _coupled(bodies, own, box, wall).getMobility()


def resistanceAboveWall(positions, radii, wall=0.0, origin=None):
    """One body's resistance per unit viscosity above a no-slip wall, the plane z = wall (nm or a
    Quantity): its blobs' K^T M^-1 K with M Rotne-Prager-Blake's (see CoupledResistance.setWall), a
    (6, 6) numpy array about origin (nm or a Quantity; default the blobs' centroid), blocks in nm,
    nm^2, nm^3, velocity first and angular velocity second.

    positions: the blobs' centres where the body is now (its height and orientation: the
    resistance depends on both, so compute it again where the body moves; it is not a
    ResistanceTensor, which would follow the body as if the wall were not there), an (N, 3) array, a
    list of Vec3 or a Quantity (nm); radii a sequence or a Quantity (nm). A blob whose centre is at or
    below the wall is refused.
    """
    blobs = _vectors(positions)
    if origin is None:
        origin = np.mean([[p[0], p[1], p[2]] for p in blobs], axis=0)
    return coupledResistance([(blobs, radii, origin)], wall=wall)


#: HYDROPRO's atomic element radius (AER) for atomic-level models: each non-hydrogen atom becomes a
#: sphere of this radius, which carries the hydration shell (Ortega, Amoros & Garcia de la Torre,
#: Biophys. J. 101, 892 (2011)).
HYDROPRO_ATOMIC_RADIUS = 0.29*unit.nanometer


def protein(topology, positions, atoms=None, hydratedRadius=HYDROPRO_ATOMIC_RADIUS, maxBeads=2000, numResolutions=6):
    """A protein's resistance tensor the HYDROPRO way: every non-hydrogen atom a sphere of the hydrated
    radius (2.9 A), the surface of their union tiled with beads at several sizes, extrapolated to zero
    bead size (shellExtrapolated).

    topology, positions: an openmm.app Topology and its positions (a PDBFile's, say). atoms: the atom
    indices of the protein (default: every atom of a residue with an alpha carbon, which leaves out
    water, ions and most ligands). Hydrogens are skipped whether or not the structure has them.
    The tensor's origin is the heavy atoms' centroid, in the positions' frame: give the same positions
    to integrator.setBodyHydrodynamics(index, tensor, positions_of_the_body).
    """
    if atoms is None:
        atoms = [atom.index for residue in topology.residues() if any(a.name == 'CA' for a in residue.atoms())
                 for atom in residue.atoms()]
    all_atoms = list(topology.atoms())
    heavy = [i for i in atoms if all_atoms[i].element is None or all_atoms[i].element.symbol not in ('H', 'D')]
    if not heavy:
        raise ValueError('protein(): no non-hydrogen atoms selected (a residue needs an atom named CA to count as protein; '
                         'pass atoms=[...] to choose them)')
    xyz = _vectors(positions)
    radius = _length(hydratedRadius)
    return shellExtrapolated([xyz[i] for i in heavy], [radius]*len(heavy), maxBeads, numResolutions)


def diffusionConstants(tensor, temperature, viscosity):
    """Translational D_t (cm^2/s) about the centre of diffusion and rotational D_r (1/s), each a third
    of its block's trace, and the harmonic mean rotational relaxation time tau_h = 1/(6 D_r) (ns)."""
    d = np.asarray(tensor.getDiffusionTensor(temperature, viscosity, tensor.getCenterOfDiffusion()))
    d_t = np.trace(d[:3, :3])/3*1e-14/1e-12   # nm^2/ps -> cm^2/s
    d_r = np.trace(d[3:, 3:])/3*1e12          # 1/ps -> 1/s
    return d_t, d_r, 1e9/(6*d_r)
