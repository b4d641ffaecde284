"""Stored windows evaluated at any times: the reference evaluator of a step's windows.

:func:`evaluate_windows` evaluates the windows a run stored (``win_t``, ``win_y``,
``win_coef`` of :func:`mbm.core.loop.run`); :mod:`mbm.frontends.dense` gives its values bit for
bit with less work per time.
"""

import collections

import numba
import numpy as np

from ..compile.jit import INLINE, kernel
from .window import (
    KIND_EXACT,
    KIND_SALAS_TORQUE,
    KIND_SPLIT,
    KIND_TAYLOR,
    evaluate,
    theta_of,
)
from ..regimes.cycle import CYCLE_TAG, CYCLE_WIDTH
from ..regimes.cycle_windows import _TWO_PI, _period_store, _period_value
from ..regimes.locked import LOCKED_TAG, LOCKED_WIDTH, LockedForm, locked_at, locked_form
from ..regimes.strobe import STROBE_TAG, STROBE_WIDTH
from ..regimes.strobe_windows import _strobe_store, _strobe_stored

#: A run's stored windows: their start times (``win_t``), the θ at each start
#: (``win_y[:, 0]``), their coefficients (``win_coef``) and their count.
StoredWindows = collections.namedtuple("StoredWindows", ("starts", "start_theta", "coefs", "n"))

# Small per-window pieces are inlined into their callers, where the kind is a constant
# (numba prunes the other kinds' branches before compiling); large ones are compiled
# once per kind and called.


@numba.njit(**INLINE)
def _same_row(coefs, i, r, width):
    """Whether rows ``i`` and ``r`` of ``coefs`` agree in their first ``width`` entries."""
    for w in range(width):
        if coefs[i, w] != coefs[r, w]:
            return False
    return True


@numba.njit(**INLINE)
def _evaluate_windows(kind, windows, direction, t, out_theta, out_v):
    """Evaluate a run's stored windows (``windows``, a :data:`StoredWindows` of ``win_t``,
    ``win_y``, ``win_coef`` of :func:`mbm.core.loop.run`) at ``t``.

    Window i covers [starts[i], starts[i+1]]; a time on an interior boundary takes the
    later window (whose anchor is the earlier window's end value), the run's end the
    last window.  Times outside the run are extrapolated by the nearest window.  A
    window of a wrapping kind is anchored at φ (TWO_PI_A); its winding count is
    recovered from its start's θ, ``start_theta[i]`` (``win_y[i, 0]``), so the value
    is the run's own θ = 2πk + φ to the bit.
    """
    starts, start_theta, coefs, n = windows
    # The stored period of the cycle windows met (R3): built once (they share it).
    per_n = -2
    per_starts = np.empty(0)
    per_ends = np.empty((0, 2))
    per_coefs = np.empty((0, 0))
    # The stored drive period of the phase-locked windows met (S6): built once per anchor.
    str_n, str_row = -2, 0
    str_starts = np.empty(0)
    str_ends = np.empty((0, 3))
    str_coefs = np.empty((0, 0))
    # The locked window met last (L2): its row and constants.
    lk_row, lk = -1, LockedForm(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, False, 0.0, 0.0, 0.0, 0.0, 0.0)
    for j in range(t.size):
        tj = t[j]
        # The last window whose start is not after tj (bisection: windows_per_step=None
        # stores a whole run).
        lo, hi = 0, n - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if direction * (tj - starts[mid]) >= 0.0:
                lo = mid
            else:
                hi = mid - 1
        i = lo
        s = tj - starts[i]
        if coefs.shape[1] >= STROBE_WIDTH and coefs[i, 0] == STROBE_TAG:
            # A phase-locked window: the stored drive period from its anchor, at the
            # absolute time (S6; at most a period of windows).
            if str_n == -2 or not _same_row(coefs, i, str_row, STROBE_WIDTH):
                str_starts, str_ends, str_coefs, str_n = _strobe_store(kind, coefs[i])
                str_row = i
            a, b, kc = _strobe_stored(kind, coefs[i], str_starts, str_ends, str_coefs, str_n, tj)
            out_theta[j] = theta_of(kc, a)
            out_v[j] = b
            continue
        if (kind == KIND_TAYLOR or kind == KIND_SPLIT) and coefs.shape[1] >= CYCLE_WIDTH \
                and coefs[i, 0] == CYCLE_TAG:
            # A cycle window: the stored period, shifted.
            if per_n == -2:
                per_starts, per_ends, per_coefs, per_n = _period_store(kind, coefs[i])
            a, b, kc = _period_value(kind, coefs[i], per_starts, per_ends, per_coefs, per_n, s)
            out_theta[j] = theta_of(kc, a)
            out_v[j] = b
            continue
        if coefs.shape[1] >= LOCKED_WIDTH and coefs[i, 0] == LOCKED_TAG:
            # A locked window (mbm.regimes): the closed form, cheap at any t, its constants
            # formed once per window met (locked_eval's bits).
            if i != lk_row:
                lk, lk_row = locked_form(coefs[i]), i
            a, b = locked_at(lk, s)
            phi0 = coefs[i, 1]
        else:
            a, b = evaluate(kind, coefs[i], s)
            phi0 = evaluate(kind, coefs[i], 0.0)[0]
        ki = 0.0
        if kind == KIND_TAYLOR or kind == KIND_SPLIT:  # WRAPPING_KINDS
            ki = float(round((start_theta[i] - phi0) / _TWO_PI))
        out_theta[j] = theta_of(ki, a)
        out_v[j] = b


@kernel
def _evaluate_windows_taylor(starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    _evaluate_windows(KIND_TAYLOR, StoredWindows(starts, start_theta, coefs, n), direction, t, out_theta, out_v)


@kernel
def _evaluate_windows_exact(starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    _evaluate_windows(KIND_EXACT, StoredWindows(starts, start_theta, coefs, n), direction, t, out_theta, out_v)


@kernel
def _evaluate_windows_salas_torque(starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    _evaluate_windows(KIND_SALAS_TORQUE, StoredWindows(starts, start_theta, coefs, n), direction, t, out_theta, out_v)


@kernel
def _evaluate_windows_split(starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    _evaluate_windows(KIND_SPLIT, StoredWindows(starts, start_theta, coefs, n), direction, t, out_theta, out_v)


_EVALUATORS = {KIND_TAYLOR: _evaluate_windows_taylor, KIND_EXACT: _evaluate_windows_exact,
               KIND_SALAS_TORQUE: _evaluate_windows_salas_torque, KIND_SPLIT: _evaluate_windows_split}


def evaluate_windows(kind, starts, start_theta, coefs, n, direction, t, *, out_theta, out_v):
    """Evaluate ``n`` stored windows (``win_t``, ``win_y[:, 0]``, ``win_coef`` of :func:`run`)
    of kind ``kind`` at times ``t`` (see :func:`_evaluate_windows`)."""
    _EVALUATORS[kind](starts, start_theta, coefs, n, direction, t, out_theta, out_v)
