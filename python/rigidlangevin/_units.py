"""Unit handling of the Python wrapper: viscosities, tensors and rotations given as Quantities or arrays."""
import collections

import numpy as np
import openmm.unit as unit

AVOGADRO = 6.02214076e23

#: The viscosity unit of OpenMM's MD unit system, amu/(nm*ps) per molecule. openmm.unit writes
#: dalton as g/mol, so dalton/(nm*ps) carries a 1/mol that Pa*s does not: 1 Pa*s is
#: 6.02214076e5 amu/(nm*ps), not 1e-18. This unit is compatible with Pa*s and has that scale.
md_viscosity = unit.Unit({unit.ScaledUnit(1e18/AVOGADRO, unit.pascal*unit.second, 'amu/(nm*ps)', 'amu/(nm*ps)'): 1.0})

#: The CGS unit of viscosity, 0.1 Pa*s.
poise = unit.Unit({unit.ScaledUnit(0.1, unit.pascal*unit.second, 'poise', 'P'): 1.0})

#: 1e-3 Pa*s, about the viscosity of water at 20 C.
centipoise = unit.Unit({unit.ScaledUnit(1e-3, unit.pascal*unit.second, 'centipoise', 'cP'): 1.0})

_md_per_molecule = unit.dalton/(unit.nanometer*unit.picosecond)


def viscosity_value(viscosity):
    """A viscosity in amu/(nm*ps) as a float, from a float (taken as amu/(nm*ps)) or any Quantity of
    viscosity: Pa*s, poise, centipoise, or openmm.unit's dalton/(nm*ps)."""
    if not unit.is_quantity(viscosity):
        return float(viscosity)
    if viscosity.unit.is_compatible(unit.pascal*unit.second):
        return viscosity.value_in_unit(md_viscosity)
    if viscosity.unit.is_compatible(_md_per_molecule):
        return viscosity.value_in_unit(_md_per_molecule)
    raise TypeError(f'{viscosity} is not a viscosity: give it in poise, centipoise, Pa*s or amu/(nm*ps)')


def tensor_values(tensor):
    """36 floats, row-major, from a 6x6 array-like or a flat sequence of 36."""
    values = np.asarray(tensor, dtype=float)
    if values.shape not in ((6, 6), (36,)):
        raise ValueError(f'a resistance tensor is a 6x6 matrix (or 36 values), got shape {values.shape}')
    return [float(v) for v in values.reshape(36)]


def rotation_values(rotation):
    """9 floats, row-major, from a 3x3 array-like or 9 values."""
    values = np.asarray(rotation, dtype=float)
    if values.shape not in ((3, 3), (9,)):
        raise ValueError(f'a rotation is a 3x3 matrix (or 9 values), got shape {values.shape}')
    return [float(v) for v in values.reshape(9)]


def matrix6(values):
    """A 6x6 numpy array from 36 row-major values."""
    return np.array(values, dtype=float).reshape(6, 6)


def square_matrix(values):
    """A flat row-major list of n*n values as an n x n numpy array."""
    values = np.asarray(values, dtype=float)
    n = int(round(np.sqrt(len(values))))
    return values.reshape(n, n)


def resistance_result(result):
    """(6x6 array, origin Vec3 in nm, reference positions (N, 3) in nm) from the wrapper's
    (36 values, (x, y, z), [(x, y, z)]), or None."""
    if result is None:
        return None
    import openmm
    values, origin, reference = result
    return matrix6(values), unit.Quantity(openmm.Vec3(*origin), unit.nanometer), vectors_in_nm(reference)


def length_in_nm(length):
    """A float in nm from a length Quantity, or from a number taken as nm."""
    return length.value_in_unit(unit.nanometer) if unit.is_quantity(length) else float(length)


def lengths_in_nm(lengths):
    """Floats in nm from a Quantity (of a sequence or an array) of lengths, or from numbers taken as nm."""
    if unit.is_quantity(lengths):
        lengths = lengths.value_in_unit(unit.nanometer)
    return [v.value_in_unit(unit.nanometer) if unit.is_quantity(v) else float(v) for v in lengths]


def blobs_result(result):
    """(centres (N, 3), radii (N,), reference positions (M, 3)), each a Quantity in nm, from the
    wrapper's ([(x, y, z)], [radius], [(x, y, z)]), or None."""
    if result is None:
        return None
    centres, radii, reference = result
    return vectors_in_nm(centres), unit.Quantity(np.array(radii, dtype=float), unit.nanometer), vectors_in_nm(reference)


def vectors_in_nm(vectors):
    """A list of Vec3 (nm) as a Quantity-wrapped (N, 3) numpy array."""
    return unit.Quantity(np.array([[v[0], v[1], v[2]] for v in vectors], dtype=float).reshape(-1, 3), unit.nanometer)


#: StickyDipoleForce's site parameters in the order the wrapper passes them, with their MD units.
_STICKY_DIPOLE_UNITS = (('sigma', unit.nanometer), ('epsilon', unit.kilojoule_per_mole),
                        ('dipole', unit.elementary_charge*unit.nanometer), ('nu0', unit.kilojoule_per_mole),
                        ('rL', unit.nanometer), ('rU', unit.nanometer), ('nu0Prime', unit.kilojoule_per_mole),
                        ('rLPrime', unit.nanometer), ('rUPrime', unit.nanometer), ('w0', unit.dimensionless))


def sticky_dipole_quantities(values):
    """A StickyDipoleForce site's parameters as a dict of Quantities (w0 a float)."""
    return {name: (float(v) if u is unit.dimensionless else unit.Quantity(float(v), u))
            for (name, u), v in zip(_STICKY_DIPOLE_UNITS, values)}


def sticky_dipole_values(model, parameters):
    """The 10 values of a site: a named model's (or zeros), replaced by any given as keywords."""
    from .core import StickyDipoleForce
    unknown = set(parameters)-{name for name, _ in _STICKY_DIPOLE_UNITS}
    if unknown:
        raise TypeError(f'StickyDipoleForce: unknown site parameters {sorted(unknown)}; '
                        f'they are {[name for name, _ in _STICKY_DIPOLE_UNITS]}')
    values = list(StickyDipoleForce._modelParameters(model)) if model is not None else [0.0]*10
    for i, (name, u) in enumerate(_STICKY_DIPOLE_UNITS):
        if name in parameters:
            value = parameters[name]
            values[i] = float(value.value_in_unit(u) if unit.is_quantity(value) else value)
    return values


RigidBodyStates = collections.namedtuple('RigidBodyStates', 'centers orientations velocities angularVelocities')
RigidBodyStates.__doc__ = """Every rigid body's centre of mass (nm), orientation (3x3 rotations, body frame to lab), velocity
(nm/ps) and angular velocity (radians/ps, lab frame), as RigidLangevinIntegrator.getRigidBodyStates() returns them."""


def rigid_body_states(lists):
    """RigidBodyStates from the four flat lists of RigidLangevinIntegrator._getRigidBodyStates()."""
    centers, orientations, velocities, angular = (np.array(values, dtype=float) for values in lists)
    return RigidBodyStates(unit.Quantity(centers.reshape(-1, 3), unit.nanometer), orientations.reshape(-1, 3, 3),
                           unit.Quantity(velocities.reshape(-1, 3), unit.nanometer/unit.picosecond),
                           unit.Quantity(angular.reshape(-1, 3), unit.radian/unit.picosecond))
