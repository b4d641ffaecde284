"""The compile helper (mbm.compile.warm): when it starts, that answers never depend on it, and
that its generated manifest matches what a first call compiles."""

import json
import os
import pickle
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import mbm
from mbm.compile import warm as _warm
from mbm.core import loop

ROOT = Path(__file__).resolve().parents[2]
DAMPED_KEY = ("solve", "mbm.core.loop", "SIMD_RUNNERS", (loop.RS_DAMPED,))


def _env(cache, **extra):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), MBM_COMPILE_NOTICE="0", **extra)
    env.pop(_warm._IN_HELPER_ENV, None)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    return env


def test_an_entry_is_keyed_where_its_own_module_binds_it():
    # not under another module's import of it or an alias (mbm.core.chains._R_V1)
    assert _warm.entry_key(loop.SIMD_RUNNERS[loop.RS_DAMPED]) == DAMPED_KEY[1:]
    assert _warm.entry_key(loop.RUNNERS[(0, 0)]) == ("mbm.core.loop", "RUNNERS", ((0, 0),))
    # the other kinds share the default Taylor degree's entries
    assert loop.RUNNERS[(2, loop.RS_FIXED)] is loop.SIMD_RUNNERS[loop.RS_FIXED]
    assert _warm.entry_key(loop.RUNNERS[(2, loop.RS_FIXED)]) == ("mbm.core.loop", "SIMD_RUNNERS", (loop.RS_FIXED,))
    from mbm.core import lanes

    assert _warm.entry_key(lanes._run_lanes) == ("mbm.core.lanes", "_run_lanes", ())


def test_every_manifest_row_names_a_kernel_of_the_package():
    paths = _warm.load_manifest()
    assert set(paths) == set(_warm.SCENES)
    for key, rows in paths.items():
        assert len(rows) > 10  # (the exact flow's mbm.solve entry: 18; its formulas under its kind's key)
        entry = _warm._resolve(*key[1:])
        for module, name, item, sig in rows:
            disp = _warm._resolve(module, name, item)
            assert disp is not entry and hasattr(disp, "compile")
            assert len(sig) == disp.py_func.__code__.co_argcount


@pytest.mark.parametrize("key", [DAMPED_KEY])
def test_the_manifest_is_what_a_first_call_compiles_now(key):
    # regenerate one scene (the others: `pytest -m slow`); a stale manifest only slows a
    # first call, but says that `python -m benchmarks.warm_manifest` is due
    _fresh_equals_stored(key)


@pytest.mark.slow
@pytest.mark.parametrize("key", [k for k in _warm.SCENES if k != DAMPED_KEY])
def test_the_manifest_is_what_every_first_call_compiles_now(key):
    _fresh_equals_stored(key)


