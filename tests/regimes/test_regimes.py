"""Long-horizon regimes (mbm.regimes): the locked switch, its bound, every path.

The independent reference is heyoka's Taylor method in long double at tol 1e-19
(compiled once per module, β, γ, ω² as runtime parameters).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

import mbm
from mbm.core import controller, loop, record, window
from mbm import regimes

# Long-double reference tolerance: its eps (1.08e-19), so its error is far below
# every tolerance tested here.
REF_TOL = 1e-19
# Scaled errors (|err| / (atol + rtol·|θ_ref|)) of the run with the switch may exceed
# the same run without it by at most the switch's own share, SWITCH_SAFETY (L5), and
# this relative slack for the transient error the linear flow carries past the switch.
PROPAGATION_SLACK = 1.05
# The T = 1e6 / T = 1e3 window-count target of issue 13.
HORIZON_COST_RATIO = 3.0


@pytest.fixture(scope="module")
def heyoka_ref():
    import heyoka as hy  # the test extra's long-double oracle

    ld = np.longdouble
    if np.finfo(ld).eps > 1e-18:
        pytest.skip("numpy.longdouble is a double here")
    x, v = hy.make_vars("x", "v")
    sys = [(x, v), (v, hy.par[1] - hy.par[0] * v - hy.par[2] * hy.sin(x))]
    ta = hy.taylor_adaptive(sys, np.zeros(2, dtype=ld), tol=ld(REF_TOL), pars=np.zeros(3, dtype=ld),
                            fp_type=ld)

    def reference(beta, gamma, omega, y0, t):
        tt = np.asarray(t, dtype=ld)
        ta.time = tt[0]
        ta.state[0], ta.state[1] = ld(y0[0]), ld(y0[1])
        ta.pars[0], ta.pars[1], ta.pars[2] = ld(beta), ld(gamma), ld(omega) * ld(omega)
        outcome, *_, out = ta.propagate_grid(tt, max_delta_t=ld(np.inf))
        assert outcome == hy.taylor_outcome.time_limit
        return np.asarray(out).T

    return reference


def _taylor_run(beta, gamma, omega, y0, T, t, tol, regimes_on):
    """The loop run by hand (mbm.solve's defaults), with the switch on or off."""
    ap, kind, karg = mbm.frontends.solve.compiled(mbm.get_approximant("taylor"))
    p = record.new_run(record.RunModel(beta, gamma, omega), record.RunState(0.0, y0[0], y0[1], T),
                       record.RunControl(kind, karg, controller.CONTROLLER_ADAPTIVE, -1.0, np.inf, np.inf, tol, tol,
                                         int(ap.error_order)), 10**7, regimes=regimes_on)
    out = np.full((2, t.size), np.nan)
    loop.run(p, t, out, np.empty(0), np.empty((0, 2)), np.empty((0, 0)), np.zeros(1, np.int64))
    return out, record.flat(p)[0]


# ---------------------------------------------------------------------------
# The kernels: closed form (L2), Green's function bounds (L4), the bound (L3–L4)
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("beta,wl2", [(0.1, 1.0), (1.0, 0.9), (2.0, 1.0), (2.0 + 1e-9, 1.0),
                                      (2.0 - 1e-9, 1.0), (3.0, 0.5), (0.05, 4.0)])
def test_locked_eval_is_the_linear_oscillator(beta, wl2):
    # Under-, critically (to 1e-9) and over-damped: the matrix exponential of the
    # linear system x'' + βx' + ω_l² x = 0.
    theta_star, x0, v0 = 0.3, 1e-3, -2e-3
    coef = regimes.locked_coef(beta, wl2, theta_star, theta_star + x0, v0)
    m = np.array([[0.0, 1.0], [-wl2, -beta]])
    for t in (0.0, 0.5, 3.0, 17.0, 60.0):
        xe = expm(m * t) @ np.array([coef[2], v0])
        th, v = regimes.locked_eval(coef, t)
        assert abs((th - theta_star) - xe[0]) <= 1e-12 * (abs(x0) + abs(v0))
        assert abs(v - xe[1]) <= 1e-12 * (abs(x0) + abs(v0))
    # The window's start is its anchor bit for bit.
    assert regimes.locked_eval(coef, 0.0) == (theta_star + x0, v0)


@pytest.mark.parametrize("beta,wl2", [(0.1, 1.0), (0.5, 0.3), (1.99, 1.0), (2.0, 1.0), (2.5, 1.0),
                                      (3.0, 0.2)])
def test_green_integrals_bound_the_greens_function(beta, wl2):
    # G₀ ≥ ∫|g|, G₁ ≥ ∫|g'| (measured on a fine grid to where g has decayed), and the
    # bounds are not vacuous (within a factor 4).
    g0, g1 = regimes.green_integrals(beta, wl2)
    s2 = wl2 - beta * beta / 4.0
    lam = max(beta / 2.0 - math.sqrt(max(-s2, 0.0)), 1e-3)
    t = np.linspace(0.0, 40.0 / lam, 400001)
    coef = regimes.locked_coef(beta, wl2, 0.0, 0.0, 1.0)  # x(0) = 0, x'(0) = 1: x = g
    g, gd = np.empty_like(t), np.empty_like(t)
    regimes.locked_eval_array(coef, t, g, gd)
    i0, i1 = np.trapezoid(np.abs(g), t), np.trapezoid(np.abs(gd), t)
    assert i0 <= g0 * (1 + 1e-6) and i1 <= g1 * (1 + 1e-6)
    assert g0 <= 4.0 * i0 and g1 <= 4.0 * i1


@pytest.mark.parametrize("seed", range(6))
def test_locked_bound_holds_against_heyoka(heyoka_ref, seed):
    # From states of moderate amplitude (the bound ~1e-6 to 1e-2: measurable), the
    # exact motion stays within the bound of the linear closed form for a long time.
    rng = np.random.default_rng(seed)
    beta = rng.uniform(0.05, 3.0)
    omega = rng.choice([0.5, 1.0, 2.0])
    gamma = rng.uniform(-0.9, 0.9) * omega**2
    d, wl2, g0, g1 = regimes.locked_constants(beta, gamma, omega)
    amp = rng.uniform(0.02, 0.3)
    phase = rng.uniform(0.0, 2 * np.pi)
    k = rng.integers(-3, 4)
    y0 = (d + 2 * np.pi * k + amp * math.cos(phase), amp * math.sqrt(wl2) * math.sin(phase))
    ts, bt, bv = regimes.locked_bound(beta, gamma, omega, y0[0], y0[1], regimes.locked.Well(d, wl2, g0, g1))
    assert math.isfinite(bt) and ts == d + 2 * np.pi * k
    t = np.linspace(0.0, 50.0 / beta + 50.0, 2001)
    ref = heyoka_ref(beta, gamma, omega, y0, t)
    coef = regimes.locked_coef(beta, wl2, ts, y0[0], y0[1])
    th, v = np.empty_like(t), np.empty_like(t)
    regimes.locked_eval_array(coef, t, th, v)
    assert np.max(np.abs((th - ref[0]).astype(float))) <= bt
    assert np.max(np.abs((v - ref[1]).astype(float))) <= bv


@pytest.mark.parametrize("seed", range(8))
def test_second_order_form_and_its_bound_against_heyoka(heyoka_ref, seed):
    # (L6, L7) Under-damped, weak damping included (where L4's G₀ ~ 1/β): from states
    # whose second-order bound is measurable (1e-10 to 1e-4) the exact motion stays
    # within it of x_lin + x₂ over many decay times, and the second-order form is far
    # closer than the linear one (the neglected terms are cubic, not quadratic).
    rng = np.random.default_rng(500 + seed)
    beta = rng.choice([0.01, 0.03, 0.2, 1.0]) * rng.uniform(0.8, 1.2)
    omega = rng.choice([0.5, 1.0, 2.0])
    gamma = rng.uniform(-0.9, 0.9) * omega**2
    d, wl2, g0, g1 = regimes.locked_constants(beta, gamma, omega)
    amp = rng.uniform(2e-3, 2e-2)
    phase = rng.uniform(0.0, 2 * np.pi)
    k = rng.integers(-3, 4)
    y0 = (d + 2 * np.pi * k + amp * math.cos(phase), amp * math.sqrt(wl2) * math.sin(phase))
    ts, a_bound = regimes.locked_amplitude(gamma, omega, y0[0], y0[1], d)
    bt, bv = regimes.locked2_bound(beta, gamma, omega, regimes.locked.Well(d, wl2, g0, g1), a_bound, y0[0] - ts,
                                   y0[1])
    assert math.isfinite(bt) and math.isfinite(bv)
    t = np.linspace(0.0, 30.0 / beta + 50.0, 3001)
    ref = heyoka_ref(beta, gamma, omega, y0, t)
    th, v = np.empty_like(t), np.empty_like(t)
    regimes.locked_eval_array(regimes.locked_coef(beta, wl2, ts, y0[0], y0[1], gamma, 2), t, th, v)
    e2 = np.max(np.abs((th - ref[0]).astype(float)))
    assert e2 <= bt
    assert np.max(np.abs((v - ref[1]).astype(float))) <= bv
    th1, v1 = np.empty_like(t), np.empty_like(t)
    regimes.locked_eval_array(regimes.locked_coef(beta, wl2, ts, y0[0], y0[1]), t, th1, v1)
    e1 = np.max(np.abs((th1 - ref[0]).astype(float)))
    if abs(gamma) > 0.1 * omega**2:  # a quadratic term to remove
        assert e2 <= 0.2 * e1


def test_second_order_coef_layout_and_anchor():
    beta, gamma, omega = 0.02, 0.4, 1.0
    d, wl2, g0, g1 = regimes.locked_constants(beta, gamma, omega)
    c = regimes.locked_coef(beta, wl2, d, d + 1e-3, -2e-3, gamma, 2)
    assert c.size == regimes.LOCKED2_WIDTH and c[0] == regimes.LOCKED_TAG and c[7] == 2.0
    assert regimes.locked_eval(c, 0.0) == regimes.locked_eval(regimes.locked_coef(beta, wl2, d, d + 1e-3, -2e-3),
                                                                0.0)
    # Zero-padded first-order vector (a window store row) reads as first order.
    c1 = np.zeros(regimes.LOCKED2_WIDTH)
    c1[:regimes.LOCKED_WIDTH] = regimes.locked_coef(beta, wl2, d, d + 1e-3, -2e-3)
    assert regimes.locked_eval(c1, 3.0) == regimes.locked_eval(c1[:regimes.LOCKED_WIDTH], 3.0)
    # x₂ solves x₂'' + βx₂' + ω_l² x₂ = (γ/2) x_lin² from rest: central differences
    # (an amplitude where x₂ ~ 1e-4 stands well above the differences' rounding).
    c = regimes.locked_coef(beta, wl2, d, d + 0.05, -0.02, gamma, 2)
    h = 1e-3
    for t in (0.7, 5.0, 40.0):
        x = [regimes.locked_eval(c, t + j * h)[0] - regimes.locked_eval(c[:regimes.LOCKED_WIDTH], t + j * h)[0]
             for j in (-1, 0, 1)]
        xl = regimes.locked_eval(c[:regimes.LOCKED_WIDTH], t)[0] - d
        res = (x[2] - 2 * x[1] + x[0]) / h**2 + beta * (x[2] - x[0]) / (2 * h) + wl2 * x[1] - 0.5 * gamma * xl**2
        assert abs(res) <= 1e-5 * abs(0.5 * gamma * xl**2) + 1e-9


def test_second_order_switches_earlier_on_weak_damping():
    # P4 (β = 0.01, γ = 0.3): the first-order bound needs A ~ 1e-6, the second ~ 1e-4.
    model = mbm.Pendulum(0.01, 0.3)
    kw = dict(rtol=1e-10, atol=1e-10)
    r = mbm.solve(model, (0.0, 1e4), [1.0, 0.0], t_eval=np.linspace(0.0, 1e4, 201), **kw)
    d, wl2, g0, g1 = regimes.locked_constants(0.01, 0.3, 1.0)
    assert r.regime == "locked" and r.t_regime < 2200.0
    ends = mbm.solve(model, (0.0, 1e4), [1.0, 0.0], **kw)
    tols = regimes.common.Tolerance(1e-10, 1e-10)
    order, ts = regimes.locked_choice(0.01, 0.3, 1.0, ends.y[0, -2], ends.y[1, -2], _lock(d, wl2, g0, g1, True),
                                      tols, 0.0)
    assert order == 2
    # Without room for the second-order vector the first-order switch only.
    assert regimes.locked_choice(0.01, 0.3, 1.0, ends.y[0, -2], ends.y[1, -2], _lock(d, wl2, g0, g1, False), tols,
                                 0.0)[0] == 0


def _lock(d, wl2, g0, g1, second):
    # A LockSetup for locked_choice (it reads d, ω_l², G₀, G₁ and can_lock2 only).
    return regimes.locked.LockSetup(d, wl2, g0, g1, 0.0, 0.0, second)


def test_locked_bound_is_infinite_where_the_motion_is_not_trapped():
    beta, gamma, omega = 0.1, 0.5, 1.0
    d, wl2, g0, g1 = regimes.locked_constants(beta, gamma, omega)
    inf = math.inf
    # At the saddle θ = π − d (H = barrier), and above the lower barrier.
    assert regimes.locked_bound(beta, gamma, omega, math.pi - d, 0.0, regimes.locked.Well(d, wl2, g0, g1))[1] == inf
    assert regimes.locked_bound(beta, gamma, omega, d, 1.5, regimes.locked.Well(d, wl2, g0, g1))[1] == inf
    # Near the bifurcation γ → ω² the well is shallow: a tiny amplitude is already large.
    gb = 0.999
    db, wlb, g0b, g1b = regimes.locked_constants(beta, gb, omega)
    assert regimes.locked_bound(beta, gb, omega, db + 0.05, 0.0, regimes.locked.Well(db, wlb, g0b, g1b))[1] > 1e-2
    assert regimes.locked_bound(beta, gb, omega, db + 0.1, 0.0, regimes.locked.Well(db, wlb, g0b, g1b))[1] == inf
    small = regimes.locked_bound(beta, gamma, omega, d + 1e-4, 0.0, regimes.locked.Well(d, wl2, g0, g1))[1]
    near = regimes.locked_bound(beta, gb, omega, db + 1e-4, 0.0, regimes.locked.Well(db, wlb, g0b, g1b))[1]
    assert near > 5.0 * small


def _bisected_amplitude(w2, gamma, d, h0, edge):
    # The plain bisection of U = H₀ between 0 and the saddle (item L3), kept where U ≥ H₀.
    lo, hi = 0.0, edge
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if regimes._potential(w2, gamma, d, mid) >= h0:
            hi = mid
        else:
            lo = mid
    return hi


@pytest.mark.parametrize("seed", range(4))
def test_newton_amplitude_is_certified_and_tight(seed):
    # (L3): the amplitude from Newton is a point where U ≥ H₀ (so above the root A±,
    # U being monotone there), within 1e-7 of the root found by bisection.
    rng = np.random.default_rng(seed)
    checked = 0
    for _ in range(500):
        omega = rng.uniform(0.2, 5.0)
        w2 = omega * omega
        gamma = rng.uniform(-0.999, 0.999) * w2
        d = math.asin(gamma / w2)
        wl2 = w2 * math.cos(d)
        x = rng.uniform(-1.0, 1.0) * 10 ** rng.uniform(-8, 0.5)
        v = rng.uniform(-1.0, 1.0) * omega * 10 ** rng.uniform(-8, 0.5)
        h0 = 0.5 * v * v + regimes._potential(w2, gamma, d, x)
        for edge in (math.pi - 2 * d, -math.pi - 2 * d):
            if h0 >= regimes._potential(w2, gamma, d, edge):
                continue
            a = regimes._amplitude_newton(w2, gamma, d, wl2, h0, edge)
            if not math.isfinite(a):
                continue  # bisection takes over in locked_bound
            checked += 1
            root = _bisected_amplitude(w2, gamma, d, h0, edge)
            assert 0.0 <= a / edge < 1.0
            assert regimes._potential(w2, gamma, d, a) >= h0
            assert abs(a - root) <= 1e-7 * abs(root) + abs(edge) * 2.0**-190  # bisection's floor
    assert checked > 500


def test_section_is_the_saddle_so_a_libration_does_no_section_work():
    # (R1): a damped libration through θ = 0 never reaches the saddle level, so the
    # return map records no crossing; a running scene still reaches its cycle.
    assert regimes.section_offset(0.0, 1.0) == math.pi
    assert regimes.section_offset(0.5, 1.0) == math.pi - math.asin(0.5)
    assert regimes.section_offset(3.0, 1.0) == math.pi / 2  # |γ| > ω²: clamped
    model = mbm.Pendulum(0.05, 0.2)
    p = record.new_run(record.RunModel(*model.params), record.RunState(0.0, 1.0, 0.0, 200.0),
                       record.RunControl(window.KIND_TAYLOR, 24, controller.CONTROLLER_ADAPTIVE, -1.0, math.inf,
                                         math.inf, 1e-9, 1e-9, 24), 10**7)
    loop.run(p, np.empty(0), np.empty((2, 0)), np.empty(0), np.empty((0, 2)),
             np.empty((0, 0)), np.zeros(1, dtype=np.int64))
    rec = record.flat(p)[0]
    assert rec["status"] == 0 and rec["n_windows"] > 50
    assert rec["sec_n"] == 0
    r = mbm.solve(mbm.Pendulum(0.1, 1.2), (0.0, 2000.0), [0.0, 0.0], rtol=1e-9, atol=1e-9)
    assert r.regime == "running" and abs(r.mean_velocity - 2 * np.pi / r.period) == 0.0


# ---------------------------------------------------------------------------
# The switch in the loop: every path, the reference, the cost
# ---------------------------------------------------------------------------

LOCKED_SCENE = (mbm.Pendulum(0.3, 0.5), [2.0, 0.0])


def test_every_path_gives_the_same_answer_and_regime():
    model, y0 = LOCKED_SCENE
    T = 1000.0
    t = np.linspace(0.0, T, 201)
    kw = dict(rtol=1e-10, atol=1e-10)
    fast = mbm.solve(model, (0.0, T), y0, t_eval=t, **kw)
    assert fast.success and fast.regime == "locked" and 0.0 < fast.t_regime < 200.0
    ig = mbm.Integrator(model, **kw).solve((0.0, T), y0, t)
    batch = mbm.solve_batch([0.3, 0.1], [0.5, 1.2], 1.0, [y0, [0.0, 0.0]], (0.0, T), t, **kw)
    out = np.empty((2, t.size))
    status, nw = mbm.solve_njit(0.3, 0.5, 1.0, 0.0, y0[0], y0[1], T, t, out, 1e-10, 1e-10, 10**7)
    ivp1 = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, dense_output=True, **kw)
    ivpn = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, windows_per_step=None, **kw)
    for y in (ig.y, batch.y[0], out, ivp1.y, ivpn.y):
        np.testing.assert_array_equal(y, fast.y)
    assert status == 0 and nw == fast.n_windows == ig.n_windows == batch.n_windows[0]
    assert ig.regime == "locked" and ig.t_regime == fast.t_regime
    assert list(batch.regime) == ["locked", "running"]
    assert batch.t_regime[0] == fast.t_regime and np.isnan(batch.period[0])
    # The dense output beyond the switch is the closed form, at any t.
    d, wl2, g0, g1 = regimes.locked_constants(0.3, 0.5, 1.0)
    ends = mbm.solve(model, (0.0, T), y0, **kw)
    assert ends.t[-2] == fast.t_regime and ends.t[-1] == T
    order, ts = regimes.locked_choice(0.3, 0.5, 1.0, ends.y[0, -2], ends.y[1, -2], _lock(d, wl2, g0, g1, True),
                                      regimes.common.Tolerance(kw["rtol"], kw["atol"]), 0.0)
    assert order in (1, 2) and ts == d
    coef = regimes.locked_coef(0.3, wl2, d, ends.y[0, -2], ends.y[1, -2], 0.5, order)
    for tq in (fast.t_regime + 0.37, 512.25, T):
        np.testing.assert_array_equal(ivp1.sol(tq), regimes.locked_eval(coef, tq - fast.t_regime))
    # One solve_ivp step past the switch, ending at t_bound on the closed form.
    solver = mbm.MBM(model, 0.0, y0, T, **kw)
    while solver.status == "running":
        solver.step()
    assert solver.regime == "locked" and solver.t_regime == fast.t_regime
    assert solver.t_old == fast.t_regime and solver.t == T
    np.testing.assert_array_equal(solver.y, ends.y[:, -1])


