"""Bodies above a no-slip wall without a Context (rigidlangevin.hydrodynamics): the library's
Rotne-Prager-Blake blocks and a body's resistance against an independent numpy implementation.

The reference is written here from the published construction, not from the library's formulas:
Blake's Green's function of a point force above a wall (Blake, Proc. Camb. Phil. Soc. 70, 303
(1971): the force's Oseen tensor, and at its mirror image a Stokeslet, a Stokes doublet and a
source dipole), with Faxen's operators (1 + a_i^2/6 lap_x)(1 + a_j^2/6 lap_y) applied to its image
part as derivative tensors of 1/r and r (Swan & Brady, Phys. Fluids 19, 113306 (2007)); the free
part the generalised Rotne-Prager-Yamakawa tensor (Zuk et al., J. Fluid Mech. 741, R5 (2014));
blobs closer to the wall than their radius raised and damped (Balboa Usabiaga, Delmotte & Donev,
J. Chem. Phys. 146, 134104 (2017)). The library instead sums five scalar coefficients per pair
(hydrodynamics/include/internal/RotnePragerBlake.h). hydrodynamics/tests/TestRotnePragerBlake.cpp
checks the self-mobility's closed forms, positive definiteness and the matrix-free product.
"""
import numpy as np
import openmm
import pytest

import rigidlangevin.hydrodynamics as hydro

I3 = np.eye(3)
MIRROR = np.diag([1.0, 1.0, -1.0])
EZ = I3[2]


def _symmetrised(R):
    """The index-symmetric sums of Kronecker deltas and R that derivatives of radial functions hold."""
    d_r = np.einsum('ij,k->ijk', I3, R)+np.einsum('ik,j->ijk', I3, R)+np.einsum('jk,i->ijk', I3, R)
    d_rr = sum(np.einsum(f'{p},{q},{s}->ijkl', I3, R, R) for p, q, s in
               (('ij', 'k', 'l'), ('ik', 'j', 'l'), ('il', 'j', 'k'), ('jk', 'i', 'l'), ('jl', 'i', 'k'), ('kl', 'i', 'j')))
    d_d = np.einsum('ij,kl->ijkl', I3, I3)+np.einsum('ik,jl->ijkl', I3, I3)+np.einsum('il,jk->ijkl', I3, I3)
    return d_r, d_rr, d_d


def _derivatives(R):
    """First to fourth derivatives of 1/r, third and fourth of r, at R."""
    r = np.linalg.norm(R)
    d_r, d_rr, d_d = _symmetrised(R)
    rrr = np.einsum('i,j,k->ijk', R, R, R)
    rrrr = np.einsum('i,j,k,l->ijkl', R, R, R, R)
    inverse = (-R/r**3, 3*np.outer(R, R)/r**5-I3/r**3, -15*rrr/r**7+3*d_r/r**5, 105*rrrr/r**9-15*d_rr/r**7+3*d_d/r**5)
    distance = (3*rrr/r**5-d_r/r**3, -15*rrrr/r**7+3*d_rr/r**5-d_d/r**3)
    return inverse, distance


def _image(target, source, ai, aj):
    """The image part of the mobility of blob i (radius ai at target) for a force on blob j (radius aj
    at source), per unit viscosity, wall at z = 0: Blake's image system W(R, h), R = target - mirrored
    source and h the source's height, under Faxen's operators. lap_x is lap_R; lap_y is lap_R +
    2 d_R3 d_h + d_h^2, the source's height entering R_3 and h."""
    h = source[2]
    R = target-MIRROR@source
    r = np.linalg.norm(R)
    (inv1, inv2, inv3, inv4), (dist3, dist4) = _derivatives(R)
    stokeslet = I3/r+np.outer(R, R)/r**3          # S_ij = 2 delta_ij/r - d_i d_j r
    dipole = -inv2                                # D_ik = d_k (R_i/r^3)
    d_stokeslet3 = 2*np.outer(EZ, inv1)-dist3[:, 2, :]         # d_k S_i3
    d3_dipole = -inv3[:, :, 2]                                 # d_3 D_ik
    d3_d_stokeslet3 = 2*np.outer(EZ, inv2[:, 2])-dist4[:, 2, :, 2]   # d_3 d_k S_i3
    d33_dipole = -inv4[:, :, 2, 2]
    w = -stokeslet+2*h*h*dipole@MIRROR-2*h*d_stokeslet3@MIRROR
    lap_x_w = -2*dipole-4*h*d3_dipole@MIRROR
    lap_y_w = -2*dipole+4*h*d3_dipole@MIRROR-4*d3_d_stokeslet3@MIRROR+4*dipole@MIRROR
    lap_x_lap_y_w = -8*d33_dipole@MIRROR
    return (w+ai**2/6*lap_x_w+aj**2/6*lap_y_w+ai**2*aj**2/36*lap_x_lap_y_w)/(8*np.pi)


