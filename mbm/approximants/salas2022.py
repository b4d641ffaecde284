r"""The second paper: the Weierstrass ℘ approximant for the damped, torqued pendulum.

A. H. Salas, L. J. Martínez, D. L. Ocampo, "Analytical Approximant to a Damped
Pendulum Forced with a Constant Torque", Int. J. Math. Comput. Sci. (2022)
(``shared/seeds/001_9fb3f89e72cef176.txt``).

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

Domain: d exists only for |γ/ω²| ≤ G_CUBIC_MAX (the cubic's maximum), and the
formula describes a bounded motion only when y₀ lies between two turning points of
f (inside the hump of the cubic's potential, not overdamped past p ≤ 0 into an
unbounded y).  Outside, :class:`ApproximantDomainError` is raised: the cubic (2.3)
would send θ to infinity in finite time.
"""

import math

import numba
import numpy as np

from ..special.weierstrass import wp_kernel
from .base import Approximant, ApproximantDomainError, register

__all__ = ["SalasTorque", "cubic_equilibrium", "G_CUBIC_MAX"]

# The Chebyshev cubic's coefficient of θ³ in (2.3).
CHEB3 = 2.0 / 13.0
# Largest |γ| (scaled by ω²) for which θ − 2θ³/13 = γ has a root near arcsin γ:
# the cubic's local maximum (2/3)·sqrt(13/6) at θ = sqrt(13/6).
G_CUBIC_MAX = (2.0 / 3.0) * math.sqrt(13.0 / 6.0)
# Newton iterations for d and for the quartic's turning points: quadratic
# convergence from a bracketed start needs < 10; the rest is a safety margin.
ROOT_MAXITER = 100
# Switch between the two algebraically equal forms of the WW formula: for
# |℘ − c| ≥ this the form in 1/(℘ − c) is used (no overflow near the poles of ℘),
# below it the form in ℘ − c (no division by a small ℘ − c).
WP_FORM_SWITCH = 1.0

STATUS_OK = 0
STATUS_NO_D = 1
STATUS_UNBOUNDED = 2
STATUS_NONFINITE = 3


@numba.njit(cache=True)
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


@numba.njit(cache=True)
def _f(y, y0, f0, p, q, r):
    # f(y) − f(y0) factored by (y0 − y) so that f is accurate near the turning points.
    g = p * (y0 + y) + (2.0 * q / 3.0) * (y0 * y0 + y0 * y + y * y) + 0.5 * r * (y0 + y) * (
        y0 * y0 + y * y
    )
    return f0 + (y0 - y) * g


@numba.njit(cache=True)
def _fprime(y, p, q, r):
    return -2.0 * y * (p + q * y + r * y * y)


@numba.njit(cache=True)
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


@numba.njit(cache=True)
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


@numba.njit(cache=True)
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


@numba.njit(cache=True)
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


@numba.njit(cache=True)
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


@numba.njit(cache=True)
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
    # pendulum is the model error: the order refers to the cubic model.
    order = 2
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
    from ..special import wp, wp_inverse, wpp

    A, B, C, g2, g3 = pr["A"], pr["B"], pr["C"], pr["g2"], pr["g3"]
    y0, yd0 = pr["y0"], pr["ydot0"]
    if y0 == A:
        return 0.0  # anchored at the turning point A itself: the pole of ℘
    w = (y0 - A - B) / (C * (A - y0))
    z0 = float(wp_inverse(w, g2, g3))
    # (2.13) differentiated: y'(0) = −B C ℘′(D) / (1 + C℘(D))².
    slope = -B * C * float(wpp(z0, g2, g3)) / (1.0 + C * float(wp(z0, g2, g3))) ** 2
    return z0 if slope * yd0 >= 0.0 else -z0
