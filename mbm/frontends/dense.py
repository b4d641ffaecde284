"""The dense output of a step of stored windows, compiled: what ``sol(t)`` of :class:`mbm.MBM` runs.

The values of :func:`mbm.core.stored.evaluate_windows` bit for bit (each time takes the same
window, the same formula and the same floating-point operations), for less work per
time:

* a window's winding count (recovered from its start's θ and its anchor, as there)
  is computed once per run of consecutive times in that window, not once per time;
* a time first tries the window of the time before it (and the next), and is
  bisected only when neither holds it, so times in order (solve_ivp's ``t_eval``)
  find their window in a step;
* a Taylor window's times go four at a time
  (:func:`mbm.approximants.taylor.taylor_eval_range`: the Horner steps of its eval
  kernel, interleaved).

A kind of :data:`mbm.core.window.COMPILED_KINDS` without an entry here is evaluated by
:func:`mbm.core.stored.evaluate_windows` itself (:func:`evaluate_windows_into`).
"""

import collections
import math

import numba
import numpy as np

from ..compile.jit import INLINE
from ..core import stored, window
from ..core.kind_ops import OP_EVAL_RANGE, OPS_PER_KIND, call_eval_range
from ..approximants.taylor import taylor_eval_range
from ..approximants.taylor_series import HEADER
from ..approximants.taylor_simd import SIMD_ORDER
from ..core.window import KIND_EXACT, KIND_SALAS_TORQUE, KIND_SPLIT, KIND_TAYLOR, evaluate, theta_of
from ..core.loop import RS_CYCLE, RS_PLAIN, RS_STROBE, Outputs
from ..regimes.cycle_windows import _period_range_taylor, _period_store, _period_value
from ..regimes.strobe_windows import _strobe_range_taylor, _strobe_value, _strobe_windows_taylor
from ..regimes import (
    REGIME_LIBRATION,
    REGIME_PHASE_LOCKED,
    REGIME_RUNNING,
)
from ..regimes import CYCLE_TAG, CYCLE_WIDTH, LOCKED_TAG, LOCKED_WIDTH, STROBE_TAG, STROBE_WIDTH
from ..regimes.locked import locked_eval_range

__all__ = ["evaluate_windows_into", "evaluate_windows_at", "evaluators", "dense_set", "DENSE_TABLE"]

# One turn, as the loop's winding count is recovered (mbm.core.stored._evaluate_windows).
_TWO_PI = 2.0 * math.pi


@numba.njit(**INLINE)
def _holds(starts, n, direction, i, tj):
    # Whether window i is the last one whose start is not after tj.
    return direction * (tj - starts[i]) >= 0.0 and (i == n - 1 or direction * (tj - starts[i + 1]) < 0.0)


@numba.njit(**INLINE)
def _find(starts, n, direction, i, tj):
    """The window of time ``tj``: the last whose start is not after it (window 0 when
    none is), as :func:`mbm.core.stored._evaluate_windows`' bisection finds it.

    The starts are monotone in ``direction``, so the predicate "start not after tj"
    holds for a prefix of the windows: a window that holds it with its successor
    failing it is the last of that prefix, the bisection's answer.  Window ``i`` (the
    previous time's) and ``i + 1`` are tried first; past them the bisection starts
    from ``i`` when the prefix reaches it (times in order), else from window 0.
    """
    if _holds(starts, n, direction, i, tj):
        return i
    if i + 1 < n and _holds(starts, n, direction, i + 1, tj):
        return i + 1
    lo, hi = 0, n - 1
    if direction * (tj - starts[i]) >= 0.0:
        lo = i
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if direction * (tj - starts[mid]) >= 0.0:
            lo = mid
        else:
            hi = mid - 1
    return lo


@numba.njit(**INLINE)
def _winding(kind, c, start_theta_i):
    # The winding count of a window anchored at φ (mbm.core.stored._evaluate_windows): from its
    # start's θ and the anchor's φ (a locked window stores θ₀ at c[1]).
    if not (kind == KIND_TAYLOR or kind == KIND_SPLIT):  # window.WRAPPING_KINDS
        return 0.0
    if c.size >= LOCKED_WIDTH and c[0] == LOCKED_TAG:
        phi0 = c[1]
    elif kind == KIND_TAYLOR:
        phi0 = c[HEADER]  # evaluate at 0: a₀ + 0·p, a₀ itself (taylor_eval_kernel)
    else:
        phi0 = evaluate(kind, c, 0.0)[0]
    return float(round((start_theta_i - phi0) / _TWO_PI))


