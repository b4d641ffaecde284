r"""The tangent pass: error transport and sensitivities along a run's windows.

A run of the moving boundary method takes windows [t_n, t_{n+1}], each anchored at the
state y_n it reached.  Per window this pass finds

* the signed local error d_n = y_{n+1} − φ(t_{n+1}; y_n) of what the run computed,
* the tangent map Φ_n = ∂φ(t_{n+1}; y_n)/∂y_n and the parameter columns P_n,

and transports the error and the sensitivities S = ∂y/∂(y₀, p) linearly:

    e_{n+1} = Φ_n e_n + d_n,        S_{n+1} = Φ_n S_n + P_n,

with the same inside a window at every output time (the output's own local error in
place of d_n).  e estimates y_computed − y_true to first order (only first order where Φ
varies across the error's size: near a separatrix, on a chaotic orbit once e is no longer
small: :doc:`/theory/error_estimate`).  The windows come in three sorts:

* the run's own Taylor windows (their coefficients stored by the run): Φ and P by the
  variational recurrence on those coefficients (:func:`mbm.tangent.series.columns`), at
  TANGENT_DEGREE for the error alone and the run's degree for sensitivities, and d_n from
  the series' first two neglected terms, which the run computed for its controller;
* a regime's windows (locked, a stored period): :mod:`mbm.tangent.regimes`;
* any other (another kind, an exact flow): the reference, a Taylor series of degree
  REF_DEGREE from y_n with its variational columns, in sub-windows at REF_SHARPNESS of the
  tolerance (:mod:`mbm.tangent.reference`); d_n = y_{n+1} − the reference's end, not
  measured for an exact flow (exact to round-off, where the reference's own error would
  be what is measured).
"""

import collections
import math

import numpy as np
from numba import njit

from ..approximants.taylor_series import _INV_K12, HEADER
from ..compile.jit import INLINE
from .reference import reference_eps, reference_step
from .regimes import expm2, linear_columns, linear_forcing, period_at, period_map, period_store
from .series import COL_THETA0, COL_V0, columns, row_value_rate, tangent_series, value_rate_to

#: Windows per compiled call of the pass: Ctrl-C is honoured between calls (a few ms each).
CHUNK_WINDOWS = 4096
#: Degree of the tangent map on the run's own Taylor windows when only the error is
#: estimated: at the run's window (h/ρ ≈ rtol^(1/24) ≤ 0.75 at rtol ≤ 1e-3) its
#: truncation is below 3 % of Φ, plenty for an error bar; sensitivities take the run's degree.
TANGENT_DEGREE = 12

_TWO_PI = 2.0 * math.pi

#: The run a pass follows: the window ends ``t`` (n + 1,) and states ``y`` (n + 1, 2), the
#: windows' stored coefficients ``coef`` (n, width; width 0: none) and the outputs
#: ``t_out`` (m,) and ``y_out`` (2 rows, m) at which to report.
Track = collections.namedtuple("Track", ("t", "y", "coef", "t_out", "y_out"))

#: What the pass is told besides the run: the run's ``tol`` = (rtol, atol); ``t_measured``:
#: the windows starting before it have their local errors measured (± inf: all or none);
#: ``t_taylor``: those before it whose stored coefficients are a Taylor window of degree
#: ``n_order`` are followed on those coefficients (later ones are a regime's), their columns
#: to degree ``kt``.
#: ``period``: the stored period of the run's regime (nan: none).
Control = collections.namedtuple("Control", ("tol", "t_measured", "t_taylor", "n_order", "kt", "period"))

#: One window as the pass follows it.
#: ``lock``: (θ*, ω_l², sharp) of a locked window (its rest taken by the linear flow once
#: settled: :mod:`mbm.tangent.regimes`; sharp ≠ 0: settled for the sensitivities' accuracy
#: too), else (nan, nan, 0).
Span = collections.namedtuple("Span", ("t0", "t1", "direction", "measured", "kt", "tol", "lock"))

#: The transported error ``e`` (2,) and sensitivities ``S`` (2, n_sens), and their values
#: at a time inside the window (``e2``, ``S2``).
Transported = collections.namedtuple("Transported", ("e", "S", "e2", "S2"))

