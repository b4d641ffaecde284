"""Third paper: A. Beléndez, C. Pascual, D. I. Méndez, T. Beléndez, C. Neipp,
"Exact solution for the nonlinear pendulum" (2007).

The paper solves θ'' + ω₀² sin θ = 0 (its Eq. (1)) from a turning point
θ(0) = θ₀, θ'(0) = 0 (Eq. (3)):

* (23)  τ(z) = K(k) − F(arcsin z; k), τ = ω₀ t, z = sin(θ/2)/sin(θ₀/2);
* (26)  T = 4 K(k)/ω₀;
* (31)  θ(t) = 2 arcsin{ sin(θ₀/2) sn[K(k) − ω₀ t; k] };
* (32)  θ(t) = θ₀ cos(ω t), with the exact angular frequency
* (33)  ω(θ₀) = π ω₀ / (2 K(sin²(θ₀/2))).

NOTE ON NOTATION.  The paper's ``k`` (its Eq. (10)) is the *parameter*
sin²(θ₀/2) of K(k), F(φ; k) and sn(u; k), i.e. what this module calls
``m``.  Here ``k = √m`` is the modulus.  (As extracted, Eq. (32) repeats
Eq. (31); the text around it and Figs. 1–6 make clear that (32) is the
harmonic θ₀ cos(ω t) with the frequency (33).)

What this module adds to the paper:

``pendulum_flow_kernel``
    The exact flow of θ'' + ω² sin θ = 0 from *any* state, for any real t:
    libration (m < 1), rotation (m > 1, with the winding counted so θ is
    continuous and unbounded), the separatrix (m = 1) and rest.  (31) is the
    turning-point case of the libration branch.
``"belendez"``
    That flow as an approximant (it is exact, so a moving boundary run with it
    is limited by round-off only).
``"harmonic"``
    The harmonic approximation (32)–(33), anchored at any libration state:
    θ = c + A cos(ω(θ₀) t + φ) with the exact frequency (33) of the anchor's
    energy, c = 2πj the centre of the swing, and A, φ fitted so that the anchor
    (θ₀, θ̇₀) is reproduced exactly (the approximant interface requires it).
    At a turning point this is (32) itself (A = |θ₀ − c|, φ ∈ {0, π}).  The
    amplitude from the energy, A_E = 2 arcsin k, is exposed as ``A_energy``; it
    is *not* used as A, because A_E cos(φ) = θ₀ and −A_E ω sin(φ) = θ̇₀ cannot
    both hold away from a turning point.
:func:`period`
    The period (26) and its rotation counterpart.

Numerics.  With E = θ'²/2 + 2ω² sin²(θ/2) the Jacobi parameter is
m = E/(2ω²) = sin²(θ/2) + (θ'/2ω)².  Near the separatrix everything is
governed by the complementary parameter, which is computed without
cancellation as mc = 1 − m = (cos(θ/2) − |θ'|/2ω)(cos(θ/2) + |θ'|/2ω) in
double-double, with θ first reduced to [−π, π] in double-double (so large
multiples of 2π cost nothing; the integer part is added back to the output),
cos(θ/2), sin(θ/2) in double-double and θ'/2ω with its division remainder:
the factor cos(θ/2) − |θ'|/2ω is then exact to ~1e-32 absolute, where a
correctly rounded double cos would leave a relative error ε/|factor| (1e-6 at
mc = 1e-10).  The phase u₀ is F(am u₀ | m) with am u₀ = atan2 of the state,
or, at a turning point next to the separatrix where dF/dφ = 1/cos(θ/2)
explodes, ±(K − F(·)) from the quarter-period relations.  K and the Jacobi
argument u = (rate)·t + u₀ are carried in double-double and u is reduced by
the exact half period 2K, so the phase error does not grow with t beyond the
conditioning of the anchor state ("horizon-free"): against 60-digit mpmath
the flow is within ~6e-14 for t <= 100 and ~2e-14 at t = 1e6 in the
tests' cases.
"""

import functools
import math

import numpy as np
from numba import njit as _njit

from ..problem import Pendulum, check_state
from ..special._dd import (
    _dd_add,
    _dd_div,
    _dd_div_d,
    _dd_mul,
    _dd_sqrt,
    _fast_two_sum,
    _two_prod,
    _two_sum,
)
from ..special.jacobi import ellipf_kernel, ellipj_kernel
from .base import Approximant, ApproximantDomainError, register

__all__ = [
    "pendulum_flow_kernel",
    "flow_setup_kernel",
    "flow_eval_kernel",
    "period_kernel",
    "period",
    "pendulum_flow",
    "BelendezExact",
    "BelendezHarmonic",
    "REGIME_LIBRATION",
    "REGIME_ROTATION",
    "REGIME_SEPARATRIX",
    "REGIME_REST",
]

# ---------------------------------------------------------------------------
# Constants
# ---------------------------------------------------------------------------

# 2π and π as unevaluated double-double sums (hi + lo): the reduction of θ₀ and
# the winding 2πn are carried to ~1e-32 relative, so large θ₀ / long rotations
# lose nothing beyond the output's own rounding.
TWO_PI_HI = 6.283185307179586
TWO_PI_LO = 2.4492935982947064e-16
PI_HI = 3.141592653589793
PI_LO = 1.2246467991473532e-16

