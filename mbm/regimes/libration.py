"""The LIBRATION: a conservative run trapped in a well, exactly periodic from its first instant.

LIBRATION (β = 0, |γ| < ω²; a conservative motion trapped in a well of the tilted
potential, exactly periodic from its first instant).
:func:`libration_period` gives the period and its error bound (C1, C2); the loop (the
entry of :func:`mbm.core.loop._runner`) tests the switch rule (C4) at the run's first
window, and the window is the running cycle's (R3, :mod:`mbm.regimes.cycle`) with winding sign 0 and
a double-double period (C3).  U(x) in double is L3's (:mod:`mbm.regimes.locked`).

The derivation, items C1–C4 (the comments below cite them), is in the
documentation's theory page, ``docs/theory/regimes.md``.
"""

import collections
import math

import numpy as np

from ..special.dd import (
    PI_HI,
    PI_LO,
    PIO2_HI,
    PIO2_LO,
    TWO_PI_HI,
    TWO_PI_LO,
    dd_add,
    dd_div,
    dd_div_d,
    dd_mul,
    dd_mul_d,
    dd_sincos,
    dd_sincos_any,
    dd_sqrt,
    reduce_2pi,
    two_prod,
)
from ..compile.jit import kernel
from .common import REGIME_LIBRATION, SWITCH_SAFETY
from .locked import X_MINUS_SIN_SERIES, _potential

# (C2): first and last node counts of the period's quadrature (doubling): 16 nodes
# reach 1e-25 on small librations; past 2**13 the orbit is at the separatrix, no switch.
LIBRATION_NODES_MIN = 16
LIBRATION_NODES_MAX = 8192
# (C2): the quadrature stops when two successive T_M agree to this (double-double
# carries ~1e-30; this leaves the stored period 1e9 times more exact than a double).
LIBRATION_QUAD_RTOL = 1e-25
# (C2): added to δT, relative: the double-double rounding of the sum and of g (a
# few ulps of 2**-104 times the cancellation of F near the turning points).
LIBRATION_DD_FLOOR = 1e-27
# (C1): double-double Newton steps on the turning points from the double root
# (quadratic: one reaches ~1e-32, the second confirms).
LIBRATION_DD_NEWTON = 3
# (C1): a bracketed Newton in double for the turning points (bisection backs it up).
LIBRATION_NEWTON_STEPS = 100
# (C1): no switch below this amplitude (rad): F's relative precision near the turning
# points scales like 1e-32/r², and at rest there is nothing to extend.
LIBRATION_MIN_AMPLITUDE = 1e-6
# (C1): the energy must be this far (times ω²) below the barrier for the double test
# of trapping to be sure of its answer (the quadrature then judges the separatrix).
LIBRATION_BARRIER_MARGIN = 1e-9
# (C4): spans shorter than this many periods are run window by window (the extension
# re-takes up to a period of windows per output: it pays only over many periods).
LIBRATION_MIN_PERIODS = 16
# (C1): below this |x| the double-double x − sin x by its series (23 terms past x³
# reach 1e-33 relative at 0.25).
DD_X_MINUS_SIN_TERMS = 12

#: The potential's constants in double-double (C1), each a (hi, lo) pair: ``w2`` = ω²,
#: ``cd`` = cos d, ``e`` = ω² sin d − γ; and ``gamma`` = γ (a double).
DDPotential = collections.namedtuple("DDPotential", ("w2", "cd", "e", "gamma"))

#: Where a fresh conservative run's libration test is taken (C4): time ``t``, φ = ``y0``,
#: θ' = ``y1``, the winding count ``k`` and ``off`` = 2πk.
LibrationStart = collections.namedtuple("LibrationStart", ("t", "y0", "y1", "k", "off"))


@kernel
def _dd_potential(pot, xh, xl):
    # (C1): U(x) = 2ω² cos d sin²(x/2) + (ω² sin d − γ) sin x − γ(x − sin x) in
    # double-double; ``pot`` a DDPotential: (w2h, w2l) = ω², (cdh, cdl) = cos d,
    # (eh, el) = ω² sin d − γ.
    (w2h, w2l), (cdh, cdl), (eh, el), gamma = pot.w2, pot.cd, pot.e, pot.gamma
    hh, hl = 0.5 * xh, 0.5 * xl
    sh, sl, ch, cl = dd_sincos_any(hh, hl)
    s2h, s2l = dd_mul(sh, sl, sh, sl)
    sxh, sxl = dd_mul(sh, sl, ch, cl)
    sxh, sxl = 2.0 * sxh, 2.0 * sxl  # sin x = 2 sin(x/2) cos(x/2)
    if abs(xh) < X_MINUS_SIN_SERIES:
        # x − sin x = Σ_{n≥1} (−1)^(n+1) x^(2n+1)/(2n+1)!
        x2h, x2l = dd_mul(xh, xl, xh, xl)
        th, tl = dd_mul(x2h, x2l, xh, xl)
        th, tl = dd_div_d(th, tl, 6.0)
        mh, ml = th, tl
        for n in range(2, DD_X_MINUS_SIN_TERMS + 2):
            th, tl = dd_mul(th, tl, x2h, x2l)
            th, tl = dd_div_d(th, tl, -float((2 * n) * (2 * n + 1)))
            mh, ml = dd_add(mh, ml, th, tl)
    else:
        mh, ml = dd_add(xh, xl, -sxh, -sxl)
    ah, al = dd_mul(w2h, w2l, cdh, cdl)
    ah, al = dd_mul(2.0 * ah, 2.0 * al, s2h, s2l)
    bh, bl = dd_mul(eh, el, sxh, sxl)
    gh, gl = dd_mul_d(mh, ml, gamma)
    uh, ul = dd_add(ah, al, bh, bl)
    return dd_add(uh, ul, -gh, -gl)


