"""``mbm.switching_grid``: switching histograms over temperature × ramp rate as an xarray Dataset."""

import numpy as np
import pytest

import mbm
from mbm.noise.grids import point_seed

import dask  # noqa: E402  (the test extra installs dask and xarray: no skip)


def test_grid_points_are_switching_currents_runs_and_order_sensibly():
    temps, rates = [0.03, 0.05], [1e-3, 1e-4]
    ds = mbm.switching_grid(1.0, temps, rates, 200, seed=1, gamma_start=0.6)
    assert ds["mean"].dims == ("temperature", "ramp_rate") and ds["mean"].shape == (2, 2)
    assert np.array_equal(ds.temperature, temps) and np.array_equal(ds.ramp_rate, rates)
    assert ds.attrs["seed"] == 1 and ds.attrs["n"] == 200 and np.all(ds["switched"] == 200)
    # point (1, 0) is switching_currents on its own seed
    h = mbm.switching_currents(1.0, 0.05, 1e-3, 200, seed=point_seed(1, 1, 0), gamma_start=0.6)
    assert int(ds["seed"][1, 0]) == h.seed
    assert [float(ds[k][1, 0]) for k in ("mean", "width", "skewness", "kurtosis")] == \
        [h.mean, h.width, h.skewness, h.kurtosis]
    # hotter: earlier switching; slower ramp: earlier switching.  The steps (0.03–0.07)
    # are over 10 standard errors of the means (width ~0.045 / sqrt(200) = 0.003).
    m = ds["mean"].values
    assert m[0, 0] - m[1, 0] > 0.03 and m[0, 0] - m[0, 1] > 0.03 and m[1, 0] - m[1, 1] > 0.03
    assert len({int(s) for s in ds["seed"].values.ravel()}) == 4


def test_a_scalar_axis_is_a_grid_of_one_and_seeds_reproduce():
    a = mbm.switching_grid(1.0, 0.05, [1e-3], 20, seed=3, gamma_start=0.6)
    b = mbm.switching_grid(1.0, [0.05], 1e-3, 20, seed=3, gamma_start=0.6)
    assert a["mean"].shape == (1, 1) and a.identical(b)


@pytest.mark.parametrize("args,words", [
    ((1.0, [0.05, -0.1], 1e-3, 10), "temperature must be > 0"),
    ((1.0, 0.05, 0.0, 10), "ramp_rate must be > 0"),
    ((1.0, [[0.05]], 1e-3, 10), "temperature must be a scalar or a non-empty 1-D array"),
    ((1.0, [], 1e-3, 10), "temperature must be a scalar or a non-empty 1-D array"),
    ((-1.0, 0.05, 1e-3, 10), "beta must be > 0"),
])
def test_switching_grid_refuses(args, words):
    with pytest.raises(ValueError, match=words):
        mbm.switching_grid(*args)


def test_chunked_grid_is_dask_backed_and_equals_the_local_grid_bit_for_bit():
    temps, rates = [0.03, 0.04, 0.05], [1e-3, 3e-4]
    kw = dict(seed=7, gamma_start=0.6)
    local = mbm.switching_grid(1.0, temps, rates, 40, **kw)
    lazy = mbm.switching_grid(1.0, temps, rates, 40, chunks={"temperature": 2}, **kw)
    assert lazy["mean"].chunks == ((2, 1), (2,))  # one task per chunk of points
    for scheduler in ("synchronous", "threads"):
        with dask.config.set(scheduler=scheduler):
            done = lazy.compute()
        for k in ("mean", "width", "skewness", "kurtosis", "switched", "seed"):
            a, b = done[k].values, local[k].values
            assert a.dtype == b.dtype and a.tobytes() == b.tobytes(), (scheduler, k)
    assert done.attrs == local.attrs


@pytest.mark.parametrize("chunks, match", [
    ({"voltage": 1}, "not dimensions of the grid"),
    ({"temperature": 0}, "chunks must be an int >= 1"),
    (1.5, "chunks must be an int >= 1"),
])
def test_chunks_refused_with_their_name(chunks, match):
    with pytest.raises(ValueError, match=match):
        mbm.switching_grid(1.0, [0.03], [1e-3], 10, seed=1, chunks=chunks)


def test_chunked_grid_checks_its_arguments_before_any_task():
    with pytest.raises(ValueError, match="dt"):
        mbm.switching_grid(1.0, [0.03], [1e-3], 10, seed=1, dt=-1.0, chunks=1)
    with pytest.raises(ValueError, match="n must"):
        mbm.switching_grid(1.0, [0.03], [1e-3], 0, seed=1, chunks=1)
