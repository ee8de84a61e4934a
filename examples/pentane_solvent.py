"""The banana scene's solvent on its own: the density of the pentane model under a barostat and its
shear viscosity by periodic perturbation, and the estimators that turn runs into those numbers.

Density: PENTANES pentanes (banana_model.pentane_box, TraPPE-UA with its 1.4 nm cutoff and tail
correction) at 273.15 K and 1 bar, OpenMM's LangevinMiddleIntegrator (1/ps; friction changes no
static average) with a MonteCarloBarostat, from a lattice at the experimental density. The box
volume is sampled every 0.1 ps; settled_mean() drops the start that has not settled (Chodera's
equilibration detection, pymbar.timeseries) and gives the mean with its standard error from the
statistical inefficiency of what is left.

Viscosity (Hess, J. Chem. Phys. 116, 209 (2002)): a periodic acceleration a_x(z) = A cos(k z),
k = 2 pi n / L, drives a steady flow v_x(z) = V cos(k z) with V = A rho / (eta k^2), rho the mass
density; eta(k) falls with k, so runs at several n are extrapolated to k = 0 by weighted fits of
both common forms, eta(k) = eta_0 + c k^2 (extrapolate_to_zero_wavenumber) and 1/eta(k) = 1/eta_0 +
a k^2 (extrapolate_inverse_to_zero_wavenumber, GROMACS's), each with its chi-squared's verdict
(fit_accepted): which is right is not known beforehand. The integrator is velocity Verlet with
Bussi, Donadio & Parrinello's stochastic velocity rescaling (J. Chem. Phys. 126, 014101 (2007))
acting on the velocities less the flow profile: a global thermostat that takes out the heat the
flow makes without damping any particle's motion, unlike a Langevin thermostat, whose friction
would add to the fluid's and change the viscosity it measures.
"""
import logging
import math

import numpy as np
import openmm as mm
import openmm.unit as unit

import banana_model as bm

TEMPERATURE = 273.15  # K: 0 C, where the experimental numbers are (the source's "273 K")
PRESSURE = 1.0  # bar
STEP = 0.001  # ps: flexible pentane bonds
PENTANES = 320
# Experiment at 273.15 K and 1 bar. Density: 0.6454 g/mL (CRC Handbook of Chemistry and Physics,
# n-pentane); shear viscosity 0.289 cP (the source's eta, the experimental value at 0 C).
EXPERIMENT_DENSITY = 0.6454
EXPERIMENT_VISCOSITY = 0.289
AVOGADRO = 6.02214076e23
AMU_PER_NM_PS_IN_CP = 1.66053906660e-27/(1e-9*1e-12)*1e3  # one amu/(nm ps) in cP
KT = bm.BOLTZ*TEMPERATURE  # kJ/mol
NPT_FRICTION = 1.0  # 1/ps
SAMPLE_PS = 0.1
FLOW_TAU = 0.5  # ps: the thermostat's time constant
FLOW_INTERVAL = 10  # steps between rescalings
# What a run's numbers depend on beside its model and length (kept with every study's runs).
NPT_SETTINGS = {'step': STEP, 'pressure': PRESSURE, 'friction': NPT_FRICTION, 'barostat_interval': 25, 'sample_ps': SAMPLE_PS}
FLOW_SETTINGS = {'step': STEP, 'tau': FLOW_TAU, 'interval': FLOW_INTERVAL, 'sample_ps': SAMPLE_PS}


def density_from_volume(volume_per_pentane):
    """Mass density (g/mL) of pentane at a volume per molecule (nm^3)."""
    return bm.PENTANE_MASS/(AVOGADRO*volume_per_pentane*1e-21)


def box_edge(density, pentanes=PENTANES):
    """Edge (nm) of the cubic box that holds pentanes molecules at density (g/mL)."""
    return (pentanes*bm.PENTANE_MASS/(AVOGADRO*density)*1e21)**(1/3)


def _timeseries():
    # pymbar warns on import that JAX, which it can use but does not need, is missing.
    logging.getLogger('pymbar').setLevel(logging.ERROR)
    from pymbar import timeseries
    return timeseries


def settled_mean(series):
    """The mean of a time series once it has settled, and its standard error: the start is the
    one that maximises the number of uncorrelated samples left (Chodera, J. Chem. Theory Comput.
    12, 1799 (2016)), the error sigma sqrt(g/N) with g the statistical inefficiency of the rest.
    Returns {'mean', 'error', 'start' (index), 'inefficiency', 'samples' (after the start)}."""
    series = np.asarray(series, dtype=float)
    start, inefficiency, _ = _timeseries().detect_equilibration(series)
    start = int(start)
    rest = series[start:]
    inefficiency = float(max(1.0, inefficiency))
    error = float(rest.std(ddof=1)*math.sqrt(inefficiency/len(rest))) if len(rest) > 1 else float('nan')
    return {'mean': float(rest.mean()), 'error': error, 'start': start, 'inefficiency': inefficiency, 'samples': len(rest)}


