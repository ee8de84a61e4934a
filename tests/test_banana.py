"""The banana scene's model, checked exactly: the body and its ellipsoid frames, the Gay-Berne
parameters as given, the shell tensor's symmetry and centre of resistance, the pentane's terms."""
import math
import pathlib
import sys

import numpy as np
import openmm as mm
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]/'examples'))
import banana_model as bm  # noqa: E402


def reference_context(system, positions):
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName('Reference'))
    context.setPositions(positions)
    context.computeVirtualSites()
    return context


def two_bananas_apart(rotation, offset):
    """Two bananas, the second turned by rotation and moved by offset (nm), no cutoff."""
    system, positions = mm.System(), []
    gayberne = bm.gayberne_force()
    first = bm.add_banana(system, gayberne, positions)
    second = bm.add_banana(system, gayberne, positions, rotation, offset)
    system.addForce(gayberne)
    return system, positions, first, second


def test_banana_mass_inertia_and_frames():
    positions = bm.banana_positions()
    masses = np.array([0.0 if k % 3 == 0 else bm.GB_MASS/2 for k in range(9)])
    assert masses.sum() == pytest.approx(3*bm.GB_MASS, rel=1e-15)
    assert np.allclose(masses@positions, 0, atol=1e-13)
    # The inertia of the mass particles is that of three point masses at the centres plus each
    # ellipsoid's own (I_perp across its axis, nothing along it).
    centers, axes = bm.ellipsoids()
    centers = centers-centers.mean(axis=0)
    inertia = sum(m*(p@p*np.eye(3)-np.outer(p, p)) for m, p in zip(masses, positions))
    expected = sum(bm.GB_MASS*(c@c*np.eye(3)-np.outer(c, c))+bm.GB_INERTIA_PERP*(np.eye(3)-np.outer(u, u)) for c, u in zip(centers, axes))
    assert np.allclose(inertia, expected, rtol=1e-13, atol=1e-15)
    # Each ellipsoid: its centre is the virtual site midway between its mass particles, its long axis
    # (towards the first) the model's, tip to tip with the middle one at the joints.
    for e in range(3):
        c, plus, minus = positions[3*e:3*e+3]
        assert np.allclose(c, (plus+minus)/2, atol=1e-15)
        assert np.allclose((plus-c)/np.linalg.norm(plus-c), axes[e], atol=1e-14)
    half = bm.GB_LENGTH/2
    for end in (0, 2):
        gaps = [np.linalg.norm(centers[end]+a*half*axes[end]-(centers[1]+b*half*axes[1])) for a in (-1, 1) for b in (-1, 1)]
        assert min(gaps) < 1e-14
    for end in (0, 2):
        assert math.degrees(math.acos(abs(axes[end]@axes[1]))) == pytest.approx(45.0, abs=1e-12)


def test_gay_berne_wells_are_the_force_fields():
    # DUFF's GBPaper: -eps_side side by side at d + (2^(1/6)-1) d, -eps_end end to end at
    # l + (2^(1/6)-1) d (OpenMM's contact distance plus the Lennard-Jones minimum's offset), and
    # those are minima along the line.
    shift = (2**(1/6)-1)*bm.GB_BREADTH
    def middle_pair_energy(offset):
        system, positions, first, second = two_bananas_apart(np.eye(3), np.array(offset))
        # Only the middle ellipsoids interact: the ends of each banana made inert.
        force = system.getForce(0)
        for members in (first, second):
            for end in (0, 6):
                p = force.getParticleParameters(members[end])
                force.setParticleParameters(members[end], p[0], 0.0, *p[2:])
        return reference_context(system, positions).getState(getEnergy=True).getPotentialEnergy()._value
    for offset, well in (((0, 0, bm.GB_BREADTH+shift), -bm.GB_EPS_SIDE), ((bm.GB_LENGTH+shift, 0, 0), -bm.GB_EPS_END)):
        offset = np.array(offset)
        energy = middle_pair_energy(offset)
        assert energy == pytest.approx(well, rel=1e-9)
        for scale in (0.99, 1.01):
            assert middle_pair_energy(offset*scale) > energy


