"""The exact flow at many times: a table of Taylor expansions over one half period.

:func:`mbm.special.pendulum_flow.flow_eval_kernel` runs the descending Landen
chain, a sine, a cosine and an arctangent per time.  The solver's exact-flow
windows (a libration or a rotation) instead expand the angle θ and the rate θ'
about anchors spaced evenly over the reduced argument r ∈ [−K, K] (the flow
repeats with period 2K in u up to signs and whole turns): per time they keep the
flow kernel's double-double argument and its reduction by 2K, then pick the
nearest anchor and sum two polynomials (Horner).  A window with many output
times builds the whole table once; a single time expands its one anchor, the
same bits, so a value never depends on which other times were asked for.

Expansions.  With s, c, d the Taylor coefficients of sn, cn, dn (parameter m)
about an anchor a, sn' = cn dn, cn' = −sn dn, dn' = −m sn cn (DLMF 22.13.1-3)
give, by Cauchy products,

    s_{i+1} = Σ c_l d_{i−l} / (i+1),  c_{i+1} = −Σ s_l d_{i−l} / (i+1),
    d_{i+1} = −m Σ s_l c_{i−l} / (i+1).

Libration, sin(θ/2) = k sn(u), cos(θ/2) = dn(u): d(θ/2)/du = k cn, so θ has
coefficients 2k c_{i−1}/i after θ(a) = 2 atan2(k sn a, dn a), and θ' = 2kω cn.
Rotation, θ/2 = am(u): d(am)/du = dn, so θ has 2 d_{i−1}/i after 2 atan2(sn a,
cn a), and θ' = 2sωk dn.  The values at the anchors are the flow kernel's own
(the Landen chain on [0, K/2], the quarter-period shift beyond), so the table
inherits their accuracy; θ is odd and θ' even in r, so the anchors −a mirror a.

Spacing.  sn, cn, dn are analytic in the strip |Im u| < K' = K(1 − m) (their
nearest poles are at ±iK' + 2jK, DLMF 22.2), and so are θ(u) and θ'(u); with
anchors K/N apart (N a power of two, so the anchors j·K/N are exact in
double-double) the neglected terms of degree > FLOW_TABLE_DEGREE are ~(K/(2N
K'))^(FLOW_TABLE_DEGREE+1) of the value, below an ulp for K/(2N) <=
FLOW_TABLE_REACH·K'.  Anchors at r = 0 and r = ±K, the zeros of sn and (in
libration) cn, keep θ and θ' relatively accurate next to their zeros (the
expansion's constant term is then exactly 0).  Against the flow kernel the
table's outputs differ by a few ulps (tests/special/test_pendulum_flow_table.py
states the bound).

Kernels: :func:`flow_table_half` (anchors per half period, 0 where no table
applies), :func:`flow_table_kernel` (the table), :func:`flow_table_eval_kernel`
(one time from a table), :func:`flow_table_point_kernel` (one time, no table),
:func:`flow_table_eval_range` (the times of one window, the run's outputs).
"""

import collections
import math

import numba
import numpy as np

from .dd import dd_add, two_prod
from .jacobi import ellipj_kernel
from .jacobi_kernels import _ellipk_rough, _stack_f64
from .pendulum_flow import (
    HalfPeriod,
    REGIME_LIBRATION,
    REGIME_ROTATION,
    flow_argument_kernel,
    flow_eval_kernel,
    odd_half_periods,
    reduce_half_period_kernel,
    rotation_theta,
)
from ..compile.jit import kernel

__all__ = [
    "FLOW_TABLE_DEGREE",
    "FLOW_TABLE_REACH",
    "FLOW_TABLE_MAX_HALF",
    "FLOW_TABLE_OUTPUTS_PER_ANCHOR",
    "FlowTable",
    "flow_table_half",
    "flow_table_kernel",
    "flow_table_eval_kernel",
    "flow_table_point_kernel",
    "flow_table_eval_range",
]

# Degree of the expansions: two Horner chains of this length per time, short enough
# to cost less than the Landen chain, long enough to keep the anchors few.
FLOW_TABLE_DEGREE = 10

# Half the anchor spacing as a fraction of K': 0.02^11 ~ 2e-19 (at 0.05 the neglected
# terms were measured at 1e-12).
FLOW_TABLE_REACH = 0.02

# Most anchors per half period: 2^12 covers mc down to 1e-220 (K ≈ 257, K' = π/2); a
# state of doubles reaches mc ~ 1e-33 (K ≈ 39: 2^10).
FLOW_TABLE_MAX_HALF = 2**12

# A table pays off from this many outputs per anchor (its build ~0.3 µs per anchor,
# the saving ~0.1 µs per output).
FLOW_TABLE_OUTPUTS_PER_ANCHOR = 4

