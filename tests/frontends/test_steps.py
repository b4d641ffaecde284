"""How `mbm.MBM` groups windows into solve_ivp steps, and the pieces that make a
short solve_ivp call cheap (a run record from a template, the store's width, the
"auto" choice): the same bits as the plain construction, every time."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm.core import record, window
from mbm.core.controller import CONTROLLER_ADAPTIVE, CONTROLLER_FIXED
from mbm.frontends import ivp as msolver
from mbm.approximants import get_approximant
from mbm.choice import choose_approximant
from mbm.scenes import get as scene


def _bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.int64)


class _Spy(mbm.MBM):
    """Records the windows per step in use and each step's window count and store size."""

    seen = []

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.steps = []
        _Spy.seen.append(self)

    def _step_impl(self):
        out = super()._step_impl()
        if self._windows is not None:
            starts, start_theta, coefs, n = self._windows
            self.steps.append((n, coefs.base.shape[0] if coefs.base is not None else coefs.shape[0]))
        return out


def _slip(t, y):
    return np.cos(y[0] / 2.0)


def test_auto_windows_per_step_follows_the_caller():
    sc = scene("P2")
    _Spy.seen.clear()
    solve_ivp(sc.model, sc.t_span, sc.y0_array, method=_Spy, t_eval=sc.t_eval(201))
    solve_ivp(sc.model, sc.t_span, sc.y0_array, method=_Spy)  # every window end reported
    solve_ivp(sc.model, sc.t_span, sc.y0_array, method=_Spy, t_eval=sc.t_eval(201), events=_slip)
    solve_ivp(sc.model, sc.t_span, sc.y0_array, method=_Spy, t_eval=sc.t_eval(201), windows_per_step=7)
    by_hand = _Spy(sc.model, 0.0, sc.y0_array, 80.0)
    assert [s.windows_per_step for s in _Spy.seen] == [msolver.WINDOWS_PER_STEP, 1, 1, 7, 1]
    assert not _Spy.seen[0].for_events and _Spy.seen[2].for_events
    assert by_hand.windows_per_step == 1


def test_auto_steps_bounded_and_same_bits_as_one_window_per_step():
    # A long run (P4 at 1e-9: ~1300 windows): "auto" groups at most WINDOWS_PER_STEP
    # windows a step, in a store never larger, and every output is the same bits as
    # one window per step (and as one step of all windows).
    sc = scene("P4")
    t_eval = sc.t_eval(201)
    kw = dict(rtol=1e-9, atol=1e-9, t_eval=t_eval, dense_output=True)
    _Spy.seen.clear()
    auto = solve_ivp(sc.model, sc.t_span, sc.y0_array, method=_Spy, **kw)
    spy = _Spy.seen[-1]
    one = solve_ivp(sc.model, sc.t_span, sc.y0_array, method=mbm.MBM, windows_per_step=1, **kw)
    whole = solve_ivp(sc.model, sc.t_span, sc.y0_array, method=mbm.MBM, windows_per_step=None, **kw)
    cap = msolver.WINDOWS_PER_STEP
    assert spy.n_windows > 4 * cap and len(spy.steps) >= 5
    assert all(n <= cap and size <= cap for n, size in spy.steps)
    assert sum(n for n, _ in spy.steps) == spy.n_windows == len(one.sol.interpolants)
    for other in (one, whole):
        assert auto.success and other.success
        np.testing.assert_array_equal(_bits(auto.t), _bits(other.t))
        np.testing.assert_array_equal(_bits(auto.y), _bits(other.y))
    tt = np.random.default_rng(5).uniform(*sc.t_span, 2000)
    np.testing.assert_array_equal(_bits(auto.sol(tt)), _bits(one.sol(tt)))


def test_store_grows_from_small():
    # An unbounded step (windows_per_step=None) starts at WINDOW_BUFFER windows, so a
    # short run allocates a small store.
    sc = scene("P1")
    _Spy.seen.clear()
    solve_ivp(sc.model, sc.t_span, sc.y0_array, method=_Spy, t_eval=sc.t_eval(201), rtol=1e-3, atol=1e-3,
              windows_per_step=None)
    (n, size), = _Spy.seen[-1].steps
    assert n < msolver.WINDOW_BUFFER and size == msolver.WINDOW_BUFFER


def test_bounded_step_allocates_its_bound_at_once():
    # "auto" with t_eval bounds a step at WINDOWS_PER_STEP windows: the store is that
    # size from the start (no pause to grow it), the same bits as a growing store.
    sc = scene("P4")
    _Spy.seen.clear()
    te = sc.t_eval(201)
    a = solve_ivp(sc.model, sc.t_span, sc.y0_array, method=_Spy, t_eval=te, rtol=1e-6, atol=1e-6)
    steps = _Spy.seen[-1].steps
    assert len(steps) > 1 and all(size == msolver.WINDOWS_PER_STEP for _, size in steps)
    b = solve_ivp(sc.model, sc.t_span, sc.y0_array, method=mbm.MBM, t_eval=te, rtol=1e-6, atol=1e-6,
                  windows_per_step=None)
    np.testing.assert_array_equal(_bits(a.y), _bits(b.y))


