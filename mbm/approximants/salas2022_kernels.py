r"""Kernels of the second paper's approximants (:mod:`mbm.approximants.salas2022`).

The numba kernels of Salas, Martínez, Ocampo (2022): the Weierstrass ℘ form
(2.3)–(2.16), the cn form (2.17)–(2.24) and the trigonometric form (2.25)–(2.28),
their anchors, evaluators, status codes and tolerances.  The construction is
described in :mod:`mbm.approximants.salas2022`, which registers the Approximant
classes.
"""

import collections
import math

import numba
import numpy as np

from ..special.jacobi import ellipf_kernel, ellipj_kernel
from ..compile.jit import NJIT_OPTIONS, kernel
from ..special.trig import trig_m_kernel
from ..special.weierstrass import wp_kernel, wp_lattice_kernel


# The Chebyshev cubic's coefficient of θ³ in (2.3).
CHEB3 = 2.0 / 13.0
# Largest |γ| (scaled by ω²) for which θ − 2θ³/13 = γ has a root near arcsin γ:
# the cubic's local maximum (2/3)·sqrt(13/6) at θ = sqrt(13/6).
G_CUBIC_MAX = (2.0 / 3.0) * math.sqrt(13.0 / 6.0)
# Newton iterations for d and for the quartic's turning points.  Near a turning
# point convergence is quadratic (< 10 steps), but from the bracket's midpoint
# toward a root next to the double root y = 0 of a tiny amplitude Newton only
# halves the distance per step: amplitude 2e-28 needed ~95 steps (100 stopped it
# 11 % short, test_tiny_amplitude_turning_point_converges); 1100 covers 2^-1074.
ROOT_MAXITER = 1100
# Switch between the two algebraically equal forms of the WW formula: for
# |℘ − c| ≥ this the form in 1/(℘ − c) is used (no overflow near the poles of ℘),
# below it the form in ℘ − c (no division by a small ℘ − c).
WP_FORM_SWITCH = 1.0

#: The Whittaker–Watson anchor of y'² = f(y) (coef[12:18], coef[8:10] of "salas-torque"):
#: y0, y'(0) = yd0, f1 = f′(y0), c = f″(y0)/24, k0 = f(y0) f‴(y0)/24,
#: k1 = f(y0) f⁗(y0)/48, and ℘'s invariants g2, g3.
WhittakerWatson = collections.namedtuple("WhittakerWatson", ("y0", "yd0", "f1", "c", "k0", "k1", "g2", "g3"))

STATUS_OK = 0
STATUS_NO_D = 1
STATUS_UNBOUNDED = 2
STATUS_NONFINITE = 3


@kernel(error_model="numpy")
def cubic_equilibrium(gamma_s):
    """Root d of θ − 2θ³/13 = γ nearest arcsin γ (2.6); nan when |γ| > G_CUBIC_MAX."""
    if abs(gamma_s) > G_CUBIC_MAX:
        return math.nan
    # On [−θm, θm], θm = sqrt(13/6), the cubic is increasing from −G to G: the root
    # there is unique and is the one nearest arcsin γ (the other two lie beyond ±θm).
    hi = math.sqrt(13.0 / 6.0)
    lo = -hi
    x = math.asin(gamma_s) if abs(gamma_s) <= 1.0 else 0.0
    if x > hi:
        x = hi
    for _ in range(ROOT_MAXITER):
        g = x - CHEB3 * x * x * x - gamma_s
        if g > 0.0:
            hi = x
        else:
            lo = x
        dg = 1.0 - 3.0 * CHEB3 * x * x
        xn = x - g / dg if dg > 0.0 else 0.5 * (lo + hi)
        if not (lo < xn < hi):
            xn = 0.5 * (lo + hi)
        if abs(xn - x) <= 2e-16 * max(abs(x), 1e-300):
            x = xn
            break
        x = xn
    return x


