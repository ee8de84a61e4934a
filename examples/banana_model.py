"""The source's second scene, its model in one place: banana-shaped molecules of three Gay-Berne
ellipsoids, and united-atom pentane.

The banana (Sun, Lin & Gezelter, J. Chem. Phys. 128, 234107 (2008), section IV B) is three
Gay-Berne ellipsoids rigidly joined. The source does not give its geometry. Its ellipsoid is taken
from the Gezelter group's own force field: OpenMD's DUFF.frc, atom type GBPaper (breadth d = 3.35 A,
length l = 10.05 A, side-by-side well 0.774729 and end-to-end well 0.154945 kcal/mol, mass
48.0428 amu, moments of inertia 86.477, 86.477, 0 amu A^2), the only Gay-Berne type there named
for a paper. The bent core is our assumption: the middle ellipsoid along x, each end ellipsoid
joined tip to tip with it and turned by BEND (45 degrees, an opening angle of 135 degrees) toward
+y, all three in the xy plane. That bend makes the ratio of the smallest to the largest
rotational resistance that of the source's tensor (0.18); no bend of these ellipsoids reproduces
the source's tensor itself (see banana_scene.py and docs/banana.md).

Each ellipsoid is two particles of half its mass on its axis, +-s from its centre with
s = sqrt(I_perp/m), which gives it exactly its mass and moments of inertia, and a massless virtual
site at its centre that carries the Gay-Berne interaction; the ellipsoid's x axis points at its
first mass particle, so OpenMM's GayBerneForce takes its frame from particles inside the body.

OpenMM's GayBerneForce is the Berardi-Fava-Zannoni / Everaers-Ejtehadi generalisation, not DUFF's
mu = 2, nu = 1 form: its widths are the ellipsoid's (l, d, d), sigma is d, the end-to-end
strength is ex = eps_end/eps_side, and epsilon is scaled so that the two defining wells come out
exactly: -eps_side side by side at d + (2^(1/6)-1) d and -eps_end end to end at
l + (2^(1/6)-1) d (tests/test_banana.py checks both). Other orientations differ from DUFF's form.

Pentane is TraPPE-UA (Martin & Siepmann, J. Phys. Chem. B 102, 2569 (1998)): CH3 and CH2 sites,
bonds fixed at 1.54 A, harmonic bends, the OPLS torsion, Lennard-Jones between sites more than
three bonds apart and between molecules (bonds harmonic: see BOND_K), cut at TraPPE's own 1.4 nm
with its analytic tail corrections to the energy and pressure.

The scene's forces (SceneForces) give every pair its own form and no pair twice:
- site-site pairs: Lennard-Jones in a NonbondedForce, cut at 1.4 nm, with its dispersion
  correction (OpenMM's analytic tail for g(r) = 1 beyond the cutoff, summed over the sites' classes
  with Lorentz-Berthelot mixing: TraPPE's own treatment, exact for the energy and the pressure the
  barostat sees; tests/test_banana.py checks it against a direct sum);
- pairs with an ellipsoid: OpenMM's GayBerneForce, cut at 1.4 nm. Ellipsoid-ellipsoid pairs come
  from its particles; each ellipsoid-site pair is an exception carrying exactly the parameters
  GayBerneForce's mixing would give (sigma_ij = (d + sigma_site)/2, eps_ij = sqrt(eps eps_site)),
  so that the sites, whose own epsilon there is zero, cost GayBerneForce nothing among
  themselves. A site meets an ellipsoid through OpenMM's Gay-Berne form, the ellipsoid's shape
  and end-to-end strength setting contact and well along each of its axes. Those pairs have no
  tail correction: the dispersion of 6 ellipsoids beyond 1.4 nm, an estimated 0.02% of the
  scene's energy.
That split changes no energy from one GayBerneForce holding every particle (all_in_gayberne=True,
kept for the test that shows it and for the speed comparison): on the CPU platform
GayBerneForce's scalar pair loop costs six times NonbondedForce's vectorised one at 1.4 nm.
"""
import math

import numpy as np
import openmm as mm
import openmm.unit as unit

