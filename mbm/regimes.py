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
= ω²(2 cos d sin²(x/2) − sin d (x − sin x)) (the form evaluated), is non-increasing along the exact motion
(dH/dt = −βx'²).  The well of θ* is bounded by the saddles x_r = π − 2d and
x_l = −π − 2d, with U(x_r) = 2ω² cos d − γ(π − 2d), U(x_l) = 2ω² cos d + γ(π + 2d); U
increases on [0, x_r] and decreases on [x_l, 0].  If x₀ ∈ (x_l, x_r) and
H₀ < min(U(x_l), U(x_r)), the exact motion stays in the well for all later t, with
|x(t)| ≤ A = max(A₊, A₋), A± the roots of U = H₀ on either side (Newton from the
linear amplitude sqrt(2H₀/ω_l²), or bisection where Newton does not converge; either
way the point kept has U ≥ H₀, checked, so A is an upper bound).  Near the saddle or a bifurcation
(|γ| → ω²: the barrier → 0) no A exists or A is large, and the switch waits.

(L4) Bound on the neglected remainder.  e = x − x_lin solves e'' + βe' + ω_l² e =
−ω² r(x(t)), e(0) = e'(0) = 0, so e = −ω² ∫ g(t − s) r(x(s)) ds with g the oscillator's
Green's function (g'' + βg' + ω_l² g = δ), and for every t ≥ 0

    |e(t)| ≤ ω² ρ(A) G₀,  |e'(t)| ≤ ω² ρ(A) G₁,  G₀ = ∫₀^∞ |g|,  G₁ = ∫₀^∞ |g'|.

Under-damped, g = E sin(st)/s, |sin(st)/s| ≤ min(t, 1/s):
G₀ ≤ min(4/β², 2/(βs)), and g' = E (cos st − (β/2) sin(st)/s) gives
G₁ ≤ 2/β + min(2/β, 1/s).  Over-damped or critical, g ≥ 0, so G₀ = ∫g = 1/ω_l²
exactly, and g rises once and decays, so G₁ = 2 max g; g = e^{λ₁t}(1 − e^{−2μt})/(2μ)
≤ min(t, 1/(2μ)) e^{λ₁t} gives G₁ ≤ 2 min(1/(e|λ₁|), 1/(2μ)) (critical: 4/(eβ), exact).

(L5) Switch rule.  The run switches when ω² ρ(A) G₀ ≤ SWITCH_SAFETY · (atol + rtol·|θ*|)
and ω² ρ(A) G₁ ≤ SWITCH_SAFETY · atol: after the switch every output differs from the
exact motion through the state reached by at most that, for any horizon (the error
the run carried into the switch is then propagated by a contracting linear flow).
Rounding in H₀ and U is covered by the margin AMPLITUDE_MARGIN on A.

RUNNING cycle (β > 0; a rotation settling on the limit cycle θ(t + T_c) = θ(t) ± 2π):

