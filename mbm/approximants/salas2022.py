r"""The second paper: the Weierstrass ℘ approximant for the damped, torqued pendulum.

A. H. Salas, L. J. Martínez, D. L. Ocampo, "Analytical Approximant to a Damped
Pendulum Forced with a Constant Torque", Int. J. Math. Comput. Sci. (2022).

The paper solves θ'' + βθ' + sin θ = γ (ω = 1).  mbm's ω ≠ 1 is reduced to it by
the time scale s = ωt: θ_ss + (β/ω) θ_s + sin θ = γ/ω², θ_s = θ'/ω.  Everything
below is in the scaled time s; the kernels convert at their boundary.

Construction, by the paper's equation numbers:

(2.3)  sin θ ≈ θ − 2θ³/13 (Chebyshev cubic on |θ| ≤ 75°).
(2.4)  θ'' + βθ' + θ − 2θ³/13 = γ: the *model* the approximant solves; re-anchoring
       does not remove this model error (see the tests).
(2.6)  θ = x + d with d the root of θ − 2θ³/13 = γ nearest arcsin γ.  (The paper
       takes d = arcsin γ "for |γ| ≤ 1/2"; its Example 1 prints d = 0.304337, which is
       the cubic's root, not arcsin 0.3 = 0.304693: we use the cubic's root.)
(2.7)  x = e^{−βs/2} y.
(2.8)/(2.12)  y'' + p y + q y² + r y³ = 0 (the printed (2.8) and (2.12) omit "= 0"),
       y(0) = θ₀ − d, y'(0) = β(θ₀ − d)/2 + θ̇₀.
(2.11) p = 1 − 6d²/13 − β²/4, q = −6d/13, r = −2/13, from dropping the factors
       e^{−βs/2}, e^{−βs} of the residual (2.9) → (2.10) (valid for |βs| ≪ 1, which is
       what re-anchoring over short windows provides).
(2.13) y = A + B / (1 + C ℘(s + D; g₂, g₃)),
(2.14) B, C, g₂, g₃ in terms of A, p, q, r,
(2.15) A a root of the quartic 3rA⁴ + 4qA³ + 6pA² − (6py₀² + 4qy₀³ + 3ry₀⁴ + 6ẏ₀²) = 0,
(2.16) D = ±℘⁻¹((y₀ − A − B)/(C(A − y₀))).

Any anchor state.  Multiplying (2.12) by y' and integrating gives y'² = f(y) with the
quartic f(y) = ẏ₀² + p(y₀² − y²) + (2q/3)(y₀³ − y³) + (r/2)(y₀⁴ − y⁴); (2.15) is
−6 f(A) = 0, so A is a turning point of y, and (2.13)–(2.14) is the Whittaker–Watson
§20.6 solution written from that root (g₂, g₃ of (2.14) are the invariants of f, the
same for every root).  The paper's A is the lower turning point of the oscillation
(Example 1: the roots are −4.179, −0.214896, 0.219561, 2.957 and the paper takes
−0.214896).  Evaluating (2.13) needs ℘⁻¹ and a branch for D; instead the kernels
evaluate the equivalent Whittaker–Watson formula anchored at y₀ itself (no root, no
℘⁻¹, any sign of ẏ₀, the anchor reproduced exactly at s = 0):

    y(s) = y₀ + [−ẏ₀ ℘′(s) + ½f′(y₀)(℘(s) − f″(y₀)/24) + f(y₀)f‴(y₀)/24]
                / [2(℘(s) − f″(y₀)/24)² − f(y₀)f⁗(y₀)/48],

with the same g₂, g₃.  (Whittaker–Watson write √f(y₀) ℘′: with ℘′(s) ~ −2/s³ at the
pole the sign that gives y′(0) = ẏ₀ is √f(y₀) = −ẏ₀.)  A, B, C, D of the paper's
form are computed too and exposed in ``params``; the tests check that both forms
give the same function.

The cn form (2.17)–(2.24) ("salas-torque-cn") and the trigonometric forms
(2.25)–(2.28) ("salas-torque-trig") follow the ℘ approximant below; they reuse its
anchor and convert it with (2.23) (see the comment block there for the route and
the misprints found in the printed formulas).

Domain: d exists only for |γ/ω²| ≤ G_CUBIC_MAX (the cubic's maximum), and the
formula describes a bounded motion only when y₀ lies between two turning points of
f (inside the hump of the cubic's potential, not overdamped past p ≤ 0 into an
unbounded y).  Outside, :class:`ApproximantDomainError` is raised: the cubic (2.3)
would send θ to infinity in finite time.
"""

