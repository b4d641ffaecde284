"""Parameter sweeps: outer-product grids of scenes as labelled ``xarray.Dataset`` results.

:func:`sweep` runs every scene of a grid over (β, γ, ω, θ₀, θ'₀) through the compiled
batch solver (:func:`mbm.solve_batch`) and returns an ``xarray.Dataset``: each
parameter given as a 1-D array is a dimension with its coordinate, the scalars are
attributes, and every scene carries its ``status``.  ``reduce=`` keeps only a few
numbers per scene (final state, mean velocity, winding count, regime), computed from
a batch call with only the two output times they need, so a large grid never holds
an (N, 2, m) array.

With ``chunks=`` the Dataset is dask-backed, each chunk one :func:`mbm.solve_batch`
call, and computes on whatever Dask scheduler is active: threads in this process or
a ``dask.distributed`` cluster.  The function shipped to the workers,
:func:`_solve_block`, is a module-level function of this module, so a worker imports
``mbm`` and loads the cached (``cache=True``) kernels instead of compiling them.
Every scene is an independent run, so chunked and unchunked sweeps are identical bit
for bit.

xarray is needed (``pip install "mbm[dask]"``); Dask only for ``chunks=``.

Reductions
----------
``reduce=`` of :func:`sweep` keeps only these per scene, from the batch call's two
output times t_m = t0 + (t1 − t0)/2 and t1:

``"final_state"``
    ``theta_final``, ``theta_dot_final``: θ(t1), θ'(t1).
``"mean_velocity"``
    ``mean_velocity``: exact where the run reached a regime (``mbm.solve``'s
    ``regime``): 2π/T_c on the running limit cycle, 0 once locked, (p/q)Ω
    once phase-locked to a drive.  Elsewhere
    (θ(t1) − θ(t_m)) / (t1 − t_m); for t0 = 0, (θ(T) − θ(T/2)) / (T/2): two
    samples, not an average over a cycle, off by at most 2·(swing of
    θ − ⟨θ'⟩t) / (t1 − t_m), i.e. O(P/T) for a cycle of period P.
``"winding"``
    ``winding`` = rint((θ(t1) − θ₀) / 2π): the net number of 2π turns at the end,
    rounded to the nearest integer (a locked scene: the wells it moved by).
    Float (integer values), so that failed scenes can be NaN.
``"regime"``
    ``regime``: ``"running"`` where ``|θ(t1) − θ(t_m)|`` ≥ :data:`REGIME_TURNS` · 2π
    (the mean velocity ≥ 2π/(t1 − t_m) in magnitude), else ``"locked"``;
    ``"failed"`` where the status is not 0.  Misreads a running scene whose
    period exceeds (t1 − t0)/2 and a scene still slipping wells after t_m.
"""

import math
import sys
import threading

import numpy as np

from ..status import STATUS_OK
from .. import status as _status
from ..validate import (
    DEFAULT_MAX_WINDOWS,
    check_drive,
    check_max_windows,
    check_positive,
    check_real_array,
    check_rule_array,
    check_span,
    check_t_eval,
    check_tolerances,
    keywords_named,
)
from ..approximants import Approximant, get_approximant
from ..frontends.batch import solve_batch
from ..model import Pendulum
from .progress import progress_bar

try:
    import xarray as xr
except ImportError as exc:  # pragma: no cover - exercised only without the extra
    raise ImportError(
        'mbm.sweep needs xarray (and dask for chunks=): pip install "mbm[dask]"'
    ) from exc

__all__ = [
    "sweep",
    "PARAMETERS",
    "DRIVE_PARAMETERS",
    "REDUCTIONS",
    "LOCAL_BATCH",
    "REGIME_TURNS",
    "STATUS_FLAGS",
    "status_message",
    "PROTOCOLS",
]

#: The sweep's parameters, in the order their dimensions take.
PARAMETERS = ("beta", "gamma", "omega", "theta0", "theta_dot0")
#: The AC drive's parameters (:class:`mbm.Pendulum`), dimensions after :data:`PARAMETERS`;
#: a sweep without a drive (all three 0, the default) has neither their dimensions nor
#: their attributes.
DRIVE_PARAMETERS = ("drive_amplitude", "drive_frequency", "drive_phase")

