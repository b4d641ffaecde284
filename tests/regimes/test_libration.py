"""The libration regime (mbm.regimes, C1-C4): a conservative motion trapped in a well.

References: the period by mpmath at 60 digits (tests/data/libration_mpmath.py), the
motion by heyoka's Taylor method in long double at tol 1e-19 (tests/data/oracle_heyoka.py).
"""

import math
import sys
from pathlib import Path

import mpmath as mp
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm.core import controller, loop, record, window
from mbm import regimes

sys.path.insert(0, str(Path(__file__).parents[1] / "data"))
import libration_mpmath  # noqa: E402
import oracle_heyoka  # noqa: E402

SCENE = (mbm.Pendulum(0.0, 0.4), [0.9, 0.0])  # the long-horizon issue's libration


def _trapped(rng):
    # A random state trapped in a well of a random tilted potential (rejection sampling).
    while True:
        omega = float(rng.choice([0.5, 1.0, 2.0]))
        w2 = omega * omega
        gamma = float(rng.uniform(-0.9, 0.9) * w2)
        d = math.asin(gamma / w2)
        x = rng.uniform(-math.pi - 2 * d, math.pi - 2 * d)
        v = rng.uniform(-2.0, 2.0) * omega
        h = 0.5 * v * v + w2 * (math.cos(d) - math.cos(d + x)) - gamma * x
        barrier = min(2 * w2 * math.cos(d) - gamma * (math.pi - 2 * d),
                      2 * w2 * math.cos(d) + gamma * (math.pi + 2 * d))
        if 1e-3 * w2 < h < 0.98 * barrier:
            k = int(rng.integers(-3, 4))
            return gamma, omega, d + x + 2 * math.pi * k, v


def _taylor_run(gamma, omega, y0, T, t, tol, regimes_on):
    """The loop run by hand (mbm.solve's defaults, β = 0), with the switch on or off."""
    ap, kind, karg = mbm.frontends.solve.compiled(mbm.get_approximant("taylor"))
    p = record.new_run(record.RunModel(0.0, gamma, omega), record.RunState(0.0, y0[0], y0[1], T),
                       record.RunControl(kind, karg, controller.CONTROLLER_ADAPTIVE, -1.0, np.inf, np.inf, tol, tol,
                                         int(ap.error_order)), 10**7, regimes=regimes_on)
    out = np.full((2, t.size), np.nan)
    loop.run(p, t, out, np.empty(0), np.empty((0, 2)), np.empty((0, 0)), np.zeros(1, np.int64))
    return out, record.flat(p)[0]


@pytest.fixture(scope="module")
def heyoka_ref():
    if not oracle_heyoka.available():
        pytest.skip("the heyoka long-double oracle needs an 80-bit long double (x86-64); "
                    "numpy.longdouble is a double here")
    return oracle_heyoka.reference


# ---------------------------------------------------------------------------
# The period (C1, C2)
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("seed", range(12))
def test_period_against_mpmath(seed):
    # The double-double midpoint rule and its error estimate against 60 digits.
    gamma, omega, theta, v = _trapped(np.random.default_rng(700 + seed))
    t_hi, t_lo, dt, vmax, span = regimes.libration_period(gamma, omega, theta, v)
    ref = libration_mpmath.period_mp(gamma, omega, theta, v)
    assert ref is not None
    with mp.workdps(40):
        err = abs(mp.mpf(t_hi) + mp.mpf(t_lo) - ref)
    assert err <= dt
    assert dt <= 1e-24 * t_hi
    # The speed at the bottom θ* of the well, the angle's excursion.
    w2 = omega * omega
    d = math.asin(gamma / w2)
    bottom = d + 2 * math.pi * math.floor((theta + d + math.pi) / (2 * math.pi))
    drop = w2 * (math.cos(bottom) - math.cos(theta)) - gamma * (theta - bottom)
    assert vmax >= abs(v) and vmax == pytest.approx(math.sqrt(v * v + 2 * drop), rel=1e-9)
    assert 0.0 < span < 2 * math.pi


def test_period_of_the_small_oscillation_and_the_pendulum():
    # γ = 0: T = 4K(sin²(θ₀/2))/ω exactly; tiny amplitude: the linear 2π/ω_l.
    for theta0 in (0.3, 1.0, 2.5, 3.0):
        t_hi, t_lo, dt, _, _ = regimes.libration_period(0.0, 1.0, theta0, 0.0)
        with mp.workdps(40):
            ref = 4 * mp.ellipk(mp.sin(mp.mpf(theta0) / 2) ** 2)
            assert abs(mp.mpf(t_hi) + mp.mpf(t_lo) - ref) <= dt
    w2, gamma = 4.0, 1.0
    d = math.asin(gamma / w2)
    t_hi, _, _, _, _ = regimes.libration_period(gamma, 2.0, d + 1e-5, 0.0)
    assert t_hi == pytest.approx(2 * math.pi / math.sqrt(w2 * math.cos(d)), rel=1e-9)