@kernel
def _turning_point(w2, gamma, d, h0, edge):
    # (C1): the root of U(x) = H' between 0 and the saddle ``edge`` (U rises from 0 to
    # above H' there), bracketed Newton in double.
    lo, hi = 0.0, edge
    x = 0.5 * edge
    for _ in range(LIBRATION_NEWTON_STEPS):
        f = _potential(w2, gamma, d, x) - h0
        if f == 0.0:
            return x
        if f < 0.0:
            lo = x
        else:
            hi = x
        du = w2 * math.sin(d + x) - gamma
        x_new = x - f / du if du != 0.0 else 0.5 * (lo + hi)
        if not (min(lo, hi) < x_new < max(lo, hi)):
            x_new = 0.5 * (lo + hi)
        if x_new == x:
            break
        x = x_new
    return x


@kernel
def _period_quadrature(pot, h, m, r):
    """(C2): the period as the midpoint rule over ψ of x = m + r sin ψ, M doubled until two
    successive sums agree: ``(t_hi, t_lo, their change)``, nan where the energy H' − U
    is not positive at a node or no M ≤ LIBRATION_NODES_MAX converged.  The potential's
    constants (a :data:`DDPotential`), H' and the turning points' midpoint m and
    half-width r, each a (hi, lo) pair in double-double (:func:`libration_period`)."""
    (hh, hl), (mh, ml), (rh, rl) = h, m, r
    nan = math.nan
    prev_h, prev_l = nan, 0.0
    m_nodes = LIBRATION_NODES_MIN
    while m_nodes <= LIBRATION_NODES_MAX:
        sh_, sl_ = 0.0, 0.0
        for j in range(m_nodes):
            # ψ_j = −π/2 + (j + ½)π/M ((j + ½)/M is exact: M is a power of 2).
            qh, ql = dd_mul_d(PI_HI, PI_LO, (j + 0.5) / m_nodes)
            qh, ql = dd_add(qh, ql, -PIO2_HI, -PIO2_LO)
            snh, snl, csh, csl = dd_sincos(qh, ql)
            xh_, xl_ = dd_mul(rh, rl, snh, snl)
            xh_, xl_ = dd_add(mh, ml, xh_, xl_)
            uh, ul2 = _dd_potential(pot, xh_, xl_)
            fh, fl = dd_add(hh, hl, -uh, -ul2)
            if not (fh > 0.0):
                return nan, nan, nan
            qh, ql = dd_sqrt(2.0 * fh, 2.0 * fl)
            gh, gl = dd_mul(rh, rl, csh, csl)
            gh, gl = dd_div(gh, gl, qh, ql)
            sh_, sl_ = dd_add(sh_, sl_, gh, gl)
        # T_M = (2π/M) Σ g.
        th, tl = dd_mul_d(TWO_PI_HI, TWO_PI_LO, 1.0 / m_nodes)
        th, tl = dd_mul(th, tl, sh_, sl_)
        diff = abs((th - prev_h) + (tl - prev_l))
        if diff <= LIBRATION_QUAD_RTOL * th:
            return th, tl, diff
        prev_h, prev_l = th, tl
        m_nodes *= 2
    return nan, nan, nan