# Largest |θ₀| accepted: θ₀ − 2πj is exact to ~1e-16 while j·2π's double-double
# error j·2π·2^-107 stays below that; beyond, a finer 2π would be needed (and θ₀
# itself has an ulp of 0.125 there).
THETA_REDUCE_MAX = 1e15

# Taylor terms of the double-double sin/cos at |y| <= π/16: the first omitted
# term y^21/21! < 1e-33.
DD_SINCOS_TERMS = 10

# Cap on AGM iterations for K in double-double.  Convergence is quadratic after
# ~log2(ln(1/mc)) steps; mc down to the smallest subnormal needs < 20.
AGM_MAX_ITER = 64


# AGM stopping point: once the relative gap |a − b|/a is below this, (a + b)/2 is
# within gap²/8 ≈ 1e-33 (relative) of the limit, below double-double round-off.
AGM_GAP_RTOL = 1e-16

# Regimes (coef entry "regime").  Libration: m < 1 (includes rest at the
# bottom, m = 0); rotation: m > 1; separatrix: m = 1 (mc == 0 exactly) with
# θ' ≠ 0; rest: mc == 0 and θ' == 0 (the inverted equilibrium).
REGIME_LIBRATION = 0
REGIME_ROTATION = 1
REGIME_SEPARATRIX = 2
REGIME_REST = 3

# Status codes (coef[0]).
STATUS_OK = 0
STATUS_NOT_CONSERVATIVE = 1  # β ≠ 0 or γ ≠ 0
STATUS_BAD_OMEGA = 2  # ω not finite or not > 0
STATUS_BAD_STATE = 3  # state not finite, |θ₀| > THETA_REDUCE_MAX, or energy overflows
STATUS_NOT_LIBRATION = 4  # harmonic (32)-(33) needs an oscillation

# Length of the tuple returned by flow_setup_kernel: the 20 entries of the
# "belendez" coef[1:] followed by the status.
N_FLOW = 21

# Length of the "harmonic" coef[1:].
N_HARM = 11

_NAN = float("nan")
_INF = float("inf")

# Kernels never raise: a division by zero gives inf/nan (numpy error model), as in
# mbm.special.jacobi, rather than a ZeroDivisionError inside the solver's loop.
njit = functools.partial(_njit, error_model="numpy")


# ---------------------------------------------------------------------------
# Double-double helpers (error-free transformations)
# ---------------------------------------------------------------------------


@njit(cache=True)
def _dd_sincos(xh, xl):
    """sin x and cos x in double-double for |x| <= π/2 (+ tiny).

    Taylor series at x/8 (|x/8| < 0.2: ten terms reach 1e-33) followed by three
    double-angle steps, cos 2y = (c − s)(c + s) keeping cos accurate near π/2.
    Returns ``(sin_hi, sin_lo, cos_hi, cos_lo)``.
    """
    yh, yl = xh * 0.125, xl * 0.125
    y2h, y2l = _dd_mul(yh, yl, yh, yl)
    sh, sl = yh, yl
    ch, cl = 1.0, 0.0
    th, tl = yh, yl  # sin term y^(2n+1)/(2n+1)!
    uh, ul = 1.0, 0.0  # cos term y^(2n)/(2n)!
    for n in range(1, DD_SINCOS_TERMS + 1):
        th, tl = _dd_mul(th, tl, y2h, y2l)
        th, tl = _dd_div_d(th, tl, -float((2 * n) * (2 * n + 1)))
        sh, sl = _dd_add(sh, sl, th, tl)
        uh, ul = _dd_mul(uh, ul, y2h, y2l)
        uh, ul = _dd_div_d(uh, ul, -float((2 * n - 1) * (2 * n)))
        ch, cl = _dd_add(ch, cl, uh, ul)
    for _ in range(3):
        s2h, s2l = _dd_mul(sh, sl, ch, cl)
        dh, dl = _dd_add(ch, cl, -sh, -sl)
        ph, pl = _dd_add(ch, cl, sh, sl)
        ch, cl = _dd_mul(dh, dl, ph, pl)
        sh, sl = 2.0 * s2h, 2.0 * s2l
    return sh, sl, ch, cl