@pytest.mark.parametrize("seed", range(10))
@pytest.mark.parametrize("tol", [1e-8, 1e-12])
def test_random_locked_scenes_against_heyoka(heyoka_ref, seed, tol):
    # Before the switch the run is the run without it, bit for bit; after it, the
    # scaled error exceeds the unswitched run's worst by at most the switch's share.
    rng = np.random.default_rng(100 + seed)
    beta = rng.uniform(0.05, 3.0)
    omega = rng.choice([0.5, 1.0, 2.0])
    gamma = rng.uniform(-0.9, 0.9) * omega**2
    y0 = np.array([rng.uniform(-3.0, 3.0), rng.uniform(-2.0, 2.0) * omega])
    T = max(300.0, 60.0 / beta)
    t = np.linspace(0.0, T, 201)
    on, p_on = _taylor_run(beta, gamma, omega, y0, T, t, tol, 1)
    off, p_off = _taylor_run(beta, gamma, omega, y0, T, t, tol, 0)
    assert p_on["status"] == 0 and p_off["status"] == 0 and p_off["regime"] == regimes.REGIME_NONE
    ref = heyoka_ref(beta, gamma, omega, y0, t)
    after = t > p_on["t_regime"] if p_on["regime"] == regimes.REGIME_LOCKED else np.zeros(t.size, bool)
    np.testing.assert_array_equal(on[:, ~after], off[:, ~after])
    scale = tol + tol * np.abs(ref[0].astype(float))
    e_on = np.abs((on[0] - ref[0]).astype(float)) / scale
    e_off = np.abs((off[0] - ref[0]).astype(float)) / scale
    v_on = np.abs((on[1] - ref[1]).astype(float)) / tol
    v_off = np.abs((off[1] - ref[1]).astype(float)) / tol
    if after.any():
        assert e_on[after].max() <= PROPAGATION_SLACK * e_off.max() + regimes.SWITCH_SAFETY
        assert v_on[after].max() <= PROPAGATION_SLACK * v_off.max() + regimes.SWITCH_SAFETY
        assert p_on["n_windows"] <= p_off["n_windows"]


