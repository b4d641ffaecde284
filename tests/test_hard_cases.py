"""Named hard cases: each records its measured error, pinned with a margin.

The pinned numbers were measured on this code base (comments give the value); the
assertions allow a factor of about 3 over the measurement so that a platform's
round-off does not flip them, while a real regression (an order of magnitude) does.
"""

import math
import warnings

import mpmath
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

import mbm

RTOL = ATOL = 1e-9
REF_TOL = 1e-13


def _mbm(model, t_span, y0, t_eval, **kw):
    kw.setdefault("rtol", RTOL)
    kw.setdefault("atol", ATOL)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "no error estimate" warnings of the papers' approximants
        sol = solve_ivp(model, t_span, y0, method=mbm.MBM, t_eval=t_eval, **kw)
    assert sol.status == 0, sol.message
    assert np.all(np.isfinite(sol.y))
    return sol


def _err_vs_reference(model, y0, T, n=41, **kw):
    t = np.linspace(0.0, T, n)
    sol = _mbm(model, (0.0, T), y0, t, **kw)
    ref = mbm.reference(model, (0.0, T), y0, t_eval=t, rtol=REF_TOL, atol=REF_TOL)
    assert ref.success
    return float(np.max(np.abs(sol.y - ref.y)))


# ---------------------------------------------------------------------------
# The separatrix, approached as θ̇₀ = 2ω(1 − 10⁻ᵏ) and hit exactly
# ---------------------------------------------------------------------------


def _exact_libration(kappa, omega, t):
    # From θ₀ = 0, θ̇₀ = 2ωκ: sin(θ/2) = κ sn(ωt | κ²), θ' = 2ωκ cn(ωt | κ²) (40 digits).
    m = kappa**2
    th = [float(2 * mpmath.asin(kappa * mpmath.ellipfun("sn", omega * mpmath.mpf(x), m=m))) for x in t]
    v = [float(2 * omega * kappa * mpmath.ellipfun("cn", omega * mpmath.mpf(x), m=m)) for x in t]
    return np.array([th, v])


def _exact_separatrix(omega, t):
    # θ = 4 arctan(tanh(ωt/2)), θ' = 2ω sech(ωt).
    th = [float(4 * mpmath.atan(mpmath.tanh(omega * mpmath.mpf(x) / 2))) for x in t]
    v = [float(2 * omega / mpmath.cosh(omega * mpmath.mpf(x))) for x in t]
    return np.array([th, v])


@pytest.mark.parametrize("k", list(range(1, 13)) + [None])
def test_separatrix_undamped_auto(k):
    # β = γ = 0: "auto" is the exact elliptic flow; against 40-digit mpmath it is at
    # round-off for every k: measured max |error| over t in [0, 10] (θ and θ'):
    # 4.4e-16 (k = 1, 2, 3, 6, 8, 12), 1.3e-15 (k = 4), 6.7e-16 (k = 5, 10), 8.9e-16
    # (k = 7, 9), 5.6e-16 (k = 11), 2.2e-16 (on the separatrix).  (The CVODE
    # reference at 1e-13 is *worse* here, 7e-9: the period diverges as k grows.)
    mpmath.mp.dps = 40
    omega = 1.0
    t = np.linspace(0.0, 10.0, 21)
    if k is None:
        v0 = 2.0 * omega
        exact = _exact_separatrix(omega, t)
    else:
        kappa = 1 - mpmath.mpf(10) ** -k
        v0 = float(2 * omega * kappa)
        exact = _exact_libration(mpmath.mpf(v0) / (2 * omega), omega, t)
    sol = _mbm(mbm.Pendulum(omega=omega), (0.0, 10.0), [0.0, v0], t)
    assert sol.y[0].max() < math.pi  # never crosses the top: a libration (or the separatrix)
    assert np.max(np.abs(sol.y - exact)) <= 4e-15


@pytest.mark.parametrize("k, pinned", [(1, 3.1e-9), (6, 1.85e-8), (12, 1.85e-8)])
def test_separatrix_damped_auto(k, pinned):
    # β = 0.01: the convergent family at rtol = atol = 1e-9 against CVODE at 1e-13 over
    # [0, 10]; measured 3.15e-9 (k = 1), 1.85e-8 (k = 6 and 12: the same orbit to 1e-6).
    err = _err_vs_reference(mbm.Pendulum(beta=0.01), [0.0, 2.0 * (1 - 10.0**-k)], 10.0)
    assert err <= 3 * pinned