def test_period_is_nan_where_there_is_no_libration():
    nan_cases = [
        (0.4, 1.0, 0.0, 3.0),  # above the barrier: a rotation
        (1.0, 1.0, 0.0, 0.1),  # |γ| = ω²: no well
        (-1.5, 1.0, 0.0, 0.0),  # |γ| > ω²
        (0.4, 1.0, math.asin(0.4), 0.0),  # at rest at the bottom
        (0.4, 1.0, math.asin(0.4) + 1e-8, 0.0),  # below LIBRATION_MIN_AMPLITUDE
        (0.4, 1.0, math.pi - math.asin(0.4), 0.0),  # on the saddle
    ]
    for gamma, omega, theta, v in nan_cases:
        assert math.isnan(regimes.libration_period(gamma, omega, theta, v)[0]), (gamma, theta, v)


@pytest.mark.parametrize("gap", [1e-3, 1e-6, 1e-9])
def test_period_near_the_separatrix_is_right_or_refused(gap):
    # Energy a fraction ``gap`` below the barrier (γ = 0: T = 4K(k²), k² → 1): the
    # quadrature either converges, within its δT, or returns nan (no switch).
    theta0 = 2 * math.asin(math.sqrt(1.0 - gap))
    t_hi, t_lo, dt, _, _ = regimes.libration_period(0.0, 1.0, theta0, 0.0)
    if math.isnan(t_hi):
        return
    with mp.workdps(40):
        ref = 4 * mp.ellipk(mp.sin(mp.mpf(theta0) / 2) ** 2)
        assert abs(mp.mpf(t_hi) + mp.mpf(t_lo) - ref) <= dt


# ---------------------------------------------------------------------------
# The switch in the loop (C3, C4): every path, the references, the cost
# ---------------------------------------------------------------------------


def test_every_path_gives_the_same_answer():
    model, y0 = SCENE
    T = 1000.0
    t = np.linspace(0.0, T, 201)
    kw = dict(rtol=1e-10, atol=1e-10)
    fast = mbm.solve(model, (0.0, T), y0, t_eval=t, **kw)
    t_hi = regimes.libration_period(0.4, 1.0, y0[0], y0[1])[0]
    assert fast.success and fast.regime == "libration" and fast.t_regime == 0.0
    assert fast.period == t_hi and fast.mean_velocity == 0.0
    ig = mbm.Integrator(model, **kw).solve((0.0, T), y0, t)
    batch = mbm.solve_batch([0.0, 0.1], [0.4, 1.2], 1.0, [y0, [0.0, 0.0]], (0.0, T), t, **kw)
    out = np.empty((2, t.size))
    status, nw = mbm.solve_njit(0.0, 0.4, 1.0, 0.0, y0[0], y0[1], T, t, out, 1e-10, 1e-10, 10**7)
    ivp1 = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, dense_output=True, **kw)
    ivpn = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, windows_per_step=None, **kw)
    for y in (ig.y, batch.y[0], out, ivp1.y, ivpn.y):
        np.testing.assert_array_equal(y, fast.y)
    assert status == 0 and nw == fast.n_windows == ig.n_windows == batch.n_windows[0]
    assert list(batch.regime) == ["libration", "running"]
    assert batch.period[0] == fast.period and batch.mean_velocity[0] == 0.0
    # The dense output: any t, as mbm.solve's output there.
    for tq in (0.37, 6.5, 512.25, 987.654):
        at = mbm.solve(model, (0.0, T), y0, t_eval=[tq], **kw)
        np.testing.assert_array_equal(ivp1.sol(tq), at.y[:, 0])
    # solve_ivp's contract on the one step to t_bound.
    solver = mbm.MBM(model, 0.0, y0, T, **kw)
    solver.step()
    assert solver.status == "finished" and solver.regime == "libration" and solver.t == T
    sol = solver.dense_output()
    np.testing.assert_array_equal(sol(0.0), y0)
    np.testing.assert_array_equal(sol(T), solver.y)
    assert solver.period == fast.period and solver.mean_velocity == 0.0


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("tol", [1e-8, 1e-12])
def test_random_librations_against_heyoka(heyoka_ref, seed, tol):
    # Within the first period the run is the ordinary one bit for bit (the same
    # windows); at every output, θ and θ' stay within the tolerance of the reference
    # however many periods have passed (the error is one period's, C3).
    gamma, omega, theta, v = _trapped(np.random.default_rng(900 + seed))
    y0 = [theta, v]
    T = 2000.0
    t = np.linspace(0.0, T, 401)
    on, p_on = _taylor_run(gamma, omega, y0, T, t, tol, 1)
    off, p_off = _taylor_run(gamma, omega, y0, T, t, tol, 0)
    assert p_on["status"] == 0 and p_off["status"] == 0 and p_off["regime"] == regimes.REGIME_NONE
    assert p_on["regime"] == regimes.REGIME_LIBRATION and p_on["t_regime"] == 0.0
    period = p_on["cyc_T"]
    first = t < 0.5 * period
    np.testing.assert_array_equal(on[:, first], off[:, first])
    ref = np.asarray(heyoka_ref(0.0, gamma, omega, y0, t), dtype=np.longdouble)
    e = np.abs((on[0] - ref[0]).astype(float)) / (tol + tol * np.abs(ref[0].astype(float)))
    ev = np.abs((on[1] - ref[1]).astype(float)) / (tol + tol * np.abs(ref[1].astype(float)))
    assert e.max() <= 1.0 and ev.max() <= 1.0