@pytest.mark.parametrize("wps", ["auto", None, 1, 5, np.int64(2)])
def test_windows_per_step_accepted(wps):
    solver = mbm.MBM(mbm.Pendulum(0.1, 0.3), 0.0, [0.5, 0.0], 10.0, windows_per_step=wps)
    assert solver.windows_per_step == (1 if isinstance(wps, str) else (None if wps is None else int(wps)))


@pytest.mark.parametrize("wps", [0, -3, 2.5, True, "all", "AUTO"])
def test_windows_per_step_refused(wps):
    with pytest.raises(ValueError, match="windows_per_step must be an integer >= 1, None or 'auto'"):
        mbm.MBM(mbm.Pendulum(0.1, 0.3), 0.0, [0.5, 0.0], 10.0, windows_per_step=wps)


def test_events_take_auto_and_refuse_several_windows():
    model = mbm.Pendulum(0.2, 0.8)
    a = solve_ivp(model, (0.0, 50.0), [0.0, 4.0], method=mbm.MBM, events=_slip, rtol=1e-9, atol=1e-9)
    b = solve_ivp(model, (0.0, 50.0), [0.0, 4.0], method=mbm.MBM, events=_slip, rtol=1e-9, atol=1e-9,
                  windows_per_step=1)
    np.testing.assert_array_equal(_bits(a.t_events[0]), _bits(b.t_events[0]))
    assert len(a.t_events[0]) > 20
    with pytest.raises(ValueError, match="windows_per_step=4 with events"):
        solve_ivp(model, (0.0, 50.0), [0.0, 4.0], method=mbm.MBM, events=_slip, windows_per_step=4)


RECORD_CASES = [
    # (model, t0, y0, t_bound, approximant, controller, h_abs, max_step, rtol, atol, order,
    #  max_windows, max_dtheta, call_windows)
    (mbm.Pendulum(0.4, 0.0), 0.0, [0.0, 0.25], 20.0, "taylor", CONTROLLER_ADAPTIVE, -1.0, math.inf,
     1e-3, 1e-3, 24, 10**7, math.inf, 0),
    (mbm.Pendulum(0.1, 1.2, 2.0), -3.0, [-1.5, 7.25], -50.0, "split4", CONTROLLER_FIXED, 0.25, 0.5,
     1e-9, 1e-12, 0, 123, math.pi / 4, 2**15),
    (mbm.Pendulum(0.3, -0.2, 1.0, drive_amplitude=0.8, drive_frequency=0.7, drive_phase=0.3), 1.5,
     [0.1, -0.0], 60.0, "taylor12", CONTROLLER_ADAPTIVE, 0.01, 2.0, 1e-6, 1e-8, 12, 10**7, math.inf, 0),
    (mbm.Pendulum(0.0, -0.0), 0.0, [-0.0, 1.999], 200.0, "belendez", CONTROLLER_FIXED, 200.0, math.inf,
     1e-6, 1e-6, 0, 10**7, math.inf, 0),
]


@pytest.mark.parametrize("case", RECORD_CASES)
def test_record_from_template_is_new_runs_bit_for_bit(case):
    model, t0, y0, t1, name, controller, h_abs, max_step, rtol, atol, order, max_windows, dtheta, calls = case
    kind = window.kind_of(get_approximant(name))
    beta, gamma, omega = model.params
    amp, freq, phase = model.drive
    control = record.RunControl(kind=kind[0], karg=kind[1], controller=controller, h_abs=h_abs, max_step=max_step,
                                max_dtheta=dtheta, rtol=rtol, atol=atol, error_order=order)
    ref = record.new_run(record.RunModel(beta, gamma, omega, amp, freq, phase),
                         record.RunState(t0, y0[0], y0[1], t1), control, max_windows, call_windows=calls)
    msolver._TEMPLATES.clear()
    for _ in range(2):  # built from new_run, then from the cached template
        words = msolver._new_record(model, record.RunState(t0, *y0, t1), control, max_windows, calls)
        np.testing.assert_array_equal(words.view(np.int64), ref.view(np.int64))
    # Another run of the same option set: only the run's own words change.
    start2 = record.RunState(2.0, 0.3, 0.4, 9.0)
    control2 = control._replace(h_abs=0.5)
    other = msolver._new_record(mbm.Pendulum(0.7, 0.1), start2, control2, max_windows, calls)
    ref2 = record.new_run(record.RunModel(0.7, 0.1, 1.0), start2, control2, max_windows, call_windows=calls)
    np.testing.assert_array_equal(other.view(np.int64), ref2.view(np.int64))