@kernel(error_model="numpy")
def _f(y, y0, f0, p, q, r):
    # f(y) − f(y0) factored by (y0 − y) so that f is accurate near the turning points.
    g = p * (y0 + y) + (2.0 * q / 3.0) * (y0 * y0 + y0 * y + y * y) + 0.5 * r * (y0 + y) * (
        y0 * y0 + y * y
    )
    return f0 + (y0 - y) * g


@kernel(error_model="numpy")
def _fprime(y, p, q, r):
    return -2.0 * y * (p + q * y + r * y * y)


@kernel(error_model="numpy")
def _root_between(a, b, y0, f0, p, q, r):
    # f is monotone on [a, b] with a sign change (f(a) > 0 ≥ f(b) or the reverse):
    # safeguarded Newton.
    fa = _f(a, y0, f0, p, q, r)
    lo, hi = a, b
    flo = fa
    x = 0.5 * (a + b)
    for _ in range(ROOT_MAXITER):
        fx = _f(x, y0, f0, p, q, r)
        if fx == 0.0:
            return x
        if (fx > 0.0) == (flo > 0.0):
            lo, flo = x, fx
        else:
            hi = x
        d = _fprime(x, p, q, r)
        xn = x - fx / d if d != 0.0 else 0.5 * (lo + hi)
        if not (min(lo, hi) < xn < max(lo, hi)):
            xn = 0.5 * (lo + hi)
        if abs(xn - x) <= 4e-16 * abs(x) + 1e-300:
            return xn
        x = xn
    return x


@kernel(error_model="numpy")
def _sorted3(a, n):
    """The first ``n`` ≤ 3 items of ``a`` in increasing order, NaN last (np.sort's order),
    as a new array: np.sort compiles numba's whole quicksort (~2 s of a first call)."""
    out = np.empty(n)
    for i in range(n):
        out[i] = a[i]
    for i in range(1, n):
        x = out[i]
        j = i - 1
        # x before out[j] when smaller, or when out[j] is NaN and x is not.
        while j >= 0 and (x < out[j] or (out[j] != out[j] and x == x)):
            out[j + 1] = out[j]
            j -= 1
        out[j + 1] = x
    return out


@kernel(error_model="numpy")
def _turning_points(y0, f0, p, q, r):
    """Turning points (lo, hi) of y'² = f(y) around y0; ok=False if the motion is unbounded."""
    # Critical points of f: 0 and the roots of r y² + q y + p = 0 (r < 0).
    cps = np.empty(3)
    n = 0
    cps[n] = 0.0
    n += 1
    disc = q * q - 4.0 * p * r
    if disc >= 0.0:
        sq = math.sqrt(disc)
        # Cancellation-free quadratic roots.
        qq = -0.5 * (q + math.copysign(sq, q))
        if qq != 0.0:
            cps[n] = qq / r
            n += 1
            cps[n] = p / qq
            n += 1
    cps = _sorted3(cps, n)
    fp0 = _fprime(y0, p, q, r)
    # Upper turning point: the first root of f to the right of y0.
    hi = math.nan
    if f0 == 0.0 and fp0 < 0.0:
        hi = y0
    else:
        a = y0
        for i in range(n):
            c = cps[i]
            if c <= y0:
                continue
            if _f(c, y0, f0, p, q, r) <= 0.0:
                hi = _root_between(a, c, y0, f0, p, q, r) if f0 > 0.0 or a != y0 else y0
                break
            a = c
        if f0 == 0.0 and fp0 == 0.0:
            hi = y0
    lo = math.nan
    if f0 == 0.0 and fp0 > 0.0:
        lo = y0
    else:
        a = y0
        for i in range(n - 1, -1, -1):
            c = cps[i]
            if c >= y0:
                continue
            if _f(c, y0, f0, p, q, r) <= 0.0:
                lo = _root_between(a, c, y0, f0, p, q, r) if f0 > 0.0 or a != y0 else y0
                break
            a = c
        if f0 == 0.0 and fp0 == 0.0:
            lo = y0
    ok = not (math.isnan(lo) or math.isnan(hi))
    return lo, hi, ok


