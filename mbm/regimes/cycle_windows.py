"""The running cycle and the libration in the loop: the return map's watch and the stored period.

After each ordinary window the loop watches the return map of θ ≡ θ_s (mod 2π)
(:func:`_cycle_watch_for`, R1, R2 of :mod:`mbm.regimes.cycle`); once it has converged,
the windows are the stored period shifted (R3): the period's windows are re-taken once
from the cycle's anchor (:func:`_period_windows_for`) and every value looked up in them
(:func:`_period_lookup`); at the first cycle window the averaged period is refined
once from two returns re-taken at a tight tolerance (:func:`refine_period`, R4).  A
libration (:mod:`mbm.regimes.libration`) uses the same stored period with a
double-double period (C3).
"""

import collections
import math

import numba
import numpy as np

from ..approximants.taylor import taylor_workspace
from ..core.controller import _EPS, _adaptive, _first
from ..core.record import window_control
from ..core.window import (
    KIND_SPLIT,
    KIND_TAYLOR,
    Model,
    anchor,
    evaluate,
    window_log_eps,
)
from ..core.kind_ops import (
    OP_CROSSING,
    OP_PERIOD_STORE,
    OP_PERIOD_VALUE,
    OP_REFINE,
    OPS_PER_KIND,
    call_crossing,
    call_period_store,
    call_period_value,
    call_refine,
)
from ..compile.jit import INLINE, kernel
from .common import REGIME_RUNNING
from .stored_block import STORED_BLOCK, block_scratch, block_window, block_write, rate_rows, first_window_at
from .common import Tolerance
from .cycle import (
    CROSSING_ITERATIONS,
    CycleAnchor,
    MapStep,
    Retake,
    cycle_coef,
    CYCLE_AVERAGE_PERIODS,
    CYCLE_MAX_WINDOWS,
    cycle_switch,
)
from ..special.dd import two_prod, two_sum
from ..status import STATUS_OK

# Small per-window pieces are inlined into their callers, where the kind is a constant
# (numba prunes the other kinds' branches before compiling); large ones are compiled
# once per kind and called.


# A section crossing's Newton stops once its next correction, (θ''/2θ')·d² after a
# step d, is below this many ulps of s (quadratic convergence: the step after the
# last one made would be below it; 1 would ask for the last bit).
CROSSING_NEWTON_SAFETY = 2.0


_TWO_PI = 2.0 * math.pi


# (R4): the refined period's re-take: its tolerance (far below the run's, so that the
# two return times carry ~1e-15 of error), its span in periods (past the second return),
# the least 1 − μ it extrapolates with (the error of (T₂ − μT₁)/(1 − μ) grows as 1/(1 − μ)),
# and how far from the averaged period, in the run's tolerances, it may land (farther:
# the re-take went wrong, and the averaged period stands).
PERIOD_REFINE_RTOL = 1e-13
PERIOD_REFINE_SPAN = 2.2
PERIOD_REFINE_MIN_CONTRACTION = 1e-2
PERIOD_REFINE_TRUST = 1e3
# The record's cyc_k at the running cycle's switch (the averaging's count, done with),
# and once its period is refined (R4).
CYCLE_SWITCHED = CYCLE_AVERAGE_PERIODS + 1
CYCLE_REFINED = -1

# Windows a stored period's arrays hold at first (doubled as needed): a period takes
# ~10-100 windows at the tolerances in use.
PERIOD_STORE_START = 64

#: A section level crossed (R1): the ``level``, θ'' = ``acc0`` − ``beta``·θ' on it
#: (``acc0`` = γ − ω² sin(level)) and ``w2`` = ω².
Level = collections.namedtuple("Level", ("level", "acc0", "beta", "w2"))


