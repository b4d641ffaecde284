"""A first call's kernels compiled by a helper process beside the call's own compile.

numba compiles one function at a time, depth first, holding the GIL: a first call of a
loop entry compiles its ~50 kernels one after the other on one core.  Where the cache
holds no compiled code for the entry a Python path is about to call,
:func:`prefetch` starts one helper process (:func:`main` with KEY) that compiles
the same kernels with the signatures recorded for that path in :data:`MANIFEST_FILE`,
into the same on-disk cache, in the mirror image of the call's order: the call compiles
its call tree leftmost callee first, the helper rightmost first (each kernel after its
callees in both).  When the call's own compile reaches a kernel the helper has finished,
numba loads it from the cache instead of compiling it; the two meet in the middle of
the tree.

A kind other than "taylor" shares the loop's entries and has its own compiled pieces
called through a table (:mod:`mbm.core.kind_ops`): its first call prefetches the key of
its kind (``("kind", "mbm.core.kind_ops", "KINDS", (kind,))``), the pieces it loads, before
its entry's, so that the helper compiles them while the call compiles the entry (or, the
entry cached, the two share the kind's pieces).

A caller that knows its next first calls (``python -m mbm demo``: solve_ivp with "auto",
then with "salas-torque") starts one helper for all of them with :func:`prefetch_keys`:
it compiles the second call's kernels while this process is still on the first.

The call compiles whatever it does not find, so its answers never depend on the helper
(a helper that fails, is late or is absent changes only the wall time).  It is started
only with a second core, the JIT on, a manifest written by this numba version, and not
from a helper; ``MBM_COMPILE_HELPER=0`` turns it off.  A helper stays up for
HELPER_LINGER seconds after its last key, and a later cold entry of the same process
sends its key to it rather than starting another; a helper still running when its
parent exits is stopped (numba writes each cache file whole, by rename).

The manifest is generated, never edited: ``python -m benchmarks.warm_manifest`` runs each
scene of :data:`SCENES` in a fresh process with an empty cache and records the kernels it
compiled, in order, with their signatures (numba types, pickled).
"""

import atexit
import os
import pickle
import subprocess
import sys

__all__ = ["DEMO_KEYS", "HELPER_ENV", "HELPER_LINGER", "MANIFEST_FILE", "SCENES", "prefetch", "prefetch_keys",
           "release", "entry_key", "load_manifest"]

# Environment variable that turns the helper off when set to 0 / false / no / off.
HELPER_ENV = "MBM_COMPILE_HELPER"
# Set in a helper's environment, so that a helper starts none of its own.
_IN_HELPER_ENV = "MBM_IN_COMPILE_HELPER"
# How long a helper waits for a further first call's keys after its last (a script's
# next kind, a notebook's next cell): that call then finds it up, and skips a helper's
# start (~1 s of a ~4 s first call: its interpreter and the imports of numba and mbm).
HELPER_LINGER = 60.0
# The generated manifest: {"numba": version, "paths": {key: [(module, name, item, signature)]}}.
MANIFEST_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "manifest.pkl")