(R1) Section.  After each window the loop looks for a crossing of a level
θ = θ_s + 2πm inside it (the window's formula, safeguarded Newton on θ(s) − θ_s − 2πm):
the crossings (t_n, v_n) of successive levels in one direction are the return map of
the section θ ≡ θ_s (mod 2π).  θ_s = π − d is the saddle, the top of the tilted
potential's barrier (d = arcsin(γ/ω²), clamped to ±π/2 when |γ| ≥ ω², where no
equilibrium exists and every level is crossed alike; :func:`section_offset`): a
motion trapped in a well never reaches it, so a librating or settling run does no
section work (at θ ≡ 0 every swing through the bottom of the well was a crossing,
solved by Newton: a quarter of P1's run time).

(R2) Convergence.  Near the cycle the return map contracts geometrically: the flow's
divergence is −β, so the cycle's non-trivial Floquet multiplier, the slope of the
return map there, is μ = e^{−βT_c} (Liouville); the loop measures it as
μ = |v_n − v_{n−1}| / |v_{n−1} − v_{n−2}|.  The deviations still to come sum to at
most |Δv|·μ/(1 − μ) in v and |ΔT|·μ/(1 − μ) in the period; the period's error repeats
in each of the N periods left to t_bound, so it shifts the phase by up to
N·|ΔT|/(1 − μ).  The run switches when μ ≤ CYCLE_MAX_MULTIPLIER,
|Δv|/(1 − μ) ≤ SWITCH_SAFETY · (atol + rtol·|v_n|), N|ΔT|/(1 − μ) · max|θ''| within the
same, and N|ΔT|/(1 − μ) · max|θ'| ≤ SWITCH_SAFETY · (atol + rtol·|θ_n|)
(:func:`cycle_switch`): the longer the horizon, the later (by log N periods) the switch.
From there the period is averaged over CYCLE_AVERAGE_PERIODS more returns, and the
last crossing is the cycle's anchor.

(R3) Extension.  After the switch the motion is the last period's, shifted: with
τ = t − t_n = nT_c + s (0 ≤ s < T_c), θ(t) = θ_p(s) ± 2πn, where θ_p is the run
re-taken from the anchor (θ_s + 2πm, v_n) by the same approximant and controller (the
windows of one period, a function of the anchor only, so every path and the dense
output give the same value; each evaluation costs at most one period of windows,
whatever the horizon).  Its error per period is the ordinary windows' (one period
of them), and its phase error grows with n·ΔT as the ordinary run's would: the
extension is the ordinary run without the windows between outputs, not a bound
tighter than it (the phase of a limit cycle is neutral).
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
    "section_offset",
    "locked_quick_reject",
    "locked_bound",
    "locked_coef",
    "locked_eval",
    "locked_eval_array",
    "green_integrals",
    "REGIME_RUNNING",
    "CYCLE_TAG",
    "CYCLE_WIDTH",
    "cycle_coef",
    "cycle_switch",
    "cycle_summary",
]

# (L5): the remainder bound must be this fraction of the tolerance, so the switch adds
# at most a tenth of one window's allowed error to the outputs after it.
SWITCH_SAFETY = 0.1
# (L3): relative widening of the amplitude bound A, covering the rounding of H₀ and U
# (a few ulps of each) with orders of magnitude to spare.
AMPLITUDE_MARGIN = 1e-8
# (L3): bisection steps for A± (each halves a bracket of length ≤ 2π: 60 reach ulps).
AMPLITUDE_BISECTIONS = 60
# (L3): Newton steps for A± from the linear amplitude (quadratic convergence: 3-5
# reach ulps near the bottom of the well; bisection takes over if they do not certify).
AMPLITUDE_NEWTON_STEPS = 8
# Below this |x|, x − sin x by its series to x¹¹ (the next term is below 1e-15 of it).
X_MINUS_SIN_SERIES = 0.25
# Quick rejection before the rigorous test (it only delays a switch, never allows
# one): the linear estimate sqrt(2H/ω_l²) of A times this factor must already pass.
QUICK_FACTOR = 0.5

REGIME_NONE = 0
REGIME_LOCKED = 1
REGIME_RUNNING = 2
#: The name of each regime (``regime`` of a result).
REGIME_NAMES = {REGIME_NONE: None, REGIME_LOCKED: "locked", REGIME_RUNNING: "running"}

# A locked window's coefficient vector, as stored in a run's window store:
# [LOCKED_TAG, θ₀, x₀ = θ₀ − θ*, v₀, β/2, s², ω_l²], θ = θ₀ + (x − x₀) so that the
# window's start is its anchor bit for bit.  coef[0] of an approximant's window is its
# anchor status, 0.0, so the tag tells a locked window from any other.
LOCKED_TAG = 101.0
LOCKED_WIDTH = 7
# A running-cycle window's coefficient vector (R3): [CYCLE_TAG, θ_c, v_c, T_c, t_off,
# β, γ, ω, rtol, atol, winding sign, kind argument, error order, k_c]; t_off is the
# time from the cycle's anchor crossing to the window's start, and the anchor is at
# θ = 2πk_c + θ_c (the loop's winding count, mbm.loop "Winding").
CYCLE_TAG = 102.0
CYCLE_WIDTH = 14
# (R2): a return map whose contraction measured over two periods is above this is not
# (yet) converging geometrically: no switch.
CYCLE_MAX_MULTIPLIER = 0.9
# (R2): once the map has converged, the period is averaged over this many more
# returns: the crossing times carry the run's global error, which a single
# difference would repeat in every later period; averaged, the stored period's
# drift is the run's own mean drift per period.
CYCLE_AVERAGE_PERIODS = 32
# (R1): safeguarded Newton steps for a section crossing inside a window (quadratic
# convergence from the bracket's secant start: a handful suffice; bisection backs it up).
CROSSING_ITERATIONS = 60
# (R3): most windows one evaluation of the stored period may take (a period takes
# ~10-100 at the tolerances in use); past it the evaluation is NaN (a failure).
CYCLE_MAX_WINDOWS = 100000