#: Where the pass writes: ``err`` (2, m) and ``sens`` (n_sens, 2, m); ``rows`` (n_sens,):
#: each sensitivity's row in the series' columns (0: θ₀'s, 1: θ̇₀'s, ≥ 2: a parameter's).
Report = collections.namedtuple("Report", ("err", "sens", "rows"))

#: Where the pass stands: the window ``n``, the next output ``j`` and the direction of
#: time (±1).
Cursor = collections.namedtuple("Cursor", ("n", "j", "direction"))


@njit(**INLINE)
def _phi_at(d, nt, s):
    # Φ(s) = (∂θ/∂θ₀, ∂θ'/∂θ₀, ∂θ/∂θ̇₀, ∂θ'/∂θ̇₀) from the columns' series to degree nt.
    p00, p10 = row_value_rate(d, 0, nt, s)
    p01, p11 = row_value_rate(d, 1, nt, s)
    return p00, p10, p01, p11


@njit(**INLINE)
def _columns_at(ws, nt, s, rows, tr, vr):
    # Φ(s)·e into tr.e2 and Φ(s)·S + P(s) into tr.S2, from the columns' series to degree nt
    # (their values and rates into vr); returns θ's value and rate at s.  θ's and every
    # column's Horner chains side by side (value_rate's operations each).
    a, d = ws[0], ws[5]
    tp = a[nt]
    tq = 0.0
    for r in range(d.shape[0]):
        vr[0, r] = d[r, nt]
        vr[1, r] = 0.0
    for k in range(nt - 1, -1, -1):
        tq = tq * s + tp
        tp = tp * s + a[k]
        for r in range(d.shape[0]):
            p = vr[0, r]
            vr[1, r] = vr[1, r] * s + p
            vr[0, r] = p * s + d[r, k]
    e, S, out_e, out_s = tr.e, tr.S, tr.e2, tr.S2
    p00, p10, p01, p11 = vr[0, 0], vr[1, 0], vr[0, 1], vr[1, 1]
    out_e[0] = p00 * e[0] + p01 * e[1]
    out_e[1] = p10 * e[0] + p11 * e[1]
    for i in range(rows.size):
        x0 = p00 * S[0, i] + p01 * S[1, i]
        x1 = p10 * S[0, i] + p11 * S[1, i]
        if rows[i] >= 2:
            x0 += vr[0, rows[i]]
            x1 += vr[1, rows[i]]
        out_s[0, i] = x0
        out_s[1, i] = x1
    return tp, tq


@njit(**INLINE)
def _wrapped(dtheta):
    # A difference of angles, to the nearest turn (the outputs may be θ wrapped).
    return dtheta - _TWO_PI * round(dtheta / _TWO_PI)


@njit(**INLINE)
def _ipow(s, n):
    # s**n for n ≥ 0 by squaring (a handful of multiplies where pow costs tens of ns).
    r = 1.0
    while n > 0:
        if n & 1:
            r *= s
        s *= s
        n >>= 1
    return r


@njit(**INLINE)
def _tail(a, n, s):
    # The signed local error of a degree-n Taylor window at s (θ, θ'): minus its first two
    # neglected terms, a_{n+1} s^{n+1} + a_{n+2} s^{n+2} (the run's own error estimate's).
    sn = _ipow(s, n)
    return (-(a[n + 1] + a[n + 2] * s) * sn * s,
            -((n + 1.0) * a[n + 1] + (n + 2.0) * a[n + 2] * s) * sn)


@njit(**INLINE)
def _report(report, j, tr, d0, d1):
    # Output j: the transported error plus the output's own (d0, d1), and S2.
    report.err[0, j] = tr.e2[0] + d0
    report.err[1, j] = tr.e2[1] + d1
    for i in range(tr.S2.shape[1]):  # element loops: no broadcast machinery
        report.sens[i, 0, j] = tr.S2[0, i]
        report.sens[i, 1, j] = tr.S2[1, i]


@njit(**INLINE)
def _advance(tr):
    tr.e[0], tr.e[1] = tr.e2[0], tr.e2[1]
    for i in range(tr.S.shape[1]):
        tr.S[0, i], tr.S[1, i] = tr.S2[0, i], tr.S2[1, i]