KCAL = 4.184  # kJ per kcal
BOLTZ = unit.MOLAR_GAS_CONSTANT_R.value_in_unit(unit.kilojoule_per_mole/unit.kelvin)

# The ellipsoid: OpenMD forceFields/DUFF.frc, atom type GBPaper (nm, kJ/mol, amu).
GB_BREADTH = 0.335
GB_LENGTH = 1.005
GB_EPS_SIDE = 0.774729*KCAL
GB_EPS_END = 0.154945*KCAL
GB_MASS = 48.0428
GB_INERTIA_PERP = 0.86477  # amu nm^2 (86.477 amu A^2); zero about the axis

# OpenMM's Gay-Berne well for two of these ellipsoids side by side, in units of its epsilon
# (2/sqrt(3) for widths (l, d, d) with sigma = d; tests/test_banana.py checks the resulting wells).
OPENMM_SIDE_WELL = 2/math.sqrt(3)

BEND = math.radians(45.0)
AXIS_OFFSET = math.sqrt(GB_INERTIA_PERP/GB_MASS)

# The source's numbers (its section IV B).
SOURCE_TEMPERATURE = 273.0  # K
SOURCE_VISCOSITY = 0.289e-2  # poise (0.289 cP)
SOURCE_CENTER_OF_RESISTANCE = np.array([0.0, 0.7482, -0.1988])  # A, frame not stated
SOURCE_TENSOR = np.array([[0.9261, 0, 0, 0, 0.08585, 0.2057],
                          [0, 0.9270, -0.007063, 0.08585, 0, 0],
                          [0, -0.007063, 0.7494, 0.2057, 0, 0],
                          [0, 0.0858, 0.2057, 58.64, 0, 0],
                          [0.08585, 0, 0, 0, 48.30, 3.219],
                          [0.2057, 0, 0, 0, 3.219, 10.7373]])
SOURCE_SHELL_BEADS = 2266
SOURCE_BEAD_SIZE = 0.03  # nm

# TraPPE-UA (Martin & Siepmann 1998): sigma (nm), epsilon/k_B (K), mass (amu).
TRAPPE_SITES = {'CH3': (0.375, 98.0, 15.035), 'CH2': (0.395, 46.0, 14.027)}
TRAPPE_BOND = 0.154  # nm
# TraPPE fixes its bonds; this plugin's integrator moves free particles without constraints, so the
# bonds are harmonic with OPLS-UA's force constant (Jorgensen, Madura & Swenson, J. Am. Chem. Soc.
# 106, 6638 (1984): 260 kcal/mol/A^2 in k (r - r0)^2), which needs a 1 fs step.
BOND_K = 2*260.0*KCAL*100  # kJ/mol/nm^2 in OpenMM's k/2 (r - r0)^2
TRAPPE_ANGLE = math.radians(114.0)
TRAPPE_ANGLE_K = 62500.0  # K/rad^2, U = k/2 (theta - theta0)^2
TRAPPE_TORSION = (355.03, -68.19, 791.32)  # K: c1 (1 + cos phi) + c2 (1 - cos 2 phi) + c3 (1 + cos 3 phi)
PENTANE_MASS = 2*15.035+3*14.027
# TraPPE-UA's Lennard-Jones cutoff (nm), with analytic tail corrections; the scene's Gay-Berne pairs
# are cut there too.
CUTOFF = 1.4


def ellipsoids():
    """Centres (nm) and unit long axes of the banana's three ellipsoids in its own frame: the
    middle one along x at the origin, the ends turned by BEND toward +y, tip to tip with it."""
    half = GB_LENGTH/2
    centers, axes = [np.zeros(3)], [np.array([1.0, 0, 0])]
    for side in (-1, 1):
        axis = np.array([side*math.cos(BEND), math.sin(BEND), 0.0])
        centers.insert(0 if side < 0 else 2, np.array([side*half, 0, 0])+half*axis)
        axes.insert(0 if side < 0 else 2, axis)
    return np.array(centers), np.array(axes)


