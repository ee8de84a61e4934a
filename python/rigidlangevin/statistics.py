"""Standard errors of simulation averages: of correlated time series (block averages) and of
independent estimates (replicas, groups of bodies); and the mean-square displacement and the
diffusion constant fitted to it."""
import math

import numpy as np


def block_error(values, blocks=10):
    """Standard error of the mean of a correlated series, from the spread of `blocks` block means.
    Blocks must be longer than the correlation time for the estimate to hold."""
    values = np.asarray(values)
    n = len(values)//blocks
    if n == 0:
        return float('nan')
    means = values[:n*blocks].reshape(blocks, n).mean(axis=1)
    return float(means.std(ddof=1)/math.sqrt(blocks))


def standard_error(values):
    """Standard error of the mean of independent estimates (scalars or arrays, along the first axis)."""
    values = np.asarray(values, dtype=float)
    if len(values) < 2:
        return float('nan')
    error = values.std(axis=0, ddof=1)/math.sqrt(len(values))
    return float(error) if error.ndim == 0 else error


def agreement_threshold(degrees_of_freedom, false_alarm=1e-3):
    """How many estimated standard errors two means may differ by: 4, or the two-sided Student-t
    quantile for `false_alarm` where the errors come from so few blocks or replicas that 4 would
    let a true agreement fail more often than that. Needs scipy."""
    from scipy.stats import t
    return max(4.0, float(t.ppf(1-false_alarm/2, degrees_of_freedom)))


def welch_degrees_of_freedom(error_a, dof_a, error_b, dof_b):
    """Welch-Satterthwaite degrees of freedom of the combined error of a difference of two means."""
    a, b = error_a**2, error_b**2
    return (a+b)**2/(a**2/dof_a+b**2/dof_b)


def mean_square_displacement(trajectory, lags):
    """Mean-square displacement at each lag (in frames) of a trajectory (frames x particles x 3,
    unwrapped: followed through any periodic wrapping), averaged over particles and every time origin."""
    trajectory = np.asarray(trajectory, dtype=float)
    n = len(trajectory)
    return np.array([np.mean(np.sum((trajectory[lag:]-trajectory[:n-lag])**2, axis=-1)) for lag in lags])


def diffusion_constant(trajectory, dt, lags):
    """D = slope/6 of the least-squares line through the mean-square displacement over `lags`
    (frames), with frames dt apart: in length^2 per unit of dt."""
    lags = np.asarray(lags)
    return float(np.polyfit(lags*dt, mean_square_displacement(trajectory, lags), 1)[0]/6)