def _free(d, ai, aj):
    """The generalised Rotne-Prager-Yamakawa block of two blobs an offset d apart (d = 0: one blob's own)."""
    r = np.linalg.norm(d)
    if r > ai+aj:
        s = (ai*ai+aj*aj)/r**2
        return ((1+s/3)*I3+(1-s)*np.outer(d, d)/r**2)/(8*np.pi*r)
    if r > abs(ai-aj):
        return ((16*r**3*(ai+aj)-((ai-aj)**2+3*r*r)**2)/(32*r**3)*I3
                + 3*((ai-aj)**2-r*r)**2/(32*r**3)*np.outer(d, d)/r**2)/(6*np.pi*ai*aj)
    return I3/(6*np.pi*max(ai, aj))


def _mobility(positions, radii, wall):
    """The blobs' regularised mobility above the wall z = wall, both triangles formed."""
    p = np.array(positions, dtype=float)-[0, 0, wall]
    heights = p[:, 2].copy()
    p[:, 2] = np.maximum(heights, radii)
    damping = np.minimum(heights/radii, 1)
    n = len(p)
    m = np.zeros((3*n, 3*n))
    for i in range(n):
        for j in range(n):
            block = _free(p[i]-p[j], radii[i], radii[j])+_image(p[i], p[j], radii[i], radii[j])
            m[3*i:3*i+3, 3*j:3*j+3] = damping[i]*damping[j]*block
    return m


def _resistance(positions, radii, wall, origin):
    """One body's K^T M^-1 K about origin, dense."""
    k = np.zeros((3*len(positions), 6))
    for i, p in enumerate(np.asarray(positions)-origin):
        k[3*i:3*i+3, :3] = I3
        k[3*i:3*i+3, 3:] = -np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])
    return k.T@np.linalg.solve(_mobility(positions, radii, wall), k)


def _difference(a, b):
    """max |a_ij - b_ij| / sqrt(b_ii b_jj): each element against its own scale (translation in nm,
    rotation in nm^3 differ by orders of magnitude)."""
    scale = np.sqrt(np.abs(np.diag(b)))
    return (np.abs(a-b)/np.outer(scale, scale)).max()


def _boomerang(corner, tilt):
    """The shared notes' boomerang: 15 blobs 0.3 um apart (in nm), two arms of 7 at right angles, blob
    radius 0.265 sqrt(1.5) um, turned about the x axis by tilt and its corner placed at corner."""
    arm = 300*np.arange(1, 8)
    flat = np.array([[0, 0, 0]]+[[x, 0, 0] for x in arm]+[[0, y, 0] for y in arm], dtype=float)
    c, s = np.cos(tilt), np.sin(tilt)
    return flat@np.array([[1, 0, 0], [0, c, s], [0, -s, c]])+corner, np.full(15, 265*np.sqrt(1.5))


def test_reference_is_blakes_solution():
    # The reference's own check: point forces (no Faxen terms) give zero velocity on the wall, the
    # no-slip condition; its blocks are reciprocal (M_ij = M_ji^T) for unequal radii; and a blob's
    # self-mobility at h = 2a is Swan & Brady's 375/512 and 127/256 of Stokes's.
    source, target = np.array([0.3, 0.2, 0.7]), np.array([1.1, -0.4, 0.0])
    velocity = _free(target-source, 0, 0)+_image(target, source, 0, 0)
    assert np.abs(velocity).max() < 1e-15*np.abs(_free(target-source, 0, 0)).max()
    x, y = np.array([0.1, 0.5, 0.6]), np.array([0.9, 0.2, 0.35])
    assert np.abs(_image(x, y, 0.3, 0.2)-_image(y, x, 0.2, 0.3).T).max() < 1e-15*np.abs(_image(x, y, 0.3, 0.2)).max()
    self_mobility = (_free(np.zeros(3), 1, 1)+_image(np.array([0, 0, 2.0]), np.array([0, 0, 2.0]), 1, 1))*6*np.pi
    assert np.allclose(np.diag(self_mobility), [375/512, 375/512, 127/256], rtol=0, atol=1e-14)