#: The names ``reduce=`` accepts, and the variables each adds to the Dataset.
REDUCTIONS = {
    "final_state": ("theta_final", "theta_dot_final"),
    "mean_velocity": ("mean_velocity",),
    "winding": ("winding",),
    "regime": ("regime",),
}

# Scenes per solve_batch call on the local (unchunked) path: the progress bar moves
# once a batch, and the run records (mbm.core.record.RUN.itemsize bytes a scene) and outputs of one call stay
# bounded by the batch.  4096 scenes of t ≤ 1000 are ~0.1–0.5 s on 2 cores (so the bar
# moves), while a call's fixed cost (~0.2 ms) stays below 0.1 % of it.
LOCAL_BATCH = 4096
# With progress=True the batches shrink so that the bar moves at least every 1/PROGRESS_STEPS
# of the grid (2 %)...
PROGRESS_STEPS = 50
# ...but not below PROGRESS_MIN_BATCH scenes, where a call's fixed cost (~0.2 ms) would
# start to show beside its scenes (~1 ms each at t ≤ 1000).
PROGRESS_MIN_BATCH = 16

# Turns of θ over the second half of the span that make a scene "running": a scene
# locked in one well of the tilted washboard stays between two neighbouring maxima of
# the potential, so its θ moves less than 2π; on a running cycle θ' > 0 and θ gains
# 2π every period, so the second half gains ≥ 2π once the period is ≤ half the span.
REGIME_TURNS = 1.0

# The regime labels (fixed-width strings; "failed" where the scene's status ≠ 0).
REGIME_LOCKED = "locked"
REGIME_RUNNING = "running"
REGIME_FAILED = "failed"
_REGIME_DTYPE = np.dtype("<U7")

# The CF flag_meanings words of the statuses: mbm.status's table.
STATUS_FLAGS = _status.STATUS_FLAGS

# status as int32: the netCDF-3 classic format (scipy's writer, no extra package)
# has no 64-bit integers, and the codes are small.
_STATUS_DTYPE = np.dtype(np.int32)

# One solve_batch at a time per process: each call already runs on every core (numba's
# threads), two at once only oversubscribe them, and numba's "workqueue" threading
# layer (its fallback without OpenMP or TBB) aborts on concurrent parallel launches.
_BATCH_LOCK = threading.Lock()

_TWO_PI = 2.0 * math.pi


status_message = _status.status_message


# --------------------------------------------------------------------------- validation


def _check_parameter(name, value):
    """A parameter as a float scalar or a non-empty finite 1-D float array (the rules of
    :class:`mbm.Pendulum`, mbm.validate: TypeError for what is not real numbers)."""
    arr = check_real_array(name, value)
    if arr.ndim > 1:
        raise ValueError(f"{name} must be a scalar or a 1-D array (one dimension of the grid), got shape {arr.shape}")
    if arr.ndim == 1 and arr.size == 0:
        raise ValueError(f"{name} must not be an empty array")
    check_rule_array(name, arr)
    return float(arr) if arr.ndim == 0 else np.ascontiguousarray(arr)


def _check_reduce(reduce):
    """``reduce`` as a tuple of unique names of :data:`REDUCTIONS`, or None."""
    if reduce is None:
        return None
    names = [reduce] if isinstance(reduce, str) else reduce
    try:
        names = list(names)
    except TypeError:
        raise ValueError(f"reduce must be a name or a list of names of {sorted(REDUCTIONS)}, got {reduce!r}") from None
    if not names:
        raise ValueError(f"reduce must name at least one of {sorted(REDUCTIONS)} (or be None), got {reduce!r}")
    for r in names:
        if not isinstance(r, str) or r not in REDUCTIONS:
            raise ValueError(f"reduce must name reductions of {sorted(REDUCTIONS)}, got {r!r}")
    return tuple(dict.fromkeys(names))


