"""The exact flow of the undamped, unforced pendulum θ'' + ω² sin θ = 0 from any state.

Beléndez et al. (2007) solve θ'' + ω₀² sin θ = 0 from a turning point (their
Eq. (31), θ = 2 arcsin{sin(θ₀/2) sn[K(k) − ω₀t; k]}, implemented as the
approximant "belendez" in :mod:`mbm.approximants.belendez2007`); this module
gives the flow from *any* state (θ₀, θ̇₀), for any real t, as shared numerics
(the splitting approximants compose it with the drift flow):

* libration (m < 1): sin(θ/2) = k sn(ωt + u₀ | m), cos(θ/2) = dn;
* rotation (m > 1): θ = 2 am(s k ω t + u₀ | 1/m), the winding counted so that θ is
  continuous and unbounded;
* the separatrix (m = 1): θ = s(4 arctan e^{ωt+u₀} − π) + 2πj;
* rest (at the bottom, and the inverted equilibrium).

Numerics.  With E = θ'²/2 + 2ω² sin²(θ/2) the Jacobi parameter is
m = E/(2ω²) = sin²(θ/2) + (θ'/2ω)².  Near the separatrix everything is
governed by the complementary parameter, which is computed without
cancellation as mc = 1 − m = (cos(θ/2) − |θ'|/2ω)(cos(θ/2) + |θ'|/2ω) in
double-double, with θ first reduced to [−π, π] in double-double
(:func:`mbm.special.dd.reduce_2pi`; large multiples of 2π cost nothing and the
integer part is added back to the output), cos(θ/2), sin(θ/2) in double-double
and θ'/2ω with its division remainder: the factor cos(θ/2) − |θ'|/2ω is then
exact to ~1e-32 absolute, where a correctly rounded double cos would leave a
relative error ε/|factor| (1e-6 at mc = 1e-10).  The phase u₀ is F(am u₀ | m)
with am u₀ = atan2 of the state, or, at a turning point next to the separatrix
where dF/dφ = 1/cos(θ/2) explodes, ±(K − F(·)) from the quarter-period
relations.  K (:func:`mbm.special.jacobi.ellipk_dd_kernel`) and the Jacobi
argument u = (rate)·t + u₀ are carried in double-double and u is reduced by
the exact half period 2K, so the phase error does not grow with t beyond the
conditioning of the anchor state ("horizon-free"): against 60-digit mpmath
the flow is within ~6e-14 for t <= 100 and ~2e-14 at t = 1e6 in the tests'
cases.

The solver's windows (the approximant "belendez", the exact flow of β = γ = 0) read
the same flow from a table of Taylor expansions over the half period,
:mod:`mbm.special.pendulum_flow_table`, within a few ulps of these kernels.

Kernels: :func:`pendulum_flow_kernel` (one state, one time),
:func:`flow_setup_kernel` / :func:`flow_eval_kernel` (set up once, evaluate
many times), :func:`pendulum_flow_array_kernel`, :func:`period_kernel`.
Python level: :func:`pendulum_flow`, :func:`period` (exported as
``mbm.pendulum_flow`` and ``mbm.period``).
"""

import collections
import math

import numba
import numpy as np

from ..validate import check_state
from ..model import Pendulum
from .dd import (
    TWO_PI_HI,
    TWO_PI_LO,
    dd_add,
    dd_div,
    dd_mul,
    dd_sincos,
    fast_two_sum,
    reduce_2pi,
    two_prod,
    two_sum,
)
from .jacobi import ellipf_kernel, ellipj_kernel, ellipk_dd_kernel
from ..compile.jit import NJIT_OPTIONS, kernel

__all__ = [
    "flow_setup_kernel",
    "flow_eval_kernel",
    "flow_argument_kernel",
    "reduce_half_period_kernel",
    "odd_half_periods",
    "rotation_theta",
    "HalfPeriod",
    "pendulum_flow_kernel",
    "pendulum_flow_array_kernel",
    "period_kernel",
    "pendulum_flow",
    "period",
    "FLOW_PARAM_NAMES",
    "N_FLOW",
    "THETA_REDUCE_MAX",
    "REGIME_LIBRATION",
    "REGIME_ROTATION",
    "REGIME_SEPARATRIX",
    "REGIME_REST",
    "STATUS_OK",
    "STATUS_BAD_OMEGA",
    "STATUS_BAD_STATE",
]

