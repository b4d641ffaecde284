r"""Kernels of the first paper's approximants (:mod:`mbm.approximants.salas2021`).

The numba kernels of Salas (2021): the elementary solution (2.2)–(2.8) and
Johannessen's (3.9) with its trigonometric form, their anchors, evaluators, status
codes and tolerances.  The derivations, the misprints and the domain are described
in :mod:`mbm.approximants.salas2021`, which registers the Approximant classes.
"""

import math

import numpy as np

from ..special.dd import TWO_PI_HI, nearest_2pi_multiple
from ..special.jacobi import ellipf_kernel, ellipj_kernel
from ..compile.jit import kernel
from ..special.trig import sin_m_dm_kernel, trig_m_kernel


# Status codes of the anchor kernels (their messages: salas2021._STATUS_MESSAGES)
STATUS_OK = 0
STATUS_TORQUE = 1
STATUS_OVERDAMPED = 2
STATUS_ROTATION = 3
STATUS_NO_AMPLITUDE = 4
STATUS_NO_PARAMETER = 5
STATUS_NONFINITE = 6


# Below this |y| the power series of q(y) = (1 − (1 + y)e^{−y})/y is used: the direct
# form loses about 2ε/|y| relative (two terms of size y cancel to y²/2), the series
# needs ~20 terms at |y| = 1 to reach 1e-17.
Q_SERIES_MAX = 1.0
# Cap on series terms (|y| ≤ 1 needs fewer than 20).
Q_SERIES_TERMS = 40
# Below this |y|, expm1(y)/y is taken from its Taylor polynomial 1 + y/2 + y²/6
# (truncation y³/24 < 1e-16 there); above, the quotient itself is accurate.
EXPREL_SERIES_MAX = 1e-5
# The quadratic's root x = a² may come out a few ulps below U² = tan²(θ₀/2) at a
# turning point (V = 0, where x = U² exactly); within this relative slack it is
# clamped to U², beyond it the root is inadmissible.
ROOT_CLAMP_RTOL = 64.0 * np.finfo(float).eps
# Johannessen's anchor equation is solved for y = √(M − S²) on [0, C(1 − Y_MARGIN)]:
# keeps 1 − M ≥ 2C²·Y_MARGIN > 0, i.e. M strictly below the separatrix value 1.
Y_MARGIN = 1e-12
# Largest |θ′(0)/2 − θ̇₀/2| (relative to 1 + |θ̇₀|) accepted from Johannessen's anchor
# equation: true roots leave ~1e-13 (conditioning of the 1/(1 − M) terms near
# M = 1), a sign change through the pole at M → 1 leaves ~1e-4.
ANCHOR_RESIDUAL_TOL = 1e-10
# Iteration cap of the bracketed root finder (Illinois converges superlinearly:
# ~10 iterations; bisection steps, if ever taken, need ≤ 64 to exhaust a double).
ROOT_MAXITER = 200
# Carlson duplication stops when the spread of the arguments is below this times
# their mean: the 5th/7th-order series then has truncation error < 1e-17.
CARLSON_TOL = 1e-4
# Safety cap on Carlson duplication steps (each divides the spread by 4).
CARLSON_MAXITER = 64


# ---------------------------------------------------------------------------
# Small stable helpers
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def _exprel(y):
    """expm1(y)/y, 1 at y = 0."""
    if abs(y) < EXPREL_SERIES_MAX:
        return 1.0 + y * (0.5 + y / 6.0)
    return math.expm1(y) / y


@kernel(error_model="numpy")
def _rlog1p(x):
    """log1p(x)/x, 1 at x = 0 (log1p is relatively accurate for small x)."""
    if x == 0.0:
        return 1.0
    return math.log1p(x) / x


@kernel(error_model="numpy")
def _ratan(x):
    """atan(x)/x, 1 at x = 0."""
    if x == 0.0:
        return 1.0
    return math.atan(x) / x


@kernel(error_model="numpy")
def _q(y):
    """q(y) = (1 − (1 + y) e^{−y}) / y = y/2 − y²/3 + y³/8 − …, 0 at y = 0."""
    if abs(y) <= Q_SERIES_MAX:
        # Σ_{n≥2} (−1)^n (n − 1) y^{n−1} / n!
        s = 0.0
        term = 1.0  # (−y)^{n−1}/n! running, starts at n = 1: 1/1!
        for n in range(2, Q_SERIES_TERMS):
            term *= -y / n
            add = (n - 1) * term
            s += add
            if abs(add) <= 1e-17 * abs(s):
                break
        return -s
    return (-math.expm1(-y) - y * math.exp(-y)) / y