@numba.njit(**INLINE)
def _strobe_run(kind, c, t, lo, hi, out_theta, out_v):
    # A phase-locked window: the stored period (q drive periods) from its anchor, at the
    # absolute time (mbm.regimes S6, S7).
    if kind == KIND_TAYLOR and hi - lo > 1:
        # The period's windows taken once for these times, walked (sorted) in one call.
        per = _strobe_windows_taylor(c)
        _strobe_range_taylor(c, per, Outputs(t, out_theta, out_v, out_theta, False), lo, hi)
        return
    for q in range(lo, hi):
        a, b, kc = _strobe_value(kind, c, t[q])
        out_theta[q] = theta_of(kc, a)
        out_v[q] = b


#: The times ``t[lo:hi]`` that one window gives.
Rows = collections.namedtuple("Rows", ("lo", "hi"))


@numba.njit(**INLINE)
def _cycle_run(kind, simd, c, t0, t, rows, out_theta, out_v):
    # A cycle window: the stored period (re-taken once for these times), shifted (its
    # own winding count).
    lo, hi = rows
    p_starts, p_ends, p_coefs, p_n = _period_store(kind, c, simd)
    if kind == KIND_TAYLOR:
        # These times in one call, sorted ones walking the period's windows.
        _period_range_taylor(c, (p_starts, p_ends, p_coefs, p_n), Outputs(t, out_theta, out_v, out_theta, False),
                             lo, hi, t0)
        return
    for q in range(lo, hi):
        a, b, kc = _period_value(kind, c, p_starts, p_ends, p_coefs, p_n, t[q] - t0)
        out_theta[q] = theta_of(kc, a)
        out_v[q] = b


@numba.njit(**INLINE)
def _nan_run(lo, hi, out_theta, out_v):
    # A stored period of a set the entry lacks: NaN, never another formula.
    for q in range(lo, hi):
        out_theta[q] = theta_of(0.0, math.nan)
        out_v[q] = math.nan


@numba.njit(**INLINE)
def _plain_run(kind, c, t0, start_theta_i, t, rows, out_theta, out_v):
    # An ordinary or locked window.
    lo, hi = rows
    ki = _winding(kind, c, start_theta_i)
    if c.size >= LOCKED_WIDTH and c[0] == LOCKED_TAG:
        locked_eval_range(c, t0, t, lo, hi, out_theta, out_v)
        if ki != 0.0:
            for q in range(lo, hi):
                out_theta[q] = theta_of(ki, out_theta[q])
    elif kind == KIND_TAYLOR:
        taylor_eval_range(c, t0, t, lo, hi, out_theta, out_v)
        if ki != 0.0:
            for q in range(lo, hi):
                out_theta[q] = theta_of(ki, out_theta[q])
    elif kind == KIND_EXACT:
        # The window's times in one call (the flow's table where they are many: the
        # same bits as per time), through the kinds' table as the loop's emit_exact.
        call_eval_range(KIND_EXACT * OPS_PER_KIND + OP_EVAL_RANGE, (c, t0, t, lo, hi, out_theta, out_v))
        if ki != 0.0:
            for q in range(lo, hi):
                out_theta[q] = theta_of(ki, out_theta[q])
    else:
        for q in range(lo, hi):
            a, b = evaluate(kind, c, t[q] - t0)
            out_theta[q] = theta_of(ki, a)
            out_v[q] = b