@numba.njit(cache=True)
def green_integrals(beta, wl2):
    """Upper bounds on the L¹ norms of the oscillator's Green's function (item L4).

    Parameters
    ----------
    beta : float
        Damping, > 0.
    wl2 : float
        ω_l², > 0.

    Returns
    -------
    g0, g1 : float
        G₀ ≥ ∫₀^∞ |g| and G₁ ≥ ∫₀^∞ |g'| for g'' + βg' + ω_l² g = δ.
    """
    s2 = wl2 - 0.25 * beta * beta
    if s2 > 0.0:
        s = math.sqrt(s2)
        # Divided one at a time: β² may underflow (β = 1e-270), 4/β/β is then inf.
        g0 = min(4.0 / beta / beta, 2.0 / beta / s)
        g1 = 2.0 / beta + min(2.0 / beta, 1.0 / s)
    else:
        mu = math.sqrt(-s2)
        lam1 = wl2 / (0.5 * beta + mu)  # |λ₁|
        g0 = 1.0 / wl2
        g1 = 2.0 / (math.e * lam1) if mu == 0.0 else 2.0 * min(1.0 / (math.e * lam1), 0.5 / mu)
    return g0, g1


@numba.njit(cache=True)
def section_offset(gamma, omega):
    """θ_s of the running cycle's section θ ≡ θ_s (mod 2π) (item R1): the saddle π − d.

    Parameters
    ----------
    gamma, omega : float
        The model's torque and ω > 0.

    Returns
    -------
    float
        π − arcsin(γ/ω²), with γ/ω² clamped to [−1, 1].
    """
    return math.pi - math.asin(min(1.0, max(-1.0, gamma / (omega * omega))))


@numba.njit(cache=True)
def locked_constants(beta, gamma, omega):
    """Per-run constants of the locked test (items L1, L4).

    Parameters
    ----------
    beta, gamma, omega : float
        The model, β > 0 and |γ| < ω².

    Returns
    -------
    d, wl2, g0, g1 : float
        d = arcsin(γ/ω²), ω_l² = ω² cos d and :func:`green_integrals`.
    """
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
def _x_minus_sin(x):
    # x − sin x without cancellation: its Taylor series below X_MINUS_SIN_SERIES.
    if abs(x) < X_MINUS_SIN_SERIES:
        x2 = x * x
        return x * x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0 - x2 * (
            1.0 / 362880.0 - x2 / 39916800.0))))
    return x - math.sin(x)


@numba.njit(cache=True, inline="always")
def _potential(w2, gamma, d, x):
    # (L3): U(x) = ω²(2 cos d sin²(x/2) − sin d (x − sin x)), sin d = γ/ω²: both terms
    # carry their leading order, so U keeps its relative precision at any small x.
    h = math.sin(0.5 * x)
    return w2 * (2.0 * math.cos(d) * h * h) - gamma * _x_minus_sin(x)


@numba.njit(cache=True, inline="always")
def _nearest_k(theta, d):
    return math.floor((theta - d) / (2.0 * math.pi) + 0.5)


