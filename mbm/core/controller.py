"""The controllers: which window length a run takes.

:func:`fixed_window` (τ, cut at the span's end) or the adaptive controller
(:func:`adaptive_window_for`: scipy's acceptance test on the approximant's estimate;
the window tried is the kind's a-priori window from its anchored coefficients where
it has one, else scipy's RK step factor, Hairer–Nørsett–Wanner II.4), started by
:func:`first_window_for`.  A rejected window re-evaluates the same anchored formula at
a shorter length.  The adaptive pieces are compiled once per kind and called.
"""

import math
import numba
import numpy as np

from ..compile.jit import INLINE, kernel
from .kind_ops import OP_ADAPTIVE, OP_FIRST, OPS_PER_KIND, call_adaptive, call_first
from .window import (
    KIND_EXACT,
    KIND_SALAS_TORQUE,
    KIND_SPLIT,
    KIND_TAYLOR,
    kind_of,
    prior_window,
    step,
)
from ..status import STATUS_NONFINITE, STATUS_OK, STATUS_TOO_SMALL



CONTROLLER_FIXED = 0


CONTROLLER_ADAPTIVE = 1


# Adaptive controller, as scipy's RK controller (Hairer–Nørsett–Wanner II.4): a
# safety factor below 1 keeps most windows accepted, the growth cap keeps one lucky
# estimate from jumping past the region the estimate describes (scipy caps at 10; 5
# because an estimate near the series' radius is least reliable), and the shrink
# floor keeps a bad estimate from collapsing the window.
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


def plan_windows(approximant, tau, max_step, span):
    """The controller for an approximant: ``(controller, h_abs, error_order)`` or None.

    A given ``tau`` means fixed windows of that length; an exact flow has no
    truncation error, so one fixed window as long as ``max_step`` allows (the whole
    ``span`` when it is infinite); an approximant with an error estimate and a
    compiled kind runs under the adaptive controller (h_abs = −1: the first window is
    searched from the estimate).  None: the approximant needs a τ from the caller.
    """
    if tau is not None:
        return CONTROLLER_FIXED, float(tau), 0
    if approximant.exact:
        return CONTROLLER_FIXED, (max_step if math.isfinite(max_step) else (span or 1.0)), 0
    if approximant.error_kernel is not None and kind_of(approximant) is not None:
        return CONTROLLER_ADAPTIVE, -1.0, int(approximant.error_order)
    return None


@kernel
def _window_end(t, direction, t_bound, h_abs):
    t_new = t + direction * h_abs
    if direction * (t_new - t_bound) > 0.0:
        t_new = t_bound
    return t_new


@kernel
def _error_norm(et, ev, y0, y1, theta, v, rtol, atol):
    # scipy's RMS norm of the estimate scaled by atol + rtol·max(|y_start|, |y_end|).
    st = atol + rtol * max(abs(y0), abs(theta))
    sv = atol + rtol * max(abs(y1), abs(v))
    return math.sqrt(0.5 * ((et / st) ** 2 + (ev / sv) ** 2))


@numba.njit(**INLINE)
def fixed_window(kind, coef, t, direction, t_bound, tau):
    """Fixed controller: one window of length τ (cut at t_bound).

    Returns ``(status, t_new, theta, v)``; a non-finite state fails the window.
    """
    t_new = _window_end(t, direction, t_bound, tau)
    theta, v, _, _ = step(kind, coef, t_new - t, False)
    if not (math.isfinite(theta) and math.isfinite(v)):
        return STATUS_NONFINITE, t_new, theta, v
    return STATUS_OK, t_new, theta, v


