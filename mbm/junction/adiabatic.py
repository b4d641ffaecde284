"""The adiabatic protocol of :func:`mbm.sweep`: the bias axis followed as an experiment does.

With ``protocol="adiabatic"`` the scenes at the k-th bias γ_k start from the state at t1
of the scene at γ_{k−1} with the same other parameters (the first from θ₀, θ'₀): the
bias is stepped slowly along ``gamma`` in the order given, each step settling over
``t_span``, so a map shows the hysteresis an I–V measurement shows (the running branch
followed down past the switching current, the locked one up past the retrapping
current).  For a sweep down, give ``gamma`` in decreasing order.

The carried state is (θ(t1) modulo 2π into [−π, π], θ'(t1)): the same point of the
pendulum's phase space, with θ kept small.  A scene whose run fails (status ≠ 0) has
no settled state; the next bias starts again from θ₀, θ'₀, as the independent protocol
does.

Each chain (one combination of the other parameters) runs its biases in sequence; the
chains of a block run together, one :func:`mbm.solve_batch` call per bias.  With
``chunks=`` each Dask task runs the whole bias axis of its chunk of the other
dimensions, so chunked and unchunked adiabatic sweeps agree bit for bit.
"""

import math

import numpy as np
import xarray as xr

from .sweeps import _dtype, _solve_block

__all__ = ["solve_chain", "adiabatic_local", "adiabatic_chunked"]

_TWO_PI = 2.0 * math.pi


def _series(variable):
    return variable in ("theta", "theta_dot")


def _step_plan(variables, times, t1):
    """What one bias step asks its batch call for: the variables and times the user asked
    for, plus θ(t1), θ'(t1) (the carried state) where they are missing."""
    if _series(variables[0]):
        extra_time = times[-1] != t1
        step_times = np.append(times, t1) if extra_time else times
        return variables, step_times, extra_time
    step_vars = variables
    if "theta_final" not in variables:
        step_vars = variables[:-1] + ("theta_final", "theta_dot_final", "status")
    return step_vars, times, False


def solve_chain(*arrays, names, fixed, t_span, times, variables, options, gamma, batch=None,
                on_step=None):
    """Solve a block of chains along the bias axis ``gamma``, each bias from the last state.

    Parameters
    ----------
    *arrays : ndarray
        The other parameters given as arrays, in the order of ``names``, broadcastable
        to the block's shape.
    names : tuple of str
        The parameter each of ``arrays`` is (never ``"gamma"``).
    fixed, t_span, times, variables, options
        As for :func:`mbm.junction.sweeps._solve_block`.
    gamma : ndarray, shape (k,)
        The biases, in the order the chains follow them.
    batch : int, optional
        Chains per batch call (default: the whole block in one call per bias).
    on_step : callable, optional
        Called with the number of scenes done after each batch call (a progress bar).

    Returns
    -------
    tuple of ndarray
        One per variable, of shape block + (k,) (time series: plus (m,)).
    """
    arrays = [np.asarray(a, dtype=float) for a in arrays]
    shape = np.broadcast_shapes(*(a.shape for a in arrays)) if arrays else ()
    n = math.prod(shape)
    gamma = np.asarray(gamma, dtype=float).reshape(-1)
    m = times.size
    out = [np.empty((n, gamma.size) + ((m,) if _series(v) else ()), dtype=_dtype(v)) for v in variables]
    if n == 0:
        return tuple(o.reshape(shape + o.shape[1:]) for o in out)
    given = {k: np.broadcast_to(a, shape).reshape(-1) for k, a in zip(names, arrays)}
    start = np.stack([given.get(k, np.full(n, fixed.get(k, 0.0))) for k in ("theta0", "theta_dot0")])
    others = tuple(k for k in names if k not in ("theta0", "theta_dot0"))
    step_names = others + ("gamma", "theta0", "theta_dot0")
    step_vars, step_times, extra_time = _step_plan(tuple(variables), times, t_span[1])
    state = start.copy()
    batch = n if batch is None else int(batch)
    for k, g in enumerate(gamma):
        for lo in range(0, n, batch):
            hi = min(lo + batch, n)
            cols = [given[name][lo:hi] for name in others] + [np.full(hi - lo, g), state[0, lo:hi], state[1, lo:hi]]
            found = dict(zip(step_vars, _solve_block(*cols, names=step_names, fixed=fixed, t_span=t_span,
                                                     times=step_times, variables=step_vars, options=options)))
            if _series(variables[0]):
                end = np.stack([found["theta"][:, -1], found["theta_dot"][:, -1]])
                if extra_time:
                    found = {v: (a[:, :-1] if _series(v) else a) for v, a in found.items()}
            else:
                end = np.stack([found["theta_final"], found["theta_dot_final"]])
            for o, v in zip(out, variables):
                o[lo:hi, k] = found[v]
            settled = (found["status"] == 0) & np.all(np.isfinite(end), axis=0)
            wrapped = end[0] - _TWO_PI * np.rint(end[0] / _TWO_PI)
            state[0, lo:hi] = np.where(settled, wrapped, start[0, lo:hi])
            state[1, lo:hi] = np.where(settled, end[1], start[1, lo:hi])
            if on_step is not None:
                on_step(hi - lo)
    return tuple(o.reshape(shape + o.shape[1:]) for o in out)


def adiabatic_local(values, dims, kw, bar, batch):
    """All chains in this process; the variables over ``dims`` (+ time), as ``sweep``'s paths return."""
    others = tuple(d for d in dims if d != "gamma")
    other_shape = tuple(values[d].size for d in others)
    n = math.prod(other_shape)
    idx = np.unravel_index(np.arange(n), other_shape) if others else ()
    cols = [values[d][i] for d, i in zip(others, idx)]
    blocks = solve_chain(*cols, names=others, gamma=values["gamma"], batch=batch,
                         on_step=None if bar is None else bar.update, **kw)
    axis = dims.index("gamma")
    data = {}
    for v, a in zip(kw["variables"], blocks):
        a = a.reshape(other_shape + (values["gamma"].size,) + ((kw["times"].size,) if _series(v) else ()))
        data[v] = (dims + (("time",) if _series(v) else ()), np.moveaxis(a, len(others), axis))
    return data


def adiabatic_chunked(values, dims, kw, chunks):
    """A lazy dask-backed computation: one :func:`solve_chain` task per chunk of the other dimensions."""
    others = tuple(d for d in dims if d != "gamma")
    inputs = [xr.DataArray(values[d], dims=(d,)).chunk({d: chunks[d]}) for d in others]
    variables = kw["variables"]
    m = kw["times"].size
    outs = xr.apply_ufunc(
        solve_chain, *inputs,
        kwargs=dict(kw, names=others, gamma=values["gamma"]),
        input_core_dims=[[] for _ in others],
        output_core_dims=[["gamma", "time"] if _series(v) else ["gamma"] for v in variables],
        dask="parallelized",
        output_dtypes=[_dtype(v) for v in variables],
        dask_gufunc_kwargs={"output_sizes": {"gamma": values["gamma"].size,
                                             **({"time": m} if _series(variables[0]) else {})}},
    )
    data = {}
    for v, o in zip(variables, outs):
        o = o.transpose(*(dims + (("time",) if _series(v) else ())))
        data[v] = (o.dims, o.data)
    return data