@numba.njit(cache=True, inline="always")
def locked_quick_reject(theta, v, d, wl2, g0, omega, rtol, atol):
    """True when the locked test surely fails (cheap; run before every window).

    A necessary condition only (the linear amplitude estimate times QUICK_FACTOR must
    already pass L5): a True delays a switch, a False leads to :func:`locked_bound`.

    Parameters
    ----------
    theta, v : float
        The state.
    d, wl2, g0 : float
        From :func:`locked_constants`.
    omega, rtol, atol : float
        The model's ω and the run's tolerances.

    Returns
    -------
    bool
    """
    k = _nearest_k(theta, d)
    ts = d + 2.0 * math.pi * k
    x = theta - ts
    a = QUICK_FACTOR * math.sqrt(x * x + v * v / wl2)
    return omega * omega * _rho(abs(math.sin(d)), a) * g0 > SWITCH_SAFETY * (atol + rtol * abs(ts))


@numba.njit(cache=True, inline="always")
def _amplitude_newton(w2, gamma, d, wl2, h0, edge):
    # (L3): a point x between 0 and the saddle ``edge`` with U(x) ≥ H₀, so that the
    # root A± of U = H₀ on that side (U is monotone there) is at most |x|; inf if
    # none was certified.  Newton on U(x) = H₀ (U' = ω² sin(d + x) − γ) from the
    # linear amplitude sqrt(2H₀/ω_l²): a few steps instead of AMPLITUDE_BISECTIONS
    # (the test runs before windows near the equilibrium: 2.7 µs bisected, 0.2 here).
    if h0 <= 0.0:
        return 0.0
    x = math.copysign(math.sqrt(2.0 * h0 / wl2), edge)
    for _ in range(AMPLITUDE_NEWTON_STEPS):
        du = w2 * math.sin(d + x) - gamma
        if not (du * edge > 0.0):
            return math.inf
        x_new = x - (_potential(w2, gamma, d, x) - h0) / du
        if not (0.0 < x_new / edge < 1.0):
            return math.inf
        if x_new == x:
            break
        x = x_new
    # Certify: U(x) ≥ H₀ at x or at x pushed outwards by a growing fraction.
    widen = AMPLITUDE_MARGIN
    for _ in range(4):
        if abs(x) < abs(edge) and _potential(w2, gamma, d, x) >= h0:
            return x
        x *= 1.0 + widen
        widen *= 1e3
    return math.inf


