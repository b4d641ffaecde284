"""The default approximant "auto": its choice, its reason, and the horizon-free undamped run."""

import math
import time

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm


def test_auto_picks_exact_flow_when_undamped_untorqued():
    s = mbm.MBM(mbm.Pendulum(0.0, 0.0, 2.0), 0.0, [0.3, 1.0], 10.0)
    name, reason = s.approximant_choice
    assert name == "belendez" and "exact" in reason
    assert s.tau == 10.0  # one window: the exact flow has no truncation error


def test_auto_picks_convergent_family_otherwise():
    for model in (mbm.Pendulum(0.1, 0.3), mbm.Pendulum(0.0, 0.3), mbm.Pendulum(0.2, 0.0), mbm.Pendulum(0.1, 1.2)):
        s = mbm.MBM(model, 0.0, [0.3, 1.0], 10.0)
        name, reason = s.approximant_choice
        assert name == mbm.choice.CONVERGENT_DEFAULT and s.adaptive
        assert "model error" in reason


def test_explicit_choice_is_recorded():
    s = mbm.MBM(mbm.Pendulum(0.1, 0.3), 0.0, [0.3, 0.0], 10.0, approximant="salas-torque", tau=1.0)
    assert s.approximant_choice == ("salas-torque", "chosen by the caller")


def _median_time(fn, n=7):
    ts = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts))


def test_horizon_free_undamped_run():
    # θ(1e6) costs about what θ(1) costs, and is the exact flow (phase error vs mpmath
    # pinned in tests/approximants/test_belendez2007.py at t ~ 1e6: < 1e-15).
    model = mbm.Pendulum(0.0, 0.0)
    y0 = [0.3, 1.0]

    def run(T):
        return solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=[T])

    run(1.0)
    t1 = _median_time(lambda: run(1.0))
    t6 = _median_time(lambda: run(1e6))
    assert t6 < 3.0 * t1 + 1e-3
    sol = run(1e6)
    exact = mbm.pendulum_flow(model, y0, np.array([1e6]))
    np.testing.assert_array_equal(sol.y[:, -1], exact[:, 0])
    # energy conserved over 1e6 time units by construction
    assert model.energy(sol.y[:, -1]) == pytest.approx(model.energy(y0), rel=1e-12)


def test_auto_never_nan_on_scenes():
    scenes = [
        (mbm.Pendulum(0.1, 0.3), [math.radians(30.0), 0.0], 80.0),
        (mbm.Pendulum(0.1, 1.2), [0.0, 0.0], 200.0),
        (mbm.Pendulum(0.0, 0.0), [0.0, 1.999], 200.0),
        (mbm.Pendulum(3.0, 0.5), [2.0, -4.0], 50.0),
    ]
    for model, y0, T in scenes:
        for rtol in (1e-3, 1e-10):
            sol = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, rtol=rtol, atol=rtol, dense_output=True)
            assert sol.success and np.all(np.isfinite(sol.y))
            assert np.all(np.isfinite(sol.sol(np.linspace(0.0, T, 101))))
