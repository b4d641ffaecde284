"""mbm.sweep: labelled grids of scenes as xarray Datasets, local and on Dask.

Chunked and unchunked sweeps must agree bit for bit with one :func:`mbm.solve_batch`
over the same scenes, in-process and on a real ``dask.distributed.LocalCluster`` (two
worker processes), also when a worker is killed mid-compute.
"""

import math
import os
import re
import signal
import threading
import time

import numpy as np
import pytest

import mbm
from mbm.status import STATUS_MAX_WINDOWS, STATUS_MESSAGES, STATUS_OK

import dask  # noqa: E402  (the test extra installs dask, distributed, xarray)
import xarray as xr  # noqa: E402
from mbm.junction import sweeps as sweep_mod  # noqa: E402  (needs xarray)
from mbm.junction.sweeps import sweep  # noqa: E402

BETA = np.array([0.05, 0.1, 0.4])
GAMMA = np.array([0.0, 0.3, 1.2])
T_EVAL = np.linspace(0.0, 40.0, 9)


def _same_bits(a, b):
    """Two arrays equal bit for bit (NaN payloads included), dtype and shape too."""
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _assert_identical_bits(ds, ref):
    assert list(ds.data_vars) == list(ref.data_vars)
    for v in ref.data_vars:
        assert ds[v].dims == ref[v].dims, v
        assert _same_bits(ds[v].values, ref[v].values), v
    for c in ref.coords:
        assert _same_bits(ds[c].values, ref[c].values), c


# ------------------------------------------------------------------- layout and values


def test_dims_coords_and_attrs():
    theta0 = np.array([0.0, 0.5])
    ds = sweep(beta=BETA, gamma=GAMMA, omega=1.5, theta0=theta0, t_span=(0.0, 40.0), t_eval=T_EVAL)
    assert ds.theta.dims == ("beta", "gamma", "theta0", "time")
    assert ds.theta_dot.dims == ("beta", "gamma", "theta0", "time")
    assert ds.status.dims == ("beta", "gamma", "theta0")
    assert ds.status.dtype == np.int32
    assert _same_bits(ds.beta.values, BETA) and _same_bits(ds.gamma.values, GAMMA)
    assert _same_bits(ds.theta0.values, theta0) and _same_bits(ds.time.values, T_EVAL)
    # Scalars are attributes, not dimensions; the options are recorded.
    assert "omega" not in ds.dims and "theta_dot0" not in ds.dims
    assert ds.attrs["omega"] == 1.5 and ds.attrs["theta_dot0"] == 0.0
    assert list(ds.attrs["t_span"]) == [0.0, 40.0]
    assert ds.attrs["rtol"] == 1e-6 and ds.attrs["atol"] == 1e-9
    assert ds.attrs["approximant"] == "auto"
    assert ds.attrs["mbm_version"] == mbm.__version__
    assert ds.attrs["max_windows"] == mbm.validate.DEFAULT_MAX_WINDOWS
    # The status flags name every status of mbm.status, and its messages.
    flags = ds.status.attrs
    assert list(flags["flag_values"]) == sorted(STATUS_MESSAGES)
    assert len(flags["flag_meanings"].split()) == len(STATUS_MESSAGES)
    for code, msg in STATUS_MESSAGES.items():
        assert f"{code}: {msg}" in flags["flag_messages"]
        assert sweep_mod.status_message(code) == msg
    assert (ds.status == 0).all()


def test_mbm_sweep_is_the_function():
    # mbm.sweep is the function (loaded lazily: import mbm does not import xarray); its
    # module is mbm.junction.sweeps, so importing the module cannot shadow it.
    kw = dict(beta=BETA, gamma=0.3, t_span=(0.0, 10.0), reduce="winding")
    assert mbm.sweep is sweep and mbm.junction.sweeps is sweep_mod
    _assert_identical_bits(mbm.sweep(**kw), sweep(**kw))


def test_dims_follow_argument_order_not_call_order():
    ds = sweep(theta_dot0=[0.0, 1.0], omega=[1.0, 2.0], gamma=0.2, beta=0.1, t_span=(0.0, 5.0),
               reduce="final_state")
    assert ds.theta_final.dims == ("omega", "theta_dot0")
    assert ds.attrs["beta"] == 0.1 and ds.attrs["gamma"] == 0.2


