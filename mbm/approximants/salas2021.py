r"""The first paper: elementary and Johannessen approximants of the damped pendulum.

A. H. Salas, "Elementary Solution to the Damped Pendulum", Int. J. Math. Comput.
Sci. 16(4) (2021) 1647–1652, for

    θ'' + 2εθ' + ω² sin θ = 0,   θ(0) = 0,  θ'(0) = θ̇₀                       (1.1)

i.e. mbm's family with β = 2ε and γ = 0 (γ ≠ 0 is refused).  Four approximants:

``"salas-damped"``          θ = 2 arctan(a e^{−εt} sin f(t)), (2.2), f from (2.5)–(2.6)
                            in closed form (below);
``"salas-damped-linear"``   the same with f ≈ f′(0) t, the paper's practical form;
``"johannessen"``           Johannessen's θ = 2 arcsin(κ e^{−εt} sn(ξ(t), κ² e^{−2εt})), (3.9);
``"johannessen-trig"``      (3.9) with sn replaced by the trigonometric sin_m of
                            (3.12)–(3.13) (:mod:`mbm.special.trig`).

All four take ω ≠ 1 directly (every formula carries ω) and any anchor state; see
"Any anchor state" below.

The elementary solution, (2.2)–(2.8)
------------------------------------
Substituting (2.2) into (1.1) gives (2.3); asking the coefficients of sin f and cos f
to vanish gives (2.4), and eliminating f″ gives (2.5):

    f′(t)² = ω² − ε² − 2a²(2ε² + ω²) / (5a² + 4e^{2εt}).                        (2.5)

(The sin 3f, cos 3f terms of (2.3) are what the ansatz leaves as residual.)  With
c = ω² − ε², E = e^{2ετ}, P = 3a²(ω² − 3ε²)/(4c) and Q = 5a²/4, (2.5) reads
f′ = √c·u with u(E) = √((E + P)/(E + Q)), and s = E turns (2.6) into

    f(t) − f(0) = (√c / 2ε) ∫_1^{e^{2εt}} u(E) dE/E.

With u as the variable (E = (Qu² − P)/(1 − u²)) the integrand is rational; note
Q − P = a²(2ε² + ω²)/(2c) ≥ 0, so 0 < u < 1:

    ∫ u dE/E = 2 artanh u + √(P/Q) ln((u − r)/(u + r)),   r = √(P/Q),  P > 0,
    ∫ u dE/E = 2 artanh u − 2 s arctan(u/s),              s = √(−P/Q), P < 0,

(P/Q = 3(ω² − 3ε²)/(5c) < 3/5 does not depend on a).  The kernels evaluate the
differences without cancellation: 2(artanh u₁ − artanh u₀) =
2 log1p(Δu/(1 + u₀)) + log((E₁ + Q)/(1 + Q)), the log and arctan differences as
log1p(2rΔu/((u₁ + r)(u₀ − r))) and arctan(sΔu/(s² + u₁u₀)), with
Δu = u₁ − u₀ = (Q − P)(E₁ − 1)/((E₁ + Q)(1 + Q)(u₁ + u₀)).  Every term is then
(E₁ − 1)/(2ε) = t·expm1(2εt)/(2εt) times a smooth factor, so the removable 0/0 of
(2.6) at ε → 0 is gone: at ε = 0 exactly, f(t) − f(0) = √c u₀ t, the undamped
Salas approximant.  (The tests compare with adaptive quadrature of (2.6).)

Amplitude a, (2.7)–(2.8), and the misprint.  θ′(0) = θ̇₀ at a zero crossing gives
θ̇₀ = 2a f′(0), which is the quadratic (2.7) in a².  As printed, (2.8) takes the
root with "+√Δ"; for ε² < ω²/3 its denominator 6(3ε² − ω²) is negative and the
numerator positive, so a² < 0 and there is no real a.  The root that exists, and
is O(θ̇₀²) for small θ̇₀, is the "−√Δ" root

    a² = (16(ω² − ε²) − 5θ̇₀² − √Δ) / (24(3ε² − ω²)),
    Δ  = 32θ̇₀²(ω² − 13ε²) + 256(ε² − ω²)² + 25θ̇₀⁴,

which the kernels evaluate as 8θ̇₀²/(16(ω² − ε²) − 5θ̇₀² + √Δ) (same number, no
cancellation, no division by 3ε² − ω²); :func:`paper_amplitude` evaluates the
printed form with either sign for the tests.

Any anchor state
----------------
The paper anchors at a zero crossing.  Two constants are free in (2.2): a and the
value f(0), since (2.4) involves only f′ and f″ (a shift of f changes neither).
The paper fixes f(0) = 0 because θ(0) = 0.  Keeping the phase φ = f(0) free gives
a two-parameter family θ = 2 arctan(a e^{−εt} sin(φ + F(t))), F(t) = ∫_0^t f′,
and any state (θ₀, θ̇₀) below the separatrix (see "Domain") fixes (a, φ): with
U = tan(θ₀/2) and V = θ̇₀(1 + U²)/2 + εU (θ′ = 2u′/(1 + u²) for u = tan(θ/2)),

    a sin φ = U,   a f′(0) cos φ = V,   f′(0)² = c (1 + P)/(1 + Q),

so (a² − U²) f′(0)² = V², which is the quadratic in x = a²

    3(ω² − 3ε²) x² + (4c − 3(ω² − 3ε²)U² − 5V²) x − 4(cU² + V²) = 0.

At U = 0 it is (2.7) (multiplied by −1; V = θ̇₀/2); we take the same branch
(the root that vanishes with U and V), evaluated as 2·4(cU² + V²)/(b + √disc),
then a = √x ≥ 0 and φ = atan2(U f′(0), V): the sign of the paper's a, sign(θ̇₀) in
(2.8), becomes φ = 0 or π, and θ̇₀ = 0 needs no sign at all.  A time shift t₀ with
θ(t₀) = θ₀ in the paper's formula is a special case of this family (the pair
a e^{−εt₀}, f(t₀) plays the role of (a, φ)), but it exists only for states that
the zero-crossing orbit actually reaches; the phase form covers every state and
needs no root finding.  The family is closed under time shifts (f′ depends on t
only through a e^{−εt}), so anchoring at a state of its own trajectory returns the
same function.  θ₀ is first reduced to [−π, π] and the multiple of 2π is added back.

Re-anchoring.  None of the four formulas solves (1.1) exactly (the sin 3f, cos 3f
terms of (2.3); the frozen parameter in (3.9)), and their θ″ at the anchor differs
from −2εθ̇₀ − ω² sin θ₀ by an O(1) amount (ε = 0 Johannessen excepted: it is the
exact solution).  A moving boundary run with window τ therefore converges, as
τ → 0, to the solution of the modified equation θ″ = θ″_formula(θ, θ′), not to the
pendulum; for "salas-damped" it reproduces the single formula for every τ (the
family is closed under time shifts).  The tests pin this acceleration defect.

Johannessen's approximant (3.9)
-------------------------------
With Ω = √(ω² − ε²), κ = θ̇₀/(2Ω) and m(t) = κ² e^{−2εt}, (3.9) is
sin(θ/2) = κ e^{−εt} sn(ξ(t), m(t)) with

    ξ(t) = Ωt − 9κ⁴Ω(1 − (1 + 4εt)e^{−4εt})/(256 ε) − κ²Ω(1 − (1 + 2εt)e^{−2εt})/(8ε).

Second misprint.  As extracted, the first correction of ξ is
9θ̇₀²(1 − (4εt + 1)e^{−4εt})/(4096 ε (ω² − ε²)^{3/2}); that term has units of time²
while ξ is dimensionless.  It must be θ̇₀⁴ (= 16Ω⁴κ⁴, giving the 9κ⁴Ω/(256ε) above):
the two corrections are the secular phase terms Ω[m t − ∫₀ᵗ m dτ]·(1/4, 9m/64) of
the expansion K(m) = (π/2)(1 + m/4 + 9m²/64 + …), with m ∝ e^{−2εt} and m² ∝ e^{−4εt};
the second, κ²Ω/(8ε) = θ̇₀²/(32εΩ), is printed correctly.  With θ̇₀² the errors at small ε
are about 10× larger (at θ̇₀ = 0.25, 0 ≤ t ≤ 20: 4.8e-4 instead of 6.2e-5 at
2ε = 0.02, 4.7e-6 instead of 4.6e-7 at 2ε = 1e-4); the tests compare the kernels
with an independent implementation of the corrected (3.9).  Both brackets
are (1 − (1 + y)e^{−y}) = y²/2 − y³/3 + …, so ξ has a removable 0/0 at ε = 0; the
kernels use y·q(y) with q(y) = (1 − (1 + y)e^{−y})/y from its power series for
|y| ≤ 1, and ξ → ωt, the exact undamped solution, at ε = 0.  θ′ is the exact
derivative of the formula, including the variation of the parameter:
m ∂sn/∂m = ½ cn dn (u − ℰ(u|m)/(1 − m)) + m sn cn²/(2(1 − m)) (from the derivative of
F(φ|m) in the parameter, DLMF §19.4, at fixed u = F(am u|m)), with ℰ(u|m) = E(am u | m)
the Jacobi epsilon function (E(φ|m) by Carlson's R_F, R_D, :func:`ellipe_kernel`).

Any anchor: by the same reasoning, the family is
sin(θ/2) = σ √M e^{−εt} sn(ξ(t) + u₀, M e^{−2εt}) with sign σ = ±1, amplitude M ∈ [0, 1)
and phase |u₀| ≤ K(M) (cn(u₀) ≥ 0; keeping u₀ in one half period and the sign in σ
makes θ → −θ a symmetry, as in (3.9)), with ξ of (3.9) restarted at the anchor
(ξ(0) = 0, ξ′(0) = Ω) and κ² → M.  θ(0) = θ₀ gives sn(u₀|M) = σ sin(θ₀/2)/√M, and
with y = √(M − S²), S = sin(θ₀/2), C = cos(θ₀/2), the θ′(0) = θ̇₀ condition becomes
the scalar equation

    σ y Ω − ε y (F(φ|M) − E(φ|M)/(1 − M)) − ε S C/(1 − M) = θ̇₀/2,   φ = atan2(S, y),

with σ = sign(θ̇₀/2 + εS/C) (the sign of the left side for small y).  It is solved
for y ∈ [0, C) by bracketed regula falsi (Illinois); at a zero crossing (S = 0) it
gives M = (θ̇₀/2Ω)², u₀ = 0, σ = sign θ̇₀: (3.9) itself.  For "johannessen-trig"
the same is done with sin_m, cos_m, dn_m and ∂sin_m/∂m in place of sn, cn, dn and
∂sn/∂m, and u₀ from inverting (3.12) in closed form:
tan(w₀) = σS√(A − M + 2)/(√14 y), w₀ = √((A − M + 2)/14) u₀.

Domain
------
``ApproximantDomainError`` (status codes below) for: γ ≠ 0 (the paper's equation has
no torque); ε = β/2 ≥ ω (critical or over-damping: √(ω² − ε²) in (2.5) and (3.9) is
not real); an anchor at or above the separatrix energy, sin²(θ₀/2) + (θ̇₀/2ω)² ≥ 1
(both formulas, 2 arctan(·) and 2 arcsin(·), stay inside one potential well and
cannot describe a pendulum going over the top; a damped state just above that
energy that would still librate is refused as well); no admissible root of the
quadratic above (possible only for ε² > ω²/3 and a large amplitude) or no M < 1
solving Johannessen's anchor equation (e.g. high in the well with damping: the
envelope e^{−εt} of sin(θ/2) alone contributes θ′ ≈ −2ε tan(θ₀/2), which the sn
part, at most 2Ω cos(θ₀/2) in θ′, cannot cancel).  For ε² > ω²/3, P < 0 and f′² < 0 for t
sufficiently negative, and for negative t the parameter m(t) = M e^{2ε|t|} of the
Johannessen forms can pass 1: the kernels return nan there (the MBM solver reports
that as leaving the domain).
"""