# ---------------------------------------------------------------------------
# Saddle-node γ = ω²(1 ± 1e-6), critical damping β = 2ω ± 1e-9
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("sign, pinned", [(+1, 4.2e-10), (-1, 1.7e-10)])
def test_saddle_node(sign, pinned):
    # Start at θ = π/2, the saddle-node's position, at rest, β = 0.1: for γ just above ω²
    # the pendulum creeps through the bottleneck; just below, it sits between the node
    # and the saddle 2.8e-3 apart.  Measured over [0, 50]: 4.21e-10 (+), 1.67e-10 (−).
    model = mbm.Pendulum(beta=0.1, gamma=1.0 + sign * 1e-6)
    err = _err_vs_reference(model, [math.pi / 2, 0.0], 50.0)
    assert err <= 3 * pinned


@pytest.mark.parametrize("omega, y0, pinned", [(1.0, [1.0, 0.0], 3.13e-11), (3.0, [1.0, -2.0], 1.27e-11)])
@pytest.mark.parametrize("sign", [+1, -1])
def test_critical_damping_auto(omega, y0, pinned, sign):
    # Measured over [0, 20]: 3.13e-11 (ω = 1), 1.27e-11 (ω = 3), both signs alike.
    err = _err_vs_reference(mbm.Pendulum(beta=2 * omega + sign * 1e-9, omega=omega), y0, 20.0)
    assert err <= 3 * pinned


@pytest.mark.parametrize("name", ["salas-damped", "salas-damped-linear", "johannessen", "johannessen-trig"])
def test_critical_damping_first_paper(name):
    # Just below critical damping (ε² = ω² − 1e-9 > ω²/3) the first paper's amplitude
    # equation (2.7) has no admissible root for θ₀ = 0.3 (salas-damped*, status 4), and no
    # Jacobi M < 1 reproduces the anchor (johannessen*, status 5): documented domain
    # errors, not NaN; just above, the scene itself is refused (status 2).
    ap = mbm.get_approximant(name)
    with pytest.raises(mbm.ApproximantDomainError, match=r"no admissible root|no Jacobi parameter M < 1"):
        ap.anchor(mbm.Pendulum(beta=2.0 - 1e-9), 0.3, 0.0)
    with pytest.raises(mbm.ApproximantDomainError, match=r"beta/2 < omega"):
        ap.anchor(mbm.Pendulum(beta=2.0 + 1e-9), 0.3, 0.0)


# ---------------------------------------------------------------------------
# β = 0 through every approximant that allows it: removable 0/0 at ε = 0
# ---------------------------------------------------------------------------

BETA0_T = np.array([0.3, 1.0, 5.0, 20.0])
BETA0_STATES = [(1.0, 0.0), (0.5, 0.7), (-2.0, -0.3)]


@pytest.mark.parametrize(
    "name, slope",
    [
        # measured max |f(β) − f(0)| / β over the states, t ≤ 20, β in 1e-14 … 1e-6:
        ("salas-damped", 13.0),  # 1.30e1
        ("salas-damped-linear", 8.7),  # 8.67
        ("johannessen", 242.0),  # 2.42e2 (θ₀ = −2, near the top)
        ("johannessen-trig", 275.0),  # 2.75e2
        ("salas-torque", 18.6),  # 1.86e1
        ("salas-torque-cn", 18.6),
        ("salas-torque-trig", 18.6),
        ("split4", 19.8),  # 1.98e1
    ],
)
def test_beta_zero_is_continuous(name, slope):
    # (2.5)–(2.6) of the first paper and Johannessen's ξ(t) divide by ε = β/2: a naive
    # evaluation near ε = 0 cancels catastrophically (f(β) − f(0) ~ eps/β).  Stable
    # evaluation: the change is linear in β down to β = 1e-14 and exactly 0 at 1e-300.
    ap = mbm.get_approximant(name)
    worst = 0.0
    for th0, v0 in BETA0_STATES:
        f0 = np.array(ap.anchor(mbm.Pendulum(), th0, v0)(BETA0_T))
        assert np.all(np.isfinite(f0))
        f_tiny = np.array(ap.anchor(mbm.Pendulum(beta=1e-300), th0, v0)(BETA0_T))
        assert np.max(np.abs(f_tiny - f0)) <= 1e-15  # 0 except split4: 8.9e-16
        for beta in (1e-14, 1e-12, 1e-10, 1e-8, 1e-6):
            fb = np.array(ap.anchor(mbm.Pendulum(beta=beta), th0, v0)(BETA0_T))
            d = np.max(np.abs(fb - f0))
            # round-off floor 1e-14 (θ up to ~3, t up to 20) plus the linear change
            assert d <= 1e-13 + 1.5 * slope * beta, (th0, v0, beta, d)
            worst = max(worst, (d - 1e-13) / beta)
    assert worst <= 1.5 * slope