# The first calls the manifest covers (Python statements after the imports of _SCENE_SETUP),
# keyed as prefetch looks them up: (path, where the entry is bound: module, name, items),
# or a kind's pieces: ("kind", "mbm.core.kind_ops", "KINDS", (kind id,)).  The second
# paper's Example 1 (benchmarks.first_calls), the fixed windows' entry (salas-torque's,
# the demo's, and the exact flow's, β = γ = 0), the pieces of salas-torque, split4 and
# the exact flow, a driven scene, a scene that reaches the running cycle (its stored
# period's entry), the lanes of a damped batch, and the tangent pass of error_estimate=True.
_LOOP = "mbm.core.loop"
_KINDS = "mbm.core.kind_ops"
# The demo's second call: its fixed windows' entry and its kind's pieces.
_SALAS_IVP = "solve_ivp(m, span, y0, method=mbm.MBM, approximant='salas-torque', tau=0.25, t_eval=t, dense_output=True)"
SCENES = {
    ("solve", _LOOP, "SIMD_RUNNERS", (1,)): "mbm.solve(m, span, y0, rtol=1e-9, atol=1e-9, t_eval=t)",
    ("ivp", _LOOP, "SIMD_RUNNERS", (1,)): "solve_ivp(m, span, y0, method=mbm.MBM, rtol=1e-9, atol=1e-9, t_eval=t, "
                                          "dense_output=True)",
    ("ivp", _LOOP, "SIMD_RUNNERS", (6,)): _SALAS_IVP,
    ("solve", _LOOP, "SIMD_RUNNERS", (6,)): "mbm.solve(mbm.Pendulum(0.0, 0.0), span, y0, t_eval=t)",
    ("kind", _KINDS, "KINDS", (2,)): _SALAS_IVP,
    ("kind", _KINDS, "KINDS", (3,)): "solve_ivp(m, span, y0, method=mbm.MBM, approximant='split4', rtol=1e-9, "
                                     "atol=1e-9, t_eval=t, dense_output=True)",
    ("kind", _KINDS, "KINDS", (1,)): "solve_ivp(mbm.Pendulum(0.0, 0.0), span, y0, method=mbm.MBM, t_eval=t, "
                                     "dense_output=True)",
    ("solve", _LOOP, "SIMD_RUNNERS", (3,)): "mbm.solve(mbm.Pendulum(0.1, 0.3, drive_amplitude=0.5, "
                                            "drive_frequency=0.8), span, y0, rtol=1e-9, atol=1e-9, t_eval=t)",
    ("solve", _LOOP, "SIMD_RUNNERS", (4,)): "mbm.solve(running, long_span, [0.0, 0.0], rtol=1e-9, atol=1e-9, "
                                            "t_eval=t_long)",
    ("ivp", _LOOP, "SIMD_RUNNERS", (4,)): "solve_ivp(running, long_span, [0.0, 0.0], method=mbm.MBM, rtol=1e-9, "
                                          "atol=1e-9, t_eval=t_long, dense_output=True)",
    ("batch", "mbm.core.lanes", "_run_lanes", ()): "mbm.solve_batch(0.1, np.linspace(0.05, 1.5, 64), 1.0, y0, "
                                                   "span, t, rtol=1e-9, atol=1e-9)",
    ("tangent", "mbm.tangent.transport", "transport", ()): "mbm.solve(m, span, y0, rtol=1e-9, atol=1e-9, t_eval=t, "
                                                           "error_estimate=True)",
}
#: The demo's first calls (``python -m mbm demo``): solve_ivp with "auto", then with
#: "salas-torque" (its kind's pieces, then the fixed windows' entry).
DEMO_KEYS = (("ivp", _LOOP, "SIMD_RUNNERS", (1,)), ("kind", _KINDS, "KINDS", (2,)),
             ("ivp", _LOOP, "SIMD_RUNNERS", (6,)))
_SCENE_SETUP = """
import math
import numpy as np
from scipy.integrate import solve_ivp
import mbm
m = mbm.Pendulum(beta=0.1, gamma=0.3)
span, y0, t = (0.0, 80.0), [math.radians(30), 0.0], np.linspace(0.0, 80.0, 201)
running, long_span, t_long = mbm.Pendulum(beta=0.1, gamma=1.2), (0.0, 400.0), np.linspace(0.0, 400.0, 201)
"""

_started = {}  # key -> the helper's Popen, one per key and process
_checked = set()  # the entries and kind ids prefetch has looked at: each once per process (a set lookup)
_manifest = []  # the loaded manifest's paths, once (a list: loaded or not)


def _env_off(name):
    return os.environ.get(name, "").strip().lower() in ("0", "false", "no", "off")


def load_manifest():
    """The manifest's paths, ``{key: [(module, name, item, signature), ...]}``, or ``{}``
    where there is none or another numba version wrote it."""
    if not _manifest:
        paths = {}
        try:
            import numba

            with open(MANIFEST_FILE, "rb") as f:
                data = pickle.load(f)
            if data.get("numba") == numba.__version__:
                paths = data["paths"]
        except Exception:  # a missing, unreadable or foreign manifest: no helper
            paths = {}
        _manifest.append(paths)
    return _manifest[0]


