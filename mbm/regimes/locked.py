"""The LOCKED regime: a damped run settling on a stable equilibrium, in closed form.

The LOCKED regime (β > 0, |γ| < ω²) is a run settling on a stable
equilibrium θ* = d + 2πk, d = arcsin(γ/ω²).  The window loop (the entry of
:func:`mbm.core.loop._runner`) asks :func:`locked_bound` before each window; when the bound on the neglected
nonlinearity over the whole rest of the horizon is within the tolerance, the run
takes one last "window" to ``t_bound`` whose formula is the linearized motion
(:func:`locked_eval`), so the run costs its transient only.  The first-order form is
L2, the second-order one L6; :func:`locked_choice` takes the one whose bound passes
(L5, L7).  U(x) and x − sin x (:func:`_potential`, L3) serve the libration's trapping
test too (:mod:`mbm.regimes.libration`, C1).

The derivation, items L1–L7 (the comments below cite them), is in the
documentation's theory page, ``docs/theory/regimes.md``.
"""

import collections
import math

import numba
import numpy as np

from ..compile.jit import INLINE, kernel
from .common import SWITCH_SAFETY

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
# The quick test's energy bound of A: x = θ − θ* of whole angles is off by at most a
# few ulps of them (the full test's reduced x by fewer); this many, with room to spare.
X_ROUNDING = 8.0
_EPS = 2.220446049250313e-16
# :func:`locked_far`'s margin over its rounding against the quick test's first stage
# (a few ulps apart): it rejects only where that stage surely does.
FAR_MARGIN = 1e-12
# Beyond this |x| (rad, below π) the nearest well by a product may differ from
# :func:`_nearest_k`'s by a quotient (θ on a saddle's level): the quick test decides.
FAR_X = 3.0
_INV_TWO_PI = 1.0 / (2.0 * math.pi)
# (L2): below this argument exp rounds to +0 (its value is under 2⁻¹⁰⁷⁶, half the least
# subnormal; exp(−745.14) is the first +0): +0 taken without the call, whose underflow
# path (errno) cost an over-damped output half its time past t ≈ 270 (L2's e^{λ₂t}).
EXP_ZERO = -746.0
# (L6): below this e = exp(−βt/2), e² = e·e rounds to +0 (e² < 2⁻¹⁰⁷⁶, under half the
# least subnormal), so e² is formed as 0·0, the same +0 without the underflow, whose
# microcode assist doubled an output's time (a product's operand is chosen, not its
# result: a selected result is formed anyway).
E2_FLOOR = 2.0 ** -538

# A locked window's coefficient vector, as stored in a run's window store:
# [LOCKED_TAG, θ₀, x₀ = θ₀ − θ*, v₀, β/2, s², ω_l²], θ = θ₀ + (x − x₀) so that the
# window's start is its anchor bit for bit.  coef[0] of an approximant's window is its
# anchor status, 0.0, so the tag tells a locked window from any other.
LOCKED_TAG = 101.0
LOCKED_WIDTH = 7
# The second-order window (L6) appends [2.0, Q_r, Q_i, M, D_r, D_i]: coef[7] = 2 marks it
# (a first-order vector stored zero-padded reads 0 there).
LOCKED2_WIDTH = 13

# The locked window's coefficient layout (LOCKED_WIDTH, at order 2 LOCKED2_WIDTH): the index
# of each entry of :func:`locked_coef`'s vector, as :func:`locked_eval` reads it.
LCK_TAG = 0  # LOCKED_TAG (an approximant window's anchor status, 0.0, there)
LCK_THETA0 = 1  # θ₀: the anchor's θ (the window's start, bit for bit)
LCK_X0 = 2  # x₀ = θ₀ − θ*, the anchor's offset from the equilibrium (L1)
LCK_V0 = 3  # v₀ = θ'(0)
LCK_HALF_BETA = 4  # β/2
LCK_S2 = 5  # s² = ω_l² − β²/4: its sign tells the damping (L2)
LCK_WL2 = 6  # ω_l² = ω² cos d (L1)
LCK_ORDER = 7  # 2.0 marks the second-order form (L6; a zero-padded first-order vector reads 0)
LCK_QR = 8  # Q_r of x₂ (L6)
LCK_QI = 9  # Q_i of x₂ (L6)
LCK_M = 10  # M of x₂ (L6)
LCK_DR = 11  # D_r of x₂ (L6)
LCK_DI = 12  # D_i of x₂ (L6)


