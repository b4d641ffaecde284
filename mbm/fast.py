"""The compiled path: whole moving-boundary runs with no Python per window.

:func:`solve` runs one scene, :func:`solve_batch` many in parallel (``numba.prange``).
Both are thin over the loop of :mod:`mbm.loop`, the one :class:`mbm.MBM` calls, so their
answers equal the solve_ivp path's bit for bit for the same options.
"""

import functools
import math
import threading

import numpy as np

from . import loop
from ._validate import (
    DEFAULT_MAX_WINDOWS,
    check_max_windows,
    check_positive,
    check_span,
    check_state,
    check_t_eval,
    check_tolerances,
)
from .approximants import Approximant, get_approximant
from .choice import auto_name, auto_reason
from .problem import Pendulum

__all__ = ["solve", "solve_batch", "SolveResult"]

# Stride of solve_batch's scene order, as a fraction of the batch: the golden ratio's
# (Weyl sequence i·φ mod 1), so every contiguous block of the order samples the whole
# batch evenly.  Sweeps list scenes by parameter and cost varies ~100x along them
# (settling vs running); numba splits a prange into contiguous blocks, and in sweep
# order one thread got all the running scenes (2 threads: 1.16x; in this order 1.95x).
ORDER_STRIDE = 0.6180339887498949
# Initial capacity of the window-end record when no t_eval is given (doubled as needed).
ENDS_CAPACITY = 64
# Windows one compiled call of solve may take before Python regains control (where
# Ctrl-C is honoured): 2^15 windows are 10–300 ms (0.3 µs a Taylor window, ~10 µs a
# splitting's), and a call costs ~1 µs, so the chunking costs nothing measurable.
CALL_WINDOWS = 2**15
# How often the thread waiting for a batch wakes to let Ctrl-C in (seconds).
BATCH_POLL = 0.05

_NO_TIMES = np.empty(0)
_NO_OUT = np.empty((2, 0))
_NO_WIN_T = np.empty(0)
_NO_WIN_Y = np.empty((0, 2))
_NO_WIN_COEF = np.empty((0, 0))
# The cancel flag of single-scene runs: never set (they stop between calls instead).
_NEVER = np.zeros(1, dtype=np.int64)


