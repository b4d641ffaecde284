"""Compiled window control shared by the solve_ivp path and the compiled path.

numba cannot cache a kernel that takes another kernel as an argument, so the
approximants that run inside compiled loops are dispatched by an integer *kind*
(:data:`KIND_TAYLOR`, :data:`KIND_EXACT`, :data:`KIND_SALAS_TORQUE`, with a kind
argument ``karg``, e.g. the Taylor degree).  :class:`mbm.MBM` and :func:`mbm.solve`
call the same functions, so both paths take the same windows and give the same
answers bit for bit.

Window control (``adaptive_window``) is the controller of scipy's RK methods
(Hairer–Nørsett–Wanner II.4) on the approximant's own local error estimate; the
anchor is computed once per window start, and a rejected window re-evaluates the
same formula at a shorter length.
"""

import math

import numba

from .approximants.belendez2007 import belendez_anchor_kernel, belendez_eval_kernel
from .approximants.salas2022 import salas_torque_anchor, salas_torque_eval
from .approximants.splitting import _split_anchor, split_error_kernel, split_eval_kernel
from .approximants.taylor import taylor_coefficients, taylor_error_kernel, taylor_eval_kernel

__all__ = [
    "KIND_TAYLOR",
    "KIND_EXACT",
    "KIND_SALAS_TORQUE",
    "KIND_SPLIT",
    "kind_of",
    "anchor",
    "evaluate",
    "estimate",
    "adaptive_window",
    "fixed_window",
    "advance",
]

KIND_TAYLOR = 0
KIND_EXACT = 1
KIND_SALAS_TORQUE = 2
KIND_SPLIT = 3

# Window-control constants, as in scipy's RK controller (Hairer–Nørsett–Wanner
# II.4): a safety factor below 1 keeps most windows accepted, the growth cap keeps
# one lucky estimate from jumping past the region the estimate describes, and the
# shrink floor keeps a bad estimate from collapsing the window.
SAFETY = 0.9
MAX_FACTOR = 5.0
MIN_FACTOR = 0.2
# First-window search: start from a quarter of the small-oscillation period and
# correct it by the estimate's own h^(p+1) scaling this many times (the anchor is
# computed once; each correction costs one evaluation and one estimate).
FIRST_WINDOW_PERIODS = 0.25
FIRST_WINDOW_ITERS = 4
# A window shorter than this many ulps of t cannot advance t: fail instead of looping.
MIN_WINDOW_ULPS = 10.0
_EPS = 2.220446049250313e-16

STATUS_OK = 0
STATUS_TOO_SMALL = 1
STATUS_ANCHOR = 2
STATUS_NONFINITE = 3


@numba.njit(cache=True)
def anchor(kind, karg, beta, gamma, omega, theta0, v0):
    """Coefficient vector of approximant ``kind`` anchored at (θ₀, θ̇₀); coef[0] = status."""
    if kind == KIND_TAYLOR:
        return taylor_coefficients(beta, gamma, omega, theta0, v0, karg)
    elif kind == KIND_EXACT:
        return belendez_anchor_kernel(beta, gamma, omega, theta0, v0)
    elif kind == KIND_SPLIT:
        return _split_anchor(karg, beta, gamma, omega, theta0, v0)
    else:
        return salas_torque_anchor(beta, gamma, omega, theta0, v0)


@numba.njit(cache=True)
def evaluate(kind, coef, t):
    """(θ, θ') of an anchored approximant at time ``t`` from its anchor."""
    if kind == KIND_TAYLOR:
        return taylor_eval_kernel(coef, t)
    elif kind == KIND_EXACT:
        return belendez_eval_kernel(coef, t)
    elif kind == KIND_SPLIT:
        return split_eval_kernel(coef, t)
    else:
        return salas_torque_eval(coef, t)


@numba.njit(cache=True)
def estimate(kind, coef, h):
    """Local error estimate (err_θ, err_θ') of the window [0, h]; 0 for the exact flow."""
    if kind == KIND_TAYLOR:
        return taylor_error_kernel(coef, h)
    elif kind == KIND_SPLIT:
        return split_error_kernel(coef, h)
    return 0.0, 0.0


def kind_of(approximant):
    """``(kind, karg)`` of an approximant the compiled loops can run, or None."""
    from .approximants import belendez2007, salas2022, splitting, taylor

    if isinstance(approximant, taylor.Taylor):
        return KIND_TAYLOR, int(approximant.order)
    if isinstance(approximant, belendez2007.BelendezExact):
        return KIND_EXACT, 0
    if type(approximant) is salas2022.SalasTorque:
        return KIND_SALAS_TORQUE, 0
    if isinstance(approximant, splitting.Splitting):
        return KIND_SPLIT, int(splitting._METHOD_IDS[approximant.name])
    return None


@numba.njit(cache=True)
def _window_end(t, direction, t_bound, h_abs):
    t_new = t + direction * h_abs
    if direction * (t_new - t_bound) > 0.0:
        t_new = t_bound
    return t_new


@numba.njit(cache=True)
def _error_norm(kind, coef, h, y0, y1, theta, v, rtol, atol):
    et, ev = estimate(kind, coef, h)
    st = atol + rtol * max(abs(y0), abs(theta))
    sv = atol + rtol * max(abs(y1), abs(v))
    return math.sqrt(0.5 * ((et / st) ** 2 + (ev / sv) ** 2))


