"""Observables of rigid molecules sampled from a running Context, the same for every integrator.

Every estimate is computed from particle positions, velocities and forces, so RigidLangevinIntegrator
and OpenMM's own integrators are measured the same way.
"""
import math

import numpy as np

KB = 0.0083144626181532  # kJ/(mol K)


class Molecules:
    """Rigid molecules: their particle indices (all with the same layout) and masses."""

    def __init__(self, indices, masses):
        self.indices = np.asarray(indices)          # (molecules, sites)
        self.masses = np.asarray(masses, dtype=float)  # (sites,)
        self.mass = self.masses.sum()

    def centers(self, x):
        return np.einsum('s,msk->mk', self.masses, x[self.indices])/self.mass

    def rigid_motion(self, x, v):
        """Centre-of-mass velocities, angular momenta and inertia tensors (lab frame) of each molecule."""
        r = x[self.indices]-self.centers(x)[:, None, :]
        vel = v[self.indices]
        V = np.einsum('s,msk->mk', self.masses, vel)/self.mass
        L = np.einsum('s,msk->mk', self.masses, np.cross(r, vel-V[:, None, :]))
        r2 = np.einsum('msk,msk->ms', r, r)
        I = np.einsum('s,ms,jk->mjk', self.masses, r2, np.eye(3))-np.einsum('s,msj,msk->mjk', self.masses, r, r)
        return V, L, I


def kinetic_temperatures(molecules, x, v, remove_com=True):
    """Translational and rotational temperatures of rigid molecules (3 and 3 degrees of freedom each;
    the centre of mass of the whole system is left out if a CMMotionRemover acts)."""
    V, L, I = molecules.rigid_motion(x, v)
    n = len(V)
    translational = 0.5*molecules.mass*np.sum(V**2)
    dof_t = 3*n
    if remove_com:
        P = V.mean(axis=0)
        translational -= 0.5*molecules.mass*n*np.dot(P, P)
        dof_t -= 3
    omega = np.linalg.solve(I, L[..., None])[..., 0]
    rotational = 0.5*np.sum(L*omega)
    return 2*translational/(dof_t*KB), 2*rotational/(3*n*KB)


def switched_lennard_jones_laplacian(r, sigma, epsilon, switch, cutoff):
    """Laplacian phi'' + 2 phi'/r of the Lennard-Jones pair potential times OpenMM's switching
    function S(x) = 1 - 10x^3 + 15x^4 - 6x^5, x = (r - switch)/(cutoff - switch)."""
    sr6 = (sigma/r)**6
    phi = 4*epsilon*(sr6*sr6-sr6)
    d1 = 4*epsilon*(-12*sr6*sr6+6*sr6)/r
    d2 = 4*epsilon*(156*sr6*sr6-42*sr6)/r**2
    x = np.clip((r-switch)/(cutoff-switch), 0, 1)
    w = cutoff-switch
    s = 1-10*x**3+15*x**4-6*x**5
    s1 = (-30*x**2+60*x**3-30*x**4)/w
    s2 = (-60*x+180*x**2-120*x**3)/w**2
    f = phi*s
    f1 = d1*s+phi*s1
    f2 = d2*s+2*d1*s1+phi*s2
    lap = f2+2*f1/r
    return np.where(r < cutoff, lap, 0.0)


def pair_distances(points, box):
    """Minimum-image distances between all pairs of points in a rectangular box (i < j)."""
    d = points[:, None, :]-points[None, :, :]
    d -= box*np.round(d/box)
    r = np.sqrt(np.sum(d**2, axis=-1))
    i, j = np.triu_indices(len(points), 1)
    return r[i, j]


def configurational_temperature_terms(molecules, forces, oxygens, box, sigma, epsilon, switch, cutoff):
    """The two sums of the translational configurational temperature kT = <sum |F_A|^2>/<sum lap_A U>.
    Translating a neutral molecule leaves the (harmonic) Coulomb part's Laplacian zero, so only the
    switched O-O Lennard-Jones term contributes to it."""
    f = np.einsum('msk->mk', forces[molecules.indices])
    r = pair_distances(oxygens, box)
    laplacian = 2*np.sum(switched_lennard_jones_laplacian(r, sigma, epsilon, switch, cutoff))  # each pair counts for both molecules
    return np.sum(f**2), laplacian


def radial_distribution(points, box, r_max, bins):
    r = pair_distances(points, box)
    counts, edges = np.histogram(r, bins=bins, range=(0, r_max))
    n = len(points)
    shell = 4*math.pi/3*(edges[1:]**3-edges[:-1]**3)
    ideal = shell*n*(n-1)/2/np.prod(box)
    return counts/ideal


def dipole_directions(x, molecules):
    """Unit vectors from the first site (oxygen) to the midpoint of the next two (hydrogens)."""
    o = x[molecules.indices[:, 0]]
    mid = 0.5*(x[molecules.indices[:, 1]]+x[molecules.indices[:, 2]])
    u = mid-o
    return u/np.linalg.norm(u, axis=1)[:, None]


def time_correlation(series, lag, f):
    """Average over time origins and molecules of f(a, b) for samples lag apart."""
    values = [np.mean(f(series[i], series[i+lag])) for i in range(len(series)-lag)]
    return float(np.mean(values))


def diffusion_from_msd(centers, dt, lag1, lag2):
    """Translational diffusion from the slope of the mean square displacement between two lags."""
    msd = lambda lag: time_correlation(centers, lag, lambda a, b: np.sum((b-a)**2, axis=1))
    return (msd(lag2)-msd(lag1))/(6*(lag2-lag1)*dt)


def correlation_time(directions, dt, max_lag):
    """Integral of <u(t).u(0)> up to where it decays to 1/e^2, plus the exponential tail beyond."""
    values = [1.0]
    for lag in range(1, max_lag+1):
        values.append(time_correlation(directions, lag, lambda a, b: np.sum(a*b, axis=1)))
        if values[-1] < math.exp(-2):
            break
    values = np.array(values)
    integral = np.trapezoid(values, dx=dt)
    if values[-1] > 0 and len(values) > 2 and values[-2] > values[-1]:
        rate = math.log(values[-2]/values[-1])/dt
        integral += values[-1]/rate
    return integral


def velocity_autocorrelation(velocities, lags):
    """Normalized <V(t).V(0)> of molecule centre-of-mass velocities at the given lags (in samples)."""
    norm = time_correlation(velocities, 0, lambda a, b: np.sum(a*b, axis=1))
    return np.array([time_correlation(velocities, lag, lambda a, b: np.sum(a*b, axis=1))/norm for lag in lags])