def test_pair_blocks_match_the_reference():
    # Single-blob bodies of unequal radii, some overlapping, some closer to the wall than their
    # radius (at z0 = -0.3): their translational resistance is M^-1, so the library's blocks are the
    # reference's to rounding (relative 1e-12: M's condition number times rounding).
    rng = np.random.default_rng(4)
    positions = np.column_stack([rng.uniform(0, 1.2, 12), rng.uniform(0, 1.2, 12), rng.uniform(-0.27, 0.6, 12)])
    radii = rng.uniform(0.15, 0.3, 12)
    r = hydro.coupledResistance([([p], [a], p) for p, a in zip(positions, radii)], wall=-0.3)
    translation = r.reshape(12, 6, 12, 6)[:, :3, :, :3]
    inverse = np.linalg.inv(_mobility(positions, radii, -0.3)).reshape(12, 3, 12, 3)
    assert np.abs(translation-inverse).max() < 1e-12*np.abs(inverse).max()
    assert np.abs(r.reshape(12, 6, 12, 6)[:, 3:, :, 3:]).max() < 1e-14*np.abs(inverse).max()


@pytest.mark.parametrize('body', ['boomerang', 'sphere'])
def test_body_resistance_matches_dense_numpy(body):
    # A body's 6x6 above the wall (z0 = 50 nm, given in angstrom) against the reference's dense
    # K^T M^-1 K, to rounding: the shared notes' boomerang tilted 0.4 rad, one arm within a radius
    # of the wall (the regularisation acts), and a sphere of radius 1 um of 32 blobs (a rough shell)
    # with its centre 2 radii above the wall. A wall 1e6 body sizes below leaves the unbounded bead
    # tensor (to 2e-6).
    if body == 'boomerang':
        positions, radii = _boomerang(np.array([100.0, -200.0, 50+200.0]), 0.4)
        assert positions[:, 2].min()-50 < radii[0]
    else:
        shell = np.asarray(hydro.roughShellBeads([[0, 0, 0]], [1000.0], 200.0).value_in_unit(openmm.unit.nanometer))
        positions, radii = shell+[0, 0, 50+2000.0], np.full(len(shell), 200.0)
    origin = positions.mean(axis=0)
    library = hydro.resistanceAboveWall(positions, radii, 500*openmm.unit.angstrom, origin)
    reference = _resistance(positions, radii, 50.0, origin)
    assert _difference(library, reference) < 1e-12
    open_space = np.asarray(hydro.beads(positions, radii).getMatrix(openmm.Vec3(*origin)))
    assert _difference(library, open_space) > 0.1    # the wall matters here
    size = np.linalg.norm(positions-origin, axis=1).max()+radii[0]
    far = hydro.resistanceAboveWall(positions, radii, 50.0-1e6*size, origin)
    assert _difference(far, open_space) < 2e-6     # the leading term 9a/(8h): 0.6e-6 and 1e-6 here


def test_resolved_sphere_near_the_wall():
    # A sphere of radius a resolved by 136 blobs on its surface (scaled to its Stokes friction) at
    # centre heights 2a and 4a: its mobility across and along the wall against a resolved 2562-blob
    # model's (RigidMultiblobsWall; the shared notes: 0.4706, 0.7232 and 0.7245, 0.8606 of
    # 1/(6 pi eta a)). Within 0.5% (0.34%, 0.00%, 0.10%, 0.02% measured; 560 blobs: 0.15% at most);
    # 13 blobs miss by 2%.
    a = 1.0
    shell = np.asarray(hydro.roughShellBeads([[0, 0, 0]], [a], 0.1).value_in_unit(openmm.unit.nanometer))
    radii = np.full(len(shell), 0.1)
    blobs = np.asarray(hydro.scaleBlobsToFriction(shell, radii, [0, 0, 0], hydro.sphere(a)).value_in_unit(openmm.unit.nanometer))
    for h, across, along in ((2, 0.4706, 0.7232), (4, 0.7245, 0.8606)):
        mobility = np.linalg.inv(hydro.resistanceAboveWall(blobs+[0, 0, h], radii, 0.0, [0, 0, h]))*6*np.pi*a
        assert mobility[2, 2] == pytest.approx(across, rel=5e-3)
        assert mobility[0, 0] == pytest.approx(along, rel=5e-3)
        assert mobility[1, 1] == pytest.approx(along, rel=5e-3)


def test_blob_below_the_wall_is_refused_naming_its_body():
    positions, radii = _boomerang(np.array([0.0, 0.0, 400.0]), 0.0)
    bodies = [(positions, radii, positions[0]), (positions+[0, 0, -300], radii, positions[0]+[0, 0, -300])]
    with pytest.raises(openmm.OpenMMException, match='blob 0 of body 1 has its centre at z = 100 nm, at or below the no-slip wall at z = 150 nm'):
        hydro.coupledResistance(bodies, wall=150.0)
    with pytest.raises(openmm.OpenMMException, match='not supported'):
        hydro.coupledResistance(bodies[:1], box=np.eye(3)*1e4, wall=0.0)