def test_the_issue_scene_at_2e4_and_the_cost_of_a_long_horizon(heyoka_ref):
    # Issue 13's target: at T = 2e4, rtol = atol = 1e-12, max|θ − θ_ref|/max(1, |θ_ref|)
    # ≤ 1e-11 (the ordinary run reached 2.0e-11); T = 1e6 takes the windows of T = 1e3.
    model, y0 = SCENE
    t = np.linspace(0.0, 2e4, 201)
    r = mbm.solve(model, (0.0, 2e4), y0, rtol=1e-12, atol=1e-12, t_eval=t)
    ref = np.asarray(heyoka_ref(0.0, 0.4, 1.0, y0, t), dtype=np.longdouble)
    err = np.abs((r.y[0] - ref[0]).astype(float)) / np.maximum(1.0, np.abs(ref[0].astype(float)))
    assert r.regime == "libration" and err.max() <= 1e-11
    n = {}
    for T in (1e3, 1e6):
        rr = mbm.solve(model, (0.0, T), y0, rtol=1e-10, atol=1e-10, t_eval=np.linspace(0.0, T, 201))
        assert rr.regime == "libration"
        n[T] = rr.n_windows
    assert n[1e6] == n[1e3]
    # The outputs after n periods repeat the first period's to the stored period's
    # precision: t = nT + s against s, n = 10⁵ (T's rounding to a double alone would
    # shift the phase by ~n·ulp(T)/2 ≈ 4e-11).
    p = regimes.libration_period(0.4, 1.0, y0[0], y0[1])
    s = 1.25
    with mp.workdps(40):
        tn = float(100000 * (mp.mpf(p[0]) + mp.mpf(p[1])) + s)
    far = mbm.solve(model, (0.0, 1e6), y0, rtol=1e-10, atol=1e-10, t_eval=[s, tn])
    assert far.regime == "libration"
    # tn is a rounded time (ulp 1.5e-10 near 7e5): the phase differs by its rounding.
    with mp.workdps(40):
        shift = float(mp.mpf(tn) - 100000 * (mp.mpf(p[0]) + mp.mpf(p[1])) - s)
    assert abs(far.y[0, 1] - far.y[0, 0] - far.y[1, 0] * shift) <= 1e-14


@pytest.mark.parametrize("case", ["short", "backwards", "damped", "fixed", "untrapped"])
def test_no_libration_where_it_does_not_apply(case):
    model, y0 = SCENE
    kw = dict(rtol=1e-10, atol=1e-10)
    span = (0.0, 1000.0)
    if case == "short":
        span = (0.0, 15 * 6.687)  # under LIBRATION_MIN_PERIODS periods
    elif case == "backwards":
        span = (0.0, -1000.0)
    elif case == "damped":
        model = mbm.Pendulum(1e-9, 0.4)  # β > 0: the locked regime's business, not this one
    elif case == "fixed":
        kw = dict(tau=0.1)
    elif case == "untrapped":
        y0, span = [0.0, 3.0], (0.0, 100.0)  # over the barrier: an accelerating rotation
    r = mbm.solve(model, span, y0, **kw)
    assert r.success and r.regime != "libration"
    assert math.isnan(r.period) or case == "damped"


def test_wound_start_and_wrapped_outputs(heyoka_ref):
    # A libration a thousand turns out: θ = 2π·1000 + φ held as its winding count.
    k = 1000
    y0 = [0.9 + 2 * math.pi * k, 0.0]
    model = SCENE[0]
    t = np.linspace(0.0, 3000.0, 301)
    kw = dict(rtol=1e-12, atol=1e-12, t_eval=t)
    r = mbm.solve(model, (0.0, 3000.0), y0, wrap=True, **kw)
    plain = mbm.solve(model, (0.0, 3000.0), y0, **kw)
    assert r.regime == plain.regime == "libration"
    assert np.all(r.winding == k) and np.all(np.abs(r.y[0]) <= math.pi)
    np.testing.assert_array_equal([window.theta_of(float(k), p) for p in r.y[0]], plain.y[0])
    np.testing.assert_array_equal(r.y[1], plain.y[1])
    ref = np.asarray(heyoka_ref(0.0, 0.4, 1.0, y0, t), dtype=np.longdouble)
    err = np.abs((plain.y - ref).astype(float)) / (1e-12 + 1e-12 * np.abs(ref.astype(float)))
    assert err.max() <= 1.0


def test_a_driven_conservative_run_takes_no_libration():
    # The drive breaks the energy's conservation: the period test is never made.
    model = mbm.Pendulum(0.0, 0.4, drive_amplitude=0.1, drive_frequency=0.7)
    r = mbm.solve(model, (0.0, 500.0), SCENE[1], rtol=1e-8, atol=1e-8)
    assert r.success and r.regime is None and math.isnan(r.period)
