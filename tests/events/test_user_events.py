"""Event functions of one's own (mbm.events.functions): a numba.njit g(t, θ, θ') watched on
the windows of mbm.solve and Integrator.solve.

References: heyoka in long double at tol 1e-19 (nt_event), the built-in events of the
same run (roots of the same polynomials), the exact section times of a drive, and the
dense output of the same run.
"""

import math

import numba
import numpy as np
import pytest

import mbm

hy = pytest.importorskip("heyoka")


def _heyoka_events(beta, gamma, y0, t_end, g):
    # Event times of θ'' + βθ' + sin θ = γ by heyoka in long double (tol 1e-19).
    x, v = hy.make_vars("x", "v")
    found = []
    ev = hy.nt_event(g(x, v), lambda ta, t, d: found.append(t), fp_type=np.longdouble)
    ta = hy.taylor_adaptive([(x, v), (v, gamma - beta * v - hy.sin(x))],
                            [np.longdouble(y0[0]), np.longdouble(y0[1])], fp_type=np.longdouble,
                            tol=np.longdouble(1e-19), nt_events=[ev])
    ta.propagate_until(np.longdouble(t_end))
    return np.array(found, dtype=np.longdouble)


@numba.njit
def slip(t, theta, theta_dot):
    return math.cos(0.5 * theta)


@numba.njit
def speed(t, theta, theta_dot):
    return theta_dot - 1.5


@numba.njit
def pair(t, theta, theta_dot):
    return (theta - 1.0) * (theta - 1.1)


def _fresh(g, **attributes):
    # A new dispatcher of g's function with its own scipy attributes.
    f = numba.njit(g.py_func)
    for name, value in attributes.items():
        setattr(f, name, value)
    return f