#: A table of :func:`flow_table_kernel`: ``rows`` (2·half + 1, 2 + 2(FLOW_TABLE_DEGREE + 1)),
#: row half + j the anchor j·K/half (double-double, columns 0, 1) and the coefficients of
#: θ and θ' about it, interleaved from the highest degree down; ``half`` the anchors per
#: half period; ``inv_step`` half/K (to pick the nearest anchor).
FlowTable = collections.namedtuple("FlowTable", ("rows", "half", "inv_step"))

_NAN = float("nan")
_N_COEF = FLOW_TABLE_DEGREE + 1
_ROW = 2 + 2 * _N_COEF  # a row: the anchor (double-double), then θ's and θ''s coefficients
_SCD = 3 * _N_COEF  # scratch of _expand: sn's, cn's and dn's coefficients


@kernel(error_model="numpy")
def flow_table_half(flow):
    """Anchors per half period of the table of :data:`FlowSetup` ``flow`` (a power of two),
    or 0 where the flow is no libration or rotation or would need more than
    FLOW_TABLE_MAX_HALF."""
    if flow.status != 0.0 or not (flow.regime == REGIME_LIBRATION or flow.regime == REGIME_ROTATION):
        return 0
    K = flow.K
    if not (math.isfinite(K) and K > 0.0):
        return 0
    # K' = K(1 − par), whose complementary modulus is √par (inf at par = 0: any spacing
    # will do); 8 digits of it choose the power of two.
    Kp = _ellipk_rough(math.sqrt(flow.par))
    want = K / (2.0 * FLOW_TABLE_REACH * Kp)
    half = 1
    while half < want:
        half *= 2
        if half > FLOW_TABLE_MAX_HALF:
            return 0
    return half


@kernel(error_model="numpy")
def _anchor_values(flow, a_hi, a_lo):
    """sn, cn, dn at the anchor a = a_hi + a_lo ∈ [0, K], as the flow kernel computes them."""
    par, parc, K_hi, K_lo = flow.par, flow.parc, flow.K, flow.K_lo
    if a_hi <= 0.5 * K_hi:
        sn, cn, dn, _am = ellipj_kernel(a_hi + a_lo, par, parc)
        return sn, cn, dn
    # Quarter-period shift (A&S 16.8.1), as in flow_eval_kernel.
    x_hi, x_lo = dd_add(K_hi, K_lo, -a_hi, -a_lo)
    s_x, c_x, d_x, _am = ellipj_kernel(max(x_hi + x_lo, 0.0), par, parc)
    kc = math.sqrt(parc)
    return c_x / d_x, kc * s_x / d_x, kc / d_x


@kernel(error_model="numpy")
def _expand(flow, a_hi, a_lo, row):
    """Taylor coefficients of θ and θ' about the anchor a ∈ [0, K] into ``row[2:]``
    (interleaved, highest degree first), using sn, cn, dn's product recurrences."""
    buf = numba.carray(_stack_f64(_SCD), _SCD)  # s, c, d: no heap allocation per time
    s, c, d = buf[:_N_COEF], buf[_N_COEF:2 * _N_COEF], buf[2 * _N_COEF:]
    s[0], c[0], d[0] = _anchor_values(flow, a_hi, a_lo)
    par = flow.par
    for i in range(_N_COEF - 1):
        ss, cc, dd = 0.0, 0.0, 0.0
        for l in range(i + 1):
            ss += c[l] * d[i - l]
            cc += s[l] * d[i - l]
            dd += s[l] * c[i - l]
        s[i + 1] = ss / (i + 1)
        c[i + 1] = -cc / (i + 1)
        d[i + 1] = -par * dd / (i + 1)
    if flow.regime == REGIME_LIBRATION:
        th0, slope, w = 2.0 * math.atan2(flow.k * s[0], d[0]), 2.0 * flow.k, c
    else:
        th0, slope, w = 2.0 * math.atan2(s[0], c[0]), 2.0, d
    for i in range(_N_COEF):
        col = 2 + 2 * (FLOW_TABLE_DEGREE - i)
        row[col] = th0 if i == 0 else slope * w[i - 1] / i
        row[col + 1] = flow.vscale * w[i]


@kernel(error_model="numpy")
def _fill_row(flow, half, j, row):
    """Row ``j`` (−half … half) of the table of ``flow``: the anchor j·K/half in
    double-double and the coefficients about it."""
    h_hi, h_lo = flow.K / half, flow.K_lo / half  # exact: half is a power of two
    aj = abs(j)
    a_hi, a_lo = two_prod(float(aj), h_hi)
    a_lo += aj * h_lo
    _expand(flow, a_hi, a_lo, row)
    row[0], row[1] = a_hi, a_lo
    if j < 0:
        # θ is odd and θ' even in r: about −a the coefficients of degree i are
        # −(−1)^i and (−1)^i times those about a.
        row[0], row[1] = -a_hi, -a_lo
        for i in range(_N_COEF):
            col = 2 + 2 * (FLOW_TABLE_DEGREE - i)
            if i % 2 == 1:
                row[col + 1] = -row[col + 1]
            else:
                row[col] = -row[col]