def entry_key(entry):
    """``(module, name, items)`` where the package binds compiled function ``entry`` (a
    global, or an item of a global dict), or None."""
    return _locations().get(id(entry))


def _cold(entry):
    # Whether numba's cache holds no code of this entry: its index (a file shared by the
    # closures of one function) has no key of this closure's code and constants (numba's
    # Cache._index_key less the signature, which only the call's typing knows).
    try:
        cache = entry._cache
        mine = cache._index_key(None, entry.targetctx.codegen())[1:]
        return not any(key[1:] == mine for key in cache._cache_file._load_index())
    except Exception:  # another numba's cache layout, an unreadable index: treat as warm
        return False


def _uncompiled(entry):
    # Neither compiled in this process nor held by the cache.
    return not entry.signatures and _cold(entry)


def _cores():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:
        return os.cpu_count() or 1


def prefetch(path, entry, kind=None):
    """Start the helper for ``path`` ("solve", "ivp", "batch" or "tangent") about to call compiled
    entry ``entry`` from a cold cache, where the module docstring's conditions hold;
    with ``kind`` (a kind id other than "taylor"'s), for that kind's pieces first.

    Returns
    -------
    bool
        Whether a helper was started.
    """
    pairs = []
    if kind is not None and kind not in _checked:  # (a set lookup for every later call)
        _checked.add(kind)
        target = _key_target(kind_key(kind))
        if target is not None:
            pairs.append((kind_key(kind), target))
    if entry not in _checked:  # (the check of every later call: a dispatcher's signatures cost ~20 us)
        _checked.add(entry)
        where = entry_key(entry)
        if where is not None:
            pairs.append(((path,) + where, entry))
    return bool(pairs) and _start(pairs)


def kind_key(kind):
    """The manifest's key of kind id ``kind``'s pieces (:mod:`mbm.core.kind_ops`)."""
    return ("kind", _KINDS, "KINDS", (int(kind),))


def _key_target(key):
    # The dispatcher whose compiled state says whether ``key`` is cold: an entry, or a
    # kind's evaluation (None for a kind without one).
    if key[0] == "kind":
        from ..core import kind_ops

        return kind_ops.op_function(key[3][0], kind_ops.OP_EVAL)
    return _resolve(*key[1:])


def prefetch_keys(keys):
    """Start one helper for the manifest's ``keys`` (``(path, module, name, items)``, as
    :data:`SCENES`), in order: for a caller that knows which first calls it makes next
    (``python -m mbm demo``), so that the helper compiles a later call's kernels while
    this process is still busy with an earlier one's.  The keys whose entries are
    compiled or cached already are left out.

    Returns
    -------
    bool
        Whether a helper was started.
    """
    todo = []
    for key in keys:
        entry = _key_target(key)
        if entry is not None and entry not in _checked:
            _checked.add(entry)
            todo.append((key, entry))
    return _start(todo)


