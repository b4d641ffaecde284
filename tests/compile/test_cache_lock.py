"""mbm.compile.cache_lock: numba's cache index is not crossed by two processes saving at once.

How often it is crossed without the lock: ``python -m benchmarks.cache_race`` (50-60 of
120 keys per trial on the 2-core development machine).
"""

import os

import pytest

from mbm.compile import cache_lock

pytest.importorskip("fcntl", reason="no fcntl (Windows): the lock is not installed there, numba's cache stays as it is")


def test_two_processes_saving_at_once_keep_each_key_with_its_own_data(tmp_path):
    from benchmarks.cache_race import crossed

    assert cache_lock.install()
    assert crossed(str(tmp_path)) == []
    assert any(name.endswith(cache_lock.LOCK_SUFFIX) for name in os.listdir(tmp_path))


def test_the_benchmark_counts_both_ways():
    from benchmarks.cache_race import counts

    c = counts(trials=1, keys=20)
    assert c["locked"] == [0] and len(c["unlocked"]) == 1 and 0 <= c["unlocked"][0] <= 40
    from numba.core.caching import IndexDataCacheFile

    assert IndexDataCacheFile.save.__mbm_cache_lock__  # left as import mbm installed it


def test_install_is_idempotent_and_can_be_turned_off(monkeypatch):
    from numba.core.caching import IndexDataCacheFile

    assert cache_lock.install() and cache_lock.install()
    assert IndexDataCacheFile.save.__mbm_cache_lock__
    assert not IndexDataCacheFile.save.__wrapped__.__dict__.get("__mbm_cache_lock__", False)
    monkeypatch.setenv(cache_lock.LOCK_ENV, "0")
    assert not cache_lock.install()
