"""`mbm.MBM` as a solve_ivp method: scipy's OdeSolver contract, adapted from
scipy's own tests (scipy/integrate/_ivp/tests/test_ivp.py: test_integration,
test_t_eval, test_t_eval_dense_output, test_events, test_max_step,
test_no_integration, test_classes, test_args), plus the moving boundary method's
convergence on the second paper's scenes."""

import math

import numpy as np
import pytest
from scipy.integrate import OdeSolver, solve_ivp

import mbm
from mbm.approximants.salas2022 import cubic_equilibrium

EX1 = mbm.Pendulum(beta=0.1, gamma=0.3)
EX1_Y0 = [math.radians(30.0), 0.0]
EX2 = mbm.Pendulum(beta=0.1, gamma=0.6)
EX2_Y0 = [math.radians(90.0), 0.0]


def test_drop_in_solve_ivp_with_pendulum():
    sol = solve_ivp(EX1, (0.0, 10.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.5)
    assert sol.success and sol.status == 0
    assert sol.t[0] == 0.0 and sol.t[-1] == 10.0
    assert np.all(np.diff(sol.t) > 0)
    assert sol.nfev == 0  # a Pendulum is not probed
    assert sol.y.shape == (2, sol.t.size)
    assert np.allclose(np.diff(sol.t)[:-1], 0.5)


def test_plain_callable_is_probed():
    def rhs(t, y):
        return [y[1], 0.3 - 0.1 * y[1] - np.sin(y[0])]

    a = solve_ivp(rhs, (0.0, 10.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.5)
    b = solve_ivp(EX1, (0.0, 10.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.5)
    assert a.nfev > 0
    np.testing.assert_allclose(a.y, b.y, rtol=0, atol=1e-12)


def test_args_are_passed():
    def rhs(t, y, beta, gamma):
        return [y[1], gamma - beta * y[1] - np.sin(y[0])]

    a = solve_ivp(rhs, (0.0, 5.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.5, args=(0.1, 0.3))
    b = solve_ivp(EX1, (0.0, 5.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.5)
    np.testing.assert_allclose(a.y, b.y, atol=1e-12)


def test_identify_model_recovers_parameters():
    for beta, gamma, omega in [(0.1, 0.3, 1.0), (0.0, -1.7, 2.5), (3.0, 0.0, 0.2), (0.25, 5.0, 10.0)]:
        def rhs(t, y, b=beta, g=gamma, w=omega):
            return np.array([y[1], g - b * y[1] - w * w * np.sin(y[0])])

        model, nfev = mbm.identify_model(rhs)
        assert nfev >= 3
        assert model.beta == pytest.approx(beta, abs=1e-12)
        assert model.gamma == pytest.approx(gamma, abs=1e-12)
        assert model.omega == pytest.approx(omega, rel=1e-12)


@pytest.mark.parametrize(
    "rhs",
    [
        lambda t, y: [y[1], (1 - y[0] ** 2) * y[1] - y[0]],  # Van der Pol
        lambda t, y: [y[1], -y[0] + 2 * y[0] ** 3 / 13],  # the cubic model itself
        lambda t, y: [y[1], -0.1 * (1 + 0.2 * np.cos(t)) * y[1] - np.sin(y[0])],  # damping modulated in t
        lambda t, y: [2 * y[1], -np.sin(y[0])],  # first component not θ'
        lambda t, y: [y[1], -0.1 * y[1] * abs(y[1]) - np.sin(y[0])],  # quadratic drag
    ],
)
def test_non_member_rejected(rhs):
    with pytest.raises(ValueError, match="not of the pendulum family"):
        solve_ivp(rhs, (0, 1), [0.1, 0.0], method=mbm.MBM, approximant="salas-torque")


def test_negative_damping_rejected():
    with pytest.raises(ValueError, match="beta"):
        mbm.identify_model(lambda t, y: [y[1], 0.1 * y[1] - np.sin(y[0])])


def test_model_option_checks_fun():
    # model= is checked against fun (tests/frontends/test_probe.py: the mismatches)
    def never(t, y):
        raise AssertionError("fun is called to check it against model=")

    with pytest.raises(AssertionError, match="check it against model="):
        solve_ivp(never, (0.0, 3.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", model=EX1, tau=0.5)
    rhs = lambda t, y: [y[1], 0.3 - 0.1 * y[1] - np.sin(y[0])]  # noqa: E731
    sol = solve_ivp(rhs, (0.0, 3.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", model=EX1, tau=0.5)
    ref = solve_ivp(EX1, (0.0, 3.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.5)
    assert sol.success and sol.nfev > 0 and np.array_equal(sol.y, ref.y)
    with pytest.raises(TypeError, match="model"):
        solve_ivp(never, (0.0, 3.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", model=(0.1, 0.3, 1.0))


def test_step_contract_exact_window_ends():
    # sol(t_old) == y_old and sol(t) == y bit for bit; the last window lands on t_bound.
    solver = mbm.MBM(EX1, 0.0, EX1_Y0, 7.3, tau=1.0, approximant="salas-torque")
    assert isinstance(solver, OdeSolver)
    y_old = solver.y.copy()
    ends = []
    while solver.status == "running":
        msg = solver.step()
        assert msg is None
        sol = solver.dense_output()
        assert np.array_equal(sol(solver.t_old), y_old)
        assert np.array_equal(sol(solver.t), solver.y)
        assert sol.t_min == solver.t_old and sol.t_max == solver.t
        ends.append(solver.t)
        y_old = solver.y.copy()
    assert solver.status == "finished"
    assert ends[-1] == 7.3
    np.testing.assert_allclose(np.diff(ends)[:-1], 1.0)
    assert solver.step_size == pytest.approx(0.3)
    with pytest.raises(RuntimeError):
        solver.step()


def test_backward_integration():
    fwd = solve_ivp(EX1, (0.0, 5.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.25)
    back = solve_ivp(EX1, (5.0, 0.0), fwd.y[:, -1], method=mbm.MBM, approximant="salas-torque", tau=0.25)
    assert back.success and back.t[-1] == 0.0
    assert np.all(np.diff(back.t) < 0)
    # Both directions follow the same cubic-model flow up to its re-anchoring error.
    np.testing.assert_allclose(back.y[:, -1], EX1_Y0, atol=2e-4)


def test_t_eval_and_dense_output_agree():
    t_eval = np.linspace(0.0, 20.0, 41)
    sol = solve_ivp(EX1, (0.0, 20.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.7, t_eval=t_eval, dense_output=True)
    assert sol.success
    np.testing.assert_array_equal(sol.t, t_eval)
    np.testing.assert_allclose(sol.sol(t_eval), sol.y, rtol=0, atol=1e-15)
    # t_eval points inside windows are the analytic formula of that window.
    ap = mbm.get_approximant("salas-torque")
    windows = solve_ivp(EX1, (0.0, 20.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.7)
    k = 5
    a = ap.anchor(EX1, *windows.y[:, k])
    tm = windows.t[k] + 0.3
    np.testing.assert_allclose(sol.sol(tm), np.array(a(tm - windows.t[k])), rtol=0, atol=1e-15)


def test_t_eval_backward():
    t_eval = np.linspace(10.0, 0.0, 11)
    sol = solve_ivp(EX1, (10.0, 0.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.5, t_eval=t_eval)
    np.testing.assert_array_equal(sol.t, t_eval)


def test_events_terminal_and_direction():
    d = cubic_equilibrium(0.3)

    def crossing(t, y):
        return y[0] - d

    def turning(t, y):
        return y[1]

    turning.direction = 1
    sol = solve_ivp(EX1, (0.0, 40.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.5, events=[crossing, turning])
    assert sol.success
    tc, tt = sol.t_events
    assert len(tc) >= 10 and len(tt) >= 5
    # θ' = 0 crossed upward only at minima of θ.
    assert np.all(sol.y_events[1][:, 0] < d)
    # MBM converges to the cubic model (2.4): its crossings match the cubic model's closely ...
    def cubic(_, y):
        return [y[1], 0.3 - 0.1 * y[1] - (y[0] - 2 * y[0] ** 3 / 13)]

    ref_cubic = solve_ivp(cubic, (0.0, 40.0), EX1_Y0, method="DOP853", rtol=1e-12, atol=1e-12, events=crossing)
    np.testing.assert_allclose(tc, ref_cubic.t_events[0], atol=2e-3)
    # ... while the pendulum's drift away at the cubic's frequency error (measured 0.069 by t = 34).
    ref = solve_ivp(EX1, (0.0, 40.0), EX1_Y0, method="DOP853", rtol=1e-12, atol=1e-12, events=crossing)
    lag = ref.t_events[0][: len(tc)] - tc
    assert 0.03 < lag[-1] < 0.1 and lag[-1] > lag[0]

    crossing.terminal = True
    sol = solve_ivp(EX1, (0.0, 40.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.5, events=crossing)
    assert sol.status == 1 and sol.t[-1] == pytest.approx(tc[0], abs=1e-9)
    assert sol.y[0, -1] == pytest.approx(d, abs=1e-9)


def test_max_step_caps_tau():
    sol = solve_ivp(EX1, (0.0, 5.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=2.0, max_step=0.5)
    assert np.max(np.diff(sol.t)) <= 0.5 + 1e-15


def test_no_integration():
    sol = solve_ivp(EX1, (3.0, 3.0), EX1_Y0, method=mbm.MBM, approximant="salas-torque")
    assert sol.success
    np.testing.assert_array_equal(sol.y[:, -1], EX1_Y0)


def test_bad_input():
    with pytest.raises(ValueError, match="tau"):
        solve_ivp(EX1, (0, 1), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=0.0)
    with pytest.raises(ValueError, match="tau"):
        solve_ivp(EX1, (0, 1), EX1_Y0, method=mbm.MBM, approximant="salas-torque", tau=float("nan"))
    with pytest.raises(ValueError, match="y0"):
        solve_ivp(EX1, (0, 1), [0.1, 0.0, 0.0], method=mbm.MBM, approximant="salas-torque")
    with pytest.raises(ValueError, match="y0"):
        solve_ivp(EX1, (0, 1), [np.nan, 0.0], method=mbm.MBM, approximant="salas-torque")
    with pytest.raises(ValueError, match="approximant"):
        solve_ivp(EX1, (0, 1), EX1_Y0, method=mbm.MBM, approximant="no-such")
    with pytest.raises(mbm.ApproximantDomainError, match="gamma"):
        solve_ivp(mbm.Pendulum(gamma=1.2), (0, 1), EX1_Y0, method=mbm.MBM, approximant="salas-torque")
    with pytest.raises(ValueError, match="rtol"):
        solve_ivp(EX1, (0, 1), EX1_Y0, method=mbm.MBM, approximant="salas-torque", rtol=-1.0)
    with pytest.warns(UserWarning, match="no effect"):
        solve_ivp(EX1, (0, 1), EX1_Y0, method=mbm.MBM, approximant="salas-torque", bogus=1)


def test_leaving_the_domain_fails_cleanly():
    # Example 2's scene starts inside the cubic's domain; a hard push sends the state past
    # the hump of the cubic, and the solver reports failure instead of returning NaN.
    sol = solve_ivp(mbm.Pendulum(beta=0.0, gamma=0.0), (0, 10), [0.0, 2.5], method=mbm.MBM, approximant="salas-torque", tau=0.5)
    assert not sol.success and sol.status == -1
    assert "bounded orbit" in sol.message
    assert np.all(np.isfinite(sol.y))


def _mbm_error(model, y0, tau, t, against):
    sol = solve_ivp(model, (t[0], t[-1]), y0, method=mbm.MBM, approximant="salas-torque", tau=tau, t_eval=t)
    assert sol.success
    return np.max(np.abs(sol.y[0] - against))


def _cubic_reference(model, y0, t):
    def rhs(_, y):
        return [y[1], model.gamma - model.beta * y[1] - (y[0] - 2 * y[0] ** 3 / 13)]

    return solve_ivp(rhs, (t[0], t[-1]), y0, method="DOP853", rtol=1e-13, atol=1e-14, t_eval=t).y[0]


TAUS = 8.0 / 2.0 ** np.arange(7)  # 8 … 0.125


@pytest.mark.parametrize(
    "model,y0,model_err,rel",
    [
        # Measured (tests/frontends/test_solver.py sweep): against the cubic model the error halves
        # with τ (fitted order 1.0: the residual (2.9) − (2.10) is O(βt), so θ'' errs by
        # O(τ) and θ' by O(τ²) per window); against the pendulum it levels off at the
        # cubic's own model error max|θ_cubic − θ| = 3.215e-3 (Example 1), 2.485e-2
        # (Example 2).  (The issue quoted 6e-4 and 8e-3; not reproduced: the single
        # approximant's 1.6e-3 is below the cubic's error because dropping e^{−βt}
        # partly compensates it.)
        (EX1, EX1_Y0, 3.215e-3, 0.02),
        (EX2, EX2_Y0, 2.485e-2, 0.12),
    ],
)
def test_tau_sweep_converges_to_cubic_model(model, y0, model_err, rel):
    t = np.linspace(0.0, 80.0, 801)
    cubic = _cubic_reference(model, y0, t)
    true = mbm.reference(model, (0.0, 80.0), y0, t_eval=t).y[0]
    assert np.max(np.abs(cubic - true)) == pytest.approx(model_err, rel=1e-3)
    e_cubic = np.array([_mbm_error(model, y0, tau, t, cubic) for tau in TAUS])
    e_true = np.array([_mbm_error(model, y0, tau, t, true) for tau in TAUS])
    # Fitted order over the asymptotic range τ ≤ 1 against the cubic model (2.4).
    small = TAUS <= 1.0
    order = np.polyfit(np.log(TAUS[small]), np.log(e_cubic[small]), 1)[0]
    assert 0.9 <= order <= 1.2
    assert np.all(np.diff(e_cubic[small]) < 0)
    # Against the pendulum the error levels off at the cubic's model error.
    assert e_true[-1] == pytest.approx(model_err, rel=rel)
    steps = np.abs(np.diff(e_true[small]))
    assert np.all(steps[1:] < steps[:-1])


@pytest.mark.parametrize(
    "model,kw",
    [
        (EX1, dict()),  # auto: the convergent family with rtol/atol windows
        (EX1, dict(rtol=1e-9, atol=1e-9)),
        (EX1, dict(approximant="taylor12", tau=0.3)),
        (mbm.Pendulum(0.0, 0.0), dict(max_step=2.5)),  # auto: exact flow
        (EX1, dict(approximant="salas-torque", anchors="events", events_from="approximant")),
    ],
)
@pytest.mark.parametrize("direction", [1, -1])
def test_step_contract_every_mode(model, kw, direction):
    t_bound = 9.7 * direction
    solver = mbm.MBM(model, 0.0, EX1_Y0, t_bound, **kw)
    y_old = solver.y.copy()
    n = 0
    while solver.status == "running":
        assert solver.step() is None
        sol = solver.dense_output()
        assert np.array_equal(sol(solver.t_old), y_old)
        assert np.array_equal(sol(solver.t), solver.y)
        assert direction * (solver.t - solver.t_old) > 0
        y_old = solver.y.copy()
        n += 1
    assert solver.status == "finished" and solver.t == t_bound and n >= 2


@pytest.mark.parametrize("wps", [3, None])
@pytest.mark.parametrize("kw", [dict(rtol=1e-8, atol=1e-8), dict(approximant="salas-torque", tau=0.4)])
def test_many_windows_per_step_same_answer(wps, kw):
    # Grouping windows into steps changes the Python overhead, not the windows.
    t = np.linspace(0.0, 30.0, 301)
    one = solve_ivp(EX1, (0.0, 30.0), EX1_Y0, method=mbm.MBM, t_eval=t, dense_output=True, **kw)
    many = solve_ivp(EX1, (0.0, 30.0), EX1_Y0, method=mbm.MBM, t_eval=t, dense_output=True, windows_per_step=wps, **kw)
    assert many.success and many.t.size == t.size
    np.testing.assert_array_equal(many.y, one.y)
    tt = np.linspace(0.0, 30.0, 1001)
    np.testing.assert_array_equal(many.sol(tt), one.sol(tt))
    solver = mbm.MBM(EX1, 0.0, EX1_Y0, 30.0, windows_per_step=wps, **kw)
    y_old = solver.y.copy()
    steps = 0
    while solver.status == "running":
        solver.step()
        sol = solver.dense_output()
        assert np.array_equal(sol(solver.t_old), y_old) and np.array_equal(sol(solver.t), solver.y)
        y_old = solver.y.copy()
        steps += 1
    if wps is None:
        assert steps == 1


def test_windows_per_step_validated():
    with pytest.raises(ValueError, match="windows_per_step"):
        mbm.MBM(EX1, 0.0, EX1_Y0, 1.0, windows_per_step=0)


# ------------------------------------------------------------------ events


def _slip(t, y):
    return np.cos(y[0] / 2.0)


def test_events_found_in_every_window():
    # A running junction (β = 0.2, γ = 0.8, θ'(0) = 4): 127 phase slips by t = 200,
    # each a zero of cos(θ/2), as DOP853 at 1e-11 finds them.
    model = mbm.Pendulum(0.2, 0.8)
    sol = solve_ivp(model, (0.0, 200.0), [0.0, 4.0], method=mbm.MBM, events=_slip, rtol=1e-9, atol=1e-9)
    dop = solve_ivp(model, (0.0, 200.0), [0.0, 4.0], method="DOP853", events=_slip, rtol=1e-11, atol=1e-11)
    assert sol.success and len(dop.t_events[0]) == 127
    assert len(sol.t_events[0]) == 127
    np.testing.assert_allclose(sol.t_events[0], dop.t_events[0], atol=1e-7)


def test_events_with_several_windows_per_step_refused():
    # solve_ivp looks for events at step ends only: several windows per step would
    # drop events silently (1 slip of 127), so MBM refuses.
    with pytest.raises(ValueError, match="windows_per_step"):
        solve_ivp(mbm.Pendulum(0.2, 0.8), (0.0, 200.0), [0.0, 4.0], method=mbm.MBM, events=_slip,
                  windows_per_step=None)


def test_events_on_the_exact_flow_cut_its_single_window():
    # β = γ = 0: one window spans the whole run unless events are asked for.
    model = mbm.Pendulum(0.0, 0.0)

    def turning(t, y):
        return y[1]

    sol = solve_ivp(model, (0.0, 100.0), [0.0, 1.5], method=mbm.MBM, events=turning)
    dop = solve_ivp(model, (0.0, 100.0), [0.0, 1.5], method="DOP853", events=turning, rtol=1e-12, atol=1e-12)
    assert len(dop.t_events[0]) == 26
    assert len(sol.t_events[0]) == 26
    np.testing.assert_allclose(sol.t_events[0], dop.t_events[0], atol=1e-8)
    plain = solve_ivp(model, (0.0, 100.0), [0.0, 1.5], method=mbm.MBM)
    assert plain.t.size == 2  # no events: the one exact window


def test_solve_ivp_events_are_seen_by_the_solver():
    # MBM reads solve_ivp's `events` argument from its frame (solve_ivp does not pass
    # it on): check that this still works on the installed scipy.
    seen = {}

    class Spy(mbm.MBM):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            seen["for_events"] = self.for_events

    solve_ivp(EX1, (0.0, 1.0), EX1_Y0, method=Spy, events=_slip)
    assert seen["for_events"] is True
    solve_ivp(EX1, (0.0, 1.0), EX1_Y0, method=Spy)
    assert seen["for_events"] is False
    assert mbm.MBM(EX1, 0.0, EX1_Y0, 1.0).for_events is False