@numba.njit(**INLINE)
def _crossing(kind, coef, h, f0, f1, lev):
    """Where the window's θ(s) crosses ``lev.level`` in (0, h] (f0, f1: θ − level at 0, h).

    Safeguarded Newton (θ' from the formula) inside the sign bracket (R1).  ``lev`` is a
    :data:`Level`: its ``acc0`` is γ − ω² sin(level) and ``w2`` ω², so that θ'' =
    acc0 − βθ' on the level (the equation of motion).  Newton's next correction after a step d is about
    (θ''/2θ')·d²; once that is below CROSSING_NEWTON_SAFETY ulps of s, the step's end
    is the root, and θ' there is carried from the last evaluation by d·θ''.  That
    carry is off by at most ~1.5(ω²|θ'| + β|θ''|)·d² (θ'' varies with θ − level = −θ'd
    and with t), which must be below CROSSING_NEWTON_SAFETY ulps of θ' too.  Then the
    usual last two evaluations (one to see the step vanish, one for θ' at the root)
    are not made: two evaluations per crossing instead of four on a running scene.
    Returns ``(s, θ'(s))``.
    """
    level, acc0, beta, w2 = lev.level, lev.acc0, lev.beta, lev.w2
    lo, hi, flo = 0.0, h, f0
    s = h * f0 / (f0 - f1) if f0 != f1 else h
    v = 0.0
    for _ in range(CROSSING_ITERATIONS):
        a, v = evaluate(kind, coef, s)
        fa = a - level
        if fa == 0.0:
            break
        if (fa > 0.0) == (flo > 0.0):
            lo, flo = s, fa
        else:
            hi = s
        s_new = s - fa / v if v != 0.0 else 0.5 * (lo + hi)
        if not (lo < s_new < hi):
            s_new = 0.5 * (lo + hi)
        else:
            d = s_new - s
            d2 = d * d
            acc = acc0 - beta * v
            tol_v = CROSSING_NEWTON_SAFETY * _EPS * abs(v)
            if (abs(acc) * d2 <= 2.0 * tol_v * abs(s_new)
                    and 1.5 * (w2 * abs(v) + beta * abs(acc)) * d2 <= tol_v):
                return s_new, v + d * acc
        if abs(s_new - s) <= 4.0 * _EPS * max(abs(s), 1e-300):
            s = s_new
            a, v = evaluate(kind, coef, s)
            break
        s = s_new
    return s, v


@numba.njit(**INLINE)
def _cycle_phase(c, t):
    """``(n, s)``: τ = t + t_off = nT + s, 0 ≤ s ≤ T, for a cycle window ``c`` (R3, C3).

    With a double-double period (c[14] ≠ 0, a libration) n·T is formed exactly, so
    the period's rounding to a double does not accumulate over n periods.
    """
    period, lo = c[3], c[14]
    tau = t + c[4]
    n = float(math.floor(tau / period))
    if lo == 0.0:
        s = tau - n * period
    else:
        ph, pl = two_prod(n, period)
        sh, se = two_sum(tau, -ph)
        s = sh + ((se - pl) - n * lo)
    return n, min(max(s, 0.0), period)


def _period_windows_for(kind, simd=False):
    """The stored period's windows (:func:`period_windows`) compiled for kind ``kind``: a
    constant of the closure, so numba prunes the other kinds' branches before it inlines
    their kernels (a whole controller and step: as an inlined callee, its every kind
    would be copied and pruned only afterwards).  ``simd``: kind "taylor" at its default
    degree SIMD_ORDER alone, anchored by the vector kernel (no loop form of the
    recurrence compiled; another degree fails the period, n = −1)."""

    @kernel
    def period_windows(c):
        """The windows of a cycle window's stored period, re-taken from its anchor (R3).

        The same approximant and controller as the run, span [0, T]: a function of the
        anchor only, so every path and the dense output evaluate the same windows.

        Returns
        -------
        starts : ndarray, shape (n + 1,)
            Window starts from the anchor (starts[n] = T).
        ends : ndarray, shape (n + 1, 2)
            The state at each start (row 0 the anchor; row i + 1 the end of window i).
        coefs : ndarray, shape (n, width)
            The windows' coefficient vectors.
        n : int
            Windows in the period; −1 where the run failed or took more than
            CYCLE_MAX_WINDOWS.
        """
        theta_c, v_c, period = c[1], c[2], c[3]
        beta, gamma, omega, rtol, atol = c[5], c[6], c[7], c[8], c[9]
        karg = int(c[11])
        error_order = int(c[12])
        log_eps = window_log_eps(rtol)
        off = c[13] * _TWO_PI
        cap = PERIOD_STORE_START
        starts = np.empty(cap + 1)
        ends = np.empty((cap + 1, 2))
        # Allocated at the first window, when its width is known (one anchor call site:
        # each inlined anchor is the whole recurrence, compiled again).
        coefs = np.empty((0, 0))
        ws_coef, ws_scratch = taylor_workspace(karg)
        starts[0], ends[0, 0], ends[0, 1] = 0.0, theta_c, v_c
        tt, a0, a1, h = 0.0, theta_c, v_c, -1.0
        for n in range(CYCLE_MAX_WINDOWS):
            coef = anchor(kind, karg, Model(beta, gamma, omega), a0, a1, ws_coef, ws_scratch, simd)
            if coef[0] != 0.0:
                break
            if n == 0:
                coefs = np.empty((cap, coef.size))
            ctl = window_control(1.0, period, math.inf, rtol, atol, error_order, log_eps)
            if h <= 0.0:
                h = _first(kind, coef, tt, a0, a1, off, omega, ctl)
            st, t_new, th, v, h_next = _adaptive(kind, coef, tt, a0, a1, off, h, ctl)
            if st != STATUS_OK:
                break
            # Element loops, not slice assignments: those compile numpy's broadcast-error
            # machinery (a few seconds of a cold start) for shapes that always agree here.
            if n == cap:
                cap *= 2
                starts2 = np.empty(cap + 1)
                ends2 = np.empty((cap + 1, 2))
                coefs2 = np.empty((cap, coef.size))
                for q in range(n + 1):
                    starts2[q] = starts[q]
                    ends2[q, 0], ends2[q, 1] = ends[q, 0], ends[q, 1]
                for q in range(n):
                    for w in range(coef.size):
                        coefs2[q, w] = coefs[q, w]
                starts, ends, coefs = starts2, ends2, coefs2
            for w in range(coef.size):
                coefs[n, w] = coef[w]
            starts[n + 1], ends[n + 1, 0], ends[n + 1, 1] = t_new, th, v
            if t_new >= period:
                return starts, ends, coefs, n + 1
            tt, a0, a1, h = t_new, th, v, h_next
        return starts, ends, coefs, -1

    return period_windows