@njit(cache=True)
def ellipk_dd_kernel(mc, mc_lo):
    """Complete elliptic integral K(m) from the complementary parameter, in double-double.

    K(m) = π / (2 AGM(1, √mc)) (Abramowitz & Stegun 17.6), evaluated entirely in
    double-double so that the half period used for argument reduction carries
    ~1e-30 relative error (the horizon-free reduction needs K beyond double).

    Parameters
    ----------
    mc, mc_lo : float
        Complementary parameter 1 − m = mc + mc_lo (double-double), 0 < mc
        (mc > 1, i.e. m < 0, is allowed).

    Returns
    -------
    hi, lo : float
        K = hi + lo.  ``(inf, 0)`` for mc <= 0.
    """
    if not mc > 0.0:
        return _INF, 0.0
    ah, al = 1.0, 0.0
    # mc > 0 here and AGM products stay >= 0; _dd_sqrt rescales a tiny mc itself
    # (its low part would be subnormal).
    bh, bl = _dd_sqrt(mc, mc_lo)
    for _ in range(AGM_MAX_ITER):
        if abs(ah - bh) <= AGM_GAP_RTOL * ah:
            break
        ph, pl = _dd_mul(ah, al, bh, bl)
        sh, sl = _dd_add(ah, al, bh, bl)
        ah, al = 0.5 * sh, 0.5 * sl
        bh, bl = _dd_sqrt(ph, pl)
    # The mean (a + b)/2 is within gap²/(8a) of the limit (one more AGM step).
    mh, ml = _dd_add(ah, al, bh, bl)
    # K = (π/2) / AGM
    return _dd_div(0.5 * PI_HI, 0.5 * PI_LO, 0.5 * mh, 0.5 * ml)


# ---------------------------------------------------------------------------
# The exact flow
# ---------------------------------------------------------------------------


@njit(cache=True)
def _failed_setup(status):
    x = _NAN
    return (x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, float(status))


