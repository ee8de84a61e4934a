"""Which velocities the body-state read-out and a State report, for spheres pulled by a constant force.

Exact answers: a sphere of mass m and friction m gamma under a constant force F drifts at
F/(m gamma), and its velocity fluctuations decay as exp(-gamma t). getRigidBodyStates() reports the
synchronous velocity, whose mean is the drift at any gamma h under ExactFlow; a State holds the
stored velocity, whose mean under a constant force is documented (RigidLangevinIntegrator.h):
gamma h/(e^(gamma h)-1) of the drift under ExactFlow and BAOAB, 1 - gamma h/2 of it with
hydrodynamic interactions (whose friction step is the midpoint rule, decay (1-x/2)/(1+x/2) a step).
At zero temperature the steady state is reached exactly, so the means are checked to round-off.
"""
import numpy as np
import openmm as mm
import pytest

import rigidlangevin as rl

MASS, RADIUS, STEP, FORCE = 18.0, 0.15, 0.002, 50.0
FRICTION_PER_VISCOSITY = 6*np.pi*RADIUS  # Stokes, per unit viscosity


def pulled_spheres(platform, gamma_h, scheme, temperature=0.0, count=1, interactions=False, seed=1):
    """count spheres in single-particle bodies, 10 nm apart, each pulled along x by FORCE."""
    viscosity = gamma_h*MASS/(STEP*FRICTION_PER_VISCOSITY)
    system = mm.System()
    pull = mm.CustomExternalForce('-f*x')
    pull.addGlobalParameter('f', FORCE)
    integrator = rl.RigidLangevinIntegrator(temperature, viscosity, STEP)
    integrator.setScheme(scheme)
    integrator.setRandomNumberSeed(seed)
    for i in range(count):
        system.addParticle(MASS)
        pull.addParticle(i, [])
        integrator.addRigidBody([i])
        integrator.setParticleRadius(i, RADIUS)
    system.addForce(pull)
    integrator.setHydrodynamicInteractions(interactions)
    context = platform.context(system, integrator)
    context.setPositions([(10.0*i, 0, 0) for i in range(count)])
    return context, integrator


def drift_velocity(gamma_h):
    return FORCE/(MASS*gamma_h/STEP)


def body_velocities(integrator):
    return np.array(integrator.getRigidBodyStates()[2]._value)


def state_velocities(context):
    return context.getState(getVelocities=True).getVelocities(asNumpy=True)._value


def x_position(context):
    return context.getState(getPositions=True).getPositions(asNumpy=True)._value[0, 0]


CASES = [(rl.RigidLangevinIntegrator.ExactFlow, False), (rl.RigidLangevinIntegrator.BAOAB, False), (rl.RigidLangevinIntegrator.BAOAB, True)]


@pytest.mark.parametrize('scheme, interactions', CASES, ids=['ExactFlow', 'BAOAB', 'interactions'])
@pytest.mark.parametrize('gamma_h', [0.2, 2.0, 21.0])
def test_mean_velocities_under_a_constant_force(platform, gamma_h, scheme, interactions):
    context, integrator = pulled_spheres(platform, gamma_h, scheme, interactions=interactions)
    integrator.step(400)
    start = x_position(context)
    integrator.step(10)
    displacement_rate = (x_position(context)-start)/(10*STEP)
    drift = drift_velocity(gamma_h)
    x = gamma_h
    baoab = scheme == rl.RigidLangevinIntegrator.BAOAB and not interactions
    own_drift = drift*(0.5*x/np.tanh(0.5*x) if baoab else 1.0)
    stored = drift*((1-x/2) if interactions else x/np.expm1(x))
    assert displacement_rate == pytest.approx(own_drift, rel=1e-9)
    assert body_velocities(integrator)[0] == pytest.approx([own_drift, 0, 0], rel=1e-9, abs=1e-12)
    assert state_velocities(context)[0] == pytest.approx([stored, 0, 0], rel=1e-9, abs=1e-12)


def lag_one_correlation(series):
    """The one-step autocorrelation of a (steps, bodies) series, pooled over bodies."""
    d = series-series.mean(axis=0)
    return (d[1:]*d[:-1]).mean()/(d*d).mean()


@pytest.mark.parametrize('gamma_h', [0.5, 2.0])
def test_synchronous_velocity_fluctuations_decay_exactly_under_exact_flow(platform, gamma_h):
    # 64 spheres pulled at 300 K: the fluctuations of the reported velocity keep exp(-gamma h) from
    # one step to the next, and its mean the drift. 1500 steps: the correlation's standard error is
    # about 0.004, the mean's 2% of the thermal speed.
    context, integrator = pulled_spheres(platform, gamma_h, rl.RigidLangevinIntegrator.ExactFlow, temperature=300, count=64)
    integrator.step(100)
    samples = []
    for i in range(1500):
        integrator.step(1)
        samples.append(body_velocities(integrator)[:, 0])
    samples = np.array(samples)
    thermal = np.sqrt(mm.unit.MOLAR_GAS_CONSTANT_R.value_in_unit(mm.unit.kilojoule_per_mole/mm.unit.kelvin)*300/MASS)
    correlation = lag_one_correlation(samples)
    assert abs(correlation-np.exp(-gamma_h)) < 0.02
    assert abs(samples.mean()-drift_velocity(gamma_h)) < 0.1*thermal
    assert samples.std() == pytest.approx(thermal, rel=0.05)


def test_midpoint_friction_step_alternates_as_documented(platform):
    # With hydrodynamic interactions at gamma h = 21 the stored velocity decays by
    # (1 - x/2)/(1 + x/2) = -0.826 a step (the midpoint rule): documented, not exp(-21).
    context, integrator = pulled_spheres(platform, 21.0, rl.RigidLangevinIntegrator.BAOAB, temperature=300, count=1, interactions=True)
    integrator.step(10)
    samples = []
    for i in range(3000):
        integrator.step(1)
        samples.append(state_velocities(context)[0])
    correlation = lag_one_correlation(np.array(samples))
    assert correlation == pytest.approx((1-10.5)/(1+10.5), abs=0.03)