@kernel(error_model="numpy")
def _reduce_angle(theta0):
    """(offset, θr): θ0 = offset + θr with offset a multiple of 2π and θr ∈ [−π, π].

    The offset is added back to the formula's angle in double ((2.2): θ = offset +
    2 arctan(…)), so θr is the plain remainder θ0 − offset, not the double-double
    one of :func:`mbm.special.dd.reduce_2pi` (whose j it shares).
    """
    off = nearest_2pi_multiple(theta0) * TWO_PI_HI
    return off, theta0 - off


# ---------------------------------------------------------------------------
# Carlson R_F, R_D and the incomplete integral of the second kind
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def _rf(x, y, z):
    """Carlson's R_F(x, y, z), x, y, z ≥ 0, at most one zero (duplication, DLMF 19.36.1)."""
    for _ in range(CARLSON_MAXITER):
        mu = (x + y + z) / 3.0
        dx = 1.0 - x / mu
        dy = 1.0 - y / mu
        dz = 1.0 - z / mu
        if max(abs(dx), abs(dy), abs(dz)) < CARLSON_TOL:
            break
        sx = math.sqrt(x)
        sy = math.sqrt(y)
        sz = math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        x = 0.25 * (x + lam)
        y = 0.25 * (y + lam)
        z = 0.25 * (z + lam)
    mu = (x + y + z) / 3.0
    dx = 1.0 - x / mu
    dy = 1.0 - y / mu
    dz = -dx - dy
    e2 = dx * dy - dz * dz
    e3 = dx * dy * dz
    return (
        1.0 - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - 3.0 * e2 * e3 / 44.0
    ) / math.sqrt(mu)


@kernel(error_model="numpy")
def _rd(x, y, z):
    """Carlson's R_D(x, y, z), x, y ≥ 0 (not both 0), z > 0 (DLMF 19.36.2)."""
    s = 0.0
    fac = 1.0
    for _ in range(CARLSON_MAXITER):
        mu = (x + y + 3.0 * z) / 5.0
        dx = 1.0 - x / mu
        dy = 1.0 - y / mu
        dz = 1.0 - z / mu
        if max(abs(dx), abs(dy), abs(dz)) < CARLSON_TOL:
            break
        sx = math.sqrt(x)
        sy = math.sqrt(y)
        sz = math.sqrt(z)
        lam = sx * (sy + sz) + sy * sz
        s += fac / (sz * (z + lam))
        fac *= 0.25
        x = 0.25 * (x + lam)
        y = 0.25 * (y + lam)
        z = 0.25 * (z + lam)
    mu = (x + y + 3.0 * z) / 5.0
    dx = 1.0 - x / mu
    dy = 1.0 - y / mu
    dz = 1.0 - z / mu
    ea = dx * dy
    eb = dz * dz
    ec = ea - eb
    ed = ea - 6.0 * eb
    ee = ed + ec + ec
    ser = 1.0 + ed * (-3.0 / 14.0 + 9.0 / 88.0 * ed - 4.5 / 26.0 * dz * ee) + dz * (
        ee / 6.0 + dz * (-9.0 / 22.0 * ec + 3.0 / 26.0 * dz * ea)
    )
    return 3.0 * s + fac * ser / (mu * math.sqrt(mu))


@kernel(error_model="numpy")
def ellipe_kernel(phi, m, mc):
    """E(φ|m) for real φ and m < 1 (mc = 1 − m > 0), numba kernel.

    E(φ|m) = sin φ R_F(cos²φ, Δ², 1) − (m/3) sin³φ R_D(cos²φ, Δ², 1) on |φ| ≤ π/2
    (DLMF 19.25.9–10), Δ² = cos²φ + mc sin²φ, extended by E(φ + jπ) = E(φ) + 2jE(m).
    """
    j = math.floor(phi / math.pi + 0.5)
    r = phi - j * math.pi
    s = math.sin(r)
    c = math.cos(r)
    c2 = c * c
    d2 = c2 + mc * s * s
    e = s * _rf(c2, d2, 1.0) - (m / 3.0) * s * s * s * _rd(c2, d2, 1.0)
    if j != 0.0:
        e += 2.0 * j * (_rf(0.0, mc, 1.0) - (m / 3.0) * _rd(0.0, mc, 1.0))
    return e