#: :func:`locked2_terms`' result (item L6): x₂'s parts and its bound's terms.
Locked2Terms = collections.namedtuple("Locked2Terms", ("qr", "qi", "m", "dr", "di", "c_abs", "x2"))

#: :func:`_lock_setup`'s result: the locked test's constants of a run (L5).
LockSetup = collections.namedtuple("LockSetup", ("d", "wl2", "g0", "g1", "sd", "q2", "can_lock2"))

#: :func:`locked_constants`' result: the well's constants d, ω_l² (L1) and G₀, G₁ (L4).
Well = collections.namedtuple("Well", ("d", "wl2", "g0", "g1"))


@kernel
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


@kernel
def locked_constants(beta, gamma, omega):
    """Per-run constants of the locked test (items L1, L4).

    Parameters
    ----------
    beta, gamma, omega : float
        The model, β > 0 and |γ| < ω².

    Returns
    -------
    Well
        d = arcsin(γ/ω²), ω_l² = ω² cos d and :func:`green_integrals`' G₀, G₁.
    """
    w2 = omega * omega
    d = math.asin(gamma / w2)
    wl2 = w2 * math.cos(d)
    g0, g1 = green_integrals(beta, wl2)
    return Well(d, wl2, g0, g1)


@numba.njit(**INLINE)
def _rho(sd, a):
    # (L1): bound on |r(x)| for |x| ≤ a.
    return 0.5 * sd * a * a + a * a * a / 6.0


@numba.njit(**INLINE)
def _x_minus_sin(x):
    # x − sin x without cancellation: its Taylor series below X_MINUS_SIN_SERIES.
    if abs(x) < X_MINUS_SIN_SERIES:
        x2 = x * x
        return x * x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0 - x2 * (
            1.0 / 362880.0 - x2 / 39916800.0))))
    return x - math.sin(x)


@kernel
def _potential(w2, gamma, d, x):
    # (L3): U(x) = ω²(2 cos d sin²(x/2) − sin d (x − sin x)), sin d = γ/ω²: both terms
    # carry their leading order, so U keeps its relative precision at any small x.
    h = math.sin(0.5 * x)
    return w2 * (2.0 * math.cos(d) * h * h) - gamma * _x_minus_sin(x)


@numba.njit(**INLINE)
def _nearest_k(theta, d):
    return math.floor((theta - d) / (2.0 * math.pi) + 0.5)


@numba.njit(**INLINE)
def _bounds_fail(a, cd, omega, lk, tol, tol_v):
    # At a lower bound ``a`` of A: L5's first-order bounds ω²ρ(A)G₀, ω²ρ(A)G₁ and, where
    # the second order is available (``lk.q2`` > 0), L7's, which are at least ω²G₀ρ₃(A)
    # and ω²G₁ρ₃(A), all fail (each grows with A).  ``lk``: a :data:`LockSetup`.
    sd, g0, g1, second = lk.sd, lk.g0, lk.g1, lk.q2 > 0.0
    w2 = omega * omega
    r = w2 * _rho(sd, a)
    if r * g0 <= tol and r * g1 <= tol_v:
        return False
    if not second:
        return True
    rho3 = cd * a * a * a / 6.0 + sd * a * a * a * a / 24.0
    return w2 * g0 * rho3 > tol or w2 * g1 * rho3 > tol_v


@numba.njit(**INLINE)
def locked_far(theta, v, lk, omega, tols):
    """True where :func:`locked_quick_reject`'s first stage surely rejects: its test by
    products in place of its quotients (off the window's critical path: 1/ω_l²
    is the run's constant), with :data:`FAR_MARGIN` on the tolerance; False leaves the
    answer to :func:`locked_quick_reject`.  Arguments as there."""
    d, sd, wl2, g0, q2 = lk.d, lk.sd, lk.wl2, lk.g0, lk.q2
    rtol, atol = tols.rtol, tols.atol
    k = np.floor((theta - d) * _INV_TWO_PI + 0.5)
    ts = d + 2.0 * math.pi * k
    x = theta - ts
    a = QUICK_FACTOR * math.sqrt(x * x + v * v * (1.0 / wl2))
    tol = SWITCH_SAFETY * (atol + rtol * abs(ts)) * (1.0 + FAR_MARGIN)
    a2 = a * a
    return (abs(x) <= FAR_X and omega * omega * g0 * (a2 * (0.5 * sd + a * (1.0 / 6.0))) > tol
            and not (q2 > 0.0 and q2 * a2 * a <= tol))