NCOEF = 20


@numba.njit(**NJIT_OPTIONS)  # also called from Python
def salas_torque_anchor(beta, gamma, omega, theta0, v0):
    """Anchor kernel of "salas-torque": coefficient vector (see module docstring)."""
    # np.empty and a loop: np.zeros compiles an implementation of its own (~0.1 s of a first call).
    coef = np.empty(NCOEF)
    for i in range(NCOEF):
        coef[i] = 0.0
    bs = beta / omega
    gs = gamma / (omega * omega)
    d = cubic_equilibrium(gs)
    coef[18] = theta0
    coef[19] = v0
    coef[11] = omega
    coef[10] = bs
    if math.isnan(d):
        coef[0] = STATUS_NO_D
        return coef
    p = 1.0 - 6.0 * d * d / 13.0 - 0.25 * bs * bs  # (2.11)
    q = -6.0 * d / 13.0
    r = -2.0 / 13.0
    y0 = theta0 - d  # (2.12)
    yd0 = 0.5 * bs * y0 + v0 / omega
    f0 = yd0 * yd0
    lo, hi, ok = _turning_points(y0, f0, p, q, r)
    coef[1] = d
    coef[2] = p
    coef[3] = q
    coef[4] = r
    coef[12] = y0
    coef[13] = yd0
    if not ok:
        coef[0] = STATUS_UNBOUNDED
        return coef
    A = lo  # the paper's choice: the lower turning point (Example 1)
    den = 3.0 * A * A * r + 2.0 * A * q + p
    B = -6.0 * A * (A * A * r + A * q + p) / den  # (2.14)
    C = 12.0 / den
    # g2, g3 as invariants of f (equal to (2.14) at any root A, but free of A's error):
    # f = a0 y⁴ + 4a1 y³ + 6a2 y² + 4a3 y + a4.
    a0 = -0.5 * r
    a1 = -q / 6.0
    a2 = -p / 6.0
    a4 = f0 + p * y0 * y0 + (2.0 * q / 3.0) * y0 ** 3 + 0.5 * r * y0 ** 4
    g2 = a0 * a4 + 3.0 * a2 * a2
    g3 = a0 * a2 * a4 - a2 * a2 * a2 - a1 * a1 * a4
    coef[5] = A
    coef[6] = B
    coef[7] = C
    coef[8] = g2
    coef[9] = g3
    f1 = -2.0 * y0 * (p + q * y0 + r * y0 * y0)
    f2 = -2.0 * p - 4.0 * q * y0 - 6.0 * r * y0 * y0
    f3 = -4.0 * q - 12.0 * r * y0
    f4 = -12.0 * r
    coef[14] = f1
    coef[15] = f2 / 24.0
    coef[16] = f0 * f3 / 24.0
    coef[17] = f0 * f4 / 48.0
    for i in range(1, NCOEF):
        if not math.isfinite(coef[i]) and i != 6 and i != 7:
            coef[0] = STATUS_NONFINITE
    return coef


@kernel(error_model="numpy")
def _ww(s, ww):
    """Whittaker–Watson solution of y'² = f(y) anchored at y0 (:data:`WhittakerWatson`
    ``ww``): returns (y, y') at s."""
    y0, yd0, f1, c, k0, k1, g2, g3 = ww
    wp, wpp = wp_kernel(s, g2, g3)
    P = wp - c
    sgn = -yd0  # √f(y0) in WW's formula; the sign follows from ℘′ ~ −2/s³
    wppp = 6.0 * wp * wp - 0.5 * g2  # ℘″ = 6℘² − g2/2
    if abs(P) >= WP_FORM_SWITCH:
        u = 1.0 / P
        du = -wpp * u * u
        nn = sgn * wpp * u * u + 0.5 * f1 * u + k0 * u * u
        dd = 2.0 - k1 * u * u
        dnn = sgn * (wppp * u * u - 2.0 * wpp * wpp * u * u * u) + 0.5 * f1 * du + 2.0 * k0 * u * du
        ddd = -2.0 * k1 * u * du
    else:
        nn = sgn * wpp + 0.5 * f1 * P + k0
        dd = 2.0 * P * P - k1
        dnn = sgn * wppp + 0.5 * f1 * wpp
        ddd = 4.0 * P * wpp
    y = y0 + nn / dd
    dy = (dnn * dd - nn * ddd) / (dd * dd)
    return y, dy


