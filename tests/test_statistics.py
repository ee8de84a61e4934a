"""rigidlangevin.statistics: the mean-square displacement and the diffusion constant fitted to it
(the examples' estimator; tests/test_examples.py checks D on wrapped, drifting Brownian walks)."""
import numpy as np

from rigidlangevin.statistics import diffusion_constant, mean_square_displacement


def test_mean_square_displacement_of_ballistic_motion_is_exact():
    # x = x0 + v t: every origin gives |v|^2 lag^2, so the average over particles is exact (a
    # displacement taken over the wrong axis, or origins that run off the end, would not be).
    rng = np.random.default_rng(2)
    x0, v = rng.normal(size=(7, 3)), rng.normal(size=(7, 3))
    trajectory = x0[None]+v[None]*np.arange(20)[:, None, None]
    lags = [0, 1, 5, 19]
    expected = np.mean(np.sum(v**2, axis=1))*np.array(lags)**2
    assert np.allclose(mean_square_displacement(trajectory, lags), expected, rtol=1e-12, atol=1e-12)


def test_diffusion_constant_of_brownian_walks():
    # 4096 walkers with D = 0.5 in steps of dt = 0.1: the fit over lags 1-20 gives D back within
    # 4 standard errors of the spread of 8 independent sets (about 0.5 %: a 5 % error fails).
    rng = np.random.default_rng(5)
    d_true, dt = 0.5, 0.1
    estimates = [diffusion_constant(np.cumsum(rng.normal(scale=np.sqrt(2*d_true*dt), size=(200, 512, 3)), axis=0), dt, range(1, 21))
                 for _ in range(8)]
    mean, error = np.mean(estimates), np.std(estimates, ddof=1)/np.sqrt(len(estimates))
    assert error < 0.01*d_true
    assert abs(mean-d_true) < 4*error, (mean, error)
