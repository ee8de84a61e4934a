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
    forces = bm.SceneForces(cutoff=None)
    first = bm.add_banana(system, forces, positions)
    second = bm.add_banana(system, forces, positions, rotation, offset)
    forces.add_to(system)
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
    forces = bm.SceneForces(cutoff=None)
    sites = bm.add_pentane(system, forces, positions, np.zeros(3), np.array([1.0, 0, 0]))
    forces.add_to(system)
    torsions = forces.torsions
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
    # Within the molecule only the two ends, four bonds apart, interact by Lennard-Jones: TraPPE's
    # sigma and epsilon, which the sites' Gay-Berne entries leave to the NonbondedForce.
    lj = forces.lennard_jones
    excluded = {tuple(sorted(lj.getExceptionParameters(k)[:2])) for k in range(lj.getNumExceptions())}
    assert excluded == {(sites[i], sites[j]) for i in range(5) for j in range(i+1, 5) if j-i <= 3}
    assert all(lj.getExceptionParameters(k)[4]._value == 0 for k in range(lj.getNumExceptions()))
    for i, kind in zip(sites, ['CH3', 'CH2', 'CH2', 'CH2', 'CH3']):
        sigma, eps_k, _ = bm.TRAPPE_SITES[kind]
        assert [v._value for v in lj.getParticleParameters(i)] == [0.0, sigma, pytest.approx(eps_k*bm.BOLTZ, rel=1e-15)]
        assert forces.gayberne.getParticleParameters(i)[1]._value == 0


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
        forces = bm.SceneForces(cutoff=None)
        first = add(system, forces, positions, turn, shift)
        bm.add_banana(system, forces, positions, np.eye(3), np.zeros(3))
        forces.add_to(system)
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
    # The scene's matching viscosities rest on banana_runs.predicted_diffusion(): long-time D_t, a
    # third of the translational trace of kT (eta Xi)^-1 at the centre of diffusion (whose
    # displacement the scene measures), and
    # <u(0).u(t)> = exp(-2 D_r t) for the middle ellipsoid's axis u (exact at long times: u is a
    # principal axis of the rotational mobility, by the banana's two mirror planes). 2000 free
    # bananas at a quarter of the source's viscosity (faster diffusion, better statistics per
    # picosecond), 60 ps. Both constants come from slopes over lags of 2-6 ps, past the inertial
    # times (M/xi = 0.33 ps, I/xi_r = 0.16 ps here), whose offsets slopes do not see; longer lags
    # add little information and much variance. The standard error is the spread over 20 groups
    # of 100 bananas: 0.6-0.9% here (60 ps; 0.4-0.7% at 80 ps), small enough to see 5%.
    import rigidlangevin as rl
    import banana_runs as scene
    viscosity = bm.SOURCE_VISCOSITY/4
    xi = bm.resistance_tensor(maxBeads=1000)
    system, positions, bodies = mm.System(), [], []
    integrator = rl.RigidLangevinIntegrator(scene.TEMPERATURE, viscosity*rl.poise, 0.002)
    integrator.setScheme(getattr(rl.RigidLangevinIntegrator, scheme))
    integrator.setRandomNumberSeed(7)
    rng = np.random.default_rng(7)
    reference = [mm.Vec3(*p) for p in bm.banana_positions()]
    unused = bm.SceneForces(cutoff=None)  # free bananas: their forces stay out of the System
    for b in range(2000):
        turn, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        turn *= np.sign(np.linalg.det(turn))
        members = bm.add_banana(system, unused, positions, turn, np.array([4.0*(b % 40), 4.0*(b//40), 0.0]))
        integrator.setBodyHydrodynamics(integrator.addRigidBody(members), xi, reference)
        bodies.append(members)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('CPU'))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(scene.TEMPERATURE, 7)
    integrator.step(1000)
    weights = scene.center_weights(np.array(xi.getCenterOfDiffusion()._value))
    centers, axis = [], []
    for _ in range(600):  # every 0.1 ps
        integrator.step(50)
        x = context.getState(getPositions=True).getPositions(asNumpy=True)._value[np.array(bodies)]
        centers.append(np.einsum('k,bkj->bj', weights, x))
        u = x[:, 4]-x[:, 3]
        axis.append(u/np.linalg.norm(u, axis=1, keepdims=True))
    centers, axis = np.array(centers), np.array(axis)
    predicted_t, predicted_r = scene.predicted_diffusion(xi, viscosity)
    groups = np.arange(2000).reshape(20, 100)
    def slope(series, lags):
        return np.polyfit(0.1*lags, series, 1)[0]
    lags = np.arange(20, 61)  # 2-6 ps
    d_t = [slope([np.mean(np.sum((centers[lag:, g]-centers[:-lag, g])**2, axis=2)) for lag in lags], lags)/6 for g in groups]
    d_r = [-slope([np.log(np.mean(np.sum(axis[lag:, g]*axis[:-lag, g], axis=2))) for lag in lags], lags)/2 for g in groups]
    for measured, predicted, what in ((d_t, predicted_t, 'D_t'), (d_r, predicted_r, 'D_r')):
        mean, error = np.mean(measured), np.std(measured, ddof=1)/np.sqrt(len(measured))
        assert abs(mean-predicted) < 4*error, f'{what}: {mean:.4g} +- {error:.2g} against {predicted:.4g}'
        assert 4*error < 0.05*predicted, f'{what}: standard error {error:.2g} too large to see 5%'


def test_scene_forces_split_changes_no_energy():
    # Sites' Lennard-Jones in a NonbondedForce and only the pairs with an ellipsoid in the
    # GayBerneForce (ellipsoid-site pairs as exceptions with the mixed parameters) give the energy
    # and forces of one GayBerneForce holding every particle, at the same cutoff. CPU platform: its
    # GayBerneForce takes two spheres as Lennard-Jones exactly (Reference's evaluates the full
    # Gay-Berne form, whose strength for unequal spheres differs from Lorentz-Berthelot's by 0.2%).
    results = []
    positions = None
    for all_in_gayberne in (True, False):
        system, lattice, _, forces = bm.pentane_box(320, 4.07, 5, bananas=2, all_in_gayberne=all_in_gayberne)
        if not all_in_gayberne:
            forces['lennard_jones'].setUseDispersionCorrection(False)
            assert forces['gayberne'].getNumExceptions() == forces['lennard_jones'].getNumExceptions()
        context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName('CPU'))
        context.setPositions(lattice if positions is None else positions)
        if positions is None:
            mm.LocalEnergyMinimizer.minimize(context, 10.0, 200)
            positions = context.getState(getPositions=True).getPositions()
        state = context.getState(getEnergy=True, getForces=True)
        results.append((state.getPotentialEnergy()._value, state.getForces(asNumpy=True)._value))
    (energy_all, forces_all), (energy_split, forces_split) = results
    assert energy_split == pytest.approx(energy_all, rel=1e-5)
    assert np.abs(forces_split-forces_all).max() < 1e-4*np.abs(forces_all).max()
    # Pairs with an ellipsoid are a small part of the energy; a split that lost them would fail.
    assert abs(energy_all) > 1000


def lennard_jones_pair(sigma, epsilon, r):
    return 4*epsilon*((sigma/r)**12-(sigma/r)**6)


def test_lennard_jones_tail_against_a_direct_sum():
    # TraPPE's treatment of the dispersion beyond the cutoff rc, with g(r) = 1 there:
    #   U_tail = 2 pi / V sum_ab n_a n_b int_rc^inf r^2 u_ab(r) dr,
    # and the pressure a Monte Carlo barostat feels from it (TraPPE's own volume moves, and
    # OpenMM's barostat, take energy differences): -dU_tail/dV, which is
    #   -2 pi / (3 V^2) sum_ab n_a n_b [int_rc^inf r^3 u_ab'(r) dr + rc^3 u_ab(rc)]
    # (the virial's tail plus the impulse of the pairs that scaling moves across the cutoff; it
    # equals U_tail / V, here by a separate quadrature). Checked:
    # 1. OpenMM's dispersion correction as the model sets it up (the energy with it less without,
    #    and that difference's change with the volume) equals both integrals over the model's site
    #    classes;
    # 2. the integrals equal direct sums: sites uniformly at random (an ideal gas: g(r) = 1
    #    exactly on average), every pair between rc and R < L/2 summed, averaged over
    #    configurations: the energy, and the energy's change when each configuration is scaled
    #    with the box, against the same integrals from rc to R;
    # 3. each sum resolves its integral well enough that a sign error or a missing factor of 2
    #    would fail.
    from scipy.integrate import quad
    box, rc, far = 6.0, bm.CUTOFF, 2.9
    system, _, _, forces = bm.pentane_box(300, box, 1)
    lj = forces['lennard_jones']
    assert lj.getUseDispersionCorrection() and not lj.getUseSwitchingFunction()
    assert lj.getNonbondedMethod() == mm.NonbondedForce.CutoffPeriodic and lj.getCutoffDistance()._value == rc
    n = system.getNumParticles()
    sigma = np.array([lj.getParticleParameters(i)[1]._value for i in range(n)])
    epsilon = np.array([lj.getParticleParameters(i)[2]._value for i in range(n)])
    classes = {}
    for s, e in zip(sigma, epsilon):
        classes[(s, e)] = classes.get((s, e), 0)+1

    def tail(lower, upper, volume):
        """(energy, barostat's pressure) of the pairs between lower and upper, g(r) = 1."""
        energy = pressure = 0.0
        for (s1, e1), n1 in classes.items():
            for (s2, e2), n2 in classes.items():
                s, e = (s1+s2)/2, math.sqrt(e1*e2)
                u = lambda r: lennard_jones_pair(s, e, r)
                derivative = lambda r: 4*e*(-12*s**12/r**13+6*s**6/r**7)
                energy += 2*math.pi/volume*n1*n2*quad(lambda r: r*r*u(r), lower, upper)[0]
                ends = lower**3*u(lower)-(upper**3*u(upper) if np.isfinite(upper) else 0.0)
                pressure += -2*math.pi/(3*volume**2)*n1*n2*(quad(lambda r: r**3*derivative(r), lower, upper)[0]+ends)
        return energy, pressure

    volume = box**3
    expected_energy, expected_pressure = tail(rc, np.inf, volume)
    assert expected_energy < 0 and expected_pressure < 0
    assert expected_pressure == pytest.approx(expected_energy/volume, rel=1e-8)

    # 1. OpenMM's correction, at three box edges (it does not depend on the positions: they are on
    # a grid, so that no overlap makes the energies too large to subtract).
    grid = np.stack(np.meshgrid(*[np.arange(12)]*3, indexing='ij'), axis=-1).reshape(-1, 3)[:n]/12

    def correction(edge):
        values = []
        for use in (True, False):
            lj.setUseDispersionCorrection(use)
            system.setDefaultPeriodicBoxVectors(mm.Vec3(edge, 0, 0), mm.Vec3(0, edge, 0), mm.Vec3(0, 0, edge))
            context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName('Reference'))
            context.setPositions(grid*edge)
            values.append(context.getState(getEnergy=True).getPotentialEnergy()._value)
        return values[0]-values[1]
    assert correction(box) == pytest.approx(expected_energy, rel=2/n)  # OpenMM counts pairs as N(N+1)/2
    h = 1e-4*box
    assert -(correction(box+h)-correction(box-h))/((box+h)**3-(box-h)**3) == pytest.approx(expected_pressure, rel=2/n)

    # 2. Direct sums over random configurations, pairs between rc and far, at the box and scaled by
    # 1 -+ 1% in volume.
    shell_energy, shell_pressure = tail(rc, far, volume)
    rng = np.random.default_rng(11)
    pair_sigma = (sigma[:, None]+sigma[None, :])/2
    pair_epsilon = np.sqrt(epsilon[:, None]*epsilon[None, :])
    upper = np.triu_indices(n, 1)
    scales = ((1-0.01)**(1/3), (1+0.01)**(1/3))
    sums = []
    for _ in range(40):
        x = rng.uniform(0, box, (n, 3))
        d = x[:, None, :]-x[None, :, :]
        d -= box*np.round(d/box)
        r0 = np.sqrt((d*d).sum(axis=2))[upper]
        s0, e0 = pair_sigma[upper], pair_epsilon[upper]
        energies = []
        for scale in (1.0,)+scales:
            r = r0*scale
            inside = (r >= rc) & (r < far)
            energies.append(np.sum(lennard_jones_pair(s0[inside], e0[inside], r[inside])))
        sums.append((energies[0], -(energies[2]-energies[1])/(0.02*volume)))
    sums = np.array(sums)
    mean, error = sums.mean(axis=0), sums.std(axis=0, ddof=1)/math.sqrt(len(sums))
    for value, expected, err in zip(mean, (shell_energy, shell_pressure), error):
        assert abs(value-expected) < 4*err, (value, expected, err)
        assert 4*err < 0.25*abs(expected)  # a factor of 2 or a sign error would fail


class CutShort(Exception):
    """The stand-in for a session's end in the middle of a run."""


class StartedOver(Exception):
    """A run that was to carry on from its progress started over."""


@pytest.mark.parametrize('cut', [1, 3])
@pytest.mark.parametrize('kind', ['explicit', 'ExactFlow', 'LangevinMiddle'])
def test_replica_cut_short_carries_on_where_it_saved(tmp_path, monkeypatch, kind, cut):
    # A study's run saves its progress (study_folder.RunProgress) as it goes; cut short (here after
    # its first save, made when sampling starts, or its third, the saves made at every coarse
    # sample) and started again, it carries on from its last save and ends with the observables of
    # the run never cut: a sample repeated, lost or shifted, or a checkpoint not restored would
    # differ (the explicit equilibration is made to fail on the second sitting: a run that starts
    # over fails; an implicit run that started over would repeat the whole run and pass). One
    # thread: an uninterrupted run repeats bit for bit; the slack (1e-6 of each observable's
    # largest value) is the checkpoint's: a restored CPU Context sums its single-precision
    # nonbonded forces in another order (5e-9 seen after 0.3 ps), where a sample out of place or a
    # state not restored changes the observables by far more. Progress saved on another platform
    # (a GPU's, whose checkpoint the CPU cannot load) makes the run start over.
    import banana_runs as runs
    from study_folder import RunProgress, StudyFolder, StudyMismatch
    monkeypatch.setattr(runs, 'CHECKPOINT_SECONDS', 0.0)
    settings = dict(pentanes=320, melt_ps=0.1, equilibration_ps=0.4, production_ps=0.6, implicit_equilibration_ps=0.5, implicit_ps=3.0,
                    max_lag_ps=0.2)
    xi = bm.resistance_tensor(maxBeads=500)
    weights = runs.center_weights(np.array(xi.getCenterOfDiffusion()._value))
    seed = 11

    def replica(progress):
        if kind == 'explicit':
            return runs.explicit_replica(settings, 3.93, xi, weights, seed, 'CPU', {'Threads': '1'}, progress)
        return runs.implicit_replica(settings, 3.93, xi, weights, kind, bm.SOURCE_VISCOSITY, seed, 'CPU', {'Threads': '1'}, progress)

    class Interrupted(RunProgress):
        saves = 0

        def save(self, **arrays):
            super().save(**arrays)
            Interrupted.saves += 1
            if Interrupted.saves == cut:
                raise CutShort
    whole = replica(None)
    stage = StudyFolder(tmp_path).stage(kind, {'kind': kind}, inputs={})
    with pytest.raises(CutShort):
        replica(Interrupted(stage.progress(0, seed).path, seed))
    saved = stage.progress(0, seed).load()
    assert int(saved['samples_done']) == 10*(cut-1)  # at the start, then after each coarse sample of ten
    def started_over(*args):
        raise StartedOver
    monkeypatch.setattr(runs, 'equilibrated_nve_start', started_over)  # a run that started over would call it
    parts = replica(stage.progress(0, seed))
    assert set(parts) == set(whole)
    for name in whole:
        if name != 'seconds':
            assert np.shape(parts[name]) == np.shape(whole[name]), name
            deviation = np.max(np.abs(np.subtract(parts[name], whole[name])))/np.max(np.abs(whole[name]))
            assert deviation < 1e-6, (name, deviation)
    if kind == 'explicit':  # progress from another platform (whose checkpoint this one cannot load): the run starts over
        foreign = dict(saved, platform='CUDA')
        del foreign['progress_seed']
        stage.progress(0, seed).save(**foreign)
        with pytest.raises(StartedOver):
            replica(stage.progress(0, seed))
    stage.save(0, **parts)
    assert stage.progress(0, seed).load() is None  # a saved run's progress goes

    # Progress that is not this run's, or not readable, is refused, naming the file and the fix.
    RunProgress(stage.progress(1, seed).path, seed+1).save(samples_done=3)
    with pytest.raises(StudyMismatch, match='seed 12, not 11; remove it'):
        stage.progress(1, seed).load()
    stage.progress(1, seed).path.write_bytes(b'PK\x03\x04 cut off')
    with pytest.raises(StudyMismatch, match='cannot be read.*remove it'):
        stage.progress(1, seed).load()


def _gpu_platforms():
    from conftest import available_platforms
    return [name for name in available_platforms() if name not in bm.PERIODIC_GAYBERNE_EXCEPTIONS]


def _energy(system, positions, name):
    # Single precision where the platform has it: PoCL aborts in double on the scene's GayBerneForce.
    properties = {'Precision': 'single'} if name not in bm.PERIODIC_GAYBERNE_EXCEPTIONS else {}
    context = bm.scene_context(system, mm.VerletIntegrator(0.001), name, properties)
    context.setPositions(positions)
    return context.getState(getEnergy=True).getPotentialEnergy().value_in_unit(mm.unit.kilojoule_per_mole)


@pytest.mark.parametrize('name', _gpu_platforms())
def test_gayberne_exceptions_across_the_box_edge_drop_out_on_gpu_platforms(name):
    # Why scene_context() refuses these platforms for the scene with pentanes: two spheres 0.4 nm
    # apart across the edge of a 4 nm box, interacting only through a GayBerneForce exception. The
    # CPU platform gives their Lennard-Jones energy; OpenMM's common kernel takes the exception's
    # distance as 3.6 nm, beyond the cutoff, and gives none. When OpenMM makes that kernel periodic
    # this test fails: then let scene_context() take the platform.
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(4, 0, 0), mm.Vec3(0, 4, 0), mm.Vec3(0, 0, 4))
    force = bm.gayberne_force(1.4)
    for _ in range(2):
        system.addParticle(10.0)
        force.addParticle(0.35, 0.0, -1, -1, 0.35, 0.35, 0.35, 1.0, 1.0, 1.0)
    force.addException(0, 1, 0.35, 1.0)
    system.addForce(force)
    positions = [mm.Vec3(0.2, 1, 1), mm.Vec3(3.8, 1, 1)]
    expected = lennard_jones_pair(0.35, 1.0, 0.4)  # a Gay-Berne sphere of semi-axes sigma is Lennard-Jones
    assert _energy(system, positions, 'CPU') == pytest.approx(expected, rel=1e-6)
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName(name), {'Precision': 'single'})
    context.setPositions(positions)
    assert context.getState(getEnergy=True).getPotentialEnergy().value_in_unit(mm.unit.kilojoule_per_mole) == 0.0