# ---------------------------------------------------------------------------
# The elementary solution (2.2)–(2.8)
# ---------------------------------------------------------------------------

# coef layout of the two "salas-damped" approximants
_S_EPS, _S_SQRTC, _S_A, _S_PHI, _S_P, _S_Q, _S_QMP, _S_RR, _S_U0 = 1, 2, 3, 4, 5, 6, 7, 8, 9
_S_OFF, _S_TH0, _S_V0, _S_OMEGA = 10, 11, 12, 13
_S_NCOEF = 14
_S_PARAM_NAMES = (
    "epsilon", "sqrt_c", "a", "phi", "P", "Q", "Q_minus_P", "P_over_Q", "u0",
    "offset", "theta0", "theta_dot0", "omega",
)


@kernel(error_model="numpy")
def _common_status(beta, gamma, omega, theta0, v0):
    """Status shared by all four approximants, and the reduced anchor."""
    eps = 0.5 * beta
    off, thr = _reduce_angle(theta0)
    if gamma != 0.0:
        return STATUS_TORQUE, eps, off, thr
    if not (eps < omega):
        return STATUS_OVERDAMPED, eps, off, thr
    s = math.sin(0.5 * thr)
    w = v0 / (2.0 * omega)
    if s * s + w * w >= 1.0:
        return STATUS_ROTATION, eps, off, thr
    return STATUS_OK, eps, off, thr


@kernel(error_model="numpy")
def salas_anchor(beta, gamma, omega, theta0, v0):
    """Anchor kernel of "salas-damped" and "salas-damped-linear" (see module docstring)."""
    coef = np.zeros(_S_NCOEF)
    status, eps, off, thr = _common_status(beta, gamma, omega, theta0, v0)
    coef[_S_EPS] = eps
    coef[_S_OFF] = off
    coef[_S_TH0] = theta0
    coef[_S_V0] = v0
    coef[_S_OMEGA] = omega
    if status != STATUS_OK:
        coef[0] = status
        return coef
    c = (omega - eps) * (omega + eps)
    alpha = 3.0 * (omega * omega - 3.0 * eps * eps)
    kk = 2.0 * (2.0 * eps * eps + omega * omega)
    U = math.tan(0.5 * thr)
    V = 0.5 * v0 * (1.0 + U * U) + eps * U
    b = 4.0 * c - alpha * U * U - 5.0 * V * V
    g = -4.0 * (c * U * U + V * V)
    disc = b * b - 4.0 * alpha * g
    if b > 0.0:
        if disc < 0.0:
            coef[0] = STATUS_NO_AMPLITUDE
            return coef
        x = -2.0 * g / (b + math.sqrt(disc))  # the root vanishing with U, V
    elif alpha > 0.0:
        x = (-b + math.sqrt(disc)) / (2.0 * alpha)  # same root; no cancellation for b ≤ 0
    else:
        coef[0] = STATUS_NO_AMPLITUDE
        return coef
    U2 = U * U
    if x < U2:
        if x >= U2 * (1.0 - ROOT_CLAMP_RTOL):
            x = U2
        else:
            coef[0] = STATUS_NO_AMPLITUDE
            return coef
    P = alpha * x / (4.0 * c)
    Q = 1.25 * x
    if not (1.0 + P > 0.0):
        coef[0] = STATUS_NO_AMPLITUDE
        return coef
    u0 = math.sqrt((1.0 + P) / (1.0 + Q))
    sqc = math.sqrt(c)
    a = math.sqrt(x)
    phi = math.atan2(U * sqc * u0, V) if x > 0.0 else 0.0
    coef[_S_SQRTC] = sqc
    coef[_S_A] = a
    coef[_S_PHI] = phi
    coef[_S_P] = P
    coef[_S_Q] = Q
    coef[_S_QMP] = x * kk / (4.0 * c)
    coef[_S_RR] = alpha / (5.0 * c)
    coef[_S_U0] = u0
    for i in range(1, _S_NCOEF):
        if not math.isfinite(coef[i]):
            coef[0] = STATUS_NONFINITE
    return coef