@numba.njit(cache=True)
def first_window(kind, coef, t, y0, y1, direction, t_bound, omega, max_step, rtol, atol, order):
    """Initial window length from the anchored formula's own error estimate."""
    h_abs = min(FIRST_WINDOW_PERIODS * 2.0 * math.pi / omega, max_step)
    inv = -1.0 / (order + 1.0)
    for _ in range(FIRST_WINDOW_ITERS):
        h = _window_end(t, direction, t_bound, h_abs) - t
        theta, v = evaluate(kind, coef, h)
        err = _error_norm(kind, coef, h, y0, y1, theta, v, rtol, atol)
        if not (math.isfinite(err) and math.isfinite(theta) and math.isfinite(v)):
            h_abs *= MIN_FACTOR
            continue
        fac = MAX_FACTOR if err == 0.0 else SAFETY * err**inv
        h_abs = min(h_abs * min(MAX_FACTOR, max(MIN_FACTOR, fac)), max_step)
    return h_abs


@numba.njit(cache=True)
def adaptive_window(kind, coef, t, y0, y1, direction, t_bound, h_abs, max_step, rtol, atol, order):
    """One accepted window under rtol/atol: ``(status, t_new, theta, v, h_next)``."""
    min_h = MIN_WINDOW_ULPS * _EPS * max(abs(t), 1e-300)
    h_abs = min(h_abs, max_step)
    rejected = False
    inv = -1.0 / (order + 1.0)
    while True:
        if h_abs < min_h:
            return STATUS_TOO_SMALL, t, y0, y1, h_abs
        t_new = _window_end(t, direction, t_bound, h_abs)
        h = t_new - t
        theta, v = evaluate(kind, coef, h)
        err = _error_norm(kind, coef, h, y0, y1, theta, v, rtol, atol)
        if math.isfinite(err) and err <= 1.0 and math.isfinite(theta) and math.isfinite(v):
            fac = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err**inv)
            if rejected:
                fac = min(1.0, fac)
            return STATUS_OK, t_new, theta, v, h_abs * fac
        if math.isfinite(err):
            h_abs *= max(MIN_FACTOR, SAFETY * err**inv)
        else:
            h_abs *= MIN_FACTOR
        rejected = True


@numba.njit(cache=True)
def fixed_window(kind, coef, t, direction, t_bound, tau):
    """One window of fixed length τ (cut at t_bound): ``(status, t_new, theta, v)``."""
    t_new = _window_end(t, direction, t_bound, tau)
    theta, v = evaluate(kind, coef, t_new - t)
    if not (math.isfinite(theta) and math.isfinite(v)):
        return STATUS_NONFINITE, t_new, theta, v
    return STATUS_OK, t_new, theta, v


@numba.njit(cache=True)
def advance(kind, karg, order, beta, gamma, omega, t, y0, y1, direction, t_bound,
            h_abs, max_step, rtol, atol, adaptive, t_stop, max_windows, out_t, out_coef):
    """Advance up to ``max_windows`` windows or to ``t_stop``, storing each window.

    ``out_t[i]`` is the start of window i (``out_t[n]`` the end of the last) and
    ``out_coef[i, :]`` its coefficients (zero-padded).  ``h_abs`` is the next
    adaptive window (≤ 0: search it), or τ in fixed mode.

    Returns
    -------
    status, n, t, y0, y1, h_abs
    """
    n = 0
    out_t[0] = t
    while n < max_windows and direction * (t_stop - t) > 0.0:
        coef = anchor(kind, karg, beta, gamma, omega, y0, y1)
        if coef[0] != 0.0:
            return STATUS_ANCHOR, n, t, y0, y1, h_abs
        bound = t_stop
        if adaptive:
            if h_abs <= 0.0:
                h_abs = first_window(kind, coef, t, y0, y1, direction, bound, omega, max_step, rtol, atol, order)
            st, t_new, th, v, h_next = adaptive_window(
                kind, coef, t, y0, y1, direction, bound, h_abs, max_step, rtol, atol, order
            )
        else:
            st, t_new, th, v = fixed_window(kind, coef, t, direction, bound, min(h_abs, max_step))
            h_next = h_abs
        if st != STATUS_OK:
            return st, n, t, y0, y1, h_abs
        m = min(coef.size, out_coef.shape[1])
        out_coef[n, :m] = coef[:m]
        out_coef[n, m:] = 0.0
        t, y0, y1, h_abs = t_new, th, v, h_next
        n += 1
        out_t[n] = t
    return STATUS_OK, n, t, y0, y1, h_abs


@numba.njit(cache=True)
def evaluate_windows(kind, starts, coefs, n, direction, t, out_theta, out_v):
    """Evaluate a run of ``n`` windows (starts, coefs from :func:`advance`) at times ``t``.

    Window i covers [starts[i], starts[i+1]]; a time on an interior boundary takes the
    later window (whose anchor is the earlier window's end value), the run's end the
    last window.  Times outside the run are extrapolated by the nearest window.
    """
    for j in range(t.size):
        tj = t[j]
        i = 0
        # n is small per step (windows_per_step), a linear scan is cheaper than bisection
        while i < n - 1 and direction * (tj - starts[i + 1]) >= 0.0:
            i += 1
        a, b = evaluate(kind, coefs[i], tj - starts[i])
        out_theta[j] = a
        out_v[j] = b