@kernel(error_model="numpy")
def salas_torque_eval(coef, t):
    """Evaluate θ(t), θ'(t) of an anchored "salas-torque" approximant (2.13) with (2.7)."""
    if t == 0.0:
        return coef[18], coef[19]
    omega = coef[11]
    bs = coef[10]
    s = omega * t
    y, dy = _ww(s, WhittakerWatson(coef[12], coef[13], coef[14], coef[15], coef[16], coef[17], coef[8], coef[9]))
    e = math.exp(-0.5 * bs * s)  # (2.7)
    theta = coef[1] + e * y
    vs = e * (dy - 0.5 * bs * y)
    return theta, omega * vs


@kernel(error_model="numpy")
def salas_torque_eval_array(coef, t, out_theta, out_v):
    """:func:`salas_torque_eval` over an array of times."""
    for i in range(t.size):
        a, b = salas_torque_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


# =============================================================================
# The cn form (2.17)–(2.21), the ℘ ↔ cn relations (2.22)–(2.24) and the
# trigonometric approximants (2.25)–(2.28).
# =============================================================================
#
# Route.  The printed (2.18)–(2.21) determine Ā, c₁ as roots of a sextic and a
# quadratic in c₁² and leave the root choice open.  We instead convert the ℘ form
# (2.13) of "salas-torque" (its A, B, C, g₂, g₃ at the same anchor) through
#
#     ℘(u; g₂, g₃) = a + b / (1 − cn(ω u | m))                          (2.23)
#
# (a, b, ω, m from the roots of 4x³ − g₂x − g₃, see :func:`wp_from_cn_kernel`).
# Then 1 + C℘ = [(1 + Ca)(1 − X) + Cb]/(1 − X), X = cn(ω(s + D)), and
#
#     y = A + (B/C)(1 − X) / (P − R X),   R = 1/C + a,  P = R + b,      (*)
#
# which is (2.17) with
#
#     Ā = A + (B/C)/R,   B̄ = −(B/C) b/(R P),   c₁ = −R/P,   √ω̄ = ω,   c₂ = ω D.
#
# (B/C = −A(A²r + Aq + p)/2 and 1/C = (3A²r + 2Aq + p)/12 by (2.14) stay finite
# where C does not.)  The kernels evaluate (*), not Ā + B̄/(1 + c₁X): for small
# oscillations R → 0 (Example 1 already has P/R = 92), Ā and B̄ grow like 1/R and
# the literal (2.17) loses digits by cancellation, while (*) is as accurate as cn.
# For γ = 0 (q = 0, f even) R = 0 exactly: y is linear in cn and (2.17) holds only
# as the limit c₁ → 0, Ā, B̄ → ∞ (the paper's "γ → 0" remark does not carry over).
#
# Printed formulas, checked in tests/approximants/test_salas2022_cn.py:
# * (2.18), (2.19): the A, B there must be Ā, B̄ (bars lost in print or extraction):
#   with the ℘ form's A the numerator of B̄ is (2.15) itself, i.e. B̄ = 0.  (2.18)'s
#   cn⁻¹ also needs the sign of ẏ0, like the ± of (2.16); (2.19)'s ω is ω̄.
# * (2.20): right as printed (it is minus the eliminant we derive).
# * (2.21): three misprints: −8prĀ²y0² → −18prĀ²y0², −19r²Ā²y0⁴ → −9r²Ā²y0⁴,
#   −4pqqy0³ → −4pqy0³; its c⁰ term is the derived one modulo (2.20).
# * (2.23): right, but √g₂/√(16m² − 16m + 1) must be read as one root
#   √(g₂/(16m² − 16m + 1)) (for g₂ < 0 both factors are imaginary).
# * (2.24): right as printed; which root and sign: see wp_from_cn_kernel.
# * (2.27): the root in "2√(48m² − 48m + 3(1 − Ψ))" closes before (1 − Ψ).
# * (4.35), (4.36): the phase printed is D = 3.17128 of (2.16), in units of t; the cn
#   argument is ω(t + D) = 0.97294t + 3.08547 (as (2.27) writes it), so the printed
#   formulas miss the anchor (θ'(0) = −0.018 instead of 0).  (4.36)'s 3.17441 and
#   6.34882 are ν·D and 2ν·D: the same slip.

