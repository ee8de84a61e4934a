"""The banana scene's solvent estimators on cases with known answers: the settled mean of a time
series, the density under OpenMM's Monte Carlo barostat (an ideal gas), the flow a periodic
acceleration drives (a collisionless gas), and the extrapolation of eta(k) to k = 0."""
import math
import pathlib
import sys

import numpy as np
import openmm as mm
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]/'examples'))
import banana_model as bm  # noqa: E402
import pentane_solvent as ps  # noqa: E402


def ar1(rng, n, phi, sigma):
    noise = rng.normal(0, sigma, n)
    x = np.empty(n)
    x[0] = noise[0]/math.sqrt(1-phi*phi)
    for i in range(1, n):
        x[i] = phi*x[i-1]+noise[i]
    return x


def test_settled_mean_drops_the_start_and_gives_the_right_error():
    # An AR(1) series (correlation phi per sample) about 10 with a start decaying from 10 + 10 sigma_x
    # over 100 samples (as a density relaxes from its lattice start): the settled mean must be 10
    # within its error, that error must be the known one of an AR(1) mean
    # (sigma_x sqrt((1 + phi)/((1 - phi) N))) within 30% on average over series, and the plain mean,
    # start included, must be off by many of those errors (so the test can fail).
    rng = np.random.default_rng(4)
    phi, sigma, n = 0.9, 1.0, 2000
    sigma_x = sigma/math.sqrt(1-phi*phi)
    ratios, misses, plain = [], [], []
    for _ in range(12):
        series = 10+ar1(rng, n, phi, sigma)+10*sigma_x*np.exp(-np.arange(n)/100.0)
        result = ps.settled_mean(series)
        assert result['start'] > 50
        known = sigma_x*math.sqrt((1+phi)/((1-phi)*result['samples']))
        ratios.append(result['error']/known)
        misses.append((result['mean']-10)/result['error'])
        plain.append((series.mean()-10)/known)
    assert 0.7 < np.mean(ratios) < 1.3
    assert np.sqrt(np.mean(np.square(misses))) < 2.0  # z-scores of about 1
    assert min(plain) > 3


def test_density_estimator_on_an_ideal_gas():
    # OpenMM's Monte Carlo barostat on N free particles samples V^N exp(-PV/kT): <V> = (N+1) kT/P
    # exactly. The volume trace through settled_mean (from a box far too small) must give it
    # within four of its own errors, and that error must be small enough to see 5%.
    n, temperature, pressure = 200, 273.15, 200.0  # bar
    system = mm.System()
    for _ in range(n):
        system.addParticle(15.0)
    kt = bm.BOLTZ*temperature  # kJ/mol
    bar = 0.0602214076  # kJ/mol/nm^3 per bar
    expected = (n+1)*kt/(pressure*bar)
    edge = (0.3*expected)**(1/3)
    system.setDefaultPeriodicBoxVectors(mm.Vec3(edge, 0, 0), mm.Vec3(0, edge, 0), mm.Vec3(0, 0, edge))
    periodic = mm.NonbondedForce()  # no interaction: only makes the System periodic, as a barostat needs
    periodic.setNonbondedMethod(mm.NonbondedForce.CutoffPeriodic)
    periodic.setCutoffDistance(0.5)
    for _ in range(n):
        periodic.addParticle(0.0, 0.1, 0.0)
    system.addForce(periodic)
    system.addForce(mm.MonteCarloBarostat(pressure, temperature, 1))
    integrator = mm.LangevinMiddleIntegrator(temperature, 1.0, 0.01)
    integrator.setRandomNumberSeed(3)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))
    context.setPositions(np.random.default_rng(3).uniform(0, edge, (n, 3)))
    volumes = []
    for _ in range(2000):
        integrator.step(2)
        volumes.append(context.getState().getPeriodicBoxVolume()._value)
    result = ps.settled_mean(volumes)
    assert result['start'] > 0
    assert abs(result['mean']-expected) < 4*result['error'], (result, expected)
    assert 4*result['error'] < 0.05*expected


