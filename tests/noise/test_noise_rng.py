"""The counter-based generator: its law, and runs reproducible across thread counts."""

import math

import numba
import numpy as np
import pytest
from numba import njit

import mbm
from mbm.noise import rng


@njit
def _normals(seed, scene, n):
    key = rng.scene_key(np.uint64(seed), scene)
    out = np.empty(2 * n)
    for k in range(n):
        out[2 * k], out[2 * k + 1] = rng.normal_pair(key, k)
    return out


def test_normals_have_the_standard_normal_moments():
    z = _normals(1, 3, 500_000)
    n = z.size
    assert abs(z.mean()) < 4.5 / math.sqrt(n)
    assert abs(z.var() - 1.0) < 4.5 * math.sqrt(2.0 / n)
    assert abs((z**3).mean()) < 4.5 * math.sqrt(15.0 / n)
    assert abs((z**4).mean() - 3.0) < 4.5 * math.sqrt(96.0 / n)
    # neighbours uncorrelated, and the two halves of a pair
    assert abs(np.mean(z[1:] * z[:-1])) < 4.5 / math.sqrt(n)
    # streams of neighbouring scenes and seeds are not correlated either
    for other in (_normals(1, 4, 500_000), _normals(2, 3, 500_000)):
        assert abs(np.mean(z * other)) < 4.5 / math.sqrt(n)


def test_same_seed_same_bits_on_one_and_two_threads():
    kw = dict(seed=2024, dt=0.2)
    one = mbm.escape_times(1.0, 0.5, 0.15, 64, threads=1, **kw).times
    two = mbm.escape_times(1.0, 0.5, 0.15, 64, threads=min(2, numba.config.NUMBA_NUM_THREADS), **kw).times
    again = mbm.escape_times(1.0, 0.5, 0.15, 64, **kw).times
    assert np.array_equal(one, two) and np.array_equal(one, again)
    assert np.all(np.isfinite(one))
    # a scene's numbers do not depend on how many scenes run with it (chunking)
    assert np.array_equal(mbm.escape_times(1.0, 0.5, 0.15, 7, **kw).times, one[:7])
    other = mbm.escape_times(1.0, 0.5, 0.15, 64, seed=2025, dt=0.2).times
    assert not np.any(other == one)


def test_switching_reproducible_across_threads():
    kw = dict(seed=9, dt=0.2, gamma_start=0.6)
    one = mbm.switching_currents(0.5, 0.05, 1e-3, 32, threads=1, **kw).currents
    two = mbm.switching_currents(0.5, 0.05, 1e-3, 32, threads=min(2, numba.config.NUMBA_NUM_THREADS), **kw).currents
    assert np.array_equal(one, two)
    assert not np.array_equal(one, mbm.switching_currents(0.5, 0.05, 1e-3, 32, seed=10, dt=0.2,
                                                          gamma_start=0.6).currents)


def test_seed_none_is_drawn_and_kept():
    r = mbm.escape_times(1.0, 0.5, 0.3, 4, dt=0.2)
    assert 0 <= r.seed < 2**64
    assert np.array_equal(mbm.escape_times(1.0, 0.5, 0.3, 4, dt=0.2, seed=r.seed).times, r.times)


@pytest.mark.parametrize("seed,err", [(-1, ValueError), (2**64, ValueError), (1.5, TypeError),
                                      (True, TypeError), ("1", TypeError)])
def test_bad_seeds_are_refused(seed, err):
    with pytest.raises(err, match="seed"):
        rng.resolve_seed(seed)


def test_chunks_do_not_change_the_bits(monkeypatch):
    # The scenes run CHUNK_SCENES per compiled call (a Ctrl-C lands between calls):
    # scene i draws stream i whatever the chunking.
    from mbm.noise import api

    whole = mbm.escape_times(1.0, 0.5, 0.15, 10, seed=7).times
    sw = mbm.switching_currents(0.5, 0.05, 1e-3, 10, seed=7).currents
    monkeypatch.setattr(api, "CHUNK_SCENES", 3)
    np.testing.assert_array_equal(mbm.escape_times(1.0, 0.5, 0.15, 10, seed=7).times.view(np.int64),
                                  whole.view(np.int64))
    np.testing.assert_array_equal(mbm.switching_currents(0.5, 0.05, 1e-3, 10, seed=7).currents.view(np.int64),
                                  sw.view(np.int64))
    # ... and the first scenes of a larger run are those of a smaller one.
    np.testing.assert_array_equal(mbm.escape_times(1.0, 0.5, 0.15, 4, seed=7).times, whole[:4])
