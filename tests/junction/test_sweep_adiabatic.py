"""mbm.sweep(protocol="adiabatic"): each bias from the previous bias's settled state.

The reference is the chain written out by hand with :func:`mbm.solve_batch` (one call per
bias, the state at t1 carried, θ modulo 2π); the physics check is the hysteresis of an
underdamped junction (running branch followed down below the switching current).
"""

import io
import math
import sys

import numpy as np
import pytest

import mbm

import dask  # noqa: E402  (the test extra installs dask and xarray)
from mbm.junction import sweeps as sweep_mod  # noqa: E402
from mbm.junction.sweeps import sweep  # noqa: E402

BETA = np.array([2.0, 0.05])  # overdamped: settles; weakly damped: fails at max_windows=100
GAMMA = np.array([0.3, 0.5, 0.4])
THETA0 = 0.25
SPAN = (0.0, 300.0)


def _same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _chain_by_hand(times, max_windows):
    """The adiabatic protocol written out: one solve_batch per bias, the state at t1 carried."""
    start = np.array([[THETA0, 0.0]] * BETA.size)
    y0 = start.copy()
    ys, statuses = [], []
    for g in GAMMA:
        res = mbm.solve_batch(BETA, np.full(BETA.size, g), 1.0, y0, SPAN, times, max_windows=max_windows)
        ys.append(res.y)
        statuses.append(res.status)
        end = res.y[:, :, -1]
        ok = (res.status == 0) & np.all(np.isfinite(end), axis=1)
        wrapped = end[:, 0] - 2 * math.pi * np.rint(end[:, 0] / (2 * math.pi))
        y0 = np.where(ok[:, None], np.stack([wrapped, end[:, 1]], axis=1), start)
    return np.stack(ys, axis=1), np.stack(statuses, axis=1)  # (beta, gamma, 2, m), (beta, gamma)


def test_adiabatic_reductions_equal_the_chain_by_hand():
    ds = sweep(beta=BETA, gamma=GAMMA, theta0=THETA0, t_span=SPAN, reduce=("final_state", "winding"),
               protocol="adiabatic", max_windows=100)
    y, status = _chain_by_hand(np.array([SPAN[1]]), 100)
    assert _same_bits(ds.status.values, status.astype(np.int32))
    assert status[0].tolist() == [0, 0, 0] and status[1].tolist() == [4, 4, 4]  # both cases met
    ok = status == 0
    assert _same_bits(ds.theta_final.values, np.where(ok, y[:, :, 0, -1], np.nan))
    assert _same_bits(ds.theta_dot_final.values, np.where(ok, y[:, :, 1, -1], np.nan))
    # winding from each scene's own start (the carried state).
    starts = np.concatenate([[THETA0], np.remainder(y[0, :-1, 0, -1] + math.pi, 2 * math.pi) - math.pi])
    assert np.array_equal(ds.winding.values[0], np.rint((y[0, :, 0, -1] - starts) / (2 * math.pi)))
    assert ds.attrs["protocol"] == "adiabatic"


@pytest.mark.parametrize("t_eval", [[100.0, 200.0], [100.0, 300.0]])  # t1 missing, t1 given
def test_adiabatic_series_equal_the_chain_by_hand(t_eval):
    ds = sweep(beta=BETA, gamma=GAMMA, theta0=THETA0, t_span=SPAN, t_eval=t_eval, protocol="adiabatic")
    y, status = _chain_by_hand(np.unique(np.append(t_eval, SPAN[1])), mbm.validate.DEFAULT_MAX_WINDOWS)
    m = len(t_eval)
    assert ds.theta.dims == ("beta", "gamma", "time")
    assert _same_bits(ds.theta.values, y[:, :, 0, :m]) and _same_bits(ds.theta_dot.values, y[:, :, 1, :m])
    assert _same_bits(ds.status.values, status.astype(np.int32))