def test_values_equal_one_solve_batch_over_the_outer_product():
    theta0 = np.array([0.0, 0.5])
    ds = sweep(beta=BETA, gamma=GAMMA, theta0=theta0, t_span=(0.0, 40.0), t_eval=T_EVAL)
    b, g, th = np.meshgrid(BETA, GAMMA, theta0, indexing="ij")
    y0 = np.stack([th.ravel(), np.zeros(th.size)], axis=1)
    res = mbm.solve_batch(b.ravel(), g.ravel(), 1.0, y0, (0.0, 40.0), T_EVAL)
    assert _same_bits(ds.theta.values, res.y[:, 0, :].reshape(3, 3, 2, -1))
    assert _same_bits(ds.theta_dot.values, res.y[:, 1, :].reshape(3, 3, 2, -1))
    assert _same_bits(ds.status.values, res.status.astype(np.int32).reshape(3, 3, 2))


def test_a_single_scene_has_no_dimensions():
    ds = sweep(beta=0.1, gamma=0.3, theta0=math.radians(30), t_span=(0.0, 80.0), t_eval=[0.0, 80.0])
    assert ds.theta.dims == ("time",) and ds.status.dims == ()
    fast = mbm.solve(mbm.Pendulum(0.1, 0.3), (0.0, 80.0), [math.radians(30), 0.0], t_eval=[0.0, 80.0])
    assert _same_bits(ds.theta.values, fast.y[0])


def test_reduce_variables_and_their_definitions():
    # A horizon where some runs reach their regime and some do not (both definitions of
    # ⟨θ'⟩ below): at T = 400 all nine do since the second-order locked form (L6).
    T = 300.0
    full = sweep(beta=BETA, gamma=GAMMA, theta0=0.5, t_span=(0.0, T), t_eval=[T / 2, T])
    red = sweep(beta=BETA, gamma=GAMMA, theta0=0.5, t_span=(0.0, T),
                reduce=["final_state", "mean_velocity", "winding", "regime"])
    assert list(red.data_vars) == ["theta_final", "theta_dot_final", "mean_velocity", "winding",
                                   "regime", "status"]
    assert "time" not in red.dims
    assert red.attrs["reduce"] == "final_state,mean_velocity,winding,regime"
    th_half, th_end = full.theta.isel(time=0).values, full.theta.isel(time=1).values
    # Output times do not move the windows, so the reductions are exact functions of θ.
    assert _same_bits(red.theta_final.values, th_end)
    assert _same_bits(red.theta_dot_final.values, full.theta_dot.isel(time=1).values)
    # ⟨θ'⟩ exact where the run reached a regime (2π/T_c, or 0 once locked), else two samples
    b, g = np.meshgrid(BETA, GAMMA, indexing="ij")
    batch = mbm.solve_batch(b.ravel(), g.ravel(), 1.0, [0.5, 0.0], (0.0, T), [T / 2, T])
    exact = np.isfinite(batch.mean_velocity).reshape(b.shape)
    assert exact.any() and not exact.all()
    assert _same_bits(red.mean_velocity.values,
                      np.where(exact, batch.mean_velocity.reshape(b.shape), (th_end - th_half) / (T / 2)))
    assert _same_bits(red.winding.values, np.rint((th_end - 0.5) / (2 * np.pi)) + 0.0)
    running = np.abs(th_end - th_half) >= sweep_mod.REGIME_TURNS * 2 * np.pi
    assert (red.regime.values == np.where(running, "running", "locked")).all()


def test_regime_and_mean_velocity_on_known_scenes():
    # Example 1 (β = 0.1, γ = 0.3) locks at arcsin-like equilibrium; P5 (γ = 1.2) runs at
    # ⟨θ'⟩ ≈ γ/β (the damping balances the torque; measured 11.9997 over t ≤ 1000).
    ds = sweep(beta=0.1, gamma=[0.3, 1.2], t_span=(0.0, 1000.0), reduce=["mean_velocity", "regime", "winding"])
    assert list(ds.regime.values) == ["locked", "running"]
    v = ds.mean_velocity.values
    # both runs reach their regime: exactly 0 once locked, 2π/T_c on the cycle
    assert v[0] == 0.0
    assert v[1] == mbm.solve(mbm.Pendulum(0.1, 1.2), (0.0, 1000.0), [0.0, 0.0], t_eval=[1000.0]).mean_velocity
    assert v[1] == pytest.approx(12.0, rel=1e-3)
    assert ds.winding.values[0] == 0.0
    # From rest θ' rises to γ/β with time constant 1/β, so θ lags 12·(1/β) behind 12·t.
    assert ds.winding.values[1] == pytest.approx(12.0 * (1000.0 - 1 / 0.1) / (2 * np.pi), rel=1e-3)


