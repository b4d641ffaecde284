r"""The Taylor recurrence of the variational equations along a window.

Along a solution θ(t) of θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ), a first-order
perturbation δ of the state or of a parameter p obeys

    δ'' + β δ' + ω² cos θ · δ = b_p(t),

with b = 0 for the initial state (θ₀: δ(0) = 1, δ'(0) = 0; θ̇₀: δ(0) = 0, δ'(0) = 1) and,
from zero initial values, b_β = −θ', b_γ = 1, b_ω = −2ω sin θ, b_A = sin(Ωt + φ),
b_Ω = A t cos(Ωt + φ), b_φ = A cos(Ωt + φ).  In powers of s = t − t₀ the product
cos θ · δ is a Cauchy product of the series c_k of cos θ (which the recurrence of θ
computes anyway: s' = cθ', c' = −sθ') with δ's, so every column costs one convolution
per order:

    δ_{k+2} = (b_k − β (k+1) δ_{k+1} − ω² Σ_{j≤k} c_j δ_{k−j}) / ((k+1)(k+2)).
"""

import math

import numpy as np
from numba import njit

from ..approximants.taylor_series import _INV_K12, drive_phase_sincos
from ..compile.jit import INLINE

#: Column codes: the sensitivity names in their order (the public names of
#: :data:`mbm.tangent.SENSITIVITY_NAMES`).
COL_THETA0, COL_V0, COL_BETA, COL_GAMMA, COL_OMEGA, COL_AMP, COL_FREQ, COL_PHASE = range(8)

#: Columns whose convolutions share one loop: independent chains hide the adds' latency
#: (the loop is latency-bound with a few); six: the five undriven columns in one pass.
COLUMN_GROUP = 6


@njit(**INLINE)
def drive_series(freq, u, w, nt, ds, dc):
    """ds_k, dc_k: the coefficients of sin(ψ + Ωs), cos(ψ + Ωs) in s (u = sin ψ, w = cos ψ)."""
    f = 1.0
    for k in range(nt + 1):
        ds[k] = f * u
        dc[k] = f * w
        f = f * freq / (k + 1.0)
        u, w = w, -u


@njit(**INLINE)
def _forcing(code, k, sc, t0, a, sn, ds, dc):
    # b_k of the column ``code`` (module docstring); sc = (β, γ, ω, A, Ω, φ).
    if code == COL_BETA:
        return -(k + 1.0) * a[k + 1]
    if code == COL_GAMMA:
        return 1.0 if k == 0 else 0.0
    if code == COL_OMEGA:
        return -2.0 * sc[2] * sn[k]
    if code == COL_AMP:
        return ds[k]
    if code == COL_FREQ:
        return sc[3] * (t0 * dc[k] + (dc[k - 1] if k > 0 else 0.0))
    if code == COL_PHASE:
        return sc[3] * dc[k]
    return 0.0


@njit(**INLINE)
def _sincos_order(k, a, sn, cn):
    # Order k ≥ 1 of s = sin θ and c = cos θ from s' = cθ', c' = −sθ'.
    ss = 0.0
    cc = 0.0
    for j in range(1, k + 1):
        ja = j * a[j]
        ss += ja * cn[k - j]
        cc += ja * sn[k - j]
    sn[k] = ss / k
    cn[k] = -cc / k


@njit(**INLINE)
def sincos_of(a, nt, sn, cn):
    """sin θ's and cos θ's coefficients of orders 0 … nt from θ's (``a``, degree ≥ nt)."""
    sn[0], cn[0] = math.sin(a[0]), math.cos(a[0])
    for k in range(1, nt + 1):
        _sincos_order(k, a, sn, cn)


@njit(**INLINE)
def columns(sc, t0, codes, ws, nt, sincos):
    """The variational columns ``codes`` to degree ``nt`` (``ws``'s d[:, :nt + 1]) along the
    θ whose coefficients (a, to nt + 1) ``ws`` holds, and its sin/cos series (to nt − 2):
    given, or with ``sincos`` computed here from their order 0 on, each order beside the
    columns' (independent chains side by side; the same operations as :func:`sincos_of`)."""
    a, sn, cn, ds, dc, d = ws
    if codes[codes.size - 1] >= COL_AMP:  # (codes ascending) a drive column: the drive's series
        u, w = drive_phase_sincos(sc[4], sc[5], t0)
        drive_series(sc[4], u, w, nt, ds, dc)
    _columns_start(codes, d)
    for k in range(nt - 1):
        if sincos and k > 0:
            _sincos_order(k, a, sn, cn)
        _columns_order(sc, t0, codes, ws, k)