def test_coefficient_width_does_not_depend_on_model_or_state():
    # The store's width is cached per (anchor kernel, kind argument): it must be the
    # size of the coefficient vector whatever the model and state.
    models = [mbm.Pendulum(0.4, 0.0), mbm.Pendulum(0.0, 0.0), mbm.Pendulum(0.1, 1.2, 3.0),
              mbm.Pendulum(2.0, -0.5, 0.3)]
    states = [(0.0, 0.25), (3.0, -4.0), (-40.0, 0.0), (1e-300, 1e300)]
    for name in mbm.approximant_names():
        ap = get_approximant(name)
        kind = window.kind_of(ap)
        if kind is None:
            continue
        sizes = {ap.anchor_kernel(*m.params, th, v).size for m in models for th, v in states}
        assert len(sizes) == 1, name
        assert msolver._coefficient_width(ap, kind[1], models[0], np.array(states[0])) == sizes.pop()


@pytest.mark.parametrize("model", [mbm.Pendulum(0.4, 0.0), mbm.Pendulum(0.0, 0.0), mbm.Pendulum(0.0, 0.3),
                                   mbm.Pendulum(0.0, 0.0, 1.0, drive_amplitude=0.5, drive_frequency=1.0)])
@pytest.mark.parametrize("tol", [(1e-3, 1e-6), (1e-10, 1e-12)])
def test_auto_choice_is_choose_approximants(model, tol):
    solver = mbm.MBM(model, 0.0, [0.5, 0.0], 1.0, model=model, rtol=tol[0], atol=tol[1])
    assert solver.approximant_choice == choose_approximant(model, solver.y, *tol)


def test_auto_choice_follows_rtol_floor_and_warns_each_time():
    # The cached choice sees the tolerances after scipy's rtol floor; the warning is not cached away.
    model = mbm.Pendulum(0.1, 0.3)
    for _ in range(2):
        with pytest.warns(UserWarning, match="100 machine epsilons"):
            solver = mbm.MBM(model, 0.0, [0.5, 0.0], 1.0, model=model, rtol=1e-20, atol=1e-12)
        assert solver.approximant_choice == choose_approximant(model, solver.y, solver.rtol, 1e-12)


@pytest.mark.parametrize("kw", [dict(rtol=1e-3, atol=1e-3), dict(rtol=1e-10, atol=1e-10),
                                dict(approximant="split4", tau=0.05)])
def test_auto_backwards_same_bits(kw):
    model = mbm.Pendulum(0.1, 0.3)
    t_eval = np.linspace(30.0, 0.0, 301)
    runs = [solve_ivp(model, (30.0, 0.0), [1.0, -0.5], method=mbm.MBM, t_eval=t_eval, dense_output=True,
                      **dict(kw, **extra)) for extra in ({}, {"windows_per_step": 1}, {"windows_per_step": None})]
    tt = np.linspace(30.0, 0.0, 777)
    for other in runs[1:]:
        assert other.success
        np.testing.assert_array_equal(_bits(runs[0].y), _bits(other.y))
        np.testing.assert_array_equal(_bits(runs[0].sol(tt)), _bits(other.sol(tt)))


@pytest.mark.parametrize("t_span", [(0.0, 400.0), (400.0, 0.0)])
def test_long_steps_keep_the_ode_solver_contract(t_span):
    # Steps of up to WINDOWS_PER_STEP windows, stepped by hand: sol(t_old) is the state
    # before the step and sol(t) the state after it, to the bit; the last step lands on
    # t_bound, in either direction.
    # Weakly damped: no regime by t = 400 (a libration of β = 0 would be one window,
    # mbm.regimes C4), and no blow-up backwards.
    model = mbm.Pendulum(1e-3, 0.3)
    solver = mbm.MBM(model, t_span[0], [0.5, 0.0], t_span[1], windows_per_step=msolver.WINDOWS_PER_STEP,
                     rtol=1e-10, atol=1e-10)
    y_old, steps = solver.y.copy(), 0
    while solver.status == "running":
        assert solver.step() is None
        sol = solver.dense_output()
        np.testing.assert_array_equal(_bits(sol(solver.t_old)), _bits(y_old))
        np.testing.assert_array_equal(_bits(sol(solver.t)), _bits(solver.y))
        assert solver.direction * (solver.t - solver.t_old) > 0
        y_old, steps = solver.y.copy(), steps + 1
    assert solver.status == "finished" and solver.t == t_span[1]
    assert steps >= 2 and solver.n_windows > msolver.WINDOWS_PER_STEP
