"""Switching histograms over a (temperature, ramp rate) grid: :func:`switching_grid`.

Each grid point is one :func:`mbm.switching_currents` run on a seed of its own, drawn
from the grid's seed and the point's indices; the results are the histograms'
moments as an ``xarray.Dataset`` (xarray: ``pip install "mbm[dask]"``).  With
``chunks=`` the Dataset is dask-backed, one task per chunk of points
(:func:`_grid_block`, a module-level function a worker imports), on whatever Dask
scheduler is active; every point draws its own seed, so chunked and unchunked grids
are identical bit for bit.
"""

import numpy as np

from ..validate import check_real_array, check_rule_array
from .api import DT_DEFAULT, _check_count, _check_dt, switching_currents
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


def _grid_block(temps, rates, ii, jj, *, beta, n, options):
    """The points of one block of the grid (arrays broadcastable to its shape: the
    temperatures, ramp rates and the points' indices i, j); ``options``: ``seed``,
    ``omega``, ``dt``, ``gamma_start``, ``threads``.  Returns the moments, the switched
    counts and the points' seeds, each of the block's shape."""
    shape = np.broadcast_shapes(np.shape(temps), np.shape(rates), np.shape(ii), np.shape(jj))
    T, R, I, J = (np.broadcast_to(a, shape) for a in (temps, rates, ii, jj))
    out = {k: np.empty(shape) for k in MOMENTS}
    switched = np.empty(shape, dtype=np.int64)
    seeds = np.empty(shape, dtype=np.uint64)
    for idx in np.ndindex(*shape):
        seeds[idx] = point_seed(options["seed"], int(I[idx]), int(J[idx]))
        h = switching_currents(beta, float(T[idx]), float(R[idx]), n, omega=options["omega"], seed=int(seeds[idx]),
                               dt=options["dt"], gamma_start=options["gamma_start"], threads=options["threads"])
        for k in MOMENTS:
            out[k][idx] = getattr(h, k)
        switched[idx] = np.isfinite(h.currents).sum()
    return tuple(out[k] for k in MOMENTS) + (switched, seeds)


def _chunk_spec(chunks):
    # chunks as {dimension: length}: an int for both, or a dict (missing: whole).
    dims = ("temperature", "ramp_rate")
    spec = dict(chunks) if isinstance(chunks, dict) else {d: chunks for d in dims}
    if set(spec) - set(dims):
        raise ValueError(f"chunks names {sorted(set(spec) - set(dims))}, not dimensions of the grid {list(dims)}")
    for d in dims:
        c = spec.setdefault(d, -1)
        if isinstance(c, (bool, np.bool_)) or not isinstance(c, (int, np.integer)) or not (c >= 1 or c == -1):
            raise ValueError(f"chunks must be an int >= 1 (or -1: the whole dimension) per dimension, got {d}: {c!r}")
    return spec


def _grid_data(temps, rates, kw, chunks):
    """The grid's variables: one block here, or one dask task per chunk."""
    import xarray as xr

    dims = ("temperature", "ramp_rate")
    names = MOMENTS + ("switched", "seed")
    if chunks is None:
        block = _grid_block(temps[:, None], rates[None, :], np.arange(temps.size)[:, None],
                            np.arange(rates.size)[None, :], **kw)
        return {k: (dims, v) for k, v in zip(names, block)}
    spec = _chunk_spec(chunks)
    t = xr.DataArray(temps, dims=("temperature",)).chunk({"temperature": spec["temperature"]})
    i = xr.DataArray(np.arange(temps.size), dims=("temperature",)).chunk({"temperature": spec["temperature"]})
    r = xr.DataArray(rates, dims=("ramp_rate",)).chunk({"ramp_rate": spec["ramp_rate"]})
    j = xr.DataArray(np.arange(rates.size), dims=("ramp_rate",)).chunk({"ramp_rate": spec["ramp_rate"]})
    outs = xr.apply_ufunc(_grid_block, t, r, i, j, kwargs=kw, output_core_dims=[[]] * len(names),
                          dask="parallelized", output_dtypes=[float] * len(MOMENTS) + [np.int64, np.uint64])
    return {k: (o.transpose(*dims).dims, o.transpose(*dims).data) for k, o in zip(names, outs)}


def switching_grid(beta, temperature, ramp_rate, n, *, omega=1.0, seed=None, dt=DT_DEFAULT,
                   gamma_start=0.0, threads=None, chunks=None):
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
    chunks : int or dict, optional
        Make the Dataset dask-backed (lazy): chunks of points along ``temperature``
        and ``ramp_rate`` (an int for both, or {dimension: length}; -1 or missing:
        the whole dimension), each one task of the active Dask scheduler (threads
        here, or a ``dask.distributed`` cluster).  The same values as without.

    Returns
    -------
    xarray.Dataset
        Dimensions ``temperature`` and ``ramp_rate`` (their coordinates); variables
        ``mean``, ``width``, ``skewness``, ``kurtosis`` (as
        :class:`mbm.SwitchingHistogram`), ``switched`` (the finite currents' count)
        and ``seed`` (uint64); attributes ``beta``, ``omega``, ``n``, ``dt``,
        ``gamma_start``, ``seed``.

    Raises
    ------
    ValueError
        For an invalid argument, naming it (as :func:`mbm.switching_currents`, and
        axes that are not values > 0, ``chunks`` not a length per dimension); the
        first point's arguments are checked before anything runs.
    """
    import xarray as xr

    temps = _axis("temperature", temperature)
    rates = _axis("ramp_rate", ramp_rate)
    seed = resolve_seed(seed)
    n = _check_count(n)
    if chunks is not None:
        # Checked here (one scene of the first point), not on a worker at compute time.
        switching_currents(beta, float(temps[0]), float(rates[0]), 1, omega=omega, seed=0, dt=dt,
                           gamma_start=gamma_start, threads=threads)
    kw = dict(beta=beta, n=n, options=dict(seed=seed, omega=omega, dt=dt, gamma_start=gamma_start, threads=threads))
    data = _grid_data(temps, rates, kw, chunks)
    return xr.Dataset(data, coords={"temperature": temps, "ramp_rate": rates},
                      attrs={"beta": float(beta), "omega": float(omega), "n": int(n), "dt": _check_dt(dt, omega),
                             "gamma_start": float(gamma_start), "seed": seed})
