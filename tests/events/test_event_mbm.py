"""Event-point moving boundary method (3.32) through ``solve_ivp(..., anchors="events")``."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm.events import points as events
from mbm.approximants.salas2022 import SalasTorque, cubic_equilibrium

EX2 = mbm.Pendulum(beta=0.1, gamma=0.6)
EX2_Y0 = [math.radians(90.0), 0.0]
T = np.linspace(0.0, 80.0, 4001)


@pytest.fixture(scope="module")
def ref():
    return mbm.reference(EX2, (0.0, 80.0), EX2_Y0, t_eval=T).y[0]


def _run(mode, **kw):
    return solve_ivp(
        EX2, (0.0, 80.0), EX2_Y0, method=mbm.MBM, approximant="salas-torque",
        anchors="events", events_from=mode, t_eval=T, **kw,
    )


def test_hybrid_mode_beats_single_approximant(ref):
    single = mbm.get_approximant("salas-torque").anchor(EX2, *EX2_Y0)(T)[0]
    e_single = np.max(np.abs(single - ref))
    sol = _run("cvode")
    assert sol.success
    e_hybrid = np.max(np.abs(sol.y[0] - ref))
    # measured: single 0.368, hybrid 0.0463 (45 windows)
    assert e_single == pytest.approx(0.368, abs=0.01)
    assert e_hybrid == pytest.approx(0.0463, rel=0.05)
    assert e_hybrid < e_single / 5


def test_analytic_mode(ref):
    sol = _run("approximant")
    assert sol.success
    # measured: 0.0471 with 46 windows
    assert np.max(np.abs(sol.y[0] - ref)) == pytest.approx(0.0471, rel=0.05)


def test_hybrid_windows_end_at_cvode_events():
    d = cubic_equilibrium(0.6)
    te, ye, kinds = events.hybrid_event_points(EX2, (0.0, 80.0), EX2_Y0, d, rtol=1e-10, atol=1e-12)
    solver = mbm.MBM(EX2, 0.0, EX2_Y0, 80.0, approximant="salas-torque", anchors="events")
    ends = []
    while solver.status == "running":
        assert solver.step() is None
        ends.append(solver.t)
    np.testing.assert_array_equal(ends[:-1], te)
    assert ends[-1] == 80.0
    # Event times agree with an independent DOP853 at 1e-12 to 1e-8.
    def crossing(t, y):
        return y[0] - d

    def turning(t, y):
        return y[1]

    dop = solve_ivp(EX2, (0.0, 80.0), EX2_Y0, method="DOP853", rtol=1e-12, atol=1e-12, events=[crossing, turning])
    dop_t = np.sort(np.concatenate(dop.t_events))
    dop_t = dop_t[dop_t > 0.0]  # the start θ'(0) = 0 is a turning point DOP853 reports
    np.testing.assert_allclose(te, dop_t, atol=1e-8)


def test_hybrid_jump_is_the_window_error():
    # (3.32) anchors each window at CVODE's state: the dense output jumps at event points
    # by the previous window's error.
    solver = mbm.MBM(EX2, 0.0, EX2_Y0, 80.0, approximant="salas-torque", anchors="events")
    solver.step()
    y_end = solver.y.copy()
    t_end = solver.t
    solver.step()
    anchor = solver.dense_output()(t_end)
    jump = np.abs(anchor - y_end)
    assert 0 < jump[0] < 0.05


def test_anchor_kind_must_be_met():
    class TurningOnly(SalasTorque):
        name = "test-turning-only"
        anchors = "turning-point"

    with pytest.raises(ValueError, match="turning points"):
        mbm.MBM(EX2, 0.0, [1.0, 0.3], 10.0, approximant=TurningOnly(), anchors="events")
    solver = mbm.MBM(EX2, 0.0, [1.0, 0.0], 10.0, approximant=TurningOnly(), anchors="events")
    while solver.status == "running":
        solver.step()
        if solver.status == "running":
            # every window boundary is a turning point of CVODE's solution
            assert abs(solver._next_anchor[1]) < 1e-8


def test_bad_mode_arguments():
    with pytest.raises(ValueError, match="anchors"):
        mbm.MBM(EX2, 0.0, EX2_Y0, 1.0, anchors="everywhere")
    with pytest.raises(ValueError, match="events_from"):
        mbm.MBM(EX2, 0.0, EX2_Y0, 1.0, anchors="events", events_from="rk4")