def _fresh_equals_stored(key):
    import tempfile

    with tempfile.TemporaryDirectory() as cache:
        proc = subprocess.run([sys.executable, "-c", _warm._CAPTURE, _warm._SCENE_SETUP, _warm.SCENES[key],
                               repr(key)], env=_env(cache, MBM_COMPILE_HELPER="0"), capture_output=True,
                              timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    fresh = pickle.loads(proc.stdout)
    stored = _warm.load_manifest()[key]
    assert [(m, n, i, str(s)) for m, n, i, s in fresh] == [(m, n, i, str(s)) for m, n, i, s in stored]


_COLD_SOLVE = textwrap.dedent("""
    import json, math, sys
    import numpy as np
    import mbm
    from mbm.compile import warm as _warm
    m = mbm.Pendulum(beta=0.1, gamma=0.3)
    t = np.linspace(0.0, 80.0, 201)
    r = mbm.solve(m, (0.0, 80.0), [math.radians(30), 0.0], rtol=1e-9, atol=1e-9, t_eval=t)
    helpers = _warm.release()  # no further keys: the helper ends once done
    codes = [h.wait(timeout=600) for h in helpers]
    # the entry the call compiled is in the cache now; another closure of the same
    # function (the fixed windows' entry, sharing its index file) is not
    from mbm.core import loop
    cold = [_warm._cold(loop.SIMD_RUNNERS[loop.RS_DAMPED]), _warm._cold(loop.SIMD_RUNNERS[loop.RS_FIXED])]
    print(json.dumps({"y": r.y.tolist(), "helpers": len(helpers), "codes": codes, "cold": cold}))
""")


def test_a_cold_first_call_starts_one_helper_and_its_answers_are_the_warm_ones(tmp_path):
    if _warm._cores() < 2:
        pytest.skip("the helper needs a second core")
    proc = subprocess.run([sys.executable, "-c", _COLD_SOLVE], env=_env(tmp_path), cwd=ROOT, capture_output=True,
                          text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-2000:]
    got = json.loads(proc.stdout.strip().splitlines()[-1])
    assert got["helpers"] == 1 and got["codes"] == [0]
    assert got["cold"] == [False, True]
    want = mbm.solve(mbm.Pendulum(beta=0.1, gamma=0.3), (0.0, 80.0), [np.radians(30), 0.0], rtol=1e-9,
                     atol=1e-9, t_eval=np.linspace(0.0, 80.0, 201))
    np.testing.assert_array_equal(np.array(got["y"]), want.y)


def test_a_process_that_exits_with_its_helper_up_stops_it_and_leaves_no_file_open(tmp_path):
    if _warm._cores() < 2:
        pytest.skip("the helper needs a second core")
    code = ("from mbm.compile import warm as _warm; print(_warm.prefetch_keys([_warm.DEMO_KEYS[0]]), "
            "[p.poll() for p in _warm._started.values()])")
    proc = subprocess.run([sys.executable, "-X", "dev", "-c", code], env=_env(tmp_path), cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.split() == ["True", "[None]"]  # started, and up when the process ended
    assert "ResourceWarning" not in proc.stderr, proc.stderr[-2000:]


def test_no_helper_for_a_compiled_entry_when_turned_off_or_inside_a_helper(monkeypatch):
    entry = loop.SIMD_RUNNERS[loop.RS_DAMPED]
    mbm.solve(mbm.Pendulum(0.1, 0.3), (0.0, 1.0), [0.1, 0.0])  # compiled in this process
    monkeypatch.setattr(_warm, "_checked", set())
    assert entry.signatures and _warm.prefetch("solve", entry) is False
    monkeypatch.setattr(_warm, "_cold", lambda e: True)

    class Fake:  # a cold entry: nothing compiled, bound where the damped scene's entry is
        signatures = []

    fake = Fake()
    monkeypatch.setattr(_warm, "entry_key", lambda e: DAMPED_KEY[1:] if e is fake else None)
    started = []
    monkeypatch.setattr(_warm.subprocess, "Popen", lambda *a, **k: started.append(a) or object())
    monkeypatch.setattr(_warm, "_started", {})

    def prefetch(path):  # a process that has not looked at the entry yet
        _warm._checked.discard(fake)
        return _warm.prefetch(path, fake)

    monkeypatch.setenv(_warm.HELPER_ENV, "0")
    assert prefetch("solve") is False
    monkeypatch.delenv(_warm.HELPER_ENV)
    monkeypatch.setenv(_warm._IN_HELPER_ENV, "1")
    assert prefetch("solve") is False
    monkeypatch.delenv(_warm._IN_HELPER_ENV)
    assert prefetch("ivp-unknown") is False  # no manifest path for it
    if _warm._cores() >= 2:
        assert prefetch("solve") is True
        assert prefetch("solve") is False  # one helper per path and process
        assert len(started) == 1 and "main" in started[0][0][2]
    # an entry looked at once is not looked at again (a set lookup per later call)
    monkeypatch.setattr(_warm, "_cold", lambda e: pytest.fail("looked at twice"))
    assert _warm.prefetch("solve", fake) is False


def test_prefetch_keys_starts_one_helper_for_the_cold_keys_in_order(monkeypatch):
    if _warm._cores() < 2:
        pytest.skip("the helper needs a second core")
    keys = list(_warm.DEMO_KEYS)  # the demo's: auto, then salas-torque's pieces and entry
    assert set(keys) <= set(_warm.SCENES) and keys[1] == _warm.kind_key(loop.KIND_SALAS_TORQUE)
    assert keys[2][3] == (loop.RS_FIXED,)
    entries = [_warm._key_target(key) for key in keys]
    assert len(keys) == 3 and len({id(e) for e in entries}) == 3
    started = []
    monkeypatch.setattr(_warm.subprocess, "Popen", lambda *a, **k: started.append(a[0]) or object())
    for cold, want in (({1}, [keys[1]]), ({0, 1, 2}, keys)):
        monkeypatch.setattr(_warm, "_uncompiled", lambda e, cold=cold: any(e is entries[j] for j in cold))
        monkeypatch.setattr(_warm, "_started", {})
        monkeypatch.setattr(_warm, "_checked", set())
        started.clear()
        assert _warm.prefetch_keys(keys) is True
        # one helper, for the cold keys in order; each key is then taken
        assert len(started) == 1 and started[0][3:] == [repr(k) for k in want]
        assert set(_warm._started) == set(want)
        assert _warm.prefetch_keys(keys) is False and _warm.prefetch("ivp", entries[2]) is False
        assert len(started) == 1
    monkeypatch.setattr(_warm, "_started", {})
    monkeypatch.setattr(_warm, "_checked", set())
    monkeypatch.setenv(_warm.HELPER_ENV, "0")
    assert _warm.prefetch_keys(keys) is False and not _warm._started


def test_a_manifest_of_another_numba_or_a_stale_row_is_ignored(monkeypatch, tmp_path):
    other = tmp_path / "m.pkl"
    other.write_bytes(pickle.dumps({"numba": "0.0.0", "paths": {DAMPED_KEY: []}}))
    monkeypatch.setattr(_warm, "MANIFEST_FILE", str(other))
    monkeypatch.setattr(_warm, "_manifest", [])
    assert _warm.load_manifest() == {}
    monkeypatch.setattr(_warm, "_manifest", [])
    (tmp_path / "bad.pkl").write_bytes(b"not a pickle")
    monkeypatch.setattr(_warm, "MANIFEST_FILE", str(tmp_path / "bad.pkl"))
    assert _warm.load_manifest() == {}
    # a row naming a kernel that is gone, then one with a signature it no longer takes
    rows = [("mbm.core.loop", "no_such_kernel", (), ()), ("mbm.core.window", "theta_of", (), ())]
    assert _warm.compile_path(rows) == 0


def test_the_helper_takes_the_mirror_image_of_the_calls_order(monkeypatch):
    # A call tree entry -> (a -> (a1, a2), b -> (b1, a2)), compiled by the call leftmost
    # first (ends: a1, a2, a, b1, b, entry), then x after the entry (the dense output's)
    # and p before it out of the entry's reach (solve_ivp's width from Python).
    class Lib:
        def __init__(self, callees=()):
            self._linking_libraries = [c.lib for c in callees]

    class Res:
        def __init__(self, lib):
            self.library = lib

    class Disp:
        def __init__(self, name, *callees):
            self.name, self.lib = name, Lib(callees)
            self.overloads = {("sig", name): Res(self.lib)}

    a1, a2, b1, p, x = (Disp(n) for n in ("a1", "a2", "b1", "p", "x"))
    a, b = Disp("a", a1, a2), Disp("b", b1, a2)
    entry = Disp("entry", a, b)
    ends = [p, a1, a2, a, b1, b, entry, x]
    monkeypatch.setattr(_warm, "_resolve", lambda *where: entry)
    monkeypatch.setattr(_warm, "_locations", lambda: {id(d): ("m", d.name, ()) for d in ends})
    rows = _warm._recorded(ends, ("ivp", "m", "entry", ()))
    assert [name for _, name, _, _ in rows] == ["b1", "a2", "b", "a1", "a", "p", "x"]
    assert rows[0][3] == ("sig", "b1")


def test_a_helper_takes_further_keys_on_stdin_until_it_ends(monkeypatch):
    # the helper's body in this process: its argv's keys, then each line of its stdin
    import io

    done = []
    monkeypatch.setattr(_warm, "compile_path", lambda rows: done.append(rows) or len(rows))
    monkeypatch.setattr(_warm, "load_manifest", lambda: {("a",): ["A"], ("b",): ["B"], ("c",): ["C"]})
    monkeypatch.setattr(sys, "stdin", io.StringIO(repr(("b",)) + "\n\n" + repr(("c",)) + "\n"))
    assert _warm.main([repr(("a",))]) == 0
    assert done == [["A"], ["B"], ["C"]]


def test_a_helper_without_a_further_key_ends_after_its_linger(monkeypatch):
    import time

    r, w = os.pipe()  # a stdin that stays open and silent
    try:
        monkeypatch.setattr(sys, "stdin", os.fdopen(r, "r"))
        monkeypatch.setattr(_warm, "HELPER_LINGER", 0.2)
        monkeypatch.setattr(_warm, "compile_path", lambda rows: 0)
        t0 = time.perf_counter()
        assert _warm.main([]) == 0
        assert time.perf_counter() - t0 < 5.0
    finally:
        os.close(w)


def test_a_further_cold_entry_sends_its_key_to_the_running_helper(monkeypatch):
    import io

    class Helper:  # a helper process: up until ``ended``
        def __init__(self, *args, **kwargs):
            self.args, self.stdin, self.ended = args, io.BytesIO(), False
            started.append(self)

        def poll(self):
            return 0 if self.ended else None

    started = []
    keys = [key for key in _warm.SCENES if key[0] == "ivp"][:2]
    entries = [_warm._resolve(*key[1:]) for key in keys]
    monkeypatch.setattr(_warm.subprocess, "Popen", Helper)
    monkeypatch.setattr(_warm, "_cores", lambda: 2)
    monkeypatch.setattr(_warm, "_uncompiled", lambda e: True)
    monkeypatch.setattr(_warm, "_started", {})
    monkeypatch.setattr(_warm, "_checked", set())
    assert _warm.prefetch("ivp", entries[0]) is True and len(started) == 1
    assert _warm.prefetch("ivp", entries[1]) is True and len(started) == 1  # sent, not started
    assert started[0].stdin.getvalue().decode() == repr(keys[1]) + "\n"
    assert _warm._started == {keys[0]: started[0], keys[1]: started[0]}
    # a helper that has ended takes nothing: the next cold key starts another
    started[0].ended = True
    monkeypatch.setattr(_warm, "_started", {keys[0]: started[0]})
    monkeypatch.setattr(_warm, "_checked", set())
    assert _warm.prefetch("ivp", entries[1]) is True and len(started) == 2
    assert started[1].args[0][3:] == [repr(keys[1])]
    # release: no further keys, each helper's stdin closed
    assert set(_warm.release()) == {started[0], started[1]} and started[1].stdin.closed