@njit(**INLINE)
def _own_outputs(d, an, span, te, j, arrays):
    # The outputs j, … in (t0, t1] of a Taylor window: Φ(s)·e plus the output's own
    # local error (:func:`_tail`) into err, Φ(s)·S + P(s) into sens (as
    # :func:`_columns_at` and :func:`_report`).  ``span`` = (t0, t1, direction, kt, n);
    # ``arrays`` = (e, S, err, sens, rows, the columns' values and rates at s: (2, columns)).
    # Returns the next output index.
    t0, t1, direction, kt, n = span
    e, S, err, sens, rows, vr = arrays
    while j < te.size and direction * (te[j] - t1) <= 0.0:
        s = te[j] - t0
        if rows.size == 0:
            phi = _phi_at(d, kt, s)
        else:  # every column at once: independent Horner chains side by side
            _rows_value_rate(d, kt, s, vr)
            phi = vr[0, 0], vr[1, 0], vr[0, 1], vr[1, 1]
        p00, p10, p01, p11 = phi
        d0, d1 = _tail(an, n, s)
        err[0, j] = (p00 * e[0] + p01 * e[1]) + d0
        err[1, j] = (p10 * e[0] + p11 * e[1]) + d1
        for i in range(rows.size):
            x0 = p00 * S[0, i] + p01 * S[1, i]
            x1 = p10 * S[0, i] + p11 * S[1, i]
            if rows[i] >= 2:
                x0 += vr[0, rows[i]]
                x1 += vr[1, rows[i]]
            sens[i, 0, j], sens[i, 1, j] = x0, x1
        j += 1
    return j


@njit(**INLINE)
def _rows_value_rate(d, n, s, vr):
    # vr[0, r], vr[1, r] = value_rate of row r of d to degree n at s, for every row: the
    # same Horner steps per row as row_value_rate, the rows' chains interleaved.
    nr = d.shape[0]
    for r in range(nr):
        vr[0, r] = d[r, n]
        vr[1, r] = 0.0
    for k in range(n - 1, -1, -1):
        for r in range(nr):
            p = vr[0, r]
            vr[1, r] = vr[1, r] * s + p
            vr[0, r] = p * s + d[r, k]


@njit(cache=True)
def _own_windows(sc, codes, ws, track, ctl, io, at):
    # The run's own Taylor windows from window at[0] while they last (:func:`_is_own`),
    # at most to window at[2]: Φ and the columns to degree ctl.kt from their stored
    # coefficients (degree n = coef[1]), the local error from their tail.  The arrays
    # are taken out of their tuples once per call (each taking costs a reference count),
    # not per window.  ``at`` = (window, output, last window, direction); returns (next
    # window, next output).
    n, j, end, direction = at
    report, tr = io
    if report.rows.size == 0:
        return _own_error_windows(sc, ws, track, ctl, (report.err, tr.e), at)
    a, sn, cn, d = ws[0], ws[1], ws[2], ws[5]
    wt, coefs, te = track.t, track.coef, track.t_out
    e, S, e2, S2, rows = tr.e, tr.S, tr.e2, tr.S2, report.rows
    vr = np.empty((2, d.shape[0]))  # the columns' values and rates at a time
    arrays = (e, S, report.err, report.sens, rows, vr)
    kt = ctl.kt
    while n < end and _is_own(wt, coefs, ctl, n, direction):
        t0, t1 = wt[n], wt[n + 1]
        coef = coefs[n]
        deg = int(coef[1])
        for k in range(kt + 1):
            a[k] = coef[HEADER + k]
        sn[0], cn[0] = math.sin(a[0]), math.cos(a[0])
        columns(sc, t0, codes, ws, kt, True)
        an = coef[HEADER:]
        j = _own_outputs(d, an, (t0, t1, direction, kt, deg), te, j, arrays)
        h = t1 - t0
        _rows_value_rate(d, kt, h, vr)  # every column at once (as at the outputs)
        p00, p10, p01, p11 = vr[0, 0], vr[1, 0], vr[0, 1], vr[1, 1]
        d0, d1 = _tail(an, deg, h)
        for i in range(rows.size):  # S ← Φ(h)·S + P(h), as _columns_at
            x0 = p00 * S[0, i] + p01 * S[1, i]
            x1 = p10 * S[0, i] + p11 * S[1, i]
            if rows[i] >= 2:
                x0 += vr[0, rows[i]]
                x1 += vr[1, rows[i]]
            S[0, i], S[1, i] = x0, x1
            S2[0, i], S2[1, i] = x0, x1
        e2[0], e2[1] = p00 * e[0] + p01 * e[1], p10 * e[0] + p11 * e[1]
        e[0], e[1] = e2[0] + d0, e2[1] + d1
        n += 1
    return n, j