@njit(**INLINE)
def _columns_start(codes, d):
    # The columns' orders 0 and 1: θ₀'s (1, 0), θ̇₀'s (0, 1), a parameter's (0, 0).
    for i in range(codes.size):
        d[i, 0] = 1.0 if codes[i] == COL_THETA0 else 0.0
        d[i, 1] = 1.0 if codes[i] == COL_V0 else 0.0


@njit(**INLINE)
def _columns_order(sc, t0, codes, ws, k):
    # Every column's order k + 2 from cos θ's orders ≤ k (the module docstring's recurrence).
    a, sn, cn, ds, dc, d = ws
    beta, w2 = sc[0], sc[2] * sc[2]
    last = codes.size - 1
    inv = _INV_K12[k]
    kk = k + 1.0
    for i in range(0, codes.size, COLUMN_GROUP):
        # Six columns per pass: their sums are independent chains (each in the same
        # order as alone); a short group repeats its last column, stored once.
        i1, i2, i3 = min(i + 1, last), min(i + 2, last), min(i + 3, last)
        i4, i5 = min(i + 4, last), min(i + 5, last)
        c0 = 0.0
        c1 = 0.0
        c2 = 0.0
        c3 = 0.0
        c4 = 0.0
        c5 = 0.0
        for j in range(k + 1):
            cj = cn[j]
            c0 += cj * d[i, k - j]
            c1 += cj * d[i1, k - j]
            c2 += cj * d[i2, k - j]
            c3 += cj * d[i3, k - j]
            c4 += cj * d[i4, k - j]
            c5 += cj * d[i5, k - j]
        _column_order(d, i, k, kk, _forcing(codes[i], k, sc, t0, a, sn, ds, dc), beta, w2 * c0, inv)
        if i1 > i:
            _column_order(d, i1, k, kk, _forcing(codes[i1], k, sc, t0, a, sn, ds, dc), beta, w2 * c1, inv)
        if i2 > i1:
            _column_order(d, i2, k, kk, _forcing(codes[i2], k, sc, t0, a, sn, ds, dc), beta, w2 * c2, inv)
        if i3 > i2:
            _column_order(d, i3, k, kk, _forcing(codes[i3], k, sc, t0, a, sn, ds, dc), beta, w2 * c3, inv)
        if i4 > i3:
            _column_order(d, i4, k, kk, _forcing(codes[i4], k, sc, t0, a, sn, ds, dc), beta, w2 * c4, inv)
        if i5 > i4:
            _column_order(d, i5, k, kk, _forcing(codes[i5], k, sc, t0, a, sn, ds, dc), beta, w2 * c5, inv)


@njit(**INLINE)
def _column_order(d, i, k, kk, b, beta, wc, inv):
    # Column i's order k + 2 from its forcing b and the convolution's ω²·Σ c_j d_{k−j}.
    d[i, k + 2] = (b - beta * kk * d[i, k + 1] - wc) * inv