@njit(cache=True)
def flow_setup_kernel(theta0, v0, omega):
    """Constants of the exact flow of θ'' + ω² sin θ = 0 through (θ₀, θ̇₀).

    Parameters
    ----------
    theta0, v0 : float
        The state at t = 0 (finite; θ₀ may be a large multiple of 2π, up to
        |θ₀| <= THETA_REDUCE_MAX = 1e15).
    omega : float
        ω > 0.

    Returns
    -------
    tuple of N_FLOW floats
        ``(regime, omega, theta0, v0, k, m, mc, K, period, u0, sign, par, parc,
        K_lo, k_lo, theta_red, theta_red_lo, rate, rate_lo, vscale, status)``
        where ``par``/``parc`` are the Jacobi parameter and its complement actually
        used (m and mc in libration, 1/m and −mc/m in rotation), ``K + K_lo`` is
        K(par) in double-double, ``u0`` the Jacobi argument at t = 0, ``rate +
        rate_lo`` its rate du/dt, ``theta_red + theta_red_lo`` the anchor θ₀
        reduced to [−π, π], and ``vscale`` the factor of θ' (2kω for libration,
        2sωk for rotation, 2sω on the separatrix).  ``status`` is STATUS_OK or
        STATUS_BAD_STATE / STATUS_BAD_OMEGA.
    """
    if not (math.isfinite(omega) and omega > 0.0):
        return _failed_setup(STATUS_BAD_OMEGA)
    if not (math.isfinite(theta0) and math.isfinite(v0)) or abs(theta0) > THETA_REDUCE_MAX:
        return _failed_setup(STATUS_BAD_STATE)

    # --- θ₀ reduced to [−π, π] exactly: θ₀ − 2πj in double-double ---------------
    # np.floor, not math.floor: numba's math.floor returns an int64 (overflows).
    j = np.floor(theta0 / TWO_PI_HI + 0.5)
    if j == 0.0:
        th_hi, th_lo = theta0, 0.0
    else:
        p_hi, p_lo = _two_prod(j, TWO_PI_HI)
        d, d_err = _two_sum(theta0, -p_hi)
        th_hi, th_lo = _two_sum(d, (d_err - p_lo) - j * TWO_PI_LO)
    # The rounded quotient can be off by one at the boundary (θ₀ = fl(π) gives
    # j = 1 and a remainder just below −π, in the neighbouring well).
    if th_hi < -PI_HI or (th_hi == -PI_HI and th_lo < -PI_LO):
        th_hi, th_lo = _dd_add(th_hi, th_lo, TWO_PI_HI, TWO_PI_LO)
    elif th_hi > PI_HI or (th_hi == PI_HI and th_lo > PI_LO):
        th_hi, th_lo = _dd_add(th_hi, th_lo, -TWO_PI_HI, -TWO_PI_LO)
    h_hi = 0.5 * th_hi
    h_lo = 0.5 * th_lo
    # sin and cos of θ/2 in double-double: mc = (ch − |w|)(ch + |w|) inherits the
    # absolute error of ch divided by ch − |w|, so a correctly rounded double cos
    # would already cost 1e-6 relative in mc at mc = 1e-10.
    sh_hi, sh_lo, ch_hi, ch_lo = _dd_sincos(h_hi, h_lo)
    sh = sh_hi + sh_lo
    # cos(θ/2) >= 0 on [−π, π]; the flip only removes a possible −1e-32 at ±π.
    if ch_hi < 0.0:
        ch_hi, ch_lo = -ch_hi, -ch_lo
    ch = ch_hi + ch_lo

    # --- w = θ̇₀/(2ω) in double-double (the division's rounding matters next to
    # the separatrix, where mc is the difference ch − |w|) -----------------------
    two_omega = 2.0 * omega
    w_hi = v0 / two_omega
    q_p, q_e = _two_prod(w_hi, two_omega)
    w_lo = ((v0 - q_p) - q_e) / two_omega
    if not math.isfinite(w_lo):  # the exact product overflowed (|ω| > ~1e300)
        w_lo = 0.0
    s_dir = 1.0 if v0 > 0.0 else (-1.0 if v0 < 0.0 else 0.0)
    aw_hi = abs(w_hi)
    aw_lo = w_lo if w_hi >= 0.0 else -w_lo

    # --- mc = 1 − m = (ch − |w|)(ch + |w|) without cancellation, in double-double:
    # K (hence the phase at t = 1e6) inherits its rounding. ------------------------
    cm_hi, cm_lo = _dd_add(ch_hi, ch_lo, -aw_hi, -aw_lo)
    cp_hi, cp_lo = _dd_add(ch_hi, ch_lo, aw_hi, aw_lo)
    mc, mc_lo = _dd_mul(cm_hi, cm_lo, cp_hi, cp_lo)
    # k = √m = hypot(sin(θ/2), w): never underflows for tiny states.
    k = math.hypot(sh, aw_hi)
    m = k * k
    if not (math.isfinite(mc) and math.isfinite(m)):
        return _failed_setup(STATUS_BAD_STATE)

    k_lo = 0.0
    sign = 1.0
    if mc > 0.0:
        # ---------------- libration: sin(θ/2) = k sn(ωt + u0 | m) ----------------
        regime = REGIME_LIBRATION
        par, parc = m, mc
        K_hi, K_lo = ellipk_dd_kernel(mc, mc_lo)
        # k sn(u0) = sin(θ₀/2), k cn(u0) = θ̇₀/(2ω), dn(u0) = cos(θ₀/2).
        if ch * ch >= math.sqrt(mc):
            # u0 = F(am u0), am u0 = atan2(sn, cn): no arcsin of a number near 1.
            # The rounding of am u0 is amplified by dF/dφ = 1/dn(u0) = 1/ch.
            u0 = ellipf_kernel(math.atan2(sh, w_hi + w_lo), par, parc)
        else:
            # Near a turning point close to the separatrix 1/ch is huge (at θ₀ =
            # fl(π), θ̇₀ = 0 it is 1.6e16: the rounding of am u0 = fl(π/2) alone
            # would move u0 by ~1).  Use u0 = ±(K − v) with
            # sn v = cd u0, cn v = √mc sd u0 (A&S 16.8), i.e.
            # am v = atan2(θ̇₀/2ω, √mc |sin(θ₀/2)|), amplification ch/√mc instead;
            # the branch point ch² = √mc balances the two.
            v = ellipf_kernel(math.atan2(w_hi + w_lo, math.sqrt(mc) * abs(sh)), par, parc)
            u0 = math.copysign((K_hi - v) + K_lo, sh)
        rate_hi, rate_lo = omega, 0.0
        vscale = 2.0 * k * omega
        per = (4.0 * K_hi + 4.0 * K_lo) / omega  # (26)
    elif mc < 0.0:
        # ---------------- rotation: θ/2 = am(s k ω t + u0 | 1/m) ------------------
        regime = REGIME_ROTATION
        sign = s_dir
        # k in double-double: the rotation rate k ω sets the phase at long times.
        a2, a2e = _two_prod(sh_hi, sh_hi)
        a2e += 2.0 * sh_hi * sh_lo
        b2, b2e = _two_prod(aw_hi, aw_hi)
        k2, k2e = _two_prod(k, k)
        s1, e1 = _two_sum(a2, b2)
        resid = (s1 - k2) + (((e1 + a2e) + b2e - k2e) + 2.0 * aw_hi * aw_lo)
        k_lo = resid / (2.0 * k)
        par = 1.0 / m
        # Complement of the rotation parameter, 1 − 1/m = −mc/m, in double-double
        # (m = k² from (k, k_lo)): it sets K(1/m), hence the phase at long times.
        mm_hi, mm_lo = _dd_mul(k, k_lo, k, k_lo)
        pc_hi, pc_lo = _dd_div(-mc, -mc_lo, mm_hi, mm_lo)
        parc = pc_hi + pc_lo
        # F(θ₀/2 | 1/m), plus the first-order term of the reduction's low part.
        dn0 = math.sqrt(parc + par * ch * ch)
        u0 = ellipf_kernel(h_hi, par, parc) + h_lo / dn0
        K_hi, K_lo = ellipk_dd_kernel(pc_hi, pc_lo)
        r_hi, r_lo = _two_prod(k, omega)
        r_lo += k_lo * omega
        rate_hi, rate_lo = _fast_two_sum(sign * r_hi, sign * r_lo)
        vscale = 2.0 * sign * omega * k
        per = (2.0 * K_hi + 2.0 * K_lo) / ((k + k_lo) * omega)
    elif v0 != 0.0:
        # ---------------- separatrix: sin(θ/2) = s tanh(ωt + u0) ------------------
        regime = REGIME_SEPARATRIX
        sign = s_dir
        par, parc = 1.0, 0.0
        u0 = math.asinh(sign * sh / ch)  # ch = |w| > 0 here
        K_hi, K_lo = _INF, 0.0
        rate_hi, rate_lo = omega, 0.0
        vscale = 2.0 * sign * omega
        per = _INF
    else:
        # ---------------- rest at the inverted equilibrium ------------------------
        # (defensive: from double inputs the double-double cos(θ/2) is never 0,
        # fl(π) itself is a libration with mc = 3.7e-33)
        regime = REGIME_REST
        par, parc = 1.0, 0.0
        u0 = 0.0
        K_hi, K_lo = _INF, 0.0
        rate_hi, rate_lo = 0.0, 0.0
        vscale = 0.0
        per = _INF
    return (
        float(regime), omega, theta0, v0, k, m, mc, K_hi, per, u0, sign, par, parc,
        K_lo, k_lo, th_hi, th_lo, rate_hi, rate_lo, vscale, float(STATUS_OK),
    )