# ---------------------------------------------------------------------------
# Constants
# ---------------------------------------------------------------------------

# Largest |θ₀| accepted: θ₀ − 2πj is exact to ~1e-16 while j·2π's double-double
# error j·2π·2^-107 stays below that; beyond, a finer 2π would be needed (and θ₀
# itself has an ulp of 0.125 there).
THETA_REDUCE_MAX = 1e15

# Regimes (entry "regime" of the setup).  Libration: m < 1 (includes rest at the
# bottom, m = 0); rotation: m > 1; separatrix: m = 1 (mc == 0 exactly) with
# θ' ≠ 0; rest: mc == 0 and θ' == 0 (the inverted equilibrium).
REGIME_LIBRATION = 0
REGIME_ROTATION = 1
REGIME_SEPARATRIX = 2
REGIME_REST = 3

# Status codes of the setup (its last entry).  1 and 4 are left to the Beléndez
# approximants (β, γ ≠ 0; not a libration), which pass these through as coef[0].
STATUS_OK = 0
STATUS_BAD_OMEGA = 2  # ω not finite or not > 0
STATUS_BAD_STATE = 3  # state not finite, |θ₀| > THETA_REDUCE_MAX, or energy overflows

# Names of the entries of flow_setup_kernel's tuple before the status (the
# "belendez" approximant's coef[1:]).
FLOW_PARAM_NAMES = (
    "regime", "omega", "theta0", "v0", "k", "m", "mc", "K", "period", "u0", "sign",
    "par", "parc", "K_lo", "k_lo", "theta_red", "theta_red_lo", "rate", "rate_lo",
    "vscale",
)

#: flow_setup_kernel's result: the entries FLOW_PARAM_NAMES, then the status.
FlowSetup = collections.namedtuple("FlowSetup", FLOW_PARAM_NAMES + ("status",))

#: The elliptic constants of a libration or a rotation (k_lo is 0 for a libration).
EllipticConstants = collections.namedtuple(
    "EllipticConstants", ("k_lo", "par", "parc", "K_hi", "K_lo", "u0", "rate_hi", "rate_lo", "vscale", "per"))

#: The anchor of a flow, reduced (:func:`flow_setup_kernel`): θ₀/2 reduced to [−π/2, π/2]
#: (h_hi + h_lo), its sine (sh_hi + sh_lo, rounded to sh) and cosine ch, w = θ̇₀/(2ω)
#: (w_hi + w_lo) and |w| (aw_hi + aw_lo), all in double-double.
FlowAnchor = collections.namedtuple(
    "FlowAnchor", ("h_hi", "h_lo", "sh_hi", "sh_lo", "sh", "ch", "w_hi", "w_lo", "aw_hi", "aw_lo"))

#: The Jacobi modulus of a flow: k = √m, m, and mc = 1 − m in double-double (mc + mc_lo).
FlowModulus = collections.namedtuple("FlowModulus", ("k", "m", "mc", "mc_lo"))

# Length of flow_setup_kernel's result: FLOW_PARAM_NAMES and the status.
N_FLOW = len(FlowSetup._fields)

_NAN = float("nan")
_INF = float("inf")


# ---------------------------------------------------------------------------
# The exact flow
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def _failed_setup(status):
    x = _NAN
    return FlowSetup(x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, x, float(status))


@kernel(error_model="numpy")
def _half_rate_dd(v0, omega):
    """w = θ̇₀/(2ω) in double-double (the division's rounding matters next to the separatrix)."""
    two_omega = 2.0 * omega
    w_hi = v0 / two_omega
    q_p, q_e = two_prod(w_hi, two_omega)
    w_lo = ((v0 - q_p) - q_e) / two_omega
    if not math.isfinite(w_lo):  # the exact product overflowed (|ω| > ~1e300)
        w_lo = 0.0
    return w_hi, w_lo


