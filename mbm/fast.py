"""The compiled path: whole moving-boundary runs in one numba call.

:func:`solve` runs one scene with no Python per window; :func:`solve_batch` runs
many scenes in parallel (``numba.prange``).  Both use the window control of
:mod:`mbm.kernels`, the same functions :class:`mbm.MBM` calls, so their answers
equal the solve_ivp path's bit for bit for the same options.
"""

import functools
import math

import numba
import numpy as np

from . import kernels as K
from .approximants import get_approximant
from .choice import auto_name, auto_reason
from .problem import Pendulum

__all__ = ["solve", "solve_batch", "SolveResult"]


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

# Stride of solve_batch's scene order, as a fraction of the batch: the golden ratio's
# (Weyl sequence i·φ mod 1), so every contiguous block of the order samples the whole
# batch evenly.  Sweeps list scenes by parameter and cost varies ~100x along them
# (settling vs running); numba splits a prange into contiguous blocks, and in sweep
# order one thread got all the running scenes (2 threads: 1.16x; in this order 1.95x).
ORDER_STRIDE = 0.6180339887498949
# Initial capacity of the window-end record when no t_eval is given (doubled as needed).
ENDS_CAPACITY = 64
_NO_TIMES = np.empty(0)

STATUS_MESSAGES = {
    K.STATUS_OK: "The solver successfully reached the end of the integration interval.",
    K.STATUS_TOO_SMALL: "Required window is below the spacing of floating point numbers "
    "(the tolerance cannot be met).",
    K.STATUS_ANCHOR: "The approximant cannot be anchored at the state reached (outside its domain).",
    K.STATUS_NONFINITE: "The approximant produced a non-finite state (outside its domain).",
}


# Layout of the packed scalar arguments of _run (one float64 array: numba's
# dispatcher costs ~0.5 µs per argument, more than a window of work).
P_BETA, P_GAMMA, P_OMEGA, P_T0, P_Y0, P_Y1, P_T1, P_H, P_MAXSTEP, P_RTOL, P_ATOL, P_ADAPTIVE = range(12)
N_PACKED = 12


@numba.njit(cache=True)
def _run(kind, karg, order, p, t_eval, out_th, out_v, record_ends):
    """One scene.  ``p`` holds the packed scalars (P_* indices).  Fills out_th/out_v
    at t_eval (monotone in the direction of integration); with ``record_ends``
    returns the window ends instead.

    Returns (status, n_windows, ends_t, ends_th, ends_v, n_filled).
    """
    beta, gamma, omega = p[P_BETA], p[P_GAMMA], p[P_OMEGA]
    t0, y0, y1, t_bound = p[P_T0], p[P_Y0], p[P_Y1], p[P_T1]
    h_abs, max_step, rtol, atol = p[P_H], p[P_MAXSTEP], p[P_RTOL], p[P_ATOL]
    adaptive = p[P_ADAPTIVE] != 0.0
    direction = 1.0 if t_bound >= t0 else -1.0
    t = t0
    n_windows = 0
    j = 0
    ne = t_eval.size
    cap = ENDS_CAPACITY if record_ends else 1
    ends_t = np.empty(cap)
    ends_th = np.empty(cap)
    ends_v = np.empty(cap)
    n_ends = 0
    if record_ends:
        ends_t[0] = t0
        ends_th[0] = y0
        ends_v[0] = y1
        n_ends = 1
    status = K.STATUS_OK
    while direction * (t_bound - t) > 0.0:
        coef = K.anchor(kind, karg, beta, gamma, omega, y0, y1)
        if coef[0] != 0.0:
            status = K.STATUS_ANCHOR
            break
        if adaptive:
            if h_abs <= 0.0:
                h_abs = K.first_window(kind, coef, t, y0, y1, direction, t_bound, omega, max_step, rtol, atol, order)
            st, t_new, th, v, h_next = K.adaptive_window(
                kind, coef, t, y0, y1, direction, t_bound, h_abs, max_step, rtol, atol, order
            )
        else:
            st, t_new, th, v = K.fixed_window(kind, coef, t, direction, t_bound, min(h_abs, max_step))
            h_next = h_abs
        if st != K.STATUS_OK:
            status = st
            break
        # Outputs inside (t, t_new] (and t0 itself) come from this window's formula;
        # the window end repeats the evaluation that produced (th, v).
        while j < ne and (direction * (t_eval[j] - t_new) <= 0.0):
            if t_eval[j] == t_new:
                out_th[j] = th
                out_v[j] = v
            else:
                a, b = K.evaluate(kind, coef, t_eval[j] - t)
                out_th[j] = a
                out_v[j] = b
            j += 1
        t, y0, y1, h_abs = t_new, th, v, h_next
        n_windows += 1
        if record_ends:
            if n_ends == ends_t.size:
                ends_t = np.concatenate((ends_t, np.empty(ends_t.size)))
                ends_th = np.concatenate((ends_th, np.empty(ends_th.size)))
                ends_v = np.concatenate((ends_v, np.empty(ends_v.size)))
            ends_t[n_ends] = t
            ends_th[n_ends] = y0
            ends_v[n_ends] = y1
            n_ends += 1
    # t_span of zero length: the outputs are the initial state.
    while j < ne and t_eval[j] == t0 and n_windows == 0:
        out_th[j] = y0
        out_v[j] = y1
        j += 1
    return status, n_windows, ends_t[:n_ends], ends_th[:n_ends], ends_v[:n_ends], j