def pentane_system(box, seed, pentanes=PENTANES, cutoff=bm.CUTOFF):
    """The neat solvent: (system, lattice positions) of pentanes molecules in a cubic box (nm)."""
    system, positions, _, _ = bm.pentane_box(pentanes, box, seed, cutoff=cutoff)
    return system, positions


def barostat(seed):
    """The Monte Carlo barostat of every NPT run here, its random numbers from seed (OpenMM picks
    them anew for each Context unless given one, and a run could not be repeated)."""
    force = mm.MonteCarloBarostat(PRESSURE, TEMPERATURE, NPT_SETTINGS['barostat_interval'])
    force.setRandomNumberSeed(seed)
    return force


def npt_run(picoseconds, seed, platform, properties=None, pentanes=PENTANES, sample_ps=SAMPLE_PS):
    """NPT from a lattice at the experimental density: the volume per pentane (nm^3) every
    sample_ps, and the final State. The lattice is minimised first."""
    system, positions = pentane_system(box_edge(EXPERIMENT_DENSITY, pentanes), seed, pentanes)
    system.addForce(barostat(seed))
    integrator = mm.LangevinMiddleIntegrator(TEMPERATURE, NPT_FRICTION, STEP)
    integrator.setRandomNumberSeed(seed)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform), properties or {})
    context.setPositions(positions)
    mm.LocalEnergyMinimizer.minimize(context, 10.0, 1000)
    context.setVelocitiesToTemperature(TEMPERATURE, seed)
    every = int(round(sample_ps/STEP))
    volumes = []
    for _ in range(int(round(picoseconds/sample_ps))):
        integrator.step(every)
        volumes.append(context.getState().getPeriodicBoxVolume().value_in_unit(unit.nanometer**3)/pentanes)
    return np.array(volumes), context.getState(getPositions=True, getVelocities=True, enforcePeriodicBox=True)


def cosine_acceleration_integrator(amplitude, wavenumber, temperature, step, tau, degrees_of_freedom, interval=10):
    """Velocity Verlet with the periodic acceleration a_x = amplitude cos(wavenumber z) (nm/ps^2,
    1/nm) and, every interval steps, stochastic velocity rescaling (time constant tau, ps) of the
    velocities less the flow profile V cos(k z) x, V measured then as 2 sum m v_x cos(k z) / sum m.
    The global variables flowSum, kineticSum and samples accumulate V and the kinetic energy less
    the flow (kJ/mol) at each rescaling, for block averages read between calls to step(). The
    rescaling's chi-squared draw of degrees_of_freedom - 1 Gaussians is taken as its normal
    approximation, (n-1) + sqrt(2 (n-1)) g, exact to a relative 1/sqrt(n) in its skewness (n is
    about 4800 here). Rescaling every 10 steps rather than every step keeps the cost of the sums
    (OpenMM evaluates a CustomIntegrator's expressions particle by particle on one thread) at a
    tenth; the thermostat's time constant is 50 of those intervals."""
    integrator = mm.CustomIntegrator(step)
    for name, value in (('A', amplitude), ('k', wavenumber), ('kT', bm.BOLTZ*temperature), ('c', math.exp(-interval*step/tau)),
                        ('nf', degrees_of_freedom), ('interval', interval), ('counter', 0.0), ('totalMass', 0.0), ('V', 0.0),
                        ('K', 0.0), ('alpha', 1.0), ('r1', 0.0), ('flowSum', 0.0), ('kineticSum', 0.0), ('samples', 0.0)):
        integrator.addGlobalVariable(name, value)
    # cos(k z) of each particle, in the x component only: the profile's shape at the current positions.
    integrator.addPerDofVariable('profile', 0.0)
    integrator.addComputePerDof('profile', 'vector(cos(k*_z(x)), 0, 0)')
    integrator.addComputePerDof('v', 'v + 0.5*dt*(f/m + A*profile)')
    integrator.addComputePerDof('x', 'x + dt*v')
    integrator.addComputePerDof('profile', 'vector(cos(k*_z(x)), 0, 0)')
    integrator.addComputePerDof('v', 'v + 0.5*dt*(f/m + A*profile)')
    integrator.addComputeGlobal('counter', 'counter + 1')
    integrator.beginIfBlock('counter >= interval')
    # The flow's amplitude and the kinetic energy of the rest of the motion.
    integrator.addComputeSum('totalMass', 'm')  # every particle's mass three times, once per degree of freedom
    integrator.addComputeGlobal('totalMass', 'totalMass/3')
    integrator.addComputeSum('V', 'm*v*profile')
    integrator.addComputeGlobal('V', '2*V/totalMass')
    integrator.addComputeSum('K', '0.5*m*(v-V*profile)^2')
    integrator.addComputeGlobal('r1', 'gaussian')
    target = '(0.5*nf*kT)'
    integrator.addComputeGlobal('alpha', f'sqrt(max(0, c + (1-c)*((nf-1) + sqrt(2*(nf-1))*gaussian + r1*r1)*{target}/(nf*K)'
                                        f' + 2*r1*sqrt(c*(1-c)*{target}/(nf*K))))')
    integrator.addComputePerDof('v', 'V*profile + alpha*(v-V*profile)')
    integrator.addComputeGlobal('flowSum', 'flowSum + V')
    integrator.addComputeGlobal('kineticSum', 'kineticSum + alpha*alpha*K')
    integrator.addComputeGlobal('samples', 'samples + 1')
    integrator.addComputeGlobal('counter', '0')
    integrator.endBlock()
    return integrator