@kernel(error_model="numpy")
def _libration_constants(anchor, modulus, omega):
    """Libration, sin(θ/2) = k sn(ωt + u0 | m), from the :data:`FlowAnchor` and
    :data:`FlowModulus` of the state.

    Returns the :data:`EllipticConstants` of :func:`flow_setup_kernel` (k_lo = 0).
    """
    sh, ch, w_hi, w_lo = anchor.sh, anchor.ch, anchor.w_hi, anchor.w_lo
    k, m, mc, mc_lo = modulus
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
    per = (4.0 * K_hi + 4.0 * K_lo) / omega  # Beléndez et al. (2007), Eq. (26)
    return EllipticConstants(0.0, par, parc, K_hi, K_lo, u0, rate_hi, rate_lo, vscale, per)


@kernel(error_model="numpy")
def _rotation_constants(anchor, modulus, sign, omega):
    """Rotation, θ/2 = am(s k ω t + u0 | 1/m), from the :data:`FlowAnchor` and
    :data:`FlowModulus` of the state, s = ``sign``.

    Returns the :data:`EllipticConstants` of :func:`flow_setup_kernel`.
    """
    sh_hi, sh_lo, ch, h_hi, h_lo = anchor.sh_hi, anchor.sh_lo, anchor.ch, anchor.h_hi, anchor.h_lo
    aw_hi, aw_lo = anchor.aw_hi, anchor.aw_lo
    k, m, mc, mc_lo = modulus
    # k in double-double: the rotation rate k ω sets the phase at long times.
    a2, a2e = two_prod(sh_hi, sh_hi)
    a2e += 2.0 * sh_hi * sh_lo
    b2, b2e = two_prod(aw_hi, aw_hi)
    k2, k2e = two_prod(k, k)
    s1, e1 = two_sum(a2, b2)
    resid = (s1 - k2) + (((e1 + a2e) + b2e - k2e) + 2.0 * aw_hi * aw_lo)
    k_lo = resid / (2.0 * k)
    par = 1.0 / m
    # Complement of the rotation parameter, 1 − 1/m = −mc/m, in double-double
    # (m = k² from (k, k_lo)): it sets K(1/m), hence the phase at long times.
    mm_hi, mm_lo = dd_mul(k, k_lo, k, k_lo)
    pc_hi, pc_lo = dd_div(-mc, -mc_lo, mm_hi, mm_lo)
    parc = pc_hi + pc_lo
    # F(θ₀/2 | 1/m), plus the first-order term of the reduction's low part.
    dn0 = math.sqrt(parc + par * ch * ch)
    u0 = ellipf_kernel(h_hi, par, parc) + h_lo / dn0
    K_hi, K_lo = ellipk_dd_kernel(pc_hi, pc_lo)
    r_hi, r_lo = two_prod(k, omega)
    r_lo += k_lo * omega
    rate_hi, rate_lo = fast_two_sum(sign * r_hi, sign * r_lo)
    vscale = 2.0 * sign * omega * k
    per = (2.0 * K_hi + 2.0 * K_lo) / ((k + k_lo) * omega)
    return EllipticConstants(k_lo, par, parc, K_hi, K_lo, u0, rate_hi, rate_lo, vscale, per)