def first_window_for(kind):
    """:func:`first_window` compiled for kind ``kind`` (a constant of the closure: numba prunes
    the other kinds' kernels), called rather than inlined: inlining copies the
    callee's IR at each site, which was most of a first call's compile."""

    @kernel
    def first_window(coef, t, y0, y1, off, omega, ctl):
        """Initial adaptive window length: the a-priori window (:func:`prior_window`) where
        the kind has one, else searched from the anchored formula's own error estimate.
        ``off`` (2π × the winding count) is added to θ where it sets the tolerance's scale;
        ``ctl`` is the run's :data:`~mbm.core.record.WindowControl`."""
        rtol, atol = ctl.rtol, ctl.atol
        prior = prior_window(kind, coef, off + y0, y1, rtol, atol, ctl.log_eps)
        if prior < math.inf:
            return min(prior, ctl.max_step)
        h_abs = min(FIRST_WINDOW_PERIODS * 2.0 * math.pi / omega, ctl.max_step)
        inv = -1.0 / (ctl.error_order + 1.0)
        for _ in range(FIRST_WINDOW_ITERS):
            h = _window_end(t, ctl.direction, ctl.t_bound, h_abs) - t
            theta, v, et, ev = step(kind, coef, h, True)
            err = _error_norm(et, ev, off + y0, y1, off + theta, v, rtol, atol)
            if not (math.isfinite(err) and math.isfinite(theta) and math.isfinite(v)):
                h_abs *= MIN_FACTOR
                continue
            fac = MAX_FACTOR if err == 0.0 else SAFETY * err**inv
            h_abs = min(h_abs * min(MAX_FACTOR, max(MIN_FACTOR, fac)), ctl.max_step)
        return h_abs

    return first_window


@kernel
def _accepted_factor(err, theta, v, prior, inv, rejected):
    """:func:`adaptive_window`'s test of a try: the factor of the next proposal when the
    try is accepted (scaled estimate ≤ 1, finite), else 0."""
    if math.isfinite(err) and err <= 1.0 and math.isfinite(theta) and math.isfinite(v):
        if prior < math.inf:
            fac = MAX_FACTOR
        else:
            fac = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err**inv)
        if rejected:
            fac = min(1.0, fac)
        return fac
    return 0.0


def adaptive_window_for(kind):
    """:func:`adaptive_window` compiled for kind ``kind`` (a constant of the closure: numba prunes
    the other kinds' kernels), called rather than inlined: inlining copies the
    callee's IR at each site, which was most of a first call's compile."""

    @kernel
    def adaptive_window(coef, t, y0, y1, off, h_abs, ctl):
        """Adaptive controller: one accepted window under rtol/atol.

        The window tried is ``h_abs`` (the previous proposal, or ``first_step``), no longer
        than ``max_step`` nor than the kind's a-priori window (:func:`prior_window`).  It
        is accepted when the scaled estimate is ≤ 1 (scipy's test), else shortened by the
        estimate's h^(p+1) scaling and retried.  Returns ``(status, t_new, theta, v,
        h_next)``.  The proposal h_next: with an a-priori window, MAX_FACTOR × this window
        (the next anchor's own prior decides; the cap only lets a ``first_step`` grow);
        without, scipy's factor from the estimate.  After a rejection, no longer than the
        window accepted.  ``off`` (2π × the winding count) is added to θ where it sets the
        tolerance's scale (scipy's atol + rtol·|y| of the whole angle); ``ctl`` is the
        run's :data:`~mbm.core.record.WindowControl`.
        """
        rtol, atol = ctl.rtol, ctl.atol
        min_h = MIN_WINDOW_ULPS * _EPS * max(abs(t), 1e-300)
        prior = prior_window(kind, coef, off + y0, y1, rtol, atol, ctl.log_eps)
        h_abs = min(h_abs, ctl.max_step, prior)
        rejected = False
        inv = -1.0 / (ctl.error_order + 1.0)
        while True:
            if h_abs < min_h:
                return STATUS_TOO_SMALL, t, y0, y1, h_abs
            t_new = _window_end(t, ctl.direction, ctl.t_bound, h_abs)
            theta, v, et, ev = step(kind, coef, t_new - t, True)
            err = _error_norm(et, ev, off + y0, y1, off + theta, v, rtol, atol)
            fac = _accepted_factor(err, theta, v, prior, inv, rejected)
            if fac > 0.0:
                return STATUS_OK, t_new, theta, v, h_abs * fac
            if math.isfinite(err):
                h_abs *= max(MIN_FACTOR, SAFETY * err**inv)
            else:
                h_abs *= MIN_FACTOR
            rejected = True

    return adaptive_window