@numba.njit(cache=True)
def locked_bound(beta, gamma, omega, theta, v, d, wl2, g0, g1):
    """Rigorous bounds on the locked closed form's deviation over any horizon (L3, L4).

    Parameters
    ----------
    beta, gamma, omega : float
        The model, β > 0 and |γ| < ω².
    theta, v : float
        The state the closed form is anchored at.
    d, wl2, g0, g1 : float
        From :func:`locked_constants`.

    Returns
    -------
    theta_star : float
        The nearest stable equilibrium d + 2πk.
    bound_theta, bound_v : float
        sup over t ≥ 0 of |θ − θ_lin| and |θ' − θ_lin'| between the exact motion and
        :func:`locked_eval` from this state; inf when the state is not trapped in the
        well of θ* (on or above its lower saddle).
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
    wl2 = w2 * math.cos(d)
    for side in range(2):
        edge = xr if side == 0 else xl
        hi = _amplitude_newton(w2, gamma, d, wl2, h0, edge)
        if not hi < math.inf:
            # Newton did not certify a root (far from the bottom of the well): bisection.
            lo = 0.0
            hi = edge
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
    """The locked window's coefficient vector anchored at (θ, θ').

    Parameters
    ----------
    beta, wl2 : float
        β and ω_l².
    theta_star : float
        The equilibrium (from :func:`locked_bound`).
    theta, v : float
        The anchor state.

    Returns
    -------
    ndarray, shape (LOCKED_WIDTH,)
        [LOCKED_TAG, θ₀, x₀, v₀, β/2, s², ω_l²] (see LOCKED_TAG).
    """
    c = np.empty(LOCKED_WIDTH)
    c[0] = LOCKED_TAG
    c[1] = theta
    c[2] = theta - theta_star
    c[3] = v
    c[4] = 0.5 * beta
    c[5] = wl2 - 0.25 * beta * beta
    c[6] = wl2
    return c


@numba.njit(cache=True, inline="always")
def locked_eval(coef, t):
    """The linearized motion of a locked window (item L2).

    Parameters
    ----------
    coef : ndarray
        From :func:`locked_coef`.
    t : float
        Time from the anchor (≥ 0; any size: the exponentials only decay).

    Returns
    -------
    theta, v : float
        θ and θ' (at t = 0 the anchor, bit for bit).
    """
    th0, x0, v0, hb, s2, wl2 = coef[1], coef[2], coef[3], coef[4], coef[5], coef[6]
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
    return th0 + (x - x0), xd


@numba.njit(cache=True, inline="always")
def cycle_switch(dv, dv_prev, dT, v, theta, vmax, amax, n_rest, rtol, atol):
    """Whether the return map has converged enough to switch to the cycle (item R2).

    Parameters
    ----------
    dv, dv_prev : float
        The last two changes of θ' between successive crossings.
    dT : float
        The last change of the return time.
    v, theta : float
        θ', θ at the last crossing.
    vmax : float
        Largest |θ'| seen over the last period.
    amax : float
        A bound on |θ''| (|γ| + β·vmax + ω²).
    n_rest : float
        Periods left to the end of the span.
    rtol, atol : float
        The run's tolerances.

    Returns
    -------
    bool
    """
    if dv_prev == 0.0:
        return dv == 0.0 and dT == 0.0
    mu = abs(dv) / abs(dv_prev)
    if not (mu <= CYCLE_MAX_MULTIPLIER):
        return False
    tail = 1.0 / (1.0 - mu)
    # (R2): the period's distance to the cycle's, |dT|·tail, repeats every remaining period.
    drift = n_rest * abs(dT) * tail
    scale_v = SWITCH_SAFETY * (atol + rtol * abs(v))
    return (abs(dv) * tail <= scale_v and drift * amax <= scale_v
            and drift * vmax <= SWITCH_SAFETY * (atol + rtol * abs(theta)))


@numba.njit(cache=True)
def cycle_coef(theta_c, v_c, period, t_off, beta, gamma, omega, rtol, atol, sign, karg, error_order,
               wind_c):
    """A running-cycle window's coefficient vector (layout: CYCLE_TAG; item R3).

    Parameters
    ----------
    theta_c, v_c : float
        The cycle's anchor: the crossing of θ = θ_c with speed v_c.
    period : float
        T_c.
    t_off : float
        Time from the anchor crossing to the window's start.
    beta, gamma, omega, rtol, atol : float
        The model and the tolerances the stored period is re-taken with.
    sign : float
        +1 or −1: θ advances by 2π·sign per period.
    karg, error_order : int
        The approximant's kind argument and error order.
    wind_c : float
        Winding count of the anchor: it lies at θ = 2π·wind_c + θ_c.

    Returns
    -------
    ndarray, shape (CYCLE_WIDTH,)
    """
    c = np.empty(CYCLE_WIDTH)
    c[0] = CYCLE_TAG
    c[1] = theta_c
    c[2] = v_c
    c[3] = period
    c[4] = t_off
    c[5] = beta
    c[6] = gamma
    c[7] = omega
    c[8] = rtol
    c[9] = atol
    c[10] = sign
    c[11] = karg
    c[12] = error_order
    c[13] = wind_c
    return c


@numba.njit(cache=True)
def locked_eval_array(coef, t, out_theta, out_v):
    """:func:`locked_eval` at each of ``t``.

    Parameters
    ----------
    coef : ndarray
        From :func:`locked_coef`.
    t : ndarray
        Times from the anchor.
    out_theta, out_v : ndarray
        Filled with θ, θ' (same shape as ``t``).
    """
    for i in range(t.size):
        a, b = locked_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


def cycle_summary(regime, period, sign):
    """``(period, mean_velocity)`` of a result: T_c and ⟨θ'⟩ = ±2π/T_c when the run
    switched to the running cycle, (nan, 0) when it switched to the locked state, else
    (nan, nan).

    Parameters
    ----------
    regime : int
        The run record's ``regime``.
    period, sign : float
        Its ``cyc_T`` and ``cyc_sign``.

    Returns
    -------
    (float, float)
    """
    if regime == REGIME_LOCKED:
        return math.nan, 0.0  # at rest at the equilibrium: no net motion
    if regime != REGIME_RUNNING:
        return math.nan, math.nan
    return float(period), float(sign) * 2.0 * math.pi / float(period)