from .base import Approximant, ApproximantDomainError, register
from .salas2021_kernels import (  # noqa: F401  callers and tests import these from here
    STATUS_OK, STATUS_TORQUE, STATUS_OVERDAMPED, STATUS_ROTATION,
    STATUS_NO_AMPLITUDE, STATUS_NO_PARAMETER, STATUS_NONFINITE, Q_SERIES_MAX,
    Q_SERIES_TERMS, EXPREL_SERIES_MAX, ROOT_CLAMP_RTOL, Y_MARGIN,
    ANCHOR_RESIDUAL_TOL, ROOT_MAXITER, CARLSON_TOL, CARLSON_MAXITER, _exprel,
    _rlog1p, _ratan, _q, _reduce_angle, _rf, _rd, ellipe_kernel, _S_EPS, _S_SQRTC,
    _S_A, _S_PHI, _S_P, _S_Q, _S_QMP, _S_RR, _S_U0, _S_OFF, _S_TH0, _S_V0, _S_OMEGA,
    _S_NCOEF, _S_PARAM_NAMES, _common_status, salas_anchor, salas_f_kernel,
    _salas_state, salas_eval_formula, salas_eval, salas_eval_array,
    salas_linear_eval_formula, salas_linear_eval, salas_linear_eval_array,
    paper_amplitude, _J_EPS, _J_OM, _J_SGN, _J_M, _J_MC, _J_U0, _J_OFF, _J_TH0,
    _J_V0, _J_OMEGA, _J_NCOEF, _J_PARAM_NAMES, johannessen_xi_kernel, _j_theta_v,
    _j_u0, _j_residual, _johannessen_anchor, johannessen_anchor,
    johannessen_trig_anchor, _j_eval_formula, johannessen_eval_formula,
    johannessen_eval, johannessen_eval_array, johannessen_trig_eval_formula,
    johannessen_trig_eval, johannessen_trig_eval_array,
)