@pytest.mark.parametrize("beta,gamma,y0", [(0.4, 0.0, [0.0, 0.25]), (0.3, 0.5, [2.0, 0.0]),
                                           (0.05, -0.3, [-1.2, 0.2]), (2.5, 0.2, [1.0, 0.0])])
def test_windows_do_not_grow_with_the_horizon(beta, gamma, y0):
    # Issue 13's target: T = 1e6 costs at most 3× T = 1e3 (201 outputs, rtol = atol
    # = 1e-10), counted in windows, through mbm.solve and through solve_ivp's MBM.
    model = mbm.Pendulum(beta, gamma)
    kw = dict(rtol=1e-10, atol=1e-10)
    n = {}
    for T in (1e3, 1e6):
        r = mbm.solve(model, (0.0, T), y0, t_eval=np.linspace(0.0, T, 201), **kw)
        assert r.success and (r.regime == "locked" or T < 1e6)
        solver = mbm.MBM(model, 0.0, y0, T, **kw)
        while solver.status == "running":
            solver.step()
        assert solver.status == "finished" and solver.n_windows == r.n_windows
        n[T] = r.n_windows
        d = math.asin(gamma)
        assert abs(r.y[0, -1] - d - 2 * np.pi * round((r.y[0, -1] - d) / (2 * np.pi))) < 1e-10
    assert n[1e6] <= HORIZON_COST_RATIO * n[1e3]