@numba.njit(**INLINE)
def _period_lookup(kind, c, starts, ends, coefs, n, t):
    """A cycle window ``c`` at ``t`` from its stored period (:func:`_period_windows_for`).

    Returns ``(φ, θ', k)``: θ = 2πk + φ (:func:`theta_of`), k the anchor's winding
    count plus the periods passed times the winding sign (0 for a libration).  The
    value is the first window ending at or after s (its end state where it ends at
    s), as a run to s would give it.
    """
    if n < 1:
        return math.nan, math.nan, 0.0
    k_n, s = _cycle_phase(c, t)
    lo = first_window_at(starts, n, s)
    if starts[lo + 1] == s:
        th, v = ends[lo + 1, 0], ends[lo + 1, 1]
    else:
        th, v = evaluate(kind, coefs[lo], s - starts[lo])
    return th, v, c[13] + c[10] * k_n


@kernel
def _period_range_taylor(c, per, outs, lo, hi, t0):
    """:func:`_period_lookup` (kind "taylor") at the times ``outs[0][lo:hi]`` from the
    cycle window ``c`` that started at ``t0`` (``outs``: the loop's Outputs record,
    t_eval, θ, θ', winding and wrapped rows; ``per``: its stored period), the same bits,
    a block at a time (:mod:`mbm.regimes.stored_block`)."""
    t_eval = outs[0]
    starts, _, _, n = per
    blk = block_scratch()
    rates = rate_rows(per)
    sb, wb, kb = blk[0], blk[1], blk[2]
    i = 0
    for b0 in range(lo, hi, STORED_BLOCK):
        m = min(STORED_BLOCK, hi - b0)
        for q in range(m):
            periods, s = _cycle_phase(c, t_eval[b0 + q] - t0)
            i = block_window(starts, n, s, i)
            sb[q], wb[q] = s, i
            kb[q] = c[13] + c[10] * periods
        block_write(per, rates, blk, m, b0, outs)


# The stored period re-runs a period of windows (a whole controller and step): compiled
# once per kind that can reach a cycle (the adaptive ones) and called, not inlined at
# each call site (inlined, it tripled the loop's compile).
_period_windows_taylor = _period_windows_for(KIND_TAYLOR)


_period_windows_taylor24 = _period_windows_for(KIND_TAYLOR, True)


_period_windows_split = _period_windows_for(KIND_SPLIT)


@numba.njit(**INLINE)
def _period_store(kind, c, simd=False):
    """:func:`_period_windows_for` of kind ``kind`` through its compiled entry; ``simd`` (a
    constant of the caller, whose runs are of the default Taylor degree): the vector
    kernel's."""
    if kind == KIND_SPLIT:
        return call_period_store(KIND_SPLIT * OPS_PER_KIND + OP_PERIOD_STORE, (c,))
    if simd:
        return _period_windows_taylor24(c)
    return _period_windows_taylor(c)


# The lookup likewise: one compiled copy serves the loop and both dense outputs.
@kernel
def _period_lookup_taylor(c, starts, ends, coefs, n, t):
    return _period_lookup(KIND_TAYLOR, c, starts, ends, coefs, n, t)


@kernel
def _period_lookup_split(c, starts, ends, coefs, n, t):
    return _period_lookup(KIND_SPLIT, c, starts, ends, coefs, n, t)