def banana_positions():
    """Positions (nm) of one banana's nine particles in its own frame, centre of mass at the
    origin: for each ellipsoid (end, middle, end) its centre, then its two mass particles."""
    centers, axes = ellipsoids()
    centers = centers-centers.mean(axis=0)
    points = []
    for c, u in zip(centers, axes):
        points += [c, c+AXIS_OFFSET*u, c-AXIS_OFFSET*u]
    return np.array(points)


class SceneForces:
    """The scene's forces, filled particle by particle (see the module's text): Lennard-Jones among
    pentane sites in `lennard_jones` (a NonbondedForce), every pair with an ellipsoid in `gayberne`,
    the pentanes' bonds, bends and torsions in `bonds`, `angles` and `torsions`. cutoff (nm) None
    means no cutoff and no periodic box; all_in_gayberne puts the sites' Lennard-Jones in the
    GayBerneForce too (as spheres: exactly Lennard-Jones, with no tail correction), as the model
    was first built. Call add_to(system) once every particle is in."""

    def __init__(self, cutoff=CUTOFF, dispersion_correction=True, all_in_gayberne=False):
        self.gayberne = gayberne_force(cutoff)
        self.lennard_jones = None if all_in_gayberne else mm.NonbondedForce()
        if self.lennard_jones is not None:
            if cutoff is None:
                self.lennard_jones.setNonbondedMethod(mm.NonbondedForce.NoCutoff)
            else:
                self.lennard_jones.setNonbondedMethod(mm.NonbondedForce.CutoffPeriodic)
                self.lennard_jones.setCutoffDistance(cutoff)
                self.lennard_jones.setUseSwitchingFunction(False)
                self.lennard_jones.setUseDispersionCorrection(dispersion_correction)
        self.bonds, self.angles, self.torsions = mm.HarmonicBondForce(), mm.HarmonicAngleForce(), mm.RBTorsionForce()
        self.sites, self.ellipsoids = [], []  # (particle, sigma, epsilon)
        self.excluded = set()

    def add_site(self, particle, sigma, epsilon):
        """A Lennard-Jones site (nm, kJ/mol)."""
        assert particle == self.gayberne.getNumParticles()
        self.sites.append((particle, sigma, epsilon))
        gb_epsilon = epsilon if self.lennard_jones is None else 0.0
        self.gayberne.addParticle(sigma, gb_epsilon, -1, -1, sigma, sigma, sigma, 1.0, 1.0, 1.0)
        if self.lennard_jones is not None:
            self.lennard_jones.addParticle(0.0, sigma, epsilon)

    def add_ellipsoid(self, particle, axis_particle):
        """One GBPaper ellipsoid at particle, its long (x) axis pointing at axis_particle."""
        assert particle == self.gayberne.getNumParticles()
        epsilon = GB_EPS_SIDE/OPENMM_SIDE_WELL
        self.ellipsoids.append((particle, GB_BREADTH, epsilon))
        self.gayberne.addParticle(GB_BREADTH, epsilon, axis_particle, -1, GB_LENGTH, GB_BREADTH, GB_BREADTH, GB_EPS_END/GB_EPS_SIDE, 1.0, 1.0)
        if self.lennard_jones is not None:
            self.lennard_jones.addParticle(0.0, 1.0, 0.0)

    def add_inert(self, particle):
        """A particle that no nonbonded force acts on (a banana's mass particles)."""
        assert particle == self.gayberne.getNumParticles()
        self.gayberne.addParticle(GB_BREADTH, 0.0, -1, -1, GB_BREADTH, GB_BREADTH, GB_BREADTH, 1.0, 1.0, 1.0)
        if self.lennard_jones is not None:
            self.lennard_jones.addParticle(0.0, 1.0, 0.0)

    def exclude(self, i, j):
        """No nonbonded interaction between particles i and j. Both forces get the same exclusions:
        the CPU platform requires it of forces that share its neighbour list. An exception's
        sigma must not be 0: OpenMM's Gay-Berne force takes 0/0 for the force of an excluded pair
        of overlapping ellipsoids then (NaN forces)."""
        self.excluded.add((min(i, j), max(i, j)))
        self.gayberne.addException(i, j, 1.0, 0.0)
        if self.lennard_jones is not None:
            self.lennard_jones.addException(i, j, 0.0, 1.0, 0.0)

    def add_to(self, system):
        """Give every ellipsoid-site pair its Gay-Berne exception and add the forces that act on
        anything to system; returns {name: force} of those added."""
        if self.lennard_jones is not None:
            for e, e_sigma, e_epsilon in self.ellipsoids:
                for s, s_sigma, s_epsilon in self.sites:
                    if (min(e, s), max(e, s)) not in self.excluded:
                        self.gayberne.addException(e, s, (e_sigma+s_sigma)/2, math.sqrt(e_epsilon*s_epsilon))
                        self.lennard_jones.addException(e, s, 0.0, 1.0, 0.0)
        added = {}
        if self.ellipsoids or (self.lennard_jones is None and self.sites):
            added['gayberne'] = self.gayberne
        if self.lennard_jones is not None and self.sites:
            added['lennard_jones'] = self.lennard_jones
        for name in ('bonds', 'angles', 'torsions'):
            force = getattr(self, name)
            if force.getNumBonds() if name == 'bonds' else force.getNumAngles() if name == 'angles' else force.getNumTorsions():
                added[name] = force
        for force in added.values():
            system.addForce(force)
        return added