import math

import numba
import numpy as np

from ..special.jacobi import ellipf_kernel, ellipj_kernel
from ..special.jit import NJIT_OPTIONS
from ..special.trig import trig_m_kernel
from ..special.weierstrass import wp_kernel, wp_lattice_kernel
from .base import Approximant, ApproximantDomainError, register

__all__ = ["SalasTorque", "cubic_equilibrium", "G_CUBIC_MAX"]

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

STATUS_OK = 0
STATUS_NO_D = 1
STATUS_UNBOUNDED = 2
STATUS_NONFINITE = 3


@numba.njit(**NJIT_OPTIONS)
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


@numba.njit(**NJIT_OPTIONS)
def _f(y, y0, f0, p, q, r):
    # f(y) − f(y0) factored by (y0 − y) so that f is accurate near the turning points.
    g = p * (y0 + y) + (2.0 * q / 3.0) * (y0 * y0 + y0 * y + y * y) + 0.5 * r * (y0 + y) * (
        y0 * y0 + y * y
    )
    return f0 + (y0 - y) * g


@numba.njit(**NJIT_OPTIONS)
def _fprime(y, p, q, r):
    return -2.0 * y * (p + q * y + r * y * y)


@numba.njit(**NJIT_OPTIONS)
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


@numba.njit(**NJIT_OPTIONS)
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
    cps = np.sort(cps[:n])
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


@numba.njit(**NJIT_OPTIONS)
def salas_torque_anchor(beta, gamma, omega, theta0, v0):
    """Anchor kernel of "salas-torque": coefficient vector (see module docstring)."""
    coef = np.zeros(NCOEF)
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


@numba.njit(**NJIT_OPTIONS)
def _ww(s, y0, yd0, f1, c, k0, k1, g2, g3):
    """Whittaker–Watson solution of y'² = f(y) anchored at y0: returns (y, y')."""
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


@numba.njit(**NJIT_OPTIONS)
def salas_torque_eval(coef, t):
    """Evaluate θ(t), θ'(t) of an anchored "salas-torque" approximant (2.13) with (2.7)."""
    if t == 0.0:
        return coef[18], coef[19]
    omega = coef[11]
    bs = coef[10]
    s = omega * t
    y, dy = _ww(s, coef[12], coef[13], coef[14], coef[15], coef[16], coef[17], coef[8], coef[9])
    e = math.exp(-0.5 * bs * s)  # (2.7)
    theta = coef[1] + e * y
    vs = e * (dy - 0.5 * bs * y)
    return theta, omega * vs


@numba.njit(**NJIT_OPTIONS)
def salas_torque_eval_array(coef, t, out_theta, out_v):
    """:func:`salas_torque_eval` over an array of times."""
    for i in range(t.size):
        a, b = salas_torque_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


_PARAM_NAMES = (
    "d", "p", "q", "r", "A", "B", "C", "g2", "g3", "beta_s", "omega", "y0", "ydot0",
)