@njit(cache=True)
def _own_error_windows(sc, ws, track, ctl, io, at):
    # :func:`_own_windows` for the error alone: Φ·e is the variational column started
    # from (e, e') itself (the equation is linear), so one column to degree ctl.kt is
    # transported in place of Φ's two; its recurrence shares each order's loop with the
    # sin/cos series' next order (independent chains side by side).  ``io`` = (err, e).
    n, j, end, direction = at
    err, e = io
    ja, sn, cn, col = ws[0], ws[1], ws[2], ws[3]
    wt, coefs, te = track.t, track.coef, track.t_out
    kt = ctl.kt
    beta, w2 = sc[0], sc[2] * sc[2]
    e0, e1 = e[0], e[1]
    while n < end and _is_own(wt, coefs, ctl, n, direction):
        t0, t1 = wt[n], wt[n + 1]
        deg = int(coefs[n, 1])
        for k in range(1, kt - 1):
            ja[k] = k * coefs[n, HEADER + k]
        sn[0], cn[0] = math.sin(coefs[n, HEADER]), math.cos(coefs[n, HEADER])
        col[0], col[1] = e0, e1
        for k in range(kt - 1):
            if k + 1 <= kt - 2:  # sin θ, cos θ at order k + 1 (as series._sincos_order)
                ss = 0.0
                cc = 0.0
                for i in range(1, k + 2):
                    ss += ja[i] * cn[k + 1 - i]
                    cc += ja[i] * sn[k + 1 - i]
                sn[k + 1] = ss / (k + 1)
                cn[k + 1] = -cc / (k + 1)
            c0 = 0.0
            for i in range(k + 1):
                c0 += cn[i] * col[k - i]
            col[k + 2] = (-beta * (k + 1.0) * col[k + 1] - w2 * c0) * _INV_K12[k]
        an = coefs[n, HEADER:]
        while j < te.size and direction * (te[j] - t1) <= 0.0:
            s = te[j] - t0
            p, q = value_rate_to(col, kt, s)
            d0, d1 = _tail(an, deg, s)
            err[0, j] = p + d0
            err[1, j] = q + d1
            j += 1
        h = t1 - t0
        p, q = value_rate_to(col, kt, h)
        d0, d1 = _tail(an, deg, h)
        e0, e1 = p + d0, q + d1
        n += 1
    e[0], e[1] = e0, e1
    return n, j


@njit(**INLINE)
def _is_own(wt, coefs, ctl, n, direction):
    # Whether window n is one of the run's own Taylor windows of degree ctl.n_order,
    # before the regime's formula takes over (at ctl.t_taylor).
    return (n < coefs.shape[0] and direction * (ctl.t_taylor - wt[n]) > 0.0 and coefs[n, 0] == 0.0
            and coefs[n, 1] == ctl.n_order)


