"""Events of the compiled runs (mbm.events.compiled): located on the windows' formulas.

References: heyoka in long double at tol 1e-19 (nt_event), the exact section times,
the dense output of the same run, and numpy's polynomial roots for the isolation.
"""

import math

import numpy as np
import pytest

import mbm
from mbm.special.polyroots import crossings

hy = pytest.importorskip("heyoka")


def _heyoka_events(beta, gamma, y0, t_end, g, direction=None):
    # Event times of θ'' + βθ' + sin θ = γ by heyoka in long double (tol 1e-19).
    x, v = hy.make_vars("x", "v")
    found = []
    kw = {} if direction is None else {"direction": direction}
    ev = hy.nt_event(g(x, v), lambda ta, t, d: found.append(t), fp_type=np.longdouble, **kw)
    ta = hy.taylor_adaptive([(x, v), (v, gamma - beta * v - hy.sin(x))],
                            [np.longdouble(y0[0]), np.longdouble(y0[1])], fp_type=np.longdouble,
                            tol=np.longdouble(1e-19), nt_events=[ev])
    ta.propagate_until(np.longdouble(t_end))
    return np.array(found, dtype=np.longdouble)


def test_crossings_match_numpy_roots():
    rng = np.random.default_rng(7)
    xs, ds = np.empty(32), np.empty(32)
    for _ in range(300):
        roots = np.sort(rng.uniform(-0.5, 1.5, rng.integers(1, 8)))
        c = np.poly(roots)[::-1].copy() * rng.choice([-1.0, 1.0])
        m = crossings(c, c.size - 1, 1e-16, xs, ds)
        want = roots[(roots > 0.0) & (roots <= 1.0)]
        assert m == want.size
        np.testing.assert_allclose(xs[:m], want, atol=1e-9)
        # directions alternate, from the sign of p at 0
        if m:
            assert ds[0] == (1.0 if c[0] < 0.0 else -1.0)
            assert np.all(ds[1:m] == -ds[: m - 1])


def test_tangency_is_not_a_crossing_but_a_close_pair_is():
    xs, ds = np.empty(8), np.empty(8)
    c = np.poly([0.25, 0.25])[::-1].copy()  # a double root, exact in doubles: touches 0
    assert crossings(c, 2, 1e-16, xs, ds) == 0
    c = np.poly([0.5, 0.5 + 1e-9])[::-1].copy()  # two crossings 1e-9 apart
    assert crossings(c, 2, 1e-16, xs, ds) == 2
    assert list(ds[:2]) == [-1.0, 1.0]