__all__ = [
    "SalasDamped",
    "SalasDampedLinear",
    "Johannessen",
    "JohannessenTrig",
    "paper_amplitude",
    "salas_f_kernel",
    "johannessen_xi_kernel",
    "ellipe_kernel",
]


_STATUS_MESSAGES = {
    STATUS_TORQUE: (
        "gamma != 0: the first paper's equation (1.1) has no torque (use 'salas-torque')"
    ),
    STATUS_OVERDAMPED: (
        "beta/2 >= omega (critically or over-damped): sqrt(omega**2 - epsilon**2) of "
        "(2.5)/(3.9) is not real"
    ),
    STATUS_ROTATION: (
        "the state is at or above the separatrix energy, sin(theta/2)**2 + "
        "(theta'/(2 omega))**2 >= 1: the formula stays inside one potential well and "
        "cannot describe the pendulum going over the top"
    ),
    STATUS_NO_AMPLITUDE: (
        "the amplitude equation (2.7), generalized to this anchor, has no admissible "
        "root (strong damping epsilon**2 > omega**2/3 with a large amplitude)"
    ),
    STATUS_NO_PARAMETER: (
        "no Jacobi parameter M < 1 reproduces this anchor state in Johannessen's form (3.9) "
        "(too close to the separatrix for this damping)"
    ),
    STATUS_NONFINITE: "non-finite constants (overflow)",
}