def free_gas(n, mass, edge, seed, temperature, integrator):
    system = mm.System()
    for _ in range(n):
        system.addParticle(mass)
    system.setDefaultPeriodicBoxVectors(mm.Vec3(edge, 0, 0), mm.Vec3(0, edge, 0), mm.Vec3(0, 0, edge))
    integrator.setRandomNumberSeed(seed)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))
    context.setPositions(np.random.default_rng(seed).uniform(0, edge, (n, 3)))
    context.setVelocitiesToTemperature(temperature, seed)
    return context


def test_periodic_acceleration_drives_the_exact_collisionless_flow():
    # Free particles at rest along x, moving along z at speeds v_j, under a_x = A cos(kz) with no
    # thermostat: each z moves ballistically, so the flow amplitude the integrator measures,
    # V(t) = 2 <v_x cos(k z)>, is exactly A <sin(k v_j t) / (k v_j)> over the particles when their
    # z lie evenly over a wavelength (then <cos(kz) cos(kz - b)> = cos(b)/2 exactly). With v_j the
    # quantiles of the Maxwell distribution that is A int_0^t exp(-k^2 (kT/m) s^2 / 2) ds to
    # within the quadrature's error. The integrator must follow it to 1e-4 at every measurement
    # over 8 ps (velocity Verlet's trapezoidal rule is exact to (k v dt)^2 here): a wrong factor in
    # the acceleration, the measure of V or k fails.
    from scipy.stats import norm
    mass, edge, temperature, step, amplitude = 15.0, 4.0, 273.15, 0.005, 0.05
    k = 2*math.pi/edge
    speeds = math.sqrt(bm.BOLTZ*temperature/mass)*norm.ppf((np.arange(250)+0.5)/250)
    heights = edge*(np.arange(8)+0.5)/8
    system = mm.System()
    positions, velocities = [], []
    for z in heights:
        for v in speeds:
            system.addParticle(mass)
            positions.append((0.1, 0.1, z))
            velocities.append((0.0, 0.0, v))
    system.setDefaultPeriodicBoxVectors(mm.Vec3(edge, 0, 0), mm.Vec3(0, edge, 0), mm.Vec3(0, 0, edge))
    integrator = ps.cosine_acceleration_integrator(amplitude, k, temperature, step, 1e30, 3*len(positions)-4)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName('Reference'))
    context.setPositions(positions)
    context.setVelocities(velocities)
    for block in range(1, 161):
        integrator.step(10)
        t = 10*step*block
        expected = amplitude*np.mean(np.sin(k*speeds*t)/(k*speeds))
        assert integrator.getGlobalVariableByName('V') == pytest.approx(expected, rel=1e-4), t
    spread = math.sqrt(bm.BOLTZ*temperature/mass)
    assert expected == pytest.approx(amplitude*math.sqrt(math.pi/2)/(k*spread)*math.erf(k*spread*t/math.sqrt(2)), rel=0.01)


def test_flow_thermostat_samples_the_canonical_kinetic_energy():
    # Stochastic velocity rescaling of a free gas started at 150 K: the kinetic energy less the
    # flow, sampled at each rescaling, must settle to the canonical distribution at 273.15 K, a
    # Gamma distribution of mean N_f kT/2 and variance N_f (kT)^2/2 (the variance tells a rescaling
    # that only holds the mean, such as Berendsen's, or twice the noise, from the right one).
    n, mass, temperature, step = 200, 15.0, 273.15, 0.005
    dof = 3*n-4
    integrator = ps.cosine_acceleration_integrator(0.0, 1.0, temperature, step, 0.05, dof, interval=1)
    context = free_gas(n, mass, 4.0, 9, 150.0, integrator)
    kinetic = []
    for _ in range(10000):
        integrator.step(1)
        kinetic.append(integrator.getGlobalVariableByName('alpha')**2*integrator.getGlobalVariableByName('K'))
    del context
    kinetic = np.array(kinetic)
    kt = bm.BOLTZ*temperature
    mean = ps.settled_mean(kinetic)
    assert abs(mean['mean']-0.5*dof*kt) < 4*mean['error']
    settled = kinetic[mean['start']:]
    squares = ps.settled_mean((settled-0.5*dof*kt)**2)
    assert abs(squares['mean']-0.5*dof*kt**2) < 4*squares['error'], (squares, 0.5*dof*kt**2)
    assert 4*squares['error'] < 0.3*0.5*dof*kt**2