@pytest.mark.parametrize('name', _gpu_platforms())
def test_scene_with_pentanes_is_refused_on_gpu_platforms_and_bananas_alone_agree(name):
    # The scene with pentanes (the explicit runs, the scene's box) is refused there, naming the
    # platform and the fix; the bananas alone (the implicit runs: no exception interacts) give the
    # CPU platform's energy, the second banana straddling the box's edge.
    import banana_runs as runs
    system, positions, _, _ = bm.pentane_box(40, 4.0, 3, bananas=2)
    with pytest.raises(mm.OpenMMException, match=f'cannot run on the {name} platform.*--platform CPU'):
        bm.scene_context(system, mm.VerletIntegrator(0.001), name)
    with pytest.raises(mm.OpenMMException, match=f'cannot run on the {name} platform'):
        runs.scene_box_run(320, 0.01, 3, name)
    system, positions, _, _ = bm.pentane_box(0, 4.0, 3, bananas=2)
    positions = np.array(positions)
    positions[0:9, 2] += 0.2-positions[0:9, 2].mean()
    positions[9:18] = positions[0:9]+np.array([0.0, 0.0, 4.0-0.5])  # 0.5 nm below the first, across z = 0
    positions = [mm.Vec3(*p) for p in positions]
    cpu = _energy(system, positions, 'CPU')
    assert abs(cpu) > 1.0  # the bananas interact
    assert _energy(system, positions, name) == pytest.approx(cpu, rel=1e-5)