@kernel
def libration_period(gamma, omega, theta, v):
    """The period of the conservative libration through (θ, θ') (items C1, C2).

    Parameters
    ----------
    gamma, omega : float
        The model's torque and ω > 0 (β = 0).
    theta, v : float
        The state.

    Returns
    -------
    t_hi, t_lo : float
        The period T = t_hi + t_lo in double-double; nan, nan where the state is not
        trapped in a well, its amplitude is below LIBRATION_MIN_AMPLITUDE, or the
        quadrature did not converge by LIBRATION_NODES_MAX nodes.
    dt : float
        δT ≥ |t_hi + t_lo − T| (C2).
    v_max : float
        The largest |θ'| on the orbit.
    x_span : float
        x₊ − x₋: θ stays within this of the given θ.
    """
    nan = math.nan
    w2 = omega * omega
    if not (abs(gamma) < w2):
        return nan, nan, nan, nan, nan
    d = math.asin(gamma / w2)
    # (C1): the angle in the well of d, in double-double.
    _j, ph, pl = reduce_2pi(theta)
    if ph > math.pi - d:
        ph, pl = dd_add(ph, pl, -TWO_PI_HI, -TWO_PI_LO)
    elif ph <= -math.pi - d:
        ph, pl = dd_add(ph, pl, TWO_PI_HI, TWO_PI_LO)
    x0h, x0l = dd_add(ph, pl, -d, 0.0)
    xr = math.pi - 2.0 * d
    xl = -math.pi - 2.0 * d
    ur = _potential(w2, gamma, d, xr)
    ul = _potential(w2, gamma, d, xl)
    h0 = 0.5 * v * v + _potential(w2, gamma, d, x0h)
    barrier = min(ur, ul)
    if not (xl < x0h < xr) or not (h0 < barrier - LIBRATION_BARRIER_MARGIN * w2):
        return nan, nan, nan, nan, nan
    # Constants of U in double-double.
    w2h, w2l = two_prod(omega, omega)
    sdh, sdl, cdh, cdl = dd_sincos(d, 0.0)
    eh, el = dd_mul(w2h, w2l, sdh, sdl)
    eh, el = dd_add(eh, el, -gamma, 0.0)
    pot = DDPotential((w2h, w2l), (cdh, cdl), (eh, el), gamma)
    # H' = v²/2 + U(x₀).
    vh, vl = two_prod(v, v)
    uh, ul2 = _dd_potential(pot, x0h, x0l)
    hh, hl = dd_add(0.5 * vh, 0.5 * vl, uh, ul2)
    if not (hh > 0.0):
        return nan, nan, nan, nan, nan
    # (C1): turning points, double then double-double Newton on F = H' − U.
    tp = np.empty(4)
    for side in range(2):
        edge = xr if side == 0 else xl
        xh_ = _turning_point(w2, gamma, d, hh, edge)
        xl_ = 0.0
        for _ in range(LIBRATION_DD_NEWTON):
            uh, ul2 = _dd_potential(pot, xh_, xl_)
            fh, fl = dd_add(hh, hl, -uh, -ul2)
            du = w2 * math.sin(d + xh_) - gamma
            if du == 0.0:
                return nan, nan, nan, nan, nan
            xh_, xl_ = dd_add(xh_, xl_, fh / du, 0.0)
        tp[2 * side] = xh_
        tp[2 * side + 1] = xl_
    mh, ml = dd_add(tp[0], tp[1], tp[2], tp[3])
    mh, ml = 0.5 * mh, 0.5 * ml
    rh, rl = dd_add(tp[0], tp[1], -tp[2], -tp[3])
    rh, rl = 0.5 * rh, 0.5 * rl
    if not (rh >= LIBRATION_MIN_AMPLITUDE):
        return nan, nan, nan, nan, nan
    th, tl, diff = _period_quadrature(pot, (hh, hl), (mh, ml), (rh, rl))
    if th != th:
        return nan, nan, nan, nan, nan
    return th, tl, diff + LIBRATION_DD_FLOOR * th, math.sqrt(2.0 * hh), 2.0 * rh


@kernel
def _libration_test(r, start, gamma, omega, t_bound, tols):
    """The libration test of a fresh conservative run (mbm.regimes, C1-C4) from ``start``
    (a :data:`LibrationStart`): switches the record ``r`` to REGIME_LIBRATION where the
    stored period's phase error over the rest of the span (to ``t_bound``) is within the
    tolerances ``tols`` (a :data:`mbm.regimes.common.Tolerance`; C4)."""
    t, y0, y1, k, off = start.t, start.y0, start.y1, start.k, start.off
    rtol, atol = tols.rtol, tols.atol
    lb_hi, lb_lo, lb_dt, lb_vmax, lb_span = libration_period(gamma, omega, y0, y1)
    if lb_hi == lb_hi:
        n_rest = (t_bound - t) / lb_hi
        drift = (n_rest + 1.0) * lb_dt
        theta_min = max(0.0, abs(off + y0) - lb_span)
        if (n_rest >= LIBRATION_MIN_PERIODS
                and drift * lb_vmax <= SWITCH_SAFETY * (atol + rtol * theta_min)
                and drift * (omega * omega + abs(gamma)) <= SWITCH_SAFETY * atol):
            r.switch.regime = REGIME_LIBRATION
            r.switch.t_regime = t
            r.cycle.cyc_theta, r.cycle.cyc_v, r.cycle.cyc_t, r.cycle.cyc_sign, r.cycle.cyc_wind = y0, y1, t, 0.0, k
            r.cycle.cyc_T, r.cycle.cyc_Tlo = lb_hi, lb_lo