@kernel
def locked_quick_reject(theta, v, lk, omega, tols):
    """True when the locked test surely fails (cheap; run before every window).

    A necessary condition only, in two stages: the linear amplitude estimate times
    QUICK_FACTOR must already pass L5 (no trigonometry); where it does, a rigorous lower
    bound of A from the energy (L3) must pass too, so that the full test
    (:func:`locked_choice`, its Newton steps on both sides of the well) runs only where
    it may succeed.  A True where the full test would pass never happens by the second
    stage, and by the first it would only delay a switch.

    Parameters
    ----------
    theta, v : float
        The state.
    lk : LockSetup
        From :func:`_lock_setup`: d, ω_l², G₀, G₁ (:func:`locked_constants`), |sin d|
        (formed once per run: a sin per window was ~10 % of the test) and q₂ =
        ω²G₀ cos d / 6, the leading term of L7's bound per A³ (a lower estimate of it),
        or 0 where the second-order form is not available.
    omega : float
        The model's ω.
    tols : Tolerance
        The run's tolerances (:data:`mbm.regimes.common.Tolerance`).

    Returns
    -------
    bool
    """
    d, sd, wl2, g0, q2 = lk.d, lk.sd, lk.wl2, lk.g0, lk.q2
    rtol, atol = tols.rtol, tols.atol
    k = _nearest_k(theta, d)
    ts = d + 2.0 * math.pi * k
    x = theta - ts
    a = QUICK_FACTOR * math.sqrt(x * x + v * v / wl2)
    tol = SWITCH_SAFETY * (atol + rtol * abs(ts))
    if omega * omega * _rho(sd, a) * g0 > tol and not (q2 > 0.0 and q2 * a * a * a <= tol):
        return True
    # (L3) U(x) = ω²(cos d (1 − cos x) − sin d (x − sin x)) ≤ ω_l² x²/2 + ω²|sin d| |x|³/6
    # on both sides, so the root a* of that bound at H₀ is below A± (both increase), and
    # a* ≥ a_lin / sqrt(1 + c a_lin) with a_lin = sqrt(2H₀/ω_l²) ≥ a*, c = ω²|sin d|/(3ω_l²).
    # H₀ as locked_amplitude forms it (γ = ω² sin d) from the reduced angle: the margin
    # covers their rounding, the last term x's own here (θ and θ* whole angles).
    w2 = omega * omega
    h0 = 0.5 * v * v + _potential(w2, w2 * math.copysign(sd, d), d, x)
    a_lin = math.sqrt(max(2.0 * h0 / wl2, 0.0))
    a_lo = (a_lin / math.sqrt(1.0 + w2 * sd * a_lin / (3.0 * wl2)) * (1.0 - AMPLITUDE_MARGIN)
            - X_ROUNDING * _EPS * (abs(theta) + abs(ts)))
    return _bounds_fail(max(a_lo, 0.0), wl2 / w2, omega, lk, tol, SWITCH_SAFETY * atol)


@kernel
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


@kernel
def locked_bound(beta, gamma, omega, theta, v, well):
    """Rigorous bounds on the locked closed form's deviation over any horizon (L3, L4).

    Parameters
    ----------
    beta, gamma, omega : float
        The model, β > 0 and |γ| < ω².
    theta, v : float
        The state the closed form is anchored at.
    well : Well
        From :func:`locked_constants` (or a :data:`LockSetup`: d, G₀, G₁ are read).

    Returns
    -------
    theta_star : float
        The nearest stable equilibrium d + 2πk.
    bound_theta, bound_v : float
        sup over t ≥ 0 of |θ − θ_lin| and |θ' − θ_lin'| between the exact motion and
        :func:`locked_eval` from this state; inf when the state is not trapped in the
        well of θ* (on or above its lower saddle).
    """
    d, g0, g1 = well.d, well.g0, well.g1
    ts, amp = locked_amplitude(gamma, omega, theta, v, d)
    r = omega * omega * _rho(abs(math.sin(d)), amp)
    return ts, r * g0, r * g1