@njit(cache=True)
def flow_eval_kernel(regime, theta0, v0, k, par, parc, K_hi, K_lo, u0, sign,
                     th_hi, th_lo, rate_hi, rate_lo, vscale, t):
    """Evaluate the exact flow set up by :func:`flow_setup_kernel` at time ``t``.

    Returns ``(theta, theta_dot)``; exactly ``(theta0, v0)`` at ``t == 0.0``.
    """
    if t == 0.0:
        return theta0, v0
    if not math.isfinite(t):
        return _NAN, _NAN
    if regime == REGIME_REST:
        return theta0, 0.0

    # Jacobi argument u = rate·t + u0 in double-double: at t = 1e6 the plain
    # product would already cost ~1e-10 of phase.
    p, pe = _two_prod(rate_hi, t)
    pe += rate_lo * t
    u_hi, u_lo = _two_sum(p, u0)
    u_lo += pe
    if not math.isfinite(u_lo):
        # |rate·t| > ~1e300: the exact product overflows; the phase is meaningless there.
        return _NAN, _NAN

    if regime == REGIME_SEPARATRIX:
        u = u_hi + u_lo
        # θ = s(4 arctan e^u − π) = 2 s gd(u),  gd(u) = atan(sinh u).
        th_loc = 2.0 * sign * math.atan(math.sinh(u))
        v = vscale / math.cosh(u)
        return theta0 + ((th_loc - th_hi) - th_lo), v

    # Reduce by the exact half period 2K (double-double): sn, cn change sign,
    # dn is unchanged, am advances by π.
    P_hi, P_lo = 2.0 * K_hi, 2.0 * K_lo
    n = np.floor((u_hi + u_lo) / P_hi + 0.5)
    q, qe = _two_prod(n, P_hi)
    r_hi, r_lo = _dd_add(u_hi, u_lo, -q, -(qe + n * P_lo))
    # Second pass: the quotient was rounded (r just outside [−K, K]), or, for
    # |u| ≳ 1e16, P_hi alone was off by n·P_lo > K.  n + n2 may not be
    # representable then, so the two counts are kept apart.
    n2 = np.floor(r_hi / P_hi + 0.5)
    if n2 != 0.0:
        q, qe = _two_prod(n2, P_hi)
        r_hi, r_lo = _dd_add(r_hi, r_lo, -q, -(qe + n2 * P_lo))
    if abs(r_hi) <= 0.5 * K_hi:
        sn, cn, dn, _am = ellipj_kernel(r_hi + r_lo, par, parc)
    else:
        # Quarter-period shift with our double-double K (A&S 16.8.1):
        # sn(K − x) = cd x, cn(K − x) = k' sd x, dn(K − x) = k'/dn x, x = K − |r|.
        # cn, dn stay relatively accurate near r = ±K, and ellipj_kernel runs on
        # |x| <= K/2, where it needs no K of its own (half the cost).
        sg = 1.0 if r_hi > 0.0 else -1.0
        x_hi, x_lo = _dd_add(K_hi, K_lo, -sg * r_hi, -sg * r_lo)
        s_x, c_x, d_x, _am = ellipj_kernel(max(x_hi + x_lo, 0.0), par, parc)
        kc = math.sqrt(parc)
        sn = sg * (c_x / d_x)
        cn = kc * s_x / d_x
        dn = kc / d_x

    if regime == REGIME_LIBRATION:
        # n + n2 odd (a double above 2^53 is even)
        if (n - 2.0 * np.floor(0.5 * n)) != (n2 - 2.0 * np.floor(0.5 * n2)):
            sn = -sn
            cn = -cn
        # (31) generalized: sin(θ/2) = k sn, cos(θ/2) = dn (> 0 in libration), so
        # θ = 2 atan2(k sn, dn) stays accurate at the turning points, where the
        # paper's 2 arcsin(k sn) loses half the digits.
        th_loc = 2.0 * math.atan2(k * sn, dn)
        return theta0 + ((th_loc - th_hi) - th_lo), vscale * cn

    # Rotation: θ = 2 am(u) = 2 am(r) + 2πn, with am(r) ∈ [−π/2, π/2] for |r| ≤ K.
    two_am = 2.0 * math.atan2(sn, cn)
    d = (two_am - th_hi) - th_lo
    if n == 0.0 and n2 == 0.0:
        return theta0 + d, vscale * dn
    b_hi, b_lo = _two_prod(n, TWO_PI_HI)
    b_lo += n * TWO_PI_LO + n2 * TWO_PI_HI
    s1, e1 = _two_sum(b_hi, d)
    s2, e2 = _two_sum(theta0, s1)
    return s2 + ((e2 + e1) + b_lo), vscale * dn