# Trigonometric approximant (2.25): the paper's Table 1 covers −1 ≤ m ≤ 0.55 and
# states the approximant is good there; outside it the error of cos_m grows.
TRIG_M_MIN = -1.0
TRIG_M_MAX = 0.55

STATUS_NO_CN = 4
STATUS_TRIG_M = 5

# Coefficient layout of "salas-torque-cn" and "salas-torque-trig" (same anchor).
_CN_D, _CN_P, _CN_Q, _CN_R, _CN_A, _CN_BC, _CN_IC = 1, 2, 3, 4, 5, 6, 7
_CN_G2, _CN_G3, _CN_BS, _CN_OM, _CN_Y0, _CN_YD0 = 8, 9, 10, 11, 12, 13
_CN_WA, _CN_WB, _CN_W, _CN_M, _CN_MC, _CN_RR, _CN_PP = 14, 15, 16, 17, 18, 19, 20
_CN_ABAR, _CN_BBAR, _CN_C1, _CN_OMBAR, _CN_C2, _CN_DD = 21, 22, 23, 24, 25, 26
_CN_X0, _CN_SN0, _CN_DN0, _CN_KAPPA, _CN_NU = 27, 28, 29, 30, 31
_CN_TH0, _CN_V0 = 32, 33
NCOEF_CN = 34

_CN_PARAM_NAMES = (
    "d", "p", "q", "r", "A", "B_over_C", "inv_C", "g2", "g3", "beta_s", "omega",
    "y0", "ydot0", "a", "b", "omega_cn", "m", "mc", "R", "P",
    "Abar", "Bbar", "c1", "omegabar", "c2", "D", "cn_c2", "sn_c2", "dn_c2",
    "kappa", "nu",
)


@kernel(error_model="numpy")
def cn_from_wp_kernel(t, m, mc):
    """cn(t | m) through ℘, the relation (2.22), numba kernel.

    cn(t|m) = 1 − 6/(4m + 1 + 12 ℘(t; g₂, g₃)) with
    g₂ = (16m² − 16m + 1)/12 and g₃ = (2m − 1)(32m² − 32m − 1)/216.

    Parameters
    ----------
    t, m, mc : float
        Argument, parameter and its complement 1 − m (used in
        16m² − 16m + 1 = 1 − 16 m mc, 2m − 1 = m − mc, 32m² − 32m − 1 =
        −1 − 32 m mc, so that m near 1 keeps its digits).

    Returns
    -------
    float
        cn(t | m); 1.0 at t = 0 (the pole of ℘).
    """
    mm = m * mc
    g2 = (1.0 - 16.0 * mm) / 12.0
    g3 = (m - mc) * (-1.0 - 32.0 * mm) / 216.0
    w, _ = wp_kernel(t, g2, g3)
    if w == math.inf:
        return 1.0
    # On the real axis ℘ ≥ its minimum, where 4m + 1 + 12℘ = 3 (cn = −1): no zero
    # denominator.
    return 1.0 - 6.0 / (4.0 * m + 1.0 + 12.0 * w)