def test_viscosity_from_a_steady_flow():
    # The Navier-Stokes steady state of a_x = A cos(kz) in a fluid of viscosity eta and mass density
    # rho is v_x = (A rho / (eta k^2)) cos(kz): the estimator inverts it, with V's relative error.
    eta, rho, k, amplitude = 150.0, 355.0, 1.6, 0.3  # amu/(nm ps), amu/nm^3, 1/nm, nm/ps^2
    flow = amplitude*rho/(eta*k*k)
    assert ps.viscosity_from_flow(amplitude, rho, k, flow, 0.02*flow) == pytest.approx((eta, 0.02*eta), rel=1e-12)


def test_extrapolation_to_zero_wavenumber():
    # Exact points on a line in k^2 give its intercept and slope; noisy ones give the intercept
    # within its error, and the error is what the scatter of repeated fits shows.
    k = np.array([1.5, 3.0, 4.5])
    eta0, slope = 0.25, -0.004
    exact = eta0+slope*k**2
    fit = ps.extrapolate_to_zero_wavenumber(k, exact, np.full(3, 0.01))
    assert fit[0] == pytest.approx(eta0, rel=1e-12) and fit[2] == pytest.approx(slope, rel=1e-10) and fit[4] < 1e-20
    rng = np.random.default_rng(8)
    errors = np.array([0.01, 0.005, 0.004])
    fits = np.array([ps.extrapolate_to_zero_wavenumber(k, exact+rng.normal(0, errors), errors) for _ in range(2000)])
    assert np.std(fits[:, 0]) == pytest.approx(fits[0, 1], rel=0.1)
    assert abs(np.mean(fits[:, 0])-eta0) < 4*fits[0, 1]/math.sqrt(len(fits))
    assert np.mean(fits[:, 4]) == pytest.approx(1.0, rel=0.15)  # chi-squared with one degree of freedom
    with pytest.raises(ValueError, match='two wavenumbers'):
        ps.extrapolate_to_zero_wavenumber([1.5, 1.5], [0.2, 0.21], [0.01, 0.01])


def test_inverse_extrapolation_to_zero_wavenumber():
    # GROMACS's form, 1/eta(k) = 1/eta_0 + a k^2: points exactly on it give eta_0 and a exactly (a fit
    # of eta, or an intercept not inverted, would not), with eta_0's error the intercept's times
    # eta_0^2; noisy points scatter eta_0 by the error it states (without the factor eta_0^2 it would
    # be 25 times too small here).
    k = np.array([1.6, 3.2, 4.8])
    eta0, a = 0.2, 0.4  # cP, 1/(cP nm^2)
    exact = 1/(1/eta0+a*k**2)
    errors = np.array([0.004, 0.004, 0.003])
    fit = ps.extrapolate_inverse_to_zero_wavenumber(k, exact, errors)
    assert fit[0] == pytest.approx(eta0, rel=1e-12) and fit[2] == pytest.approx(a, rel=1e-10) and fit[4] < 1e-20
    intercept_error = ps.weighted_line(k**2, 1/exact, errors/exact**2)[1]
    assert fit[1] == pytest.approx(intercept_error*eta0**2, rel=1e-12)
    rng = np.random.default_rng(9)
    fits = np.array([ps.extrapolate_inverse_to_zero_wavenumber(k, exact+rng.normal(0, 0.1*errors), 0.1*errors) for _ in range(2000)])
    assert np.std(fits[:, 0]) == pytest.approx(fits[0, 1], rel=0.1)
    assert np.mean(fits[:, 4]) == pytest.approx(1.0, rel=0.15)


