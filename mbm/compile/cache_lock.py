"""numba's on-disk cache written under a file lock, so that two processes cannot cross it.

numba keeps the compiled signatures of a function in one index file (``*.nbi``) that
maps each signature (with the closure's variables) to a numbered data file (``*.nbc``).
Saving a new signature reads the index, takes the first unused number, writes the index
and then the data, with no lock (``numba.core.caching.IndexDataCacheFile.save``).  Two
processes saving two new signatures of one function at the same time both take the
same number: the index of one and the data of the other survive, and the first
signature then loads the second one's machine code.  mbm compiles in two processes by
design (the compile helper, :mod:`mbm.compile.warm`, beside a first call; pytest-xdist's
workers), and its loop's entries are closures of one function per regime set: a run
entry for one set loaded another's code (measured: ``solve_njit`` on the running scene
P5 paused one window before its end, the batch returned NaN, until the cache was
cleared).

:func:`install` wraps ``save`` in an exclusive ``fcntl.flock`` on ``<index>.lock`` (the
read of the index, the choice of the number and both writes are then one step) and
``load`` in a shared one (an index and its data are read as one writer left them).
Where ``fcntl`` is missing (Windows) nothing is installed.  ``MBM_CACHE_LOCK=0`` turns
it off.

A second crossing needs no race: numba names a compiled function by its qualified name,
its argument types and a per-process counter (``FunctionIdentity._unique_ids``, the
``v<n>`` of the mangled symbol).  Two processes that compile two closures of one
function (the loop's entries per regime set) in the same order give both the same name;
a kernel cached by each carries its own closure's body under that name, and a third
process that loads both kernels links both calls to one body (numba issue #10486;
measured: ``solve_batch``'s driven scene paused at t0 with NaN outputs after a test
run on two workers, until the cache was cleared).  :func:`install` therefore draws the
ids at random (:data:`ID_BITS` bits), so that no two processes share one.
"""

import contextlib
import functools
import os
import secrets

__all__ = ["install", "LOCK_ENV", "LOCK_SUFFIX", "ID_BITS"]

# Environment variable that leaves numba's cache as it is when set to 0 / false / no / off.
LOCK_ENV = "MBM_CACHE_LOCK"
# The lock file beside each index (numba reads and deletes only *.nbi and *.nbc files).
LOCK_SUFFIX = ".lock"
_FALSE = ("0", "false", "no", "off")
# Bits of a function's random id: two of the ~10⁴ functions of all processes that ever
# share a cache meet with a chance of ~10⁸/2⁶⁴ (birthday bound), nil in practice.
ID_BITS = 64


class _RandomIds:
    """An endless iterator of random positive ids, in place of numba's counter."""

    def __iter__(self):
        return self

    def __next__(self):
        return secrets.randbits(ID_BITS) | 1  # odd: never 0


@contextlib.contextmanager
def _locked(fcntl, index_path, mode):
    """Hold ``mode`` (``fcntl.LOCK_EX`` or ``LOCK_SH``) on ``index_path`` + LOCK_SUFFIX;
    no lock where the folder cannot take the file (numba's own write fails there too)."""
    try:
        fd = os.open(index_path + LOCK_SUFFIX, os.O_RDWR | os.O_CREAT, 0o666)
    except OSError:
        yield
        return
    try:
        fcntl.flock(fd, mode)
        yield
    finally:
        os.close(fd)  # closing releases the lock


def _wrap(method, fcntl, mode):
    @functools.wraps(method)
    def locked(self, *args, **kwargs):
        with _locked(fcntl, self._index_path, mode):
            return method(self, *args, **kwargs)

    locked.__mbm_cache_lock__ = True
    return locked


def install():
    """Take numba's cache index under a file lock and draw numba's function ids at
    random (module docstring); idempotent.

    Returns
    -------
    bool
        Whether the lock is installed (False: ``MBM_CACHE_LOCK=0``, no ``fcntl``, or a
        numba without ``IndexDataCacheFile.save``/``load``).
    """
    if os.environ.get(LOCK_ENV, "").strip().lower() in _FALSE:
        return False
    _random_ids()
    try:
        import fcntl
        from numba.core.caching import IndexDataCacheFile
    except ImportError:
        return False
    cls = IndexDataCacheFile
    if not (callable(getattr(cls, "save", None)) and callable(getattr(cls, "load", None))):
        return False
    if getattr(cls.save, "__mbm_cache_lock__", False):
        return True
    cls.save = _wrap(cls.save, fcntl, fcntl.LOCK_EX)
    cls.load = _wrap(cls.load, fcntl, fcntl.LOCK_SH)
    return True


def _random_ids():
    # numba's function ids drawn at random (module docstring); a numba without the
    # counter is left as it is.
    from numba.core.bytecode import FunctionIdentity

    if hasattr(FunctionIdentity, "_unique_ids") and not isinstance(FunctionIdentity._unique_ids, _RandomIds):
        FunctionIdentity._unique_ids = _RandomIds()