def degrees_of_freedom(system):
    """Degrees of freedom of the motion less the flow: 3 per massive particle, less the total
    momentum and the flow's own mode."""
    return 3*sum(1 for i in range(system.getNumParticles()) if system.getParticleMass(i).value_in_unit(unit.dalton) > 0)-4


def flow_run(positions, velocities, box, harmonic, flow_speed, picoseconds, seed, platform, properties=None, pentanes=PENTANES,
             build_up_ps=20.0, sample_ps=SAMPLE_PS, tau=FLOW_TAU):
    """Periodic perturbation of the neat solvent at positions and velocities (nm, nm/ps) in a cubic
    box of edge box (nm), at wavenumber k = 2 pi harmonic / box, with the acceleration that drives a
    flow of about flow_speed (nm/ps) at the experimental viscosity. After build_up_ps, block means
    over sample_ps of the flow amplitude V (nm/ps) and the temperature of the motion less the flow
    (K). Returns {'amplitude', 'wavenumber', 'density' (amu/nm^3), 'V', 'temperature'}."""
    system, _ = pentane_system(box, seed, pentanes)
    volume = box**3
    k = 2*math.pi*harmonic/box
    masses = np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())])
    rho = masses.sum()/volume
    amplitude = flow_speed*(EXPERIMENT_VISCOSITY/AMU_PER_NM_PS_IN_CP)*k*k/rho
    dof = degrees_of_freedom(system)
    integrator = cosine_acceleration_integrator(amplitude, k, TEMPERATURE, STEP, tau, dof, FLOW_INTERVAL)
    integrator.setRandomNumberSeed(seed)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform), properties or {})
    context.setPositions(positions)
    context.setVelocities(velocities)
    integrator.step(int(round(build_up_ps/STEP)))
    every = int(round(sample_ps/STEP))
    flow, temperature = [], []
    for _ in range(int(round(picoseconds/sample_ps))):
        for name in ('flowSum', 'kineticSum', 'samples'):
            integrator.setGlobalVariableByName(name, 0.0)
        integrator.step(every)
        samples = integrator.getGlobalVariableByName('samples')
        flow.append(integrator.getGlobalVariableByName('flowSum')/samples)
        temperature.append(2*integrator.getGlobalVariableByName('kineticSum')/samples/(dof*bm.BOLTZ))
    return {'amplitude': amplitude, 'wavenumber': k, 'density': rho, 'V': np.array(flow), 'temperature': np.array(temperature)}


def viscosity_from_flow(amplitude, density, wavenumber, flow, flow_error):
    """eta = A rho / (V k^2) (amu/(nm ps)) and its standard error from V's, for a steady flow of
    amplitude flow (nm/ps) driven by amplitude (nm/ps^2) at wavenumber (1/nm) in a fluid of mass
    density (amu/nm^3)."""
    eta = amplitude*density/(flow*wavenumber**2)
    return eta, eta*flow_error/abs(flow)