@kernel(error_model="numpy")
def wp_from_cn_kernel(g2, g3):
    """a, b, ω, m, mc with ℘(t; g₂, g₃) = a + b/(1 − cn(ωt | m)), (2.23)–(2.24), numba kernel.

    Parameters
    ----------
    g2, g3 : float
        Real invariants, not both zero.

    Returns
    -------
    a, b, omega, m, mc : float
        NaNs for non-finite input and for g₂ = g₃ = 0 (℘ = 1/t² has no cn form).

    Notes
    -----
    (2.22) rescaled (℘(t; g₂, g₃) = λ²℘(λt; λ⁻⁴g₂, λ⁻⁶g₃)) gives (2.23) with
    λ = ω = (12 g₂/(16m² − 16m + 1))^{1/4}, b = ω²/2, a = −(4m + 1) b/6, for every m
    with g₃²/g₂³ equal to that of (2.22) and sign(g₃) = sign((2m − 1)(32m² − 32m − 1)).
    With z = m² − m + 1 the first condition is the cubic (2.24) (printed correctly),
    which has up to three admissible roots, i.e. several valid cn forms.  We take the
    one continuous in (g₂, g₃) through the trigonometric limit m = 0, obtained from
    the roots e₁, e₂, e₃ without solving (2.24):

    * Δ = g₂³ − 27g₃² > 0: on the real axis ℘ ≥ e₁ = a + b/2 (cn = −1), and
      dn = 0 gives e₂, e₃ = a + b/(1 ± √((m − 1)/m)); this is consistent only for
      m < 0, and then (e₁ − e₂)/(e₁ − e₃) = k'² forces
      m = −(1 − k')²/(4k'), 1 − m = (1 + k')²/(4k'), b = 2k'(e₁ − e₃).  This is the
      root z of (2.24) in (1, 33/32) for g₃ > 0 (Example 1: the middle root) and in
      (33/32, ∞) for g₃ < 0 (the largest), with the minus sign in
      m = (1 − √(4z − 3))/2.  (The plus sign of the other root z > 1 gives an m > 1
      form, cn = dn(√m u | 1/m), also valid; the third root has complex m.)
    * Δ < 0: cn(2v)-halving of the Δ < 0 formula of :mod:`mbm.special.weierstrass`,
      ℘ = e₂ + H(1 + cn)/(1 − cn)(2√H t | m), m = 1/2 − 3e₂/(4H) ∈ (0, 1): the root z
      of (2.24) in [3/4, 1).
    * Δ = 0: g₃ > 0 gives m = 0 (cos); g₃ < 0 gives m = 1 (sech), the limit from
      Δ < 0 (the m < 0 form would need m = −∞).
    """
    nan = math.nan
    kind, r1, r2, r3, ds, base, lam2, lh, ll, ms, mcs, kch, kcl = wp_lattice_kernel(g2, g3)
    if not (kind == kind) or kind == 0.0:
        return nan, nan, nan, nan, nan
    if kind < 0.0:
        # Δ < 0: base = e₂, lam2 = H.
        return base - lam2, 2.0 * lam2, 2.0 * (lh + ll), ms, mcs
    if kch == 0.0:
        # Δ = 0, g₃ < 0 (e₁ = e₂): m = 1, a = e₁ − 2(e₁ − e₃), b = 2(e₁ − e₃).
        return base - 2.0 * lam2, 2.0 * lam2, 2.0 * (lh + ll), 1.0, 0.0
    kp = kch + kcl
    # 1 − k' = k²/(1 + k') with k² = (e₂ − e₃)/(e₁ − e₃): no cancellation as k' → 1.
    one_m_kp = ms / (1.0 + kp)
    m = -one_m_kp * one_m_kp / (4.0 * kp)
    mc = (1.0 + kp) * (1.0 + kp) / (4.0 * kp)
    b = 2.0 * kp * lam2
    a = base - kp * lam2
    w = 2.0 * (lh + ll) * math.sqrt(kp)
    return a, b, w, m, mc


