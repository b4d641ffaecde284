"""The collector relaxed while numba compiles mbm's kernels (mbm.compile.gc): raised for
the outermost compile of an mbm kernel and all compiles inside it, restored after it
(also when it fails), untouched for other compiles, for a warm cache and when turned off."""

import gc
import inspect
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from numba.core import event

from mbm.compile import gc as _compile_gc

ROOT = Path(__file__).resolve().parents[2]


class _Dispatcher:
    def __init__(self, module):
        def f():
            pass

        f.__module__ = module
        self.py_func = f


def _compile(listener, module, inner=()):
    # A compile of a kernel of ``module`` as numba broadcasts it, with ``inner`` compiled
    # inside it; returns the gen-0 thresholds seen during each, outermost first.
    seen = []
    data = {"dispatcher": _Dispatcher(module)}
    listener.on_start(event.Event("numba:compile", event.EventStatus.START, data))
    seen.append(gc.get_threshold()[0])
    for m in inner:
        seen += _compile(listener, m)
    listener.on_end(event.Event("numba:compile", event.EventStatus.END, data))
    return seen


@pytest.fixture
def thresholds():
    saved = gc.get_threshold()
    gc.set_threshold(700, 10, 10)
    yield
    gc.set_threshold(*saved)


def test_raised_for_an_mbm_kernel_and_what_it_compiles_then_restored(thresholds):
    listener = _compile_gc._listener_class()()
    high = _compile_gc.COMPILE_GEN0_THRESHOLD
    assert _compile(listener, "mbm.core.loop", inner=("numba.np.arrayobj", "mbm.special.dd")) == [high] * 3
    assert gc.get_threshold() == (700, 10, 10)
    # another package's compile, and an mbm kernel compiled inside it
    assert _compile(listener, "numba.np.arrayobj", inner=("mbm.special.dd",)) == [700, high]
    assert gc.get_threshold() == (700, 10, 10) and listener.depth == 0


def test_a_higher_user_threshold_is_kept(thresholds):
    gc.set_threshold(10 ** 6, 5, 5)
    assert _compile(_compile_gc._listener_class()(), "mbm.frontends.solve") == [10 ** 6]
    assert gc.get_threshold() == (10 ** 6, 5, 5)


class _Probe(event.Listener):
    """Registered after mbm's listener: the gen-0 threshold each compile starts with."""

    def __init__(self):
        self.seen = []

    def on_start(self, ev):
        self.seen.append(gc.get_threshold()[0])

    def on_end(self, ev):
        pass


def test_restored_when_a_compile_fails(thresholds):
    import numba

    listener = _compile_gc.install()  # import mbm's, registered once
    if listener is None:
        pytest.skip("turned off by MBM_COMPILE_GC")

    def probe(x):
        return x.no_such_attribute

    probe.__module__ = "mbm._probe_gc"  # an mbm kernel as the listener tells them
    spy = _Probe()
    event.register("numba:compile", spy)
    try:
        with pytest.raises(numba.core.errors.TypingError):
            numba.njit(probe)(1.0)
    finally:
        event.unregister("numba:compile", spy)
    assert spy.seen == [_compile_gc.COMPILE_GEN0_THRESHOLD]
    assert gc.get_threshold() == (700, 10, 10) and listener.depth == 0


_CHILD = textwrap.dedent("""
    import gc, json
    import numpy as np
    import mbm
    from numba.core import event
    from mbm.compile import gc as _compile_gc
""") + textwrap.dedent(inspect.getsource(_Probe)) + textwrap.dedent("""
    spy = _Probe()
    event.register("numba:compile", spy)
    before = gc.get_threshold()
    mbm.solve(mbm.Pendulum(0.1, 0.3), (0.0, 1.0), [0.1, 0.0], tau=0.5)
    print(json.dumps({"before": before, "after": gc.get_threshold(), "seen": sorted(set(spy.seen))}))
""")


@pytest.mark.parametrize("setting", ["", "0"])
def test_a_first_call_compiles_with_it_unless_turned_off(tmp_path, setting):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), MBM_COMPILE_NOTICE="0", MBM_COMPILE_HELPER="0",
               MBM_COMPILE_GC=setting, PYTHONPATH=str(ROOT))
    proc = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    import json

    got = json.loads(proc.stdout.strip().splitlines()[-1])
    assert got["after"] == got["before"]
    want = _compile_gc.COMPILE_GEN0_THRESHOLD if setting == "" else got["before"][0]
    assert got["seen"] == [want]
    # a warm cache compiles nothing: a second process sees no compile at all
    proc = subprocess.run([sys.executable, "-c", _CHILD], env=env, capture_output=True, text=True, timeout=600)
    assert json.loads(proc.stdout.strip().splitlines()[-1])["seen"] == []


def test_the_benchmark_page_takes_medians_and_marks_a_failed_setting():
    from benchmarks import compile_gc

    page = compile_gc.format_page({"relaxed": [[7.9, 6.0, 316.4], None, [8.1, 6.2, 311.0]],
                                   "MBM_COMPILE_GC=0": [None]}, 3)
    assert "| relaxed | 8.0 | 6.1 | 314 |" in page
    assert "| MBM_COMPILE_GC=0 | failed | failed | failed |" in page
    assert "median of 3" in page and "python -m benchmarks.compile_gc" in page