def test_reduce_accepts_one_name_and_drops_duplicates():
    ds = sweep(beta=BETA, gamma=0.3, t_span=(0.0, 10.0), reduce=["winding", "winding"])
    assert list(ds.data_vars) == ["winding", "status"]
    ds = sweep(beta=BETA, gamma=0.3, t_span=(0.0, 10.0), reduce="mean_velocity")
    assert list(ds.data_vars) == ["mean_velocity", "status"]


# ------------------------------------------------------------------------- failed scenes


def test_failed_scene_has_a_status_and_nan_never_silently():
    # β = γ = 0 runs the exact solution in one window; the damped scenes need many more
    # than max_windows = 3 windows, so they stop with STATUS_MAX_WINDOWS.
    ds = sweep(beta=[0.0, 0.1], gamma=[0.0, 1.2], theta0=0.5, t_span=(0.0, 50.0),
               reduce=["final_state", "mean_velocity", "winding", "regime"], max_windows=3)
    status = ds.status.values
    assert status[0, 0] == STATUS_OK
    failed = status != STATUS_OK
    assert failed.sum() == 3 and (status[failed] == STATUS_MAX_WINDOWS).all()
    for v in ("theta_final", "theta_dot_final", "mean_velocity", "winding"):
        vals = ds[v].values
        assert np.isnan(vals[failed]).all() and np.isfinite(vals[~failed]).all(), v
    assert (ds.regime.values[failed] == "failed").all()
    # Every NaN has a status that says why.
    assert not np.any(np.isnan(ds.mean_velocity.values) & (status == STATUS_OK))
    assert "max_windows" in sweep_mod.status_message(status[1, 0])


def test_failed_scene_time_series_keeps_what_it_reached():
    t_eval = np.linspace(0.0, 50.0, 11)
    ds = sweep(beta=[0.0, 0.1], gamma=0.0, theta0=0.5, t_span=(0.0, 50.0), t_eval=t_eval, max_windows=3)
    assert list(ds.status.values) == [STATUS_OK, STATUS_MAX_WINDOWS]
    ok, bad = ds.theta.values
    assert np.isfinite(ok).all()
    assert bad[0] == 0.5 and np.isnan(bad[-1])  # valid up to the failure, NaN after
    res = mbm.solve_batch([0.0, 0.1], 0.0, 1.0, [0.5, 0.0], (0.0, 50.0), t_eval, max_windows=3)
    assert _same_bits(ds.theta.values, res.y[:, 0, :])


# --------------------------------------------------------------------------- bad input


@pytest.mark.parametrize(
    "change, match",
    [
        (dict(beta=[]), "beta must not be an empty array"),
        (dict(beta=[[0.1, 0.2]]), "beta must be a scalar or a 1-D"),
        (dict(gamma=[0.1, np.nan]), r"gamma must be finite, got gamma\[1\]"),
        (dict(beta=-0.1), "beta must be >= 0"),
        (dict(beta=[0.1, -0.1]), r"beta must be >= 0 .*beta\[1\]"),
        (dict(omega=0.0), "omega must be > 0"),
        (dict(omega=[1.0, -1.0]), "omega must be > 0"),
        (dict(theta0=np.inf), "theta0 must be finite"),
        (dict(reduce="nope"), "reduce must name"),
        (dict(reduce=[]), "reduce must name at least one"),
        (dict(reduce=["mean_velocity", 3]), "reduce must name"),
        (dict(reduce=None), "give t_eval"),
        (dict(t_eval=[0.0, 1.0]), "t_eval and reduce exclude each other"),
        (dict(reduce=None, t_eval=[0.0, 20.0]), "t_eval must lie within t_span"),
        (dict(reduce=None, t_eval=[[0.0, 1.0]]), "t_eval must be a non-empty 1-D"),
        (dict(reduce=None, t_eval=[]), "t_eval must be a non-empty 1-D"),
        (dict(reduce=None, t_eval=[2.0, 1.0]), "t_eval must be sorted"),
        (dict(t_span=(10.0, 0.0)), "t_span must be increasing"),
        (dict(t_span=(0.0, np.nan)), "t_span must be finite"),
        (dict(t_span=(0.0,)), "t_span must be a pair"),
        (dict(rtol=-1.0), r"rtol must be > 0, got -1\.0"),
        (dict(tau=0.0), r"tau must be > 0, got 0\.0"),
        (dict(drive_amplitude=[0.0, 1.0], drive_frequency=0.0),
         r"drive_frequency must be > 0 with a drive \(drive_amplitude != 0\), got 0\.0"),
        (dict(max_windows=0), "max_windows must be an integer"),
        (dict(approximant="nope"), "approximant must be one of"),
        (dict(approximant="johannessen"), "no compiled kernel"),
        (dict(approximant="belendez"), "needs beta = 0 and gamma = 0"),
        (dict(approximant=mbm.get_approximant("taylor")), "approximant must be the name"),
        (dict(chunks={"zeta": 2}), "chunks names"),
        (dict(chunks=0), "chunks must be an int"),
        (dict(chunks={"beta": 1.5}), "chunks must be an int"),
        (dict(progress="yes"), "progress must be True or False"),
    ],
)
def test_bad_input_names_the_argument(change, match):
    kw = dict(beta=[0.1, 0.2], gamma=0.3, t_span=(0.0, 10.0), reduce="mean_velocity")
    kw.update(change)
    with pytest.raises(ValueError, match=match):
        sweep(**kw)