def _entries(dset, simd=False):
    """``(into, at)`` for windows of any kind (their first argument) with the stored
    periods of ``dset``; ``simd``: of kind "taylor" at its default degree alone (a stored
    period re-taken by the vector kernel, :func:`mbm.regimes.cycle_windows._period_store`),
    the entries the other kinds share.

    Both are constants of the closures, and the closures' own bodies branch on them:
    numba prunes those branches before it inlines the calls in them, so an entry
    inlines only the window forms its set holds (a stored period's form is large; a
    branch inside an inlined helper would be pruned only after its calls were inlined).
    The kind is an argument: kind "taylor"'s kernels are called directly, the other
    kinds' through the table of :mod:`mbm.core.kind_ops`, so a further kind compiles
    only its own formulas.  A window is evaluated as :func:`mbm.core.stored._evaluate_windows`
    evaluates it per time; a window of a stored period the entry lacks is NaN, never
    another formula.
    """

    @numba.njit(cache=True)
    def into(kind, starts, start_theta, coefs, n, direction, t, out):
        out_theta, out_v = out[0], out[1]
        m = t.size
        i = 0
        j = np.int64(0)  # not a literal 0: that would compile the window kernels twice
        while j < m:
            # A run of times per window.
            i = _find(starts, n, direction, i, t[j])
            # The window's bounds read once (_holds for each time: the same test).
            lo_t, hi_t = starts[i], starts[i + 1] if i < n - 1 else direction * math.inf
            j2 = j + 1
            while j2 < m and direction * (t[j2] - lo_t) >= 0.0 and direction * (t[j2] - hi_t) < 0.0:
                j2 += 1
            c = coefs[i]
            if kind == KIND_TAYLOR and c.size >= STROBE_WIDTH and c[0] == STROBE_TAG:
                if dset == RS_STROBE:
                    _strobe_run(kind, c, t, j, j2, out_theta, out_v)
                else:
                    _nan_run(j, j2, out_theta, out_v)
            elif (kind == KIND_TAYLOR or kind == KIND_SPLIT) and c.size >= CYCLE_WIDTH and c[0] == CYCLE_TAG:
                if dset == RS_CYCLE:
                    _cycle_run(kind, simd, c, starts[i], t, Rows(j, j2), out_theta, out_v)
                else:
                    _nan_run(j, j2, out_theta, out_v)
            else:
                _plain_run(kind, c, starts[i], start_theta[i], t, Rows(j, j2), out_theta, out_v)
            j = j2

    @numba.njit(cache=True)
    def at(kind, starts, start_theta, coefs, n, direction, tj):
        # One time: a new array [θ, θ'] (into's branches, for t = [tj]).
        i = _find(starts, n, direction, 0, tj)
        # Typed int64, as into's (a literal index compiles the kernels a second time).
        lo, hi = np.int64(0), np.int64(1)
        t = np.empty(1)
        t[0] = tj
        out = np.empty((2, 1))
        c = coefs[i]
        if kind == KIND_TAYLOR and c.size >= STROBE_WIDTH and c[0] == STROBE_TAG:
            if dset == RS_STROBE:
                _strobe_run(kind, c, t, lo, hi, out[0], out[1])
            else:
                _nan_run(lo, hi, out[0], out[1])
        elif (kind == KIND_TAYLOR or kind == KIND_SPLIT) and c.size >= CYCLE_WIDTH and c[0] == CYCLE_TAG:
            if dset == RS_CYCLE:
                _cycle_run(kind, simd, c, starts[i], t, Rows(lo, hi), out[0], out[1])
            else:
                _nan_run(lo, hi, out[0], out[1])
        else:
            _plain_run(kind, c, starts[i], start_theta[i], t, Rows(lo, hi), out[0], out[1])
        y = np.empty(2)
        y[0] = out[0, 0]
        y[1] = out[1, 0]
        return y

    return into, at


#: The sets of windows a dense output evaluates: ordinary and locked (RS_PLAIN), and
#: with them a stored period (RS_CYCLE, RS_STROBE: the kinds that reach it).
DENSE_TABLE = tuple(
    [(kd, RS_PLAIN) for kd in (KIND_TAYLOR, KIND_EXACT, KIND_SALAS_TORQUE, KIND_SPLIT)]
    + [(KIND_TAYLOR, RS_CYCLE), (KIND_SPLIT, RS_CYCLE), (KIND_TAYLOR, RS_STROBE)]
)
#: The entries per (stored-period set, default degree): ``simd`` differs only where a
#: stored period is re-taken (RS_CYCLE).
_ENTRIES = {(RS_PLAIN, False): _entries(RS_PLAIN), (RS_STROBE, False): _entries(RS_STROBE),
            (RS_CYCLE, False): _entries(RS_CYCLE), (RS_CYCLE, True): _entries(RS_CYCLE, True)}