@njit(cache=True)
def pendulum_flow_kernel(theta0, v0, omega, t):
    """Exact flow of θ'' + ω² sin θ = 0: the state at time t from (θ₀, θ̇₀) at 0.

    Generalizes the paper's (31) to any state and any real t (negative too):
    libration ``sin(θ/2) = k sn(ωt + u0 | m)``, rotation
    ``θ = 2 am(s k ω t + u0 | 1/m)`` with the winding counted (θ continuous and
    unbounded), separatrix ``θ = s(4 arctan e^{ωt+u0} − π) + 2πj``, and rest.

    Parameters
    ----------
    theta0, v0 : float
        State at t = 0.
    omega : float
        ω > 0.
    t : float
        Time.

    Returns
    -------
    theta, theta_dot : float
        Exactly ``(theta0, v0)`` at ``t == 0.0``.  NaN for invalid input (ω <= 0,
        non-finite values, |θ₀| > 1e15, energy overflow) and for |ω t| > ~1e300.

    Notes
    -----
    Cost ~1 µs (setup ~0.7 µs: double-double sin/cos, AGM and F; evaluation
    ~0.3 µs).  To evaluate many times from one state, anchor once with
    :func:`flow_setup_kernel` / the "belendez" approximant and call the eval kernel.
    """
    (regime, _om, _th0, _v0, k, _m, _mc, K_hi, _per, u0, sign, par, parc, K_lo,
     _klo, th_hi, th_lo, rate_hi, rate_lo, vscale, status) = flow_setup_kernel(
        theta0, v0, omega)
    if status != 0.0:
        return _NAN, _NAN
    return flow_eval_kernel(regime, theta0, v0, k, par, parc, K_hi, K_lo, u0, sign,
                            th_hi, th_lo, rate_hi, rate_lo, vscale, t)


@njit(cache=True)
def period_kernel(theta0, v0, omega):
    """Period of the motion through (θ₀, θ̇₀): (26) T = 4K(m)/ω for libration,
    2K(1/m)/(kω) (θ advances by 2π) for rotation, inf on the separatrix / at the
    inverted equilibrium, 2π/ω at the bottom rest (small-oscillation limit).
    NaN for invalid input."""
    res = flow_setup_kernel(theta0, v0, omega)
    if res[N_FLOW - 1] != 0.0:
        return _NAN
    return res[8]


# ---------------------------------------------------------------------------
# Approximant "belendez": the exact flow
# ---------------------------------------------------------------------------


@njit(cache=True)
def belendez_anchor_kernel(beta, gamma, omega, theta0, v0):
    """Anchor the exact flow: ``coef = [status, *flow_setup_kernel(...)[:-1]]``.

    Layout of coef[1:] (``BelendezExact.param_names()``): regime, omega, theta0, v0,
    k, m, mc, K, period, u0, sign, par, parc, K_lo, k_lo, theta_red, theta_red_lo,
    rate, rate_lo, vscale (see :func:`flow_setup_kernel`).  Status
    STATUS_NOT_CONSERVATIVE unless β = γ = 0.
    """
    coef = np.empty(N_FLOW)
    if beta != 0.0 or gamma != 0.0:
        coef[:] = _NAN
        coef[0] = STATUS_NOT_CONSERVATIVE
        return coef
    res = flow_setup_kernel(theta0, v0, omega)
    coef[0] = res[N_FLOW - 1]
    for i in range(N_FLOW - 1):
        coef[1 + i] = res[i]
    return coef


@njit(cache=True)
def belendez_eval_kernel(coef, t):
    """(θ, θ') at time t after the anchor; exactly the anchor at t == 0.0."""
    return flow_eval_kernel(coef[1], coef[3], coef[4], coef[5], coef[12], coef[13],
                            coef[8], coef[14], coef[10], coef[11], coef[16], coef[17],
                            coef[18], coef[19], coef[20], t)