@kernel(error_model="numpy")
def _cn_from_wp_loop(t, m, mc, out):
    for i in range(t.shape[0]):
        out[i] = cn_from_wp_kernel(t[i], m[i], mc[i])


@kernel(error_model="numpy")
def _wp_from_cn_loop(g2, g3, oa, ob, ow, om, omc):
    for i in range(g2.shape[0]):
        a, b, w, m, mc = wp_from_cn_kernel(g2[i], g3[i])
        oa[i] = a
        ob[i] = b
        ow[i] = w
        om[i] = m
        omc[i] = mc


# R = 0 (Abar, Bbar of (2.17) infinite) must give inf, not raise: NJIT_OPTIONS' error model.
@kernel(error_model="numpy")
def _cn_anchor(beta, gamma, omega, theta0, v0):
    """Anchor of the cn form (2.17) from the ℘ anchor of "salas-torque" and (2.23)."""
    coef = np.zeros(NCOEF_CN)
    base = salas_torque_anchor(beta, gamma, omega, theta0, v0)
    coef[0] = base[0]
    coef[_CN_TH0] = theta0
    coef[_CN_V0] = v0
    for i in (1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 13):
        coef[i] = base[i]
    if coef[0] != STATUS_OK:
        return coef
    p, q, r, A = base[2], base[3], base[4], base[5]
    y0, yd0 = base[12], base[13]
    # B/C and 1/C of (2.14), finite even where C is not.
    bc = -0.5 * A * (A * A * r + A * q + p)
    ic = (3.0 * A * A * r + 2.0 * A * q + p) / 12.0
    wa, wb, w, m, mc = wp_from_cn_kernel(base[8], base[9])  # (2.23)
    if not (math.isfinite(wa) and math.isfinite(wb) and wb > 0.0):
        coef[0] = STATUS_NO_CN
        return coef
    R = ic + wa
    P = R + wb
    coef[_CN_BC] = bc
    coef[_CN_IC] = ic
    coef[_CN_WA] = wa
    coef[_CN_WB] = wb
    coef[_CN_W] = w
    coef[_CN_M] = m
    coef[_CN_MC] = mc
    coef[_CN_RR] = R
    coef[_CN_PP] = P
    # Phase: X0 = cn(c₂) from y0 by (*), i.e. (1 − X0)/(P − R X0) = η = (y0 − A)/(B/C);
    # sn(c₂)dn(c₂) from ẏ0 = (B/C) b ω sn dn/(P − R X)², which stays accurate at the
    # turning points where √(1 − X0²) would not.  This is (2.18)'s
    # c₂ = cn⁻¹((y0 − Ā − B̄)/(c₁(Ā − y0))) with the sign of ẏ0 (the ± of (2.16)).
    if bc == 0.0:
        # A = 0 (anchored at the equilibrium): y ≡ A, any phase.
        x0 = 1.0
        sn0 = 0.0
        dn0 = 1.0
    else:
        eta = (y0 - A) / bc
        den = 1.0 - eta * R
        x0 = (1.0 - eta * P) / den
        omx = eta * wb / den  # 1 − X0
        opx = (2.0 - eta * (P + R)) / den  # 1 + X0
        s2 = min(max(omx * opx, 0.0), 1.0)
        dn0 = math.sqrt(1.0 - m * s2)
        snd = yd0 * wb / (bc * w * den * den)
        sn0 = snd / dn0
        x0 = min(max(x0, -1.0), 1.0)
    c2 = ellipf_kernel(math.atan2(sn0, x0), m, mc)
    coef[_CN_X0] = x0
    coef[_CN_SN0] = sn0
    coef[_CN_DN0] = dn0
    coef[_CN_C2] = c2
    coef[_CN_DD] = c2 / w  # D of (2.16): c₂ = ω D
    # Displayed constants of (2.17); they grow like 1/R for small oscillations.
    coef[_CN_ABAR] = A + bc / R
    coef[_CN_BBAR] = -bc * wb / (R * P)
    coef[_CN_C1] = -R / P
    coef[_CN_OMBAR] = w * w
    # κ and the frequency factor ν of (2.26), for the trigonometric form.
    kappa = math.sqrt(m * m - 144.0 * m + 144.0)
    coef[_CN_KAPPA] = kappa
    coef[_CN_NU] = math.sqrt((kappa - m + 2.0) / 14.0)
    for i in range(1, NCOEF_CN):
        if not math.isfinite(coef[i]) and i != _CN_ABAR and i != _CN_BBAR and i != _CN_C1:
            coef[0] = STATUS_NONFINITE
    return coef


