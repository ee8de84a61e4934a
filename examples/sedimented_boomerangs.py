"""A sedimented suspension of boomerang colloids above a glass wall, with and without hydrodynamic
interactions, against the Gibbs-Boltzmann density of their heights.

The boomerang is the anchors' (Sprinkle et al., JCP 147, 244103 (2017); the scene file
benchmarks/hydrodynamics/boomerang_suspension.py): 15 blobs of radius 0.3246 um, 0.3 um apart, two
arms meeting at a corner, the cross point, whose height this example follows. Its forces are
RigidMultiblobsWall's boomerang input files', as OpenMM forces on the blobs' particles (a
CustomExternalForce): each blob's excess weight 1.539e-4 pN (2.309e-3 pN a body) and the wall's
repulsion U = e exp(-(h - a)/b) above h = a, continued linearly below (e = 23.1 kT, b = a/2), in
water (8.9e-4 Pa s) at 300 K, RigidBrownianIntegrator. There are no
forces between bodies (RigidMultiblobsWall's files add a blob-blob repulsion): bodies may pass
through each other, so each body's density of heights and orientations is exactly the single-body
Gibbs-Boltzmann one, exp(-U/kT), whatever the hydrodynamics. This script computes its density of
cross-point heights by quadrature (heights on a grid; orientations by Gauss-Legendre in cos(theta)
and the trapezoidal rule in phi of the body's normal, converged to 1e-8 in the mean).

The same scene is run twice:
- with hydrodynamic interactions and the no-slip wall z = 0: the bodies' coupled rigid-multiblob
  mobility above the wall (Rotne-Prager-Blake), the stochastic drift kT div N by random finite
  differences;
- without: each body its own 6x6 friction, as alone in unbounded water. There is no wall
  hydrodynamics then either, since the wall acts through the blobs' mobility (setWall() needs
  setHydrodynamicInteractions(True)); the wall's repulsion, a force, is still there.
The statics are the same (hydrodynamics never change the Gibbs-Boltzmann density); the dynamics
are not: near the wall a body moves up and down more slowly with interactions (the right panel
shows the heights' autocorrelation; the default 2-minute run is too short to resolve the
difference, which needs runs of many correlation times). The step is not the same either: with the wall's
hydrodynamics the blobs' mobility vanishes at contact and 0.01 s steps sample the density; without,
a blob pressed against the glass moves as in bulk water, the stiff repulsion throws bodies up, and
Euler-Maruyama's bias falls only linearly with the step: over 16 bodies the mean height is
9.2 +- 0.4 um at 1 ms (120 s), 5.4 +- 0.6 at 0.25 ms and 4.0 +- 0.2 at 0.1 ms (60 s each; the
errors the bodies' spread) against the density's 3.63 um. The table shows that bias at 0.1 ms, the
step used here; a step of about 10 us would remove it, at ten times this run's cost.

Each body starts from a sample of the Gibbs-Boltzmann density itself (orientation by resampling
uniform rotations by their weight, then the height given it), so the run is in equilibrium from its
first step and every step counts; a departure from the density is the integrator's error, and the
heights' autocorrelation shows the bodies have forgotten their start. Mean heights carry the
standard error of 10 block averages of the suspension's mean height (valid where a block outlasts
the heights' correlation time, printed beside it), and, independently, the spread of the bodies'
own means over the bodies.

    python examples/sedimented_boomerangs.py [--quick] [--platform CPU] [--bodies 16] [--seconds 120] [--out DIR]

Every platform runs it (--platform Reference, CPU, OpenCL or CUDA; GPU platforms in double
precision). Writes DIR/table.md and DIR/boomerangs.png (default out/sedimented_boomerangs, outside
version control); the committed results are the default run written with
--out examples/results/sedimented_boomerangs.
"""
import argparse
import math
import os
import pathlib
import sys
import time

import numpy as np
import openmm as mm
import openmm.unit as unit

import rigidlangevin as rl
import rigidlangevin.hydrodynamics as hydro
from rigidlangevin.statistics import block_error, standard_error

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]/'benchmarks'/'hydrodynamics'))
from boomerang_suspension import BLOB_RADIUS_UM, boomerang_blobs  # noqa: E402  (the scene's body)