def _start(pairs):
    # One helper for the keys of ``pairs`` (key, entry) whose entries are cold (none
    # started for them yet), where the module docstring's conditions hold.
    if _env_off(HELPER_ENV) or os.environ.get(_IN_HELPER_ENV) or _cores() < 2:
        return False
    manifest = load_manifest()
    keys = [k for k, e in pairs if k in manifest and k not in _started and _uncompiled(e)]
    if not keys:
        return False
    import numba

    if numba.config.DISABLE_JIT:
        return False
    proc = _send(keys)
    if proc is None:
        root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
        env = dict(os.environ, **{_IN_HELPER_ENV: "1", "MBM_COMPILE_NOTICE": "0"})
        env["PYTHONPATH"] = os.pathsep.join([root] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
        try:
            proc = subprocess.Popen(
                [sys.executable, "-c", "import sys; from mbm.compile.warm import main; sys.exit(main(sys.argv[1:]))"]
                + [repr(key) for key in keys],
                env=env, stdin=subprocess.PIPE,
                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        except OSError:
            return False
    for key in keys:
        _started[key] = proc
    return True


def _send(keys):
    # ``keys`` sent to a helper of this process that is still up (HELPER_LINGER), one
    # line each; returns that helper, or None where none took them.
    for proc in set(_started.values()):
        if proc.poll() is None:
            try:
                proc.stdin.write("".join(repr(key) + "\n" for key in keys).encode())
                proc.stdin.flush()
                return proc
            except (OSError, ValueError):  # it has just ended: start another
                continue
    return None


def release():
    """Tell this process's helpers that no keys follow: each ends once its work is done
    (rather than HELPER_LINGER seconds later).  Returns them (``Popen`` objects)."""
    helpers = list(set(_started.values()))
    for proc in helpers:
        try:
            proc.stdin.close()
        except (OSError, ValueError, AttributeError):
            pass
    return helpers


@atexit.register
def _stop_helpers():
    for proc in set(_started.values()):
        if proc.poll() is None:
            proc.terminate()
            try:
                proc.wait(timeout=5)
            except subprocess.TimeoutExpired:  # pragma: no cover - a helper ignoring SIGTERM
                proc.kill()
        try:
            proc.stdin.close()  # (its pipe's file, else an unclosed-file warning at exit)
        except (OSError, ValueError, AttributeError):
            pass


def _resolve(module, name, item):
    import importlib

    obj = getattr(importlib.import_module(module), name)
    for part in item:
        obj = obj[part]
    return obj


def compile_path(entries):
    """Compile ``entries`` (a manifest's list) in order, each skipped where it fails;
    returns the count compiled."""
    done = 0
    for module, name, item, sig in entries:
        try:
            _resolve(module, name, item).compile(sig)
            done += 1
        except Exception:  # a stale entry: the parent compiles what it needs itself
            continue
    return done


_CAPTURE = r'''
import pickle, sys
from numba.core import event
ends = []
class Listener(event.Listener):
    def on_start(self, ev):
        pass
    def on_end(self, ev):
        d = (ev.data or {}).get("dispatcher")
        if d is not None and d not in ends:
            ends.append(d)
event.register("numba:compile", Listener())
exec(sys.argv[1])
exec(sys.argv[2])
from mbm.compile import warm as _warm
sys.stdout.buffer.write(pickle.dumps(_warm._recorded(ends, eval(sys.argv[3]))))
'''


def _locations():
    # Where each dispatcher of the package is bound: id -> (module, name, item path); of
    # several bindings (a facade re-exports, a global aliases a table's item), the first
    # in the module that defines it.
    found = {}

    def put(d, where):
        home = d.py_func.__module__
        if id(d) not in found or (found[id(d)][0] != home and where[0] == home):
            found[id(d)] = where

    for modname, mod in sorted(sys.modules.items(), key=lambda kv: kv[0]):
        if modname != "mbm" and not modname.startswith("mbm."):
            continue
        for name, value in list(vars(mod).items()):
            if hasattr(value, "overloads") and hasattr(value, "py_func"):
                put(value, (modname, name, ()))
            elif isinstance(value, dict):
                for k, v in value.items():
                    if hasattr(v, "overloads") and hasattr(v, "py_func"):
                        put(v, (modname, name, (k,)))
                    elif isinstance(v, tuple):
                        for q, x in enumerate(v):
                            if hasattr(x, "overloads") and hasattr(x, "py_func"):
                                put(x, (modname, name, (k, q)))
    return found


def _callees(d, by_library):
    # The package's kernels that dispatcher ``d``'s compiled code calls (its linked libraries).
    out = []
    for cres in d.overloads.values():
        for lib in getattr(cres.library, "_linking_libraries", ()):
            c = by_library.get(id(lib))
            if c is not None and c is not d and c not in out:
                out.append(c)
    return out


def _op_kinds():
    # id -> kind id of each kind's piece (mbm.core.kind_ops.OPS) this process imported.
    from ..core import kind_ops

    return {id(kind_ops.op_function(k, op)): k for k, op in kind_ops.OPS}


def _mirror(roots, by_library, pos, seen):
    # ``roots`` and their callees, each after its callees, rightmost callee first (the
    # mirror image of the call's order); ``seen`` the ids already placed.
    order = []

    def visit(d):
        seen.add(id(d))
        for c in sorted(_callees(d, by_library), key=lambda c: pos.get(id(c), -1), reverse=True):
            if id(c) not in seen:
                visit(c)
        order.append(d)

    for root in roots:
        if id(root) not in seen:
            visit(root)
    return order


def _recorded(ends, key):
    # The manifest's list for ``key``, in the helper's order.  The call compiles the
    # kernels depth first, each after its callees, leftmost callee first (``ends``: the
    # order their compiles ended); the helper takes the mirror image of that order,
    # rightmost callee first and still each after its callees (from the compiled call
    # graph), so that the two meet in the middle of the tree rather than racing down the
    # same branch.  An entry's key: the kernels the call compiled before its entry and
    # out of the entry's reach come next, the last first; then those it compiled after
    # the entry (the dense output's), in order, which the helper reaches while the call
    # lowers the entry.  The entry itself, numba's own implementations and the kinds'
    # pieces are left out.  A kind's key: that kind's pieces (called through the table,
    # each loaded at its first call), the last loaded first.
    found = _locations()
    by_library = {id(cres.library): d for d in ends for cres in d.overloads.values()}
    pos = {id(d): q for q, d in enumerate(ends)}
    kinds = _op_kinds()
    ops = [d for d in ends if id(d) in kinds]
    if key[0] == "kind":
        order = _mirror([d for d in ops if kinds[id(d)] == key[3][0]][::-1], by_library, pos, set())
    else:
        entry = _resolve(*key[1:])
        split = pos.get(id(entry), len(ends))
        seen = set()
        order = _mirror([entry] + [d for d in ends[:split][::-1] if id(d) not in kinds], by_library, pos, seen)
        order.remove(entry)
        pieces = {id(d) for d in _mirror(ops, by_library, pos, set(seen))}
        order += [d for d in ends[split + 1:] if id(d) not in seen and id(d) not in pieces]
    rows = []
    for d in order:
        where = found.get(id(d))
        if where is not None:
            rows.extend(where + (sig,) for sig in d.overloads)
    return rows


def regenerate(path=MANIFEST_FILE):
    """Write the manifest: each scene of :data:`SCENES` in a fresh process with an empty
    cache.  Returns ``{key: entries}``."""
    import tempfile

    import numba

    paths = {}
    for key, code in SCENES.items():
        with tempfile.TemporaryDirectory() as cache:
            env = dict(os.environ, NUMBA_CACHE_DIR=cache, MBM_COMPILE_NOTICE="0", **{HELPER_ENV: "0"})
            proc = subprocess.run([sys.executable, "-c", _CAPTURE, _SCENE_SETUP, code, repr(key)], env=env,
                                  capture_output=True, check=True)
        paths[key] = pickle.loads(proc.stdout)
    with open(path, "wb") as f:
        pickle.dump({"numba": numba.__version__, "paths": paths}, f)
    return paths


def main(argv):
    """A helper's body: ``main([repr(KEY), ...])`` compiles the manifest's paths KEY, in
    order, then those of the keys its parent sends on stdin (a line each), until stdin
    ends or none comes for HELPER_LINGER seconds."""
    import ast
    import importlib
    import queue
    import threading

    importlib.import_module("mbm")  # the package's import-time cache check first

    todo = queue.Queue()

    def read():
        try:
            for line in sys.stdin:
                todo.put(line.strip())
        finally:
            todo.put(None)

    threading.Thread(target=read, daemon=True).start()
    for text in argv:
        compile_path(load_manifest().get(ast.literal_eval(text), []))
    while True:
        try:
            text = todo.get(timeout=HELPER_LINGER)
        except queue.Empty:
            return 0
        if text is None:
            return 0
        if text:
            compile_path(load_manifest().get(ast.literal_eval(text), []))