def test_gay_berne_frames_follow_the_body():
    # Turning the second banana with its particles turns its ellipsoids: the energy of the pair
    # depends only on their relative placement, so turning both together changes nothing.
    rng = np.random.default_rng(5)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.linalg.det(q))
    turn, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    turn *= np.sign(np.linalg.det(turn))
    offset = np.array([0.2, 0.9, 0.35])
    system, positions, _, _ = two_bananas_apart(turn, offset)
    state = reference_context(system, positions).getState(getEnergy=True, getForces=True)
    energy = state.getPotentialEnergy()._value
    # Finite forces on every particle (excluded overlapping ellipsoids inside a body once gave NaN).
    assert np.isfinite(state.getForces(asNumpy=True)._value).all()
    turned = [mm.Vec3(*(q@np.array(p))) for p in positions]
    assert reference_context(system, turned).getState(getEnergy=True).getPotentialEnergy()._value == pytest.approx(energy, rel=1e-10)
    # ... while turning the second banana alone about its centre does change it.
    other, other_positions, _, _ = two_bananas_apart(q@turn, offset)
    assert abs(reference_context(other, other_positions).getState(getEnergy=True).getPotentialEnergy()._value-energy) > 1e-3*abs(energy)


def test_shell_tensor_symmetry_and_center_of_resistance():
    # The banana has two mirror planes (x = 0 and z = 0) in its frame: the extrapolated shell
    # tensor has the zeros they impose and its centre of resistance lies on their line (the y axis),
    # displaced from the centre of mass toward the bend (+y); both to the shell's accuracy (~1e-3
    # of the largest element, the tiling being symmetric only to its bead spacing; measured 1-3e-4).
    xi = bm.resistance_tensor(maxBeads=1000)
    center = np.array(xi.getCenterOfResistance()._value)
    assert abs(center[0]) < 1e-3*bm.GB_LENGTH and abs(center[2]) < 1e-3*bm.GB_LENGTH
    assert 0.05 < center[1] < 0.15
    m = np.array(xi.getMatrix(xi.getCenterOfResistance()))
    assert np.allclose(m, m.T, atol=1e-12*abs(m).max())
    mirror = np.diag([-1, 1, -1])  # the product of both reflections is the C2 turn about y
    for reflection in (np.diag([-1, 1, 1]), np.diag([1, 1, -1]), mirror):
        # Translations are polar vectors, rotations axial: under a reflection R they turn with R and det(R) R.
        t = np.zeros((6, 6))
        t[:3, :3] = reflection
        t[3:, 3:] = np.linalg.det(reflection)*reflection
        assert np.abs(t@m@t.T-m).max() < 1e-3*np.abs(m).max()
    # The coupling block about the centre of resistance is symmetric.
    assert np.abs(m[:3, 3:]-m[:3, 3:].T).max() < 1e-3*np.abs(m[:3, :3]).max()*bm.GB_LENGTH


def test_shell_at_the_source_bead_count():
    # About 2266 beads (the source's count) need a bead radius near 0.11 A on these ellipsoids, and
    # that shell's resistance is above the extrapolated one by a few per cent at most.
    radius, count, shell = bm.source_size_shell()
    assert abs(count-bm.SOURCE_SHELL_BEADS) < 0.02*bm.SOURCE_SHELL_BEADS
    assert 0.008 < radius < 0.015
    extrapolated = np.array(bm.resistance_tensor(maxBeads=1000).getMatrix())
    ratio = np.diag(np.array(shell.getMatrix()))/np.diag(extrapolated)
    assert np.all(ratio > 1) and np.all(ratio < 1.05)