@register
class SalasTorque(Approximant):
    """Weierstrass ℘ approximant of the second paper, (2.3)–(2.16), any anchor state.

    ``params`` holds the paper's constants in scaled time s = ωt: d, p, q, r (2.11),
    A, B, C, g2, g3 (2.14)–(2.15), D (2.16, in (−ω₁, ω₁], ω₁ the real half-period),
    the scaled damping ``beta_s`` = β/ω, ``omega``, and y₀, ẏ₀ of (2.12).
    """

    name = "salas-torque"
    citation = "Salas, Martínez, Ocampo (2022), eqs. (2.3)-(2.16)"
    anchors = "any"
    # Re-anchoring converges to the cubic model (2.4), whose distance from the
    # pendulum is the model error: the order refers to the cubic model, measured 1.0
    # (the residual (2.9) − (2.10) is O(βt); tests/test_solver.py's τ sweep).
    measured_order = 1
    compiled_kind = "salas-torque"
    status_messages = {
        STATUS_NO_D: (
            f"|gamma|/omega**2 exceeds {G_CUBIC_MAX:.6f}, the maximum of the Chebyshev cubic "
            "theta - 2 theta**3/13 (2.3): the shift d of (2.6) does not exist"
        ),
        STATUS_UNBOUNDED: (
            "the state is not on a bounded orbit of the Duffing-Helmholtz equation (2.12): "
            "|theta - d| is beyond the hump of the cubic (2.3) (valid for |theta| <= 75 deg), "
            "or the damping makes p of (2.11) too small; the cubic would send theta to "
            "infinity"
        ),
        STATUS_NONFINITE: "non-finite constants (overflow) in (2.14)",
    }
    anchor_kernel = staticmethod(salas_torque_anchor)
    eval_kernel = staticmethod(salas_torque_eval)
    eval_array_kernel = staticmethod(salas_torque_eval_array)

    def check_model(self, model):
        gs = model.gamma / model.omega**2
        if abs(gs) > G_CUBIC_MAX:
            raise ApproximantDomainError(
                f"approximant {self.name!r} needs |gamma|/omega**2 <= {G_CUBIC_MAX:.6f}, got "
                f"gamma={model.gamma!r}, omega={model.omega!r}: "
                + self.status_messages[STATUS_NO_D]
            )

    def param_names(self):
        return _PARAM_NAMES

    def event_center(self, model):
        """The cubic's root d of (2.6), about which the formula oscillates; None past its maximum."""
        d = float(cubic_equilibrium(model.gamma / model.omega**2))
        return None if math.isnan(d) else d

    def params_from_coef(self, coef):
        params = super().params_from_coef(coef)
        params["D"] = _paper_D(params)
        return params


def _paper_D(pr):
    """D of (2.16): ℘(D) = (y₀ − A − B)/(C(A − y₀)), sign from ẏ₀."""
    from ..special import wp, wp_half_period, wp_inverse, wpp

    A, B, C, g2, g3 = pr["A"], pr["B"], pr["C"], pr["g2"], pr["g3"]
    y0, yd0 = pr["y0"], pr["ydot0"]
    if y0 == A:
        return 0.0  # anchored at the turning point A itself: the pole of ℘
    if yd0 == 0.0:
        # At rest away from A: the other turning point, where ℘ takes its minimum,
        # at the half period.  Computing w here would cancel: for amplitudes below
        # ~1e-8 A and y0 carry absolute errors that are large relative to A − y0
        # (amplitude 1e-20 gave w 1.4e-9 below the minimum; 6e-29 gave nonsense).
        return float(wp_half_period(g2, g3))
    w = (y0 - A - B) / (C * (A - y0))
    # y0 at the upper turning point makes w the minimum of ℘ (at the half period),
    # which rounding can undercut by a few ulps: clamp only such undercuts.
    w_min = float(wp(float(wp_half_period(g2, g3)), g2, g3))
    if w_min - 1e-9 * abs(w_min) <= w < w_min:
        w = w_min
    z0 = float(wp_inverse(w, g2, g3))
    # (2.13) differentiated: y'(0) = −B C ℘′(D) / (1 + C℘(D))².
    slope = -B * C * float(wpp(z0, g2, g3)) / (1.0 + C * float(wp(z0, g2, g3))) ** 2
    return z0 if slope * yd0 >= 0.0 else -z0


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
# Printed formulas, checked in tests/test_salas2022_cn.py:
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


@numba.njit(**NJIT_OPTIONS)
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


@numba.njit(**NJIT_OPTIONS)
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


@numba.njit(**NJIT_OPTIONS)
def _cn_from_wp_loop(t, m, mc, out):
    for i in range(t.shape[0]):
        out[i] = cn_from_wp_kernel(t[i], m[i], mc[i])


@numba.njit(**NJIT_OPTIONS)
def _wp_from_cn_loop(g2, g3, oa, ob, ow, om, omc):
    for i in range(g2.shape[0]):
        a, b, w, m, mc = wp_from_cn_kernel(g2[i], g3[i])
        oa[i] = a
        ob[i] = b
        ow[i] = w
        om[i] = m
        omc[i] = mc


def _finite_array(name, x):
    a = np.asarray(x, dtype=np.float64)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite, got {x!r}")
    return a


