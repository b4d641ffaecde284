"""Events on a stored running cycle: whole turns written in one sweep (event_watch._fill_turns)
into buffers reserved at once (event_watch.cycle_events_bound), split per event (event_columns).

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


def _chunks(monkeypatch, events, **kw):
    # Each chunk's reserve (cycle_events_bound) and the events locate then appended.
    from mbm.events import compiled

    seen = []
    bound, locate = compiled.cycle_events_bound, compiled.locate

    def bound_spy(windows, ev, tally):
        b = bound(windows, ev, tally)
        seen.append([b, bool(np.any(windows[2][: windows[3], 0] == _cycle_tag()))])
        return b

    def locate_spy(windows, ev, tally, watch, found, lock):
        out = locate(windows, ev, tally, watch, found, lock)
        seen[-1].append(out[2] - found[2])
        return out

    monkeypatch.setattr(compiled, "cycle_events_bound", bound_spy)
    monkeypatch.setattr(compiled, "locate", locate_spy)
    r = mbm.solve(SCENE, SPAN, [0.0, 0.0], events=events, **TOL, **kw)
    return r, seen


def _cycle_tag():
    from mbm.regimes.cycle import CYCLE_TAG

    return CYCLE_TAG


def test_the_cycle_windows_events_are_reserved_at_once(monkeypatch):
    # Uncapped, the bound is the count the cycle window appends (one allocation); capped
    # or stopped, it is within the cap or the terminal count, not the horizon's turns.
    r, seen = _chunks(monkeypatch, mbm.angle_event(0.5))
    cyc = [s for s in seen if s[1]]
    assert len(cyc) == 1 and 20000 < cyc[0][2] <= cyc[0][0] <= cyc[0][2] + 2  # the turns the window meets
    assert all(s[0] == 0 for s in seen if not s[1])
    r, seen = _chunks(monkeypatch, _events(), max_events=777)
    assert all(s[2] <= s[0] <= 2 * 778 for s in seen if s[1])
    r, seen = _chunks(monkeypatch, mbm.angle_event(0.5, terminal=5000))
    assert all(s[2] <= s[0] <= 5001 for s in seen if s[1])


def test_event_columns_split_one_events_rows_as_numpy_gathers_them():
    from mbm.core.event_watch import event_columns

    rng = np.random.default_rng(52)
    evf = rng.normal(size=(1000, 4)) * 30.0
    evf[:, 3] = np.round(evf[:, 3])
    evi = rng.integers(0, 2, 1000)
    for e in range(2):
        for from_theta in (False, True):
            rows = evf[:990][evi[:990] == e]
            for k in (rows.shape[0], 7):
                cols = (np.empty(k), np.empty((k, 2)), np.empty(k, np.int64))
                assert event_columns((evf, evi, 990), e, cols, from_theta) == k
                want = np.floor((rows[:k, 1] + math.pi) / (2 * math.pi)) if from_theta else rows[:k, 3]
                assert _same(cols[0], rows[:k, 0].copy()) and _same(cols[1], rows[:k, 1:3].copy())
                assert _same(cols[2], want.astype(np.int64))