def add_banana(system, forces, positions, rotation=np.eye(3), translation=np.zeros(3)):
    """Add one banana (nine particles) to system and forces (SceneForces), placed at
    rotation @ r + translation; append its positions (nm) to the list positions and return its
    particle indices."""
    first = system.getNumParticles()
    for k, p in enumerate(banana_positions()):
        system.addParticle(0.0 if k % 3 == 0 else GB_MASS/2)
        positions.append(mm.Vec3(*(rotation@p+translation)))
    for e in range(3):
        center, plus, minus = first+3*e, first+3*e+1, first+3*e+2
        system.setVirtualSite(center, mm.TwoParticleAverageSite(plus, minus, 0.5, 0.5))
    return _add_banana_to_forces(forces, first, 9)


def _add_banana_to_forces(forces, first, count):
    """The banana's particles first..first+count-1 in forces: the ellipsoid centres (every third
    from first, oriented by the next particle), the others inert, every pair inside excluded;
    returns the particle indices."""
    for k in range(count):
        if k < 9 and k % 3 == 0:
            forces.add_ellipsoid(first+k, first+k+1)
        else:
            forces.add_inert(first+k)
    members = list(range(first, first+count))
    for i in members:
        for j in members:
            if i < j:
                forces.exclude(i, j)
    return members

def add_constrained_banana(system, forces, positions, rotation=np.eye(3), translation=np.zeros(3), thickness=0.02):
    """A banana for OpenMM's own integrators, rigid through constraints: the nine particles of
    add_banana(), all massless virtual sites here, on a tetrahedron of four massive particles (a
    quarter of the mass each) joined by six constraints. The tetrahedron (+-a, 0, h), (0, +-b, -h)
    about the centre of mass has the banana's mass and second moments along x and y; the banana is
    flat, which constraints cannot hold rigid, so the tetrahedron has a height 2h = thickness
    (nm), adding M h^2 to two of the moments of inertia (about 1% for the default). Returns the
    13 particle indices: the nine in add_banana()'s order, then the tetrahedron."""
    points = banana_positions()
    masses = np.array([0.0 if k % 3 == 0 else GB_MASS/2 for k in range(9)])
    total = masses.sum()
    second = (masses[:, None]*points).T@points
    a, b, h = math.sqrt(2*second[0, 0]/total), math.sqrt(2*second[1, 1]/total), thickness/2
    frame = np.array([[a, 0, h], [-a, 0, h], [0, b, -h], [0, -b, -h]])
    first = system.getNumParticles()
    for p in points:
        system.addParticle(0.0)
        positions.append(mm.Vec3(*(rotation@p+translation)))
    for p in frame:
        system.addParticle(total/4)
        positions.append(mm.Vec3(*(rotation@p+translation)))
    corners = [first+9+k for k in range(4)]
    # Each site in the frame OpenMM's LocalCoordinatesSite builds from corners 0, 1, 2: origin their
    # midpoint of 0 and 1, x along 1 -> 0, y toward corner 2.
    origin = (frame[0]+frame[1])/2
    x = frame[0]-frame[1]
    y = frame[2]-origin
    z = np.cross(x, y)
    x, z = x/np.linalg.norm(x), z/np.linalg.norm(z)
    local = np.array([x, np.cross(z, x), z])
    for k, p in enumerate(points):
        site = mm.LocalCoordinatesSite(corners[:3], [0.5, 0.5, 0.0], [1.0, -1.0, 0.0], [-0.5, -0.5, 1.0], mm.Vec3(*(local@(p-origin))))
        system.setVirtualSite(first+k, site)
    for i in range(4):
        for j in range(i+1, 4):
            system.addConstraint(corners[i], corners[j], float(np.linalg.norm(frame[i]-frame[j])))
    return _add_banana_to_forces(forces, first, 13)


