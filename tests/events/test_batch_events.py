"""Events of mbm.solve_batch: every scene's events those of mbm.solve, bit for bit.

Reference: mbm.solve on each scene (itself checked against heyoka long double in
tests/events/test_crossings.py); the batch runs the same windows in compiled groups.
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


def _events_are_solve_events(r, i, s, nev):
    np.testing.assert_array_equal(r.n_events[i], s.n_events)
    for e in range(nev):
        k = s.t_events[e].size
        np.testing.assert_array_equal(r.t_events[i, e, :k], s.t_events[e])
        np.testing.assert_array_equal(r.y_events[i, e, :k], s.y_events[e])
        np.testing.assert_array_equal(r.winding_events[i, e, :k], s.winding_events[e])


@pytest.mark.parametrize("te", [np.empty(0), np.array([0.0, 5.0, 12.5])])
def test_trapped_scenes_end_with_their_outputs_and_events_those_of_solve(te):
    # From rest, γ below ~0.775 never slips at β = 0.1: once its energy is below both
    # barriers (at once for γ < ~0.72, after a swing or more above) and its outputs are
    # written, the scene ends, locked, where mbm.solve runs ~150 time units more to its
    # locked form.  Its events and outputs are mbm.solve's all the same.
    gammas = np.linspace(0.0, 1.2, 25)
    events = [mbm.angle_event(math.pi), mbm.velocity_event(2.5), mbm.angle_event(-1.0, modulo=4 * math.pi)]
    span = (0.0, 300.0)
    r = mbm.solve_batch(0.1, gammas, 1.0, [0.0, 0.0], span, te, rtol=1e-9, atol=1e-9, events=events)
    trapped = np.zeros(gammas.size, bool)
    for i, g in enumerate(gammas):
        s = mbm.solve(mbm.Pendulum(0.1, g), span, [0.0, 0.0], t_eval=te if te.size else None, rtol=1e-9,
                      atol=1e-9, events=events)
        _events_are_solve_events(r, i, s, len(events))
        assert r.status[i] == s.status == 0
        if te.size:
            np.testing.assert_array_equal(r.y[i], s.y)
        if r.n_windows[i] < s.n_windows:
            trapped[i] = True
            assert r.regime[i] == s.regime == "locked" and r.mean_velocity[i] == 0.0
            assert (te[-1] if te.size else 0.0) <= r.t_regime[i] <= s.t_regime
            if g > 0.0:
                # ended within a few swings of its last output, not at the locked form's switch
                assert r.t_regime[i] < (te[-1] if te.size else 0.0) + 40.0 < s.t_regime
        else:
            assert r.n_windows[i] == s.n_windows and r.regime[i] == s.regime
    # The never-slipping scenes, those near the threshold after their first swings (γ = 0
    # rests at θ* = 0: with outputs to write, mbm.solve's locked form takes it at once).
    assert np.array_equal(trapped, (gammas < 0.77) & ((gammas > 0.0) | (te.size == 0)))
    assert np.any((gammas > 0.72) & (gammas < 0.77) & (r.t_regime > 1.0))


def test_trapped_random_scenes_count_the_events_solve_counts():
    # Damped undriven scenes from random states (some slipping, some trapped at once,
    # some after turns), non-terminal angle events at random levels: the batch ends its
    # trapped scenes early, and each scene's events are mbm.solve's over the whole span.
    rng = np.random.default_rng(29)
    n = 40
    beta, gamma = rng.uniform(0.05, 0.6, n), rng.uniform(-0.95, 0.95, n)
    y0 = [rng.uniform(-4.0, 4.0), rng.uniform(-3.0, 3.0)]
    events = [mbm.angle_event(float(rng.uniform(-math.pi, math.pi))), mbm.angle_event(0.3, direction=-1.0)]
    span = (0.0, 400.0)
    r = mbm.solve_batch(beta, gamma, 1.0, y0, span, [], rtol=1e-8, atol=1e-8, events=events)
    shorter = 0
    for i in range(n):
        s = mbm.solve(mbm.Pendulum(beta[i], gamma[i]), span, y0, rtol=1e-8, atol=1e-8, events=events)
        _events_are_solve_events(r, i, s, len(events))
        shorter += r.n_windows[i] < s.n_windows
    assert shorter > n // 4


def test_trap_waits_while_an_event_is_reachable():
    # θ' = 0 (every swing's turning points) keeps the locked regime and the trap off.
    events = [mbm.angle_event(math.pi), mbm.velocity_event(0.0)]
    r = mbm.solve_batch(0.1, [0.3], 1.0, [2.0, 0.0], (0.0, 300.0), [], rtol=1e-9, atol=1e-9, events=events)
    s = mbm.solve(mbm.Pendulum(0.1, 0.3), (0.0, 300.0), [2.0, 0.0], rtol=1e-9, atol=1e-9, events=events)
    assert r.n_windows[0] == s.n_windows and r.regime[0] is s.regime is None
    _events_are_solve_events(r, 0, s, len(events))
    # An angle level inside the well (θ* = arcsin 0.3 ≈ 0.305): crossed while the swings
    # reach it, and the scene ends only after the last crossing.
    events = [mbm.angle_event(0.5)]
    r = mbm.solve_batch(0.1, [0.3], 1.0, [2.0, 0.0], (0.0, 300.0), [], rtol=1e-9, atol=1e-9, events=events)
    s = mbm.solve(mbm.Pendulum(0.1, 0.3), (0.0, 300.0), [2.0, 0.0], rtol=1e-9, atol=1e-9, events=events)
    _events_are_solve_events(r, 0, s, 1)
    assert s.n_events[0] > 5 and s.t_events[0][-1] < r.t_regime[0] < s.t_regime
    assert r.n_windows[0] < s.n_windows


def test_trapped_unreachable_bounds():
    from mbm.core.event_watch import EV_ANGLE, EV_VELOCITY, trapped_unreachable

    g, w, tol = 0.5, 1.0, 1e-9
    d = math.asin(g)
    # The right barrier x_r = π − d, its energy above θ*: U(x_r) − U(θ*) = 2 cos d − γ(π − 2d).
    barrier = 2.0 * math.cos(d) - g * (math.pi - 2.0 * d)
    angle_pi = np.array([[EV_ANGLE, math.pi, 2.0 * math.pi, 0.0, 0.0]])
    for h, trapped in ((0.5 * barrier, True), (barrier * (1.0 - 1e-4), True), (barrier * (1.0 - 1e-7), False),
                       (barrier * (1.0 + 1e-9), False)):
        v = math.sqrt(2.0 * h)  # at θ*: H = v²/2
        assert trapped_unreachable(d, v, angle_pi, g, w, tol, tol, d) is trapped, h / barrier
    # A level the swing reaches (θ* + 0.5 at amplitude ~1), and one it does not.
    inside = np.array([[EV_ANGLE, d + 0.5, 2.0 * math.pi, 0.0, 0.0]])
    assert not trapped_unreachable(d, 1.0, inside, g, w, tol, tol, d)
    assert trapped_unreachable(d, 0.3, inside, g, w, tol, tol, d)
    # Velocity levels: |θ'| ≤ sqrt(2H) for ever.
    vel = np.array([[EV_VELOCITY, 0.29, 0.0, 0.0, 0.0]])
    assert trapped_unreachable(d, 0.3, vel, g, w, tol, tol, d) is False
    vel[0, 1] = 0.31
    assert trapped_unreachable(d, 0.3, vel, g, w, tol, tol, d)
    # A section event (a driven scene) is never unreachable; nor a state past a barrier.
    section = np.array([[2.0, 0.0, 0.0, 0.0, 0.0]])
    assert not trapped_unreachable(d, 0.1, section, g, w, tol, tol, d)
    assert not trapped_unreachable(math.pi - d + 0.1, 0.0, angle_pi, g, w, tol, tol, d)