@kernel
def locked_amplitude(gamma, omega, theta, v, d):
    """The nearest stable equilibrium and the amplitude bound A of item L3.

    Returns
    -------
    theta_star : float
        d + 2πk nearest θ.
    amp : float
        A ≥ sup_t |θ(t) − θ*| of the exact motion from (θ, θ'); inf when the state is
        not trapped in the well of θ*.
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
        return ts, math.inf
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
    return ts, max(amp, abs(x)) * (1.0 + AMPLITUDE_MARGIN)


@kernel
def locked2_terms(beta, gamma, wl2, x0, v0):
    """The second-order term x₂ of item L6 from the anchor offset (x₀, x₀').

    Returns
    -------
    qr, qi, m, dr, di : float
        Q, M, D of L6 (under-damped: s² = ω_l² − β²/4 > 0).
    c_abs : float
        |C| = sqrt(x₀² + (b/s)²), b = x₀' + βx₀/2 (sup |x_lin| over t ≥ 0).
    x2 : float
        X₂ = |Q| + |M| + |D| ≥ sup |x₂|.
    """
    hb = 0.5 * beta
    s = math.sqrt(wl2 - hb * hb)
    b = v0 + hb * x0
    cr, ci = x0, -b / s
    kq = 0.25 * gamma
    # C² / P(2λ), P(2λ) = (ω_l² − 4s²) − 2iβs.
    c2r, c2i = cr * cr - ci * ci, 2.0 * cr * ci
    pr, pi = wl2 - 4.0 * s * s, -2.0 * beta * s
    den = pr * pr + pi * pi
    qr = kq * (c2r * pr + c2i * pi) / den
    qi = kq * (c2i * pr - c2r * pi) / den
    c_abs2 = cr * cr + ci * ci
    m = kq * c_abs2 / wl2
    dr = -(qr + m)
    xp1 = -beta * qr - 2.0 * s * qi - beta * m
    di = (xp1 - hb * dr) / s
    x2 = math.hypot(qr, qi) + abs(m) + math.hypot(dr, di)
    return Locked2Terms(qr, qi, m, dr, di, math.sqrt(c_abs2), x2)


@kernel
def locked2_bound(beta, gamma, omega, well, amp, x0, v0):
    """L7's bounds on the second-order form's deviation over any horizon.

    Parameters
    ----------
    beta, gamma, omega : float
        The model (under-damped about θ*: ω_l² > β²/4).
    well : Well
        From :func:`locked_constants` (or a :data:`LockSetup`: d, ω_l², G₀, G₁ are read).
    amp : float
        A from :func:`locked_amplitude`.
    x0, v0 : float
        The anchor's offset θ − θ* and θ'.

    Returns
    -------
    bound_theta, bound_v : float
        sup over t ≥ 0 of |θ − θ_L| and |θ' − θ_L'|; inf where q ≥ 1 or A is inf.
    """
    d, wl2, g0, g1 = well.d, well.wl2, well.g0, well.g1
    if not (amp < math.inf) or not (wl2 - 0.25 * beta * beta > 0.0):
        return math.inf, math.inf
    w2 = omega * omega
    sd = abs(math.sin(d))
    _, _, _, _, _, c_abs, x2 = locked2_terms(beta, gamma, wl2, x0, v0)
    rho3 = math.cos(d) * amp * amp * amp / 6.0 + sd * amp * amp * amp * amp / 24.0
    lip = 0.5 * sd * (amp + c_abs)
    q = w2 * g0 * lip
    if not (q < 1.0):
        return math.inf, math.inf
    e = w2 * g0 * (rho3 + lip * x2) / (1.0 - q)
    ev = w2 * g1 * (rho3 + lip * (x2 + e))
    return e, ev


@kernel
def locked_choice(beta, gamma, omega, theta, v, lk, tols, off):
    """Whether the locked closed form may take over from (θ, θ'), and of which order (L5, L7).

    Parameters
    ----------
    beta, gamma, omega : float
        The model, β > 0, |γ| < ω².
    theta, v : float
        The state (θ reduced by the loop's winding: ``off`` + θ is the angle).
    lk : LockSetup
        From :func:`_lock_setup`: d, ω_l², G₀, G₁ (:func:`locked_constants`) and
        ``can_lock2``, whether the second-order form may be taken (room for
        LOCKED2_WIDTH); |sin d| and q₂ are not read.
    tols : Tolerance
        The run's tolerances.
    off : float
        2π × the winding count (the tolerance's scale is that of the whole angle).

    Returns
    -------
    order : int
        0 (no switch), 1 (L2) or 2 (L6): the first-order form where its bound passes.
    theta_star : float
        The equilibrium (of θ's reduced value).
    """
    d, g0, g1, second = lk.d, lk.g0, lk.g1, lk.can_lock2
    rtol, atol = tols.rtol, tols.atol
    ts, amp = locked_amplitude(gamma, omega, theta, v, d)
    if not (amp < math.inf):
        return 0, ts
    tol_t = SWITCH_SAFETY * (atol + rtol * abs(off + ts))
    tol_v = SWITCH_SAFETY * atol
    r = omega * omega * _rho(abs(math.sin(d)), amp)
    if r * g0 <= tol_t and r * g1 <= tol_v:
        return 1, ts
    if second:
        bt, bv = locked2_bound(beta, gamma, omega, lk, amp, theta - ts, v)
        if bt <= tol_t and bv <= tol_v:
            return 2, ts
    return 0, ts


@kernel
def locked2_quick(beta, gamma, omega, d, wl2, g0):
    """q2 of :func:`locked_quick_reject`: ω²G₀ cos d / 6 where L6 applies, else 0."""
    if not (wl2 - 0.25 * beta * beta > 0.0):
        return 0.0
    return omega * omega * g0 * math.cos(d) / 6.0


@kernel
def locked_coef(beta, wl2, theta_star, theta, v, gamma=0.0, order=1):
    """The locked window's coefficient vector anchored at (θ, θ').

    Parameters
    ----------
    beta, wl2 : float
        β and ω_l².
    theta_star : float
        The equilibrium (from :func:`locked_bound`).
    theta, v : float
        The anchor state.
    gamma : float, optional
        γ (the second order's forcing γx²/2; unused at order 1).
    order : int, optional
        1 (L2) or 2 (L6, under-damped only: :func:`locked_choice` says which).

    Returns
    -------
    ndarray, shape (LOCKED_WIDTH,) or (LOCKED2_WIDTH,)
        [LOCKED_TAG, θ₀, x₀, v₀, β/2, s², ω_l²], at order 2 followed by
        [2, Q_r, Q_i, M, D_r, D_i] (see LOCKED_TAG).
    """
    c = np.empty(LOCKED2_WIDTH if order == 2 else LOCKED_WIDTH)
    c[LCK_TAG] = LOCKED_TAG
    c[LCK_THETA0] = theta
    c[LCK_X0] = theta - theta_star
    c[LCK_V0] = v
    c[LCK_HALF_BETA] = 0.5 * beta
    c[LCK_S2] = wl2 - 0.25 * beta * beta
    c[LCK_WL2] = wl2
    if order == 2:
        qr, qi, m, dr, di, _, _ = locked2_terms(beta, gamma, wl2, c[LCK_X0], v)
        c[LCK_ORDER], c[LCK_QR], c[LCK_QI], c[LCK_M], c[LCK_DR], c[LCK_DI] = 2.0, qr, qi, m, dr, di
    return c


#: :func:`locked_form`'s result: a locked window's constants (L2, L6), formed once for
#: all its outputs: the coefficient vector's entries, b = v₀ + βx₀/2, s = sqrt(s²) (under-
#: damped), μ = sqrt(−s²) and λ₁ = −ω_l²/(β/2 + μ) (over-damped), whether x₂ is added.
LockedForm = collections.namedtuple("LockedForm", ("th0", "x0", "hb", "s2", "b", "s", "mu", "lam1", "order2",
                                                   "qr", "qi", "m", "dr", "di"))


@kernel
def locked_form(coef):
    """The constants of :func:`locked_eval` of one window, formed once (items L2, L6).

    Parameters
    ----------
    coef : ndarray
        From :func:`locked_coef`.

    Returns
    -------
    LockedForm
        Read by :func:`locked_at` at each time (its square roots and quotient taken here
        once instead of at every output).
    """
    th0, x0, v0, hb, s2, wl2 = (coef[LCK_THETA0], coef[LCK_X0], coef[LCK_V0],
                                coef[LCK_HALF_BETA], coef[LCK_S2], coef[LCK_WL2])
    s = mu = lam1 = 0.0
    if s2 > 0.0:
        s = math.sqrt(s2)
    elif s2 < 0.0:
        mu = math.sqrt(-s2)
        lam1 = -wl2 / (hb + mu)
    order2 = coef.size >= LOCKED2_WIDTH and coef[LCK_ORDER] == 2.0 and s2 > 0.0
    qr = qi = m = dr = di = 0.0
    if order2:
        qr, qi, m, dr, di = coef[LCK_QR], coef[LCK_QI], coef[LCK_M], coef[LCK_DR], coef[LCK_DI]
    return LockedForm(th0, x0, hb, s2, v0 + hb * x0, s, mu, lam1, order2, qr, qi, m, dr, di)


# The forms of :func:`locked_at` (literals there) and of :func:`locked_eval` and
# :func:`locked_eval_range` (a value there: one compiled copy of the formula).
FORM_UNDER = 1  # s² > 0, first order (L2)
FORM_UNDER2 = 2  # s² > 0, L6's x₂ added
FORM_OVER = 3  # s² < 0 (over-damped) or s² = 0 (critically damped), L2


@numba.njit(**INLINE)
def _parts(f, t, form):
    # The library calls of ``form`` at t (L2): under-damped e = exp(−βt/2), cos st, sin st;
    # over-damped e^{λ₁t}, e^{λ₂t} (λ₂ = −β/2 − μ), expm1(−2μt); critical e = exp(−βt/2).
    if form != FORM_OVER:
        return _exp(-f.hb * t), math.cos(f.s * t), math.sin(f.s * t)
    if f.s2 < 0.0:
        mu = f.mu
        return _exp(f.lam1 * t), _exp((-f.hb - mu) * t), math.expm1(-2.0 * mu * t)
    return _exp(-f.hb * t), 0.0, 0.0


@numba.njit(**INLINE)
def _exp(x):
    # exp(x), +0 below EXP_ZERO without the call (the same +0; NaN still exp's).
    return 0.0 if x < EXP_ZERO else math.exp(x)


@numba.njit(**INLINE)
def _value(f, parts, t, form):
    # θ, θ' of ``form`` at t from its ``parts`` (:func:`_parts`): x = x₀ e_c + b e_s and
    # its derivative (L2), L6's x₂ added in FORM_UNDER2.
    x0, hb, s2, b, s = f.x0, f.hb, f.s2, f.b, f.s
    e, c1, s1 = parts
    if form != FORM_OVER:
        ec = e * c1
        es = e * s1 / s
    elif s2 < 0.0:
        mu = f.mu
        ec = 0.5 * (e + c1)
        es = e * (-s1) / (2.0 * mu)
    else:
        ec = e
        es = e * t
    x = x0 * ec + b * es
    xd = x0 * (-hb * ec - s2 * es) + b * (ec - hb * es)
    if form == FORM_UNDER2 and t != 0.0:
        ee = e if e >= E2_FLOOR else 0.0
        x, xd = _l6_add(x, xd, (e, ee * ee, c1, s1), (s, hb), (f.qr, f.qi, f.m, f.dr, f.di))
    return f.th0 + (x - x0), xd


@numba.njit(**INLINE)
def _l6_add(x, xd, parts, rates, l6):
    # (L6): x₂ and x₂' added to x, x' from ``parts`` = (E, E², cos st, sin st), ``rates``
    # = (s, β/2) and ``l6`` = (Q_r, Q_i, M, D_r, D_i); zero at the anchor by construction,
    # where the callers skip it so that t = 0 is the anchor bit for bit.
    e, e2, c1, s1 = parts
    s, hb = rates
    qr, qi, m, dr, di = l6
    c2 = c1 * c1 - s1 * s1
    sn2 = 2.0 * s1 * c1
    beta = 2.0 * hb
    x = x + (e2 * (qr * c2 - qi * sn2) + m * e2 + e * (dr * c1 - di * s1))
    xd = xd + (e2 * ((-beta * qr - 2.0 * s * qi) * c2 - (-beta * qi + 2.0 * s * qr) * sn2) - beta * m * e2
               + e * ((-hb * dr - s * di) * c1 - (-hb * di + s * dr) * s1))
    return x, xd


@numba.njit(**INLINE)
def locked_at(f, t):
    """θ and θ' of the locked form ``f`` (:func:`locked_form`) at ``t`` from the anchor:
    :func:`locked_eval`'s formula (L2; L6's x₂ added at order 2)."""
    if f.s2 > 0.0 and f.order2:
        return _value(f, _parts(f, t, FORM_UNDER2), t, FORM_UNDER2)
    if f.s2 > 0.0:
        return _value(f, _parts(f, t, FORM_UNDER), t, FORM_UNDER)
    return _value(f, _parts(f, t, FORM_OVER), t, FORM_OVER)


@kernel
def locked_eval(coef, t):
    """The linearized motion of a locked window (item L2; with L6's x₂ at order 2).

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
    # One time through locked_eval_range's loop (_form_range): the formula compiled once
    # for both (a first call's compile), the same operations (t − 0.0 is t).
    one = np.empty(3)
    one[0] = t
    locked_eval_range(coef, 0.0, one[0:1], np.int64(0), np.int64(1), one[1:2], one[2:3])
    return one[1], one[2]


@kernel
def locked_eval_range(coef, t0, times, lo, hi, out_theta, out_v):
    """:func:`locked_eval` at ``times[lo:hi] − t0``, written to ``out_*[lo:hi]``.

    The window's constants formed once (:func:`locked_form`), then one loop over the
    times of the library calls and arithmetic of :func:`locked_eval` for the window's
    form: the same operations per time, so the same bits.

    Parameters
    ----------
    coef : ndarray
        From :func:`locked_coef`.
    t0 : float
        The window's anchor time.
    times : ndarray
        Absolute times, in any order.
    lo, hi : int
        The rows to evaluate.
    out_theta, out_v : ndarray
        θ and θ' written to their rows ``lo .. hi``.
    """
    f = locked_form(coef)
    # The form as a value: _form_range compiled once, its loop's branch on the form
    # invariant (LLVM takes it out of the loop).
    form = FORM_UNDER2 if (f.s2 > 0.0 and f.order2) else (FORM_UNDER if f.s2 > 0.0 else FORM_OVER)
    _form_range(f, (t0, times, lo, hi), out_theta, out_v, form)


@kernel
def _form_range(f, rows, out_theta, out_v, form):
    # The outputs ``rows`` = (t0, times, lo, hi) of one form (locked_eval_range).
    t0, times, lo, hi = rows
    for q in range(lo, hi):
        t = times[q] - t0
        out_theta[q], out_v[q] = _value(f, _parts(f, t, form), t, form)


@kernel
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
    locked_eval_range(coef, 0.0, t, 0, t.size, out_theta, out_v)


@kernel
def _lock_setup(beta, gamma, omega, can_lock, can_lock2):
    """The locked test's constants of a run (L5; |sin d| and the second-order quick
    test's q₂ where ``can_lock2``): ``(d, ω_l², G₀, G₁, |sin d|, q₂, can_lock2)``, the
    second-order form off where its quick test rules it out."""
    d, wl2, g0, g1, sd, q2 = 0.0, 1.0, 0.0, 0.0, 0.0, 0.0
    if can_lock:
        d, wl2, g0, g1 = locked_constants(beta, gamma, omega)
        sd = abs(math.sin(d))
        if can_lock2:
            q2 = locked2_quick(beta, gamma, omega, d, wl2, g0)
            can_lock2 = q2 > 0.0
    return LockSetup(d, wl2, g0, g1, sd, q2, can_lock2)