def test_no_early_switch_near_the_saddle_or_the_bifurcation(heyoka_ref):
    # Started just below the saddle θ = π − d, or with γ near ω², the switch waits
    # until the amplitude is small; the outputs stay within tolerance of heyoka.
    kw = dict(rtol=1e-10, atol=1e-10)
    for beta, gamma, y0, T in ((0.2, 0.5, [math.pi - math.asin(0.5) - 1e-6, 0.0], 600.0),
                               (0.2, 0.99, [math.asin(0.99) + 0.05, 0.0], 600.0)):
        model = mbm.Pendulum(beta, gamma)
        d, wl2, g0, g1 = regimes.locked_constants(beta, gamma, 1.0)
        assert regimes.locked_bound(beta, gamma, 1.0, y0[0], y0[1], regimes.locked.Well(d, wl2, g0, g1))[1] > 1e-3
        ends = mbm.solve(model, (0.0, T), y0, **kw)
        assert ends.regime == "locked"
        x = ends.y[0, -2] - d - 2 * np.pi * round((ends.y[0, -2] - d) / (2 * np.pi))
        # Small against the ~2.6 rad to the saddle (the second-order form, L6, takes over
        # at ~1e-4 here, the first-order one at ~1e-6), and the switch the rule's own.
        assert abs(x) < 1e-3 and ends.t[-2] == ends.t_regime
        order, _ = regimes.locked_choice(beta, gamma, 1.0, ends.y[0, -2], ends.y[1, -2], _lock(d, wl2, g0, g1, True),
                                         regimes.common.Tolerance(kw["rtol"], kw["atol"]), 0.0)
        assert order > 0
        t = np.linspace(0.0, T, 201)
        r = mbm.solve(model, (0.0, T), y0, t_eval=t, **kw)
        _, p_off = _taylor_run(beta, gamma, 1.0, np.array(y0), T, t, 1e-10, 0)
        ref = heyoka_ref(beta, gamma, 1.0, y0, t)
        after = t > r.t_regime
        assert np.max(np.abs((r.y[0, after] - ref[0, after]).astype(float))) < 1e-8


