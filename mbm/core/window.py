"""The window: the approximant kinds the loop runs and the approximant's step.

A window, as (3.29)–(3.31) of the second paper: the approximant is anchored at the
state reached (:func:`anchor`, :func:`anchor_driven`), and the state at the window end
is the formula's value there (:func:`evaluate`); its local error estimate is
:func:`estimate`, its a-priori length :func:`prior_window`, and :func:`step` returns
both.  numba cannot cache a kernel that takes another kernel as an argument, so the
kind is an integer (:data:`COMPILED_KINDS`) and each of these functions dispatches on
it; they are inlined where the kind is a constant, so numba keeps one kind's kernels.

Winding (:data:`TWO_PI_A`): the angle of a run of a wrapping kind is held as
θ = 2πk + φ (:func:`theta_of`, :func:`wrap`).
"""

import collections
import math

import numba
import numpy as np

from ..approximants.belendez2007 import belendez_eval_kernel
from ..approximants.salas2022 import salas_torque_eval
from ..approximants.splitting import split_eval_kernel
from ..approximants.taylor import (
    taylor24_coefficients_into,
    taylor24_driven_coefficients_into,
    taylor_coefficients_into,
    taylor_driven_coefficients_into,
    taylor_error_kernel,
    taylor_eval_kernel,
    taylor_window_log,
)
from ..compile.jit import INLINE, kernel
from .kind_ops import OP_ANCHOR, OP_ERROR, OP_EVAL, OPS_PER_KIND, call_anchor, call_error, call_eval



#: The autonomous pendulum's constants of an anchor: θ'' + βθ' + ω² sin θ = γ.
Model = collections.namedtuple("Model", ("beta", "gamma", "omega"))

#: The AC drive of an anchor (torque γ + A sin(Ωt + φ)): amplitude, frequency, phase.
Drive = collections.namedtuple("Drive", ("amp", "freq", "phase"))

#: A driven window's start: its time, θ and θ'.
Start = collections.namedtuple("Start", ("t", "theta", "v"))


# Kinds of the compiled dispatch: ``compiled_kind`` name -> (id, the approximant's
# eval kernel).  The kernel is checked against the approximant's own, so a subclass
# that overrides its formula never runs the parent's compiled kernels.
KIND_TAYLOR = 0


KIND_EXACT = 1


KIND_SALAS_TORQUE = 2


KIND_SPLIT = 3


COMPILED_KINDS = {
    "taylor": (KIND_TAYLOR, taylor_eval_kernel),
    "exact": (KIND_EXACT, belendez_eval_kernel),
    "salas-torque": (KIND_SALAS_TORQUE, salas_torque_eval),
    "split": (KIND_SPLIT, split_eval_kernel),
}


#: Kinds whose runs hold θ as a winding count and φ (see TWO_PI_A): the true
#: equation's approximants, periodic in θ.  The exact flow takes one window, and the
#: papers' ℘ formula models sin θ by a cubic in θ (not periodic): they keep θ.
WRAPPING_KINDS = (KIND_TAYLOR, KIND_SPLIT)


# Taylor windows are chosen a priori from the anchored coefficients
# (:func:`prior_window`, heyoka's radius rule per component) with the neglected terms
# at 1/TAYLOR_WINDOW_MARGIN of the tolerance per window.  Why so far below it: along a
# conservative (β = 0) orbit the local errors lean to one sign and add up over the
# 10³–10⁴ windows of a run, and the energy error they leave turns into a phase error
# growing with t; at a margin of ~1 the global error reached 1e5× tol on issue 16's
# random scenes.  Measured on 3 × 1006 of them (docs/oracle.md): 1e3 leaves up to 84×
# tol, 1e4 up to 47× (and 7× at 1e-4) for 10 % more windows; 1e5 drives some 1e-8 runs
# to the round-off floor, where the 1e-12 run (more windows, more rounding) is then
# the less accurate one.
TAYLOR_WINDOW_MARGIN = 1e4


# ... but not below TAYLOR_WINDOW_FLOOR·(atol/rtol + |y|), about one ulp of |y|:
# truncation under round-off buys nothing, and more windows round more (the floor
# binds for rtol < TAYLOR_WINDOW_MARGIN · 2.2e-16 ≈ 2.2e-12).
TAYLOR_WINDOW_FLOOR = 2.220446049250313e-16