# ---------------------------------------------------------------------------
# Registered classes
# ---------------------------------------------------------------------------


class _FirstPaper(Approximant):
    """Common model check of the first paper's approximants."""

    anchors = "any"
    status_messages = _STATUS_MESSAGES

    def check_model(self, model):
        if model.gamma != 0.0:
            raise ApproximantDomainError(
                f"approximant {self.name!r} needs gamma == 0, got gamma={model.gamma!r}: "
                + _STATUS_MESSAGES[STATUS_TORQUE]
            )
        if not (0.5 * model.beta < model.omega):
            raise ApproximantDomainError(
                f"approximant {self.name!r} needs beta/2 < omega, got beta={model.beta!r}, "
                f"omega={model.omega!r}: " + _STATUS_MESSAGES[STATUS_OVERDAMPED]
            )


@register
class SalasDamped(_FirstPaper):
    """Elementary approximant (2.2) with f from (2.6) in closed form, any anchor.

    ``params``: ε = β/2, √c = √(ω² − ε²), a ≥ 0 and the phase φ = f(0) (the paper's
    a is ``sign * a`` with φ = 0 or π at a zero crossing), P, Q, Q − P, P/Q of
    f′ = √c √((E + P)/(E + Q)), u₀ = f′(0)/√c, the 2π offset, the anchor and ω.
    """

    name = "salas-damped"
    citation = "Salas (2021), eqs. (2.2)-(2.8), (2.8) with the root sign corrected"
    anchor_kernel = staticmethod(salas_anchor)
    eval_kernel = staticmethod(salas_eval)
    eval_array_kernel = staticmethod(salas_eval_array)

    def param_names(self):
        return _S_PARAM_NAMES


@register
class SalasDampedLinear(SalasDamped):
    """Elementary approximant (2.2) with the paper's f(t) ≈ f′(0) t, any anchor."""

    name = "salas-damped-linear"
    citation = "Salas (2021), eq. (2.2) with f ~ f'(0) t, (2.7)-(2.8) sign corrected"
    eval_kernel = staticmethod(salas_linear_eval)
    eval_array_kernel = staticmethod(salas_linear_eval_array)


@register
class Johannessen(_FirstPaper):
    """Johannessen's approximant (3.9) of the first paper, generalized to any anchor.

    ``params``: ε, Ω = √(ω² − ε²), the sign σ, the parameter M = κ² at the anchor,
    1 − M, the phase u₀ (0 at a zero crossing), the 2π offset, the anchor and ω.
    """

    name = "johannessen"
    citation = "Johannessen (2014) as quoted in Salas (2021), eq. (3.9)"
    anchor_kernel = staticmethod(johannessen_anchor)
    eval_kernel = staticmethod(johannessen_eval)
    eval_array_kernel = staticmethod(johannessen_eval_array)

    def param_names(self):
        return _J_PARAM_NAMES


@register
class JohannessenTrig(Johannessen):
    """(3.9) with sn replaced by the trigonometric sin_m of (3.12)–(3.13)."""

    name = "johannessen-trig"
    citation = "Salas (2021), eq. (3.9) with sn -> sin_m of (3.12)-(3.13)"
    anchor_kernel = staticmethod(johannessen_trig_anchor)
    eval_kernel = staticmethod(johannessen_trig_eval)
    eval_array_kernel = staticmethod(johannessen_trig_eval_array)