@numba.njit(**INLINE)
def _period_value(kind, c, starts, ends, coefs, n, t):
    """:func:`_period_lookup` of kind ``kind`` through its compiled entry."""
    if kind == KIND_SPLIT:
        return call_period_value(KIND_SPLIT * OPS_PER_KIND + OP_PERIOD_VALUE, (c, starts, ends, coefs, n, t))
    return _period_lookup_taylor(c, starts, ends, coefs, n, t)


def _refine_period_for(kind, simd=False):
    """:func:`refine_period`'s body compiled for kind ``kind`` (a constant of the closure:
    numba prunes the other kinds' kernels, where a kind passed as an argument would
    compile every kind's period windows and evaluation into each cycle entry); ``simd``
    as :func:`_period_store`'s."""

    @kernel
    def refine_period_of_kind(r):
        y = r.cycle
        if r.switch.regime == REGIME_RUNNING and y.cyc_k == CYCLE_SWITCHED:
            y.cyc_T = _refined_period(kind, simd, r, y.cyc_theta, y.cyc_v, y.cyc_T, y.cyc_sign, y.cyc_wind)
            y.cyc_k = CYCLE_REFINED

    return refine_period_of_kind


@numba.njit(**INLINE)
def _refined_period(kind, simd, r, theta_c, v_c, period, sgn, wind):
    """T_c from two returns to the section re-taken from the cycle's anchor (θ_c, v_c),
    in time from the anchor and at PERIOD_REFINE_RTOL (R4): the return times T₁, T₂
    approach T_c geometrically by the cycle's multiplier μ = e^{−βT_c} (the flow's
    divergence is −β), so T_c = (T₂ − μT₁)/(1 − μ).  The averaged ``period`` (R2) where
    μ is too close to 1 for that, the re-take fails, or its answer is not within
    PERIOD_REFINE_TRUST of the averaged one."""
    m, ctl = r.model, r.control
    if not (1.0 - math.exp(-m.beta * period) >= PERIOD_REFINE_MIN_CONTRACTION):
        return period
    rt, at = min(ctl.rtol, PERIOD_REFINE_RTOL), min(ctl.atol, PERIOD_REFINE_RTOL)
    c = cycle_coef(CycleAnchor(theta_c, v_c, PERIOD_REFINE_SPAN * period, 0.0, sgn, wind), 0.0,
                   Retake(m.beta, m.gamma, m.omega, rt, at, ctl.karg, ctl.error_order))
    starts, ends, coefs, n = _period_store(kind, c, simd)
    w2 = m.omega * m.omega
    acc0 = m.gamma - w2 * math.sin(theta_c)  # θ'' = acc0 − βθ' on every level θ_c + 2πj
    t1 = t2 = math.nan
    i = 0
    for j in range(1, 3):
        level = theta_c + sgn * _TWO_PI * j
        while i < n:
            f0, f1 = ends[i, 0] - level, ends[i + 1, 0] - level
            if f1 == 0.0 or (f0 < 0.0) != (f1 < 0.0):
                sx = _crossing(kind, coefs[i], starts[i + 1] - starts[i], f0, f1, Level(level, acc0, m.beta, w2))[0]
                if j == 1:
                    t1 = starts[i] + sx
                else:
                    t2 = starts[i] + sx
                break
            i += 1
    mu = math.exp(-m.beta * (t2 - t1))
    refined = ((t2 - t1) - mu * t1) / (1.0 - mu)
    if not (abs(refined - period) <= PERIOD_REFINE_TRUST * (ctl.atol + ctl.rtol * period)):
        return period
    return refined


_refine_period_taylor = _refine_period_for(KIND_TAYLOR)


_refine_period_taylor24 = _refine_period_for(KIND_TAYLOR, True)


_refine_period_split = _refine_period_for(KIND_SPLIT)


@numba.njit(**INLINE)
def refine_period(kind, r, simd=False):
    """The running cycle's period refined once (R4), at the run's first cycle window: its
    record's T_c (:func:`_refined_period`), ``cyc_k`` CYCLE_REFINED after, through kind
    ``kind``'s compiled entry (a kind that reaches no cycle: nothing; ``simd`` as
    :func:`_period_store`'s).  Called by the cycle's window source (RS_CYCLE), so that
    the damped set's entries do not compile the period's re-take."""
    if kind == KIND_TAYLOR:
        if simd:
            _refine_period_taylor24(r)
        else:
            _refine_period_taylor(r)
    elif kind == KIND_SPLIT:
        call_refine(KIND_SPLIT * OPS_PER_KIND + OP_REFINE, (r,))