@numba.njit(cache=True)
def _t_eval_problem(t_eval, t0, t1):
    # 0 ok, 1 non-finite, 2 outside t_span, 3 not sorted in the direction of integration
    lo, hi = min(t0, t1), max(t0, t1)
    direction = 1.0 if t1 >= t0 else -1.0
    for i in range(t_eval.size):
        x = t_eval[i]
        if not math.isfinite(x):
            return 1
        if x < lo or x > hi:
            return 2
        if i > 0 and direction * (x - t_eval[i - 1]) < 0.0:
            return 3
    return 0


@functools.lru_cache(maxsize=64)
def _resolve(name, undamped):
    """Approximant, kernel kind and flags for a registered name (cached: this is
    per-call overhead of :func:`solve`, paid once per name)."""
    return _describe(get_approximant(auto_name(undamped) if name == "auto" else name))


def _describe(ap):
    kk = K.kind_of(ap)
    if kk is None:
        raise ValueError(
            f"approximant {ap.name!r} has no compiled kernel; mbm.solve runs 'auto', 'taylor*', "
            "'split*', 'belendez' and 'salas-torque' (use solve_ivp(method=mbm.MBM) for the others)"
        )
    exact = bool(getattr(ap, "exact", False))
    has_estimate = getattr(ap, "error_kernel", None) is not None
    return ap, kk[0], kk[1], exact, has_estimate


