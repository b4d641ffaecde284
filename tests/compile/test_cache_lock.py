"""mbm.compile.cache_lock: numba's cache index is not crossed by two processes saving at once."""

import multiprocessing
import os

import pytest

from mbm.compile import cache_lock

pytest.importorskip("fcntl", reason="no fcntl (Windows): the lock is not installed there, numba's cache stays as it is")

KEYS_PER_PROCESS = 60


def _save_keys(folder, tag, start, lock):
    from numba.core.caching import IndexDataCacheFile

    if lock:
        cache_lock.install()
    f = IndexDataCacheFile(folder, "kernel-1.py311", ("stamp", 1))
    start.wait()
    for i in range(KEYS_PER_PROCESS):
        f.save((tag, i), f"{tag}{i}".encode())


def _crossed(folder, lock):
    from numba.core.caching import IndexDataCacheFile

    ctx = multiprocessing.get_context("fork")
    start = ctx.Barrier(2)
    procs = [ctx.Process(target=_save_keys, args=(folder, tag, start, lock)) for tag in "ab"]
    for p in procs:
        p.start()
    for p in procs:
        p.join(60)
        assert p.exitcode == 0
    f = IndexDataCacheFile(folder, "kernel-1.py311", ("stamp", 1))
    return [(tag, i) for tag in "ab" for i in range(KEYS_PER_PROCESS) if f.load((tag, i)) != f"{tag}{i}".encode()]


def test_two_processes_saving_at_once_keep_each_key_with_its_own_data(tmp_path):
    assert cache_lock.install()
    assert _crossed(str(tmp_path), lock=True) == []
    assert any(name.endswith(cache_lock.LOCK_SUFFIX) for name in os.listdir(tmp_path))


def test_install_is_idempotent_and_can_be_turned_off(monkeypatch):
    from numba.core.caching import IndexDataCacheFile

    assert cache_lock.install() and cache_lock.install()
    assert IndexDataCacheFile.save.__mbm_cache_lock__
    assert not IndexDataCacheFile.save.__wrapped__.__dict__.get("__mbm_cache_lock__", False)
    monkeypatch.setenv(cache_lock.LOCK_ENV, "0")
    assert not cache_lock.install()