@njit(cache=True)
def _reference_window(sc, codes, ws, start, span, io, j):
    # Window [t0, t1] from the run's state ``start`` = (θ, θ') by the reference series
    # (sub-windows of REF_DEGREE), its local error measured unless span.measured is
    # False.  Returns (next output index, sub-windows taken; −1: a non-finite state).
    t0, t1, direction, measured = span.t0, span.t1, span.direction, span.measured
    track, report, tr = io
    rtol, atol = span.tol
    nt = ws[0].size - 1
    te, yo = track.t_out, track.y_out
    ts, x0, x1 = t0, start[0], start[1]
    vr = np.empty((2, codes.size))  # the columns' values and rates at a time
    n_sub = 0
    while True:
        tangent_series(sc, ts, x0, x1, codes, ws)
        hs = reference_step(ws, rtol, atol)
        if not hs > 0.0:
            return j, -1
        n_sub += 1
        last = hs >= direction * (t1 - ts)
        t_sub = t1 if last else ts + direction * hs
        while j < te.size and direction * (te[j] - t_sub) <= 0.0:
            th, v = _columns_at(ws, nt, te[j] - ts, report.rows, tr, vr)
            if measured:
                _report(report, j, tr, _wrapped(yo[0, j] - th), yo[1, j] - v)
            else:
                _report(report, j, tr, 0.0, 0.0)
            j += 1
        x0, x1 = _columns_at(ws, nt, t_sub - ts, report.rows, tr, vr)
        _advance(tr)
        ts = t_sub
        if last:
            break
        if _settled(sc, span.lock, x0, x1, rtol, atol):
            x0, x1, j = _linear_rest(sc, codes, (ts, x0, x1), span, io, j)
            break
    if measured:
        tr.e[0] += _wrapped(start[2] - x0)
        tr.e[1] += start[3] - x1
    return j, n_sub


@njit(**INLINE)
def _named(track, ctl, report):
    # The pass's inputs as named tuples, built here: Python passes plain tuples, which
    # numba's dispatcher types in ~0.3 µs where a named tuple takes ~9 µs.
    return (Track(track[0], track[1], track[2], track[3], track[4]),
            Control(ctl[0], ctl[1], ctl[2], ctl[3], ctl[4], ctl[5]),
            Report(report[0], report[1], report[2]))


def carry_arrays(n_sens, n_codes, nt, period):
    """The arrays of a pass's carry, for :func:`start` to set: (:data:`Transported`'s
    fields as a plain tuple, the stored period's arrays, cursor), for ``n_sens``
    sensitivities, ``n_codes`` series columns of degree ``nt``, with a stored period's
    arrays where ``period`` is not nan.  Reusable from pass to pass."""
    store = period_store(n_codes, nt) if period == period else period_store(0, 0)
    return ((np.zeros(2), np.zeros((2, n_sens)), np.zeros(2), np.zeros((2, n_sens))), store,
            np.zeros(3, np.int64))


@njit(cache=True)
def start(track, report, carry):
    """Set ``carry`` (:func:`carry_arrays`) to the run's start: zero error, the initial
    sensitivities, cursor = [next window, next output, reference sub-windows so far]; the
    outputs at t0 written.  ``track`` and ``report``: the fields of :data:`Track` and
    :data:`Report` as plain tuples."""
    track = Track(track[0], track[1], track[2], track[3], track[4])
    report = Report(report[0], report[1], report[2])
    fields, _, cursor = carry
    tr = Transported(fields[0], fields[1], fields[2], fields[3])
    rows = report.rows
    for q in range(2):
        tr.e[q] = 0.0
        tr.e2[q] = 0.0
    for i in range(rows.size):
        tr.S[0, i] = 1.0 if rows[i] == COL_THETA0 else 0.0
        tr.S[1, i] = 1.0 if rows[i] == COL_V0 else 0.0
        tr.S2[0, i] = tr.S[0, i]
        tr.S2[1, i] = tr.S[1, i]
    j = 0
    while j < track.t_out.size and track.t_out[j] == track.t[0]:
        _report(report, j, tr, 0.0, 0.0)
        j += 1
    cursor[0], cursor[1], cursor[2] = 0, j, 0


