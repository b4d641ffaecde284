"""Long-horizon regimes: once a run reaches its attractor, the closed form of the rest.

Implemented: the LOCKED regime (β > 0, |γ| < ω²), a run settling on a stable
equilibrium θ* = d + 2πk, d = arcsin(γ/ω²).  The window loop (:func:`mbm.loop._run`)
asks :func:`locked_bound` before each window; when the bound on the neglected
nonlinearity over the whole rest of the horizon is within the tolerance, the run
takes one last "window" to ``t_bound`` whose formula is the linearized motion
(:func:`locked_eval`), so the run costs its transient only.

Derivation (the comments below cite these items)
-------------------------------------------------

(L1) Linearization.  With θ = θ* + x and ω² sin θ* = γ,

    x'' + βx' + ω_l² x = −ω² r(x),   ω_l² = ω² cos d = sqrt(ω⁴ − γ²),
    r(x) = sin(θ* + x) − sin θ* − cos θ* · x.

By Taylor's theorem with the Lagrange remainder, r(x) = −sin d · x²/2 − cos(θ*+ξ) x³/6,
so |r(x)| ≤ ρ(|x|), ρ(A) = |sin d| A²/2 + A³/6.

(L2) Closed form of the linear part, from x(0) = x₀, x'(0) = v₀: with
s² = ω_l² − β²/4 (the sign tells the damping), b = v₀ + βx₀/2, E = e^{−βt/2},

    x_lin = x₀ E·C(t) + b E·S(t),
    x_lin' = x₀ (−β/2 E·C − s² E·S) + b (E·C − β/2 E·S),

where C = cos(st), S = sin(st)/s (under-damped, s² > 0); C = cosh(μt), S = sinh(μt)/μ,
μ² = −s² (over-damped); C = 1, S = t (critical).  (C' = −s² S, S' = C in every case.)
Over-damped, E·C and E·S are formed from λ₁ = −β/2 + μ = −ω_l²/(β/2 + μ) (no
cancellation) as E·C = (e^{λ₁t} + e^{λ₂t})/2 and E·S = e^{λ₁t}·(−expm1(−2μt))/(2μ), which
neither overflow nor cancel near critical damping.

(L3) Trapping and amplitude.  H = x'²/2 + U(x), U(x) = ω²(cos d − cos(d + x)) − γx
= 2ω² sin(d + x/2) sin(x/2) − γx, is non-increasing along the exact motion
(dH/dt = −βx'²).  The well of θ* is bounded by the saddles x_r = π − 2d and
x_l = −π − 2d, with U(x_r) = 2ω² cos d − γ(π − 2d), U(x_l) = 2ω² cos d + γ(π + 2d); U
increases on [0, x_r] and decreases on [x_l, 0].  If x₀ ∈ (x_l, x_r) and
H₀ < min(U(x_l), U(x_r)), the exact motion stays in the well for all later t, with
|x(t)| ≤ A = max(A₊, A₋), A± the roots of U = H₀ on either side (bisection, keeping
the end where U ≥ H₀, so A is an upper bound).  Near the saddle or a bifurcation
(|γ| → ω²: the barrier → 0) no A exists or A is large, and the switch waits.

(L4) Bound on the neglected remainder.  e = x − x_lin solves e'' + βe' + ω_l² e =
−ω² r(x(t)), e(0) = e'(0) = 0, so e = −ω² ∫ g(t − s) r(x(s)) ds with g the oscillator's
Green's function (g'' + βg' + ω_l² g = δ), and for every t ≥ 0

    |e(t)| ≤ ω² ρ(A) G₀,  |e'(t)| ≤ ω² ρ(A) G₁,  G₀ = ∫₀^∞ |g|,  G₁ = ∫₀^∞ |g'|.

Under-damped, g = E sin(st)/s, |sin(st)/s| ≤ min(t, 1/s):
G₀ ≤ min(4/β², 2/(βs)), and g' = E (cos st − (β/2) sin(st)/s) gives
G₁ ≤ 2/β + min(2/β, 1/s).  Over-damped or critical, g ≥ 0, so G₀ = ∫g = 1/ω_l²
exactly, and g rises once and decays, so G₁ = 2 max g ≤ 2/(e|λ₁|) (g ≤ t e^{λ₁t}).

(L5) Switch rule.  The run switches when ω² ρ(A) G₀ ≤ SWITCH_SAFETY · (atol + rtol·|θ*|)
and ω² ρ(A) G₁ ≤ SWITCH_SAFETY · atol: after the switch every output differs from the
exact motion through the state reached by at most that, for any horizon (the error
the run carried into the switch is then propagated by a contracting linear flow).
Rounding in H₀ and U is covered by the margin AMPLITUDE_MARGIN on A.
"""