def test_explicit_nve_starts_at_its_target_energy():
    # The explicit runs' NVE starts at the total energy whose microcanonical temperature is the
    # bath's, E = <U> + (N_f - 3) kT / 2, in the integrator's own kinetic energy (the one the runs'
    # temperatures come from): velocity Verlet's stored velocities lag the positions by half a kick,
    # and scaling them to the target by their own kinetic energy left the total 5 to 26 kJ/mol short
    # (seen: a replica 1.3 K cold). After 100 steps the total energy is still the target (NVE).
    import banana_runs as runs
    xi = bm.resistance_tensor(maxBeads=500)
    system, positions, bodies, _ = bm.pentane_box(320, 3.93, 5, bananas=2)
    integrator = runs.explicit_integrator(system, bodies, xi, runs.MELT_VISCOSITY)
    integrator.setRandomNumberSeed(5)
    context = bm.scene_context(system, integrator, 'CPU')
    context.setPositions(positions)
    dof = integrator.getNumDegreesOfFreedom()-3
    target = runs.equilibrated_nve_start(dict(melt_ps=0.5, equilibration_ps=2.0), context, integrator, runs.particle_masses(system), dof, 5)

    def total():
        state = context.getState(getEnergy=True)
        return (state.getKineticEnergy()+state.getPotentialEnergy()).value_in_unit(mm.unit.kilojoule_per_mole)
    assert abs(total()-target) < runs.NVE_START_TOLERANCE
    integrator.step(100)
    assert abs(total()-target) < 1.0