@njit(cache=True)
def transport(sc, codes, track, ctl, report, ws, carry):
    """Error transport and sensitivities along a run (module docstring), CHUNK_WINDOWS
    windows from where ``carry`` stands.

    Parameters
    ----------
    sc : tuple of 6 floats
        (β, γ, ω, A, Ω, φ).
    codes : int64 array
        The series' columns: θ₀'s and θ̇₀'s (Φ), then the parameters' (``COL_*``).
    track : tuple
        The fields of :data:`Track` (plain tuples: see :func:`_named`).
    ctl : tuple
        The fields of :data:`Control`.
    report : tuple
        The fields of :data:`Report`, filled for the outputs reached.
    ws : tuple
        :func:`mbm.tangent.series.workspace` of degree REF_DEGREE and len(codes) columns.
    carry : tuple
        From :func:`carry_arrays`, advanced in place; a fresh pass's with cursor[0] = −1
        (:func:`start` sets it first).

    Returns
    -------
    int
        1 while windows are left (call again: Ctrl-C gets in between), 0 when done, −1
        where a reference step failed (a non-finite state).
    """
    if carry[2][0] < 0:  # a fresh pass (cursor[0] = −1): its start in this call, not one of its own
        start(track, report, carry)
    track, ctl, report = _named(track, ctl, report)
    wt, coefs = track.t, track.coef
    fields, store, cursor = carry
    tr = Transported(fields[0], fields[1], fields[2], fields[3])
    direction = 1.0 if wt[wt.size - 1] >= wt[0] else -1.0
    io = (track, report, tr)
    j = cursor[1]
    end = min(wt.size - 1, cursor[0] + CHUNK_WINDOWS)
    n = cursor[0]
    while n < end:
        if _is_own(wt, coefs, ctl, n, direction):
            n, j = _own_windows(sc, codes, ws, track, ctl, (report, tr), (n, j, end, direction))
        else:
            j, taken = _regime_window(sc, codes, ws, ctl, io, Cursor(n, j, direction), store)
            if taken < 0:
                return -1
            cursor[2] += taken
            n += 1
    cursor[0], cursor[1] = end, j
    return 1 if end < wt.size - 1 else 0


_NO_LOCK = (math.nan, math.nan, 0.0)
_ZERO2 = np.zeros(2)
_LOCKED_TAG = 101.0  # mbm.regimes.locked.LOCKED_TAG
_CYCLE_TAG = 102.0  # mbm.regimes.cycle.CYCLE_TAG
_STROBE_TAG = 103.0  # mbm.regimes.strobe.STROBE_TAG
_COL_FREQ = 6  # mbm.tangent.series.COL_FREQ


@njit(cache=True)
def _regime_window(sc, codes, ws, ctl, io, at, store):
    # Window n when it is not the run's own Taylor window (``at``: a Cursor): a locked
    # window (the reference until settled, then the linear flow), a stored period's
    # (Floquet over the stored period), or any other (the reference).  Returns (next
    # output, sub-windows; −1: failed).
    n, j, direction = at
    track = io[0]
    wt, wy, coefs = track.t, track.y, track.coef
    t0, t1 = wt[n], wt[n + 1]
    measured = direction * (ctl.t_measured - t0) > 0.0
    ends = (wy[n, 0], wy[n, 1], wy[n + 1, 0], wy[n + 1, 1])
    tag = coefs[n, 0] if n < coefs.shape[0] else 0.0
    lock = _NO_LOCK
    if tag == _LOCKED_TAG:  # θ* = θ₀ − x₀, ω_l², and whether the columns must be sharp
        lock = (coefs[n, 1] - coefs[n, 2], coefs[n, 6], 1.0 if ctl.kt == ctl.n_order else 0.0)
    # An exact flow's window (not measured): the reference at round-off, as the run is
    # exact and sensitivities near a separatrix amplify the reference's error.
    span = Span(t0, t1, direction, measured, ctl.kt, ctl.tol if measured else (0.0, 0.0), lock)
    periodic = ((tag == _CYCLE_TAG or tag == _STROBE_TAG) and ctl.period == ctl.period and direction > 0.0
                and not (tag == _STROBE_TAG and _has(codes, _COL_FREQ)))
    if periodic:
        if tag == _CYCLE_TAG:  # (t_A = t0 − t_off, θ_c, v_c), T_c + T_lo (mbm.regimes.cycle's layout)
            anchor, T = (t0 - coefs[n, 4], coefs[n, 1], coefs[n, 2]), coefs[n, 3] + coefs[n, 14]
        else:  # (t_a, φ_a, θ'_a) (mbm.regimes.strobe's layout), T = q·2π/Ω
            anchor, T = (coefs[n, 4], coefs[n, 1], coefs[n, 2]), ctl.period
        j2, taken = _periodic_window(sc, codes, ws, ends, span, io, j, (store, T, anchor))
        if taken >= 0:
            return j2, taken
    return _reference_window(sc, codes, ws, ends, span, io, j)