@kernel(error_model="numpy")
def flow_setup_kernel(theta0, v0, omega):
    """Constants of the exact flow of θ'' + ω² sin θ = 0 through (θ₀, θ̇₀).

    Parameters
    ----------
    theta0, v0 : float
        The state at t = 0 (finite; θ₀ may be a large multiple of 2π, up to
        ``|θ₀| <= THETA_REDUCE_MAX = 1e15``).
    omega : float
        ω > 0.

    Returns
    -------
    FlowSetup
        A named tuple of N_FLOW floats ``(regime, omega, theta0, v0, k, m, mc, K, period, u0, sign, par, parc,
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
    _j, th_hi, th_lo = reduce_2pi(theta0)
    h_hi = 0.5 * th_hi
    h_lo = 0.5 * th_lo
    # sin and cos of θ/2 in double-double: mc = (ch − |w|)(ch + |w|) inherits the
    # absolute error of ch divided by ch − |w|, so a correctly rounded double cos
    # would already cost 1e-6 relative in mc at mc = 1e-10.
    sh_hi, sh_lo, ch_hi, ch_lo = dd_sincos(h_hi, h_lo)
    sh = sh_hi + sh_lo
    # cos(θ/2) >= 0 on [−π, π]; the flip only removes a possible −1e-32 at ±π.
    if ch_hi < 0.0:
        ch_hi, ch_lo = -ch_hi, -ch_lo
    ch = ch_hi + ch_lo

    # --- w = θ̇₀/(2ω) in double-double (the division's rounding matters next to
    # the separatrix, where mc is the difference ch − |w|) -----------------------
    w_hi, w_lo = _half_rate_dd(v0, omega)
    s_dir = 1.0 if v0 > 0.0 else (-1.0 if v0 < 0.0 else 0.0)
    aw_hi = abs(w_hi)
    aw_lo = w_lo if w_hi >= 0.0 else -w_lo

    # --- mc = 1 − m = (ch − |w|)(ch + |w|) without cancellation, in double-double:
    # K (hence the phase at t = 1e6) inherits its rounding. ------------------------
    cm_hi, cm_lo = dd_add(ch_hi, ch_lo, -aw_hi, -aw_lo)
    cp_hi, cp_lo = dd_add(ch_hi, ch_lo, aw_hi, aw_lo)
    mc, mc_lo = dd_mul(cm_hi, cm_lo, cp_hi, cp_lo)
    # k = √m = hypot(sin(θ/2), w): never underflows for tiny states.
    k = math.hypot(sh, aw_hi)
    m = k * k
    if not (math.isfinite(mc) and math.isfinite(m)):
        return _failed_setup(STATUS_BAD_STATE)

    k_lo, sign = 0.0, 1.0
    anchor = FlowAnchor(h_hi, h_lo, sh_hi, sh_lo, sh, ch, w_hi, w_lo, aw_hi, aw_lo)
    modulus = FlowModulus(k, m, mc, mc_lo)
    if mc > 0.0:
        # ---------------- libration: sin(θ/2) = k sn(ωt + u0 | m) ----------------
        regime = REGIME_LIBRATION
        k_lo, par, parc, K_hi, K_lo, u0, rate_hi, rate_lo, vscale, per = _libration_constants(
            anchor, modulus, omega)
    elif mc < 0.0:
        # ---------------- rotation: θ/2 = am(s k ω t + u0 | 1/m) ------------------
        regime = REGIME_ROTATION
        sign = s_dir
        k_lo, par, parc, K_hi, K_lo, u0, rate_hi, rate_lo, vscale, per = _rotation_constants(
            anchor, modulus, sign, omega)
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
    return FlowSetup(
        float(regime), omega, theta0, v0, k, m, mc, K_hi, per, u0, sign, par, parc,
        K_lo, k_lo, th_hi, th_lo, rate_hi, rate_lo, vscale, float(STATUS_OK),
    )


#: A Jacobi argument reduced by the half period 2K (:func:`reduce_half_period_kernel`):
#: u = r + (n + n2)·2K, r = r_hi + r_lo in [−K, K] (double-double).
HalfPeriod = collections.namedtuple("HalfPeriod", ("r_hi", "r_lo", "n", "n2"))


@kernel(error_model="numpy")
def flow_argument_kernel(flow, t):
    """The Jacobi argument u = rate·t + u0 of the :data:`FlowSetup` ``flow`` at time ``t``,
    in double-double ``(u_hi, u_lo)``; u_lo is not finite where the product overflows."""
    # At t = 1e6 the plain product would already cost ~1e-10 of phase.
    p, pe = two_prod(flow.rate, t)
    pe += flow.rate_lo * t
    u_hi, u_lo = two_sum(p, flow.u0)
    u_lo += pe
    return u_hi, u_lo


@kernel(error_model="numpy")
def reduce_half_period_kernel(u_hi, u_lo, K_hi, K_lo):
    """u = u_hi + u_lo reduced by the exact half period 2K (K = K_hi + K_lo): a :data:`HalfPeriod`.

    sn, cn change sign and am advances by π per half period, dn is unchanged.
    """
    P_hi, P_lo = 2.0 * K_hi, 2.0 * K_lo
    n = np.floor((u_hi + u_lo) / P_hi + 0.5)
    q, qe = two_prod(n, P_hi)
    r_hi, r_lo = dd_add(u_hi, u_lo, -q, -(qe + n * P_lo))
    # Second pass: the quotient was rounded (r just outside [−K, K]), or, for
    # |u| ≳ 1e16, P_hi alone was off by n·P_lo > K.  n + n2 may not be
    # representable then, so the two counts are kept apart.
    n2 = np.floor(r_hi / P_hi + 0.5)
    if n2 != 0.0:
        q, qe = two_prod(n2, P_hi)
        r_hi, r_lo = dd_add(r_hi, r_lo, -q, -(qe + n2 * P_lo))
    return HalfPeriod(r_hi, r_lo, n, n2)


@kernel(error_model="numpy")
def odd_half_periods(n, n2):
    """Whether n + n2 is odd (a double above 2^53 is even)."""
    return (n - 2.0 * np.floor(0.5 * n)) != (n2 - 2.0 * np.floor(0.5 * n2))


@kernel(error_model="numpy")
def rotation_theta(flow, two_am, n, n2):
    """θ of a rotation from 2 am(r) ∈ [−π, π] of the reduced argument and the half
    periods n + n2 removed: θ = 2 am(r) + 2π(n + n2), added in double-double."""
    theta0, th_hi, th_lo = flow.theta0, flow.theta_red, flow.theta_red_lo
    d = (two_am - th_hi) - th_lo
    if n == 0.0 and n2 == 0.0:
        return theta0 + d
    b_hi, b_lo = two_prod(n, TWO_PI_HI)
    b_lo += n * TWO_PI_LO + n2 * TWO_PI_HI
    s1, e1 = two_sum(b_hi, d)
    s2, e2 = two_sum(theta0, s1)
    return s2 + ((e2 + e1) + b_lo)


@kernel(error_model="numpy")
def flow_eval_kernel(flow, t):
    """Evaluate the exact flow set up by :func:`flow_setup_kernel` at time ``t``.

    ``flow`` is the :data:`FlowSetup` (its status OK).  Returns ``(theta, theta_dot)``;
    exactly ``(theta0, v0)`` at ``t == 0.0``.
    """
    regime, theta0, v0, k, sign, vscale = flow.regime, flow.theta0, flow.v0, flow.k, flow.sign, flow.vscale
    par, parc, K_hi, K_lo = flow.par, flow.parc, flow.K, flow.K_lo
    th_hi, th_lo = flow.theta_red, flow.theta_red_lo
    if t == 0.0:
        return theta0, v0
    if not math.isfinite(t):
        return _NAN, _NAN
    if regime == REGIME_REST:
        return theta0, 0.0

    # Jacobi argument u = rate·t + u0 in double-double.
    u_hi, u_lo = flow_argument_kernel(flow, t)
    if not math.isfinite(u_lo):
        # |rate·t| > ~1e300: the exact product overflows; the phase is meaningless there.
        return _NAN, _NAN

    if regime == REGIME_SEPARATRIX:
        u = u_hi + u_lo
        # θ = s(4 arctan e^u − π) = 2 s gd(u),  gd(u) = atan(sinh u).
        th_loc = 2.0 * sign * math.atan(math.sinh(u))
        v = vscale / math.cosh(u)
        return theta0 + ((th_loc - th_hi) - th_lo), v

    r_hi, r_lo, n, n2 = reduce_half_period_kernel(u_hi, u_lo, K_hi, K_lo)
    if abs(r_hi) <= 0.5 * K_hi:
        sn, cn, dn, _am = ellipj_kernel(r_hi + r_lo, par, parc)
    else:
        # Quarter-period shift with our double-double K (A&S 16.8.1):
        # sn(K − x) = cd x, cn(K − x) = k' sd x, dn(K − x) = k'/dn x, x = K − |r|.
        # cn, dn stay relatively accurate near r = ±K, and ellipj_kernel runs on
        # |x| <= K/2, where it needs no K of its own (half the cost).
        sg = 1.0 if r_hi > 0.0 else -1.0
        x_hi, x_lo = dd_add(K_hi, K_lo, -sg * r_hi, -sg * r_lo)
        s_x, c_x, d_x, _am = ellipj_kernel(max(x_hi + x_lo, 0.0), par, parc)
        kc = math.sqrt(parc)
        sn = sg * (c_x / d_x)
        cn = kc * s_x / d_x
        dn = kc / d_x

    if regime == REGIME_LIBRATION:
        if odd_half_periods(n, n2):
            sn = -sn
            cn = -cn
        # Beléndez et al. (31) generalized: sin(θ/2) = k sn, cos(θ/2) = dn (> 0 in libration), so
        # θ = 2 atan2(k sn, dn) stays accurate at the turning points, where the
        # paper's 2 arcsin(k sn) loses half the digits.
        th_loc = 2.0 * math.atan2(k * sn, dn)
        return theta0 + ((th_loc - th_hi) - th_lo), vscale * cn

    # Rotation: θ = 2 am(u) = 2 am(r) + 2πn, with am(r) ∈ [−π/2, π/2] for |r| ≤ K.
    return rotation_theta(flow, 2.0 * math.atan2(sn, cn), n, n2), vscale * dn


@numba.njit(**NJIT_OPTIONS)
def pendulum_flow_kernel(theta0, v0, omega, t):
    """Exact flow of θ'' + ω² sin θ = 0: the state at time t from (θ₀, θ̇₀) at 0.

    Generalizes Beléndez et al. (2007), Eq. (31), to any state and any real t
    (negative too): libration ``sin(θ/2) = k sn(ωt + u0 | m)``, rotation
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
        non-finite values, ``|θ₀| > 1e15``, energy overflow) and for ``|ω t| > ~1e300``.

    Notes
    -----
    Cost ~1 µs (setup ~0.7 µs: double-double sin/cos, AGM and F; evaluation
    ~0.3 µs).  To evaluate many times from one state, anchor once with
    :func:`flow_setup_kernel` / the "belendez" approximant and call the eval kernel.
    """
    f = flow_setup_kernel(theta0, v0, omega)
    if f.status != 0.0:
        return _NAN, _NAN
    return flow_eval_kernel(f, t)


@kernel(error_model="numpy")
def pendulum_flow_array_kernel(theta0, v0, omega, t, out_theta, out_v):
    """:func:`pendulum_flow_kernel` over a contiguous float64 array ``t`` (one setup).

    Writes θ(t[i]), θ'(t[i]) to ``out_theta[i]``, ``out_v[i]``; NaN everywhere for
    invalid input.
    """
    f = flow_setup_kernel(theta0, v0, omega)
    for i in range(t.shape[0]):
        if f.status != 0.0:
            a, b = _NAN, _NAN
        else:
            a, b = flow_eval_kernel(f, t[i])
        out_theta[i] = a
        out_v[i] = b


@numba.njit(**NJIT_OPTIONS)
def period_kernel(theta0, v0, omega):
    """Period of the motion through (θ₀, θ̇₀): T = 4K(m)/ω (Beléndez et al. (26)) for
    libration, 2K(1/m)/(kω) (θ advances by 2π) for rotation, inf on the separatrix / at the
    inverted equilibrium, 2π/ω at the bottom rest (small-oscillation limit).
    NaN for invalid input."""
    f = flow_setup_kernel(theta0, v0, omega)
    if f.status != 0.0:
        return _NAN
    return f.period


# ---------------------------------------------------------------------------
# Python level: the flow and the period
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
        [θ₀, θ̇₀], finite, ``|θ₀| <= 1e15``.
    t : float or array_like
        Times (any real, any shape).

    Returns
    -------
    ndarray, shape (2,) + shape(t)
        [θ(t), θ'(t)]; exactly ``y0`` where t == 0.  NaN where ``|ω t| > ~1e300``.

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
    pendulum_flow_array_kernel(th0, v0, float(model.omega), flat, th, v)
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
        If ``model`` is not a :class:`~mbm.model.Pendulum`.
    ValueError
        If ``model`` has β ≠ 0 or γ ≠ 0, or ``y0`` is not two finite reals
        (with ``|θ₀| <= 1e15``).
    """
    th0, v0 = _validated(model, y0, "period")
    return float(period_kernel(th0, v0, model.omega))