def test_never_locks_while_running_and_never_switches_backwards():
    # The bistable band (4β/π < γ < ω²): a running start keeps running (and may switch
    # to the running cycle, never to "locked"); a run backwards in time never switches
    # (the flow expands there).
    r = mbm.solve(mbm.Pendulum(0.1, 0.5), (0.0, 1000.0), [0.0, 3.0], rtol=1e-10, atol=1e-10,
                  t_eval=np.linspace(0.0, 1000.0, 11))
    assert r.success and r.regime == "running" and r.y[0, -1] > 100.0
    b = mbm.solve(mbm.Pendulum(0.3, 0.5), (0.0, -50.0), [math.asin(0.5) + 1e-9, 0.0], rtol=1e-10,
                  atol=1e-10)
    assert b.regime is None


# ---------------------------------------------------------------------------
# The running cycle (R1-R3)
# ---------------------------------------------------------------------------

# At rtol = atol = 1e-12 the stored period repeats its rounding (a few ulps of the
# crossing times) in every later period: θ' (whose scale is the smaller) may then
# exceed its tolerance by up to this factor over ~1000 periods; θ stays within it.
CYCLE_V_FACTOR = 20.0
RUNNING_SCENE = (mbm.Pendulum(0.1, 1.2), [0.0, 0.0])


