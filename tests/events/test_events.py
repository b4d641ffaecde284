"""Event points of the moving boundary method, (3.31)–(3.32): `mbm.events.points`.

Scenes are the second paper's Example 1 (β = 0.1, γ = 0.3, θ0 = 30°) and Example 2
(β = 0.1, γ = 0.6, θ0 = 90°), θ̇0 = 0, 0 ≤ t ≤ 80 (``mbm.scenes``: ex1, ex2).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
import mbm.scenes
from mbm.approximants.salas2022 import cubic_equilibrium
from mbm.events.points import (
    KIND_CROSSING,
    KIND_NONE,
    KIND_TURNING,
    SAMPLES_PER_PERIOD,
    analytic_event_points,
    event_function_d,
    event_point_solution,
    hybrid_event_points,
    next_event_analytic,
    successive,
)
from mbm.frontends.reference import reference

AP = mbm.get_approximant("salas-torque")
EX1 = mbm.scenes.get("ex1").model
EX1_Y0 = mbm.scenes.get("ex1").y0
EX2 = mbm.scenes.get("ex2").model
EX2_Y0 = mbm.scenes.get("ex2").y0
SCENES = {"ex1": (EX1, EX1_Y0), "ex2": (EX2, EX2_Y0)}
BOTH = ("crossing", "turning")


def dop853_events(model, t_span, y0, d):
    """All events θ = d, θ' = 0 of a tight DOP853 run, in time order, the start excluded."""
    sol = solve_ivp(
        model, t_span, y0, method="DOP853", rtol=1e-13, atol=1e-14,
        events=[lambda t, y: y[0] - d, lambda t, y: y[1]],
    )
    assert sol.success
    t = np.concatenate(sol.t_events)
    kind = np.concatenate([np.full(len(sol.t_events[0]), KIND_CROSSING), np.full(len(sol.t_events[1]), KIND_TURNING)])
    keep = t != t_span[0]  # DOP853 reports θ' = 0 at the start itself
    order = np.argsort(np.sign(t_span[1] - t_span[0]) * t[keep], kind="stable")
    return t[keep][order], kind[keep][order], sol.y[:, -1]


# --------------------------------------------------------------------------- d


def test_event_function_d():
    # salas-torque oscillates about the cubic's root (2.6), not about arcsin γ.
    assert event_function_d(EX1) == cubic_equilibrium(0.3) == pytest.approx(0.304337, abs=5e-7)
    w = 2.0
    m = mbm.Pendulum(beta=0.1, gamma=0.3 * w * w, omega=w)
    assert event_function_d(m, "salas-torque") == cubic_equilibrium(0.3)
    # Other approximants: the pendulum's equilibrium; none beyond |γ| > ω².
    assert event_function_d(m, "taylor") == pytest.approx(math.asin(0.3), abs=1e-15)
    assert event_function_d(mbm.Pendulum(gamma=1.2), "taylor") is None
    assert event_function_d(mbm.Pendulum(gamma=1.5), "salas-torque") is None
    with pytest.raises(ValueError, match="approximant"):
        event_function_d(EX1, "no-such-formula")
    with pytest.raises(TypeError, match="model"):
        event_function_d("pendulum")


# ---------------------------------------------------------------------- hybrid


@pytest.mark.parametrize("scene", ["ex1", "ex2"])
@pytest.mark.parametrize("rtol", [1e-12, 1e-10, 1e-8])
def test_hybrid_events_match_dop853(scene, rtol):
    model, y0 = SCENES[scene]
    d = event_function_d(model)
    t_ref, k_ref, _ = dop853_events(model, (0.0, 80.0), y0, d)
    t, y, k = hybrid_event_points(model, (0.0, 80.0), y0, d, rtol=rtol, atol=rtol * 1e-2)
    assert len(t) == len(t_ref) >= 40  # ~ four events per period over 80 ≈ 13 periods
    np.testing.assert_array_equal(k, k_ref)
    assert np.all(np.diff(t) > 0) and t[0] > 0.0 and t[-1] < 80.0
    # Event times inherit the global error of the run, ~1e2·rtol after ~50 events
    # (measured 30–220×): 1e3·rtol bounds it with the DOP853 error (~1e-12) negligible.
    assert np.max(np.abs(t - t_ref)) <= 1e3 * rtol
    # The states lie on their surfaces: CVODE's root finder works on its interpolant.
    assert np.max(np.abs(y[k == KIND_CROSSING, 0] - d)) <= 1e-9
    assert np.max(np.abs(y[k == KIND_TURNING, 1])) <= 1e-9