def cn_from_wp(t, m, mc=None):
    """Jacobi cn(t | m) evaluated through the Weierstrass ℘ relation (2.22).

    Parameters
    ----------
    t : array_like
        Real argument.
    m : array_like
        Parameter, any finite real (m < 0 included).
    mc : array_like, optional
        1 − m, when known more accurately than ``1 - m``.

    Returns
    -------
    float or ndarray
        1 − 6/(4m + 1 + 12℘(t; (16m² − 16m + 1)/12, (2m − 1)(32m² − 32m − 1)/216)).

    Raises
    ------
    ValueError
        Non-finite input.

    Examples
    --------
    >>> from mbm.approximants.salas2022 import cn_from_wp
    >>> from mbm.special import cn
    >>> abs(cn_from_wp(1.3, -0.7) - cn(1.3, -0.7)) < 1e-14
    True
    """
    ta = _finite_array("t", t)
    ma = _finite_array("m", m)
    mca = 1.0 - ma if mc is None else _finite_array("mc", mc)
    scalar = ta.ndim == 0 and ma.ndim == 0 and mca.ndim == 0
    b = np.broadcast_arrays(ta, ma, mca)
    shape = b[0].shape
    tf, mf, mcf = (np.ascontiguousarray(x, dtype=np.float64).reshape(-1) for x in b)
    out = np.empty(tf.shape[0])
    _cn_from_wp_loop(tf, mf, mcf, out)
    return float(out[0]) if scalar else out.reshape(shape)


def wp_from_cn(g2, g3):
    """The cn form of ℘, (2.23)–(2.24): ℘(t; g₂, g₃) = a + b/(1 − cn(ωt | m)).

    Parameters
    ----------
    g2, g3 : array_like
        Real invariants, finite, not both zero.

    Returns
    -------
    a, b, omega, m, mc : float or ndarray
        ``a = −(4m + 1) b/6``, ``b = ω²/2 = √(3g₂/(16m² − 16m + 1))``,
        ``omega = ω`` of (2.23); m < 0 when Δ = g₂³ − 27g₃² > 0, 0 < m < 1 when
        Δ < 0 (see :func:`wp_from_cn_kernel` for which root of (2.24) this is);
        ``mc = 1 − m`` computed without cancellation.

    Raises
    ------
    ValueError
        Non-finite input, or g₂ = g₃ = 0.

    Examples
    --------
    Example 1 of the paper, (4.34) (printed: −0.0776374, 0.473306, 0.97294,
    −0.00395178; m is ill-conditioned in the rounded invariants, ±4e-8 here):

    >>> from mbm.approximants.salas2022 import wp_from_cn
    >>> a, b, w, m, mc = wp_from_cn(0.0794131, 0.00345555)
    >>> [round(float(x), 6) for x in (a, b, w)], round(float(m), 7)
    ([-0.077637, 0.473306, 0.97294], -0.0039518)
    """
    g2a = _finite_array("g2", g2)
    g3a = _finite_array("g3", g3)
    scalar = g2a.ndim == 0 and g3a.ndim == 0
    b2, b3 = np.broadcast_arrays(g2a, g3a)
    shape = b2.shape
    f2 = np.ascontiguousarray(b2, dtype=np.float64).reshape(-1)
    f3 = np.ascontiguousarray(b3, dtype=np.float64).reshape(-1)
    if np.any((f2 == 0.0) & (f3 == 0.0)):
        raise ValueError("g2 = g3 = 0: wp(t) = 1/t**2 has no cn form (2.23)")
    outs = [np.empty(f2.shape[0]) for _ in range(5)]
    _wp_from_cn_loop(f2, f3, *outs)
    return tuple(float(o[0]) if scalar else o.reshape(shape) for o in outs)


# R = 0 (Abar, Bbar of (2.17) infinite) must give inf, not raise: NJIT_OPTIONS' error model.
@numba.njit(**NJIT_OPTIONS)
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


@numba.njit(**NJIT_OPTIONS)
def salas_torque_cn_anchor(beta, gamma, omega, theta0, v0):
    """Anchor kernel of "salas-torque-cn": the cn form (2.17) of the ℘ approximant."""
    return _cn_anchor(beta, gamma, omega, theta0, v0)


@numba.njit(**NJIT_OPTIONS)
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


