"""Events of mbm.solve_batch: every scene's events those of mbm.solve, bit for bit.

Reference: mbm.solve on each scene (itself checked against heyoka long double in
tests/test_crossings.py); the batch runs the same windows in compiled groups.
"""

import math

import numpy as np
import pytest

import mbm

GAMMAS = np.array([0.3, 0.9, 1.05, 1.2, 1.6, 2.0])  # locked, bistable, running


def _each_scene_is_solve(r, scenes, span, y0, t_eval, events, max_events=None, **kw):
    nev = len(events)
    for i, model in enumerate(scenes):
        s = mbm.solve(model, span, y0, t_eval=t_eval, events=events, max_events=max_events, **kw)
        assert r.status[i] == s.status
        assert r.n_windows[i] == s.n_windows
        np.testing.assert_array_equal(r.n_events[i], s.n_events)
        np.testing.assert_array_equal(r.y[i], s.y if s.y.shape[1] == r.y.shape[2] else np.pad(
            s.y, ((0, 0), (0, r.y.shape[2] - s.y.shape[1])), constant_values=np.nan))
        for e in range(nev):
            k = s.t_events[e].size
            np.testing.assert_array_equal(r.t_events[i, e, :k], s.t_events[e])
            np.testing.assert_array_equal(r.y_events[i, e, :k], s.y_events[e])
            np.testing.assert_array_equal(r.winding_events[i, e, :k], s.winding_events[e])
            assert np.all(np.isnan(r.t_events[i, e, k:]))


@pytest.mark.parametrize("max_events", [None, 4])
def test_batch_events_are_solve_events(max_events):
    events = [mbm.angle_event(math.pi), mbm.velocity_event(0.0)]
    te = np.linspace(0.0, 200.0, 11)
    r = mbm.solve_batch(0.1, GAMMAS, 1.0, [0.5, 0.0], (0.0, 200.0), te, rtol=1e-9, atol=1e-9, events=events,
                        max_events=max_events)
    k = r.t_events.shape[2]
    assert r.t_events.shape == (GAMMAS.size, 2, k) and r.y_events.shape == (GAMMAS.size, 2, k, 2)
    assert r.n_events.shape == (GAMMAS.size, 2) and r.n_events.dtype == np.int64
    if max_events is None:
        assert k == r.n_events.max()
    else:
        assert k == max_events and r.n_events.max() > max_events
    scenes = [mbm.Pendulum(0.1, g) for g in GAMMAS]
    _each_scene_is_solve(r, scenes, (0.0, 200.0), [0.5, 0.0], te, events, max_events, rtol=1e-9, atol=1e-9)


def test_first_slip_is_terminal_per_scene():
    te = np.linspace(0.0, 100.0, 101)
    ev = mbm.angle_event(math.pi, direction=1.0, terminal=True)
    r = mbm.solve_batch(0.1, GAMMAS, 1.0, [0.0, 0.0], (0.0, 100.0), te, rtol=1e-9, atol=1e-9, events=ev)
    slipped = r.n_events[:, 0] > 0
    assert slipped.any() and not slipped.all()  # the locked scene never slips
    assert np.all(r.status[slipped] == 6) and np.all(r.success)
    t1 = r.t_events[slipped, 0, 0]
    # no outputs after the slip, all before it
    assert np.array_equal(np.isnan(r.y[slipped, 0]), te[None, :] > t1[:, None])
    scenes = [mbm.Pendulum(0.1, g) for g in GAMMAS]
    _each_scene_is_solve(r, scenes, (0.0, 100.0), [0.0, 0.0], te, [ev], rtol=1e-9, atol=1e-9)


def test_driven_batch_sections_and_wrap():
    amp = np.array([0.5, 0.8, 1.2])
    te = np.linspace(0.0, 40.0, 5)
    events = [mbm.section_event(0.5), mbm.angle_event(0.0)]
    r = mbm.solve_batch(0.5, 0.3, 1.0, [0.0, 0.0], (0.0, 40.0), te, rtol=1e-9, atol=1e-9, drive_amplitude=amp,
                        drive_frequency=0.7, drive_phase=0.2, wrap=True, events=events)
    scenes = [mbm.Pendulum(0.5, 0.3, drive_amplitude=a, drive_frequency=0.7, drive_phase=0.2) for a in amp]
    for i, model in enumerate(scenes):
        s = mbm.solve(model, (0.0, 40.0), [0.0, 0.0], t_eval=te, rtol=1e-9, atol=1e-9, wrap=True, events=events)
        np.testing.assert_array_equal(r.winding[i], s.winding)
        np.testing.assert_array_equal(r.t_events[i, 0, : s.n_events[0]], s.t_events[0])
        np.testing.assert_array_equal(r.t_events[i, 1, : s.n_events[1]], s.t_events[1])


def test_auto_is_taylor_with_events_in_a_batch():
    # β = γ = 0 scenes: "auto" is the exact flow without events, Taylor with them (as mbm.solve).
    r = mbm.solve_batch(0.0, 0.0, 1.0, [1.0, 0.0], (0.0, 30.0), [30.0], rtol=1e-11, atol=1e-11,
                        events=mbm.velocity_event(0.0))
    assert r.approximant[0].startswith("taylor")
    T = mbm.period(mbm.Pendulum(0.0, 0.0), [1.0, 0.0])
    k = r.n_events[0, 0]
    np.testing.assert_allclose(r.t_events[0, 0, :k], T / 2 * np.arange(1, k + 1), atol=1e-8)


def test_bad_batch_events_are_refused():
    args = (0.1, [1.2, 1.3], 1.0, [0.0, 0.0], (0.0, 1.0), [1.0])
    with pytest.raises(ValueError, match="max_events needs events"):
        mbm.solve_batch(*args, max_events=3)
    with pytest.raises(ValueError, match="max_events must be"):
        mbm.solve_batch(*args, events=mbm.angle_event(0.0), max_events=0)
    with pytest.raises(TypeError, match="max_events must be"):
        mbm.solve_batch(*args, events=mbm.angle_event(0.0), max_events=2.0)
    with pytest.raises(TypeError, match="solve_ivp"):
        mbm.solve_batch(*args, events=lambda t, y: y[0])
    with pytest.raises(ValueError, match="scene 0 is not"):
        mbm.solve_batch(*args, events=mbm.section_event(0.0))
    with pytest.raises(ValueError, match="Taylor"):
        mbm.solve_batch(*args, approximant="split4", tau=0.1, events=mbm.angle_event(0.0))