def test_hybrid_states_are_the_solution():
    t, y, _ = hybrid_event_points(EX2, (0.0, 80.0), EX2_Y0, event_function_d(EX2), rtol=1e-12, atol=1e-14)
    ref = reference(EX2, (0.0, 80.0), EX2_Y0, t_eval=t)
    np.testing.assert_allclose(y, ref.y.T, rtol=0, atol=1e-9)


@pytest.mark.parametrize("scene", ["ex1", "ex2"])
def test_hybrid_backward(scene):
    model, y0 = SCENES[scene]
    d = event_function_d(model)
    t_fwd, k_fwd, y_end = dop853_events(model, (0.0, 80.0), y0, d)
    t, y, k = hybrid_event_points(model, (80.0, 0.0), y_end, d)
    assert np.all(np.diff(t) < 0)  # in the order of integration
    # The start t0 = 0 is no event of the backward run's interior unless it is one
    # reached from the other side: θ'(0) = 0, so compare the forward events only.
    inner = t > 0.0
    assert np.all(t[~inner] > -1e-6)
    np.testing.assert_array_equal(k[inner][::-1], k_fwd)
    # Backward, damping amplifies errors by e^{βT/2} ≈ 55 over the span.
    np.testing.assert_allclose(t[inner][::-1], t_fwd, rtol=0, atol=1e-7)


def test_hybrid_kinds_subset_and_start_excluded():
    d = event_function_d(EX1)
    t_all, y_all, k_all = hybrid_event_points(EX1, (0.0, 80.0), EX1_Y0, d)
    t_turn, y_turn, k_turn = hybrid_event_points(EX1, (0.0, 80.0), EX1_Y0, d, kinds=("turning",))
    assert np.all(k_turn == KIND_TURNING)
    np.testing.assert_allclose(t_turn, t_all[k_all == KIND_TURNING], rtol=0, atol=1e-12)
    t_cross, _, k_cross = hybrid_event_points(EX1, (0.0, 80.0), EX1_Y0, d, kinds="crossing")
    np.testing.assert_allclose(t_cross, t_all[k_all == KIND_CROSSING], rtol=0, atol=1e-12)
    # d = None: no crossing surface, only turning points are tracked.
    t_none, _, k_none = hybrid_event_points(EX1, (0.0, 80.0), EX1_Y0, None)
    np.testing.assert_allclose(t_none, t_turn, rtol=0, atol=1e-12)
    # θ'(0) = 0: the start is on the turning surface and is no event; the first one
    # is the crossing a quarter period later.
    assert t_all[0] > 1.0 and k_all[0] == KIND_CROSSING
    # Starting exactly at an event state: that event is not reported again.
    t_again, _, k_again = hybrid_event_points(EX1, (t_all[0], 80.0), y_all[0], d)
    assert t_again[0] > t_all[0] + 1.0
    # A restarted run is a new run: agreement to its global error, ~1e2·rtol (rtol = 1e-10).
    np.testing.assert_allclose(t_again, t_all[1:], rtol=0, atol=1e-7)


def test_hybrid_long_horizon():
    # Weak damping over 1e4: thousands of events, all on their surfaces.
    model = mbm.Pendulum(beta=0.01, gamma=0.3)
    d = event_function_d(model)
    t, y, k = hybrid_event_points(model, (0.0, 1e4), (1.0, 0.0), d)
    assert len(t) > 1000 and np.all(np.diff(t) > 0)
    assert np.max(np.abs(y[k == KIND_CROSSING, 0] - d)) <= 1e-9
    assert np.max(np.abs(y[k == KIND_TURNING, 1])) <= 1e-9


# -------------------------------------------------------------------- analytic