@numba.njit(**NJIT_OPTIONS)
def salas_torque_cn_eval(coef, t):
    """θ(t), θ'(t) of an anchored "salas-torque-cn": (2.17) with cn(√ω̄ s + c₂ | m), s = ωt."""
    if t == 0.0:
        return coef[_CN_TH0], coef[_CN_V0]
    s = coef[_CN_OM] * t
    w = coef[_CN_W]
    sn, cn, dn, _ = ellipj_kernel(w * s + coef[_CN_C2], coef[_CN_M], coef[_CN_MC])
    return _cn_theta(coef, s, cn, -w * sn * dn)


@numba.njit(**NJIT_OPTIONS)
def salas_torque_cn_eval_array(coef, t, out_theta, out_v):
    """:func:`salas_torque_cn_eval` over an array of times."""
    for i in range(t.size):
        a, b = salas_torque_cn_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


@numba.njit(**NJIT_OPTIONS)
def salas_torque_trig_anchor(beta, gamma, omega, theta0, v0):
    """Anchor kernel of "salas-torque-trig": the cn anchor, m restricted to (2.25)'s range."""
    coef = _cn_anchor(beta, gamma, omega, theta0, v0)
    if coef[0] == STATUS_OK and not (TRIG_M_MIN <= coef[_CN_M] <= TRIG_M_MAX):
        coef[0] = STATUS_TRIG_M
    return coef


@numba.njit(**NJIT_OPTIONS)
def salas_torque_trig_eval(coef, t):
    """θ(t), θ'(t) of "salas-torque-trig": (2.28), cn of (2.17) replaced by cos_m (2.25)."""
    if t == 0.0:
        return coef[_CN_TH0], coef[_CN_V0]
    s = coef[_CN_OM] * t
    w = coef[_CN_W]
    # d cos_m/du = −sin_m · dn_m exactly (mbm.special.trig).
    sm, cm, dm = trig_m_kernel(w * s + coef[_CN_C2], coef[_CN_M])
    return _cn_theta(coef, s, cm, -w * sm * dm)


@numba.njit(**NJIT_OPTIONS)
def salas_torque_trig_eval_array(coef, t, out_theta, out_v):
    """:func:`salas_torque_trig_eval` over an array of times."""
    for i in range(t.size):
        a, b = salas_torque_trig_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


_CN_STATUS_MESSAGES = dict(SalasTorque.status_messages)
_CN_STATUS_MESSAGES[STATUS_NO_CN] = (
    "g2 = g3 = 0 (or non-finite): wp = 1/t**2 has no cn form (2.23)"
)


@register
class SalasTorqueCn(Approximant):
    """The cn form (2.17) of the second paper's approximant, any anchor state.

    y = Ā + B̄/(1 + c₁ cn(√ω̄ s + c₂ | m)), s = ωt, θ = d + e^{−βs/2} y: the same
    function as "salas-torque" (2.13), rewritten with (2.23).  The constants come
    from the ℘ form's A, B, C, g₂, g₃ (see the comment block above
    :func:`cn_from_wp_kernel`), not from the sextic (2.20) and quadratic (2.21),
    which the tests check at the computed values.

    ``params`` (scaled time s = ωt, the paper's ω = 1): the ℘ constants d, p, q, r,
    A, B_over_C, inv_C (B/C and 1/C of (2.14)), g2, g3, beta_s, omega, y0, ydot0;
    a, b, omega_cn, m, mc of (2.23) (℘ = a + b/(1 − cn(omega_cn·u | m)));
    R = 1/C + a, P = R + b; Abar, Bbar, c1, omegabar (= omega_cn²), c2 of
    (2.17)–(2.19); D = c2/omega_cn (the ℘ phase of (2.16)); cn_c2, sn_c2, dn_c2
    (cn, sn, dn at c₂); kappa, nu of (2.26).  Abar, Bbar are ±inf where R = 0
    (there (2.17) degenerates to a form linear in cn; the kernels do not use them).
    """

    name = "salas-torque-cn"
    citation = "Salas, Martínez, Ocampo (2022), eqs. (2.17)-(2.24), with (2.3)-(2.16)"
    anchors = "any"
    # Measured order of the moving boundary method against the cubic model (2.4),
    # the same function as "salas-torque" (see tests/test_salas2022_cn.py).
    measured_order = 1
    status_messages = _CN_STATUS_MESSAGES
    anchor_kernel = staticmethod(salas_torque_cn_anchor)
    eval_kernel = staticmethod(salas_torque_cn_eval)
    eval_array_kernel = staticmethod(salas_torque_cn_eval_array)

    def check_model(self, model):
        """Raise :class:`ApproximantDomainError` if |γ|/ω² > G_CUBIC_MAX (no d of (2.6))."""
        SalasTorque.check_model(self, model)

    def param_names(self):
        return _CN_PARAM_NAMES