def _check_chunks(chunks, dims):
    """``chunks`` as {dim: chunk length} over the parameter dimensions, or None."""
    if chunks is None:
        return None
    if not dims:
        raise ValueError("chunks needs a parameter given as a 1-D array (no dimension to chunk)")
    if isinstance(chunks, dict):
        unknown = set(chunks) - set(dims)
        if unknown:
            raise ValueError(f"chunks names {sorted(unknown)}, not parameter dimensions of this sweep {list(dims)}")
        spec = {d: chunks.get(d, -1) for d in dims}
    else:
        spec = {d: chunks for d in dims}
    for d, c in spec.items():
        if isinstance(c, (bool, np.bool_)) or not isinstance(c, (int, np.integer)) or not (c >= 1 or c == -1):
            raise ValueError(f"chunks must be an int >= 1 (or -1: the whole dimension) per dimension, got {d}: {c!r}")
        spec[d] = int(c)
    return spec


def _check_approximant(approximant, tau, t_span, rtol, atol, max_windows, models, drive=None):
    """Validate the run options now (not on a worker at compute time).

    A zero-length probe run of one scene checks the name, the compiled kernel, ``tau``,
    the tolerances and ``max_windows`` exactly as :func:`mbm.solve_batch` will; an
    approximant that restricts its model (e.g. ``"belendez"``: β = γ = 0) is checked
    against every distinct (β, γ, ω) of the grid, and one that cannot integrate a drive
    against the grid's drive (``drive``: A, Ω, φ as given, or None).
    """
    if not isinstance(approximant, str):
        raise ValueError(f"approximant must be the name of a compiled approximant or 'auto', got {approximant!r}")
    b, g, w = (np.atleast_1d(m)[:1] for m in models)
    solve_batch(b, g, w, [0.0, 0.0], (t_span[0], t_span[0]), [t_span[0]], rtol=rtol, atol=atol,
                approximant=approximant, tau=tau, max_windows=max_windows)
    if approximant != "auto":
        ap = get_approximant(approximant)
        if drive is not None and np.any(np.atleast_1d(drive[0]) != 0.0):
            amp = np.atleast_1d(drive[0])
            ap.check_drive(Pendulum(1.0, 0.0, 1.0, float(amp[np.flatnonzero(amp != 0.0)[0]]), 1.0))
        if type(ap).check_model is not Approximant.check_model:
            for bb in np.unique(np.atleast_1d(models[0])):
                for gg in np.unique(np.atleast_1d(models[1])):
                    for ww in np.unique(np.atleast_1d(models[2])):
                        ap.check_model(Pendulum(float(bb), float(gg), float(ww)))


# ------------------------------------------------------------------------ the kernel call


def _variables(reduce):
    """The Dataset variables of a sweep, ``status`` last."""
    if reduce is None:
        names = ["theta", "theta_dot"]
    else:
        names = [v for r in reduce for v in REDUCTIONS[r]]
    return tuple(names) + ("status",)


def _output_times(reduce, t_span, t_eval):
    """The output times of the batch call: ``t_eval``, or the reductions' [t_mid, t1] / [t1]."""
    if reduce is None:
        return t_eval
    t0, t1 = t_span
    if "mean_velocity" in reduce or "regime" in reduce:
        return np.array([t0 + 0.5 * (t1 - t0), t1])
    return np.array([t1])


def _dtype(var):
    if var == "status":
        return _STATUS_DTYPE
    if var == "regime":
        return _REGIME_DTYPE
    return np.dtype(float)


