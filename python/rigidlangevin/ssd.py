"""Boxes of soft sticky dipole (SSD-family) water: Topology, System and positions for StickyDipoleForce.

Each molecule is an oxygen and two hydrogens (O-H 0.09572 nm, H-O-H 104.52 degrees; masses 15.9994
and 1.00795 amu, 18.0153 in all) held rigid by three distance constraints, and a massless site M at
the centre of mass (a ThreeParticleAverageSite of O, H1, H2 with mass weights), which carries the
StickyDipoleForce site framed by H1 and H2. The molecule's inertia is then the SSD family's
(I = 1.7696, 0.6145, 1.1550 amu A^2 about the body x, y, z axes), and it stays rigid under any
integrator that honours constraints; RigidLangevinIntegrator moves each molecule as one body
(addRigidBodies(..., residues='water')). Only M interacts.

    topology, system, positions = rigidlangevin.ssd.waterBox(256, model='SSD/RF')

The same molecules come from openmm.app.ForceField with forceField(model) (rigidWater, the
default, makes the constraints), for any Topology whose waters are residues HOH of atoms O, H1,
H2 and M (waterBox's topology, for one).
"""
import io
import math

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit

from .core import StickyDipoleForce

OXYGEN_MASS = 15.9994
HYDROGEN_MASS = 1.00795
OH_LENGTH = 0.09572  # nm
HOH_ANGLE = math.radians(104.52)


def moleculeGeometry():
    """Positions (nm) of O, H1, H2 and M in the molecule's body frame: M at the origin (the centre of
    mass), z towards the hydrogens, the molecule in the yz-plane, y from H2 towards H1."""
    half = HOH_ANGLE/2
    hydrogen_z = OH_LENGTH*math.cos(half)
    total = OXYGEN_MASS+2*HYDROGEN_MASS
    oxygen_z = -2*HYDROGEN_MASS*hydrogen_z/total  # so that the centre of mass is at 0
    return np.array([[0.0, 0.0, oxygen_z],
                     [0.0, OH_LENGTH*math.sin(half), oxygen_z+hydrogen_z],
                     [0.0, -OH_LENGTH*math.sin(half), oxygen_z+hydrogen_z],
                     [0.0, 0.0, 0.0]])


def _random_rotation(random):
    q = random.normal(size=4)
    a, b, c, d = q/np.linalg.norm(q)
    return np.array([[a*a+b*b-c*c-d*d, 2*(b*c-a*d), 2*(b*d+a*c)],
                     [2*(b*c+a*d), a*a-b*b+c*c-d*d, 2*(c*d-a*b)],
                     [2*(b*d-a*c), 2*(c*d+a*b), a*a-b*b-c*c+d*d]])


