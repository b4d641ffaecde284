"""Events on a stored running cycle: whole turns written in one sweep (event_watch._fill_turns).

Caps and terminal counts change which turns are written by the sweep and which are
walked event by event (:func:`mbm.core.event_watch._block_turns`), so a capped or
stopped run must agree bit for bit with the first events of the uncapped run: the two
paths against each other.
"""

import math

import numpy as np
import pytest

import mbm

SCENE = mbm.Pendulum(0.3, 1.5)  # running: the run switches to its stored cycle early
SPAN = (0.0, 3e4)
TOL = dict(rtol=1e-9, atol=1e-9)


def _events():
    return [mbm.angle_event(0.5), mbm.velocity_event(5.0)]


def _same(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


@pytest.fixture(scope="module")
def uncapped():
    r = mbm.solve(SCENE, SPAN, [0.0, 0.0], events=_events(), **TOL)
    assert r.regime == "running" and r.t_regime < 500.0
    assert r.t_events[0].size > 20000 and r.t_events[1].size > 20000  # both kinds, every turn
    return r


@pytest.mark.parametrize("cap", [1, 777, 20000])
def test_capped_runs_store_the_first_events_bit_for_bit(uncapped, cap):
    r = mbm.solve(SCENE, SPAN, [0.0, 0.0], events=_events(), max_events=cap, **TOL)
    assert np.array_equal(r.n_events, uncapped.n_events)  # every occurrence counted
    for e in range(2):
        assert _same(r.t_events[e], uncapped.t_events[e][:cap])
        assert _same(r.y_events[e], uncapped.y_events[e][:cap])
        assert _same(r.winding_events[e], uncapped.winding_events[e][:cap])


@pytest.mark.parametrize("stop", [3, 5000])
def test_a_terminal_event_stops_where_the_uncapped_run_has_it(uncapped, stop):
    r = mbm.solve(SCENE, SPAN, [0.0, 0.0], events=mbm.angle_event(0.5, terminal=stop), **TOL)
    assert r.status == mbm.status.STATUS_EVENT and r.n_events[0] == stop
    assert _same(r.t_events[0], uncapped.t_events[0][:stop])
    assert _same(r.y_events[0], uncapped.y_events[0][:stop])
    assert r.t[-1] == uncapped.t_events[0][stop - 1]


def test_cycle_events_repeat_with_the_period(uncapped):
    # After the switch each turn's slip is the stored period's shifted by T_c: the same θ'
    # (to the bit), θ advanced by 2π, times spaced by the period.
    after = uncapped.t_events[0] > uncapped.t_regime + uncapped.period
    t, y, w = uncapped.t_events[0][after], uncapped.y_events[0][after], uncapped.winding_events[0][after]
    assert np.all(y[:, 1] == y[0, 1])
    assert np.all(np.diff(w) == 1)
    np.testing.assert_allclose(np.diff(t), uncapped.period, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(np.diff(y[:, 0]), 2 * math.pi, rtol=0, atol=1e-9)