def weighted_line(x, y, errors):
    """Weighted least-squares line y = a + b x through points with standard errors: returns (a, its
    standard error, b, its standard error, chi-squared of the fit). The errors are the inputs' own;
    chi-squared tells whether the line describes the points (about the number of points less two if
    it does)."""
    x, y, errors = (np.asarray(v, dtype=float) for v in (x, y, errors))
    if len(x) < 2 or len(set(x)) < 2:
        raise ValueError('extrapolating to k = 0 needs viscosities at two wavenumbers at least')
    design = np.stack([np.ones_like(x), x], axis=1)/errors[:, None]
    covariance = np.linalg.inv(design.T@design)
    coefficients = covariance@design.T@(y/errors)
    chi2 = float(np.sum(((design@coefficients)-y/errors)**2))
    return (float(coefficients[0]), float(math.sqrt(covariance[0, 0])), float(coefficients[1]), float(math.sqrt(covariance[1, 1])), chi2)


def extrapolate_to_zero_wavenumber(wavenumbers, etas, errors):
    """The line eta(k) = eta_0 + c k^2 through viscosities at several wavenumbers (1/nm) with
    standard errors (weighted_line): returns (eta_0, its standard error, c, its standard error,
    chi-squared)."""
    return weighted_line(np.asarray(wavenumbers, dtype=float)**2, etas, errors)


def extrapolate_inverse_to_zero_wavenumber(wavenumbers, etas, errors):
    """The other common form: 1/eta(k) = 1/eta_0 + a k^2, which GROMACS's gmx tcaf prescribes
    (eta(k) = eta_0 (1 - a eta(k) k^2)); a weighted line through 1/eta with standard errors
    error/eta^2 (first order in the relative errors). Returns (eta_0, its standard error, a, its
    standard error, chi-squared); eta_0's error is the intercept's, error(1/eta_0) eta_0^2."""
    etas, errors = np.asarray(etas, dtype=float), np.asarray(errors, dtype=float)
    inverse, inverse_error, slope, slope_error, chi2 = weighted_line(np.asarray(wavenumbers, dtype=float)**2, 1/etas, errors/etas**2)
    return 1/inverse, inverse_error/inverse**2, slope, slope_error, chi2


def fit_accepted(chi2, degrees_of_freedom, level=0.05):
    """Whether a fit's chi-squared is no worse than chance would give with probability level: its
    survival probability (the chance of a chi-squared at least this large if the form were right)
    and whether it is at least level. Without a degree of freedom a fit cannot be tested: (nan, True)."""
    if degrees_of_freedom < 1:
        return float('nan'), True
    from scipy.stats import chi2 as distribution
    probability = float(distribution.sf(chi2, degrees_of_freedom))
    return probability, probability >= level


def extrapolations_by_shear_rate(viscosities):
    """The extrapolations to k = 0 of viscosities measured at several harmonics n, one per shear
    rate: a harmonic's flow speed V is set so that n V, and with it the shear rate k V, is shared by
    the harmonics of one series. viscosities: dicts with 'harmonic', 'speed', 'wavenumber', 'eta',
    'error'. Returns {n V: dict(eta0, error, slope, slope_error, chi2, probability, accepted,
    inverse=the same of the 1/eta form, fitted=[the viscosities])} over the rates with two harmonics
    or more: eta linear in k^2 (extrapolate_to_zero_wavenumber), and in inverse 1/eta linear
    (extrapolate_inverse_to_zero_wavenumber), each with its chi-squared's probability and whether
    that accepts it (fit_accepted)."""
    fits = {}
    for rate in sorted({round(v['harmonic']*v['speed'], 9) for v in viscosities}):
        group = sorted((v for v in viscosities if abs(v['harmonic']*v['speed']-rate) < 1e-9), key=lambda v: v['harmonic'])
        if len({v['harmonic'] for v in group}) >= 2:
            points = ([v['wavenumber'] for v in group], [v['eta'] for v in group], [v['error'] for v in group])
            forms = [dict(zip(('eta0', 'error', 'slope', 'slope_error', 'chi2'), fit(*points)))
                     for fit in (extrapolate_to_zero_wavenumber, extrapolate_inverse_to_zero_wavenumber)]
            for form in forms:
                form['probability'], form['accepted'] = fit_accepted(form['chi2'], len(group)-2)
            fits[rate] = dict(forms[0], inverse=forms[1], fitted=group)
    return fits


def newtonian_rate(fits):
    """The shear rate whose extrapolation stands for the Newtonian viscosity: the lowest with three
    harmonics or more (the least shear thinning, and a line with a degree of freedom to test it),
    else the one with the most harmonics (the highest rate among equals)."""
    full = [rate for rate, fit in fits.items() if len(fit['fitted']) >= 3]
    return min(full) if full else max(fits, key=lambda rate: (len(fits[rate]['fitted']), rate))