def _solve_block(*arrays, names, fixed, t_span, times, variables, options):
    """Solve one block of scenes with one :func:`mbm.solve_batch` call.

    The function Dask ships to its workers (module-level, so a worker imports it and
    loads the cached kernels), and the one the local path calls once per batch: the
    same code for every path, hence identical results.

    Parameters
    ----------
    *arrays : ndarray
        The parameters given as arrays, in the order of ``names``, broadcastable to the
        block's shape (xarray passes size-1 axes for the dimensions an array lacks).
    names : tuple of str
        The parameter each of ``arrays`` is.
    fixed : dict
        The scalar parameters, name → float.
    t_span : (float, float)
        The time span.
    times : ndarray, shape (m,)
        The output times of the batch call.
    variables : tuple of str
        The variables to return (see :func:`_variables`), ``status`` last.
    options : dict
        ``rtol``, ``atol``, ``approximant``, ``tau``, ``max_windows`` of solve_batch.

    Returns
    -------
    tuple of ndarray
        One per variable, of the block's shape (time series: plus (m,)).
    """
    arrays = [np.asarray(a, dtype=float) for a in arrays]
    shape = np.broadcast_shapes(*(a.shape for a in arrays)) if arrays else ()
    n = math.prod(shape)
    m = times.size
    if n == 0:  # an empty block (e.g. a meta probe): nothing to solve
        return tuple(np.empty(shape + ((m,) if v in ("theta", "theta_dot") else ()), dtype=_dtype(v))
                     for v in variables)
    given = dict(zip(names, (np.broadcast_to(a, shape).reshape(-1) for a in arrays)))
    p = {k: given[k] if k in given else np.full(n, fixed[k]) for k in PARAMETERS}
    drive = {k: given[k] if k in given else np.full(n, fixed[k]) for k in DRIVE_PARAMETERS
             if k in given or k in fixed}
    y0 = np.stack([p["theta0"], p["theta_dot0"]], axis=1)
    with _BATCH_LOCK:
        res = solve_batch(p["beta"], p["gamma"], p["omega"], y0, t_span, times, **options, **drive)
    status = res.status
    ok = status == STATUS_OK
    y = res.y
    t0, t1 = t_span
    found = {}
    if "theta" in variables:
        found["theta"], found["theta_dot"] = y[:, 0, :], y[:, 1, :]
    else:
        theta1 = np.where(ok, y[:, 0, -1], np.nan)
        if "theta_final" in variables:
            found["theta_final"] = theta1
            found["theta_dot_final"] = np.where(ok, y[:, 1, -1], np.nan)
        if "mean_velocity" in variables or "regime" in variables:
            t_mid = times[0]
            advance = theta1 - y[:, 0, 0]
            if "mean_velocity" in variables:
                # Exact where the run switched to a regime (2π/T_c on the running cycle,
                # 0 once locked, (p/q)Ω phase-locked to a drive); else the two samples' estimate.
                exact = np.isfinite(res.mean_velocity) & ok
                found["mean_velocity"] = np.where(exact, res.mean_velocity, advance / (t1 - t_mid))
            if "regime" in variables:
                running = np.abs(advance) >= REGIME_TURNS * _TWO_PI
                regime = np.where(running, REGIME_RUNNING, REGIME_LOCKED).astype(_REGIME_DTYPE)
                regime[~ok] = REGIME_FAILED
                found["regime"] = regime
        if "winding" in variables:
            found["winding"] = np.rint((theta1 - p["theta0"]) / _TWO_PI) + 0.0  # + 0.0: no -0.0
    found["status"] = status.astype(_STATUS_DTYPE)
    return tuple(
        found[v].reshape(shape + ((m,) if v in ("theta", "theta_dot") else ())) for v in variables
    )


# ------------------------------------------------------------------------------ progress


