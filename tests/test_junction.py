"""mbm.junction: I–V curves of the RCSJ junction against an independent reference.

The reference is heyoka in 80-bit long double at tol 1e-19 (tests/data/oracle_heyoka.py
is the oracle of the tests; here its integrator is used with terminal events): from
each point's start state it settles (40 decay times), then times three passages of the cycle
through θ ≡ arcsin γ; ⟨θ'⟩ = 2·2π/(t₃ − t₁).  The retrapping current's reference is the
homoclinic bifurcation itself: the saddle's unstable manifold reaches the next saddle
above γ_r and falls back below it (bisected with the same integrator).  The locked
points' reference: heyoka's state at rest at the equilibrium after 40 decay times.
"""

import math

import numpy as np
import pytest

import mbm
from mbm import junction

import heyoka as hy  # noqa: E402  (the test extra's long-double oracle)

L = np.longdouble
# ⟨θ'⟩ accuracy asked of iv_curve at every bias point (the junction issue's target).
V_TOL = 1e-9


def _system():
    x, v = hy.make_vars("x", "v")
    return x, v, [(x, v), (v, hy.par[1] - hy.par[0] * v - hy.par[2] * hy.sin(x))]


@pytest.fixture(scope="module")
def heyoka_ld():
    x, v, sys_ = _system()
    plain = hy.taylor_adaptive(sys_, np.zeros(2, dtype=L), pars=np.zeros(3, dtype=L), tol=L(1e-19), fp_type=L)
    ev = hy.t_event(x - hy.par[3], fp_type=L)
    turn = hy.t_event(v, fp_type=L)
    events = hy.taylor_adaptive(sys_, np.zeros(2, dtype=L), pars=np.zeros(4, dtype=L), tol=L(1e-19), fp_type=L,
                                t_events=[ev, turn])
    return plain, events


def _ref_mean_velocity(integrators, beta, gamma, y0):
    plain, events = integrators
    plain.pars[:] = [beta, gamma, 1.0]
    plain.state[:] = y0
    plain.time = L(0)
    # settle: 40 decay times of the slowest mode (the locked linearization's, slowest
    # when overdamped) and 60/β for the cycle (its multiplier is e^{-βT_c} per turn)
    wl2 = math.sqrt(max(1.0 - gamma * gamma, 0.0))
    disc = beta * beta / 4 - wl2
    rate = beta / 2 - math.sqrt(disc) if disc > 0 else beta / 2
    if abs(gamma) >= 1.0:
        rate = beta
    plain.propagate_until(L(max(60.0 / beta, 40.0 / rate)))
    th, v = (float(c) for c in plain.state)
    d = math.asin(gamma) if abs(gamma) <= 1.0 else math.copysign(math.pi / 2, gamma)
    # locked: at rest at the equilibrium
    if abs(gamma) < 1.0 and abs(math.remainder(th - d, 2 * math.pi)) < 1e-6 and abs(v) < 1e-6:
        return 0.0
    k = math.floor((th - d) / (2 * math.pi)) + 1
    events.pars[:] = [beta, gamma, 1.0, 0.0]
    events.state[:] = plain.state
    events.time = L(0)
    times = []
    for j in range(3):
        events.pars[3] = L(d) + 2 * L(math.pi) * (k + j)
        events.propagate_until(L(1e4))
        if events.time >= L(1e4):
            # no revolution in 10⁴ time units: creeping onto the semi-stable equilibrium
            # of γ = ω² (the saddle-node), whose mean velocity is 0
            return 0.0
        times.append(events.time)
    return float(L(4) * L(math.pi) / (times[2] - times[0]))