def _cycle_crossing_for(kind):
    """The return map's step at a crossing (R1, R2), compiled for kind ``kind`` (a
    constant of the closure: numba prunes the other kinds' kernels) and called from
    :func:`_watch_cycle` only in a window that crosses a section level (rare: once a
    period), so its Newton iteration is compiled once and the common window pays nothing."""

    @kernel
    def cycle_crossing(r, coef, span, cw, m0, m1):
        """The window ``span`` (a :data:`CycleSpan`: [t, t_new] from φ = y0 to (th, v))
        crossed the level between sections ``m0`` and ``m1`` (|m1 − m0| = 1): its time and
        speed into the return map in the run record ``r``, and the switch to the running
        cycle once converged (``cw``: the run's :data:`CycleWatch`)."""
        t, t_new, y0, th, v, k, off = span.t, span.t_new, span.y0, span.th, span.v, span.k, span.off
        sec_off, sec_acc, beta, gamma, omega = cw.sec_off, cw.sec_acc, cw.beta, cw.gamma, cw.omega
        t_bound, rtol, atol = cw.t_bound, cw.rtol, cw.atol
        cy = r.cycle
        sgn = 1.0 if m1 > m0 else -1.0
        level = sec_off + _TWO_PI * max(m0, m1)
        sx, vx = _crossing(kind, coef, t_new - t, y0 - level, th - level, Level(level, sec_acc, beta, omega * omega))
        tx = t + sx
        if cy.sec_n > 0 and cy.sec_sign == sgn:
            period = tx - cy.sec_t
            dv = vx - cy.sec_v
            if cy.cyc_k > 0:
                # Converged: the period averaged over CYCLE_AVERAGE_PERIODS returns (R2).
                cy.cyc_k += 1
                if cy.cyc_k > CYCLE_AVERAGE_PERIODS:
                    r.switch.regime = REGIME_RUNNING
                    r.switch.t_regime = t_new
                    cy.cyc_T = (tx - cy.cyc_t) / CYCLE_AVERAGE_PERIODS
                    cy.cyc_theta, cy.cyc_v, cy.cyc_t, cy.cyc_sign = level, vx, tx, sgn
                    cy.cyc_wind = k
            elif cy.sec_n >= 2 and cycle_switch(
                    MapStep(dv, cy.sec_dv, period - cy.sec_T), vx, off + level, cy.sec_vmax,
                    abs(gamma) + beta * cy.sec_vmax + omega * omega, (t_bound - t_new) / period,
                    Tolerance(rtol, atol)):
                cy.cyc_k, cy.cyc_t = 1, tx
            cy.sec_dv, cy.sec_T = dv, period
            cy.sec_n += 1
        else:
            cy.sec_n, cy.sec_sign, cy.cyc_k = 1, sgn, 0
        cy.sec_t, cy.sec_v, cy.sec_vmax = tx, vx, max(abs(vx), abs(v))

    return cycle_crossing


_cycle_crossing_taylor = _cycle_crossing_for(KIND_TAYLOR)
_cycle_crossing_split = _cycle_crossing_for(KIND_SPLIT)


@numba.njit(**INLINE)
def _watch_cycle(kind, r, coef, span, cw):
    """After an ordinary window ``span`` (a :data:`CycleSpan`: [t, t_new] from φ = y0 to
    (th, v)): the return map's bookkeeping in the run record ``r`` (a crossing of θ_s +
    2πm, its period and speed; the switch to the running cycle, ``r.switch.regime``, once
    converged; ``cw``: the run's :data:`CycleWatch`).  A window that crosses a level
    calls its kind's compiled :func:`_cycle_crossing_for`."""
    y0, th, v, sec_off = span.y0, span.th, span.v, cw.sec_off
    cy = r.cycle
    # The return map (mbm.regimes, R1, R2): a crossing of a saddle level
    # θ = θ_s + 2πm in this window.
    m0 = math.floor((y0 - sec_off) / _TWO_PI)
    m1 = math.floor((th - sec_off) / _TWO_PI)
    cy.sec_vmax = max(cy.sec_vmax, abs(v))
    if abs(m1 - m0) == 1.0:
        if kind == KIND_TAYLOR:
            _cycle_crossing_taylor(r, coef, span, cw, m0, m1)
        elif kind == KIND_SPLIT:
            call_crossing(KIND_SPLIT * OPS_PER_KIND + OP_CROSSING, (r, coef, span, cw, m0, m1))
    elif m1 != m0:
        cy.sec_n, cy.cyc_k = 0, 0
