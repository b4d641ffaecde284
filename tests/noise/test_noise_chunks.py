"""A noisy ``mbm.solve``/``solve_batch`` path runs in compiled chunks of steps: same bits whatever the cut."""

import numpy as np

import mbm
from mbm.noise import paths


def _runs():
    m = mbm.Pendulum(0.3, 0.4, 1.1, drive_amplitude=0.3, drive_frequency=0.7)
    # marks inside chunks of 7 steps, on their borders (0.35 = step 7, 4.9 = step 98),
    # repeated, and the last step
    t = np.array([0.0, 0.1, 0.35, 0.35, 0.4, 4.9, 5.0, 20.0])
    full = mbm.solve(m, (0, 20), [0.1, 0.0], temperature=0.2, seed=5, dt=0.05)
    marked = mbm.solve(m, (0, 20), [0.1, 0.0], temperature=0.2, seed=5, dt=0.05, t_eval=t)
    batch = mbm.solve_batch([0.3, 0.3, 0.5], [0.1, 0.5, 0.9], 1.0, [0.2, 0.0], (0, 20), t,
                            temperature=[0.1, 0.2, 0.3], seed=9, dt=0.05)
    return full.y, marked.y, batch.y


def test_the_bits_do_not_depend_on_the_chunk_size(monkeypatch):
    default = _runs()
    assert paths.CHUNK_STEPS > 400  # the default runs these paths in one call
    for size in (7, 1, 3):
        monkeypatch.setattr(paths, "CHUNK_STEPS", size)
        for a, b in zip(default, _runs()):
            assert np.array_equal(a, b), size
    assert np.array_equal(default[1], default[0][:, [0, 2, 7, 7, 8, 98, 100, 400]])


def test_a_path_ending_before_the_span_and_an_empty_t_eval(monkeypatch):
    monkeypatch.setattr(paths, "CHUNK_STEPS", 4)
    m = mbm.Pendulum(0.5, 0.2)
    r = mbm.solve(m, (0, 10), [0.0, 0.0], temperature=0.1, seed=1, dt=0.1, t_eval=[0.8, 1.2])
    whole = mbm.solve(m, (0, 10), [0.0, 0.0], temperature=0.1, seed=1, dt=0.1)
    assert np.array_equal(r.y, whole.y[:, [8, 12]])
    e = mbm.solve(m, (0, 10), [0.0, 0.0], temperature=0.1, seed=1, dt=0.1, t_eval=[])
    assert e.y.shape == (2, 0)