def test_phase_slips_against_heyoka_long_double():
    # The scene: β = 0.1, γ = 1.2 from rest, cos(θ/2) = 0 over T = 1000.
    m = mbm.Pendulum(0.1, 1.2)
    r = mbm.solve(m, (0.0, 1000.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=mbm.angle_event(math.pi))
    ref = _heyoka_events(0.1, 1.2, (0.0, 0.0), 1000.0, lambda x, v: hy.cos(x / 2.0))
    t = r.t_events[0]
    assert r.status == 0 and r.regime == "running"
    assert t.size == ref.size == 1889
    err = np.abs(t - ref).astype(float)
    # Before the switch to the running cycle the windows' own crossings; after it the
    # stored period's, shifted by the refined period (R4) per turn: the target,
    # within 1e-10 at rtol 1e-9 over all 1889 (the averaged period alone, ~5e-13 off a
    # turn, gave 6.3e-10).
    assert err[t < r.t_regime].max() < 1e-10
    assert err.max() < 1e-10
    # The refined period against the reference's spacing of its last slips.
    t_ref = float(np.mean(np.diff(ref[-100:])))
    assert abs(r.period - t_ref) < 2e-14
    # θ = π + 2πm at each slip, m = 0, 1, 2, ...
    np.testing.assert_array_equal(r.winding_events[0], np.arange(t.size))
    np.testing.assert_allclose(r.y_events[0][:, 0], math.pi + 2 * math.pi * np.arange(t.size), rtol=1e-12)


def test_turning_points_against_heyoka_and_the_dense_output():
    # A damped swing that would lock: θ' = 0 at each turning point (no locked regime
    # while events are watched, so every turning point is a window's crossing).
    m = mbm.Pendulum(0.3, 0.2)
    y0 = [2.0, 0.0]
    r = mbm.solve(m, (0.0, 40.0), y0, rtol=1e-10, atol=1e-10, events=mbm.velocity_event(0.0))
    ref = _heyoka_events(0.3, 0.2, y0, 40.0, lambda x, v: v)
    ref = ref[ref > 0]  # heyoka reports the start (θ' = 0 there); an event at t0 is not one
    assert r.t_events[0].size == ref.size > 5
    np.testing.assert_allclose(r.t_events[0], ref.astype(float), atol=1e-9, rtol=0)
    assert np.all(np.abs(r.y_events[0][:, 1]) < 1e-12)
    # The event states are the run's dense output at the event times, bit for bit.
    d = mbm.solve(m, (0.0, 40.0), y0, rtol=1e-10, atol=1e-10, t_eval=r.t_events[0],
                  events=mbm.velocity_event(0.0))
    np.testing.assert_array_equal(d.y.T, r.y_events[0])


def test_direction_selects_crossings():
    m = mbm.Pendulum(0.3, 0.2)
    both = mbm.solve(m, (0.0, 40.0), [2.0, 0.0], rtol=1e-10, atol=1e-10, events=mbm.velocity_event(0.0))
    up = mbm.solve(m, (0.0, 40.0), [2.0, 0.0], rtol=1e-10, atol=1e-10,
                   events=[mbm.velocity_event(0.0, direction=1), mbm.velocity_event(0.0, direction=-1)])
    merged = np.sort(np.concatenate(up.t_events))
    np.testing.assert_array_equal(merged, both.t_events[0])
    # the first turning point from θ = 2 at rest swings back: θ' goes from − to +
    assert up.t_events[0][0] == both.t_events[0][0]
    ref_up = _heyoka_events(0.3, 0.2, (2.0, 0.0), 40.0, lambda x, v: v, direction=hy.event_direction.positive)
    ref_up = ref_up[ref_up > 0]
    assert up.t_events[0].size == ref_up.size


def test_terminal_event_stops_the_run():
    m = mbm.Pendulum(0.1, 1.2)
    ev = mbm.angle_event(math.pi, terminal=3)
    for t_eval in (None, np.linspace(0.0, 100.0, 1001)):
        r = mbm.solve(m, (0.0, 100.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=ev, t_eval=t_eval)
        assert r.status == 6 and r.success
        assert r.t_events[0].size == 3
        t3 = r.t_events[0][-1]
        assert r.t[-1] <= t3
        if t_eval is None:
            assert r.t[-1] == t3
            np.testing.assert_array_equal(r.y[:, -1], r.y_events[0][-1])
        else:
            assert r.t.size == np.count_nonzero(t_eval <= t3)
    full = mbm.solve(m, (0.0, 100.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=mbm.angle_event(math.pi))
    np.testing.assert_array_equal(full.t_events[0][:3], r.t_events[0])


def test_event_at_t0_is_not_reported_and_section_times_are_exact():
    m = mbm.Pendulum(0.1, 1.2)
    r = mbm.solve(m, (0.0, 10.0), [math.pi, 1.0], rtol=1e-9, atol=1e-9, events=mbm.angle_event(math.pi))
    assert r.t_events[0].size > 0 and r.t_events[0][0] > 0.0
    d = mbm.Pendulum(0.5, 0.3, drive_amplitude=0.8, drive_frequency=0.7, drive_phase=0.2)
    r = mbm.solve(d, (0.0, 60.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=mbm.section_event(1.0))
    want = (1.0 + 2 * math.pi * np.arange(0, 10) - 0.2) / 0.7
    want = want[(want > 0.0) & (want <= 60.0)]
    np.testing.assert_allclose(r.t_events[0], want, rtol=1e-15)
    assert r.regime is None  # the phase-locked regime is not taken while events are watched
    dense = mbm.solve(d, (0.0, 60.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, t_eval=r.t_events[0],
                      events=mbm.section_event(1.0))
    np.testing.assert_array_equal(dense.y.T, r.y_events[0])


def test_backward_run_finds_the_same_turning_points():
    m = mbm.Pendulum(0.3, 0.2)
    fwd = mbm.solve(m, (0.0, 10.0), [2.0, 0.0], rtol=1e-12, atol=1e-12, t_eval=[10.0])
    back = mbm.solve(m, (10.0, 0.0), fwd.y[:, -1], rtol=1e-12, atol=1e-12, events=mbm.velocity_event(0.0))
    ahead = mbm.solve(m, (0.0, 10.0), [2.0, 0.0], rtol=1e-12, atol=1e-12, events=mbm.velocity_event(0.0))
    np.testing.assert_allclose(back.t_events[0][::-1], ahead.t_events[0], atol=1e-8)


def test_integrator_and_solve_agree_bit_for_bit():
    m = mbm.Pendulum(0.1, 1.2)
    ev = [mbm.angle_event(math.pi), mbm.velocity_event(1.5)]
    a = mbm.solve(m, (0.0, 300.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=ev)
    b = mbm.Integrator(m, rtol=1e-9, atol=1e-9).solve((0.0, 300.0), [0.0, 0.0], events=ev)
    for i in range(2):
        np.testing.assert_array_equal(a.t_events[i], b.t_events[i])
        np.testing.assert_array_equal(a.y_events[i], b.y_events[i])


def test_bad_events_are_refused():
    m = mbm.Pendulum(0.1, 1.2)
    with pytest.raises(TypeError, match="numba|solve_ivp"):
        mbm.solve(m, (0.0, 1.0), [0.0, 0.0], events=lambda t, y: y[0])
    with pytest.raises(TypeError, match="events must be"):
        mbm.solve(m, (0.0, 1.0), [0.0, 0.0], events=[])
    with pytest.raises(ValueError, match="Taylor"):
        mbm.solve(m, (0.0, 1.0), [0.0, 0.0], approximant="split4", tau=0.1, events=mbm.angle_event(0.0))
    with pytest.raises(ValueError, match="driven"):
        mbm.solve(m, (0.0, 1.0), [0.0, 0.0], events=mbm.section_event(0.0))
    with pytest.raises(ValueError, match="terminal"):
        mbm.angle_event(0.0, terminal=0)
    with pytest.raises(TypeError, match="terminal"):
        mbm.angle_event(0.0, terminal="yes")
    with pytest.raises(ValueError, match="modulo must be > 0"):
        mbm.angle_event(0.0, modulo=-1.0)
    with pytest.raises(TypeError, match="value must be a real number"):
        mbm.velocity_event("0")


def test_undamped_auto_runs_taylor_with_events():
    # β = γ = 0: "auto" is the exact flow without events, the Taylor series with them.
    m = mbm.Pendulum(0.0, 0.0)
    r = mbm.solve(m, (0.0, 30.0), [1.0, 0.0], rtol=1e-11, atol=1e-11, events=mbm.velocity_event(0.0))
    assert r.approximant.startswith("taylor")
    T = mbm.period(m, [1.0, 0.0])
    np.testing.assert_allclose(r.t_events[0], T / 2 * np.arange(1, r.t_events[0].size + 1), atol=1e-8)


@pytest.mark.parametrize("events", [
    [mbm.angle_event(math.pi), mbm.velocity_event(1.5)],  # running cycle: both shiftable
    [mbm.angle_event(1.0, modulo=math.pi)],  # modulo != 2π: turns walked, not skipped
])
def test_max_events_stores_the_first_and_counts_all(events):
    # Counting past the cap (whole cycle turns counted, not walked) gives the counts of
    # the run that stores every event, and the stored ones are its first, bit for bit.
    m = mbm.Pendulum(0.1, 1.2)
    full = mbm.solve(m, (0.0, 3000.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=events)
    assert full.regime == "running" and full.t_regime < 1000.0
    for k in (1, 7, 500):
        r = mbm.solve(m, (0.0, 3000.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=events, max_events=k)
        assert r.n_events.tolist() == [t.size for t in full.t_events]
        for e in range(len(events)):
            np.testing.assert_array_equal(r.t_events[e], full.t_events[e][:k])
            np.testing.assert_array_equal(r.y_events[e], full.y_events[e][:k])
            np.testing.assert_array_equal(r.winding_events[e], full.winding_events[e][:k])
    assert full.n_events.tolist() == [t.size for t in full.t_events]


def test_terminal_event_past_the_cap_stops_where_the_full_run_does():
    # The 4000th slip is deep in the running cycle: counted turns must stop on it.
    m = mbm.Pendulum(0.1, 1.2)
    full = mbm.solve(m, (0.0, 3000.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=mbm.angle_event(math.pi))
    assert full.t_events[0].size > 4000
    stop = mbm.angle_event(math.pi, terminal=4000)
    r = mbm.solve(m, (0.0, 3000.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=stop, max_events=3)
    assert r.status == 6 and r.n_events.tolist() == [4000]
    np.testing.assert_array_equal(r.t_events[0], full.t_events[0][:3])
    assert r.t[-1] == full.t_events[0][3999]
    np.testing.assert_array_equal(r.y[:, -1], full.y_events[0][3999])


def test_bad_max_events_is_refused():
    m = mbm.Pendulum(0.1, 1.2)
    ev = mbm.angle_event(0.0)
    for bad in (0, -3):
        with pytest.raises(ValueError, match="max_events must be an int >= 1"):
            mbm.solve(m, (0.0, 1.0), [0.0, 0.0], events=ev, max_events=bad)
    for bad in (2.0, True, "3"):
        with pytest.raises(TypeError, match="max_events must be an int >= 1"):
            mbm.solve(m, (0.0, 1.0), [0.0, 0.0], events=ev, max_events=bad)
    with pytest.raises(ValueError, match="max_events needs events"):
        mbm.solve(m, (0.0, 1.0), [0.0, 0.0], max_events=3)
    with pytest.raises(ValueError, match="max_events needs events"):
        mbm.Integrator(m).solve((0.0, 1.0), [0.0, 0.0], max_events=3)


def test_locked_regime_is_taken_where_no_level_is_reachable():
    # β = 0.3, γ = 0.2 from θ = 2 settles on θ* = arcsin 0.2: θ ≡ π is never crossed
    # after the lock, so the locked closed form ends the run; the events before it are
    # those of the run without the locked regime (velocity 0 keeps it off), bit for bit.
    m = mbm.Pendulum(0.3, 0.2)
    kw = dict(rtol=1e-9, atol=1e-9)
    both = mbm.solve(m, (0.0, 500.0), [2.0, 2.5], events=[mbm.angle_event(math.pi), mbm.velocity_event(0.0)], **kw)
    alone = mbm.solve(m, (0.0, 500.0), [2.0, 2.5], events=mbm.angle_event(math.pi), **kw)
    assert both.regime is None and alone.regime == "locked" and alone.n_windows < both.n_windows
    assert alone.t_events[0].size >= 1
    np.testing.assert_array_equal(alone.t_events[0], both.t_events[0])
    ref = _heyoka_events(0.3, 0.2, (2.0, 2.5), 500.0, lambda x, v: hy.cos(x / 2.0))
    assert ref.size == alone.t_events[0].size
    np.testing.assert_allclose(alone.t_events[0], ref.astype(float), atol=1e-7)
    fast = mbm.solve(m, (0.0, 500.0), [2.0, 2.5], events=mbm.velocity_event(1.0), **kw)
    assert fast.regime == "locked"


def test_a_level_the_locked_form_may_reach_runs_without_it():
    # A level 1e-4 above the equilibrium is crossed by the settling swings long after a
    # lock would be allowed: the run is taken again without the locked regime.
    m = mbm.Pendulum(0.3, 0.2)
    kw = dict(rtol=1e-9, atol=1e-9)
    level = math.asin(0.2) + 1e-4
    near = mbm.solve(m, (0.0, 100.0), [2.0, 0.0], events=mbm.angle_event(level), **kw)
    off = mbm.solve(m, (0.0, 100.0), [2.0, 0.0], events=[mbm.angle_event(level), mbm.velocity_event(0.0)], **kw)
    far = mbm.solve(m, (0.0, 100.0), [2.0, 0.0], events=mbm.angle_event(math.pi), **kw)
    assert far.regime == "locked" and near.regime is None  # the lock was taken, then undone
    np.testing.assert_array_equal(near.t_events[0], off.t_events[0])
    ref = _heyoka_events(0.3, 0.2, (2.0, 0.0), 100.0, lambda x, v: hy.sin((x - level) / 2.0))
    assert ref.size == near.t_events[0].size > 10
    b = mbm.solve_batch(0.3, [0.2, 0.2], 1.0, [2.0, 0.0], (0.0, 100.0), [], events=mbm.angle_event(level), **kw)
    np.testing.assert_array_equal(b.t_events[1, 0, : near.n_events[0]], near.t_events[0])
    assert list(b.regime) == [None, None]