@kernel(error_model="numpy")
def salas_f_kernel(eps, sqc, P, Q, QmP, rr, u0, t):
    """F(t) = ∫₀ᵗ f′ (2.6) in closed form, and f′(t) (2.5); stable as ε → 0.

    Parameters are those of the coefficient vector: f′ = √c u(E), u² = (E + P)/(E + Q),
    E = e^{2ετ}, QmP = Q − P, rr = P/Q (given separately so that a = 0 is regular).
    """
    y = 2.0 * eps * t
    if t > 0.0:
        inv = math.exp(-y)
        u1 = math.sqrt((1.0 + P * inv) / (1.0 + Q * inv))
        rho = t * _exprel(-y) / (1.0 + Q * inv)  # (E₁ − 1)/(2ε(E₁ + Q))
    else:
        E1 = math.exp(y)
        inv = 0.0
        u1 = math.sqrt((E1 + P) / (E1 + Q))
        rho = t * _exprel(y) / (E1 + Q)
    usum = u1 + u0
    du2e = QmP * rho / ((1.0 + Q) * usum)  # Δu / (2ε)
    du = 2.0 * eps * du2e
    # 2(artanh u₁ − artanh u₀) / (2ε) = [2 log1p(Δu/(1+u₀)) + log((E₁+Q)/(1+Q))] / (2ε)
    xa = du / (1.0 + u0)
    term = 2.0 * (du2e / (1.0 + u0)) * _rlog1p(xa)
    if y > 1.0:
        term += t + (math.log1p(Q * inv) - math.log1p(Q)) / (2.0 * eps)
    else:
        xb = math.expm1(y) / (1.0 + Q)
        term += (t * _exprel(y) / (1.0 + Q)) * _rlog1p(xb)
    # the log (P > 0) or arctan (P < 0) part, divided by 2ε
    if P > 0.0:
        r = math.sqrt(rr)
        den = (u1 + r) * usum
        w = 2.0 * eps * 2.0 * r * Q * (u0 + r) * rho / den
        term += 2.0 * P * (u0 + r) * rho / den * _rlog1p(w)
    elif P < 0.0:
        s = math.sqrt(-rr)
        den = u1 * u0 - rr
        z2 = s * du / den
        term += 2.0 * rr * du2e / den * _ratan(z2)
    return sqc * term, sqc * u1


@kernel(error_model="numpy")
def _salas_state(coef, F, fp, t):
    eps = coef[_S_EPS]
    a = coef[_S_A]
    psi = coef[_S_PHI] + F
    amp = a * math.exp(-eps * t)
    s = math.sin(psi)
    c = math.cos(psi)
    z = amp * s
    theta = coef[_S_OFF] + 2.0 * math.atan(z)  # (2.2)
    v = 2.0 * amp * (fp * c - eps * s) / (1.0 + z * z)
    return theta, v


@kernel(error_model="numpy")
def salas_eval_formula(coef, t):
    """(2.2) with (2.6) at t, without the exact-anchor shortcut at t = 0 (for tests)."""
    F, fp = salas_f_kernel(
        coef[_S_EPS], coef[_S_SQRTC], coef[_S_P], coef[_S_Q], coef[_S_QMP], coef[_S_RR],
        coef[_S_U0], t,
    )
    return _salas_state(coef, F, fp, t)


@kernel(error_model="numpy")
def salas_eval(coef, t):
    """Evaluate θ(t), θ′(t) of an anchored "salas-damped" approximant."""
    if t == 0.0:
        return coef[_S_TH0], coef[_S_V0]
    return salas_eval_formula(coef, t)


@kernel(error_model="numpy")
def salas_eval_array(coef, t, out_theta, out_v):
    """:func:`salas_eval` over an array of times."""
    for i in range(t.size):
        a, b = salas_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


@kernel(error_model="numpy")
def salas_linear_eval_formula(coef, t):
    """(2.2) with the paper's f ≈ f′(0)t, without the t = 0 shortcut (for tests)."""
    fp = coef[_S_SQRTC] * coef[_S_U0]
    return _salas_state(coef, fp * t, fp, t)