@pytest.mark.parametrize(
    "change, match",
    [
        (dict(theta_dot0="fast"), "theta_dot0 must be a real number or an array of real numbers, got 'fast'"),
        (dict(beta="0.1"), "beta must be a real number or an array of real numbers, got '0.1'"),
        (dict(gamma=1j), "gamma must be a real number or an array of real numbers"),
        (dict(theta0=[True, False]), "theta0 must be a real number or an array of real numbers"),
        (dict(atol="x"), "atol must be a real number, got 'x'"),
    ],
)
def test_what_is_not_a_real_number_is_a_type_error(change, match):
    kw = dict(beta=[0.1, 0.2], gamma=0.3, t_span=(0.0, 10.0), reduce="mean_velocity")
    kw.update(change)
    with pytest.raises(TypeError, match=re.escape(match)):
        sweep(**kw)


def test_chunks_need_an_array_parameter():
    with pytest.raises(ValueError, match="chunks needs a parameter given as a 1-D array"):
        sweep(beta=0.1, gamma=0.3, t_span=(0.0, 10.0), reduce="winding", chunks=2)


def test_bad_input_is_caught_before_any_dask_compute():
    # Checked at the call, not on a worker at compute time.
    with pytest.raises(ValueError, match="rtol"):
        sweep(beta=[0.1, 0.2], gamma=0.3, t_span=(0.0, 10.0), reduce="winding", rtol=0.0, chunks=1)


# ------------------------------------------------------------------------------ netCDF


def test_to_netcdf_round_trip(tmp_path):
    # scipy's netCDF-3 writer: no extra package (netCDF4/h5netcdf are not needed).
    ds = sweep(beta=[0.0, 0.1], gamma=[0.0, 1.2], theta0=0.5, t_span=(0.0, 50.0),
               reduce=["mean_velocity", "regime", "winding"], max_windows=3)
    ts = sweep(beta=BETA, gamma=0.3, t_span=(0.0, 40.0), t_eval=T_EVAL)
    for data in (ds, ts):
        path = tmp_path / "sweep.nc"
        data.to_netcdf(path, engine="scipy")
        with xr.open_dataset(path, engine="scipy") as back:
            back = back.load()
        for c in data.coords:
            assert _same_bits(back[c].values, data[c].values), c
        assert set(back.attrs) == set(data.attrs)
        for k, v in data.attrs.items():
            assert np.array_equal(back.attrs[k], v), k
        for v in data.data_vars:
            assert back[v].dims == data[v].dims
            if data[v].dtype.kind == "U":
                assert (back[v].values.astype(str) == data[v].values).all(), v
            else:
                assert _same_bits(back[v].values, data[v].values), v
            for k, a in data[v].attrs.items():
                assert np.array_equal(back[v].attrs[k], a), (v, k)
        path.unlink()


# ------------------------------------------------------------------------- dask in-process


