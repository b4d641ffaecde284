"""The compiled path: mbm.solve and mbm.solve_batch equal the solve_ivp path."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm

EX1 = mbm.Pendulum(0.1, 0.3)
EX1_Y0 = [math.radians(30.0), 0.0]


# The benchmark's six scenes (benchmarks/, docs/benchmark.md) and a few more options.
BENCH_SCENES = {
    "P1": (mbm.Pendulum(0.4, 0.0), [0.0, 0.25], 20.0),
    "P2": (mbm.Pendulum(0.1, 0.3), [math.radians(30.0), 0.0], 80.0),
    "P3": (mbm.Pendulum(0.1, 0.6), [math.radians(90.0), 0.0], 80.0),
    "P4": (mbm.Pendulum(0.01, 0.3), [1.0, 0.0], 1.0e4),
    "P5": (mbm.Pendulum(0.1, 1.2), [0.0, 0.0], 1000.0),
    "P6": (mbm.Pendulum(0.0, 0.0), [0.0, 1.999], 200.0),
}


@pytest.mark.parametrize("name", sorted(BENCH_SCENES))
@pytest.mark.parametrize("tol", [1e-3, 1e-6, 1e-9])
def test_solve_equals_solve_ivp_on_benchmark_scenes(name, tol):
    # One loop (mbm.core.loop.run) behind both paths: equal bit for bit, outputs and windows.
    model, y0, T = BENCH_SCENES[name]
    t = np.linspace(0.0, T, 201)
    fast = mbm.solve(model, (0.0, T), y0, t_eval=t, rtol=tol, atol=tol)
    ivp = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, rtol=tol, atol=tol,
                    windows_per_step=None)
    assert fast.success and ivp.success
    np.testing.assert_array_equal(fast.y, ivp.y)
    ends = mbm.solve(model, (0.0, T), y0, rtol=tol, atol=tol)
    one = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, rtol=tol, atol=tol)
    np.testing.assert_array_equal(ends.t, one.t)
    np.testing.assert_array_equal(ends.y, one.y)


@pytest.mark.parametrize(
    "model,y0,T,kw",
    [
        (EX1, EX1_Y0, 80.0, dict(rtol=1e-6, atol=1e-9)),
        (EX1, EX1_Y0, -30.0, dict(rtol=1e-10, atol=1e-10)),
        (mbm.Pendulum(0.1, 1.2), [0.0, 0.0], 100.0, dict(rtol=1e-8, atol=1e-8)),
        (mbm.Pendulum(0.0, 0.0), [0.0, 1.999], 200.0, dict(rtol=1e-6, atol=1e-9)),
        (EX1, EX1_Y0, 20.0, dict(approximant="salas-torque", tau=0.5)),
        (EX1, EX1_Y0, 20.0, dict(approximant="split4", tau=0.5)),
        (EX1, EX1_Y0, 20.0, dict(approximant="taylor12", rtol=1e-7, atol=1e-7)),
        # AC drive (tests/frontends/test_drive.py has every path on driven scenes)
        (mbm.Pendulum(0.1, 0.3, 1.0, 0.8, 1.3, 0.5), EX1_Y0, 80.0, dict(rtol=1e-9, atol=1e-9)),
        (mbm.Pendulum(0.1, 0.3, 1.0, 0.8, 1.3, 0.5), EX1_Y0, 20.0, dict(approximant="taylor12", tau=0.3)),
    ],
)
def test_solve_equals_solve_ivp_path(model, y0, T, kw):
    t = np.linspace(0.0, T, 201)
    fast = mbm.solve(model, (0.0, T), y0, t_eval=t, **kw)
    ivp = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, **kw)
    assert fast.success and ivp.success
    np.testing.assert_array_equal(fast.t, t)
    np.testing.assert_array_equal(fast.y, ivp.y)
    # without t_eval: the window ends, as solve_ivp returns its steps
    ends = mbm.solve(model, (0.0, T), y0, **kw)
    ivp_ends = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, **kw)
    np.testing.assert_array_equal(ends.t, ivp_ends.t)
    np.testing.assert_array_equal(ends.y, ivp_ends.y)
    assert ends.n_windows == ends.t.size - 1


def test_auto_choice_reported():
    r = mbm.solve(mbm.Pendulum(0.0, 0.0), (0.0, 1e6), [0.3, 1.0], t_eval=[0.0, 1e6])
    assert r.approximant == "belendez" and "exact" in r.reason and r.n_windows == 1
    np.testing.assert_array_equal(r.y[:, 0], [0.3, 1.0])
    r = mbm.solve(EX1, (0.0, 10.0), EX1_Y0)
    assert r.approximant == mbm.choice.CONVERGENT_DEFAULT


def test_failure_is_a_status_not_nan():
    r = mbm.solve(mbm.Pendulum(0.0, 0.2), (0.0, 10.0), [0.0, 2.5], approximant="salas-torque", tau=0.5)
    assert not r.success and r.status != 0 and "domain" in r.message
    assert np.all(np.isfinite(r.y))


@pytest.mark.parametrize(
    "kw,match",
    [
        (dict(t_span=(0.0, float("inf"))), "t_span"),
        (dict(y0=[0.0, float("nan")]), "y0"),
        (dict(y0=[0.0, 1.0, 2.0]), "y0"),
        (dict(rtol=-1.0), "rtol"),
        (dict(tau=0.0), "tau"),
        (dict(t_eval=[0.0, 20.0]), "t_eval"),
        (dict(t_eval=[5.0, 1.0]), "t_eval"),
        (dict(approximant="johannessen", tau=0.1), "compiled"),
        (dict(approximant="nope"), "approximant"),
    ],
)
def test_bad_input(kw, match):
    args = dict(t_span=(0.0, 10.0), y0=EX1_Y0)
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        mbm.solve(mbm.Pendulum(0.0, 0.0) if kw.get("approximant") == "johannessen" else EX1, **args)


def test_batch_equals_single_scenes():
    gammas = np.linspace(0.0, 2.0, 9)
    t = np.linspace(0.0, 200.0, 21)
    b = mbm.solve_batch(0.1, gammas, 1.0, [0.0, 0.0], (0.0, 200.0), t, rtol=1e-8, atol=1e-8)
    assert b.y.shape == (9, 2, 21) and b.success.all()
    for i, g in enumerate(gammas):
        r = mbm.solve(mbm.Pendulum(0.1, g), (0.0, 200.0), [0.0, 0.0], t_eval=t, rtol=1e-8, atol=1e-8)
        np.testing.assert_array_equal(b.y[i], r.y)
        assert b.n_windows[i] == r.n_windows
    # γ = 0 with θ = θ' = 0 stays at rest; β = 0.1 ≠ 0 so the convergent family is used
    assert set(b.approximant) == {mbm.choice.CONVERGENT_DEFAULT}


def test_batch_mixed_scenes_and_status():
    b = mbm.solve_batch([0.0, 0.1], [0.0, 0.3], [1.0, 2.0], [[0.3, 1.0], [0.1, 0.0]], (0.0, 10.0), np.linspace(0.0, 10.0, 5))
    assert list(b.approximant) == ["belendez", mbm.choice.CONVERGENT_DEFAULT]
    assert b.success.all()
    with pytest.raises(ValueError, match="y0"):
        mbm.solve_batch([0.1, 0.2], 0.3, 1.0, [[0.0, 0.0]] * 3, (0.0, 1.0), [1.0])


def test_batch_order_balances_contiguous_blocks():
    # numba splits a prange into contiguous blocks; sweeps list scenes by cost.  Every
    # block of the order must sample the whole batch: here each quarter's mean position
    # is within 2 % of the middle, and the order is a permutation.
    from mbm.frontends.batch import _balanced_order

    for n in (1, 2, 7, 1000, 10_000):
        order = _balanced_order(n)
        assert np.array_equal(np.sort(order), np.arange(n))
    order = _balanced_order(10_000)
    for block in np.array_split(order, 4):
        assert abs(block.mean() / 10_000 - 0.5) < 0.02


def test_max_windows_is_a_status_on_every_path():
    model, y0, T = BENCH_SCENES["P5"]
    t = np.linspace(0.0, T, 11)
    r = mbm.solve(model, (0.0, T), y0, t_eval=t, max_windows=50)
    assert r.status == mbm.status.STATUS_MAX_WINDOWS and not r.success
    assert r.n_windows == 50 and "max_windows" in r.message
    assert 0 < r.t.size < t.size and np.all(np.isfinite(r.y))
    ends = mbm.solve(model, (0.0, T), y0, max_windows=50)
    assert ends.status == mbm.status.STATUS_MAX_WINDOWS and ends.t.size == 51
    b = mbm.solve_batch([0.1, 0.1], [1.2, 0.0], 1.0, [0.0, 0.0], (0.0, T), t, max_windows=50)
    assert list(b.status) == [mbm.status.STATUS_MAX_WINDOWS, 0]
    # the failed scene keeps what it reached and says so; NaN only after it
    np.testing.assert_array_equal(b.y[0][:, : r.t.size], r.y)
    assert np.isnan(b.y[0][:, r.t.size:]).all()
    sol = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, max_windows=50)
    assert sol.status == -1 and "max_windows" in sol.message
    with pytest.raises(ValueError, match="max_windows"):
        mbm.solve(model, (0.0, T), y0, max_windows=0)


def test_long_run_is_chunked_and_resumes_bit_for_bit(monkeypatch):
    # mbm.solve returns to Python every CALL_WINDOWS windows (where Ctrl-C gets in);
    # resuming from the record must not change a bit.
    model, y0, T = BENCH_SCENES["P5"]
    t = np.linspace(0.0, T, 201)
    whole = mbm.solve(model, (0.0, T), y0, t_eval=t, rtol=1e-9, atol=1e-9)
    ends = mbm.solve(model, (0.0, T), y0, rtol=1e-9, atol=1e-9)
    monkeypatch.setattr(mbm.frontends.solve, "CALL_WINDOWS", 7)
    monkeypatch.setattr(mbm.frontends.solve, "ENDS_CAPACITY", 3)
    np.testing.assert_array_equal(mbm.solve(model, (0.0, T), y0, t_eval=t, rtol=1e-9, atol=1e-9).y, whole.y)
    chunked = mbm.solve(model, (0.0, T), y0, rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(chunked.t, ends.t)
    np.testing.assert_array_equal(chunked.y, ends.y)


def test_batch_cancel_flag_stops_every_scene():
    # The flag solve_batch's waiting thread sets on Ctrl-C: every scene stops at its
    # next window with STATUS_INTERRUPTED.
    p = np.zeros(3, dtype=mbm.core.record.RUN)
    f = mbm.core.record.flat(p)
    f["beta"], f["gamma"], f["omega"], f["t_bound"] = 0.1, 1.2, 1.0, 100.0
    f["kind"], f["karg"] = mbm.core.window.kind_of(mbm.get_approximant("taylor"))
    f["controller"], f["h_abs"], f["error_order"] = mbm.core.controller.CONTROLLER_ADAPTIVE, -1.0, 24
    f["max_step"], f["rtol"], f["atol"], f["max_windows"] = np.inf, 1e-8, 1e-8, 10**7
    f["max_dtheta"] = np.inf
    out = np.full((3, 2, 5), np.nan)
    mbm.core.lanes.run_batch(p, np.linspace(0.0, 100.0, 5), out, np.arange(3), np.ones(1, dtype=np.int64))
    assert list(f["status"]) == [mbm.status.STATUS_INTERRUPTED] * 3 and list(f["n_windows"]) == [0] * 3


def test_batch_bad_input_names_the_argument():
    with pytest.raises(ValueError, match="at least one scene"):
        mbm.solve_batch([], [], [], [0.0, 0.0], (0.0, 1.0), [1.0])
    with pytest.raises(ValueError, match=r"beta\[1\]"):
        mbm.solve_batch([0.1, -1.0], 0.3, 1.0, [0.0, 0.0], (0.0, 1.0), [1.0])
    with pytest.raises(ValueError, match=r"omega\[0\]"):
        mbm.solve_batch(0.1, 0.3, [0.0, 1.0], [0.0, 0.0], (0.0, 1.0), [1.0])
    with pytest.raises(ValueError, match="broadcast"):
        mbm.solve_batch([0.1, 0.2], [0.3, 0.3, 0.3], 1.0, [0.0, 0.0], (0.0, 1.0), [1.0])
    with pytest.raises(ValueError, match="t_eval"):
        mbm.solve_batch(0.1, 0.3, 1.0, [0.0, 0.0], (0.0, 1.0), [2.0])


def test_one_rtol_policy_on_every_path():
    # Below 100 eps: warn and raise to the floor, as scipy; then all paths agree.
    model, y0, T = BENCH_SCENES["P1"]
    t = np.linspace(0.0, T, 11)
    with pytest.warns(UserWarning, match="rtol"):
        a = mbm.solve(model, (0.0, T), y0, t_eval=t, rtol=1e-20, atol=1e-12)
    with pytest.warns(UserWarning, match="rtol"):
        b = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, rtol=1e-20, atol=1e-12,
                      windows_per_step=None)
    with pytest.warns(UserWarning, match="rtol"):
        c = mbm.solve_batch(0.4, 0.0, 1.0, y0, (0.0, T), t, rtol=1e-20, atol=1e-12)
    floor = mbm.solve(model, (0.0, T), y0, t_eval=t, rtol=100 * np.finfo(float).eps, atol=1e-12)
    np.testing.assert_array_equal(a.y, floor.y)
    np.testing.assert_array_equal(b.y, floor.y)
    np.testing.assert_array_equal(c.y[0], floor.y)
    with pytest.warns(UserWarning, match="rtol"):
        mbm.reference(model, (0.0, T), y0, rtol=1e-20)


@pytest.mark.parametrize("name", ["P1", "P5", "P6"])
def test_integrator_and_njit_entry_equal_solve(name):
    model, y0, T = BENCH_SCENES[name]
    t = np.linspace(0.0, T, 101)
    ref = mbm.solve(model, (0.0, T), y0, t_eval=t, rtol=1e-8, atol=1e-8)
    ig = mbm.Integrator(model, rtol=1e-8, atol=1e-8)
    for _ in range(2):  # reusable: a second solve is the same
        r = ig.solve((0.0, T), y0, t_eval=t)
        np.testing.assert_array_equal(r.y, ref.y)
        assert r.n_windows == ref.n_windows and r.approximant == ref.approximant
    ends = ig.solve((0.0, T), y0)
    np.testing.assert_array_equal(ends.y, mbm.solve(model, (0.0, T), y0, rtol=1e-8, atol=1e-8).y)
    out = np.empty((2, t.size))
    status, n = mbm.solve_njit(model.beta, model.gamma, model.omega, 0.0, y0[0], y0[1], T, t, out,
                               1e-8, 1e-8, 10**7)
    assert status == 0 and n == ref.n_windows
    np.testing.assert_array_equal(out, ref.y)


def test_njit_entry_callable_from_numba():
    import numba

    @numba.njit
    def final_angles(gammas, t_end):
        t = np.array([t_end])
        out = np.empty((2, 1))
        res = np.empty(gammas.size)
        for i in range(gammas.size):
            mbm.solve_njit(0.1, gammas[i], 1.0, 0.0, 0.0, 0.0, t_end, t, out, 1e-8, 1e-8, 10**7)
            res[i] = out[0, 0]
        return res

    gammas = np.array([0.3, 1.2])
    got = final_angles(gammas, 50.0)
    for g, th in zip(gammas, got):
        assert th == mbm.solve(mbm.Pendulum(0.1, g), (0.0, 50.0), [0.0, 0.0], t_eval=[50.0],
                               rtol=1e-8, atol=1e-8).y[0, 0]


def test_integrator_validates_once_and_per_call():
    with pytest.raises(TypeError, match="Pendulum"):
        mbm.Integrator(lambda t, y: y)
    with pytest.raises(ValueError, match="rtol"):
        mbm.Integrator(EX1, rtol=0.0)
    with pytest.raises(ValueError, match="compiled"):
        mbm.Integrator(mbm.Pendulum(0.1, 0.0), approximant="johannessen")
    ig = mbm.Integrator(EX1)
    with pytest.raises(ValueError, match="t_span"):
        ig.solve((0.0, math.nan), EX1_Y0)
    with pytest.raises(ValueError, match="y0"):
        ig.solve((0.0, 1.0), [0.0])
    with pytest.raises(ValueError, match="t_eval"):
        ig.solve((0.0, 1.0), EX1_Y0, t_eval=[2.0])
    # the exact flow's one window follows each call's span
    ex = mbm.Integrator(mbm.Pendulum(0.0, 0.0))
    for T in (1.0, 1e3):
        assert ex.solve((0.0, T), [0.3, 0.0]).n_windows == 1


def test_integrator_is_reentrant_across_threads():
    # Each call takes a record of its own from the Integrator's pool: concurrent calls
    # on one Integrator give what sequential ones give.
    import concurrent.futures

    ig = mbm.Integrator(EX1, rtol=1e-9, atol=1e-9)
    te = np.linspace(0.0, 80.0, 201)
    y0s = [[0.1 * k, 0.0] for k in range(16)]
    want = [ig.solve((0.0, 80.0), y0, te).y for y0 in y0s]
    with concurrent.futures.ThreadPoolExecutor(4) as ex:
        got = list(ex.map(lambda y0: ig.solve((0.0, 80.0), y0, te).y, y0s * 4))
    for k, y in enumerate(got):
        np.testing.assert_array_equal(y, want[k % 16])


def test_window_outputs_in_fours_equal_one_at_a_time():
    # loop.taylor_eval_range (four times at once) gives taylor_eval_kernel's bits, for
    # every count of outputs in a window (remainders included) and at t = 0.
    from mbm.approximants.taylor import taylor_coefficients, taylor_eval_kernel, taylor_eval_range

    coef = taylor_coefficients(0.1, 0.3, 1.0, 0.7, -0.4, 24)
    times = np.r_[0.0, np.linspace(0.01, 1.3, 22)] + 5.0
    for lo in range(4):
        for hi in range(lo, times.size + 1):
            th = np.full(times.size, np.nan)
            v = np.full(times.size, np.nan)
            taylor_eval_range(coef, 5.0, times, lo, hi, th, v)
            want = [taylor_eval_kernel(coef, x - 5.0) for x in times[lo:hi]]
            assert [(a, b) for a, b in zip(th[lo:hi], v[lo:hi])] == want
            assert np.isnan(th[:lo]).all() and np.isnan(th[hi:]).all()
    assert taylor_eval_kernel(coef, 0.0)[0] == 0.7


def _interrupt_after(seconds):
    # Ctrl-C as a user sends it: SIGINT to this process, from a timer thread.
    import os
    import signal
    import threading

    timer = threading.Timer(seconds, os.kill, (os.getpid(), signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.parametrize("path", ["solve", "solve_batch", "solve_ivp"])
def test_ctrl_c_stops_a_long_run_within_a_second(path, user_sigint):
    # An undamped, torqued rotation over 10⁶ time units (it accelerates for ever: no
    # long-horizon regime of mbm.regimes applies) takes many seconds here; Ctrl-C
    # after 0.3 s must raise KeyboardInterrupt well within a second of it.
    import time

    model = mbm.Pendulum(0.0, 1.2)
    calls = {
        "solve": lambda T: mbm.solve(model, (0.0, T), [0.0, 0.0], t_eval=[T], rtol=1e-10, atol=1e-10),
        "solve_batch": lambda T: mbm.solve_batch([0.0, 0.0], 1.2, 1.0, [0.0, 0.0], (0.0, T), [T],
                                                 rtol=1e-10, atol=1e-10),
        "solve_ivp": lambda T: solve_ivp(model, (0.0, T), [0.0, 0.0], method=mbm.MBM, rtol=1e-10,
                                         atol=1e-10, windows_per_step=None, t_eval=[T]),
    }
    calls[path](1.0)  # compiled before the interrupt is armed (never interrupt numba's compiler)
    timer = _interrupt_after(0.3)
    t0 = time.perf_counter()
    try:
        calls[path](1e6)
    except KeyboardInterrupt:
        pass
    else:
        pytest.fail(f"Ctrl-C did not raise (SIGINT's handler before the test: {user_sigint!r})")
    elapsed = time.perf_counter() - t0
    timer.cancel()
    assert elapsed < 1.3, elapsed


def test_batch_honours_the_callers_numba_thread_count(monkeypatch):
    # solve_batch runs its kernel in a worker thread: numba's per-thread count must follow.
    import numba

    seen = []
    real = mbm.core.lanes.run_batch

    class Spy:
        def __call__(self, *args, **kwargs):
            seen.append(numba.get_num_threads())
            return real(*args, **kwargs)

    monkeypatch.setattr(mbm.core.lanes, "run_batch", Spy())
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        mbm.solve_batch(0.1, [0.3, 1.2], 1.0, [0.0, 0.0], (0.0, 10.0), [10.0])
    finally:
        numba.set_num_threads(before)
    mbm.solve_batch(0.1, [0.3, 1.2], 1.0, [0.0, 0.0], (0.0, 10.0), [10.0])
    assert seen == [1, before]