def test_hysteresis_up_and_down():
    # β = 0.2: switching at γ = 1, retrapping near 4β/π ≈ 0.25 (Stewart–McCumber).  Up from
    # rest the junction stays locked below 1; down from the running state it keeps running.
    up = np.array([0.45, 0.6, 0.9, 1.1])
    kw = dict(beta=0.2, t_span=SPAN, reduce="mean_velocity", protocol="adiabatic")
    v_up = sweep(gamma=up, **kw).mean_velocity.values
    v_down = sweep(gamma=up[::-1], **kw).mean_velocity.values[::-1]
    assert np.all(v_up[:3] == 0.0) and v_up[3] > 1.0
    # On the running branch ⟨θ'⟩ ≈ γ/β (the ohmic line) within a few % at these biases.
    np.testing.assert_allclose(v_down, up / 0.2, rtol=0.05)
    # The independent protocol starts every scene from rest: a sudden step to 0.9 throws the
    # weakly damped junction over the barrier, where the adiabatic sweep up stays locked.
    assert sweep(gamma=up, beta=0.2, t_span=SPAN, reduce="mean_velocity").mean_velocity.values[2] > 1.0


def test_chunked_adiabatic_equals_local():
    kw = dict(beta=BETA, gamma=GAMMA, theta0=np.array([0.0, 1.0]), t_span=SPAN, t_eval=[150.0, 250.0],
              protocol="adiabatic")
    local = sweep(**kw)
    with dask.config.set(scheduler="synchronous"):
        chunked = sweep(chunks={"beta": 1, "theta0": 1}, **kw).compute()
    assert chunked.theta.dims == local.theta.dims == ("beta", "gamma", "theta0", "time")
    for v in ("theta", "theta_dot", "status"):
        assert _same_bits(chunked[v].values, local[v].values), v


def test_adiabatic_batches_do_not_change_results(monkeypatch):
    kw = dict(beta=np.linspace(0.1, 1.0, 7), gamma=GAMMA, t_span=(0.0, 100.0), reduce="final_state",
              protocol="adiabatic")
    whole = sweep(**kw)
    monkeypatch.setattr(sweep_mod, "LOCAL_BATCH", 3)
    assert sweep_mod._batch_size(21, False) == 3
    cut = sweep(**kw)
    for v in ("theta_final", "theta_dot_final", "status"):
        assert _same_bits(cut[v].values, whole[v].values), v


@pytest.mark.parametrize("kw, match", [
    (dict(protocol="sudden"), "protocol must be one of"),
    (dict(protocol=None), "protocol must be one of"),
    (dict(protocol="adiabatic", gamma=0.5), "needs gamma as a 1-D array"),
    (dict(protocol="adiabatic", chunks={"gamma": 1}), "chunks must keep gamma whole"),
    (dict(protocol="adiabatic", beta=0.5, chunks=2), "splits the dimensions other than gamma"),
])
def test_protocol_refusals(kw, match):
    args = dict(beta=BETA, gamma=GAMMA, t_span=SPAN, reduce="final_state")
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        sweep(**args)


# ------------------------------------------------------------------------------ progress


def test_progress_batches_move_the_bar_every_two_percent():
    assert sweep_mod._batch_size(600, False) == sweep_mod.LOCAL_BATCH
    assert sweep_mod._batch_size(600, True) == sweep_mod.PROGRESS_MIN_BATCH  # 600/50 = 12 < 16
    assert sweep_mod._batch_size(10**5, True) == 2000
    assert sweep_mod._batch_size(10**6, True) == sweep_mod.LOCAL_BATCH


@pytest.mark.parametrize("protocol", ["independent", "adiabatic"])
def test_progress_bar_on_stderr_moves_in_small_steps(monkeypatch, protocol):
    updates = []

    class Bar:
        def update(self, n):
            updates.append(n)

        def close(self):
            updates.append("closed")

    monkeypatch.setattr(sweep_mod, "progress_bar", lambda total, label, unit: Bar())
    sweep(beta=np.linspace(0.5, 1.0, 60), gamma=np.linspace(0.1, 0.5, 10), t_span=(0.0, 20.0),
          reduce="final_state", progress=True, protocol=protocol)
    assert updates[-1] == "closed" and sum(updates[:-1]) == 600
    assert max(updates[:-1]) <= 0.03 * 600  # every ~2 % of the grid


def test_progress_bar_drawn_in_a_log(monkeypatch):
    err = io.StringIO()  # not a terminal
    monkeypatch.setattr(sys, "stderr", err)
    sweep(beta=np.array([0.5, 1.0]), gamma=GAMMA, t_span=(0.0, 20.0), reduce="final_state", progress=True,
          protocol="adiabatic")
    assert "6/6" in err.getvalue()