@kernel(error_model="numpy")
def flow_table_kernel(flow, half):
    """The :data:`FlowTable` of ``flow`` with ``half`` (:func:`flow_table_half`, > 0)
    anchors per half period: anchors j·K/half, j = −half … half."""
    rows = np.empty((2 * half + 1, _ROW))
    for j in range(half + 1):
        _fill_row(flow, half, j, rows[half + j])
        if j > 0:
            # The mirrored row from the row about +a (what _fill_row(−j) computes).
            down, up = rows[half - j], rows[half + j]
            down[0], down[1] = -up[0], -up[1]
            for i in range(_N_COEF):
                col = 2 + 2 * (FLOW_TABLE_DEGREE - i)
                odd = i % 2 == 1
                down[col] = up[col] if odd else -up[col]
                down[col + 1] = -up[col + 1] if odd else up[col + 1]
    return FlowTable(rows, half, half / flow.K)


@kernel(error_model="numpy")
def _phase(flow, t):
    """The reduced argument (:data:`HalfPeriod`) at time ``t``, or NaNs where t or the phase is not finite."""
    u_hi, u_lo = flow_argument_kernel(flow, t)
    if not (math.isfinite(t) and math.isfinite(u_lo)):
        return HalfPeriod(_NAN, _NAN, _NAN, _NAN)
    return reduce_half_period_kernel(u_hi, u_lo, flow.K, flow.K_lo)


@kernel(error_model="numpy")
def _nearest(r_hi, inv_step, half):
    """The anchor nearest r (its index −half … half)."""
    j = int(np.floor(r_hi * inv_step + 0.5))
    return min(max(j, -half), half)


@kernel(error_model="numpy")
def _state(flow, row, phase):
    """(θ, θ') from the table row of the anchor nearest the reduced argument ``phase``."""
    r_hi, r_lo, n, n2 = phase
    # r − a: r_hi − a_hi is exact (Sterbenz: |r − a| <= a/2 unless a = 0).
    x = (r_hi - row[0]) + (r_lo - row[1])
    th = row[2]
    w = row[3]
    for i in range(1, _N_COEF):
        th = th * x + row[2 + 2 * i]
        w = w * x + row[3 + 2 * i]
    if flow.regime == REGIME_LIBRATION:
        if odd_half_periods(n, n2):  # sn, cn change sign: θ is odd in sn, θ' = 2kω cn
            th = -th
            w = -w
        return flow.theta0 + ((th - flow.theta_red) - flow.theta_red_lo), w
    return rotation_theta(flow, th, n, n2), w


@kernel(error_model="numpy")
def flow_table_eval_kernel(flow, table, t):
    """(θ, θ') of the exact flow ``flow`` at time ``t`` from its :data:`FlowTable`.

    The argument and its reduction by 2K are :func:`flow_eval_kernel`'s (double-double,
    horizon-free); exactly ``(theta0, v0)`` at ``t == 0.0``; NaN where t or the phase
    is not finite.
    """
    if t == 0.0:
        return flow.theta0, flow.v0
    phase = _phase(flow, t)
    if not math.isfinite(phase.r_hi):
        return _NAN, _NAN
    return _state(flow, table.rows[table.half + _nearest(phase.r_hi, table.inv_step, table.half)], phase)


@kernel(error_model="numpy")
def flow_table_point_kernel(flow, t):
    """:func:`flow_table_eval_kernel` without a table, bit for bit: the one row needed
    is expanded on the stack (~2× :func:`flow_eval_kernel`'s cost).  Where no table
    applies (:func:`flow_table_half` is 0: the separatrix, rest), :func:`flow_eval_kernel`."""
    half = flow_table_half(flow)
    if half == 0:
        return flow_eval_kernel(flow, t)
    if t == 0.0:
        return flow.theta0, flow.v0
    phase = _phase(flow, t)
    if not math.isfinite(phase.r_hi):
        return _NAN, _NAN
    row = numba.carray(_stack_f64(_ROW), _ROW)
    _fill_row(flow, half, _nearest(phase.r_hi, half / flow.K, half), row)
    return _state(flow, row, phase)


@kernel(error_model="numpy")
def flow_table_eval_range(flow, t, t_eval, j, j2, out_theta, out_v):
    """:func:`flow_table_point_kernel` of the exact flow ``flow`` anchored at time ``t``
    at ``t_eval[j:j2]``, into ``out_theta``, ``out_v``: from a table
    (:func:`flow_table_kernel`, the same bits) where the block has
    FLOW_TABLE_OUTPUTS_PER_ANCHOR outputs per anchor."""
    half = flow_table_half(flow)
    if half > 0 and j2 - j >= FLOW_TABLE_OUTPUTS_PER_ANCHOR * (half + 1):
        table = flow_table_kernel(flow, half)
        for i in range(j, j2):
            out_theta[i], out_v[i] = flow_table_eval_kernel(flow, table, t_eval[i] - t)
    else:
        for i in range(j, j2):
            out_theta[i], out_v[i] = flow_table_point_kernel(flow, t_eval[i] - t)