def test_report_says_which_errors_reach_their_targets():
    # diffusion.md says which relative standard errors reach the study's targets (5% explicit,
    # the finite-size corrected D_t; 3% implicit) and, for the others, the replicas the spread so
    # far asks for: n (error/target)^2, rounded up (a square root instead of the square, or the
    # explicit target on an implicit run, would give another count).
    import banana_report

    def row(run, replicas, d_t, d_t_error, d_r, d_r_error):
        return {'run': run, 'replicas': replicas, 'D_t (1e-5 cm^2/s)': d_t, 'D_t error': d_t_error,
                'D_r (1/ns)': d_r, 'D_r error': d_r_error, 'ns/day': 1.0}
    rows = [row('explicit', 5, 3.0, 0.9, 4.0, 0.5),  # the periodic box's D_t: not the one the target is on
            row('explicit, finite-size corrected (eta linear in k^2)', 5, 4.0, 0.19, 4.0, 0.5),
            row('explicit, finite-size corrected (1/eta linear in k^2)', 5, 3.9, 0.19, 4.0, 0.5),  # its D_r said once
            row('ExactFlow', 12, 1.0, 0.03, 1.0, 0.031)]
    sentence = banana_report.target_errors(rows)
    assert 'explicit D_r 12.5% (about 32 replicas' in sentence and 'ExactFlow D_r 3.1% (about 13 replicas' in sentence
    assert 'explicit D_t' not in sentence and 'ExactFlow D_t' not in sentence and sentence.count('explicit D_r') == 1
    rows[1]['D_r error'] = rows[2]['D_r error'] = rows[3]['D_r error'] = 0.02
    assert banana_report.target_errors(rows).endswith('Every one reached.')
    rows[3]['replicas'], rows[3]['D_t error'] = 1, float('nan')  # one replica: no spread, no error yet
    assert 'ExactFlow D_t nan% (about 2 replicas' in banana_report.target_errors(rows)