def gayberne_force(cutoff=None):
    """A GayBerneForce with this scene's settings: periodic, cut at cutoff (nm) without a switch as
    TraPPE cuts its Lennard-Jones, or no cutoff."""
    force = mm.GayBerneForce()
    if cutoff is None:
        force.setNonbondedMethod(mm.GayBerneForce.NoCutoff)
    else:
        force.setNonbondedMethod(mm.GayBerneForce.CutoffPeriodic)
        force.setCutoffDistance(cutoff)
        force.setUseSwitchingFunction(False)
    return force


# Platforms whose GayBerneForce applies periodic boundary conditions to exceptions. OpenMM's common
# kernel (OpenCL, CUDA, HIP; platforms/common/src/kernels/gayBerne.cc, 8.x) takes an exception's
# distance without them, so an exception pair across the box's edge is beyond the cutoff and drops
# out; the scene's ellipsoid-site pairs are all exceptions (SceneForces.add_to()).
PERIODIC_GAYBERNE_EXCEPTIONS = ('Reference', 'CPU')


def scene_context(system, integrator, platform, properties=None):
    """A Context for a System of this scene on platform (a name). Refused (OpenMMException, naming
    the platform and the fix) where the System's periodic GayBerneForce has an exception that
    interacts and the platform's Gay-Berne kernel would drop it across the box's edge."""
    if platform not in PERIODIC_GAYBERNE_EXCEPTIONS:
        for force in system.getForces():
            if isinstance(force, mm.GayBerneForce) and force.usesPeriodicBoundaryConditions() and any(
                    force.getExceptionParameters(i)[3] != 0
                    for i in range(force.getNumExceptions())):
                raise mm.OpenMMException(
                    f'this scene cannot run on the {platform} platform: its GayBerneForce gives the ellipsoid-site pairs as exceptions, '
                    f'and OpenMM\'s {platform} Gay-Berne kernel drops an exception across the periodic box\'s edge (it takes the '
                    f'distance without periodic boundary conditions). Use --platform CPU (or Reference); the scene without pentanes '
                    f'(the implicit runs) has no such exceptions and runs anywhere')
    return mm.Context(system, integrator, mm.Platform.getPlatformByName(platform), properties or {})


def resistance_tensor(maxBeads=2000):
    """The banana's resistance per unit viscosity: the rough shell of its three ellipsoids
    extrapolated to zero bead size, in the frame of banana_positions()."""
    import rigidlangevin.hydrodynamics as hydro
    centers, axes = ellipsoids()
    centers = centers-centers.mean(axis=0)
    return hydro.spheroidShellExtrapolated(centers, axes, GB_LENGTH/2, GB_BREADTH/2, maxBeads=maxBeads)


def source_size_shell():
    """The rough shell at the source's resolution: the bead radius that gives about 2266 beads
    (the source's count; its 'bead size of 0.3 A' then reads as a diameter), and the tensor."""
    import rigidlangevin.hydrodynamics as hydro
    centers, axes = ellipsoids()
    centers = centers-centers.mean(axis=0)
    radius = SOURCE_BEAD_SIZE/2
    for _ in range(4):
        count = len(hydro.spheroidRoughShellBeads(centers, axes, GB_LENGTH/2, GB_BREADTH/2, radius))
        radius *= math.sqrt(count/SOURCE_SHELL_BEADS)
    count = len(hydro.spheroidRoughShellBeads(centers, axes, GB_LENGTH/2, GB_BREADTH/2, radius))
    return radius, count, hydro.spheroidRoughShell(centers, axes, GB_LENGTH/2, GB_BREADTH/2, radius)


