"""A block of output times from a stored period's windows, in one compiled call.

A stored period (the running cycle's and libration's, R3, C3; the drive period of the
phase-locked regime, S6) is a list of Taylor windows from its anchor: ``starts``
(n + 1), ``ends`` (row i + 1 the state where window i ended), ``coefs``.  A value at
s (the time within the period) is the first window ending at or after s, evaluated
at s − its start, or its end state where it ends at s, as a run to s gives it.  The
regimes' range kernels reduce each time to ``(s, window, winding count)`` here and
write the values: sorted times walk the windows (:func:`block_window`), and four times
are evaluated at once whatever their windows (:func:`block_values`), the same
operations per time as a lone evaluation (taylor_eval_kernel: the same bits).
"""

import math

import numba
import numpy as np

from ..approximants.taylor import HEADER as TAYLOR_HEADER
from ..approximants.taylor import taylor_eval_kernel
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
    return first_window_at(starts, n, s)


@numba.njit(**INLINE)
def first_window_at(starts, n, s):
    """The first of ``n`` (≥ 1) windows (window i covers [starts[i], starts[i + 1]]) that
    ends at or after ``s``, by bisection; the last where none does."""
    lo, hi = 0, n - 1
    while lo < hi:
        mid = (lo + hi) // 2
        if starts[mid + 1] >= s:
            hi = mid
        else:
            lo = mid + 1
    return lo


@numba.njit(**INLINE)
def rate_rows(per):
    """k·a_k of the stored period ``per``'s windows (row i, column TAYLOR_HEADER + k): the
    terms of θ''s Horner chain in :func:`block_values`, formed once per call instead of
    once per output (the same products: the same bits)."""
    _, _, coefs, n = per
    rates = np.empty((max(n, 0), coefs.shape[1]))
    for i in range(n):
        for k in range(1, int(coefs[i, 1]) + 1):
            rates[i, TAYLOR_HEADER + k] = k * coefs[i, TAYLOR_HEADER + k]
    return rates


@numba.njit(**INLINE)
def _same_degree(coefs, n, i0, i1, i2, i3):
    """Whether windows i0..i3 are all stored (below n) and of one degree."""
    if max(max(i0, i1), max(i2, i3)) >= n or min(min(i0, i1), min(i2, i3)) < 0:
        return False
    d = coefs[i0, 1]
    return coefs[i1, 1] == d and coefs[i2, 1] == d and coefs[i3, 1] == d


@numba.njit(**INLINE)
def block_values(per, rates, blk, m):
    """φ, θ' of a block's ``m`` times into ``blk``'s rows 3 and 4, each in its window (row
    1; NaN rows not written where it is not stored; ``rates``: :func:`rate_rows` of
    ``per``): taylor_eval_kernel's steps, four
    times at once whatever their windows (their eight Horner chains overlap instead of
    each waiting on its own latency; times spread over many windows are the common
    case, a few outputs per window)."""
    starts, _, coefs, n = per
    sb, wb, _, thb, vb = blk
    q = 0
    while q < m:
        if q + 4 <= m and _same_degree(coefs, n, wb[q], wb[q + 1], wb[q + 2], wb[q + 3]):
            i0, i1, i2, i3 = wb[q], wb[q + 1], wb[q + 2], wb[q + 3]
            s0, s1, s2, s3 = sb[q] - starts[i0], sb[q + 1] - starts[i1], sb[q + 2] - starts[i2], sb[q + 3] - starts[i3]
            deg = int(coefs[i0, 1])
            top = TAYLOR_HEADER + deg
            p0, p1, p2, p3 = coefs[i0, top], coefs[i1, top], coefs[i2, top], coefs[i3, top]
            d0, d1, d2, d3 = deg * p0, deg * p1, deg * p2, deg * p3
            for k in range(deg - 1, 1, -1):
                h = TAYLOR_HEADER + k
                p0 = p0 * s0 + coefs[i0, h]
                p1 = p1 * s1 + coefs[i1, h]
                p2 = p2 * s2 + coefs[i2, h]
                p3 = p3 * s3 + coefs[i3, h]
                d0 = d0 * s0 + rates[i0, h]
                d1 = d1 * s1 + rates[i1, h]
                d2 = d2 * s2 + rates[i2, h]
                d3 = d3 * s3 + rates[i3, h]
            h = TAYLOR_HEADER + 1
            thb[q] = coefs[i0, TAYLOR_HEADER] + s0 * (p0 * s0 + coefs[i0, h])
            thb[q + 1] = coefs[i1, TAYLOR_HEADER] + s1 * (p1 * s1 + coefs[i1, h])
            thb[q + 2] = coefs[i2, TAYLOR_HEADER] + s2 * (p2 * s2 + coefs[i2, h])
            thb[q + 3] = coefs[i3, TAYLOR_HEADER] + s3 * (p3 * s3 + coefs[i3, h])
            vb[q], vb[q + 1] = d0 * s0 + coefs[i0, h], d1 * s1 + coefs[i1, h]
            vb[q + 2], vb[q + 3] = d2 * s2 + coefs[i2, h], d3 * s3 + coefs[i3, h]
            q += 4
        else:
            i = wb[q]
            if 0 <= i < n:
                thb[q], vb[q] = taylor_eval_kernel(coefs[i], sb[q] - starts[i])
            q += 1


@numba.njit(**INLINE)
def block_write(per, rates, blk, m, b0, outs):
    """The values of a block's ``m`` times (``blk``: block_scratch's rows, s, window and
    winding count filled) from the stored period ``per`` = (starts, ends, coefs, n) and
    its :func:`rate_rows`,
    written to rows ``b0 .. b0 + m`` of ``outs`` (t_eval, θ, θ', winding, wrapped):
    θ = 2πk + φ, or φ wrapped and its winding count; NaN past the period's windows."""
    starts, ends, _, n = per
    sb, wb, kb, thb, vb = blk
    _, out_theta, out_v, out_w, wrapped = outs
    block_values(per, rates, blk, m)
    for r in range(m):
        i = wb[r]
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