@njit(cache=True)
def _has(codes, code):
    for c in codes:
        if c == code:
            return True
    return False


@njit(cache=True)
def _settled(sc, lock, x0, x1, rtol, atol):
    # Whether a locked window's state is so near θ* that the nonlinearity is below the
    # reference's tolerance: in the flow (ω²x²/2 of the deviation x), and with
    # sensitivities (lock[2]) in the tangent map too (ω²x of cos θ's variation).
    if lock[0] != lock[0]:
        return False
    x = _wrapped(x0 - lock[0])
    dev = abs(x) + abs(x1) / math.sqrt(abs(lock[1]))
    return sc[2] * sc[2] * dev * (1.0 if lock[2] != 0.0 else dev) <= reference_eps(x0, x1, rtol, atol)


@njit(**INLINE)
def _linear_at(sc, codes, rows, lock, E, tr):
    # tr.e2, tr.S2 = e^{Js}·(e, S) + the linear parameter columns (E = e^{Js}).
    beta = sc[0]
    tr.e2[0] = E[0] * tr.e[0] + E[1] * tr.e[1]
    tr.e2[1] = E[2] * tr.e[0] + E[3] * tr.e[1]
    for i in range(rows.size):
        x0 = E[0] * tr.S[0, i] + E[1] * tr.S[1, i]
        x1 = E[2] * tr.S[0, i] + E[3] * tr.S[1, i]
        if rows[i] >= 2:
            q0, q1 = linear_columns(E, lock[1], beta, linear_forcing(codes[rows[i]], sc, lock[0]))
            x0 += q0
            x1 += q1
        tr.S2[0, i] = x0
        tr.S2[1, i] = x1


@njit(cache=True)
def _linear_rest(sc, codes, at, span, io, j):
    # The rest of a settled locked window from ``at`` = (t, θ, θ') by the linear flow about
    # θ*; returns the reference state at the window's end and the next output index.
    track, report, tr = io
    ts, x0, x1 = at
    theta_star, wl2 = span.lock[0], span.lock[1]
    dx = _wrapped(x0 - theta_star)
    te, yo = track.t_out, track.y_out
    while j < te.size and span.direction * (te[j] - span.t1) <= 0.0:
        E = expm2(wl2, sc[0], te[j] - ts)
        _linear_at(sc, codes, report.rows, span.lock, E, tr)
        th = x0 - dx + E[0] * dx + E[1] * x1
        v = E[2] * dx + E[3] * x1
        if span.measured:
            _report(report, j, tr, _wrapped(yo[0, j] - th), yo[1, j] - v)
        else:
            _report(report, j, tr, 0.0, 0.0)
        j += 1
    E = expm2(wl2, sc[0], span.t1 - ts)
    _linear_at(sc, codes, report.rows, span.lock, E, tr)
    _advance(tr)
    return x0 - dx + E[0] * dx + E[1] * x1, E[2] * dx + E[3] * x1, j


@njit(**INLINE)
def _apply(phi, pc, d, rows, src, dst):
    # dst = Φ·src + (d, P): e ← Φ e + d, S ← Φ S + P (the parameter columns of pc); src and
    # dst are (e, S) pairs and may be the same arrays.
    e, S = src
    e0 = phi[0, 0] * e[0] + phi[0, 1] * e[1] + d[0]
    e1 = phi[1, 0] * e[0] + phi[1, 1] * e[1] + d[1]
    dst[0][0], dst[0][1] = e0, e1
    for i in range(rows.size):
        x0 = phi[0, 0] * S[0, i] + phi[0, 1] * S[1, i]
        x1 = phi[1, 0] * S[0, i] + phi[1, 1] * S[1, i]
        if rows[i] >= 2:
            x0 += pc[0, rows[i]]
            x1 += pc[1, rows[i]]
        dst[1][0, i], dst[1][1, i] = x0, x1