def source_frame(matrix):
    """A 6x6 tensor turned from the banana's frame (x long, y bend, z normal) into the source's
    (z long, y bend, x normal: smallest translational and rotational resistance along z, the
    centre of resistance displaced along y): a turn by -90 degrees about y. Returns the turned
    tensor and the 3x3 turn."""
    turn = np.array([[0, 0, -1], [0, 1, 0], [1, 0, 0]], dtype=float)
    t = np.zeros((6, 6))
    t[:3, :3] = t[3:, 3:] = turn
    return t@matrix@t.T, turn


def source_units(viscosity_poise=SOURCE_VISCOSITY):
    """Elementwise factors that turn a resistance per unit viscosity (OpenMM's units: nm, nm^2,
    nm^3 for the translational, coupling and rotational blocks) into the friction at
    viscosity_poise in the units of the source's code (amu/fs, amu A/fs, amu A^2/fs)."""
    # amu/(nm ps) x nm = amu/ps = 1e-3 amu/fs; x nm^2 (coupling) -> amu A/fs x 10; x nm^3 -> amu A^2/fs x 100.
    scale = np.ones((6, 6))*1e-3*viscosity_md_units(viscosity_poise)
    scale[:3, 3:] *= 10
    scale[3:, :3] *= 10
    scale[3:, 3:] *= 100
    return scale


def source_resistance_tensor():
    """The source's own tensor (SOURCE_TENSOR, about SOURCE_CENTER_OF_RESISTANCE) read as the
    friction at SOURCE_VISCOSITY in the units of its code and in the frame source_frame() says
    (tensor.md shows why: its numbers are Stokes's law's for an object of a few A at 0.289 cP), as a
    resistance per unit viscosity in the banana's frame about its centre of mass: the source's
    banana as this project's integrator would move it."""
    import rigidlangevin.hydrodynamics as hydro
    per_viscosity = (SOURCE_TENSOR+SOURCE_TENSOR.T)/2/source_units()  # its 0.0858 and 0.08585 made one
    _, turn = source_frame(np.eye(6))
    back = np.zeros((6, 6))
    back[:3, :3] = back[3:, 3:] = turn.T
    origin = turn.T@SOURCE_CENTER_OF_RESISTANCE/10  # nm, from the centre of mass
    return hydro.explicit(back@per_viscosity@back.T, origin)


def viscosity_md_units(poise):
    """A viscosity in amu/(nm ps) (OpenMM's units: kJ/mol ps / nm^3 = amu/(nm ps))."""
    return poise*0.1/1.66053906660e-27*1e-9*1e-12