def _ref_retrapping(integrators, beta, lo=0.0, hi=1.0, tol=1e-8):
    # γ_r: the saddle's unstable manifold reaches the next saddle (running) or turns back.
    _, events = integrators
    while hi - lo > tol:
        g = 0.5 * (lo + hi)
        theta_u = math.pi - math.asin(g)
        lam = -beta / 2 + math.sqrt(beta * beta / 4 + math.cos(math.asin(g)))
        eps = 1e-12
        events.pars[:] = [beta, g, 1.0, theta_u + 2 * math.pi]
        events.state[:] = [theta_u + eps, lam * eps]
        events.time = L(0)
        events.propagate_until(L(1e4))
        if float(events.state[0]) >= theta_u + 2 * math.pi - 1e-9:
            hi = g
        else:
            lo = g
    return 0.5 * (lo + hi)


@pytest.fixture(scope="module")
def curves():
    up_down = np.r_[np.linspace(0.0, 1.5, 16), np.linspace(1.5, 0.0, 16)]
    return {beta: junction.iv_curve(beta, up_down) for beta in (0.2, 2.0)}


@pytest.mark.parametrize("beta", [0.2, 2.0])
def test_mean_velocity_against_heyoka_long_double(curves, heyoka_ld, beta):
    c = curves[beta]
    for g, v, y0 in zip(c.gamma, c.mean_velocity, c.start_state):
        ref = _ref_mean_velocity(heyoka_ld, beta, g, y0)
        assert abs(v - ref) <= V_TOL, (g, v, ref)


def test_hysteresis_and_currents(curves, heyoka_ld):
    c = curves[0.2]
    up, down = c.branches()
    at = {g: i for i, g in enumerate(c.gamma[down])}
    # bistable at γ = 0.5: locked going up, running coming down
    assert c.regime[up][5] == "locked" and c.gamma[up][5] == 0.5
    assert c.regime[down][list(at).index(0.5)] == "running"
    # switching: the equilibrium disappears at γ = ω² = 1 (adiabatic bisection)
    assert abs(c.switching_current - 1.0) <= c.current_tol
    # retrapping: the homoclinic bifurcation, ≈ 0.252 at β = 0.2 (4β/π = 0.2546 to first order)
    ref = _ref_retrapping(heyoka_ld, 0.2, 0.2, 0.3)
    assert abs(c.retrapping_current - ref) <= c.current_tol
    assert 0.25 < ref < 0.2546
    # overdamped: no hysteresis, both currents at ω²
    o = curves[2.0]
    assert abs(o.switching_current - 1.0) <= o.current_tol
    assert abs(o.retrapping_current - 1.0) <= o.current_tol
    np.testing.assert_array_equal(o.regime[: 16], o.regime[16:][::-1])


def test_finer_current_tol(heyoka_ld):
    c = junction.iv_curve(0.2, [0.3, 0.2], current_tol=1e-6, theta_dot0=3.0)
    assert list(c.regime) == ["running", "locked"] and math.isnan(c.switching_current)
    assert abs(c.retrapping_current - _ref_retrapping(heyoka_ld, 0.2, 0.2, 0.3)) <= 1e-6


def test_results_csv_and_plot(curves, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    c = curves[0.2]
    path = tmp_path / "iv.csv"
    c.to_csv(path)
    rows = path.read_text().splitlines()
    assert rows[0].startswith("# beta=0.2") and rows[1] == "gamma,mean_velocity,regime,period"
    assert len(rows) == 2 + c.gamma.size and float(rows[2 + 20].split(",")[1]) == c.mean_velocity[20]
    ax = c.plot()
    assert len(ax.lines) >= 2


@pytest.mark.parametrize(
    "kw,match",
    [
        (dict(beta=0.0), "beta"),
        (dict(beta=-1.0), "beta"),
        (dict(gamma=[]), "gamma"),
        (dict(gamma=[0.1, math.nan]), "gamma"),
        (dict(omega=0.0), "omega"),
        (dict(current_tol=0.0), "current_tol"),
        (dict(theta0=math.inf), "theta0"),
    ],
)
def test_bad_input(kw, match):
    args = dict(beta=0.2, gamma=[0.1])
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        junction.iv_curve(**args)