import math

import numba
import numpy as np

__all__ = [
    "SWITCH_SAFETY",
    "REGIME_NONE",
    "REGIME_LOCKED",
    "REGIME_NAMES",
    "LOCKED_TAG",
    "LOCKED_WIDTH",
    "locked_constants",
    "locked_quick_reject",
    "locked_bound",
    "locked_coef",
    "locked_eval",
    "locked_eval_array",
    "green_integrals",
]

# (L5): the remainder bound must be this fraction of the tolerance, so the switch adds
# at most a tenth of one window's allowed error to the outputs after it.
SWITCH_SAFETY = 0.1
# (L3): relative widening of the amplitude bound A, covering the rounding of H₀ and U
# (a few ulps of each) with orders of magnitude to spare.
AMPLITUDE_MARGIN = 1e-8
# (L3): bisection steps for A± (each halves a bracket of length ≤ 2π: 60 reach ulps).
AMPLITUDE_BISECTIONS = 60
# Quick rejection before the rigorous test (it only delays a switch, never allows
# one): the linear estimate sqrt(2H/ω_l²) of A times this factor must already pass.
QUICK_FACTOR = 0.5

REGIME_NONE = 0
REGIME_LOCKED = 1
#: The name of each regime (``regime`` of a result).
REGIME_NAMES = {REGIME_NONE: None, REGIME_LOCKED: "locked"}

# A locked window's coefficient vector, as stored in a run's window store:
# [LOCKED_TAG, θ*, x₀, v₀, β/2, s², ω_l²].  coef[0] of an approximant's window is its
# anchor status, 0.0, so the tag tells a locked window from any other.
LOCKED_TAG = 101.0
LOCKED_WIDTH = 7


@numba.njit(cache=True)
def green_integrals(beta, wl2):
    """Upper bounds (G₀, G₁) on ∫₀^∞|g| and ∫₀^∞|g'| of x'' + βx' + ω_l² x (item L4)."""
    s2 = wl2 - 0.25 * beta * beta
    if s2 > 0.0:
        s = math.sqrt(s2)
        g0 = min(4.0 / (beta * beta), 2.0 / (beta * s))
        g1 = 2.0 / beta + min(2.0 / beta, 1.0 / s)
    else:
        mu = math.sqrt(-s2)
        lam1 = wl2 / (0.5 * beta + mu)  # |λ₁|
        g0 = 1.0 / wl2
        g1 = 2.0 / (math.e * lam1)
    return g0, g1


@numba.njit(cache=True)
def locked_constants(beta, gamma, omega):
    """Per-run constants of the locked test: ``(d, ω_l², G₀, G₁)`` (items L1, L4)."""
    w2 = omega * omega
    d = math.asin(gamma / w2)
    wl2 = w2 * math.cos(d)
    g0, g1 = green_integrals(beta, wl2)
    return d, wl2, g0, g1


@numba.njit(cache=True, inline="always")
def _rho(sd, a):
    # (L1): bound on |r(x)| for |x| ≤ a.
    return 0.5 * sd * a * a + a * a * a / 6.0


@numba.njit(cache=True, inline="always")
def _potential(w2, gamma, d, x):
    # (L3): U(x) = 2ω² sin(d + x/2) sin(x/2) − γx (no cancellation at small x).
    return 2.0 * w2 * math.sin(d + 0.5 * x) * math.sin(0.5 * x) - gamma * x