def waterBox(numWaters=256, model='SSD/RF', boxSize=1.97166*unit.nanometer, cutoff=0.9*unit.nanometer,
             switchingDistance=None, reactionFieldDielectric=80.0, seed=1):
    """A cubic periodic box of SSD-family waters on a lattice with random orientations (minimise and
    equilibrate before use). The defaults are the source's scene: 256 waters in a 19.7166 A box, a
    9 A cutoff, switched from 0.85 of the cutoff, reaction field of dielectric 80. Where the switch
    starts changes the liquid: SSD/RF's published density and diffusion (Fennell & Gezelter 2004)
    come out with switchingDistance=0.95*cutoff, OOPSE's choice for reaction-field runs; switched
    from 7.7 A (0.86 of the cutoff) it is 0.9% denser and diffuses 24% slower (examples/ssd_properties.py).

    Returns (topology, system, positions); the StickyDipoleForce is the system's only force.
    """
    box = boxSize.value_in_unit(unit.nanometer) if unit.is_quantity(boxSize) else float(boxSize)
    rc = cutoff.value_in_unit(unit.nanometer) if unit.is_quantity(cutoff) else float(cutoff)
    if switchingDistance is None:
        switch = 0.85*rc
    else:
        switch = switchingDistance.value_in_unit(unit.nanometer) if unit.is_quantity(switchingDistance) else float(switchingDistance)
    perSide = math.ceil(numWaters**(1/3)-1e-9)
    spacing = box/perSide
    random = np.random.default_rng(seed)
    geometry = moleculeGeometry()

    topology = app.Topology()
    topology.setPeriodicBoxVectors(np.eye(3)*box*unit.nanometer)
    chain = topology.addChain()
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(box, 0, 0), mm.Vec3(0, box, 0), mm.Vec3(0, 0, box))
    force = StickyDipoleForce()
    force.setNonbondedMethod(StickyDipoleForce.CutoffPeriodic)
    force.setCutoffDistance(rc)
    force.setUseSwitchingFunction(True)
    force.setSwitchingDistance(switch)
    force.setReactionFieldDielectric(reactionFieldDielectric)
    positions = []
    cells = [(i, j, k) for i in range(perSide) for j in range(perSide) for k in range(perSide)]
    for n in range(numWaters):
        residue = topology.addResidue('HOH', chain)
        atoms = [topology.addAtom('O', app.element.oxygen, residue), topology.addAtom('H1', app.element.hydrogen, residue),
                 topology.addAtom('H2', app.element.hydrogen, residue), topology.addAtom('M', None, residue)]
        topology.addBond(atoms[0], atoms[1])
        topology.addBond(atoms[0], atoms[2])
        o = system.addParticle(OXYGEN_MASS)
        h1 = system.addParticle(HYDROGEN_MASS)
        h2 = system.addParticle(HYDROGEN_MASS)
        m = system.addParticle(0.0)
        total = OXYGEN_MASS+2*HYDROGEN_MASS
        system.setVirtualSite(m, mm.ThreeParticleAverageSite(o, h1, h2, OXYGEN_MASS/total, HYDROGEN_MASS/total, HYDROGEN_MASS/total))
        system.addConstraint(o, h1, OH_LENGTH)
        system.addConstraint(o, h2, OH_LENGTH)
        system.addConstraint(h1, h2, 2*OH_LENGTH*math.sin(HOH_ANGLE/2))
        force.addSite(m, h1, h2, model)
        center = (np.array(cells[n])+0.5)*spacing
        rotation = _random_rotation(random)
        positions.extend(mm.Vec3(*(center+rotation@atom)) for atom in geometry)
    system.addForce(force)
    return topology, system, unit.Quantity(positions, unit.nanometer)


def forceFieldXml(model='SSD/RF', reactionFieldDielectric=80.0, switchingFraction=0.85):
    """A force field file (as text) for SSD-family water of the named model: atom types, the residue
    template HOH (O, H1, H2 and the site M, a mass-weighted average of the three), the geometry as
    harmonic terms that rigidWater turns into constraints, and the <StickyDipoleForce>."""
    tag = ''.join(c for c in model.lower() if c.isalnum())
    total = OXYGEN_MASS+2*HYDROGEN_MASS
    return f"""<ForceField>
 <AtomTypes>
  <Type name="{tag}-O" class="{tag}-OW" element="O" mass="{OXYGEN_MASS!r}"/>
  <Type name="{tag}-H" class="{tag}-HW" element="H" mass="{HYDROGEN_MASS!r}"/>
  <Type name="{tag}-M" class="{tag}-MW" mass="0"/>
 </AtomTypes>
 <Residues>
  <Residue name="HOH">
   <Atom name="O" type="{tag}-O"/>
   <Atom name="H1" type="{tag}-H"/>
   <Atom name="H2" type="{tag}-H"/>
   <Atom name="M" type="{tag}-M"/>
   <VirtualSite type="average3" siteName="M" atomName1="O" atomName2="H1" atomName3="H2" weight1="{OXYGEN_MASS/total!r}" weight2="{HYDROGEN_MASS/total!r}" weight3="{HYDROGEN_MASS/total!r}"/>
   <Bond atomName1="O" atomName2="H1"/>
   <Bond atomName1="O" atomName2="H2"/>
  </Residue>
 </Residues>
 <HarmonicBondForce>
  <Bond type1="{tag}-O" type2="{tag}-H" length="{OH_LENGTH!r}" k="462750.4"/>
 </HarmonicBondForce>
 <HarmonicAngleForce>
  <Angle type1="{tag}-H" type2="{tag}-O" type3="{tag}-H" angle="{HOH_ANGLE!r}" k="836.8"/>
 </HarmonicAngleForce>
 <StickyDipoleForce reactionFieldDielectric="{reactionFieldDielectric!r}" switchingFraction="{switchingFraction!r}">
  <Site type="{tag}-M" reference1="H1" reference2="H2" model="{model}"/>
 </StickyDipoleForce>
</ForceField>
"""


def forceField(model='SSD/RF', **options):
    """An openmm.app.ForceField of SSD-family water (see forceFieldXml for the options)."""
    return app.ForceField(io.StringIO(forceFieldXml(model, **options)))