def _fallback_into(starts, start_theta, coefs, n, direction, t, out, kind):
    # A kind without an entry here: mbm.core.loop's own evaluator.
    stored.evaluate_windows(kind, starts, np.ascontiguousarray(start_theta), coefs, n, direction, t, out_theta=out[0], out_v=out[1])


def _fallback_at(starts, start_theta, coefs, n, direction, tj, kind):
    out = np.empty((2, 1))
    _fallback_into(starts, start_theta, coefs, n, direction, np.array([tj]), out, kind)
    return out[:, 0].copy()


#: The entry per (kind, set, default degree) of DENSE_TABLE: the other kinds take the
#: default Taylor degree's (which a default Taylor run has compiled); one look-up per
#: step of solve_ivp.
_EVALUATORS = {(kd, ds, simd): _ENTRIES[(ds, ds == RS_CYCLE and (simd or kd != KIND_TAYLOR))]
               for kd, ds in DENSE_TABLE for simd in (False, True)}


def dense_set(regime):
    """The stored-period set (a key of :data:`DENSE_TABLE` with the kind) that evaluates
    the windows of a run whose regime is ``regime`` now (its windows so far: ordinary,
    locked, and the stored period it switched to)."""
    if regime == REGIME_RUNNING or regime == REGIME_LIBRATION:
        return RS_CYCLE
    if regime == REGIME_PHASE_LOCKED:
        return RS_STROBE
    return RS_PLAIN


def _windows_set(coefs, n):
    # The stored-period set of n stored windows, read off their tags (c[0]).
    if coefs.ndim != 2 or coefs.shape[1] < min(CYCLE_WIDTH, STROBE_WIDTH) or n < 1:
        return RS_PLAIN
    tags = coefs[:n, 0]
    if coefs.shape[1] >= STROBE_WIDTH and np.any(tags == STROBE_TAG):
        return RS_STROBE
    if np.any(tags == CYCLE_TAG):
        return RS_CYCLE
    return RS_PLAIN


def evaluators(kind, dset=RS_PLAIN, simd=False):
    """``(into, at)``: the entries of :func:`evaluate_windows_into` and
    :func:`evaluate_windows_at` for a caller that evaluates one kind many times, called
    with the kind id first (``into(kind, starts, start_theta, coefs, n, direction, t,
    out)``, ``at(kind, ..., tj)``); ``dset`` (:func:`dense_set`) names the stored
    periods the windows may hold (RS_PLAIN: none); ``simd``: windows of kind "taylor"
    at its default degree SIMD_ORDER alone (any degree where False)."""
    entry = _EVALUATORS.get((kind, dset, simd))
    if entry is not None:
        return entry
    return (lambda kd, *a: _fallback_into(*a, kd)), (lambda kd, *a: _fallback_at(*a, kd))


def evaluate_windows_into(kind, starts, start_theta, coefs, n, direction, t, out):
    """``n`` stored windows of kind ``kind`` at times ``t``, written to ``out``.

    Parameters
    ----------
    kind : int
        A kind id of :data:`mbm.core.window.COMPILED_KINDS`.
    starts : ndarray, shape (n + 1,)
        Window i covers [starts[i], starts[i + 1]] (``win_t`` of :func:`mbm.core.loop.run`).
    start_theta : ndarray, shape (n + 1,)
        θ at the starts (``win_y[:, 0]``; a strided view is accepted).
    coefs : ndarray, shape (n, width)
        The windows' coefficient vectors (``win_coef``).
    n : int
        Windows, ≥ 1.
    direction : float
        +1.0 or −1.0, the direction of the run.
    t : ndarray of float64, shape (m,), C-contiguous
        Times, in any order (in order is cheapest).
    out : ndarray of float64, shape (2, m), C-contiguous
        Filled with θ (row 0) and θ' (row 1): the values of
        :func:`mbm.core.stored.evaluate_windows` bit for bit.
    """
    evaluators(kind, _windows_set(coefs, n))[0](kind, starts, start_theta, coefs, n, direction, t, out)


def evaluate_windows_at(kind, starts, start_theta, coefs, n, direction, tj):
    """:func:`evaluate_windows_into` at one time ``tj`` (a float): a new array ``[θ, θ']``."""
    return evaluators(kind, _windows_set(coefs, n))[1](kind, starts, start_theta, coefs, n, direction, tj)