def test_running_cycle_every_path_gives_the_same_answer():
    model, y0 = RUNNING_SCENE
    T = 1000.0
    t = np.linspace(0.0, T, 201)
    kw = dict(rtol=1e-10, atol=1e-10)
    fast = mbm.solve(model, (0.0, T), y0, t_eval=t, **kw)
    assert fast.success and fast.regime == "running" and 0.0 < fast.t_regime < 600.0
    assert fast.mean_velocity * fast.period == pytest.approx(2 * np.pi, rel=1e-15)
    ig = mbm.Integrator(model, **kw).solve((0.0, T), y0, t)
    batch = mbm.solve_batch(0.1, 1.2, 1.0, y0, (0.0, T), t, **kw)
    out = np.empty((2, t.size))
    status, nw = mbm.solve_njit(0.1, 1.2, 1.0, 0.0, y0[0], y0[1], T, t, out, 1e-10, 1e-10, 10**7)
    ivp1 = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, dense_output=True, **kw)
    ivpn = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, windows_per_step=None, **kw)
    for y in (ig.y, batch.y[0], out, ivp1.y, ivpn.y):
        np.testing.assert_array_equal(y, fast.y)
    assert status == 0 and nw == fast.n_windows == batch.n_windows[0]
    assert batch.period[0] == fast.period and batch.mean_velocity[0] == fast.mean_velocity
    # The dense output beyond the switch: any t, as mbm.solve's output there.
    for tq in (fast.t_regime + 0.37, 512.25, 987.654):
        at = mbm.solve(model, (0.0, T), y0, t_eval=[tq], **kw)
        np.testing.assert_array_equal(ivp1.sol(tq), at.y[:, 0])
    solver = mbm.MBM(model, 0.0, y0, T, **kw)
    while solver.status == "running":
        solver.step()
    assert solver.regime == "running" and solver.t_old == fast.t_regime and solver.t == T
    assert solver.period == fast.period


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("tol", [1e-8, 1e-12])
def test_random_running_scenes_against_heyoka(heyoka_ref, seed, tol):
    # Torque above ω² (every start runs): before the switch the run is the run without
    # it, bit for bit; after it θ stays within its tolerance, θ' within CYCLE_V_FACTOR.
    rng = np.random.default_rng(200 + seed)
    beta = rng.uniform(0.05, 1.0)
    omega = rng.choice([0.5, 1.0, 2.0])
    gamma = rng.choice([-1.0, 1.0]) * rng.uniform(1.05, 3.0) * omega**2
    y0 = np.array([rng.uniform(-3.0, 3.0), rng.uniform(-2.0, 2.0) * omega])
    T = max(500.0, 60.0 / beta)
    t = np.linspace(0.0, T, 201)
    on, p_on = _taylor_run(beta, gamma, omega, y0, T, t, tol, 1)
    off, p_off = _taylor_run(beta, gamma, omega, y0, T, t, tol, 0)
    assert p_on["status"] == 0 and p_off["status"] == 0
    if p_on["regime"] == regimes.REGIME_NONE:
        # A slow cycle (ω = 0.5 near the saddle-node) not converged and averaged by T.
        np.testing.assert_array_equal(on, off)
        return
    assert p_on["regime"] == regimes.REGIME_RUNNING
    after = t > p_on["t_regime"]
    np.testing.assert_array_equal(on[:, ~after], off[:, ~after])
    ref = heyoka_ref(beta, gamma, omega, y0, t)
    e = np.abs((on[0] - ref[0]).astype(float)) / (tol + tol * np.abs(ref[0].astype(float)))
    ev = np.abs((on[1] - ref[1]).astype(float)) / (tol + tol * np.abs(ref[1].astype(float)))
    assert e.max() <= 1.0
    assert ev.max() <= CYCLE_V_FACTOR
    assert p_on["n_windows"] < p_off["n_windows"]