SWEEP = dict(beta=np.linspace(0.05, 0.4, 5), gamma=np.linspace(0.0, 1.5, 7), theta0=[0.0, 1.0],
             t_span=(0.0, 200.0), reduce=["final_state", "mean_velocity", "winding", "regime"])


@pytest.fixture(scope="module")
def reference():
    """The unchunked, in-process sweep of :data:`SWEEP`."""
    return sweep(**SWEEP)


def test_chunked_is_lazy_and_identical_on_threads(reference):
    ds = sweep(**SWEEP, chunks={"beta": 2, "gamma": 3})
    assert ds.mean_velocity.chunks == ((2, 2, 1), (3, 3, 1), (2,))
    assert ds.attrs.keys() == reference.attrs.keys()
    assert all(np.array_equal(ds.attrs[k], reference.attrs[k]) for k in ds.attrs)
    with dask.config.set(scheduler="threads"):
        _assert_identical_bits(ds.compute(), reference)


def test_chunked_time_series_identical():
    kw = dict(beta=BETA, gamma=GAMMA, t_span=(0.0, 40.0), t_eval=T_EVAL)
    ref = sweep(**kw)
    ds = sweep(**kw, chunks=2)
    assert ds.theta.chunks == ((2, 1), (2, 1), (T_EVAL.size,))
    with dask.config.set(scheduler="threads"):
        _assert_identical_bits(ds.compute(), ref)


def test_each_chunk_is_one_solve_batch_call(monkeypatch, reference):
    calls = []
    real = sweep_mod.solve_batch

    def counting(*args, **kwargs):
        calls.append(np.size(args[0]))
        return real(*args, **kwargs)

    ds = sweep(**SWEEP, chunks={"beta": 2, "gamma": 3})  # validated before counting
    monkeypatch.setattr(sweep_mod, "solve_batch", counting)
    with dask.config.set(scheduler="synchronous"):
        out = ds.compute()
    assert len(calls) == 3 * 3 and sum(calls) == reference.status.size
    _assert_identical_bits(out, reference)


def test_dask_progress_bar_persists(capsys, reference):
    with dask.config.set(scheduler="threads"):
        ds = sweep(**SWEEP, chunks={"beta": 2}, progress=True)
    assert ds.mean_velocity.chunks is not None  # still dask-backed, computed
    out = capsys.readouterr()
    assert "100%" in out.err and "100%" not in out.out  # on stderr, beside the user's output
    _assert_identical_bits(ds.compute(), reference)


# -------------------------------------------------------------- local progress, Ctrl-C


def test_local_progress_bar(capsys, monkeypatch, reference):
    monkeypatch.setattr(sweep_mod, "LOCAL_BATCH", 16)  # several batches: the bar moves
    ds = sweep(**SWEEP, progress=True)
    err = capsys.readouterr().err
    n = reference.status.size
    assert f"{n}/{n}" in err or "100%" in err
    _assert_identical_bits(ds, reference)


def test_local_batches_do_not_change_results(monkeypatch, reference):
    monkeypatch.setattr(sweep_mod, "LOCAL_BATCH", 7)  # batches cut across every dimension
    _assert_identical_bits(sweep(**SWEEP), reference)


def test_ctrl_c_stops_within_a_second(monkeypatch, user_sigint):
    # 8000 running scenes (seconds of work); Ctrl-C arrives 0.1 s into the second batch,
    # i.e. while solve_batch runs, however fast the kernels are.
    kw = dict(beta=np.linspace(0.05, 0.1, 80), gamma=np.linspace(1.2, 1.6, 100), t_span=(0.0, 1000.0),
              reduce="mean_velocity")
    monkeypatch.setattr(sweep_mod, "LOCAL_BATCH", 128)
    real = sweep_mod._solve_block
    calls, sent, timers = [], [], []

    def interrupt():
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    def block(*args, **kwargs):
        calls.append(1)
        if len(calls) == 2:
            timers.append(threading.Timer(0.1, interrupt))
            timers[0].start()
        return real(*args, **kwargs)

    monkeypatch.setattr(sweep_mod, "_solve_block", block)
    try:
        with pytest.raises(KeyboardInterrupt):
            sweep(**kw)
    finally:
        for t in timers:
            t.cancel()
    stopped = time.perf_counter()
    assert sent, "the sweep finished before the interrupt"
    assert stopped - sent[0] < 1.0
    assert len(calls) < 8000 // 128  # it stopped, not ran to the end