def test_phase_slips_of_a_function_against_heyoka_long_double():
    m = mbm.Pendulum(0.1, 1.2)
    r = mbm.solve(m, (0.0, 1000.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=slip)
    ref = _heyoka_events(0.1, 1.2, (0.0, 0.0), 1000.0, lambda x, v: hy.cos(x / 2.0))
    assert r.status == 0 and r.regime is None  # no regime while g is watched
    t = r.t_events[0]
    assert t.size == ref.size == 1889 and r.n_events[0] == 1889
    assert np.abs(t - ref).astype(float).max() < 1e-9
    np.testing.assert_allclose(r.y_events[0][:, 0], math.pi + 2 * math.pi * np.arange(t.size), rtol=1e-12)


def test_function_and_builtin_events_of_one_run_agree():
    # The same level as a function and as a built-in event, in one run: roots of the
    # same windows' polynomials, by Brent's method and by the Bernstein isolation.
    m = mbm.Pendulum(0.1, 1.2)
    r = mbm.solve(m, (0.0, 200.0), [0.0, 0.0], rtol=1e-9, atol=1e-9,
                  events=[mbm.angle_event(math.pi), slip, mbm.velocity_event(1.5), speed])
    assert r.t_events[0].size == r.t_events[1].size > 300
    # Each refined to TIME_ULPS (2) spacings of the doubles at t: within 4 of each other.
    for a, b in ((1, 0), (3, 2)):
        assert np.all(np.abs(r.t_events[a] - r.t_events[b]) <= 4 * np.spacing(r.t_events[b]))
    assert r.t_events[2].size == 1
    # θ's winding count round(θ/2π) for a function's events.
    np.testing.assert_array_equal(r.winding_events[1], np.floor((r.y_events[1][:, 0] + math.pi) / (2 * math.pi)))


def test_event_states_are_the_dense_output():
    m = mbm.Pendulum(0.3, 0.2)
    r = mbm.solve(m, (0.0, 40.0), [2.0, 0.0], rtol=1e-10, atol=1e-10, events=speed)
    turning = _fresh(speed, direction=0.0)
    d = mbm.solve(m, (0.0, 40.0), [2.0, 0.0], rtol=1e-10, atol=1e-10, events=turning)
    assert r.t_events[0].size == 0 and d.t_events[0].size == 0  # θ' never reaches 1.5 here

    @numba.njit
    def v0(t, theta, theta_dot):
        return theta_dot

    r = mbm.solve(m, (0.0, 40.0), [2.0, 0.5], rtol=1e-10, atol=1e-10, events=v0)
    ref = _heyoka_events(0.3, 0.2, (2.0, 0.5), 40.0, lambda x, v: v)
    assert r.t_events[0].size == ref.size > 5
    np.testing.assert_allclose(r.t_events[0], ref.astype(float), atol=1e-9, rtol=0)
    d = mbm.solve(m, (0.0, 40.0), [2.0, 0.5], rtol=1e-10, atol=1e-10, t_eval=r.t_events[0], events=v0)
    np.testing.assert_array_equal(d.y.T, r.y_events[0])


def test_a_time_dependent_function_finds_the_drive_sections():
    m = mbm.Pendulum(0.2, 0.3, drive_amplitude=0.8, drive_frequency=0.7, drive_phase=0.4)

    @numba.njit
    def section(t, theta, theta_dot):
        return math.sin(0.5 * (0.7 * t + 0.4 - 1.0))  # 0 where 0.7 t + 0.4 = 1 + 2πm

    r = mbm.solve(m, (0.0, 60.0), [0.0, 0.0], rtol=1e-10, atol=1e-10, events=section)
    exact = (1.0 + 2 * math.pi * np.arange(0, 8) - 0.4) / 0.7
    exact = exact[(exact > 0) & (exact <= 60.0)]
    np.testing.assert_allclose(r.t_events[0], exact, rtol=0, atol=1e-12)
    s = mbm.solve(m, (0.0, 60.0), [0.0, 0.0], rtol=1e-10, atol=1e-10,
                  events=[mbm.section_event(1.0), section])
    np.testing.assert_allclose(s.t_events[1], s.t_events[0], rtol=0, atol=1e-12)


def test_two_crossings_in_one_window_and_a_tangency():
    m = mbm.Pendulum(0.1, 1.2)
    r = mbm.solve(m, (0.0, 20.0), [0.0, 0.0], rtol=1e-9, atol=1e-9,
                  events=[pair, mbm.angle_event(1.0, modulo=1000.0), mbm.angle_event(1.1, modulo=1000.0)])
    both = np.sort(np.concatenate(r.t_events[1:]))
    assert r.t_events[0].size == 2
    np.testing.assert_allclose(r.t_events[0], both, rtol=0, atol=1e-13)
    # They lie in one window of the run (its window ends).
    ends = mbm.solve(m, (0.0, 20.0), [0.0, 0.0], rtol=1e-9, atol=1e-9).t
    assert np.searchsorted(ends, both[0]) == np.searchsorted(ends, both[1])

    @numba.njit
    def touch(t, theta, theta_dot):
        return theta_dot * theta_dot  # 0 at each turning point without changing sign

    r = mbm.solve(mbm.Pendulum(0.3, 0.2), (0.0, 40.0), [2.0, 0.0], rtol=1e-10, atol=1e-10, events=touch)
    assert r.t_events[0].size == 0 and r.n_events[0] == 0


def test_terminal_direction_and_the_span_ends():
    m = mbm.Pendulum(0.1, 1.2)
    every = mbm.solve(m, (0.0, 100.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=slip).t_events[0]
    rising = _fresh(slip, direction=1.0, terminal=3)
    r = mbm.solve(m, (0.0, 100.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=rising)
    # cos(θ/2) rises through 0 at θ = 3π, 7π, ...: the 2nd, 4th, 6th slips.
    np.testing.assert_array_equal(r.t_events[0], every[1:6:2])
    assert r.status == 6 and r.success and r.t[-1] == every[5]
    np.testing.assert_array_equal(r.y[:, -1], r.y_events[0][-1])
    first = mbm.solve(m, (0.0, 100.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=_fresh(slip, terminal=True),
                      t_eval=np.linspace(0.0, 10.0, 101))
    assert first.t_events[0].size == 1 and first.t[-1] <= every[0] < first.t[-1] + 0.1

    @numba.njit
    def theta(t, th, v):
        return th

    @numba.njit
    def at_end(t, th, v):
        return t - 50.0

    r = mbm.solve(m, (0.0, 50.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=[theta, at_end])
    assert r.t_events[0].size == 0  # θ = 0 at t0 only: not an event
    np.testing.assert_array_equal(r.t_events[1], [50.0])
    back = mbm.solve(m, (0.0, -30.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=slip)
    ref = _heyoka_events(0.1, 1.2, (0.0, 0.0), -30.0, lambda x, v: hy.cos(x / 2.0))
    assert back.t_events[0].size == ref.size > 50
    np.testing.assert_allclose(back.t_events[0], ref.astype(float), rtol=0, atol=1e-9)


def test_integrator_and_solve_agree_bit_for_bit():
    m = mbm.Pendulum(0.1, 1.2)
    ev = [slip, mbm.velocity_event(1.5)]
    a = mbm.solve(m, (0.0, 300.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, events=ev, max_events=50)
    b = mbm.Integrator(m, rtol=1e-9, atol=1e-9).solve((0.0, 300.0), [0.0, 0.0], events=ev, max_events=50)
    for i in range(2):
        np.testing.assert_array_equal(a.t_events[i], b.t_events[i])
        np.testing.assert_array_equal(a.y_events[i], b.y_events[i])
    np.testing.assert_array_equal(a.n_events, b.n_events)
    assert a.t_events[0].size == 50 and a.n_events[0] > 50


def test_bad_event_functions_are_refused():
    m = mbm.Pendulum(0.1, 1.2)
    with pytest.raises(TypeError, match="numba.njit"):
        mbm.solve(m, (0.0, 1.0), [0.0, 0.0], events=lambda t, th, v: th)
    with pytest.raises(ValueError, match="terminal"):
        mbm.solve(m, (0.0, 1.0), [0.0, 0.0], events=_fresh(slip, terminal=0))
    with pytest.raises(TypeError, match="terminal"):
        mbm.solve(m, (0.0, 1.0), [0.0, 0.0], events=_fresh(slip, terminal="yes"))
    with pytest.raises(TypeError, match="direction"):
        mbm.solve(m, (0.0, 1.0), [0.0, 0.0], events=_fresh(slip, direction="up"))

    @numba.njit
    def blows_up(t, th, v):
        return math.log(2.0 - t)

    with pytest.raises(ValueError, match="non-finite"):
        mbm.solve(m, (0.0, 5.0), [0.0, 0.0], events=blows_up)
    with pytest.raises(TypeError, match="numba.njit"):
        mbm.solve_batch(0.1, np.array([1.2, 1.3]), 1.0, np.zeros((2, 2)), (0.0, 1.0), np.array([1.0]),
                        events=lambda t, th, v: th)


def test_batch_scenes_are_mbm_solve_bit_for_bit():
    gammas = np.array([0.5, 1.05, 1.2, 1.5])
    te = np.linspace(0.0, 100.0, 11)
    ev = [_fresh(slip, terminal=2), mbm.velocity_event(1.5)]
    b = mbm.solve_batch(0.1, gammas, 1.0, np.zeros((4, 2)), (0.0, 100.0), te, rtol=1e-9, atol=1e-9, events=ev,
                        max_events=3)
    assert b.t_events.shape == (4, 2, 3) and b.n_events.shape == (4, 2)
    assert list(b.status) == [0, 6, 6, 6]  # γ = 0.5 < ω² never slips; the others stop at the 2nd slip
    for i, g in enumerate(gammas):
        r = mbm.solve(mbm.Pendulum(0.1, g), (0.0, 100.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, t_eval=te, events=ev,
                      max_events=3)
        assert (b.status[i], b.n_windows[i]) == (r.status, r.n_windows)
        np.testing.assert_array_equal(b.n_events[i], r.n_events)
        for e in range(2):
            k = r.t_events[e].size
            np.testing.assert_array_equal(b.t_events[i, e, :k], r.t_events[e])
            np.testing.assert_array_equal(b.y_events[i, e, :k], r.y_events[e])
            np.testing.assert_array_equal(b.winding_events[i, e, :k], r.winding_events[e])
            assert np.isnan(b.t_events[i, e, k:]).all()
        j = r.t.size
        np.testing.assert_array_equal(b.y[i][:, :j], r.y)
        assert np.isnan(b.y[i][:, j:]).all()


def test_wrap_and_a_driven_batch_with_a_function():
    m = mbm.Pendulum(0.1, 1.2)
    te = np.linspace(0.0, 30.0, 31)
    stop = _fresh(slip, terminal=3)
    a = mbm.solve(m, (0.0, 30.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, t_eval=te, wrap=True, events=stop)
    b = mbm.solve(m, (0.0, 30.0), [0.0, 0.0], rtol=1e-9, atol=1e-9, t_eval=te, events=stop)
    assert a.status == b.status == 6 and a.t.size == b.t.size
    np.testing.assert_array_equal(a.t_events[0], b.t_events[0])
    # θ = 2π·winding + y[0], the wrapped angle rounded once less than the unwrapped one.
    np.testing.assert_allclose(a.y[0] + 2 * np.pi * a.winding, b.y[0], rtol=0, atol=1e-13)
    c = mbm.solve_batch(0.1, np.array([1.2, 0.5]), 1.0, np.zeros((2, 2)), (0.0, 30.0), te, rtol=1e-9, atol=1e-9,
                        wrap=True, events=stop)
    np.testing.assert_array_equal(c.y[0][:, : a.t.size], a.y)
    np.testing.assert_array_equal(c.winding[0][: a.t.size], a.winding)
    events = [stop, mbm.section_event(1.0)]
    d = mbm.solve_batch(0.2, np.array([0.3, 0.6]), 1.0, np.zeros((2, 2)), (0.0, 60.0), 2 * te, rtol=1e-9,
                        atol=1e-9, drive_amplitude=0.8, drive_frequency=0.7, events=events)
    for i, g in enumerate((0.3, 0.6)):
        r = mbm.solve(mbm.Pendulum(0.2, g, 1.0, 0.8, 0.7), (0.0, 60.0), [0.0, 0.0], rtol=1e-9, atol=1e-9,
                      t_eval=2 * te, events=events)
        np.testing.assert_array_equal(d.n_events[i], r.n_events)
        for e in range(2):
            np.testing.assert_array_equal(d.t_events[i, e, : r.t_events[e].size], r.t_events[e])