@njit(cache=True)
def belendez_eval_array_kernel(coef, t, out_theta, out_v):
    """:func:`belendez_eval_kernel` over a contiguous float64 array ``t``."""
    for i in range(t.shape[0]):
        a, b = belendez_eval_kernel(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


_FLOW_PARAM_NAMES = (
    "regime", "omega", "theta0", "v0", "k", "m", "mc", "K", "period", "u0", "sign",
    "par", "parc", "K_lo", "k_lo", "theta_red", "theta_red_lo", "rate", "rate_lo",
    "vscale",
)


def _check_conservative(approx_name, model):
    if model.beta != 0.0 or model.gamma != 0.0:
        raise ApproximantDomainError(
            f"approximant {approx_name!r} is the solution of theta'' + omega**2 sin(theta) = 0 "
            f"(Beléndez et al. 2007, Eq. (1)); it needs beta = 0 and gamma = 0, got {model!r}"
        )


@register
class BelendezExact(Approximant):
    """Exact solution of θ'' + ω² sin θ = 0 from any state (Beléndez et al. 2007, (31)).

    Libration, rotation (winding counted), separatrix and rest; see
    :func:`pendulum_flow_kernel`.  ``params`` holds ``k`` (modulus √m), ``m`` (the
    paper's "k", Eq. (10)), ``mc = 1 − m``, ``K`` (of the Jacobi parameter in use),
    ``period`` (Eq. (26) in libration), ``u0`` (Jacobi argument at the anchor),
    ``regime`` (0 libration, 1 rotation, 2 separatrix, 3 rest) and the internals
    of the double-double evaluation.
    """

    name = "belendez"
    # The exact flow: no truncation error, so MBM's default window is the whole span.
    exact = True
    citation = (
        "Beléndez, Pascual, Méndez, Beléndez, Neipp (2007), Eqs. (23), (26), (31), "
        "generalized to any state: libration, rotation and separatrix"
    )
    anchors = "any"
    status_messages = {
        STATUS_NOT_CONSERVATIVE: "beta and gamma must be 0 (undamped, unforced pendulum)",
        STATUS_BAD_OMEGA: "omega must be finite and > 0",
        STATUS_BAD_STATE: (
            "the state must be finite, |theta0| <= 1e15 and its energy representable"
        ),
    }
    anchor_kernel = staticmethod(belendez_anchor_kernel)
    eval_kernel = staticmethod(belendez_eval_kernel)
    eval_array_kernel = staticmethod(belendez_eval_array_kernel)

    def check_model(self, model):
        _check_conservative(self.name, model)

    def param_names(self):
        return _FLOW_PARAM_NAMES


# ---------------------------------------------------------------------------
# Approximant "harmonic": (32)-(33)
# ---------------------------------------------------------------------------


@njit(cache=True)
def harmonic_anchor_kernel(beta, gamma, omega, theta0, v0):
    """Anchor the harmonic approximation (32)-(33).

    Layout of coef[1:] (``BelendezHarmonic.param_names()``): omega, theta0, v0,
    omega_h (Eq. (33)), A, phase, A_energy, period (Eq. (26)), theta_red,
    theta_red_lo (the anchor relative to the centre 2πj of its swing), m.
    Status STATUS_NOT_LIBRATION for a rotation or the separatrix.
    """
    coef = np.empty(1 + N_HARM)
    coef[:] = _NAN
    if beta != 0.0 or gamma != 0.0:
        coef[0] = STATUS_NOT_CONSERVATIVE
        return coef
    res = flow_setup_kernel(theta0, v0, omega)
    if res[N_FLOW - 1] != 0.0:
        coef[0] = res[N_FLOW - 1]
        return coef
    if res[0] != REGIME_LIBRATION:
        coef[0] = STATUS_NOT_LIBRATION
        return coef
    k = res[4]
    mc = res[6]
    K = res[7] + res[13]
    th = res[15] + res[16]
    # (33): ω(θ₀) = π ω₀ / (2K(m)), the exact angular frequency of the motion.
    om_h = 0.5 * PI_HI * omega / K
    # Harmonic through the anchor with that frequency: θ = c + A cos(ω_h t + φ),
    # c = 2πj the centre of the swing.  At a turning point (θ̇₀ = 0) this is (32):
    # A = |θ₀ − c|, φ ∈ {0, π}.
    x = -v0 / om_h
    A = math.hypot(th, x)
    phase = math.atan2(x, th)
    # Exact amplitude of the true motion, sin(A_E/2) = k, from the energy.
    A_E = 2.0 * math.atan2(k, math.sqrt(mc))
    coef[0] = STATUS_OK
    coef[1] = omega
    coef[2] = theta0
    coef[3] = v0
    coef[4] = om_h
    coef[5] = A
    coef[6] = phase
    coef[7] = A_E
    coef[8] = 2.0 * PI_HI / om_h  # (26): T = 4K/ω₀ = 2π/ω(θ₀)
    coef[9] = res[15]
    coef[10] = res[16]
    coef[11] = res[5]
    return coef


@njit(cache=True)
def harmonic_eval_kernel(coef, t):
    """(θ, θ') of the harmonic c + A cos(ω_h t + φ); exactly the anchor at t == 0.0."""
    if t == 0.0:
        return coef[2], coef[3]
    om_h = coef[4]
    A = coef[5]
    arg = om_h * t + coef[6]
    th_loc = A * math.cos(arg)
    return coef[2] + ((th_loc - coef[9]) - coef[10]), -A * om_h * math.sin(arg)


@njit(cache=True)
def harmonic_eval_array_kernel(coef, t, out_theta, out_v):
    """:func:`harmonic_eval_kernel` over a contiguous float64 array ``t``."""
    for i in range(t.shape[0]):
        a, b = harmonic_eval_kernel(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


@register
class BelendezHarmonic(Approximant):
    """Harmonic approximation with the exact frequency (Beléndez et al. 2007, (32)–(33)).

    θ(t) = c + A cos(ω(θ₀) t + φ) with ω(θ₀) = π ω₀ / (2K(m)), Eq. (33), m the
    Jacobi parameter of the anchor's energy, and c = 2πj the centre of the swing.
    A and φ are fitted so the anchor (θ₀, θ̇₀) is reproduced exactly; at a
    turning point (θ̇₀ = 0, the paper's initial conditions (3)) that is
    A = |θ₀ − c|, φ ∈ {0, π}, i.e. exactly Eq. (32).  Away from a turning point
    A differs from the true amplitude ``A_energy`` (2 arcsin k) by the
    anharmonicity of the motion; the paper's formula is the turning-point case.

    Only oscillations (m < 1) are accepted: a rotation or the separatrix has no
    harmonic approximation (ApproximantDomainError).
    """

    name = "harmonic"
    citation = (
        "Beléndez, Pascual, Méndez, Beléndez, Neipp (2007), Eqs. (32)-(33) "
        "(exact frequency from (26)); any libration anchor, (32) itself at turning points"
    )
    anchors = "any"
    status_messages = {
        STATUS_NOT_CONSERVATIVE: "beta and gamma must be 0 (undamped, unforced pendulum)",
        STATUS_BAD_OMEGA: "omega must be finite and > 0",
        STATUS_BAD_STATE: (
            "the state must be finite, |theta0| <= 1e15 and its energy representable"
        ),
        STATUS_NOT_LIBRATION: (
            "the harmonic approximation (32)-(33) needs an oscillation "
            "(energy below the separatrix, m < 1)"
        ),
    }
    anchor_kernel = staticmethod(harmonic_anchor_kernel)
    eval_kernel = staticmethod(harmonic_eval_kernel)
    eval_array_kernel = staticmethod(harmonic_eval_array_kernel)

    def check_model(self, model):
        _check_conservative(self.name, model)

    def param_names(self):
        return ("omega", "theta0", "v0", "omega_h", "A", "phase", "A_energy", "period",
                "theta_red", "theta_red_lo", "m")


# ---------------------------------------------------------------------------
# Python-level wrappers: period (26) and the flow
# ---------------------------------------------------------------------------


def _validated(model, y0, what):
    if not isinstance(model, Pendulum):
        raise TypeError(f"model must be a Pendulum, got {model!r}")
    if model.beta != 0.0 or model.gamma != 0.0:
        raise ValueError(
            f"{what} is defined for the undamped, unforced pendulum only "
            f"(beta = 0, gamma = 0); model = {model!r}"
        )
    y = check_state("y0", y0)
    if abs(y[0]) > THETA_REDUCE_MAX:
        raise ValueError(
            f"y0[0] = theta0 must satisfy |theta0| <= {THETA_REDUCE_MAX:g}, got {y0!r}"
        )
    return float(y[0]), float(y[1])


def pendulum_flow(model, y0, t):
    """Exact state of θ'' + ω² sin θ = 0 at times ``t`` from ``y0`` at t = 0.

    The Python face of :func:`pendulum_flow_kernel` (libration, rotation with the
    winding counted, separatrix; any real t).

    Parameters
    ----------
    model : Pendulum
        Must have β = 0 and γ = 0.
    y0 : array_like, shape (2,)
        [θ₀, θ̇₀], finite, |θ₀| <= 1e15.
    t : float or array_like
        Times (any real, any shape).

    Returns
    -------
    ndarray, shape (2,) + shape(t)
        [θ(t), θ'(t)]; exactly ``y0`` where t == 0.  NaN where |ω t| > ~1e300.

    Raises
    ------
    TypeError, ValueError
        As :func:`period`.
    """
    th0, v0 = _validated(model, y0, "pendulum_flow")
    t_arr = np.asarray(t, dtype=np.float64)
    flat = np.ascontiguousarray(t_arr.reshape(-1))
    th = np.empty_like(flat)
    v = np.empty_like(flat)
    coef = belendez_anchor_kernel(0.0, 0.0, model.omega, th0, v0)
    belendez_eval_array_kernel(coef, flat, th, v)
    return np.stack((th.reshape(t_arr.shape), v.reshape(t_arr.shape)))


def period(model, y0):
    """Period of the undamped pendulum motion through ``y0`` (Beléndez et al. 2007, (26)).

    Parameters
    ----------
    model : Pendulum
        Must have β = 0 and γ = 0: the period of a damped or driven motion is
        not defined here.
    y0 : array_like, shape (2,)
        State [θ₀, θ̇₀] (finite).

    Returns
    -------
    float
        Libration (m < 1): T = 4K(m)/ω, Eq. (26), with m = sin²(θ₀/2) + (θ̇₀/2ω)²
        (m = sin²(θ₀/2) at a turning point, the paper's Eq. (10)); rest at the
        bottom gives 2π/ω (Eq. (27)).  Rotation (m > 1): the time for θ to advance
        by 2π, 2K(1/m)/(√m ω).  ``inf`` on the separatrix and at the inverted
        equilibrium.

    Raises
    ------
    TypeError
        If ``model`` is not a :class:`~mbm.problem.Pendulum`.
    ValueError
        If ``model`` has β ≠ 0 or γ ≠ 0, or ``y0`` is not two finite reals
        (with |θ₀| <= 1e15).
    """
    th0, v0 = _validated(model, y0, "period")
    return float(period_kernel(th0, v0, model.omega))