def _batch_size(n, progress):
    """Scenes per solve_batch call of the local path: :data:`LOCAL_BATCH`, or with a bar
    small enough that it moves every 1/:data:`PROGRESS_STEPS` of the grid."""
    if not progress:
        return LOCAL_BATCH
    return min(LOCAL_BATCH, max(PROGRESS_MIN_BATCH, -(-n // PROGRESS_STEPS)))


# ------------------------------------------------------------------------------- paths


def _local(values, dims, kw, progress):
    """All scenes in this process, LOCAL_BATCH scenes per solve_batch call."""
    shape = tuple(values[d].size for d in dims)
    n = math.prod(shape)
    m = kw["times"].size
    variables = kw["variables"]
    flat = {v: np.empty((n, m) if v in ("theta", "theta_dot") else (n,), dtype=_dtype(v)) for v in variables}
    bar = progress_bar(n, "sweep", unit="scene") if progress else None
    batch = _batch_size(n, progress)
    try:
        for start in range(0, n, batch):
            stop = min(start + batch, n)
            idx = np.unravel_index(np.arange(start, stop), shape) if dims else ()
            cols = [values[d][i] for d, i in zip(dims, idx)]
            block = _solve_block(*cols, **kw)
            for v, a in zip(variables, block):
                flat[v][start:stop] = a.reshape(flat[v][start:stop].shape)
            if bar is not None:
                bar.update(stop - start)
    finally:
        if bar is not None:
            bar.close()
    return {
        v: (dims + (("time",) if v in ("theta", "theta_dot") else ()),
            a.reshape(shape + ((m,) if v in ("theta", "theta_dot") else ())))
        for v, a in flat.items()
    }


def _chunked(values, dims, kw, chunks):
    """A lazy dask-backed computation: one _solve_block task per chunk."""
    try:
        import dask.array  # noqa: F401  (xarray's dask backend)
    except ImportError as exc:  # pragma: no cover - exercised only without the extra
        raise ImportError('chunks= needs dask: pip install "mbm[dask]"') from exc
    inputs = [xr.DataArray(values[d], dims=(d,)).chunk({d: chunks[d]}) for d in dims]
    variables = kw["variables"]
    m = kw["times"].size
    core = [["time"] if v in ("theta", "theta_dot") else [] for v in variables]
    outs = xr.apply_ufunc(
        _solve_block, *inputs,
        kwargs=kw,
        input_core_dims=[[] for _ in dims],
        output_core_dims=core,
        dask="parallelized",
        output_dtypes=[_dtype(v) for v in variables],
        dask_gufunc_kwargs={"output_sizes": {"time": m}} if any(core) else {},
    )
    # apply_ufunc orders the dimensions as the inputs give them (PARAMETERS, then
    # DRIVE_PARAMETERS order), core last.
    return {v: (o.dims, o.data) for v, o in zip(variables, outs)}


def _show_dask_progress(ds):
    """Compute (persist) ``ds`` now, with dask's progress bar; still dask-backed after."""
    client = None
    try:
        import distributed

        client = distributed.default_client()
    except (ImportError, ValueError):
        pass
    if client is not None:
        ds = ds.persist()
        distributed.progress(ds)
        return ds
    from dask.diagnostics import ProgressBar

    with ProgressBar(out=sys.stderr):
        return ds.persist()


# ----------------------------------------------------------------------------- attrs


_VARIABLE_ATTRS = {
    "theta": {"long_name": "angle θ at the output times", "units": "rad"},
    "theta_dot": {"long_name": "angular velocity θ' at the output times", "units": "rad per unit time"},
    "theta_final": {"long_name": "angle θ(t1) at the end of the span", "units": "rad"},
    "theta_dot_final": {"long_name": "angular velocity θ'(t1) at the end of the span",
                        "units": "rad per unit time"},
    "mean_velocity": {
        "long_name": "mean angular velocity over the second half of the span",
        "description": "2 pi / T_c where the run reached the running limit cycle, 0 where it "
        "locked at an equilibrium, else (theta(t1) - theta(tm)) / (t1 - tm), tm = t0 + (t1 - t0)/2 "
        "(t0 = 0: (theta(T) - theta(T/2)) / (T/2)); NaN where status != 0",
        "units": "rad per unit time",
    },
    "winding": {
        "long_name": "net 2*pi turns at the end of the span",
        "description": "rint((theta(t1) - theta0) / (2 pi)): the nearest integer (ties to even); "
        "NaN where status != 0",
    },
    "regime": {
        "long_name": "locked or running",
        "description": "'running' where |theta(t1) - theta(tm)| >= REGIME_TURNS * 2 pi "
        "(tm = t0 + (t1 - t0)/2), else 'locked'; 'failed' where status != 0",
    },
}


def _status_attrs():
    codes = sorted(STATUS_FLAGS)
    return {
        "long_name": "run status per scene (0: reached the end of the span)",
        "flag_values": np.array(codes, dtype=_STATUS_DTYPE),
        "flag_meanings": " ".join(STATUS_FLAGS[c] for c in codes),
        "flag_messages": "\n".join(f"{c}: {_status.STATUS_MESSAGES[c]}" for c in codes),
    }


def _mbm_version():
    import mbm  # at call time: mbm/__init__ may import this module before defining it

    return str(mbm.__version__)


# ------------------------------------------------------------------------------- sweep


def _grid_parameters(params, drive_given):
    """The grid's array parameters (``values``), its scalars (``fixed``) and the drive, checked."""
    values, fixed = {}, {}
    for name, value in zip(PARAMETERS, params):
        v = _check_parameter(name, value)
        (fixed if isinstance(v, float) else values)[name] = v
    drive = None
    if not all(np.ndim(d) == 0 and _check_parameter(n, d) == 0.0 for n, d in zip(DRIVE_PARAMETERS, drive_given)):
        for name, value in zip(DRIVE_PARAMETERS, drive_given):
            v = _check_parameter(name, value)
            (fixed if isinstance(v, float) else values)[name] = v
        drive = [values.get(k, fixed.get(k)) for k in DRIVE_PARAMETERS]
        # The grid is an outer product: every amplitude meets every frequency.
        amp, freq = (np.atleast_1d(d) for d in drive[:2])
        if np.any(amp != 0.0):
            check_drive(1.0, freq if freq.size > 1 else freq[0])
    return values, fixed, drive


def _check_outputs(t_span, t_eval, reduce):
    """The span, and either the output times or the reductions (exactly one of the two)."""
    t0, t1 = check_span(t_span)
    if not t1 > t0:
        raise ValueError(f"t_span must be increasing (t0 < t1), got {t_span!r}")
    reduce = _check_reduce(reduce)
    if reduce is None and t_eval is None:
        raise ValueError("give t_eval (output times of theta, theta_dot) or reduce (per-scene reductions)")
    if reduce is not None and t_eval is not None:
        raise ValueError("t_eval and reduce exclude each other (reduce picks its own output times)")
    if t_eval is not None:
        if np.ndim(t_eval) != 1 or np.size(t_eval) == 0:
            raise ValueError(f"t_eval must be a non-empty 1-D array, got shape {np.shape(t_eval)}")
        t_eval = check_t_eval(t_eval, t0, t1)
    elif not t0 < t0 + 0.5 * (t1 - t0) < t1:
        raise ValueError(f"t_span is too short to split in halves, got {t_span!r}")
    return t0, t1, t_eval, reduce


def _check_options(rtol, atol, approximant, tau, max_windows, progress):
    """The solver options every scene shares, checked (the batch calls' keywords)."""
    rtol, atol = check_tolerances(rtol, atol)  # the floor (and its warning) once, here
    tau = None if tau is None else check_positive("tau", tau)
    max_windows = check_max_windows(max_windows)
    if progress not in (True, False):
        raise ValueError(f"progress must be True or False, got {progress!r}")
    return dict(rtol=rtol, atol=atol, approximant=approximant, tau=tau, max_windows=max_windows)


def _compute(values, dims, kw, how):
    """The grid's variables by the path ``how`` = (chunks, progress, protocol) asks for."""
    chunks, progress, protocol = how
    if protocol == "adiabatic":
        return _adiabatic(values, dims, kw, chunks, progress)
    if chunks is None:
        return _local(values, dims, dict(kw, names=dims), progress)
    return _chunked(values, dims, dict(kw, names=dims), chunks)


PROTOCOLS = ("independent", "adiabatic")


def _check_protocol(protocol, values, dims, chunks):
    """``protocol`` one of :data:`PROTOCOLS`; the adiabatic one needs a bias axis, whole in ``chunks``."""
    if not isinstance(protocol, str) or protocol not in PROTOCOLS:
        raise ValueError(f"protocol must be one of {PROTOCOLS}, got {protocol!r}")
    if protocol != "adiabatic":
        return
    if "gamma" not in values:
        raise ValueError("protocol='adiabatic' needs gamma as a 1-D array: the bias axis it follows")
    if chunks is not None:
        if len(dims) == 1:
            raise ValueError("chunks with protocol='adiabatic' splits the dimensions other than gamma, "
                             "and this sweep has none")
        if chunks["gamma"] not in (-1, values["gamma"].size):
            raise ValueError(f"chunks must keep gamma whole (-1) with protocol='adiabatic' (each bias starts "
                             f"from the previous one's state), got gamma: {chunks['gamma']}")


def _adiabatic(values, dims, kw, chunks, progress):
    """The adiabatic protocol's paths (:mod:`mbm.junction.adiabatic`)."""
    from .adiabatic import adiabatic_chunked, adiabatic_local  # it builds on this module

    if chunks is not None:
        return adiabatic_chunked(values, dims, kw, chunks)
    n = math.prod(values[d].size for d in dims)
    others = n // values["gamma"].size
    bar = progress_bar(n, "sweep", unit="scene") if progress else None
    try:
        return adiabatic_local(values, dims, kw, bar, max(1, min(others, _batch_size(n, progress))))
    finally:
        if bar is not None:
            bar.close()


def _dataset(data, values, dims, fixed, t_span, t_eval, reduce, options):
    """The sweep's Dataset: the variables over the grid, its coordinates and attributes."""
    coords = {d: (d, values[d]) for d in dims}
    if reduce is None:
        coords["time"] = ("time", t_eval, {"long_name": "output time"})
    attrs = dict(fixed)
    attrs.update(t_span=np.array(t_span), rtol=options["rtol"], atol=options["atol"],
                 approximant=options["approximant"], max_windows=options["max_windows"],
                 mbm_version=_mbm_version())
    if options["tau"] is not None:
        attrs["tau"] = options["tau"]
    if reduce is not None:
        attrs["reduce"] = ",".join(reduce)
        if "regime" in reduce:
            attrs["regime_turns"] = REGIME_TURNS
    return xr.Dataset(
        {v: (dv, a, _status_attrs() if v == "status" else _VARIABLE_ATTRS[v]) for v, (dv, a) in data.items()},
        coords=coords, attrs=attrs,
    )


@keywords_named
def sweep(*, beta, gamma, omega=1.0, theta0=0.0, theta_dot0=0.0, t_span, t_eval=None, reduce=None,
          rtol=1e-6, atol=1e-9, approximant="auto", tau=None, chunks=None, progress=False,
          max_windows=DEFAULT_MAX_WINDOWS, drive_amplitude=0.0, drive_frequency=0.0, drive_phase=0.0,
          protocol="independent"):
    """Solve θ'' + βθ' + ω² sin θ = γ (+ A sin(Ωt + φ)) over an outer-product grid of parameters.

    Parameters
    ----------
    beta, gamma, omega, theta0, theta_dot0 : float or array_like, shape (k,)
        The parameters (θ₀ = ``theta0``, θ'₀ = ``theta_dot0``).  Each 1-D array is a
        dimension of the grid, with the values as its coordinate, in this argument
        order; each scalar is an attribute of the Dataset.  Real numbers (not strings
        or booleans), finite; β ≥ 0; ω > 0.
    t_span : (float, float)
        ``(t0, t1)`` with t1 > t0, common to every scene.
    t_eval : array_like, shape (m,), optional
        Output times within ``t_span`` (sorted): the Dataset has θ and θ' there, as a
        ``time`` dimension.  Exclusive with ``reduce``; one of the two is required.
    reduce : str or list of str, optional
        Keep only these reductions per scene (no ``time`` dimension; the batch call
        outputs at most two times): ``"final_state"`` (θ(t1), θ'(t1)),
        ``"mean_velocity"``, ``"winding"``, ``"regime"``, defined under "Reductions"
        in :mod:`mbm.junction.sweeps`.
    rtol, atol, approximant, tau
        As in :func:`mbm.solve_batch` (one value for every scene; ``"auto"`` chooses
        per scene).  Checked before anything runs.
    chunks : int or dict, optional
        Make the Dataset dask-backed (lazy): chunks along the parameter dimensions,
        an int for every dimension (xarray's convention: the chunk length) or
        {dimension: length} (-1 or missing: the whole dimension).  Each chunk is one
        :func:`mbm.solve_batch` call, computed by the active Dask scheduler (threads
        here, or a ``dask.distributed`` Client's cluster).
    progress : bool
        Show progress: without ``chunks``, a ``tqdm.auto`` bar (a notebook widget, else a
        line on stderr) moving at least every 2 % of the scenes (:data:`PROGRESS_STEPS`);
        with ``chunks``, the Dataset is computed now (``persist``: still dask-backed, its chunks held in
        memory or on the cluster) under ``dask.diagnostics.ProgressBar`` on stderr or, with a
        distributed Client, ``distributed.progress``.
    max_windows : int, optional
        As in :func:`mbm.solve_batch`.
    drive_amplitude, drive_frequency, drive_phase : float or array_like, shape (k,), optional
        The AC drive A sin(Ωt + φ) (:class:`mbm.Pendulum`; Ω ≥ 0), as the parameters
        above (dimensions after theirs, scalars as attributes) where any is not 0;
        all three 0 (the default): no drive, and neither dimensions nor attributes;
        Ω > 0 wherever A ≠ 0.
        A driven scene's only regime is the phase-locked one (a Shapiro step,
        :mod:`mbm.regimes` S1–S7), where its ``"mean_velocity"`` is (p/q)Ω exactly;
        elsewhere it is the two samples' estimate, not a whole-drive-period average
        (:func:`mbm.iv_curve` measures that).
    protocol : {"independent", "adiabatic"}, optional
        ``"independent"`` (default): every scene from (θ₀, θ'₀), a sudden bias step.
        ``"adiabatic"``: the 1-D ``gamma`` swept in its order (decreasing: down), each
        bias from the previous one's state at t1 (:mod:`mbm.junction.adiabatic`): the
        hysteresis of an I–V measurement; ``chunks`` splits the other dimensions only.

    Returns
    -------
    xarray.Dataset
        Coordinates: the array parameters (and ``time`` = ``t_eval``).  Variables:
        ``theta``, ``theta_dot`` over (parameters..., time), or the reductions' over
        (parameters...); ``status`` (int32): 0 where the run reached t1, else an
        ``mbm.status`` code (words in ``flag_meanings``, messages in ``flag_messages``).
        A failed scene's reductions are NaN (``regime``: ``"failed"``), its series NaN
        past the outputs it reached.  Attributes: the scalar parameters, ``t_span``, the
        options given, ``reduce``, ``regime_turns``, ``protocol`` and ``mbm_version``.

    Raises
    ------
    ValueError
        For an invalid argument, naming it (empty, 2-D or non-finite parameter arrays,
        β < 0, ω ≤ 0, A ≠ 0 with Ω ≤ 0, an unknown reduction, a bad span, ``t_eval``,
        option or protocol), or an approximant outside the domain of a scene's model.
    TypeError
        For a parameter or option that is not real numbers (a str, bool, complex).
    KeyboardInterrupt
        Without ``chunks``: Ctrl-C stops the running batch at every scene's next
        window (:func:`mbm.solve_batch`) and the sweep at once, within a second.

    Notes
    -----
    Results do not depend on how the grid is split: chunked, unchunked and one
    :func:`mbm.solve_batch` over all scenes (adiabatic: its chain) agree bit for bit.
    """
    values, fixed, drive = _grid_parameters((beta, gamma, omega, theta0, theta_dot0),
                                            (drive_amplitude, drive_frequency, drive_phase))
    dims = tuple(d for d in PARAMETERS + DRIVE_PARAMETERS if d in values)
    t0, t1, t_eval, reduce = _check_outputs(t_span, t_eval, reduce)
    options = _check_options(rtol, atol, approximant, tau, max_windows, progress)
    models = [values.get(k, fixed.get(k)) for k in ("beta", "gamma", "omega")]
    _check_approximant(approximant, options["tau"], (t0, t1), options["rtol"], options["atol"],
                       options["max_windows"], models, drive)
    chunks = _check_chunks(chunks, dims)
    _check_protocol(protocol, values, dims, chunks)

    kw = dict(fixed=fixed, t_span=(t0, t1), times=_output_times(reduce, (t0, t1), t_eval),
              variables=_variables(reduce), options=options)
    data = _compute(values, dims, kw, (chunks, progress, protocol))
    ds = _dataset(data, values, dims, fixed, (t0, t1), t_eval, reduce, options)
    ds.attrs["protocol"] = protocol
    return _show_dask_progress(ds) if chunks is not None and progress else ds