def brute_force_next_event(coef, d, t_max, direction, omega, n=40_001):
    """Dense sampling of the formula, first sign change after the start, bisected."""
    t = np.linspace(0.0, t_max, n)
    th = np.empty(n)
    v = np.empty(n)
    AP.eval_array_kernel(coef, np.ascontiguousarray(t), th, v)
    best = (math.inf, KIND_NONE)
    for code, g in ((KIND_CROSSING, th - d), (KIND_TURNING, v)):
        # An anchor on the surface (|g(0)| tiny) is skipped by starting at sample 1.
        start = 1 if abs(g[0]) <= 1e-9 else 0
        s = np.sign(g[start:])
        idx = np.flatnonzero(s[:-1] * s[1:] < 0)
        if idx.size == 0:
            continue
        a, b = t[start + idx[0]], t[start + idx[0] + 1]
        ga = g[start + idx[0]]
        i = 0 if code == KIND_CROSSING else 1
        for _ in range(200):
            m = 0.5 * (a + b)
            if m in (a, b):
                break
            gm = AP.eval_kernel(coef, m)[i] - (d if i == 0 else 0.0)
            if (gm > 0) == (ga > 0):
                a, ga = m, gm
            else:
                b = m
        r = 0.5 * (a + b)
        if direction * r < direction * best[0] or best[1] == KIND_NONE:
            best = (r, code)
    return best


ANCHORS = [
    (EX1, EX1_Y0),
    (EX2, EX2_Y0),
    (EX1, (0.1, -0.4)),
    (EX2, (1.0, 0.35)),
    (mbm.Pendulum(beta=0.0, gamma=0.4), (-0.2, 0.5)),
    (mbm.Pendulum(beta=0.6, gamma=-0.2, omega=3.0), (0.5, 1.0)),  # ω ≠ 1: sampling step
]


@pytest.mark.parametrize("i", range(len(ANCHORS)))
@pytest.mark.parametrize("direction", [1, -1])
def test_next_event_analytic_matches_brute_force(i, direction):
    model, y0 = ANCHORS[i]
    d = event_function_d(model)
    coef = AP.anchor(model, *y0).coef
    t_max = direction * 12.0 / model.omega
    t_ev, kind = next_event_analytic(AP.eval_kernel, coef, d, BOTH, t_max, direction, omega=model.omega)
    t_bf, k_bf = brute_force_next_event(coef, d, t_max, direction, model.omega)
    assert kind == k_bf != KIND_NONE
    assert direction * t_ev > 0
    assert abs(t_ev - t_bf) <= 1e-12
    th, v = AP.eval_kernel(coef, t_ev)
    assert abs(th - d if kind == KIND_CROSSING else v) <= 1e-12


def test_anchor_on_surface_not_redetected():
    d = event_function_d(EX2)
    quarter = 0.25 * 2 * math.pi  # events are ~ a quarter period apart
    # Exactly on each surface, and at CVODE's event states (off by ~1e-14 either side).
    t_h, y_h, k_h = hybrid_event_points(EX2, (0.0, 12.0), EX2_Y0, d)
    states = [(d, 0.4), (d, -0.4), (1.2, 0.0), (0.2, 0.0)] + [tuple(s) for s in y_h]
    for th0, v0 in states:
        coef = AP.anchor(EX2, th0, v0).coef
        for direction in (1, -1):
            t_ev, kind = next_event_analytic(AP.eval_kernel, coef, d, BOTH, direction * 20.0, direction)
            assert kind != KIND_NONE
            assert direction * t_ev > 0.5 * quarter, (th0, v0, direction, t_ev)
            t_bf, k_bf = brute_force_next_event(coef, d, direction * 20.0, direction, 1.0)
            assert kind == k_bf and abs(t_ev - t_bf) <= 1e-12


def test_early_event_off_the_surface_is_found():
    # θ' = 1e-3 above d: θ'' ≈ −0.5, the turning point comes at t ≈ 2e-3, inside the
    # first sampling interval (2π/64 ≈ 0.1); it is a genuine event, not the anchor's.
    d = event_function_d(EX1)
    coef = AP.anchor(EX1, d + 0.5, 1e-3).coef
    t_ev, kind = next_event_analytic(AP.eval_kernel, coef, d, BOTH, 10.0, 1)
    assert kind == KIND_TURNING
    assert 0.0 < t_ev < 2 * math.pi / SAMPLES_PER_PERIOD
    assert abs(AP.eval_kernel(coef, t_ev)[1]) <= 1e-14