@njit(cache=True)
def tangent_series(sc, t0, theta0, v0, codes, ws):
    """Taylor coefficients, at ``t0``, of θ and of the variational columns ``codes``.

    Parameters
    ----------
    sc : tuple of 6 floats
        (β, γ, ω, A, Ω, φ).
    t0, theta0, v0 : float
        The anchor: time and state.
    codes : int64 array
        The columns (``COL_*``): ``d[i]`` holds column ``codes[i]``'s coefficients.
    ws : tuple of arrays
        ``(a, sn, cn, ds, dc, d)`` from :func:`workspace`: θ's coefficients a_0 … a_nt,
        sin θ's and cos θ's, the drive's, and d (len(codes), nt + 1).

    Each order of θ and the columns' next order share one pass (independent chains side
    by side; each the same operations as apart).
    """
    if codes.size == 2 and codes[0] == COL_THETA0 and codes[1] == COL_V0:
        _phi_series(sc, t0, theta0, v0, ws)
        return
    a, sn, cn, ds, dc, d = ws
    nt = a.size - 1
    beta, gamma, omega, amp, freq, phase = sc
    w2 = omega * omega
    _series_start(sc, t0, theta0, v0, ws, amp != 0.0 or codes[codes.size - 1] >= COL_AMP)
    _columns_start(codes, d)
    for k in range(nt - 1):
        if k > 0:
            _sincos_order(k, a, sn, cn)
        g = gamma if k == 0 else 0.0
        a[k + 2] = (g + amp * ds[k] - beta * (k + 1.0) * a[k + 1] - w2 * sn[k]) / ((k + 1.0) * (k + 2.0))
        _columns_order(sc, t0, codes, ws, k)


@njit(cache=True)
def _series_start(sc, t0, theta0, v0, ws, drive):
    # The set-up of tangent_series and _phi_series: the drive's series from t0 (zero
    # where ``drive`` is off), θ's first two coefficients, sin θ₀ and cos θ₀.
    a, sn, cn, ds, dc, _ = ws
    freq, phase = sc[4], sc[5]
    if drive:
        u, w = drive_phase_sincos(freq, phase, t0)
        drive_series(freq, u, w, a.size - 1, ds, dc)
    else:
        ds[:] = 0.0
    a[0], a[1] = theta0, v0
    sn[0], cn[0] = math.sin(theta0), math.cos(theta0)


@njit(cache=True)
def _phi_series(sc, t0, theta0, v0, ws):
    # tangent_series of Φ's two columns alone (no forcing): one pair of chains beside
    # sin/cos's, the same operations per column as the grouped pass.
    a, sn, cn, ds, dc, d = ws
    nt = a.size - 1
    beta, gamma, omega, amp, freq, phase = sc
    w2 = omega * omega
    _series_start(sc, t0, theta0, v0, ws, amp != 0.0)
    d[0, 0], d[0, 1], d[1, 0], d[1, 1] = 1.0, 0.0, 0.0, 1.0
    for k in range(nt - 1):
        if k > 0:
            _sincos_order(k, a, sn, cn)
        g = gamma if k == 0 else 0.0
        a[k + 2] = (g + amp * ds[k] - beta * (k + 1.0) * a[k + 1] - w2 * sn[k]) / ((k + 1.0) * (k + 2.0))
        c0 = 0.0
        c1 = 0.0
        for j in range(k + 1):
            cj = cn[j]
            c0 += cj * d[0, k - j]
            c1 += cj * d[1, k - j]
        kk = k + 1.0
        _column_order(d, 0, k, kk, 0.0, beta, w2 * c0, _INV_K12[k])
        _column_order(d, 1, k, kk, 0.0, beta, w2 * c1, _INV_K12[k])


@njit(**INLINE)
def value_rate(c, s):
    """(value, derivative) at ``s`` of the polynomial with coefficients ``c`` (Horner)."""
    return value_rate_to(c, c.size - 1, s)


@njit(**INLINE)
def value_rate_to(c, n, s):
    """:func:`value_rate` of ``c[:n + 1]`` (no slice: a view costs its reference count)."""
    p = c[n]
    q = 0.0
    for k in range(n - 1, -1, -1):
        q = q * s + p
        p = p * s + c[k]
    return p, q


@njit(**INLINE)
def row_value_rate(d, i, n, s):
    """:func:`value_rate` of row ``i`` of ``d`` to degree ``n`` (no slice: a view costs its
    reference count at every output)."""
    p = d[i, n]
    q = 0.0
    for k in range(n - 1, -1, -1):
        q = q * s + p
        p = p * s + d[i, k]
    return p, q


def workspace(nt, n_cols):
    """The arrays :func:`tangent_series` fills, for degree ``nt`` and ``n_cols`` columns."""
    return (np.empty(nt + 1), np.empty(nt + 1), np.empty(nt + 1), np.empty(nt + 1), np.empty(nt + 1),
            np.empty((n_cols, nt + 1)))