@pytest.mark.parametrize(
    "name, pinned",
    [
        # Model error at β = γ = 0 against the exact flow over t ≤ 20 (max over the states):
        ("johannessen", 1.8e-15),  # 1.78e-15: at ε = 0 (3.9) *is* the exact sn solution
        ("belendez", 0.0),  # exact
        ("split4", 0.0),  # β = γ = 0: the splitting is the exact flow alone
        ("harmonic", 0.168),  # 0.168 (θ₀ = −2)
        ("johannessen-trig", 0.186),  # 0.186
        ("salas-damped", 1.90),  # 1.90: the elementary approximant dephases near the top
        ("salas-damped-linear", 1.90),
        ("salas-torque", 1.87),  # 1.87: the cubic sin θ ≈ θ − 2θ³/13 at θ₀ = −2 (115°)
    ],
)
def test_beta_zero_model_error(name, pinned):
    ap = mbm.get_approximant(name)
    exact_ap = mbm.get_approximant("belendez")
    err = 0.0
    for th0, v0 in BETA0_STATES:
        a = ap.anchor(mbm.Pendulum(), th0, v0)
        assert a(0.0) == (th0, v0)
        err = max(err, np.max(np.abs(np.array(a(BETA0_T)) - np.array(exact_ap.anchor(mbm.Pendulum(), th0, v0)(BETA0_T)))))
    assert err <= 1.05 * pinned + 4e-15


# ---------------------------------------------------------------------------
# θ̇₀ = 0 exactly (the first paper's sign(θ̇₀))
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["salas-damped", "salas-damped-linear", "johannessen", "johannessen-trig",
                                  "salas-torque", "salas-torque-cn", "taylor", "split4"])
@pytest.mark.parametrize("theta0", [1.0, -1.0])
def test_zero_velocity_anchor(name, theta0):
    # sign(0) = 0 in (2.8) would give amplitude 0 (θ ≡ 0); the anchor must be reproduced
    # and the formula continuous in θ̇₀ from both sides.  Measured: the change for
    # θ̇₀ = ±1e-12 is ≤ 1.0e-12 (the state itself moves by 1e-12) at t ≤ 1.
    model = mbm.Pendulum(beta=0.2)
    ap = mbm.get_approximant(name)
    a = ap.anchor(model, theta0, 0.0)
    assert a(0.0) == (theta0, 0.0)
    t = np.array([0.1, 0.5, 1.0])
    f0 = np.array(a(t))
    assert np.all(np.isfinite(f0))
    # from rest, the pendulum swings down: θ moves toward 0 and θ' takes −sign(θ₀)
    assert np.all(np.sign(f0[1]) == -np.sign(theta0))
    for v0 in (5e-324, -5e-324, 1e-300, -1e-300, 1e-12, -1e-12):
        f = np.array(ap.anchor(model, theta0, v0)(t))
        assert np.max(np.abs(f - f0)) <= 3e-12, v0


# ---------------------------------------------------------------------------
# τ = 1e-8, and τ longer than the horizon
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "name, model, pinned",
    [
        # 1000 windows of 1e-8 over [0, 1e-5]:
        ("taylor", mbm.Pendulum(beta=0.1, gamma=0.3), 7.8e-16),  # 7.77e-16: round-off
        # 1.34e-8 = the cubic's acceleration error (1.4e-3 at θ = 0.5) times the horizon:
        # the papers' model error, which re-anchoring cannot remove however small τ is
        ("salas-torque", mbm.Pendulum(beta=0.1, gamma=0.3), 1.34e-8),
        ("salas-damped", mbm.Pendulum(beta=0.1), 7.7e-8),  # 7.70e-8, the same effect
    ],
)
def test_tiny_tau(name, model, pinned):
    err = _err_vs_reference(model, [0.5, 0.2], 1e-5, approximant=name, tau=1e-8)
    assert err <= 1.5 * pinned + 4e-16