class SolveResult(dict):
    """Result of :func:`solve` / :func:`solve_batch`: a dict with attribute access,
    like scipy's ``OptimizeResult`` (not used here to keep ``import mbm`` free of
    ``scipy.optimize``)."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __repr__(self):
        return "SolveResult(" + ", ".join(f"{k}={v!r}" for k, v in self.items()) + ")"


def compiled(ap):
    """``(approximant, kind, karg)`` of an approximant the compiled loop runs, or a ValueError."""
    kk = loop.kind_of(ap)
    if kk is None:
        raise ValueError(
            f"approximant {ap.name!r} has no compiled kernel; mbm.solve runs 'auto', 'taylor*', "
            "'split*', 'belendez' and 'salas-torque' (use solve_ivp(method=mbm.MBM) for the others)"
        )
    return ap, kk[0], kk[1]


@functools.lru_cache(maxsize=64)
def _resolve(name, undamped):
    """:func:`compiled` of a registered name (cached: per-call overhead of :func:`solve`)."""
    return compiled(get_approximant(auto_name(undamped) if name == "auto" else name))


def _approximant(approximant, model):
    undamped = model.beta == 0.0 and model.gamma == 0.0
    if isinstance(approximant, str):
        return _resolve(approximant, undamped)
    return compiled(get_approximant(approximant))


def _plan(ap, tau, max_step, t0, t1):
    if tau is not None:
        tau = check_positive("tau", tau)
    plan = loop.plan_windows(ap, tau, max_step, abs(t1 - t0))
    if plan is None:
        raise ValueError(f"approximant {ap.name!r} has no error estimate: pass tau")
    return plan


@functools.lru_cache(maxsize=256)
def _auto_reason(undamped, rtol, atol):
    # Cached: formatting the sentence on every call was a visible part of the fixed cost.
    return auto_reason(undamped, rtol, atol)


def _reason(model, rtol, atol, approximant):
    if isinstance(approximant, str) and approximant == "auto":
        return _auto_reason(model.beta == 0.0 and model.gamma == 0.0, float(rtol), float(atol))
    return "chosen by the caller"


def _finish(run, p, te, out):
    """Run ``p`` to its end by the loop entry ``run``, filling ``out`` at ``te``;
    chunked so Ctrl-C gets in."""
    while True:
        run(p, te, out, _NO_WIN_T, _NO_WIN_Y, _NO_WIN_COEF, _NEVER)
        if p[0]["status"] != loop.STATUS_PAUSED:
            return


def _finish_ends(run, p):
    """Run ``p`` to its end by the loop entry ``run``, recording the state at every window end."""
    win_t = np.empty(ENDS_CAPACITY + 1)
    win_y = np.empty((ENDS_CAPACITY + 1, 2))
    n = 0
    while True:
        n += run(p, _NO_TIMES, _NO_OUT, win_t[n:], win_y[n:], _NO_WIN_COEF, _NEVER)
        if p[0]["status"] != loop.STATUS_PAUSED:
            return win_t[: n + 1], win_y[: n + 1].T
        if n + 1 == win_t.size:
            win_t = np.concatenate((win_t, np.empty(win_t.size)))
            win_y = np.concatenate((win_y, np.empty((win_y.shape[0], 2))))


def solve(model, t_span, y0, *, tau=None, rtol=1e-6, atol=1e-9, approximant="auto",
          t_eval=None, max_step=np.inf, max_windows=DEFAULT_MAX_WINDOWS):
    """Solve one scene by the moving boundary method, the whole run compiled.

    Parameters
    ----------
    model : Pendulum
    t_span : (float, float)
        (t0, t_bound); t_bound < t0 integrates backwards.
    y0 : array_like, shape (2,)
        [θ₀, θ̇₀].
    tau : float, optional
        Fixed window length; default: windows from rtol/atol (or one window for an
        exact flow).
    rtol, atol : float, optional
        Tolerances, with scipy's meaning (local error per window against
        ``atol + rtol·|y|``); rtol below 100 machine epsilons is raised to that
        floor with a warning, as scipy does.
    approximant : str, optional
        ``"auto"`` (default) or a name with a compiled kernel (``taylor*``,
        ``split*``, ``belendez``, ``salas-torque``).
    t_eval : array_like, optional
        Output times, sorted in the direction of integration; default: the window ends.
    max_step : float, optional
        Longest window.
    max_windows : int, optional
        Windows the run may take (default 10⁷, seconds of compute); past it the run
        stops with status 4 and the outputs it reached.

    Returns
    -------
    SolveResult
        ``t``, ``y`` (shape (2, n)), ``success``, ``status`` (0 ok, else a
        :mod:`mbm.loop` status), ``message``, ``n_windows``, ``approximant`` and
        ``reason`` (what "auto" chose and why).  On a failure ``t``, ``y`` hold the
        outputs reached before it.

    Raises
    ------
    ValueError, TypeError
        For invalid arguments (naming the argument) or an approximant without a
        compiled kernel.
    """
    if not isinstance(model, Pendulum):
        raise TypeError(f"model must be an mbm.Pendulum, got {type(model).__name__}")
    t0, t1 = check_span(t_span)
    y0 = check_state("y0", y0)
    rtol, atol = check_tolerances(rtol, atol)
    max_step = check_positive("max_step", max_step, allow_inf=True)
    max_windows = check_max_windows(max_windows)
    ap, kind, karg = _approximant(approximant, model)
    ap.check_model(model)
    controller, h_abs, error_order = _plan(ap, tau, max_step, t0, t1)
    p = loop.new_run(model.beta, model.gamma, model.omega, t0, y0[0], y0[1], t1, kind, karg,
                     controller, h_abs, max_step, rtol, atol, error_order, max_windows, CALL_WINDOWS)
    run = loop.RUNNERS[kind]
    if t_eval is None:
        t, y = _finish_ends(run, p)
    else:
        te = check_t_eval(t_eval, t0, t1)
        y = np.empty((2, te.size))
        _finish(run, p, te, y)
        n_filled = int(p[0]["j"])
        t, y = (te, y) if n_filled == te.size else (te[:n_filled], y[:, :n_filled])
    status = int(p[0]["status"])
    return SolveResult(
        t=t, y=y, success=status == loop.STATUS_OK, status=status,
        message=loop.STATUS_MESSAGES[status], n_windows=int(p[0]["n_windows"]),
        approximant=ap.name, reason=_reason(model, rtol, atol, approximant),
    )


def _balanced_order(n):
    """A permutation of range(n) whose contiguous blocks each sample the whole range."""
    return np.argsort((np.arange(n) * ORDER_STRIDE) % 1.0, kind="stable")


def _check_params(beta, gamma, omega):
    # The rules of Pendulum, over arrays; the first bad scene is named.
    for name, arr, ok, rule in (
        ("beta", beta, np.isfinite, "finite"),
        ("gamma", gamma, np.isfinite, "finite"),
        ("omega", omega, np.isfinite, "finite"),
        ("beta", beta, lambda a: a >= 0.0, ">= 0 (damping)"),
        ("omega", omega, lambda a: a > 0.0, "> 0"),
    ):
        bad = np.flatnonzero(~ok(arr))
        if bad.size:
            i = int(bad[0])
            raise ValueError(f"{name} must be {rule}, got {name}[{i}] = {float(arr[i])!r}")


def _run_batch_interruptibly(p, te, out, order):
    # run_batch holds no GIL: run it in a thread and wait in short joins, so that a
    # KeyboardInterrupt reaches this (main) thread, which sets the cancel flag; every
    # scene then stops at its next window.
    cancel = np.zeros(1, dtype=np.int64)
    failure = []

    def target():
        try:
            loop.run_batch(p, te, out, order, cancel)
        except BaseException as exc:  # pragma: no cover - re-raised below
            failure.append(exc)

    worker = threading.Thread(target=target, name="mbm-solve-batch", daemon=True)
    worker.start()
    try:
        while worker.is_alive():
            worker.join(BATCH_POLL)
    except KeyboardInterrupt:
        cancel[0] = 1
        worker.join()
        raise
    if failure:
        raise failure[0]


def solve_batch(beta, gamma, omega, y0, t_span, t_eval, *, rtol=1e-6, atol=1e-9,
                approximant="auto", tau=None, max_step=np.inf, max_windows=DEFAULT_MAX_WINDOWS):
    """Solve N scenes at once, in parallel over scenes (numba ``prange``).

    Parameters
    ----------
    beta, gamma, omega : array_like
        Model parameters, broadcast to a common shape (N,), N ≥ 1.
    y0 : array_like, shape (2,) or (N, 2)
        Initial states.
    t_span : (float, float)
        Common time span.
    t_eval : array_like, shape (m,)
        Common output times.
    rtol, atol, approximant, tau, max_step, max_windows
        As in :func:`solve` (one value for all scenes; "auto" chooses per scene).

    Returns
    -------
    SolveResult
        ``t`` (m,), ``y`` (N, 2, m), ``status`` (N,) per scene (0 ok), ``success``
        (N,) bool, ``n_windows`` (N,), ``approximant`` (N,) names.  Each scene's
        answer equals :func:`solve` for that scene.  A scene that fails at run time
        (a status other than 0: its approximant's domain, ``max_windows``) keeps the
        outputs it reached and NaN after them; the other scenes are unaffected.

    Raises
    ------
    ValueError
        For invalid arguments (naming the argument and, for parameter arrays, the
        first bad scene), or an approximant outside the domain of some scene's model.
    KeyboardInterrupt
        Honoured while the batch runs: every scene stops at its next window.
    """
    try:
        beta, gamma, omega = np.broadcast_arrays(
            np.atleast_1d(np.asarray(beta, dtype=float)),
            np.atleast_1d(np.asarray(gamma, dtype=float)),
            np.atleast_1d(np.asarray(omega, dtype=float)),
        )
    except ValueError:
        raise ValueError(
            f"beta, gamma, omega must broadcast to one shape (N,), got shapes "
            f"{np.shape(beta)}, {np.shape(gamma)}, {np.shape(omega)}"
        ) from None
    if beta.ndim != 1:
        raise ValueError(f"beta, gamma, omega must broadcast to shape (N,), got shape {beta.shape}")
    n = beta.size
    if n == 0:
        raise ValueError("beta, gamma, omega must hold at least one scene (got empty arrays)")
    _check_params(beta, gamma, omega)
    y0 = np.asarray(y0, dtype=float)
    if y0.shape == (2,):
        y0 = np.broadcast_to(y0, (n, 2))
    if y0.shape != (n, 2):
        raise ValueError(f"y0 must have shape (2,) or ({n}, 2), got {y0.shape}")
    if not np.all(np.isfinite(y0)):
        raise ValueError(f"y0 must be finite, got y0[{int(np.flatnonzero(~np.isfinite(y0).all(axis=1))[0])}]")
    if t_eval is None:
        raise ValueError("t_eval is required for solve_batch (common output times)")
    t0, t1 = check_span(t_span)
    te = check_t_eval(t_eval, t0, t1)
    rtol, atol = check_tolerances(rtol, atol)
    max_step = check_positive("max_step", max_step, allow_inf=True)
    max_windows = check_max_windows(max_windows)

    p = np.zeros(n, dtype=loop.RUN)
    p["beta"], p["gamma"], p["omega"] = beta, gamma, omega
    p["t"], p["theta"], p["v"], p["t_bound"] = t0, y0[:, 0], y0[:, 1], t1
    p["max_step"], p["rtol"], p["atol"], p["max_windows"] = max_step, rtol, atol, max_windows
    p["max_dtheta"] = np.inf
    names = np.empty(n, dtype=object)
    # "auto" resolves to at most two approximants (damped or not); a named one to one.
    undamped = (beta == 0.0) & (gamma == 0.0)
    for flag in (False, True):
        rows = np.flatnonzero(undamped == flag)
        if rows.size == 0:
            continue
        ap, kind, karg = _resolve(approximant, flag) if isinstance(approximant, str) else compiled(
            get_approximant(approximant))
        if type(ap).check_model is not Approximant.check_model:
            # The approximant restricts the model: check each distinct model once.
            for b, g, w in {(beta[i], gamma[i], omega[i]) for i in rows}:
                ap.check_model(Pendulum(b, g, w))
        controller, h_abs, error_order = _plan(ap, tau, max_step, t0, t1)
        p["kind"][rows], p["karg"][rows] = kind, karg
        p["controller"][rows], p["h_abs"][rows], p["error_order"][rows] = controller, h_abs, error_order
        names[rows] = ap.name
    out = np.full((n, 2, te.size), np.nan)
    _run_batch_interruptibly(p, te, out, _balanced_order(n))
    status = p["status"].astype(np.int64)
    return SolveResult(
        t=te, y=out, status=status, success=status == 0,
        n_windows=p["n_windows"].astype(np.int64), approximant=names.astype(str),
    )