# Winding: a run of a kind whose formula depends on θ through sin θ and cos θ only
# (:data:`WRAPPING_KINDS`) holds its angle as θ = 2πk + φ, k an integer count and φ
# in (−π, π] once reduced, so that a window adds its increment to φ, rounded at
# ulp(π), not to θ, rounded at ulp(|θ|): on a rotation wound to |θ| = 10⁶ that
# rounding (1e-10 per window) would add up over the run, here it is 4e-16 and the
# outputs round θ once each.  2π = TWO_PI_A + TWO_PI_B (Cody–Waite): A has 32
# significant bits, so m·A is exact for |m| < 2²¹ and φ − m·A is exact (Sterbenz);
# B carries the next 53 bits (2π − fl(2π) = 2.4492935982947064e-16).
TWO_PI_A = math.ldexp(round(math.ldexp(2.0 * math.pi, 29)), -29)


TWO_PI_B = (2.0 * math.pi - TWO_PI_A) + 2.4492935982947064e-16


def kind_of(approximant):
    """``(kind id, kind argument)`` of an approximant the compiled loop runs, or None.

    None when the approximant declares no ``compiled_kind``, or when its eval kernel
    is not the one the kind dispatches to (a subclass with its own formula).
    """
    entry = COMPILED_KINDS.get(approximant.compiled_kind)
    if entry is None or approximant.eval_kernel is not entry[1]:
        return None
    return entry[0], int(approximant.kind_arg)


@numba.njit(**INLINE)
def anchor(kind, karg, model, theta0, v0, ws_coef, ws_scratch, simd=False):
    """Coefficient vector of approximant ``kind`` of ``model`` (a :data:`Model`) anchored
    at (θ₀, θ̇₀); coef[0] = status.

    Kind "taylor" writes it into the run's workspace ``ws_coef``, ``ws_scratch``
    (:func:`mbm.approximants.taylor.taylor_workspace`; no allocation per window), so
    the vector lives until the next anchor; the other kinds return a new array.
    ``simd`` (a constant of the caller) anchors "taylor" at degree SIMD_ORDER alone,
    compiling no loop form of the recurrence (another ``karg``: STATUS_BAD_ORDER).
    """
    beta, gamma, omega = model
    if kind == KIND_TAYLOR:
        # (nested: with a kind read at run time, ``simd`` alone prunes the loop form)
        if simd:
            return taylor24_coefficients_into(beta, gamma, omega, theta0, v0, karg, ws_coef, ws_scratch)
        return taylor_coefficients_into(beta, gamma, omega, theta0, v0, karg, ws_coef, ws_scratch)
    elif kind == KIND_EXACT or kind == KIND_SPLIT or kind == KIND_SALAS_TORQUE:
        return call_anchor(kind * OPS_PER_KIND + OP_ANCHOR, (karg, beta, gamma, omega, theta0, v0))
    # An unknown kind cannot be anchored: a status, never a formula of another kind.
    bad = np.full(1, np.nan)
    bad[0] = -1.0
    return bad


@numba.njit(**INLINE)
def anchor_driven(kind, karg, model, drive, start, ws_coef, ws_scratch, simd=False):
    """:func:`anchor` of the driven equation (torque γ + A sin(Ωt + φ): ``drive`` a
    :data:`Drive`), the window starting at ``start`` (a :data:`Start`: t₀, θ₀, θ̇₀),
    into the workspace as :func:`anchor` (``simd`` as there); only kind "taylor"
    integrates a drive (the others: a bad status, never the autonomous formula)."""
    beta, gamma, omega = model
    amp, freq, phase = drive
    t0, theta0, v0 = start
    if kind == KIND_TAYLOR:
        if simd:
            return taylor24_driven_coefficients_into((beta, gamma, omega, amp, freq, phase), t0, theta0, v0, karg,
                                                     ws_coef, ws_scratch)
        return taylor_driven_coefficients_into((beta, gamma, omega, amp, freq, phase), t0, theta0, v0, karg,
                                               ws_coef, ws_scratch)
    bad = np.full(1, np.nan)
    bad[0] = -1.0
    return bad