@numba.njit(cache=True, inline="always")
def _nearest_k(theta, d):
    return math.floor((theta - d) / (2.0 * math.pi) + 0.5)


@numba.njit(cache=True, inline="always")
def locked_quick_reject(theta, v, d, wl2, g0, omega, rtol, atol):
    """True when the locked test surely fails (cheap; run before every window)."""
    k = _nearest_k(theta, d)
    ts = d + 2.0 * math.pi * k
    x = theta - ts
    a = QUICK_FACTOR * math.sqrt(x * x + v * v / wl2)
    return omega * omega * _rho(abs(math.sin(d)), a) * g0 > SWITCH_SAFETY * (atol + rtol * abs(ts))


@numba.njit(cache=True)
def locked_bound(beta, gamma, omega, theta, v, d, wl2, g0, g1):
    """Rigorous bounds on the locked closed form's deviation over any horizon (L3, L4).

    Returns ``(θ*, bound_θ, bound_θ')``; the bounds are inf when the state is not
    trapped in the well of its nearest equilibrium θ*.
    """
    w2 = omega * omega
    k = _nearest_k(theta, d)
    ts = d + 2.0 * math.pi * k
    x = theta - ts
    xr = math.pi - 2.0 * d
    xl = -math.pi - 2.0 * d
    ur = 2.0 * w2 * math.cos(d) - gamma * (math.pi - 2.0 * d)
    ul = 2.0 * w2 * math.cos(d) + gamma * (math.pi + 2.0 * d)
    h0 = 0.5 * v * v + _potential(w2, gamma, d, x)
    barrier = min(ur, ul)
    if not (xl < x < xr) or not (h0 * (1.0 + AMPLITUDE_MARGIN) < barrier):
        return ts, math.inf, math.inf
    amp = 0.0
    for side in range(2):
        lo = 0.0
        hi = xr if side == 0 else xl
        for _ in range(AMPLITUDE_BISECTIONS):
            mid = 0.5 * (lo + hi)
            if _potential(w2, gamma, d, mid) >= h0:
                hi = mid
            else:
                lo = mid
        amp = max(amp, abs(hi))
    amp = max(amp, abs(x)) * (1.0 + AMPLITUDE_MARGIN)
    r = w2 * _rho(abs(math.sin(d)), amp)
    return ts, r * g0, r * g1


@numba.njit(cache=True)
def locked_coef(beta, wl2, theta_star, theta, v):
    """The locked window's coefficient vector anchored at (θ, θ') (layout: LOCKED_TAG)."""
    c = np.empty(LOCKED_WIDTH)
    c[0] = LOCKED_TAG
    c[1] = theta_star
    c[2] = theta - theta_star
    c[3] = v
    c[4] = 0.5 * beta
    c[5] = wl2 - 0.25 * beta * beta
    c[6] = wl2
    return c


@numba.njit(cache=True, inline="always")
def locked_eval(coef, t):
    """(θ, θ') of the linearized motion of a locked window at time ``t`` from its anchor (L2)."""
    ts, x0, v0, hb, s2, wl2 = coef[1], coef[2], coef[3], coef[4], coef[5], coef[6]
    b = v0 + hb * x0
    if s2 > 0.0:
        s = math.sqrt(s2)
        e = math.exp(-hb * t)
        ec = e * math.cos(s * t)
        es = e * math.sin(s * t) / s
    elif s2 < 0.0:
        mu = math.sqrt(-s2)
        lam1 = -wl2 / (hb + mu)
        e1 = math.exp(lam1 * t)
        ec = 0.5 * (e1 + math.exp((-hb - mu) * t))
        es = e1 * (-math.expm1(-2.0 * mu * t)) / (2.0 * mu)
    else:
        e = math.exp(-hb * t)
        ec = e
        es = e * t
    x = x0 * ec + b * es
    xd = x0 * (-hb * ec - s2 * es) + b * (ec - hb * es)
    return ts + x, xd


@numba.njit(cache=True)
def locked_eval_array(coef, t, out_theta, out_v):
    """:func:`locked_eval` at each of ``t``."""
    for i in range(t.size):
        a, b = locked_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b