def test_pentane_terms_are_trappe():
    system, positions = mm.System(), []
    gayberne = bm.gayberne_force()
    bonds, angles, torsions = mm.HarmonicBondForce(), mm.HarmonicAngleForce(), mm.RBTorsionForce()
    sites = bm.add_pentane(system, gayberne, (bonds, angles, torsions), positions, np.zeros(3), np.array([1.0, 0, 0]))
    for force in (gayberne, bonds, angles, torsions):
        system.addForce(force)
    assert [system.getParticleMass(i)._value for i in sites] == [15.035, 14.027, 14.027, 14.027, 15.035]
    xyz = np.array([[c for c in p] for p in positions])
    # Built with the fixed bond and the equilibrium angle: all-trans, bends and bonds at rest.
    for k in range(4):
        assert np.linalg.norm(xyz[k+1]-xyz[k]) == pytest.approx(bm.TRAPPE_BOND, rel=1e-12)
    # The torsion in OpenMM's Ryckaert-Bellemans form equals TraPPE's cosine series at any angle.
    torsion_only = mm.System()
    for i in sites:
        torsion_only.addParticle(1.0)
    only = mm.RBTorsionForce()
    only.addTorsion(0, 1, 2, 3, *torsions.getTorsionParameters(0)[4:])
    torsion_only.addForce(only)
    tc = mm.Context(torsion_only, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName('Reference'))
    c1, c2, c3 = (c*bm.BOLTZ for c in bm.TRAPPE_TORSION)
    for phi in np.radians([0, 37, 60, 90, 120, 180, 250, 300]):
        p = [[1, 1, 0], [1, 0, 0], [2, 0, 0], [2, math.cos(phi), math.sin(phi)], [3, 0, 0]]
        tc.setPositions(p)
        energy = tc.getState(getEnergy=True).getPotentialEnergy()._value
        assert energy == pytest.approx(c1*(1+math.cos(phi))+c2*(1-math.cos(2*phi))+c3*(1+math.cos(3*phi)), abs=1e-9)
    # Within the molecule only the two ends, four bonds apart, interact by Lennard-Jones.
    excluded = {tuple(sorted(gayberne.getExceptionParameters(k)[:2])) for k in range(gayberne.getNumExceptions())}
    assert excluded == {(sites[i], sites[j]) for i in range(5) for j in range(i+1, 5) if j-i <= 3}


def test_constrained_banana_matches_the_body():
    # The banana for OpenMM's integrators: its nine sites where the body's are, its mass and
    # centre of mass the body's, its inertia the body's plus M h^2 on the in-plane axes, and its
    # Gay-Berne energy against another banana the body's.
    rng = np.random.default_rng(3)
    turn, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    turn *= np.sign(np.linalg.det(turn))
    shift = np.array([0.3, 0.8, 0.4])
    energies = []
    for add in (bm.add_banana, bm.add_constrained_banana):
        system, positions = mm.System(), []
        gayberne = bm.gayberne_force()
        first = add(system, gayberne, positions, turn, shift)
        bm.add_banana(system, gayberne, positions, np.eye(3), np.zeros(3))
        system.addForce(gayberne)
        context = reference_context(system, positions)
        state = context.getState(getEnergy=True, getPositions=True)
        energies.append(state.getPotentialEnergy()._value)
        xyz = state.getPositions(asNumpy=True)._value
        expected = np.array([turn@p+shift for p in bm.banana_positions()])
        assert np.abs(xyz[first[:9]]-expected).max() < 1e-12
        if add is bm.add_constrained_banana:
            masses = np.array([system.getParticleMass(i)._value for i in first])
            assert masses.sum() == pytest.approx(3*bm.GB_MASS, rel=1e-14)
            r = xyz[first]-shift
            assert np.abs(masses@r).max() < 1e-12
            inertia = sum(m*(p@p*np.eye(3)-np.outer(p, p)) for m, p in zip(masses, r))
            body = sum(m*(p@p*np.eye(3)-np.outer(p, p)) for m, p in zip([0.0 if k % 3 == 0 else bm.GB_MASS/2 for k in range(9)], expected-shift))
            added = 3*bm.GB_MASS*0.01**2*(np.eye(3)-np.outer(turn[:, 2], turn[:, 2]))
            assert np.allclose(inertia, body+added, rtol=1e-10, atol=1e-12)
            assert system.getNumConstraints() == 6
    assert energies[1] == pytest.approx(energies[0], rel=1e-12)