def add_pentane(system, forces, positions, start, direction):
    """Add one all-trans TraPPE-UA pentane (5 sites) to system and forces (SceneForces) starting at
    start (nm) along the unit vector direction; returns the site indices."""
    kinds = ['CH3', 'CH2', 'CH2', 'CH2', 'CH3']
    first = system.getNumParticles()
    # Zig-zag in the plane of direction and a perpendicular.
    perp = np.cross(direction, [0.0, 0.0, 1.0] if abs(direction[2]) < 0.9 else [1.0, 0.0, 0.0])
    perp /= np.linalg.norm(perp)
    rise = TRAPPE_BOND*math.sin(TRAPPE_ANGLE/2)
    wobble = TRAPPE_BOND*math.cos(TRAPPE_ANGLE/2)
    for k, kind in enumerate(kinds):
        sigma, eps_k, mass = TRAPPE_SITES[kind]
        system.addParticle(mass)
        forces.add_site(first+k, sigma, eps_k*BOLTZ)
        positions.append(mm.Vec3(*(start+k*rise*direction+(k % 2)*wobble*perp)))
    sites = list(range(first, first+5))
    for k in range(4):
        forces.bonds.addBond(sites[k], sites[k+1], TRAPPE_BOND, BOND_K)
    for k in range(3):
        forces.angles.addAngle(sites[k], sites[k+1], sites[k+2], TRAPPE_ANGLE, TRAPPE_ANGLE_K*BOLTZ)
    # c1 (1 + cos phi) + c2 (1 - cos 2 phi) + c3 (1 + cos 3 phi) in Ryckaert-Bellemans form (psi =
    # phi - 180 degrees, OpenMM's convention): C0 = c1 + 2 c2 + c3, C1 = -c1 + 3 c3, C2 = -2 c2, C3 = -4 c3.
    c1, c2, c3 = (c*BOLTZ for c in TRAPPE_TORSION)
    rb = (c1+2*c2+c3, -c1+3*c3, -2*c2, -4*c3, 0.0, 0.0)
    for k in range(2):
        forces.torsions.addTorsion(sites[k], sites[k+1], sites[k+2], sites[k+3], *rb)
    # Lennard-Jones only between sites more than three bonds apart (the two ends).
    for i in range(5):
        for j in range(i+1, min(i+4, 5)):
            forces.exclude(sites[i], sites[j])
    return sites


def pentane_box(num_pentanes, box, seed, bananas=0, cutoff=CUTOFF, constrained=False, all_in_gayberne=False):
    """System and positions (nm) of bananas (first, 9 particles each, or 13 if constrained: see
    add_constrained_banana(); along x at evenly spaced heights) and num_pentanes all-trans pentanes
    along x on a lattice in a cubic box of side box (nm), lattice slots that would overlap a banana
    left out; forces as SceneForces(cutoff, all_in_gayberne=all_in_gayberne) makes them. Returns
    (system, positions, bananas' particle lists, {name: force} of the forces added)."""
    rng = np.random.default_rng(seed)
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(box, 0, 0), mm.Vec3(0, box, 0), mm.Vec3(0, 0, box))
    forces = SceneForces(cutoff, all_in_gayberne=all_in_gayberne)
    positions, bodies, banana_points = [], [], []
    for b in range(bananas):
        # Bananas along x, bend toward +y, at heights spread over the box (the first mid-box).
        translation = np.array([box/2, box*(b+0.5)/bananas, box*(b+0.5)/bananas])
        add = add_constrained_banana if constrained else add_banana
        bodies.append(add(system, forces, positions, np.eye(3), translation))
        centers, axes = ellipsoids()
        centers = centers-centers.mean(axis=0)+translation
        for c, u in zip(centers, axes):
            banana_points += [c+t*u for t in np.linspace(-GB_LENGTH/2+GB_BREADTH/2, GB_LENGTH/2-GB_BREADTH/2, 9)]
    def clear(start):
        if not banana_points:
            return True
        sites = start+np.outer(np.linspace(0, 0.52, 5), [1.0, 0, 0])
        d = sites[:, None, :]-np.array(banana_points)[None, :, :]
        d -= box*np.round(d/box)
        return np.sqrt((d*d).sum(axis=2)).min() > 0.45
    # Slots: 0.9 nm along the chains (x), about the sites' sigma (0.39 nm) across, closer where the
    # bananas leave too few (down to 0.33 nm: a dense start that the first steps relax).
    nx = max(1, int(box/0.9))
    for ny in range(max(1, int(box/0.39)), int(box/0.33)+1):
        slots = [np.array([(i+0.5)*box/nx-0.26, (j+0.5)*box/ny, (k+0.5)*box/ny]) for i in range(nx) for j in range(ny) for k in range(ny)]
        slots = [s for s in slots if clear(s)]
        if len(slots) >= num_pentanes:
            break
    if len(slots) < num_pentanes:
        raise ValueError(f'a box of {box} nm holds only {len(slots)} pentanes beside {bananas} bananas on the starting lattice; use a larger box')
    for index in sorted(rng.choice(len(slots), num_pentanes, replace=False)):
        add_pentane(system, forces, positions, slots[index], np.array([1.0, 0, 0]))
    return system, positions, bodies, forces.add_to(system)