def test_jackknife_error_of_a_mean_is_its_standard_error():
    # The delete-one jackknife gives exactly s/sqrt(n) for a mean (a missing (n-1)/n would be 6%
    # off at n = 9, the left-out means' own spread a factor 3 small); and for a
    # difference of two correlated quantities' means, the standard error of the per-replica
    # differences, which the two errors combined as if independent would overstate.
    import banana_report
    rng = np.random.default_rng(5)
    a = rng.normal(size=9)
    b = a+0.1*rng.normal(size=9)
    assert banana_report.jackknife_error(np.mean, a) == pytest.approx(a.std(ddof=1)/3, rel=1e-12)
    difference = banana_report.jackknife_error(lambda x, y: y.mean()-x.mean(), a, b)
    assert difference == pytest.approx((b-a).std(ddof=1)/3, rel=1e-12)
    assert difference < 0.2*math.hypot(a.std(ddof=1), b.std(ddof=1))/3


def test_source_tensor_read_in_its_own_units():
    # The source's tensor as this project reads it (amu/fs, amu A/fs, amu A^2/fs at 0.289 cP, about
    # its centre of resistance, z along the banana): turned back into the source's frame and units
    # it is the source's matrix again, about the source's centre of resistance; and the diffusion it
    # predicts is kT Xi^-1 computed here in the source's own units (amu, A, fs) with no turn or unit
    # change at all: D_r, the tumbling of the long axis (the mobility's x and y rotations in the
    # source's frame; rotation's block of Xi^-1 is the same about any point), exactly; D_t, a third
    # of the trace of the translational mobility, smallest at the centre of diffusion, at most 0.2%
    # below its value at the centre of resistance. A factor of 10 in a unit, or the wrong axis
    # tumbling (58.64 against 10.74 amu A^2/fs), would be far off.
    import banana_runs as runs
    xi = bm.source_resistance_tensor()
    _, turn = bm.source_frame(np.eye(6))
    stated = turn.T@bm.SOURCE_CENTER_OF_RESISTANCE/10  # nm, in the banana's frame
    turned, _ = bm.source_frame(np.array(xi.getMatrix(mm.Vec3(*stated)))*bm.source_units())
    symmetric = (bm.SOURCE_TENSOR+bm.SOURCE_TENSOR.T)/2
    assert np.allclose(turned, symmetric, rtol=0, atol=1e-12*np.abs(symmetric).max())
    # The point where its coupling block is symmetric is the one it states, to the 4 digits it gives.
    center = np.array(xi.getCenterOfResistance().value_in_unit(mm.unit.nanometer))
    assert np.allclose(turn@center*10, bm.SOURCE_CENTER_OF_RESISTANCE, atol=1e-4)
    d_t, d_r = runs.predicted_diffusion(xi, bm.SOURCE_VISCOSITY)
    kt = 1.380649e-23*runs.TEMPERATURE/(1.66053906660e-27*1e-20/1e-30)  # amu A^2/fs^2
    mobility = kt*np.linalg.inv(symmetric)  # A^2/fs, A/fs, 1/fs
    assert d_r*1e-3 == pytest.approx((mobility[3, 3]+mobility[4, 4])/2, rel=1e-10)  # 1/ps to 1/fs
    at_center_of_resistance = np.trace(mobility[:3, :3])/3*1e-2/1e-3  # A^2/fs to nm^2/ps
    assert 0.998*at_center_of_resistance < d_t <= at_center_of_resistance*(1+1e-12)


