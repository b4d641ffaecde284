"""A block of output times from a stored period's windows, in one compiled call.

A stored period (the running cycle's and libration's, R3, C3; the drive period of the
phase-locked regime, S6) is a list of Taylor windows from its anchor: ``starts``
(n + 1), ``ends`` (row i + 1 the state where window i ended), ``coefs``.  A value at
s (the time within the period) is the first window ending at or after s, evaluated
at s − its start, or its end state where it ends at s, as a run to s gives it.  The
regimes' range kernels reduce each time to ``(s, window, winding count)`` here and
write the values: sorted times walk the windows (:func:`block_window`), and a
window's times go to taylor_eval_range four at once (:func:`block_write`), the same
operations per time as a lone evaluation (the same bits).
"""

import math

import numba
import numpy as np

from ..approximants.taylor import taylor_eval_range
from ..compile.jit import INLINE
from ..core.window import theta_of, wrap

# Output times per block of a range kernel: its scratch rows (a few kB), long enough
# that a window's times go four at once, short enough to stay in the first-level cache.
STORED_BLOCK = 256


@numba.njit(**INLINE)
def block_scratch():
    """``(s, window, winding, φ, θ')`` rows of one block (STORED_BLOCK each)."""
    return (np.empty(STORED_BLOCK), np.empty(STORED_BLOCK, np.int64), np.empty(STORED_BLOCK),
            np.empty(STORED_BLOCK), np.empty(STORED_BLOCK))


@numba.njit(**INLINE)
def block_window(starts, n, s, i):
    """The first of ``n`` windows (``starts``) ending at or after ``s``: walked up from
    window ``i`` when that starts before s (sorted times), else bisected; ``n`` when
    none does (a period that stopped short)."""
    if n < 1 or starts[n] < s:
        return n
    if i < n and starts[i] < s:
        while starts[i + 1] < s:
            i += 1
        return i
    lo, hi = 0, n - 1
    while lo < hi:
        mid = (lo + hi) // 2
        if starts[mid + 1] >= s:
            hi = mid
        else:
            lo = mid + 1
    return lo


@numba.njit(**INLINE)
def block_write(per, blk, m, b0, outs):
    """The values of a block's ``m`` times (``blk``: block_scratch's rows, s, window and
    winding count filled) from the stored period ``per`` = (starts, ends, coefs, n),
    written to rows ``b0 .. b0 + m`` of ``outs`` (t_eval, θ, θ', winding, wrapped):
    θ = 2πk + φ, or φ wrapped and its winding count; NaN past the period's windows."""
    starts, ends, coefs, n = per
    sb, wb, kb, thb, vb = blk
    _, out_theta, out_v, out_w, wrapped = outs
    q = 0
    while q < m:
        # A run of times in one window.
        i = wb[q]
        q2 = q + 1
        while q2 < m and wb[q2] == i:
            q2 += 1
        if i < n:
            taylor_eval_range(coefs[i], starts[i], sb, q, q2, thb, vb)
        for r in range(q, q2):
            if i >= n:
                thb[r], vb[r], kb[r] = math.nan, math.nan, 0.0
            elif starts[i + 1] == sb[r]:
                thb[r], vb[r] = ends[i + 1, 0], ends[i + 1, 1]
            # (Written here, not by a call taking the arrays: their reference counts
            # doubled an output's cost.)
            if wrapped:
                out_w[b0 + r], out_theta[b0 + r] = wrap(kb[r], thb[r])
            else:
                out_theta[b0 + r] = theta_of(kb[r], thb[r])
            out_v[b0 + r] = vb[r]
        q = q2