@pytest.mark.parametrize("name, pinned", [("taylor", 1.78e-12), ("salas-torque", 1.14e-3)])
def test_tau_longer_than_horizon(name, pinned):
    # τ = 100 over [0, 1]: one window, cut to land on t_bound exactly.  Measured:
    # 1.78e-12 (Taylor degree 24 over one window of 1), 1.14e-3 (the cubic's model error).
    model = mbm.Pendulum(beta=0.1, gamma=0.3)
    err = _err_vs_reference(model, [0.5, 0.2], 1.0, approximant=name, tau=100.0)
    assert err <= 1.5 * pinned
    res = mbm.solve(model, (0.0, 1.0), [0.5, 0.2], approximant=name, tau=100.0)
    assert res.n_windows == 1 and res.t[-1] == 1.0


# ---------------------------------------------------------------------------
# Long horizons: β = 0.01, γ = 0.3 (equilibrium) and γ = 1.2 (running limit cycle)
# ---------------------------------------------------------------------------


def test_long_horizon_settles_on_equilibrium():
    # From rest at θ = 0 the energy is below the barrier: the pendulum settles at
    # arcsin(0.3) (the transient is e^{−βt/2} = e^{−50} ≈ 2e-22 at t = 1e4).  Measured at
    # rtol = atol = 1e-9: θ − arcsin 0.3 = 1.31e-10, θ' = 4.18e-10 (the windows' local
    # errors, at atol level, keep the state from settling below that).
    model = mbm.Pendulum(beta=0.01, gamma=0.3)
    sol = _mbm(model, (0.0, 1e4), [0.0, 0.0], [1e4])
    th, v = sol.y[:, -1]
    assert abs(th - math.asin(0.3)) <= 4e-10
    assert abs(v) <= 1.3e-9


def _cycle_speed(beta, gamma, theta):
    """The running limit cycle θ' = u(θ), u(θ + 2π) = u(θ), from a tight θ-domain shooting.

    Returns u(theta mod 2π) and the period T = ∫₀^{2π} dθ/u.
    """
    def rhs(th, y):
        u = y[0]
        return [(gamma - beta * u - math.sin(th)) / u, 1.0 / u]

    def shoot(u0, th_end):
        r = solve_ivp(rhs, (0.0, th_end), [u0, 0.0], method="DOP853", rtol=1e-13, atol=1e-13)
        return r.y[:, -1]

    u0 = brentq(lambda u: shoot(u, 2 * math.pi)[0] - u, 0.5 * gamma / beta, 1.5 * gamma / beta, xtol=1e-13)
    T = shoot(u0, 2 * math.pi)[1]
    ph = theta % (2 * math.pi)
    return (shoot(u0, ph)[0] if ph > 0 else u0), T


def test_long_horizon_settles_on_running_cycle():
    # γ = 1.2 > ω²: no equilibrium; the pendulum runs at ≈ γ/β = 120 rad/s.  The
    # settled state at t = 1e4 is compared with the cycle u(θ) from an independent tight
    # shooting (DOP853 at 1e-13 in the θ domain, u(0) = 120.0083, mean speed
    # 2π/T = 119.9999997).  Measured: |θ'(1e4) − u(θ(1e4))| = 6.2e-7 (5e-9 relative),
    # and the advance of θ over the last period equals 2π to 1.0e-7.
    beta, gamma = 0.01, 1.2
    model = mbm.Pendulum(beta=beta, gamma=gamma)
    _, T = _cycle_speed(beta, gamma, 0.0)
    # mbm.solve: the same windows as solve_ivp(method=mbm.MBM) bit for bit, compiled
    # (solve_ivp with windows_per_step=None took 180 s here: see the report).
    sol = mbm.solve(model, (0.0, 1e4), [0.0, 0.0], rtol=RTOL, atol=ATOL, t_eval=[1e4 - T, 1e4])
    assert sol.success and np.all(np.isfinite(sol.y))
    th, v = sol.y[:, -1]
    u, _ = _cycle_speed(beta, gamma, th)
    assert abs(v - u) <= 2e-6
    advance = sol.y[0, -1] - sol.y[0, 0]
    assert abs(advance - 2 * math.pi) <= 3e-7
    assert abs(2 * math.pi / T - 119.9999997) <= 1e-6