@kernel(error_model="numpy")
def salas_torque_cn_anchor(beta, gamma, omega, theta0, v0):
    """Anchor kernel of "salas-torque-cn": the cn form (2.17) of the ℘ approximant."""
    return _cn_anchor(beta, gamma, omega, theta0, v0)


@kernel(error_model="numpy")
def _cn_theta(coef, s, X, dXds):
    """θ, θ' from X = cn(φ) (or cos_m(φ)) and dX/ds through (*), (2.7) and s = ωt."""
    A = coef[_CN_A]
    bc = coef[_CN_BC]
    R = coef[_CN_RR]
    P = coef[_CN_PP]
    wb = coef[_CN_WB]
    den = P - R * X
    y = A + bc * (1.0 - X) / den
    dy = -bc * wb * dXds / (den * den)
    bs = coef[_CN_BS]
    omega = coef[_CN_OM]
    e = math.exp(-0.5 * bs * s)  # (2.7)
    return coef[_CN_D] + e * y, omega * e * (dy - 0.5 * bs * y)


@kernel(error_model="numpy")
def salas_torque_cn_eval(coef, t):
    """θ(t), θ'(t) of an anchored "salas-torque-cn": (2.17) with cn(√ω̄ s + c₂ | m), s = ωt."""
    if t == 0.0:
        return coef[_CN_TH0], coef[_CN_V0]
    s = coef[_CN_OM] * t
    w = coef[_CN_W]
    sn, cn, dn, _ = ellipj_kernel(w * s + coef[_CN_C2], coef[_CN_M], coef[_CN_MC])
    return _cn_theta(coef, s, cn, -w * sn * dn)


@kernel(error_model="numpy")
def salas_torque_cn_eval_array(coef, t, out_theta, out_v):
    """:func:`salas_torque_cn_eval` over an array of times."""
    for i in range(t.size):
        a, b = salas_torque_cn_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


@kernel(error_model="numpy")
def salas_torque_trig_anchor(beta, gamma, omega, theta0, v0):
    """Anchor kernel of "salas-torque-trig": the cn anchor, m restricted to (2.25)'s range."""
    coef = _cn_anchor(beta, gamma, omega, theta0, v0)
    if coef[0] == STATUS_OK and not (TRIG_M_MIN <= coef[_CN_M] <= TRIG_M_MAX):
        coef[0] = STATUS_TRIG_M
    return coef


@kernel(error_model="numpy")
def salas_torque_trig_eval(coef, t):
    """θ(t), θ'(t) of "salas-torque-trig": (2.28), cn of (2.17) replaced by cos_m (2.25)."""
    if t == 0.0:
        return coef[_CN_TH0], coef[_CN_V0]
    s = coef[_CN_OM] * t
    w = coef[_CN_W]
    # d cos_m/du = −sin_m · dn_m exactly (mbm.special.trig).
    sm, cm, dm = trig_m_kernel(w * s + coef[_CN_C2], coef[_CN_M])
    return _cn_theta(coef, s, cm, -w * sm * dm)


@kernel(error_model="numpy")
def salas_torque_trig_eval_array(coef, t, out_theta, out_v):
    """:func:`salas_torque_trig_eval` over an array of times."""
    for i in range(t.size):
        a, b = salas_torque_trig_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b