@pytest.mark.parametrize("beta,gamma,y0", [(0.1, 1.2, [0.0, 0.0]), (0.1, 0.5, [0.0, 3.0]),
                                           (0.5, -2.0, [1.0, 0.0])])
def test_running_windows_do_not_grow_with_the_horizon(beta, gamma, y0):
    # T = 1e6 takes at most 3× the windows of T = 1e3 (each output past the switch
    # re-takes at most one period of windows, whatever the horizon).
    model = mbm.Pendulum(beta, gamma)
    kw = dict(rtol=1e-10, atol=1e-10)
    n = {}
    for T in (1e3, 1e6):
        r = mbm.solve(model, (0.0, T), y0, t_eval=np.linspace(0.0, T, 201), **kw)
        assert r.success and r.regime == "running"
        n[T] = r.n_windows
    assert n[1e6] <= HORIZON_COST_RATIO * n[1e3]
    assert r.mean_velocity == pytest.approx((r.y[0, -1] - r.y[0, -2]) / (r.t[-1] - r.t[-2]), rel=1e-3)


@pytest.mark.parametrize("seed", range(4))
def test_quick_rejection_never_refuses_a_state_the_full_test_takes(seed):
    # States around the lock threshold (both stages of the quick test and the full one
    # decide there), in wells far from θ = 0 as after many turns: wherever the full test
    # (locked_choice) switches, the quick test must let it run; and its energy stage
    # must spare most failing full tests there (their Newton steps are its point).
    rng = np.random.default_rng(seed)
    lk = regimes.locked
    passed = spared = failed = 0
    for _ in range(4000):
        beta, gamma, omega = rng.uniform(0.02, 1.0), rng.uniform(-0.95, 0.95), rng.uniform(0.5, 2.0)
        tol = 10.0 ** rng.uniform(-12, -4)
        setup = lk._lock_setup.py_func(beta, gamma * omega**2, omega, True, True)
        d, wl2, g0, g1, sd, q2, two = setup
        k = float(rng.integers(-10**6, 10**6)) if rng.uniform() < 0.3 else 0.0
        off = 2.0 * math.pi * k
        amp = 10.0 ** rng.uniform(0.5 * math.log10(tol) - 1.5, math.log10(tol) / 3.0 + 0.5)
        phase = rng.uniform(0.0, 2.0 * math.pi)
        x, v = amp * math.cos(phase), amp * math.sqrt(wl2) * math.sin(phase)
        y0 = d + x
        tols = regimes.common.Tolerance(tol, tol)
        order, _ = lk.locked_choice.py_func(beta, gamma * omega**2, omega, y0, v, setup, tols, off)
        reject = lk.locked_quick_reject.py_func(off + y0, v, setup, omega, tols)
        a, tol_t = lk.QUICK_FACTOR * math.sqrt(x * x + v * v / wl2), regimes.SWITCH_SAFETY * (tol + tol * abs(off + d))
        first_stage = omega**2 * lk._rho(sd, a) * g0 > tol_t and not (q2 > 0.0 and q2 * a**3 <= tol_t)
        if order > 0:
            passed += 1
            assert not reject, (beta, gamma, omega, tol, k, x, v)
        elif not first_stage:
            failed += 1
            spared += reject
    assert passed > 100 and failed > 100, (passed, failed)
    assert spared > 0.5 * failed, (spared, failed)


