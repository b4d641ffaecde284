"""numba compilation of the package's kernels: its options (once), and :func:`kernel`.

``@numba.njit(**NJIT_OPTIONS)`` decorates a kernel of :mod:`mbm.special` and of the
paper and splitting modules of :mod:`mbm.approximants` that Python calls;
:func:`kernel` (``@kernel``, or ``@kernel(error_model="numpy")`` with NJIT_OPTIONS'
error model) one that only compiled code calls.

numba compiles, beside every ``@njit`` function, a CPython wrapper (to call it from
Python) and a cfunc wrapper (to take it as a first-class function); both are lowered,
optimised and cached with it, about 25 ms of a first call's compile per kernel on two
cores (the wrapper of a kernel that takes a run record boxes the whole record type:
several times that).  A kernel that only other kernels call needs neither, and
:func:`kernel` compiles it as ``@njit(cache=True)`` without them.

Such a kernel called from Python (a test, an interactive check) still works: the call
compiles, once per process and not cached, a twin with the wrapper from the same Python
function, whose own callees are the same cached kernels.  A library path that calls a
kernel from Python on every run uses ``numba.njit`` instead, so that its wrapper is
cached: :data:`TWINS` records each twin made and who called it (``tests/compile/test_jit.py``
checks that the library's own paths make none).
"""

import sys

import numba
from numba.core.registry import CPUDispatcher

__all__ = ["INLINE", "NJIT_OPTIONS", "TWINS", "kernel"]

# cache: compiled kernels persist in __pycache__, so only the first run compiles.
# error_model="numpy": a float division by zero gives ±inf/nan instead of raising
# ZeroDivisionError inside a compiled loop; kernels report failure by status code or
# NaN, never by an exception (the cn form (2.17) needs R = 0 → Abar = inf, the special
# functions their poles; no kernel result changes for a non-zero divisor).
NJIT_OPTIONS = {"cache": True, "error_model": "numpy"}

# ``@numba.njit(**INLINE)``: a small per-window piece inlined into its caller.  Used only
# where a caller's constant kind or regime set must prune branches (numba prunes an
# inlined constant, not a called function's literal argument) or where a call measured
# slower; numba re-types an inlined body at every site (~0.1 s of a first call each),
# while LLVM inlines a plain call anyway (docs/contributing.md).
INLINE = {"cache": True, "inline": "always"}

# numba's options of a kernel: nopython, no CPython or cfunc wrapper (module docstring).
KERNEL_OPTIONS = {"nopython": True, "no_cpython_wrapper": True, "no_cfunc_wrapper": True}

#: Twins made for calls from Python: a kernel's qualified name -> its first caller's file.
TWINS = {}


class KernelDispatcher(CPUDispatcher):
    """A dispatcher compiled without CPython wrapper; a call from Python runs its twin."""

    _twin = None

    def __call__(self, *args, **kws):
        twin = self._twin
        if twin is None:
            caller = sys._getframe(1).f_code.co_filename
            TWINS.setdefault(f"{self.py_func.__module__}.{self.py_func.__qualname__}", caller)
            # Not cached: numba's cache keys a kernel on its signature, not on its
            # wrapper flags, so a cached twin and the kernel would share entries.
            opts = {k: v for k, v in self.targetoptions.items() if k not in KERNEL_OPTIONS}
            twin = self._twin = numba.njit(**opts)(self.py_func)
        return twin(*args, **kws)


def kernel(fn=None, *, error_model="python"):
    """``fn`` as a cached compiled kernel without CPython or cfunc wrapper.

    Parameters
    ----------
    fn : function, optional
        A function numba compiles in nopython mode (``@kernel``); without it, the
        decorator (``@kernel(error_model="numpy")``).
    error_model : {"python", "numpy"}, optional
        numba's error model (NJIT_OPTIONS' is "numpy").

    Returns
    -------
    KernelDispatcher or callable
        Called from compiled code as any ``@njit`` function; called from Python, it
        runs a twin compiled with the wrapper (module docstring).
    """
    def make(f):
        if numba.config.DISABLE_JIT:
            return f
        disp = KernelDispatcher(f, targetoptions=dict(KERNEL_OPTIONS, error_model=error_model))
        disp.enable_caching()
        return disp

    return make if fn is None else make(fn)