def test_chi_squared_rejects_the_wrong_form():
    # Points exactly linear in 1/eta, curved in eta by many of their errors: the eta-linear fit's
    # chi-squared rejects it, the 1/eta fit is accepted; and the other way round. The probability is
    # chi-squared's survival function (5% at its 95th percentiles, 3.841 for one degree of freedom and
    # 5.991 for two: a wrong number of degrees of freedom would move it).
    k = np.array([1.6, 3.2, 4.8])
    errors = np.full(3, 0.001)
    inverse_linear = 1/(1/0.2+0.4*k**2)
    eta_linear = 0.2-0.003*k**2
    for points, right, wrong in ((inverse_linear, ps.extrapolate_inverse_to_zero_wavenumber, ps.extrapolate_to_zero_wavenumber),
                                 (eta_linear, ps.extrapolate_to_zero_wavenumber, ps.extrapolate_inverse_to_zero_wavenumber)):
        assert ps.fit_accepted(right(k, points, errors)[4], 1)[1]
        chi2 = wrong(k, points, errors)[4]
        assert chi2 > 20 and ps.fit_accepted(chi2, 1) == (pytest.approx(0.0, abs=1e-5), False)
    assert ps.fit_accepted(3.841458820694124, 1)[0] == pytest.approx(0.05, rel=1e-9)
    assert ps.fit_accepted(5.991464547107979, 2)[0] == pytest.approx(0.05, rel=1e-9)
    assert ps.fit_accepted(4.26, 1)[1] is False and ps.fit_accepted(3.0, 1)[1] is True
    assert ps.fit_accepted(7.0, 0)[1] is True  # two points: nothing to test


def test_extrapolations_by_shear_rate_and_the_newtonian_choice():
    # Viscosities on exact lines in k^2, one per shear rate n V, whose intercepts fall with the rate
    # (shear thinning): each rate's line is recovered from its own harmonics only; the Newtonian
    # viscosity is taken at the lowest rate with three harmonics, not at a lower rate with two.
    k1 = 1.6

    def series(rate, harmonics, eta0):
        return [dict(harmonic=n, speed=rate/n, wavenumber=n*k1, eta=eta0-0.003*(n*k1)**2, error=0.002) for n in harmonics]
    viscosities = series(0.05, (1, 2, 3), 0.175)+series(0.025, (1, 2, 3), 0.2)+series(0.0125, (1, 2), 0.21)+series(0.006, (1,), 0.3)
    fits = ps.extrapolations_by_shear_rate(viscosities)
    assert sorted(fits) == [0.0125, 0.025, 0.05]  # a lone harmonic has no line
    for rate, eta0 in ((0.05, 0.175), (0.025, 0.2), (0.0125, 0.21)):
        assert fits[rate]['eta0'] == pytest.approx(eta0, rel=1e-10) and fits[rate]['slope'] == pytest.approx(-0.003, rel=1e-8)
    assert [v['harmonic'] for v in fits[0.025]['fitted']] == [1, 2, 3]
    # Beside each line in eta, the line in 1/eta through the same points, each with its verdict: the
    # exact lines in eta are accepted, and their curvature in 1/eta is rejected (chi-squared 5.4 for
    # one degree of freedom).
    group = fits[0.025]['fitted']
    inverse = ps.extrapolate_inverse_to_zero_wavenumber([v['wavenumber'] for v in group], [v['eta'] for v in group], [0.002]*3)
    assert [fits[0.025]['inverse'][key] for key in ('eta0', 'error', 'slope', 'slope_error', 'chi2')] == list(inverse)
    assert fits[0.025]['inverse']['chi2'] == pytest.approx(5.44, abs=0.01) and not fits[0.025]['inverse']['accepted']
    assert fits[0.025]['accepted'] and fits[0.025]['chi2'] < 1e-20
    assert ps.newtonian_rate(fits) == 0.025
    assert ps.newtonian_rate(ps.extrapolations_by_shear_rate(series(0.05, (1, 2, 3), 0.175)+series(0.025, (1,), 0.2))) == 0.05
    assert ps.newtonian_rate(ps.extrapolations_by_shear_rate(series(0.05, (1, 2), 0.175)+series(0.025, (2, 3), 0.2))) == 0.05