TEMPERATURE = 300.0                      # K
KT = unit.MOLAR_GAS_CONSTANT_R.value_in_unit(unit.kilojoule_per_mole/unit.kelvin)*TEMPERATURE  # kJ/mol
VISCOSITY = 8.9e-4*10*rl.poise           # water, 8.9e-4 Pa s
# Steps (ps): 0.01 s with the wall's hydrodynamics (RigidMultiblobsWall's boomerang files'); 0.1 ms
# without, where a blob near the glass moves as freely as in bulk water: the repulsion's stiffness
# (e/b^2 = 877 kT/um^2 a blob) times a tip's rotational mobility is about 1000/s, so 0.01 s steps
# throw bodies off the wall (the mean height climbs by microns within 20 steps) and 1 ms and 0.25 ms
# steps still lift it (to 9.2 and 5.4 um against 3.6 in a minute). With the wall, the blobs'
# mobility vanishes at contact, which tames the stiffness.
STEP_PS = {True: 1e10, False: 1e8}
SAMPLE_S = 0.1                           # between samples of the heights
NM_PER_UM = 1000.0
# RigidMultiblobsWall's boomerang input files, in its units (um, s, mg): kT, each blob's weight g
# (pN), the wall's repulsion strength e (pN um) and decay length b (um).
PEER_KT, PEER_WEIGHT, PEER_REPULSION, PEER_DECAY = 0.0041419464, 0.0001539384, 0.095713728509, 0.162278695459
BLOBS_UM = boomerang_blobs()
CROSS_POINT = int(np.argmin(np.linalg.norm(BLOBS_UM, axis=1)))  # the corner blob, at the body frame's origin
SPACING_UM = 6.0                         # the bodies' starting grid in x and y


class Forces:
    """Gravity and the wall's repulsion per blob, in kT and um: weight (kT/um), repulsion (kT),
    radius and decay (um). U(h) = weight h + repulsion exp(-(h - radius)/decay) for h >= radius,
    repulsion (1 + (radius - h)/decay) below (RigidMultiblobsWall's)."""

    def __init__(self, weight_scale=1.0):
        self.weight = weight_scale*PEER_WEIGHT/PEER_KT
        self.repulsion = PEER_REPULSION/PEER_KT
        self.radius = BLOB_RADIUS_UM
        self.decay = PEER_DECAY

    def blob_energy(self, h):
        """Each blob's energy (kT) at heights h (um), an array."""
        wall = np.where(h >= self.radius, self.repulsion*np.exp(-(np.maximum(h, self.radius)-self.radius)/self.decay),
                        self.repulsion*(1+(self.radius-h)/self.decay))
        return self.weight*h+wall

    def openmm_force(self):
        """The same energy as an OpenMM force on the blobs' particles (kJ/mol, nm)."""
        force = mm.CustomExternalForce('weight*z+select(step(z-radius), repulsion*exp(-(z-radius)/decay), repulsion*(1+(radius-z)/decay))')
        for name, value in [('weight', self.weight*KT/NM_PER_UM), ('repulsion', self.repulsion*KT),
                            ('radius', self.radius*NM_PER_UM), ('decay', self.decay*NM_PER_UM)]:
            force.addGlobalParameter(name, value)
        return force


# --- The Gibbs-Boltzmann density of the cross point's height ---

def normal_quadrature(points=32):
    """Nodes and weights over the body's normal n (uniform on the sphere) for a planar body: the
    blobs' heights above the cross point are sin(theta) (x cos(phi) + y sin(phi)), even in
    cos(theta), so cos(theta) runs over (0, 1) by Gauss-Legendre and phi by the trapezoidal rule
    (exact for periodic functions up to its degree). Returns the blobs' height offsets (nodes x 15,
    um) and the weights (summing to 1)."""
    x, w = np.polynomial.legendre.leggauss(points)
    cos_theta, w = (x+1)/2, w/2
    phi = (np.arange(2*points)+0.5)*np.pi/points
    sin_theta = np.sqrt(1-cos_theta**2)
    along = np.cos(phi)[:, None]*BLOBS_UM[:, 0]+np.sin(phi)[:, None]*BLOBS_UM[:, 1]   # phi x blobs
    offsets = sin_theta[:, None, None]*along[None, :, :]
    return offsets.reshape(-1, len(BLOBS_UM)), np.repeat(w, len(phi))/len(phi)


