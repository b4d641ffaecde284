"""Switching histograms over a (temperature, ramp rate) grid: :func:`switching_grid`.

Each grid point is one :func:`mbm.switching_currents` run on a seed of its own, drawn
from the grid's seed and the point's indices; the results are the histograms'
moments as an ``xarray.Dataset`` (xarray: ``pip install "mbm[dask]"``).
"""

import numpy as np

from ..validate import check_real_array, check_rule_array
from .api import DT_DEFAULT, switching_currents
from .rng import resolve_seed

__all__ = ["switching_grid"]

# The Dataset's per-point variables, in the order of the moments of SwitchingHistogram.
MOMENTS = ("mean", "width", "skewness", "kurtosis")


def _axis(name, value):
    # A 1-D array of values > 0 (a scalar is a grid of one), none repeated.
    a = check_rule_array(name, np.atleast_1d(check_real_array(name, value)), (">0", "> 0"))
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{name} must be a scalar or a non-empty 1-D array of values > 0, got shape {a.shape}")
    return a.astype(float)


def point_seed(seed, i, j):
    """The seed of grid point (i, j) under the grid's ``seed``: a 64-bit word of
    numpy's SeedSequence((seed, i, j)) (independent streams for distinct points)."""
    return int(np.random.SeedSequence((seed, i, j)).generate_state(1, np.uint64)[0])


def switching_grid(beta, temperature, ramp_rate, n, *, omega=1.0, seed=None, dt=DT_DEFAULT,
                   gamma_start=0.0, threads=None):
    r"""Switching-current histograms of :func:`mbm.switching_currents` over temperature × ramp rate.

    Parameters
    ----------
    beta : float
        Damping, > 0.
    temperature, ramp_rate : float or array_like
        The grid's axes: each a value or a 1-D array of values > 0.
    n : int
        Scenes per grid point, ≥ 1.
    omega : float, optional
        As :func:`mbm.switching_currents`.
    seed : int, optional
        The grid's seed in [0, 2^64 − 1] (None draws one); point (i, j) runs on
        :func:`point_seed` (seed, i, j), stored as the variable ``seed``.
    dt, gamma_start, threads : optional
        As :func:`mbm.switching_currents`.

    Returns
    -------
    xarray.Dataset
        Dimensions ``temperature`` and ``ramp_rate`` (their coordinates); variables
        ``mean``, ``width``, ``skewness``, ``kurtosis`` (as
        :class:`mbm.SwitchingHistogram`), ``switched`` (the finite currents' count)
        and ``seed`` (uint64); attributes ``beta``, ``omega``, ``n``, ``dt``,
        ``gamma_start``, ``seed``.
    """
    import xarray as xr

    temps = _axis("temperature", temperature)
    rates = _axis("ramp_rate", ramp_rate)
    seed = resolve_seed(seed)
    shape = (temps.size, rates.size)
    out = {k: np.empty(shape) for k in MOMENTS}
    switched = np.empty(shape, dtype=np.int64)
    seeds = np.empty(shape, dtype=np.uint64)
    for i, temp in enumerate(temps):
        for j, rate in enumerate(rates):
            seeds[i, j] = point_seed(seed, i, j)
            h = switching_currents(beta, temp, rate, n, omega=omega, seed=int(seeds[i, j]), dt=dt,
                                   gamma_start=gamma_start, threads=threads)
            for k in MOMENTS:
                out[k][i, j] = getattr(h, k)
            switched[i, j] = np.isfinite(h.currents).sum()
    dims = ("temperature", "ramp_rate")
    data = {k: (dims, v) for k, v in out.items()}
    data["switched"] = (dims, switched)
    data["seed"] = (dims, seeds)
    return xr.Dataset(data, coords={"temperature": temps, "ramp_rate": rates},
                      attrs={"beta": float(beta), "omega": float(omega), "n": int(n), "dt": float(h.dt),
                             "gamma_start": float(gamma_start), "seed": seed})