def _setup(model, t_span, y0, tau, rtol, atol, approximant, t_eval, max_step):
    """Validate and translate the options of :func:`solve` into kernel arguments."""
    if not isinstance(model, Pendulum):
        raise TypeError(f"model must be an mbm.Pendulum, got {type(model).__name__}")
    try:
        t0, t1 = float(t_span[0]), float(t_span[1])
        if len(t_span) != 2:
            raise ValueError
    except (TypeError, ValueError, IndexError):
        raise ValueError(f"t_span must be a pair of real numbers (t0, t_bound), got {t_span!r}") from None
    if not (math.isfinite(t0) and math.isfinite(t1)):
        raise ValueError(f"t_span must be finite, got {t_span!r}")
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (2,):
        raise ValueError(f"y0 must have shape (2,) (theta, theta'), got shape {y0.shape}")
    if not (math.isfinite(y0[0]) and math.isfinite(y0[1])):
        raise ValueError(f"y0 must be finite, got {y0!r}")
    for name, val in (("rtol", rtol), ("atol", atol)):
        if not (isinstance(val, (int, float, np.floating)) and math.isfinite(val) and val > 0):
            raise ValueError(f"{name} must be a positive finite number, got {val!r}")
    if not (max_step > 0):
        raise ValueError(f"max_step must be > 0, got {max_step!r}")
    undamped = model.beta == 0.0 and model.gamma == 0.0
    if isinstance(approximant, str):
        ap, kind, karg, exact, has_estimate = _resolve(approximant, undamped)
    else:
        ap, kind, karg, exact, has_estimate = _describe(get_approximant(approximant))
    ap.check_model(model)
    adaptive = tau is None and not exact and has_estimate
    if tau is not None:
        tau = float(tau)
        if not (math.isfinite(tau) and tau > 0):
            raise ValueError(f"tau must be a positive finite number, got {tau!r}")
        h_abs = tau
    elif exact:
        h_abs = max_step if math.isfinite(max_step) else (abs(t1 - t0) or 1.0)
    elif adaptive:
        h_abs = -1.0
    else:
        raise ValueError(f"approximant {ap.name!r} has no error estimate: pass tau")
    if t_eval is not None:
        t_eval = np.ascontiguousarray(t_eval, dtype=float).reshape(-1)
        problem = _t_eval_problem(t_eval, t0, t1)
        if problem:
            raise ValueError(
                ("", "t_eval must be finite", f"t_eval must lie within t_span {(t0, t1)!r}",
                 "t_eval must be sorted in the direction of integration")[problem]
            )
    order = int(ap.order) if adaptive else 1
    return (ap, kind, karg, order, t0, t1, y0, float(h_abs), adaptive, t_eval)


@functools.lru_cache(maxsize=256)
def _auto_reason(undamped, rtol, atol):
    # Cached: formatting the sentence on every call was a visible part of the fixed cost.
    return auto_reason(undamped, rtol, atol)


def _reason(model, rtol, atol, approximant):
    if isinstance(approximant, str) and approximant == "auto":
        return _auto_reason(model.beta == 0.0 and model.gamma == 0.0, float(rtol), float(atol))
    return "chosen by the caller"