@numba.njit(**INLINE)
def evaluate(kind, coef, t):
    """(θ, θ') of an anchored approximant at time ``t`` from its anchor."""
    if kind == KIND_TAYLOR:
        return taylor_eval_kernel(coef, t)
    elif kind == KIND_EXACT or kind == KIND_SPLIT or kind == KIND_SALAS_TORQUE:
        return call_eval(kind * OPS_PER_KIND + OP_EVAL, (coef, t))
    return math.nan, math.nan


@numba.njit(**INLINE)
def estimate(kind, coef, h):
    """Local error estimate (err_θ, err_θ') of the window [0, h].

    0 for the exact flow and for kinds without an estimate (those run under the
    fixed controller only).
    """
    if kind == KIND_TAYLOR:
        return taylor_error_kernel(coef, h)
    elif kind == KIND_SPLIT:
        return call_error(kind * OPS_PER_KIND + OP_ERROR, (coef, h))
    return 0.0, 0.0


@numba.njit(**INLINE)
def prior_window(kind, coef, y0, y1, rtol, atol, log_eps):
    """A-priori window length of an anchored approximant, or inf where it has none.

    Kind "taylor": :func:`mbm.approximants.taylor.taylor_window_kernel` with the
    neglected terms at 1/:data:`TAYLOR_WINDOW_MARGIN` of scipy's scale atol + rtol·|y|
    per component (and not below :data:`TAYLOR_WINDOW_FLOOR`·(atol/rtol + |y|)), its
    logarithm ``log_eps`` from :func:`window_log_eps`.  Other kinds: inf (their
    windows come from the estimate's h^(p+1) scaling alone).
    """
    if kind == KIND_TAYLOR:
        return taylor_window_log(coef, y0, y1, rtol, atol, log_eps)
    return math.inf


@kernel
def window_log_eps(rtol):
    """ln of :func:`prior_window`'s per-window target eps (a constant of the run, formed
    once per loop call: a log per window was ~10 ns of it)."""
    return math.log(max(rtol / TAYLOR_WINDOW_MARGIN, TAYLOR_WINDOW_FLOOR))


@numba.njit(**INLINE)
def step(kind, coef, h, with_error):
    """The approximant's step over [0, h]: ``(theta, v, err_theta, err_v)``.

    The estimate is computed only ``with_error`` (the fixed controller does not read
    it, and a splitting's estimate costs as much as the step).
    """
    theta, v = evaluate(kind, coef, h)
    if with_error:
        et, ev = estimate(kind, coef, h)
        return theta, v, et, ev
    return theta, v, 0.0, 0.0


@kernel
def theta_of(k, phi):
    """θ = 2πk + φ, rounded once (φ itself when k = 0)."""
    if k == 0.0:
        return phi
    return k * TWO_PI_A + (phi + k * TWO_PI_B)


@kernel
def wrap(k, phi):
    """``(k', φ')`` with φ' in (−π, π] and 2πk' + φ' = 2πk + φ (to the rounding of φ').

    In doubles φ' lies in [−fl(π), fl(π)]: both ends are inside (−π, π], as fl(π) < π
    (and they are different angles).  Idempotent: such a φ is returned as it is.
    """
    if -math.pi <= phi <= math.pi:
        return k, phi
    m = -math.floor((math.pi - phi) / (2.0 * math.pi))
    phi = (phi - m * TWO_PI_A) - m * TWO_PI_B
    # The quotient's rounding can leave φ' just outside the interval: one more turn.
    if phi > math.pi:
        phi = (phi - TWO_PI_A) - TWO_PI_B
        m += 1.0
    elif phi < -math.pi:
        phi = (phi + TWO_PI_A) + TWO_PI_B
        m -= 1.0
    return k + m, phi


@kernel
def _reduce_phi(k, phi):
    """(k, φ) before a window: φ reduced to (−π, π] where that leaves θ's value unchanged
    to the bit (so a window's start repeats the state the last one ended at; else next
    time)."""
    if not (-math.pi <= phi <= math.pi):
        k2, phi2 = wrap(k, phi)
        if theta_of(k2, phi2) == theta_of(k, phi):
            return k2, phi2
    return k, phi


@kernel
def _put(out_theta, out_w, wrapped, i, k, phi):
    # An output angle: θ = 2πk + φ, or (φ wrapped to (−π, π], its winding count).
    if wrapped:
        kk, ph = wrap(k, phi)
        out_theta[i] = ph
        out_w[i] = kk
    else:
        out_theta[i] = theta_of(k, phi)
