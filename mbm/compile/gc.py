"""Python's cyclic garbage collector relaxed while numba compiles one of mbm's kernels.

A first call's compile allocates about a million container objects (numba's IR, its
types, the copies of inlined bodies), most of them in reference cycles that only the
collector frees.  At Python's
default gen-0 threshold (700 allocations) the collector runs thousands of times while it
compiles, each run walking the young objects, and that cost about a tenth of a first
call (``solve_ivp`` then salas-torque from an empty cache on one core: 8.6 + 6.9 s with
the default, 7.9 + 6.0 s with the threshold below; docs/compile_gc.md, written by
``python -m benchmarks.compile_gc``).  While the outermost compile of an mbm
kernel runs, :func:`install`'s listener raises the gen-0 threshold to
:data:`COMPILE_GEN0_THRESHOLD` and restores the thresholds it found when that compile
ends, by an exception too.  Nothing else changes: the garbage is collected as before,
by fewer runs (the peak memory of those first calls rose from 290 to 316 MB), and a
warm cache compiles nothing.  A user's own threshold, where higher, is kept;
``MBM_COMPILE_GC=0`` leaves the collector alone.
"""

import gc
import os

__all__ = ["COMPILE_GEN0_THRESHOLD", "GC_ENV", "install"]

# Gen-0 threshold while an mbm kernel compiles: about 70 times fewer collector runs than
# the default 700, for ~26 MB more peak memory (docs/compile_gc.md).
COMPILE_GEN0_THRESHOLD = 50_000
# Environment variable that leaves the collector's thresholds alone when set to 0 / false / no / off.
GC_ENV = "MBM_COMPILE_GC"


def _is_mbm(ev):
    py_func = getattr((ev.data or {}).get("dispatcher"), "py_func", None)
    module = getattr(py_func, "__module__", None) or ""
    return module == "mbm" or module.startswith("mbm.")


def _listener_class():
    from numba.core import event

    class _RelaxedCollector(event.Listener):
        """Raises the gen-0 threshold for the outermost compile of an mbm kernel and
        everything numba compiles inside it (numba's compiles nest, one thread at a
        time under its compiler lock); restores it when that compile ends."""

        def __init__(self):
            self.depth = 0  # compiles open inside the outermost mbm one (0: none)
            self.saved = None

        def on_start(self, ev):
            if self.depth == 0:
                if not _is_mbm(ev):
                    return
                self.saved = gc.get_threshold()
                gc.set_threshold(max(self.saved[0], COMPILE_GEN0_THRESHOLD), *self.saved[1:])
            self.depth += 1

        def on_end(self, ev):
            if self.depth == 0:
                return
            self.depth -= 1
            if self.depth == 0:
                gc.set_threshold(*self.saved)

    return _RelaxedCollector


_installed = []  # the listener install() registered, once per process


def install():
    """Register the listener on numba's ``"numba:compile"`` event, once per process (at
    ``import mbm``).

    Returns
    -------
    numba.core.event.Listener or None
        The registered listener, or None where ``MBM_COMPILE_GC`` turns it off or numba
        has no event API.
    """
    if _installed:
        return _installed[0]
    if os.environ.get(GC_ENV, "").strip().lower() in ("0", "false", "no", "off"):
        return None
    try:
        from numba.core import event

        listener = _listener_class()()
        event.register("numba:compile", listener)
    except (ImportError, AttributeError):
        return None
    _installed.append(listener)
    return listener