@register
class SalasTorqueTrig(Approximant):
    """The trigonometric approximant (2.27)–(2.28) of the second paper, any anchor state.

    The cn form (2.17) ("salas-torque-cn", same anchor, same constants) with cn
    replaced by cos_m of (2.25)–(2.26):

        θ = d + e^{−βs/2} (Ā + B̄/(1 + c₁ cos_m(√ω̄ s + c₂))),   s = ωt,

    which is (2.27) with Ψ = cos_m(ω_cn (s + D)) (the two printed forms are the same
    function).  cos_m(u) = √(κ − m + 2) cos(νu)/√(14 + (κ − m − 12) cos²(νu)),
    ν = √((κ − m + 2)/14), κ = √(m² − 144m + 144).

    Error.  |θ_trig − θ_℘| ≤ e^{−βs/2} max|dy/dX| · max|cos_m − cn| with
    dy/dX = −(B/C) b/(P − RX)²: it inherits the error of cos_m (Table 1, 1e-4 to
    7e-3 on −1 ≤ m ≤ 0.55, and much less for |m| ≪ 1, where cos_m − cn = O(m²))
    over the first period of cn; cos_m's period 2π/ν differs from 4K(m), so the
    phase error grows with s beyond it.  Measured over one period of cn on ~3000
    random anchors (θ₀ − d ∈ [−0.8, 1], θ̇₀ ∈ [−0.6, 0.6], β ∈ [0, 1], |γ| ≤ 0.9):
    max |θ_trig − θ_℘| ≈ 1.5e-2 for −1 ≤ m < −0.5, 5e-3 for −0.5 ≤ m < −0.1,
    4e-4 for −0.1 ≤ m < −0.01, 1.2e-6 for |m| < 0.01 (Example 1: m = −0.004).  The formula does not reproduce the anchor
    as t → 0⁺ (it is off by the cos_m error at c₂); ``eval_kernel`` returns the
    stored anchor at t == 0.0 exactly, as the interface requires.  A moving boundary
    run therefore carries an O(cos_m error) jump per window and does not converge as
    τ → 0 (see ``order``).

    Domain: TRIG_M_MIN ≤ m ≤ TRIG_M_MAX (the range of (2.25) and Table 1); outside,
    :class:`ApproximantDomainError`.  For the pendulum f has four real roots, so
    m < 0 always; m < −1 means an orbit near the separatrix of the cubic model.
    """

    name = "salas-torque-trig"
    citation = "Salas, Martínez, Ocampo (2022), eqs. (2.25)-(2.28), with (2.3)-(2.24)"
    anchors = "any"
    # 0: the moving boundary method with this approximant does not converge; its
    # error grows like ε_m T/τ (cos_m misses the anchor by ε_m at each window), see the
    # class docstring and tests/test_salas2022_cn.py.
    measured_order = 0
    status_messages = dict(_CN_STATUS_MESSAGES)
    status_messages[STATUS_TRIG_M] = (
        f"the cn parameter m of (2.23) is outside [{TRIG_M_MIN}, {TRIG_M_MAX}], the range of "
        "the trigonometric approximant cos_m (2.25) and of its Table 1"
    )
    anchor_kernel = staticmethod(salas_torque_trig_anchor)
    eval_kernel = staticmethod(salas_torque_trig_eval)
    eval_array_kernel = staticmethod(salas_torque_trig_eval_array)

    def check_model(self, model):
        """Raise :class:`ApproximantDomainError` if |γ|/ω² > G_CUBIC_MAX (no d of (2.6))."""
        SalasTorque.check_model(self, model)

    def param_names(self):
        return _CN_PARAM_NAMES


__all__ += [
    "SalasTorqueCn",
    "SalasTorqueTrig",
    "cn_from_wp",
    "cn_from_wp_kernel",
    "wp_from_cn",
    "wp_from_cn_kernel",
    "TRIG_M_MIN",
    "TRIG_M_MAX",
]