@pytest.mark.parametrize('scheme', ['ExactFlow', 'BAOAB'])
def test_free_bananas_diffuse_as_their_tensor_predicts(scheme):
    # The scene's matching viscosities rest on banana_scene.predicted_diffusion(): long-time D_t, a
    # third of the translational trace of kT (eta Xi)^-1 at the centre of diffusion, and
    # <u(0).u(t)> = exp(-2 D_r t) for the middle ellipsoid's axis u (exact at long times: u is a
    # principal axis of the rotational mobility, by the banana's two mirror planes). 2000 free
    # bananas at a quarter of the source's viscosity (faster diffusion, better statistics per
    # picosecond), 60 ps. Both constants come from slopes over lags of 2-6 ps, past the inertial
    # times (M/xi = 0.33 ps, I/xi_r = 0.16 ps here), whose offsets slopes do not see; longer lags
    # add little information and much variance. The standard error is the spread over 20 groups
    # of 100 bananas: 0.6-0.9% here (60 ps; 0.4-0.7% at 80 ps), small enough to see 5%.
    import rigidlangevin as rl
    import banana_scene as scene
    viscosity = bm.SOURCE_VISCOSITY/4
    xi = bm.resistance_tensor(maxBeads=1000)
    system, positions, bodies = mm.System(), [], []
    integrator = rl.RigidLangevinIntegrator(scene.TEMPERATURE, viscosity*rl.poise, 0.002)
    integrator.setScheme(getattr(rl.RigidLangevinIntegrator, scheme))
    integrator.setRandomNumberSeed(7)
    rng = np.random.default_rng(7)
    reference = [mm.Vec3(*p) for p in bm.banana_positions()]
    for b in range(2000):
        turn, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        turn *= np.sign(np.linalg.det(turn))
        members = bm.add_banana(system, bm.gayberne_force(), positions, turn, np.array([4.0*(b % 40), 4.0*(b//40), 0.0]))
        integrator.setBodyHydrodynamics(integrator.addRigidBody(members), xi, reference)
        bodies.append(members)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(scene.TEMPERATURE, 7)
    masses = np.array([system.getParticleMass(i)._value for i in range(system.getNumParticles())])
    integrator.step(1000)
    com, _, axis = scene.banana_observables(context, bodies, masses, 50, 600, integrator)  # every 0.1 ps
    predicted_t, predicted_r = scene.predicted_diffusion(xi, viscosity)
    groups = np.arange(2000).reshape(20, 100)
    def slope(series, lags):
        return np.polyfit(0.1*lags, series, 1)[0]
    lags = np.arange(20, 61)  # 2-6 ps
    d_t = [slope([np.mean(np.sum((com[lag:, g]-com[:-lag, g])**2, axis=2)) for lag in lags], lags)/6 for g in groups]
    d_r = [-slope([np.log(np.mean(np.sum(axis[lag:, g]*axis[:-lag, g], axis=2))) for lag in lags], lags)/2 for g in groups]
    for measured, predicted, what in ((d_t, predicted_t, 'D_t'), (d_r, predicted_r, 'D_r')):
        mean, error = np.mean(measured), np.std(measured, ddof=1)/np.sqrt(len(measured))
        assert abs(mean-predicted) < 4*error, f'{what}: {mean:.4g} +- {error:.2g} against {predicted:.4g}'
        assert 4*error < 0.05*predicted, f'{what}: standard error {error:.2g} too large to see 5%'