@pytest.mark.slow
@pytest.mark.parametrize("gamma", [0.3, 1.2])
def test_long_horizon_1e6_against_reference(gamma):
    # The same scenes over 1e6 against CVODE at 1e-10 (CVODE takes long on the running
    # γ = 1.2: the whole slow suite took 31 min here, nearly all of it this case): the
    # settled states must agree.  For the equilibrium: to atol; for the running cycle the phase
    # along the cycle is not comparable after 1e6 (it is not stable), so compare the
    # speed at the same θ mod 2π through the cycle u(θ) and the final speeds' difference.
    model = mbm.Pendulum(beta=0.01, gamma=gamma)
    sol = mbm.solve(model, (0.0, 1e6), [0.0, 0.0], rtol=RTOL, atol=ATOL, t_eval=[1e6])
    assert sol.success and np.all(np.isfinite(sol.y))
    ref = mbm.reference(model, (0.0, 1e6), [0.0, 0.0], t_eval=[1e6], rtol=1e-10, atol=1e-10)
    assert ref.success
    th, v = sol.y[:, -1]
    if gamma < 1:
        # The settled state is known exactly (asin γ, 0): mbm meets it to 1e-9.  CVODE
        # at 1e-10 settles 3.1e-9 off it (measured; its corrector stops within its
        # weighted tolerance, not at the fixed point), so it is held to 1e-8.
        assert abs(th - math.asin(gamma)) <= 1e-9 and abs(v) <= 1.3e-9
        assert abs(ref.y[0, -1] - math.asin(gamma)) <= 1e-8
    else:
        u, _ = _cycle_speed(0.01, gamma, th)
        ur, _ = _cycle_speed(0.01, gamma, ref.y[0, -1])
        assert abs(v - u) <= 2e-6
        assert abs(ref.y[1, -1] - ur) <= 2e-6


# ---------------------------------------------------------------------------
# Conservation: β = γ = 0 over 1e6 through solve_ivp "auto" (the exact flow)
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("y0", [[1.0, 0.0], [0.0, 1.999], [2.0, -0.5], [3.0, 0.0], [0.0, 2.0 - 1e-12]])
def test_energy_conserved_libration(y0):
    # Librations (and the separatrix's neighbourhood): measured max relative energy drift
    # over 2001 outputs on [0, 1e6]: 6.0e-16 ([1, 0]), 4.4e-16 ([0, 1.999]), 5.8e-16 ([2, −0.5]).
    model = mbm.Pendulum()
    t = np.linspace(0.0, 1e6, 2001)
    sol = _mbm(model, (0.0, 1e6), y0, t, rtol=1e-3, atol=1e-6)  # tolerances do not matter: exact
    assert sol.nfev == 0  # a Pendulum is not probed
    E0 = model.energy(np.array(y0))
    assert np.max(np.abs(model.energy(sol.y) - E0)) / E0 <= 1e-12


@pytest.mark.parametrize("y0", [[0.3, 3.0], [0.0, -2.5], [1.0, 10.0]])
def test_energy_conserved_rotation(y0):
    # A rotation reaches |θ| ~ 3e6 .. 1e7 at t = 1e6, where θ itself is only representable
    # to ulp(θ) ~ 5e-10 .. 2e-9: the energy computed from the stored θ can be no better
    # than ω² ulp(θ) absolute (measured 4.9e-11 relative for [0.3, 3] — *not* 1e-12: the
    # issue's 1e-12 is unreachable for rotations in double precision with θ unwrapped).
    # Assert the drift is at that representation floor, and that θ mod 2π is right
    # (energy of the reduced state).
    model = mbm.Pendulum()
    t = np.linspace(0.0, 1e6, 2001)
    sol = _mbm(model, (0.0, 1e6), y0, t)
    E0 = model.energy(np.array(y0))
    dE = np.abs(model.energy(sol.y) - E0)
    floor = 2.0 * np.spacing(np.abs(sol.y[0])) + 4 * np.finfo(float).eps * E0
    assert np.all(dE <= floor)
