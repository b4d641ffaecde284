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


# Two closures of one function, each called by a kernel of its own: a body long enough
# that LLVM calls it instead of inlining it (the loop's entries, on a small scale).
_CLOSURES = '''
import math
import numba

def make(k):
    @numba.njit(cache=True)
    def f(x):
        s = 0.0
        for _ in range(3):
{body}
        return s + k
    return f

f1 = make(1.0)
f2 = make(2.0)

@numba.njit(cache=True)
def call1(x):
    return f1(x)

@numba.njit(cache=True)
def call2(x):
    return f2(x)
'''
_CALLS = '''
import sys
if sys.argv[1] == "mbm":
    import mbm
import closures
print(*[{"1": closures.call1, "2": closures.call2}[w](0.0) for w in sys.argv[2]])
'''


def _cached_in_turn(tmp_path, mode):
    # call1 cached by one process, call2 by another (each compiles its closure first, so
    # with numba's counter both get the same id), both loaded by a third.
    import subprocess
    import sys

    body = "\n".join(f"            s += math.sin(x * {i} + k) * math.cos(x + {i}) / (1.0 + x * x + {i})"
                     for i in range(60))
    (tmp_path / "closures.py").write_text(_CLOSURES.format(body=body))
    (tmp_path / "calls.py").write_text(_CALLS)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(tmp_path)] + sys.path), MBM_COMPILE_NOTICE="0",
               MBM_COMPILE_HELPER="0")
    if mode == "off":
        env[cache_lock.LOCK_ENV] = "0"

    def run(which):
        out = subprocess.run([sys.executable, str(tmp_path / "calls.py"), "mbm", which], env=env, cwd=tmp_path,
                             capture_output=True, text=True, check=True).stdout.split()
        return [float(x) for x in out]

    alone = run("1") + run("2")
    return alone, run("12")


def test_closures_cached_by_two_processes_keep_their_own_bodies(tmp_path):
    alone, both = _cached_in_turn(tmp_path, "on")
    assert alone[0] != alone[1]
    assert both == alone


def test_without_random_ids_the_closures_cross(tmp_path):
    # The hazard the random ids remove, on this numba (issue #10486): the third process
    # runs call1's body for call2.  Should numba name its functions apart one day, this
    # fails and says that the workaround may go.
    alone, both = _cached_in_turn(tmp_path, "off")
    assert both == [alone[0], alone[0]]
