"""mbm.solve_njit_events: the built-in events inside one's own numba code, the runs and
events of mbm.solve bit for bit (its reference: mbm.solve, itself checked against heyoka
in tests/events/test_crossings.py)."""

import math

import numba
import numpy as np
import pytest

import mbm

SCENES = [
    # (model, y0, span, events): running, lock-allowed, driven, undamped
    (mbm.Pendulum(0.1, 1.2), (0.0, 0.0), 300.0, [mbm.angle_event(math.pi), mbm.velocity_event(1.5)]),
    (mbm.Pendulum(0.3, 0.2), (2.0, 0.0), 80.0, [mbm.angle_event(math.pi, terminal=2), mbm.velocity_event(0.0)]),
    (mbm.Pendulum(0.4, 0.3), (1.0, 0.0), 200.0, [mbm.angle_event(0.0, modulo=100.0)]),
    (mbm.Pendulum(0.2, 0.3, 0.8, 0.7, 0.4), (0.0, 0.0), 60.0, [mbm.section_event(1.0), mbm.velocity_event(0.0)]),
    (mbm.Pendulum(0.0, 0.0), (1.0, 0.0), 30.0, [mbm.velocity_event(0.0, direction=-1)]),
]


@pytest.mark.parametrize("scene", range(len(SCENES)))
def test_njit_events_equal_mbm_solve_bit_for_bit(scene):
    m, y0, T, events = SCENES[scene]
    te = np.linspace(0.0, T, 41)
    out = np.empty((2, te.size))
    table = mbm.event_table(events)
    status, nw, t_ev, y_ev, w_ev, n_ev = mbm.solve_njit_events(
        m.beta, m.gamma, m.omega, 0.0, y0[0], y0[1], T, te, out, 1e-9, 1e-9, 10**7, table, 40,
        m.drive_amplitude, m.drive_frequency, m.drive_phase)
    r = mbm.solve(m, (0.0, T), y0, rtol=1e-9, atol=1e-9, t_eval=te, events=events, max_events=40)
    assert (status, nw) == (r.status, r.n_windows)
    np.testing.assert_array_equal(n_ev, r.n_events)
    assert n_ev.sum() > 0
    if scene == 2:
        assert r.regime == "locked"  # the level out of the locked form's reach
    for e in range(len(events)):
        k = r.t_events[e].size
        np.testing.assert_array_equal(t_ev[e, :k], r.t_events[e])
        np.testing.assert_array_equal(y_ev[e, :k], r.y_events[e])
        np.testing.assert_array_equal(w_ev[e, :k], r.winding_events[e])
        assert np.isnan(t_ev[e, k:]).all() and np.isnan(y_ev[e, k:]).all()
    j = r.t.size
    np.testing.assert_array_equal(out[:, :j], r.y)
    assert np.isnan(out[:, j:]).all()


def test_njit_events_end_a_trapped_scene_as_the_batch_does():
    # From rest at γ = 0.5 the scene never slips: with no outputs left it ends at once
    # (its energy is below both barriers), where mbm.solve runs on to its locked form.
    table = mbm.event_table(mbm.angle_event(math.pi, terminal=True))
    te, out = np.empty(0), np.empty((2, 0))
    status, nw, t_ev, y_ev, w_ev, n_ev = mbm.solve_njit_events(0.1, 0.5, 1.0, 0.0, 0.0, 0.0, 1000.0, te, out, 1e-9,
                                                               1e-9, 10**7, table, 1)
    r = mbm.solve(mbm.Pendulum(0.1, 0.5), (0.0, 1000.0), [0.0, 0.0], rtol=1e-9, atol=1e-9,
                  events=mbm.angle_event(math.pi, terminal=True))
    assert status == r.status == 0 and n_ev[0] == r.n_events[0] == 0 and np.isnan(t_ev).all()
    assert nw == 0 < r.n_windows and r.regime == "locked"


@numba.njit
def _first_slips(gammas, ev):
    t, out = np.empty(0), np.empty((2, 0))
    res = np.empty(gammas.size)
    for i in range(gammas.size):
        r = mbm.solve_njit_events(0.1, gammas[i], 1.0, 0.0, 0.0, 0.0, 1e3, t, out, 1e-9, 1e-9, 10**7, ev, 1)
        res[i] = r[2][0, 0]
    return res


def test_called_from_numba_code_as_the_docstring_shows():
    gammas = np.array([0.5, 1.05, 1.2, 1.5])
    table = mbm.event_table(mbm.angle_event(math.pi, terminal=True))
    first = _first_slips(gammas, table)
    b = mbm.solve_batch(0.1, gammas, 1.0, np.zeros((4, 2)), (0.0, 1e3), np.array([1e3]), rtol=1e-9, atol=1e-9,
                        events=mbm.angle_event(math.pi, terminal=True), max_events=1)
    np.testing.assert_array_equal(first, b.t_events[:, 0, 0])
    assert np.isnan(first[0]) and np.all(first[1:] > 0)  # γ = 0.5 < ω² locks: no slip


def test_bad_arguments_are_refused():
    with pytest.raises(ValueError, match="max_events"):
        mbm.solve_njit_events(0.1, 1.2, 1.0, 0.0, 0.0, 0.0, 1.0, np.empty(0), np.empty((2, 0)), 1e-9, 1e-9, 100,
                              mbm.event_table(mbm.angle_event(0.0)), 0)

    @numba.njit
    def g(t, th, v):
        return th

    with pytest.raises(TypeError, match="takes the built-in events"):
        mbm.event_table(g)
    with pytest.raises(TypeError, match="events must be"):
        mbm.event_table([1.0])


@numba.njit
def _slip(t, theta, theta_dot):
    return math.cos(0.5 * theta)


@pytest.mark.parametrize("direction, terminal", [(1.0, 3), (0.0, 0)])
def test_function_events_equal_mbm_solve_bit_for_bit(direction, terminal):
    te = np.linspace(0.0, 100.0, 11)
    out = np.empty((2, te.size))
    status, nw, t_ev, y_ev, count = mbm.solve_njit_function_events(
        0.1, 1.2, 1.0, 0.0, 0.0, 0.0, 100.0, te, out, 1e-9, 1e-9, 10**7, _slip, direction, terminal, 5)
    g = numba.njit(_slip.py_func)
    g.direction, g.terminal = direction, terminal if terminal else False
    r = mbm.solve(mbm.Pendulum(0.1, 1.2), (0.0, 100.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, t_eval=te, events=g,
                  max_events=5)
    assert (status, nw, count) == (r.status, r.n_windows, r.n_events[0])
    k = r.t_events[0].size
    assert k == 5 if not terminal else k == terminal
    np.testing.assert_array_equal(t_ev[:k], r.t_events[0])
    np.testing.assert_array_equal(y_ev[:k], r.y_events[0])
    assert np.isnan(t_ev[k:]).all()
    np.testing.assert_array_equal(out[:, : r.t.size], r.y)
    assert np.isnan(out[:, r.t.size:]).all()
    with pytest.raises(ValueError, match="max_events"):
        mbm.solve_njit_function_events(0.1, 1.2, 1.0, 0.0, 0.0, 0.0, 1.0, te[:0], out[:, :0], 1e-9, 1e-9, 100,
                                       _slip, 0.0, 0, 0)
