"""StickyDipoleForce in openmm.app.ForceField files.

Importing rigidlangevin registers a generator for a <StickyDipoleForce> element:

    <StickyDipoleForce reactionFieldDielectric="80" switchingFraction="0.85">
      <Site type="ssd-M" reference1="H1" reference2="H2" model="SSD/RF"/>
    </StickyDipoleForce>

Each <Site> (by atom type or class) puts a site on every atom of that type, framed by the atoms of
its residue named reference1 and reference2. Its parameters are the named model's, if given, with
any of sigma, epsilon, dipole, nu0, rL, rU, nu0Prime, rLPrime, rUPrime, w0 given as attributes (MD
units: nm, kJ/mol, e*nm) replacing them. createSystem's nonbondedMethod may be NoCutoff,
CutoffNonPeriodic or CutoffPeriodic (the reaction field acts with a cutoff; there is no Ewald sum);
its switchDistance, if given, switches the pair energies, else switchingFraction times the cutoff
does, if the file gives one. Sites in one residue do not interact with each other.
"""
import openmm.app as app
import openmm.unit as unit
import openmm.app.forcefield as forcefield

from .core import StickyDipoleForce
from . import _units


class StickyDipoleForceGenerator:
    """Builds a StickyDipoleForce from a force field's <StickyDipoleForce> element."""

    def __init__(self, forcefield, reactionFieldDielectric, switchingFraction):
        self.ff = forcefield
        self.reactionFieldDielectric = reactionFieldDielectric
        self.switchingFraction = switchingFraction
        self.sites = []  # (set of atom types, reference1 name, reference2 name, 10 parameter values)

    @staticmethod
    def parseElement(element, ff):
        dielectric = float(element.attrib.get('reactionFieldDielectric', 80.0))
        fraction = element.attrib.get('switchingFraction')
        fraction = None if fraction is None else float(fraction)
        existing = [g for g in ff._forces if isinstance(g, StickyDipoleForceGenerator)]
        if existing:
            generator = existing[0]
            if generator.reactionFieldDielectric != dielectric or generator.switchingFraction != fraction:
                raise ValueError('Found <StickyDipoleForce> elements with different reactionFieldDielectric or switchingFraction')
        else:
            generator = StickyDipoleForceGenerator(ff, dielectric, fraction)
            ff.registerGenerator(generator)
        for site in element.findall('Site'):
            types = ff._findAtomTypes(site.attrib, 1)[0]
            if types is None:
                raise ValueError(f'<StickyDipoleForce> <Site {site.attrib}>: no atom type or class of that name')
            for name in ('reference1', 'reference2'):
                if name not in site.attrib:
                    raise ValueError(f'<StickyDipoleForce> <Site {site.attrib}> needs the attribute {name} (an atom name in its residue)')
            parameters = {k: float(v) for k, v in site.attrib.items() if k in StickyDipoleForce.PARAMETER_NAMES}
            values = _units.sticky_dipole_values(site.attrib.get('model'), parameters)
            generator.sites.append((types, site.attrib['reference1'], site.attrib['reference2'], values))

    def createForce(self, sys, data, nonbondedMethod, nonbondedCutoff, args):
        methods = {app.NoCutoff: StickyDipoleForce.NoCutoff, app.CutoffNonPeriodic: StickyDipoleForce.CutoffNonPeriodic,
                   app.CutoffPeriodic: StickyDipoleForce.CutoffPeriodic}
        if nonbondedMethod not in methods:
            raise ValueError(f'StickyDipoleForce takes nonbondedMethod NoCutoff, CutoffNonPeriodic or CutoffPeriodic (its reaction '
                             f'field acts beyond the cutoff; it has no Ewald sum), not {nonbondedMethod}')
        force = StickyDipoleForce()
        force.setNonbondedMethod(methods[nonbondedMethod])
        cutoff = nonbondedCutoff.value_in_unit(unit.nanometer) if unit.is_quantity(nonbondedCutoff) else float(nonbondedCutoff)
        force.setCutoffDistance(cutoff)
        force.setReactionFieldDielectric(self.reactionFieldDielectric)
        switch = args['switchDistance']
        if switch is not None:
            force.setUseSwitchingFunction(True)
            force.setSwitchingDistance(switch)
        elif self.switchingFraction is not None and nonbondedMethod != app.NoCutoff:
            force.setUseSwitchingFunction(True)
            force.setSwitchingDistance(self.switchingFraction*cutoff)
        sitesOfResidue = {}
        for atom in data.atoms:
            for types, name1, name2, values in self.sites:
                if data.atomType[atom] in types:
                    named = {a.name: a.index for a in atom.residue.atoms()}
                    for name in (name1, name2):
                        if name not in named:
                            raise ValueError(f'StickyDipoleForce: the site on atom {atom} needs an atom named {name} in its residue')
                    site = force._addSite(atom.index, named[name1], named[name2], values)
                    for other in sitesOfResidue.setdefault(atom.residue.index, []):
                        force.addExclusion(other, site)
                    sitesOfResidue[atom.residue.index].append(site)
                    break
        sys.addForce(force)


forcefield.parsers['StickyDipoleForce'] = StickyDipoleForceGenerator.parseElement