@kernel(error_model="numpy")
def salas_linear_eval(coef, t):
    """Evaluate θ(t), θ′(t) of an anchored "salas-damped-linear" approximant."""
    if t == 0.0:
        return coef[_S_TH0], coef[_S_V0]
    return salas_linear_eval_formula(coef, t)


@kernel(error_model="numpy")
def salas_linear_eval_array(coef, t, out_theta, out_v):
    """:func:`salas_linear_eval` over an array of times."""
    for i in range(t.size):
        a, b = salas_linear_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


def paper_amplitude(theta_dot0, epsilon, omega=1.0, sign=-1):
    """The amplitude a of (2.8) as printed (``sign=+1``) or corrected (``sign=-1``).

    a = ½ sign(θ̇₀) √[(±√Δ − 5θ̇₀² + 16ω² − 16ε²) / (6(3ε² − ω²))],
    Δ = 32θ̇₀²(ω² − 13ε²) + 256(ε² − ω²)² + 25θ̇₀⁴.

    Parameters
    ----------
    theta_dot0 : float
        θ'(0) at the zero crossing θ(0) = 0.
    epsilon : float
        The paper's ε = β/2.
    omega : float, optional
        ω (default 1).
    sign : {-1, +1}, optional
        Sign in front of √Δ: +1 is the printed (2.8), −1 the root that exists.

    Returns
    -------
    complex
        a; with ``sign=+1`` and ε² < ω²/3 it is purely imaginary (no real a), and
        for ε² > ω²/3 it is the large root, which does not vanish with θ̇₀.
    """
    if sign not in (-1, 1):
        raise ValueError(f"sign must be -1 or +1, got {sign!r}")
    v2 = theta_dot0 * theta_dot0
    e2 = epsilon * epsilon
    w2 = omega * omega
    delta = 32.0 * v2 * (w2 - 13.0 * e2) + 256.0 * (e2 - w2) ** 2 + 25.0 * v2 * v2
    rad = (sign * np.sqrt(complex(delta)) - 5.0 * v2 + 16.0 * w2 - 16.0 * e2) / (6.0 * (3.0 * e2 - w2))
    return 0.5 * np.sign(theta_dot0) * np.sqrt(rad)


# ---------------------------------------------------------------------------
# Johannessen's approximant (3.9) and its trigonometric form
# ---------------------------------------------------------------------------

_J_EPS, _J_OM, _J_SGN, _J_M, _J_MC, _J_U0, _J_OFF, _J_TH0, _J_V0, _J_OMEGA = range(1, 11)
_J_NCOEF = 11
_J_PARAM_NAMES = (
    "epsilon", "Omega", "sign", "M", "one_minus_M", "u0", "offset", "theta0",
    "theta_dot0", "omega",
)


@kernel(error_model="numpy")
def johannessen_xi_kernel(eps, Om, M, t):
    """ξ(t) of (3.9) (with κ² = M) and ξ′(t); regular at ε = 0 where ξ = Ωt."""
    k1 = 9.0 * Om * M * M / 256.0  # 9θ̇₀⁴/(4096 Ω³) with θ̇₀² = 4Ω²M (θ̇₀⁴, not the printed θ̇₀²)
    k2 = Om * M / 8.0  # θ̇₀²/(32 Ω)
    # k (1 − (1 + y)e^{−y})/ε = k (y/ε) q(y)
    xi = Om * t - k1 * 4.0 * t * _q(4.0 * eps * t) - k2 * 2.0 * t * _q(2.0 * eps * t)
    dxi = Om - eps * t * (16.0 * k1 * math.exp(-4.0 * eps * t) + 4.0 * k2 * math.exp(-2.0 * eps * t))
    return xi, dxi