def solve(model, t_span, y0, *, tau=None, rtol=1e-6, atol=1e-9, approximant="auto",
          t_eval=None, max_step=np.inf):
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
        ``atol + rtol·|y|``).
    approximant : str, optional
        ``"auto"`` (default) or a name with a compiled kernel (``taylor*``,
        ``split*``, ``belendez``, ``salas-torque``).
    t_eval : array_like, optional
        Output times, sorted in the direction of integration; default: the window ends.
    max_step : float, optional
        Longest window.

    Returns
    -------
    SolveResult
        ``t``, ``y`` (shape (2, n)), ``success``, ``status`` (0 ok, else a kernel
        status), ``message``, ``n_windows``, ``approximant`` and ``reason`` (what
        "auto" chose and why).

    Raises
    ------
    ValueError, TypeError
        For invalid arguments (naming the argument) or an approximant without a
        compiled kernel.
    """
    ap, kind, karg, order, t0, t1, y0, h_abs, adaptive, te = _setup(
        model, t_span, y0, tau, rtol, atol, approximant, t_eval, float(max_step)
    )
    record = te is None
    if record:
        te = _NO_TIMES
    y = np.empty((2, te.size))
    p = np.array([model.beta, model.gamma, model.omega, t0, y0[0], y0[1], t1, h_abs,
                  float(max_step), float(rtol), float(atol), float(adaptive)])
    status, n_w, et, eth, ev, n_filled = _run(kind, karg, order, p, te, y[0], y[1], record)
    if record:
        t, y = et, np.vstack((eth, ev))
    else:
        t = te if n_filled == te.size else te[:n_filled]
        y = y if n_filled == te.size else y[:, :n_filled]
    return SolveResult(
        t=t, y=y, success=status == K.STATUS_OK, status=int(status),
        message=STATUS_MESSAGES[int(status)], n_windows=int(n_w),
        approximant=ap.name, reason=_reason(model, rtol, atol, approximant),
    )


@numba.njit(cache=True, parallel=True)
def _run_batch(kinds, kargs, orders, packed, t_eval, out_th, out_v, status, n_windows, order):
    n = kinds.size
    for k in numba.prange(n):
        i = order[k]
        st, nw, _, _, _, _ = _run(kinds[i], kargs[i], orders[i], packed[i], t_eval, out_th[i], out_v[i], False)
        status[i] = st
        n_windows[i] = nw
    return n


def _balanced_order(n):
    """A permutation of range(n) whose contiguous blocks each sample the whole range."""
    return np.argsort((np.arange(n) * ORDER_STRIDE) % 1.0, kind="stable")


def solve_batch(beta, gamma, omega, y0, t_span, t_eval, *, rtol=1e-6, atol=1e-9,
                approximant="auto", tau=None, max_step=np.inf):
    """Solve N scenes at once, in parallel over scenes (numba ``prange``).

    Parameters
    ----------
    beta, gamma, omega : array_like
        Model parameters, broadcast to a common shape (N,).
    y0 : array_like, shape (2,) or (N, 2)
        Initial states.
    t_span : (float, float)
        Common time span.
    t_eval : array_like, shape (m,)
        Common output times.
    rtol, atol, approximant, tau, max_step
        As in :func:`solve` (one value for all scenes; "auto" chooses per scene).

    Returns
    -------
    SolveResult
        ``t`` (m,), ``y`` (N, 2, m), ``status`` (N,) per scene (0 ok), ``success``
        (N,) bool, ``n_windows`` (N,), ``approximant`` (N,) names.  Each scene's
        answer equals :func:`solve` for that scene.
    """
    beta, gamma, omega = np.broadcast_arrays(
        np.atleast_1d(np.asarray(beta, dtype=float)),
        np.atleast_1d(np.asarray(gamma, dtype=float)),
        np.atleast_1d(np.asarray(omega, dtype=float)),
    )
    n = beta.size
    y0 = np.asarray(y0, dtype=float)
    if y0.shape == (2,):
        y0 = np.broadcast_to(y0, (n, 2))
    if y0.shape != (n, 2):
        raise ValueError(f"y0 must have shape (2,) or ({n}, 2), got {y0.shape}")
    if t_eval is None:
        raise ValueError("t_eval is required for solve_batch (common output times)")
    kinds = np.empty(n, dtype=np.int64)
    kargs = np.empty(n, dtype=np.int64)
    orders = np.empty(n, dtype=np.int64)
    h_abs = np.empty(n)
    adaptive = np.empty(n, dtype=np.bool_)
    names = []
    te = None
    t0 = t1 = None
    for i in range(n):
        model = Pendulum(beta[i], gamma[i], omega[i])
        ap, kinds[i], kargs[i], orders[i], t0, t1, _, h_abs[i], adaptive[i], te = _setup(
            model, t_span, y0[i], tau, rtol, atol, approximant, t_eval, float(max_step)
        )
        names.append(ap.name)
    out_th = np.empty((n, te.size))
    out_v = np.empty((n, te.size))
    status = np.empty(n, dtype=np.int64)
    n_windows = np.empty(n, dtype=np.int64)
    packed = np.empty((n, N_PACKED))
    packed[:, P_BETA], packed[:, P_GAMMA], packed[:, P_OMEGA] = beta, gamma, omega
    packed[:, P_T0], packed[:, P_Y0], packed[:, P_Y1], packed[:, P_T1] = t0, y0[:, 0], y0[:, 1], t1
    packed[:, P_H], packed[:, P_MAXSTEP] = h_abs, float(max_step)
    packed[:, P_RTOL], packed[:, P_ATOL], packed[:, P_ADAPTIVE] = float(rtol), float(atol), adaptive
    _run_batch(kinds, kargs, orders, packed, te, out_th, out_v, status, n_windows, _balanced_order(n))
    return SolveResult(
        t=te, y=np.stack((out_th, out_v), axis=1), status=status, success=status == 0,
        n_windows=n_windows, approximant=np.array(names),
    )