def test_next_event_none():
    d = event_function_d(EX1)
    coef = AP.anchor(EX1, *EX1_Y0).coef
    t_first, _ = next_event_analytic(AP.eval_kernel, coef, d, BOTH, 10.0, 1)
    # A search window ending before the first event finds nothing.
    assert next_event_analytic(AP.eval_kernel, coef, d, BOTH, 0.9 * t_first, 1) == (math.inf, KIND_NONE)
    # At the formula's own rest state (θ = d, θ' = 0, β = 0) nothing ever changes sign.
    m = mbm.Pendulum(gamma=0.3)
    coef = AP.anchor(m, cubic_equilibrium(0.3), 0.0).coef
    assert next_event_analytic(AP.eval_kernel, coef, d, BOTH, 50.0, 1) == (math.inf, KIND_NONE)


def test_analytic_event_points_chain():
    d = event_function_d(EX2)
    t, y, k = analytic_event_points(EX2, (0.0, 80.0), EX2_Y0, d)
    t_h, _, k_h = hybrid_event_points(EX2, (0.0, 80.0), EX2_Y0, d)
    assert np.all(np.diff(t) > 0) and t[-1] <= 80.0
    # Each state is the previous formula at its event: on its surface.
    assert np.max(np.abs(y[k == KIND_CROSSING, 0] - d)) <= 1e-12
    assert np.max(np.abs(y[k == KIND_TURNING, 1])) <= 1e-12
    # The formula's events follow the pendulum's with the cubic model's phase error:
    # 0.04–0.085 late over the first ten events, growing to about one event by t = 80.
    assert abs(len(t) - len(t_h)) <= 1
    np.testing.assert_array_equal(k[:10], k_h[:10])
    lag = t[:10] - t_h[:10]
    assert np.all((0.03 < lag) & (lag < 0.1))
    # Backward from the end state reproduces nothing exotic: monotone, on surfaces.
    tb, yb, kb = analytic_event_points(EX2, (80.0, 0.0), y[-1], d)
    assert np.all(np.diff(tb) < 0) and tb[-1] >= 0.0
    assert np.max(np.abs(yb[kb == KIND_TURNING, 1])) <= 1e-12


# ------------------------------------------------------------------ (3.31)


def test_successive_equals_mbm_windows_then_continues():
    tau, j = 0.5, 7
    T = 12.0
    sol = solve_ivp(EX2, (0.0, T), EX2_Y0, method=mbm.MBM, approximant="salas-torque", tau=tau, dense_output=True)
    theta_j = successive(EX2, EX2_Y0, tau, j)
    t_in = np.linspace(0.0, j * tau, 301)
    np.testing.assert_allclose(np.vstack(theta_j(t_in)), sol.sol(t_in), rtol=0, atol=1e-14)
    # At the window ends the anchors are MBM's states.
    np.testing.assert_allclose(np.vstack(theta_j(sol.t[: j + 1])), sol.y[:, : j + 1], rtol=0, atol=1e-14)
    # Beyond jτ: θ_j continued, not re-anchored.
    t_out = np.linspace(j * tau, T, 101)[1:]
    cont = AP.anchor(EX2, *theta_j(j * tau))(t_out - j * tau)
    np.testing.assert_allclose(np.vstack(theta_j(t_out)), np.vstack(cont), rtol=0, atol=1e-14)
    assert np.max(np.abs(theta_j(t_out)[0] - sol.sol(t_out)[0])) > 1e-3  # MBM re-anchors there
    # Scalars in, floats out; j = 0 is the single approximant.
    th, v = successive(EX2, EX2_Y0, tau, 0)(3.3)
    assert isinstance(th, float)
    assert (th, v) == AP.anchor(EX2, *EX2_Y0)(3.3)


def test_successive_converges_in_j():
    # Θ_j → the (3.30) approximant as j grows: on [0, 20] with τ = 0.25, Θ_80 is it.
    t = np.linspace(0.0, 20.0, 401)
    full = np.vstack(successive(EX1, EX1_Y0, 0.25, 80)(t))
    errs = [np.max(np.abs(successive(EX1, EX1_Y0, 0.25, j)(t)[0] - full[0])) for j in (0, 20, 40, 79)]
    assert errs[-1] <= 1e-14 and all(a > b for a, b in zip(errs, errs[1:]))