def orientation_boltzmann(forces, heights, offsets):
    """The Boltzmann factor exp(-U/kT) at each cross-point height (rows, um) and orientation (columns:
    the blobs' height offsets, as normal_quadrature gives them)."""
    weight = forces.weight*len(BLOBS_UM)
    return np.array([np.exp(-(forces.blob_energy(z+offsets).sum(axis=1)-weight*z))*np.exp(-weight*z) for z in heights])


def cumulative_trapezoid(values, x):
    """The trapezoidal rule's integral of values (along the first axis) from x[0] to each x."""
    steps = (values[1:]+values[:-1])/2*(np.diff(x)[:, None] if values.ndim > 1 else np.diff(x))
    return np.concatenate([np.zeros((1,)+values.shape[1:]), np.cumsum(steps, axis=0)])


class GibbsBoltzmann:
    """The cross point's height density on a grid (um), normalised, with its mean, bin probabilities
    and quantiles; and the same of the lowest blob's height (the body's gap to the wall)."""

    def __init__(self, forces, points=32):
        top = 30/(forces.weight*len(BLOBS_UM))+3  # e^-30 of the weight's tail
        self.heights = np.linspace(0.0, top, 3001)
        offsets, weights = normal_quadrature(points)
        lowest = offsets.min(axis=1)  # how far the lowest blob sits below the cross point (a blob): at most 0
        density, lowest_cumulative = np.zeros(len(self.heights)), np.zeros(len(self.heights))
        for part in np.array_split(np.arange(len(weights)), max(1, len(weights)//512)):  # bounded memory
            joint = orientation_boltzmann(forces, self.heights, offsets[part])*weights[part]  # heights x orientations
            density += joint.sum(axis=1)
            # At each orientation the lowest blob is below z where the cross point is below z - lowest.
            cumulative = cumulative_trapezoid(joint, self.heights)
            lowest_cumulative += sum(np.interp(self.heights-low, self.heights, cumulative[:, k]) for k, low in enumerate(lowest[part]))
        total = np.trapezoid(density, self.heights)
        self.density = density/total
        self.mean = float(np.trapezoid(self.heights*self.density, self.heights))
        self.cumulative = cumulative_trapezoid(self.density, self.heights)
        self.lowest_cumulative = lowest_cumulative/total

    def bin_probabilities(self, edges, lowest_blob=False):
        """The probability of each bin of the cross point's height (or the lowest blob's), edges in um."""
        return np.diff(np.interp(edges, self.heights, self.lowest_cumulative if lowest_blob else self.cumulative))

    def quantiles(self, fractions, lowest_blob=False):
        return np.interp(fractions, self.lowest_cumulative if lowest_blob else self.cumulative, self.heights)


def sample_bodies(forces, count, rng, candidates=4096):
    """count (rotation matrix, cross-point height in um) pairs drawn from the Gibbs-Boltzmann density:
    the orientation from uniform rotations resampled by their weight (the height integrated out),
    then the height from its density given the orientation."""
    from scipy.spatial.transform import Rotation
    turns = Rotation.random(candidates, random_state=np.random.default_rng(rng.integers(2**32))).as_matrix()
    heights = np.linspace(0.0, 30/(forces.weight*len(BLOBS_UM))+3, 1501)
    offsets = np.einsum('cj,bj->cb', turns[:, 2, :], BLOBS_UM)              # candidates x blobs
    boltzmann = np.exp(-np.array([forces.blob_energy(z+offsets).sum(axis=1) for z in heights]).T)  # candidates x heights
    weights = boltzmann.sum(axis=1)
    chosen = rng.choice(candidates, size=count, p=weights/weights.sum())
    samples = []
    for c in chosen:
        cumulative = np.cumsum(boltzmann[c])
        samples.append((turns[c], float(np.interp(rng.random()*cumulative[-1], cumulative, heights))))
    return samples


# --- The simulation ---

def body_tensor():
    """The boomerang's rigid-multiblob resistance per unit viscosity about its cross point, in open
    space (nm): the friction it has alone, without and far from other bodies with interactions."""
    blobs = BLOBS_UM*NM_PER_UM
    return hydro.coupledResistance([(blobs, [BLOB_RADIUS_UM*NM_PER_UM]*len(blobs), blobs[CROSS_POINT])])


def build(forces, starts, interactions, platform='CPU', tolerance=None, seed=1, spacing=SPACING_UM, integrator=None, blob_mass=1.0):
    """A System of boomerangs (one particle of blob_mass amu per blob) starting at (rotation, height)
    each, on a square grid in x and y, and its integrator (a RigidBrownianIntegrator at the step of
    STEP_PS unless one is given) and Context."""
    system = mm.System()
    if integrator is None:
        integrator = rl.RigidBrownianIntegrator(TEMPERATURE, VISCOSITY, STEP_PS[interactions])
    integrator.setRandomNumberSeed(seed)
    force = forces.openmm_force()
    blobs_nm, tensor = BLOBS_UM*NM_PER_UM, body_tensor()
    side = int(math.ceil(math.sqrt(len(starts))))
    positions = []
    for b, (turn, height) in enumerate(starts):
        first = system.getNumParticles()
        for i in range(len(blobs_nm)):
            system.addParticle(blob_mass)
            force.addParticle(first+i)
            integrator.setParticleRadius(first+i, BLOB_RADIUS_UM*NM_PER_UM)
        integrator.addRigidBody(list(range(first, first+len(blobs_nm))))
        integrator.setBodyResistance(b, list(tensor.flat), mm.Vec3(*blobs_nm[CROSS_POINT]), [mm.Vec3(*p) for p in blobs_nm])
        corner = NM_PER_UM*np.array([spacing*(b % side-(side-1)/2), spacing*(b//side-(side-1)/2), height])
        positions += [mm.Vec3(*p) for p in blobs_nm @ turn.T+corner]
    system.addForce(force)
    if interactions:
        integrator.setHydrodynamicInteractions(True)
        integrator.setWall(0.0)
        if tolerance is not None:
            integrator.setHydrodynamicTolerance(tolerance)
    properties = {'Precision': 'double'} if platform in ('OpenCL', 'CUDA', 'HIP') else {}
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform), properties)
    context.setPositions(positions)
    return integrator, context


def cross_point_heights(integrator, context, steps, stride):
    """The bodies' cross-point heights (um), every stride steps: samples x bodies."""
    cross = np.arange(integrator.getNumRigidBodies())*len(BLOBS_UM)+CROSS_POINT
    heights = []
    for _ in range(steps//stride):
        integrator.step(stride)
        z = context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(unit.nanometer)[cross, 2]
        heights.append(z/NM_PER_UM)
    return np.array(heights)


def autocorrelation(heights, lags):
    """The heights' normalised autocorrelation at each lag (samples), over bodies and time origins."""
    centred = heights-heights.mean()
    variance = np.mean(centred**2)
    return np.array([np.mean(centred[lag:]*centred[:len(centred)-lag])/variance for lag in lags])


def correlation_time(heights, stride_s):
    """The heights' integrated autocorrelation time (s), summed until it first drops below 0.05."""
    lags = np.arange(len(heights)//2)
    c = autocorrelation(heights, lags)
    end = int(np.argmax(c < 0.05)) if np.any(c < 0.05) else len(c)
    return float(stride_s*(0.5+c[1:end].sum()))


def summarise(heights, stride_s):
    """Mean height and its two standard errors (block averages of the suspension's mean; spread of
    the bodies' own means), and the correlation time."""
    return {'mean': float(heights.mean()), 'block_error': block_error(heights.mean(axis=1)),
            'body_error': float(standard_error(heights.mean(axis=0))), 'correlation_s': correlation_time(heights, stride_s),
            'block_s': stride_s*(len(heights)//10)}


def run_case(forces, starts, interactions, args):
    integrator, context = build(forces, starts, interactions, args.platform, args.tolerance, args.seed)
    stride = int(round(SAMPLE_S*1e12/STEP_PS[interactions]))
    steps = stride*int(round(args.seconds/SAMPLE_S))
    start = time.perf_counter()
    heights = cross_point_heights(integrator, context, steps, stride)
    seconds = time.perf_counter()-start
    print(f"{'with' if interactions else 'without'} interactions: {steps} steps in {seconds:.1f} s", flush=True)
    return heights, seconds


# --- Output ---

def table(results, gb, edges, args):
    lines = [f'# {args.bodies} sedimented boomerangs above a wall, {args.seconds:g} s (steps of 0.01 s with interactions, 0.1 ms without) on {args.platform}'
             + (f', Krylov tolerance {args.tolerance:g}' if args.tolerance else ''), '',
             'Cross-point height (um): the mean over bodies and time with the standard error of 10 block averages '
             '(and of the bodies\' own means); the Gibbs-Boltzmann mean by quadrature; chi^2 of the histogram over its bins '
             '(each bin\'s count variance from the bodies\' spread).', '',
             '| interactions | mean height (um) | bodies\' spread | Gibbs-Boltzmann | (mean - GB) / error | chi^2 / bins | correlation time (s) | block (s) | run (s) |',
             '|---|---|---|---|---|---|---|---|---|']
    expected = gb.bin_probabilities(edges)
    for interactions, label in ((True, 'with (wall)'), (False, 'without')):
        heights, seconds = results[interactions]
        s = summarise(heights, SAMPLE_S)
        fractions = np.array([np.histogram(heights[:, b], edges)[0]/len(heights) for b in range(heights.shape[1])])
        se = standard_error(fractions)
        chi2 = float(np.sum(((fractions.mean(axis=0)-expected)[se > 0]/se[se > 0])**2))  # a bin no body visited has no spread
        lines.append(f"| {label} | {s['mean']:.3f} ± {s['block_error']:.3f} | ± {s['body_error']:.3f} | {gb.mean:.3f} | "
                     f"{(s['mean']-gb.mean)/s['block_error']:+.2f} | {chi2:.1f} / {len(expected)} | {s['correlation_s']:.1f} | "
                     f"{s['block_s']:.0f} | {seconds:.0f} |")
    return '\n'.join(lines)+'\n'


def plot(results, gb, stride_s, path):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    edges = np.linspace(0, gb.quantiles(0.995), 31)
    for interactions, label, colour in ((True, 'with interactions (wall)', 'C0'), (False, 'without', 'C1')):
        heights = results[interactions][0]
        left.hist(heights.ravel(), edges, density=True, histtype='step', color=colour, label=label)
        lags = np.arange(0, min(len(heights)//2, int(60/stride_s)))
        right.plot(lags*stride_s, autocorrelation(heights, lags), color=colour, label=label)
    left.plot(gb.heights, gb.density, 'k', lw=1, label='Gibbs-Boltzmann')
    left.set_xlim(0, edges[-1])
    left.set_xlabel('cross-point height (um)')
    left.set_ylabel('density (1/um)')
    left.legend()
    right.axhline(0, color='grey', lw=0.5)
    right.set_xlabel('lag (s)')
    right.set_ylabel('height autocorrelation')
    right.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--quick', action='store_true', help='9 bodies, 4 s (seconds)')
    parser.add_argument('--bodies', type=int, help='number of boomerangs (default 16, 9 with --quick)')
    parser.add_argument('--seconds', type=float, help='simulated time (default 120 s, 4 s with --quick)')
    parser.add_argument('--tolerance', type=float, default=1e-3,
                        help="the Krylov solves' relative tolerance (RigidMultiblobsWall's boomerang files' 1e-3; 0: the integrator's default)")
    parser.add_argument('--platform', default='CPU', help='the OpenMM platform (default CPU)')
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--out', help='output folder (default out/sedimented_boomerangs)')
    args = parser.parse_args()
    args.bodies = args.bodies or (9 if args.quick else 16)
    args.seconds = args.seconds or (4.0 if args.quick else 120.0)
    args.tolerance = args.tolerance or None
    out = args.out or os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'out', 'sedimented_boomerangs')
    os.makedirs(out, exist_ok=True)

    forces = Forces()
    gb = GibbsBoltzmann(forces)
    starts = sample_bodies(forces, args.bodies, np.random.default_rng(args.seed))
    results = {interactions: run_case(forces, starts, interactions, args) for interactions in (True, False)}
    edges = np.concatenate([[0], gb.quantiles(np.arange(1, 8)/8), [gb.heights[-1]]])
    text = table(results, gb, edges, args)
    with open(os.path.join(out, 'table.md'), 'w', encoding='utf-8') as f:
        f.write(text)
    np.savez_compressed(os.path.join(out, 'heights.npz'), with_interactions=results[True][0], without=results[False][0])
    plot(results, gb, SAMPLE_S, os.path.join(out, 'boomerangs.png'))
    print(text)
    print(f'(written to {out}/table.md, heights.npz and boomerangs.png)')


if __name__ == '__main__':
    sys.stdout.reconfigure(encoding='utf-8')
    main()