@kernel(error_model="numpy")
def _j_theta_v(sgn, M, mcM, u0, eps, Om, t, trig):
    """θ − offset and θ′ of the (generalized) Johannessen form at t."""
    y2 = 2.0 * eps * t
    em = math.exp(-y2)
    m = M * em
    mc = mcM - M * math.expm1(-y2)  # 1 − M e^{−2εt} without cancellation
    if not (mc > 0.0):
        return math.nan, math.nan
    xi, dxi = johannessen_xi_kernel(eps, Om, M, t)
    u = xi + u0
    sqm = math.sqrt(M) * math.exp(-eps * t)
    if trig == 0:
        sn, cn, dn, am = ellipj_kernel(u, m, mc)
        # Jacobi epsilon ℰ(u|m) = E(am u | m), am increasing (continuous)
        ee = ellipe_kernel(am, m, mc)
        bracket = u - ee / mc
        z = sgn * sqm * sn
        v = 2.0 * sgn * sqm * (
            -eps * sn / dn + cn * dxi - eps * cn * bracket - eps * m * sn * cn * cn / (mc * dn)
        )
    else:
        s, c, d = trig_m_kernel(u, m)
        dsdm = sin_m_dm_kernel(u, m)
        z = sgn * sqm * s
        dz = sgn * sqm * (-eps * s + c * d * dxi - 2.0 * eps * m * dsdm)
        v = 2.0 * dz / math.sqrt((1.0 - z) * (1.0 + z))
    return 2.0 * math.asin(z), v


@kernel(error_model="numpy")
def _j_u0(sgn, S, y, M, mcM, trig):
    """Phase u₀ with σ√M sn(u₀|M) = S (or sin_m), cn(u₀) ≥ 0."""
    if trig == 0:
        return ellipf_kernel(math.atan2(sgn * S, y), M, mcM)
    A = math.sqrt(M * M - 144.0 * M + 144.0)
    L = A - M + 2.0
    w0 = math.atan2(sgn * S * math.sqrt(L), math.sqrt(14.0) * y)
    return w0 / math.sqrt(L / 14.0)


@kernel(error_model="numpy")
def _j_residual(y, sgn, S, C, eps, Om, v0, trig):
    """θ′(0)/2 − θ̇₀/2 of the form with amplitude M = S² + y²."""
    M = S * S + y * y
    mcM = (C - y) * (C + y)
    u0 = _j_u0(sgn, S, y, M, mcM, trig)
    if trig == 0:
        # closed form of θ′(0)/2 (module docstring): σyΩ − εy(F − E/(1−M)) − εSC/(1−M)
        ph = math.atan2(S, y)
        f = ellipf_kernel(ph, M, mcM)
        e = ellipe_kernel(ph, M, mcM)
        return sgn * y * Om - eps * y * (f - e / mcM) - eps * S * C / mcM - 0.5 * v0
    th, v = _j_theta_v(sgn, M, mcM, u0, eps, Om, 0.0, trig)
    return 0.5 * v - 0.5 * v0


@kernel(error_model="numpy")
def _johannessen_anchor(beta, gamma, omega, theta0, v0, trig):
    coef = np.zeros(_J_NCOEF)
    status, eps, off, thr = _common_status(beta, gamma, omega, theta0, v0)
    coef[_J_EPS] = eps
    coef[_J_OFF] = off
    coef[_J_TH0] = theta0
    coef[_J_V0] = v0
    coef[_J_OMEGA] = omega
    coef[_J_SGN] = 1.0
    coef[_J_MC] = 1.0
    if status != STATUS_OK:
        coef[0] = status
        return coef
    Om = math.sqrt((omega - eps) * (omega + eps))
    coef[_J_OM] = Om
    S = math.sin(0.5 * thr)
    C = math.cos(0.5 * thr)
    h0 = 0.5 * v0 + eps * S / C  # σ·(−residual at y = 0)
    sgn = 1.0 if h0 >= 0.0 else -1.0
    if S == 0.0:
        y = abs(h0) / Om  # zero crossing: (3.9) itself, κ = θ̇₀/(2Ω)
        if not (y < C * (1.0 - Y_MARGIN)):
            coef[0] = STATUS_NO_PARAMETER
            return coef
    elif h0 == 0.0:
        y = 0.0
    else:
        ymax = C * (1.0 - Y_MARGIN)
        lo = 0.0
        flo = -abs(h0)  # σ·residual(0)
        hi = min(abs(h0) / Om, ymax)
        fhi = sgn * _j_residual(hi, sgn, S, C, eps, Om, v0, trig)
        while not (fhi > 0.0) and hi < ymax:
            lo, flo = hi, fhi
            hi = min(2.0 * hi, ymax)
            fhi = sgn * _j_residual(hi, sgn, S, C, eps, Om, v0, trig)
        if not (fhi > 0.0):
            coef[0] = STATUS_NO_PARAMETER
            return coef
        # Illinois regula falsi on [lo, hi], σ·residual(lo) ≤ 0 < σ·residual(hi)
        side = 0
        y = hi
        for _ in range(ROOT_MAXITER):
            y = (lo * fhi - hi * flo) / (fhi - flo)
            if not (lo < y < hi):
                y = 0.5 * (lo + hi)
            fy = sgn * _j_residual(y, sgn, S, C, eps, Om, v0, trig)
            if fy == 0.0:
                break
            if fy > 0.0:
                hi, fhi = y, fy
                if side == 1:
                    flo *= 0.5
                side = 1
            else:
                lo, flo = y, fy
                if side == -1:
                    fhi *= 0.5
                side = -1
            if hi - lo <= 4.0 * np.finfo(np.float64).eps * hi:
                y = hi if abs(fhi) < abs(flo) else lo
                break
        # A sign change can also be a pole of the 1/(1 − M) terms next to M = 1:
        # accept only a true root.
        if not abs(_j_residual(y, sgn, S, C, eps, Om, v0, trig)) <= ANCHOR_RESIDUAL_TOL * (
            1.0 + abs(v0)
        ):
            coef[0] = STATUS_NO_PARAMETER
            return coef
    M = S * S + y * y
    mcM = (C - y) * (C + y)
    coef[_J_SGN] = sgn
    coef[_J_M] = M
    coef[_J_MC] = mcM
    coef[_J_U0] = _j_u0(sgn, S, y, M, mcM, trig)
    for i in range(1, _J_NCOEF):
        if not math.isfinite(coef[i]):
            coef[0] = STATUS_NONFINITE
    return coef