def test_event_point_solution_is_3_32():
    d = event_function_d(EX2)
    t_ev, y_ev, _ = hybrid_event_points(EX2, (0.0, 80.0), EX2_Y0, d)
    pw = event_point_solution(EX2, 0.0, EX2_Y0, t_ev, y_ev)
    assert len(pw) == len(t_ev) + 1
    # On [0, τ₁]: θ₀; on (τ_n, τ_{n+1}]: θ_n anchored at φ(τ_n); the value at τ_n is θ_{n−1}'s.
    t0 = np.linspace(0.0, t_ev[0], 7)
    np.testing.assert_array_equal(pw(t0)[0], AP.anchor(EX2, *EX2_Y0)(t0)[0])
    n = 5
    mid = 0.5 * (t_ev[n - 1] + t_ev[n])
    assert pw(mid) == AP.anchor(EX2, *y_ev[n - 1])(mid - t_ev[n - 1])
    assert pw(t_ev[n]) == AP.anchor(EX2, *y_ev[n - 1])(t_ev[n] - t_ev[n - 1])


def test_event_point_solution_backward():
    # From the end state back to 0: windows (τ_{n+1}, τ_n] in the backward sense.
    d = event_function_d(EX1)
    t = np.linspace(0.0, 80.0, 801)
    ref = reference(EX1, (0.0, 80.0), EX1_Y0, t_eval=t).y
    t_b, y_b, _ = hybrid_event_points(EX1, (80.0, 0.0), ref[:, -1], d)
    pw = event_point_solution(EX1, 80.0, ref[:, -1], t_b, y_b)
    assert pw.sign == -1
    # Between τ_1 and τ_2 (backward), the formula anchored at φ(τ_1) holds.
    mid = 0.5 * (t_b[0] + t_b[1])
    assert pw(mid) == AP.anchor(EX1, *y_b[0])(mid - t_b[0])
    # Damping run backward magnifies the cubic model's error, but the windows keep
    # it at the size of the forward one (1.1e-3).
    assert np.max(np.abs(pw(t)[0] - ref[0])) < 1.5e-3
    with pytest.raises(ValueError, match="t must be"):
        pw(80.5)


# ------------------------------------------------------ errors of the modes


def test_event_point_mbm_errors_on_example2():
    """Max |θ − θ_ref| over 0 ≤ t ≤ 80 (4001 points): single ≈ 0.368, hybrid ≈ 0.0463,
    analytic ≈ 0.0471, fixed τ with as many windows ≈ 0.0465 (τ = 0.1: 0.0266)."""
    t = np.linspace(0.0, 80.0, 4001)
    ref = reference(EX2, (0.0, 80.0), EX2_Y0, t_eval=t).y[0]
    d = event_function_d(EX2)
    single = np.max(np.abs(AP.anchor(EX2, *EX2_Y0)(t)[0] - ref))
    t_h, y_h, _ = hybrid_event_points(EX2, (0.0, 80.0), EX2_Y0, d)
    hybrid = np.max(np.abs(event_point_solution(EX2, 0.0, EX2_Y0, t_h, y_h)(t)[0] - ref))
    t_a, y_a, _ = analytic_event_points(EX2, (0.0, 80.0), EX2_Y0, d)
    analytic = np.max(np.abs(event_point_solution(EX2, 0.0, EX2_Y0, t_a, y_a)(t)[0] - ref))
    tau = 80.0 / (len(t_h) + 1)
    fixed = np.max(np.abs(solve_ivp(EX2, (0.0, 80.0), EX2_Y0, method=mbm.MBM, approximant="salas-torque", tau=tau, t_eval=t).y[0] - ref))
    assert single == pytest.approx(0.368, abs=0.005)
    assert hybrid == pytest.approx(0.0463, abs=0.001)
    assert analytic == pytest.approx(0.0471, abs=0.001)
    # Re-anchoring at events cuts the single formula's error eightfold, and is no
    # worse than the same number of uniform windows.
    assert hybrid < single / 7 and analytic < single / 7
    assert hybrid <= fixed


