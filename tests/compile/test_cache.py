"""numba's disk cache follows edits of mbm's sources, and a compile says so (mbm.compile.cache).

The cache tests run a copy of the package in subprocesses, so that editing a source
and emptying a cache touch neither the installed package nor its cache.  Two probe
modules added to the copy (hashed like every other source) give a cached kernel whose
result comes from a cached callee in another file: the case numba's cache misses.
"""

import os
import pathlib
import shutil
import subprocess
import sys

import numba
import pytest

import mbm
from mbm.compile import cache as _cache

PACKAGE = pathlib.Path(mbm.__file__).resolve().parent
NOTICE = "mbm: "

PROBE_B = '''import numba


@numba.njit(cache=True)
def g(x):
    return 2.0 * x + 10.0
'''

PROBE_A = '''import numba

from mbm._probe_b import g


@numba.njit(cache=True)
def f(x):
    return g(x) + 1.0
'''

CALL_PROBE = "import mbm\nfrom mbm._probe_a import f\nprint(f(1.0))\n"
CALL_TRIG = "import mbm\nfrom mbm.special.trig import sin_m_kernel\nprint(sin_m_kernel(0.3, 0.5))\n"


def _run(code, cwd, pythonpath, **env_overrides):
    """Run ``code`` in a fresh interpreter; returns (stdout, notice lines on stderr)."""
    env = {k: v for k, v in os.environ.items()
           if k not in ("NUMBA_CACHE_DIR", "MBM_KEEP_CACHE", "MBM_COMPILE_NOTICE")}
    env["PYTHONPATH"] = str(pythonpath)
    env.update({k: str(v) for k, v in env_overrides.items() if v is not None})
    proc = subprocess.run([sys.executable, "-c", code], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    notices = [line for line in proc.stderr.splitlines() if line.startswith(NOTICE)]
    return proc.stdout.strip(), notices


@pytest.fixture
def package_copy(tmp_path):
    """A copy of the mbm package (no caches) under tmp_path/pkg, with the two probes."""
    root = tmp_path / "pkg"
    shutil.copytree(PACKAGE, root / "mbm", ignore=shutil.ignore_patterns("__pycache__"))
    (root / "mbm" / "_probe_b.py").write_text(PROBE_B)
    (root / "mbm" / "_probe_a.py").write_text(PROBE_A)
    return root


@pytest.mark.parametrize("where", ["in-tree", "NUMBA_CACHE_DIR"])
def test_edited_callee_in_another_file_is_recompiled(package_copy, tmp_path, where):
    numba_dir = tmp_path / "numba-cache" if where == "NUMBA_CACHE_DIR" else None

    def run(**env):
        return _run(CALL_PROBE, package_copy, package_copy, NUMBA_CACHE_DIR=numba_dir, **env)

    out, notices = run()
    assert out == "13.0" and len(notices) == 1 and "mbm._probe_a.f" in notices[0]
    # numba's files and the digest went where cache_dirs says numba puts them.
    pkg_dir = str(package_copy / "mbm")
    (cache,) = _cache.cache_dirs([pkg_dir], cache_dir=str(numba_dir) if numba_dir else "")
    if numba_dir is None:
        assert cache == os.path.join(pkg_dir, "__pycache__")
    else:
        assert cache.startswith(str(numba_dir))
        assert not list((package_copy / "mbm").glob("__pycache__/*.nb[ic]"))
    names = os.listdir(cache)
    assert _cache.HASH_FILE in names
    assert any(n.startswith("_probe_a.f-") and n.endswith(".nbi") for n in names)
    assert any(n.startswith("_probe_b.g-") and n.endswith(".nbi") for n in names)

    # Unchanged sources: the cache is kept (nothing compiles).
    assert run() == ("13.0", [])

    # The callee's constant edited (same size, so only contents tell): without the check
    # numba loads f's stale machine code, with it f is recompiled.
    probe_b = package_copy / "mbm" / "_probe_b.py"
    probe_b.write_text(PROBE_B.replace("10.0", "20.0"))
    assert run(MBM_KEEP_CACHE=1) == ("13.0", [])
    out, notices = run()
    assert out == "23.0" and len(notices) == 1
    assert run() == ("23.0", [])


def test_cache_check_survives_unwritable_locations(package_copy, tmp_path):
    """In-tree __pycache__ and NUMBA_CACHE_DIR unusable (files where folders should be,
    which stops root too): numba falls back to its user-wide folder, and so does the check."""
    blocker = tmp_path / "not-a-folder"
    blocker.write_text("")
    for sub in ("", "approximants", "special"):
        (package_copy / "mbm" / sub / "__pycache__").write_text("")
    xdg = tmp_path / "xdg"
    out, notices = _run(CALL_PROBE, package_copy, package_copy,
                        NUMBA_CACHE_DIR=blocker / "sub", XDG_CACHE_HOME=xdg)
    assert out == "13.0" and len(notices) == 1
    (cache,) = _cache.cache_dirs([str(package_copy / "mbm")], cache_dir=str(blocker / "sub"),
                                 user_cache_dir=str(xdg / "numba"))
    assert cache.startswith(str(xdg / "numba"))
    names = os.listdir(cache)
    assert _cache.HASH_FILE in names and any(n.endswith(".nbi") for n in names)


def test_cache_check_never_raises_on_os_errors(tmp_path, monkeypatch):
    """A read-only installation: every write fails; the check gives up quietly."""
    root = tmp_path / "mbm"
    (root / "__pycache__").mkdir(parents=True)
    (root / "a.py").write_text("x = 1\n")
    (root / "__pycache__" / "a.f-3.py311.nbi").write_text("")

    def refuse(*args, **kwargs):
        raise PermissionError(30, "Read-only file system")

    monkeypatch.setattr(_cache.os, "remove", refuse)
    monkeypatch.setattr(_cache.os, "replace", refuse)
    assert _cache.check_sources(str(root)) is False
    assert (root / "__pycache__" / "a.f-3.py311.nbi").exists()

    # No usable cache folder at all: nothing to do, no error.
    monkeypatch.setattr(_cache, "_usable_dir", lambda path: False)
    assert _cache.cache_dirs([str(root)], cache_dir="") == []
    assert _cache.check_sources(str(root)) is True

    # Unreadable sources (os.scandir fails): skipped, no error.
    assert _cache.check_sources(str(tmp_path / "missing")) is False


def test_keep_cache_env_skips_the_check(tmp_path, monkeypatch):
    root = tmp_path / "mbm"
    (root / "__pycache__").mkdir(parents=True)
    (root / "a.py").write_text("x = 1\n")
    stale = root / "__pycache__" / "a.f-3.py311.nbi"
    stale.write_text("")
    # The package's own __pycache__ is the cache (not a NUMBA_CACHE_DIR the run was given).
    monkeypatch.setattr(numba.core.config, "CACHE_DIR", "")
    monkeypatch.setenv("MBM_KEEP_CACHE", "1")
    assert _cache.check_sources(str(root)) is False and stale.exists()
    monkeypatch.setenv("MBM_KEEP_CACHE", "0")
    assert _cache.check_sources(str(root)) is True and not stale.exists()
    digest = (root / "__pycache__" / _cache.HASH_FILE).read_text().strip()
    assert digest == _cache.sources_digest(str(root))


def test_sources_digest_follows_contents_and_names(tmp_path):
    root = tmp_path / "mbm"
    (root / "sub").mkdir(parents=True)
    (root / "a.py").write_text("x = 1\n")
    (root / "sub" / "b.py").write_text("y = 2\n")
    (root / "sub" / "notes.txt").write_text("not a source")
    first = _cache.sources_digest(str(root))
    (root / "sub" / "notes.txt").write_text("still not a source")
    (root / "__pycache__").mkdir()
    (root / "__pycache__" / "c.py").write_text("")
    assert _cache.sources_digest(str(root)) == first
    (root / "sub" / "b.py").write_text("y = 3\n")
    assert _cache.sources_digest(str(root)) != first
    (root / "sub" / "b.py").write_text("y = 2\n")
    (root / "sub" / "b.py").rename(root / "sub" / "c.py")
    assert _cache.sources_digest(str(root)) != first


def test_compile_notice_once_then_silent(tmp_path):
    """A cold cache prints one line naming the kernel (its callee compiles too, silently);
    the warm cache prints nothing; MBM_COMPILE_NOTICE=0 silences a cold one."""
    repo = PACKAGE.parent
    cold = tmp_path / "cold"
    out, notices = _run(CALL_TRIG, tmp_path, repo, NUMBA_CACHE_DIR=cold)
    assert len(notices) == 1, notices
    # called directly (no mbm function on the stack): the kernel named
    assert notices[0].startswith("mbm: compiling numba kernels for mbm.special.trig.sin_m_kernel (the first "
                                 "call after installing or upgrading mbm; typically 5-20 s on 2 cores, ")
    assert "once: later calls load them from %s" % cold in notices[0]
    assert _run(CALL_TRIG, tmp_path, repo, NUMBA_CACHE_DIR=cold) == (out, [])
    quiet = tmp_path / "quiet"
    assert _run(CALL_TRIG, tmp_path, repo, NUMBA_CACHE_DIR=quiet,
                MBM_COMPILE_NOTICE=0) == (out, [])
    assert any(p.suffix == ".nbi" for p in quiet.rglob("*"))  # it did compile


def test_compile_notice_ignores_other_packages(capsys):
    """Kernels outside mbm compile without a word (and do not use up the one line)."""
    import numba

    listener = _cache._install_listener()
    try:
        @numba.njit
        def outside(x):
            return x + 1

        assert outside(1) == 2
        assert not listener.done
        assert NOTICE not in capsys.readouterr().err
    finally:
        from numba.core import event

        event.unregister("numba:compile", listener)


def test_compile_notice_names_the_users_call(capsys):
    """From a public function, the notice names that function, not an internal kernel."""
    import numba

    namespace = {"__name__": "mbm.fake_entry", "numba": numba}
    exec("kern = numba.njit(lambda x: x + 1.0)\n"
         "def iv_curve_like(x):\n"
         "    return helper(x)\n"
         "def helper(x):\n"
         "    return kern(x)\n", namespace)
    listener = _cache._install_listener()
    try:
        assert namespace["iv_curve_like"](1.0) == 2.0
        err = capsys.readouterr().err
        assert "mbm: the first call of iv_curve_like compiles mbm's numba kernels (after installing" in err
        assert "typically 5-20 s on 2 cores" in err  # no measured row for it
        assert "not cached: each process compiles" in err
        assert listener.done
    finally:
        from numba.core import event

        event.unregister("numba:compile", listener)


def test_compile_notice_quotes_the_measured_first_call(tmp_path):
    """An entry point with a row in first_calls.json: its own measured seconds, in the user's words."""
    text = _cache.notice_text("iv_curve", "mbm.x.k", "/cache", measured={"iv_curve": 17.6})
    assert text == ("mbm: the first call of iv_curve compiles mbm's numba kernels (after installing or "
                    "upgrading mbm; about 18 s on 2 cores, measured; once: later calls load them from /cache)\n")
    text = _cache.notice_text("MBM.__init__", "mbm.x.k", None, measured={"MBM.__init__": 5.0})
    assert text.startswith("mbm: the first call of solve_ivp(method=mbm.MBM) compiles") and "about 5 s" in text
    assert "not cached: each process compiles" in text
    bad = tmp_path / "first_calls.json"
    bad.write_text("{not json")
    assert _cache.first_call_seconds(str(bad)) == {}
    assert _cache.first_call_seconds(str(tmp_path / "missing.json")) == {}


def test_first_calls_file_covers_the_public_entry_points():
    """The generated table (python -m benchmarks.first_calls) has a row for each entry that compiles."""
    measured = _cache.first_call_seconds()
    for entry in ("MBM.__init__", "solve", "solve_batch", "iv_curve", "shapiro_steps", "sweep",
                  "escape_times", "switching_currents", "switching_grid", "retrapping_currents"):
        assert entry in measured and 0.0 < measured[entry] < 600.0, entry