@njit(cache=True)
def _periodic_window(sc, codes, ws, ends, span, io, j, stored):
    # A window of a stored period T (forwards), ``stored`` = (store, T, anchor): the run
    # repeats the period from its anchor (t_A, φ_A reduced, θ'_A) exactly (a whole turn on
    # or not).  The reference runs one period from the anchor; an output at t_A + kT + s
    # has e = Φ_A(s) E_k + d(t) and S = Φ_A(s) Σ_k + P_A(s), with E_{k+1} = M E_k + d_T
    # and Σ_{k+1} = M Σ_k + P_T (module mbm.tangent.regimes).  Returns (next output,
    # sub-windows; −1: the period did not fit).
    track, report, tr = io
    store, T, anchor = stored
    t0, t1 = span.t0, span.t1
    t_a = anchor[0]
    # The period's reference error recurs every period (along the cycle's neutral phase
    # direction it adds up): one period is taken at round-off (tolerance 0: REF_ULPS ulps
    # per sub-window), which a degree-32 series pays for with a few more sub-windows.
    one = Span(t_a, t_a + T, 1.0, span.measured, span.kt, (0.0, 0.0), _NO_LOCK)
    n_sub = period_map(sc, codes, ws, anchor, one, store)
    if n_sub < 0:
        return j, -1
    rows = report.rows
    M, PT = np.empty((2, 2)), np.empty((2, codes.size))
    thT, vT = period_at(store, n_sub, T, codes, (M, PT))
    dT = np.zeros(2)
    if span.measured:
        dT[0], dT[1] = _wrapped(anchor[1] - thT), anchor[2] - vT
    # The window's start in the anchor's frame: E_k0 = Φ_A(s0)⁻¹(e₀ − d(t0)), Σ likewise.
    k = max(0, int(math.floor((t0 - t_a) / T)))
    phi, pc = np.empty((2, 2)), np.empty((2, codes.size))
    th, v = period_at(store, n_sub, min(max(t0 - t_a - k * T, 0.0), T), codes, (phi, pc))
    d0, d1 = (_wrapped(ends[0] - th), ends[1] - v) if span.measured else (0.0, 0.0)
    _pull_back(phi, pc, rows, (d0, d1), tr)
    te, yo = track.t_out, track.y_out
    while True:
        last = j >= te.size or te[j] > t1
        t = t1 if last else te[j]
        kk = max(0, int(math.floor((t - t_a) / T)))
        while k < kk:
            _apply(M, PT, dT, rows, (tr.e, tr.S), (tr.e, tr.S))  # one stored period on
            k += 1
        th, v = period_at(store, n_sub, min(max(t - t_a - k * T, 0.0), T), codes, (phi, pc))
        _apply(phi, pc, _ZERO2, rows, (tr.e, tr.S), (tr.e2, tr.S2))  # at the phase
        y0, y1 = (ends[2], ends[3]) if last else (yo[0, j], yo[1, j])
        d0, d1 = (_wrapped(y0 - th), y1 - v) if span.measured else (0.0, 0.0)
        if last:
            _advance(tr)
            tr.e[0] += d0
            tr.e[1] += d1
            return j, n_sub
        _report(report, j, tr, d0, d1)
        j += 1


@njit(cache=True)
def _pull_back(phi, pc, rows, d, tr):
    # tr.e ← Φ⁻¹(e − d), tr.S ← Φ⁻¹(S − P) (P the parameter columns): the window start's
    # error and sensitivities in the stored period's anchor frame.
    det = phi[0, 0] * phi[1, 1] - phi[0, 1] * phi[1, 0]
    i00, i01, i10, i11 = phi[1, 1] / det, -phi[0, 1] / det, -phi[1, 0] / det, phi[0, 0] / det
    x0, x1 = tr.e[0] - d[0], tr.e[1] - d[1]
    tr.e[0], tr.e[1] = i00 * x0 + i01 * x1, i10 * x0 + i11 * x1
    for i in range(rows.size):
        x0, x1 = tr.S[0, i], tr.S[1, i]
        if rows[i] >= 2:
            x0 -= pc[0, rows[i]]
            x1 -= pc[1, rows[i]]
        tr.S[0, i], tr.S[1, i] = i00 * x0 + i01 * x1, i10 * x0 + i11 * x1
