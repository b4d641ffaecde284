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

import numpy as np

from .base import Approximant, ApproximantDomainError, register
from .salas2022_kernels import (  # noqa: F401  callers and tests import these from here
    CHEB3, G_CUBIC_MAX, ROOT_MAXITER, WP_FORM_SWITCH, STATUS_OK, STATUS_NO_D,
    STATUS_UNBOUNDED, STATUS_NONFINITE, cubic_equilibrium, _f, _fprime,
    _root_between, _turning_points, NCOEF, salas_torque_anchor, _ww,
    salas_torque_eval, salas_torque_eval_array, TRIG_M_MIN, TRIG_M_MAX,
    STATUS_NO_CN, STATUS_TRIG_M, _CN_D, _CN_P, _CN_Q, _CN_R, _CN_A, _CN_BC, _CN_IC,
    _CN_G2, _CN_G3, _CN_BS, _CN_OM, _CN_Y0, _CN_YD0, _CN_WA, _CN_WB, _CN_W, _CN_M,
    _CN_MC, _CN_RR, _CN_PP, _CN_ABAR, _CN_BBAR, _CN_C1, _CN_OMBAR, _CN_C2, _CN_DD,
    _CN_X0, _CN_SN0, _CN_DN0, _CN_KAPPA, _CN_NU, _CN_TH0, _CN_V0, NCOEF_CN,
    _CN_PARAM_NAMES, cn_from_wp_kernel, wp_from_cn_kernel, _cn_from_wp_loop,
    _wp_from_cn_loop, _cn_anchor, salas_torque_cn_anchor, _cn_theta,
    salas_torque_cn_eval, salas_torque_cn_eval_array, salas_torque_trig_anchor,
    salas_torque_trig_eval, salas_torque_trig_eval_array,
)

__all__ = ["SalasTorque", "cubic_equilibrium", "G_CUBIC_MAX"]


# The largest undercut of ℘'s minimum by w = ℘(D) of (2.16) taken as rounding (D at the
# half period): the turning points A, B are roots of the cubic (2.6), accurate only to
# ~sqrt(eps) relative where two roots nearly coincide (small amplitudes: 1.4e-9 seen at
# amplitude 1e-158); an undercut beyond this is an error, raised.
W_MIN_SLACK = 1e-6

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
    # (the residual (2.9) − (2.10) is O(βt); tests/frontends/test_solver.py's τ sweep).
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
    # which the turning points' rounding can undercut: clamp only such undercuts.
    w_min = float(wp(float(wp_half_period(g2, g3)), g2, g3))
    if w_min - W_MIN_SLACK * abs(w_min) <= w < w_min:
        w = w_min
    z0 = float(wp_inverse(w, g2, g3))
    # (2.13) differentiated: y'(0) = −B C ℘′(D) / (1 + C℘(D))².
    slope = -B * C * float(wpp(z0, g2, g3)) / (1.0 + C * float(wp(z0, g2, g3))) ** 2
    return z0 if slope * yd0 >= 0.0 else -z0


# =============================================================================
# The cn form (2.17)–(2.24) and the trigonometric approximants (2.25)–(2.28);
# the route and the printed formulas' misprints: salas2022_kernels.
# =============================================================================


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
    # the same function as "salas-torque" (see tests/approximants/test_salas2022_cn.py).
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
    # class docstring and tests/approximants/test_salas2022_cn.py.
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