# -------------------------------------------------------------- a real distributed cluster


@pytest.fixture(scope="module")
def cluster():
    """A LocalCluster of 2 worker processes, 1 thread each (numba: 1 thread per worker)."""
    import distributed
    # Set in each worker process before it starts (the nanny's environ; numba reads
    # NUMBA_NUM_THREADS when a task first imports it): 2 workers x 1 thread = the 2
    # cores.  Not the pre-spawn environ: that is set in this process while the workers
    # spawn, and a numba compile here meanwhile would see a thread count that differs
    # from this process's running pool (RuntimeError in later tests).
    with dask.config.set({"distributed.nanny.environ.NUMBA_NUM_THREADS": 1}):
        lc = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      dashboard_address=None, silence_logs=50)
    client = distributed.Client(lc)
    yield client
    client.close()
    lc.close()


def test_distributed_identical_and_kernels_loaded_from_cache(cluster, reference):
    ds = sweep(**SWEEP, chunks={"beta": 1, "gamma": 4})
    out = ds.compute()  # the Client is the default scheduler
    _assert_identical_bits(out, reference)
    # Each worker loaded the batch's kernels from numba's cache: hits, no compilation.
    # (Lambdas: cloudpickle ships them by value; a function of this module would be
    # looked up by name on the worker, which cannot import the tests.)
    stats = cluster.run(lambda: [e.stats for e in (__import__("mbm.core.lanes").core.lanes._run_lanes,
                                                    *__import__("mbm.core.lanes").core.lanes.ROWS_ENTRIES.values())])
    assert len(stats) == 2
    assert sum(sum(s.cache_hits.values()) for ss in stats.values() for s in ss) >= 1
    assert all(sum(s.cache_misses.values()) == 0 for ss in stats.values() for s in ss)
    # And the numba threads follow the worker's (the pre-spawn environment).
    threads = cluster.run(lambda: __import__("numba").get_num_threads())
    assert set(threads.values()) == {1}


def test_distributed_progress(cluster, reference, capsys):
    ds = sweep(**SWEEP, chunks={"beta": 1}, progress=True)
    assert "100% Completed" in capsys.readouterr().out  # distributed's text bar
    _assert_identical_bits(ds.compute(), reference)


def test_distributed_worker_killed_mid_compute(cluster):
    from distributed import futures_of, wait

    kw = dict(beta=np.linspace(0.05, 0.3, 16), gamma=np.linspace(0.8, 1.6, 30), t_span=(0.0, 500.0),
              reduce=["mean_velocity", "regime"])
    ref = sweep(**kw)
    persisted = cluster.persist(sweep(**kw, chunks={"beta": 1}))
    futures = futures_of(persisted)
    deadline = time.perf_counter() + 30.0
    while sum(f.done() for f in futures) < 3 and time.perf_counter() < deadline:
        time.sleep(0.01)
    processing = cluster.processing()
    victim = max(processing, key=lambda w: len(processing[w]))
    assert processing[victim], "nothing left running to kill (make the sweep longer)"
    assert not all(f.done() for f in futures)
    pid = cluster.run(os.getpid, workers=[victim])[victim]
    os.kill(pid, signal.SIGKILL)  # mid-compute: its running and finished tasks are lost
    wait(futures, timeout=60)
    _assert_identical_bits(persisted.compute(), ref)
    assert victim not in cluster.scheduler_info()["workers"]


# ------------------------------------------------------------------------------ example


def test_stability_map_example(tmp_path):
    import importlib

    import matplotlib

    matplotlib.use("Agg")
    ex = importlib.import_module("stability_map")
    ds, png = ex.main(tmp_path, n_beta=6, n_gamma=8, t_end=200.0)
    assert png.exists() and png.stat().st_size > 10_000
    assert ds.mean_velocity.dims == ("beta", "gamma", "theta_dot0")
    regime = ds.regime.values
    beta, gamma = np.meshgrid(ds.beta.values, ds.gamma.values, indexing="ij")
    # Above γ = 1 no equilibrium exists: every scene runs, from rest or launched.
    assert (regime[gamma > 1.05] == "running").all()
    # Far below γ = 4β/π (the retrapping current) every scene locks.
    assert (regime[gamma < 0.5 * 4 * beta / np.pi] == "locked").all()
    assert (ds.status == 0).all()