def _first_stage_rejects(lk, theta, v, d, sd, wl2, g0, omega, tol, q2):
    # locked_quick_reject's first stage, as it forms it (quotients, _nearest_k).
    k = lk._nearest_k.py_func(theta, d)
    ts = d + 2.0 * math.pi * k
    x = theta - ts
    a = lk.QUICK_FACTOR * math.sqrt(x * x + v * v / wl2)
    tol_t = regimes.SWITCH_SAFETY * (tol + tol * abs(ts))
    return omega * omega * lk._rho.py_func(sd, a) * g0 > tol_t and not (q2 > 0.0 and q2 * a**3 <= tol_t)


def _threshold_amplitude(lk, d, sd, wl2, g0, omega, tol, q2, k):
    # The linear amplitude (x alone, v = 0) where the first stage's test turns, by bisection.
    lo, hi = 0.0, 3.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        theta = d + 2.0 * math.pi * k + mid
        lo, hi = (lo, mid) if _first_stage_rejects(lk, theta, 0.0, d, sd, wl2, g0, omega, tol, q2) else (mid, hi)
    return hi


@pytest.mark.parametrize("seed", range(4))
def test_far_pretest_rejects_only_where_the_quick_test_rejects(seed):
    # locked_far runs before locked_quick_reject on every window: wherever it answers
    # True, the quick test's first stage must answer True too (so the windows stay bit
    # for bit), at that stage's threshold (amplitudes a few ulps either side), in wells
    # far from θ = 0, and on a saddle's level (θ − d an odd multiple of π, where a
    # product and a quotient may choose different wells); and it must take most of the
    # first stage's rejections away from the threshold (its point).
    rng = np.random.default_rng(100 + seed)
    lk = regimes.locked
    far_count = first_count = 0
    for _ in range(3000):
        beta, gamma, omega = rng.uniform(0.02, 1.0), rng.uniform(-0.95, 0.95), rng.uniform(0.5, 2.0)
        tol = 10.0 ** rng.uniform(-12, -2)
        setup = lk._lock_setup.py_func(beta, gamma * omega**2, omega, True, True)
        d, wl2, g0, g1, sd, q2, _ = setup
        k = float(rng.integers(-10**6, 10**6)) if rng.uniform() < 0.3 else 0.0
        where = rng.uniform()
        if where < 0.3:  # at the first stage's threshold
            a_star = _threshold_amplitude(lk, d, sd, wl2, g0, omega, tol, q2, k)
            x, v = a_star * (1.0 + rng.uniform(-1e-13, 1e-13)), 0.0
        elif where < 0.45:  # on a saddle's level
            x, v = math.pi * rng.choice([-1.0, 1.0]) * (1.0 + rng.uniform(-1e-15, 1e-15)), rng.uniform(-3, 3)
        else:
            amp = 10.0 ** rng.uniform(-8, 0.5)
            phase = rng.uniform(0.0, 2.0 * math.pi)
            x, v = amp * math.cos(phase), amp * math.sqrt(wl2) * math.sin(phase)
        theta = d + 2.0 * math.pi * k + x
        tols = regimes.common.Tolerance(tol, tol)
        far = lk.locked_far.py_func(theta, v, setup, omega, tols)
        reject = lk.locked_quick_reject.py_func(theta, v, setup, omega, tols)
        first = _first_stage_rejects(lk, theta, v, d, sd, wl2, g0, omega, tol, q2)
        assert not far or (first and reject), (beta, gamma, omega, tol, k, x, v)
        if where >= 0.3 and abs(x) <= lk.FAR_X and first:
            first_count += 1
            far_count += far
    assert first_count > 300, first_count
    assert far_count > 0.99 * first_count, (far_count, first_count)