def test_event_point_mbm_beats_fixed_windows_on_example1():
    # Example 1: fixed windows converge to the cubic model (2.4), 3.1e-3 from the
    # pendulum; re-anchoring on the pendulum's own states (hybrid) does not inherit it.
    t = np.linspace(0.0, 80.0, 4001)
    ref = reference(EX1, (0.0, 80.0), EX1_Y0, t_eval=t).y[0]
    d = event_function_d(EX1)
    t_h, y_h, _ = hybrid_event_points(EX1, (0.0, 80.0), EX1_Y0, d)
    hybrid = np.max(np.abs(event_point_solution(EX1, 0.0, EX1_Y0, t_h, y_h)(t)[0] - ref))
    fixed = np.max(np.abs(solve_ivp(EX1, (0.0, 80.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.1, t_eval=t).y[0] - ref))
    single = np.max(np.abs(AP.anchor(EX1, *EX1_Y0)(t)[0] - ref))
    assert hybrid == pytest.approx(1.14e-3, rel=0.02)
    assert hybrid < single < fixed


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(t_span=(0.0, 0.0)), "t_span"),
        (dict(t_span=(0.0, math.inf)), "t_span"),
        (dict(t_span=5.0), "t_span"),
        (dict(y0=[1.0]), "y0"),
        (dict(y0=[math.nan, 0.0]), "y0"),
        (dict(d=math.nan), "d"),
        (dict(d="x"), "d"),
        (dict(kinds=("crossing", "bogus")), "kinds"),
        (dict(kinds=()), "kinds"),
        (dict(d=None, kinds=("crossing",)), "d=None"),
        (dict(rtol=0.0), "rtol"),
        (dict(atol=-1.0), "atol"),
        (dict(atol=math.nan), "atol"),
    ],
)
def test_hybrid_bad_input(kwargs, name):
    args = dict(model=EX1, t_span=(0.0, 10.0), y0=EX1_Y0, d=0.3)
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        hybrid_event_points(**args)


def test_hybrid_rtol_below_floor_warns():
    # scipy's rule, as every entry point: rtol below 100 eps is raised to it with a warning.
    with pytest.warns(UserWarning, match="below 100 machine epsilons"):
        te, _, _ = hybrid_event_points(EX1, (0.0, 10.0), EX1_Y0, 0.3, rtol=1e-17)
    assert te.size > 0


def test_hybrid_bad_model():
    with pytest.raises(TypeError, match="model"):
        hybrid_event_points(None, (0.0, 1.0), EX1_Y0, 0.3)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(direction=0), "direction"),
        (dict(direction=1.5), "direction"),
        (dict(t_max=-1.0), "t_max"),
        (dict(t_max=0.0), "t_max"),
        (dict(t_max=math.inf), "t_max"),
        (dict(omega=0.0), "omega"),
        (dict(omega=math.nan), "omega"),
        (dict(kinds=["turn"]), "kinds"),
        (dict(d=math.inf), "d"),
        (dict(coef=AP.anchor_kernel(0.1, 0.3, 1.0, 3.0, 0.0)), "coef"),  # status != 0
    ],
)
def test_next_event_bad_input(kwargs, name):
    args = dict(eval_kernel=AP.eval_kernel, coef=AP.anchor(EX1, *EX1_Y0).coef, d=0.3,
                kinds=BOTH, t_max=5.0, direction=1)
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        next_event_analytic(**args)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(tau=0.0), "tau"),
        (dict(tau=math.inf), "tau"),
        (dict(j=-1), "j"),
        (dict(j=2.0), "j"),
        (dict(j=True), "j"),
        (dict(y0=(0.1, 0.2, 0.3)), "y0"),
        (dict(approximant="nope"), "approximant"),
    ],
)
def test_successive_bad_input(kwargs, name):
    args = dict(model=EX1, y0=EX1_Y0, tau=0.5, j=3)
    args.update(kwargs)
    with pytest.raises(ValueError, match=name):
        successive(**args)


def test_successive_and_piecewise_domain():
    theta = successive(EX1, EX1_Y0, 0.5, 2)
    with pytest.raises(ValueError, match="t must be"):
        theta(-0.1)
    with pytest.raises(ValueError, match="t_events"):
        event_point_solution(EX1, 0.0, EX1_Y0, [2.0, 1.0], [[0.3, 0.1], [0.3, 0.0]])
    with pytest.raises(ValueError, match="y_events"):
        event_point_solution(EX1, 0.0, EX1_Y0, [1.0, 2.0], [[0.3, 0.1]])
    # An anchor beyond the cubic's hump: the approximant's own domain error.
    with pytest.raises(mbm.ApproximantDomainError):
        event_point_solution(EX1, 0.0, EX1_Y0, [1.0], [[3.0, 0.0]])