@kernel(error_model="numpy")
def johannessen_anchor(beta, gamma, omega, theta0, v0):
    """Anchor kernel of "johannessen" (3.9), any anchor (see module docstring)."""
    return _johannessen_anchor(beta, gamma, omega, theta0, v0, 0)


@kernel(error_model="numpy")
def johannessen_trig_anchor(beta, gamma, omega, theta0, v0):
    """Anchor kernel of "johannessen-trig": (3.9) with sin_m of (3.12)–(3.13)."""
    return _johannessen_anchor(beta, gamma, omega, theta0, v0, 1)


@kernel(error_model="numpy")
def _j_eval_formula(coef, t, trig):
    M = coef[_J_M]
    if M == 0.0:
        return coef[_J_OFF], 0.0  # rest at the bottom
    th, v = _j_theta_v(
        coef[_J_SGN], M, coef[_J_MC], coef[_J_U0], coef[_J_EPS], coef[_J_OM], t, trig
    )
    return coef[_J_OFF] + th, v


@kernel(error_model="numpy")
def johannessen_eval_formula(coef, t):
    """(3.9) at t without the exact-anchor shortcut at t = 0 (for tests)."""
    return _j_eval_formula(coef, t, 0)


@kernel(error_model="numpy")
def johannessen_eval(coef, t):
    """Evaluate θ(t), θ′(t) of an anchored "johannessen" approximant."""
    if t == 0.0:
        return coef[_J_TH0], coef[_J_V0]
    return _j_eval_formula(coef, t, 0)


@kernel(error_model="numpy")
def johannessen_eval_array(coef, t, out_theta, out_v):
    """:func:`johannessen_eval` over an array of times."""
    for i in range(t.size):
        a, b = johannessen_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


@kernel(error_model="numpy")
def johannessen_trig_eval_formula(coef, t):
    """(3.9) with sin_m at t without the exact-anchor shortcut at t = 0 (for tests)."""
    return _j_eval_formula(coef, t, 1)


@kernel(error_model="numpy")
def johannessen_trig_eval(coef, t):
    """Evaluate θ(t), θ′(t) of an anchored "johannessen-trig" approximant."""
    if t == 0.0:
        return coef[_J_TH0], coef[_J_V0]
    return _j_eval_formula(coef, t, 1)


@kernel(error_model="numpy")
def johannessen_trig_eval_array(coef, t, out_theta, out_v):
    """:func:`johannessen_trig_eval` over an array of times."""
    for i in range(t.size):
        a, b = johannessen_trig_eval(coef, t[i])
        out_theta[i] = a
        out_v[i] = b