def test_velocity_autocorrelations_compared_at_their_lags():
    # diffusion.md's table of normalised velocity autocorrelations reads each curve at its lag in
    # SAMPLE_PS steps (at COARSE_PS steps 0.1 ps would read 1 ps), normalised per replica, and the
    # smallest difference from the explicit curve is in the two standard errors combined: a curve
    # identical to the explicit one is 0 apart, and one shifted by 0.05 whose replicas scatter like
    # the explicit ones (standard error 0.01 each) is 0.05/(0.01 sqrt 2) = 3.5 apart.
    import banana_report
    import banana_runs as runs

    class Stage:
        def __init__(self, curves):
            self.curves = curves

        def runs(self):
            return [(i, {'vacf': c}) for i, c in enumerate(self.curves)]
    t = np.arange(int(round(runs.VACF_PS/runs.SAMPLE_PS))+1)*runs.SAMPLE_PS
    explicit = [np.exp(-t/0.2)+s*(t > 0) for s in (-0.01, 0.01)]  # two replicas: standard error 0.01 at t > 0
    shifted = [3*(c+0.05*(t > 0)) for c in explicit]  # scaled: the table normalises each replica at t = 0
    lines = banana_report.vacf_lines({'explicit': Stage(explicit), 'same': Stage(explicit), 'shifted': Stage(shifted)})
    row = next(line for line in lines if line.startswith('| 0.1 |'))
    assert row.split(' | ')[1:3] == [f'{math.exp(-0.5):.4f} ± 0.0100', f'{math.exp(-0.5):.4f} ± 0.0100']
    assert row.split(' | ')[3] == f'{math.exp(-0.5)+0.05:.4f} ± 0.0100 |'
    assert lines[-1].endswith(f'same 0.0, shifted {0.05/(0.01*math.sqrt(2)):.1f}.')