_first_window_taylor = first_window_for(KIND_TAYLOR)


_first_window_split = first_window_for(KIND_SPLIT)


_adaptive_window_taylor = adaptive_window_for(KIND_TAYLOR)


_adaptive_window_split = adaptive_window_for(KIND_SPLIT)


@numba.njit(**INLINE)
def _first(kind, coef, t, y0, y1, off, omega, ctl):
    """:func:`first_window` of kind ``kind`` through its compiled entry (a splitting's through
    the table of :mod:`mbm.core.kind_ops`); h = −1 (no window) for a kind without an
    error estimate."""
    if kind == KIND_TAYLOR:
        return _first_window_taylor(coef, t, y0, y1, off, omega, ctl)
    if kind == KIND_SPLIT:
        return call_first(KIND_SPLIT * OPS_PER_KIND + OP_FIRST, (coef, t, y0, y1, off, omega, ctl))
    return -1.0


@numba.njit(**INLINE)
def first_try(kind, coef, t, y0, y1, off, h_abs, ctl):
    """:func:`adaptive_window`'s first try: ``(ok, h, prior, t_new)``, the window tried
    (``h_abs`` no longer than ``ctl.max_step`` nor the kind's a-priori window ``prior``),
    and whether it is above the floor (``ok``; else the controller's own status).
    Shared by the loop (:func:`_adaptive`) and the lanes (:mod:`mbm.core.lanes`)."""
    min_h = MIN_WINDOW_ULPS * _EPS * max(abs(t), 1e-300)
    prior = prior_window(kind, coef, off + y0, y1, ctl.rtol, ctl.atol, ctl.log_eps)
    h = min(h_abs, ctl.max_step, prior)
    if h >= min_h:
        return True, h, prior, _window_end(t, ctl.direction, ctl.t_bound, h)
    return False, h, prior, t


@kernel
def accept_try(est, start, end, off, prior, h, ctl):
    """The test of the first try of length ``h``: ``(accepted, h_next)``, as
    :func:`adaptive_window`'s (``est`` the estimate (err_θ, err_θ'), the state from
    ``start`` (φ, θ') to ``end`` (θ, θ'))."""
    y0, y1 = start
    theta, v = end
    err = _error_norm(est[0], est[1], off + y0, y1, off + theta, v, ctl.rtol, ctl.atol)
    # np.bool_: a literal False would compile _accepted_factor a second time.
    fac = _accepted_factor(err, theta, v, prior, -1.0 / (ctl.error_order + 1.0), np.bool_(False))
    return fac > 0.0, h * fac


@numba.njit(**INLINE)
def _adaptive(kind, coef, t, y0, y1, off, h_abs, ctl):
    """:func:`adaptive_window` of kind ``kind``: its first try here (inlined: the common
    window, accepted at once), and on a rejection the kind's compiled controller from
    the start (the same first try again, then its retries: the same bits; a splitting's
    through the table of :mod:`mbm.core.kind_ops`).  A kind
    without an error estimate cannot run adaptive windows (STATUS_TOO_SMALL)."""
    if kind == KIND_EXACT:
        return STATUS_TOO_SMALL, t, y0, y1, h_abs
    if kind == KIND_SALAS_TORQUE:
        return STATUS_TOO_SMALL, t, y0, y1, h_abs
    ok, h, prior, t_new = first_try(kind, coef, t, y0, y1, off, h_abs, ctl)
    if ok:
        theta, v, et, ev = step(kind, coef, t_new - t, True)
        accepted, h_next = accept_try((et, ev), (y0, y1), (theta, v), off, prior, h, ctl)
        if accepted:
            return STATUS_OK, t_new, theta, v, h_next
    if kind == KIND_SPLIT:
        return call_adaptive(KIND_SPLIT * OPS_PER_KIND + OP_ADAPTIVE, (coef, t, y0, y1, off, h_abs, ctl))
    return _adaptive_window_taylor(coef, t, y0, y1, off, h_abs, ctl)
