"""``mbm.solve(..., temperature=T, seed=s, dt=h)``: one Langevin path; noise off is unchanged."""

import math

import numpy as np
import pytest

import mbm


def test_noise_off_is_the_deterministic_run():
    m = mbm.Pendulum(0.1, 0.3)
    t = np.linspace(0, 20, 11)
    plain = mbm.solve(m, (0, 20), [0.5, 0.0], t_eval=t)
    for temp in (None, 0, 0.0):
        r = mbm.solve(m, (0, 20), [0.5, 0.0], t_eval=t, temperature=temp, seed=3)
        assert np.array_equal(r.y, plain.y) and r.n_windows == plain.n_windows


def test_a_path_is_reproducible_and_on_the_step_grid():
    m = mbm.Pendulum(0.5, 0.2)
    r = mbm.solve(m, (0, 10), [0.0, 0.0], temperature=0.1, seed=42, dt=0.05)
    assert r.success and r.approximant == "langevin-odo" and r.seed == 42
    assert r.t.shape == (201,) and r.y.shape == (2, 201)
    assert np.allclose(r.t, np.arange(201) * 0.05, rtol=0, atol=1e-12)
    assert np.array_equal(r.y[:, 0], [0.0, 0.0])
    again = mbm.solve(m, (0, 10), [0.0, 0.0], temperature=0.1, seed=42, dt=0.05)
    assert np.array_equal(again.y, r.y)
    assert not np.array_equal(mbm.solve(m, (0, 10), [0.0, 0.0], temperature=0.1, seed=43, dt=0.05).y, r.y)
    # t_eval picks states of the same path
    sub = mbm.solve(m, (0, 10), [0.0, 0.0], temperature=0.1, seed=42, dt=0.05, t_eval=[0.0, 2.5, 10.0])
    assert np.array_equal(sub.y, r.y[:, [0, 50, 200]])


def test_a_vanishing_temperature_follows_the_driven_deterministic_scene():
    # the drive's phase is carried to t0 = 5: with T = 1e-30 the path is the
    # deterministic scene's up to the splitting's O(h^2) error of the friction
    m = mbm.Pendulum(0.3, 0.2, 1.2, drive_amplitude=0.5, drive_frequency=0.8, drive_phase=0.4)
    t = np.linspace(5.0, 25.0, 21)
    ref = mbm.solve(m, (5.0, 25.0), [1.0, -0.5], t_eval=t, rtol=1e-12, atol=1e-12)
    r = mbm.solve(m, (5.0, 25.0), [1.0, -0.5], t_eval=t, temperature=1e-30, seed=1, dt=0.01)
    assert np.abs(r.y - ref.y).max() < 1e-4


def test_equipartition_along_one_long_path():
    m = mbm.Pendulum(1.0, 0.0, 1.0)
    r = mbm.solve(m, (0, 40000), [0.0, 0.0], temperature=0.4, seed=8, dt=0.5)
    v2 = r.y[1, 200:] ** 2
    batches = v2[: v2.size // 100 * 100].reshape(100, -1).mean(axis=1)  # batch means
    se = batches.std(ddof=1) / math.sqrt(batches.size)
    assert abs(batches.mean() - 0.4) < 4.5 * se, (batches.mean(), se)


@pytest.mark.parametrize("kw,err,words", [
    ({"temperature": -1.0}, ValueError, "temperature must be >= 0"),
    ({"temperature": 0.1, "events": mbm.angle_event(1.0)}, ValueError, "events is not supported"),
    ({"temperature": 0.1, "wrap": True}, ValueError, "wrap is not supported"),
    ({"temperature": 0.1, "tau": 0.1}, ValueError, "tau is not supported"),
    ({"temperature": 0.1, "dt": 3.0}, ValueError, "dt must be in"),
    ({"temperature": 0.1, "dt": 0.3}, ValueError, "whole number of steps"),
    ({"temperature": 0.1, "t_eval": [0.05]}, ValueError, "t_eval must be sorted times"),
    ({"temperature": 0.1, "seed": -1}, ValueError, "seed must be in"),
])
def test_noisy_solve_refuses(kw, err, words):
    with pytest.raises(err, match=words):
        mbm.solve(mbm.Pendulum(0.5, 0.2), (0, 10), [0.0, 0.0], **kw)


def test_noise_needs_damping_and_a_forward_span():
    with pytest.raises(ValueError, match="model.beta must be > 0"):
        mbm.solve(mbm.Pendulum(0.0, 0.2), (0, 10), [0.0, 0.0], temperature=0.1)
    with pytest.raises(ValueError, match="t_span must run forward"):
        mbm.solve(mbm.Pendulum(0.5, 0.2), (10, 0), [0.0, 0.0], temperature=0.1)


def test_gallery_example_runs(tmp_path):
    import importlib

    import matplotlib

    matplotlib.use("Agg")
    ex = importlib.import_module("thermal_switching")
    data, png = ex.main(tmp_path, n=60, n_escape=20)
    assert png.exists() and png.stat().st_size > 10_000
    assert set(data["histograms"]) == set(ex.TEMPERATURES)
    # lower temperature, later switching
    means = [data["histograms"][t].mean for t in ex.TEMPERATURES]
    assert means[0] > means[1] > means[2]


def test_batch_paths_match_solve_and_do_not_depend_on_threads():
    import numba

    betas, gammas = np.array([0.5, 0.5, 1.0]), np.array([0.2, 0.2, 0.0])
    t = np.linspace(0, 10, 11)
    kw = dict(temperature=[0.1, 0.1, 0.3], seed=42, dt=0.05)
    r = mbm.solve_batch(betas, gammas, 1.0, [0.0, 0.0], (0, 10), t, **kw)
    assert r.y.shape == (3, 2, 11) and np.all(r.success) and np.array_equal(r.temperature, [0.1, 0.1, 0.3])
    one = mbm.solve(mbm.Pendulum(0.5, 0.2), (0, 10), [0.0, 0.0], t_eval=t, temperature=0.1, seed=42, dt=0.05)
    assert np.array_equal(r.y[0], one.y)  # scene 0 is solve's path for the seed
    assert not np.array_equal(r.y[1], r.y[0])  # same scene, its own stream
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        single = mbm.solve_batch(betas, gammas, 1.0, [0.0, 0.0], (0, 10), t, **kw)
    finally:
        numba.set_num_threads(before)
    assert np.array_equal(single.y, r.y)


def test_batch_noise_off_is_unchanged_and_refusals():
    t = np.linspace(0, 10, 6)
    plain = mbm.solve_batch([0.1, 0.2], 0.3, 1.0, [0.5, 0.0], (0, 10), t)
    for temp in (None, 0.0, [0.0, 0.0]):
        r = mbm.solve_batch([0.1, 0.2], 0.3, 1.0, [0.5, 0.0], (0, 10), t, temperature=temp, seed=1)
        assert np.array_equal(r.y, plain.y)
    with pytest.raises(ValueError, match="beta must be > 0 with a temperature"):
        mbm.solve_batch([0.0, 0.2], 0.3, 1.0, [0.5, 0.0], (0, 10), t, temperature=0.1)
    with pytest.raises(ValueError, match="temperature must be > 0"):
        mbm.solve_batch([0.1, 0.2], 0.3, 1.0, [0.5, 0.0], (0, 10), t, temperature=[0.1, -1.0])
    with pytest.raises(ValueError, match="wrap is not supported"):
        mbm.solve_batch([0.1, 0.2], 0.3, 1.0, [0.5, 0.0], (0, 10), t, temperature=0.1, wrap=True)
