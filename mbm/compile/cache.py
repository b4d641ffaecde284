"""Keeping numba's on-disk cache of mbm's kernels in step with mbm's sources.

Two things run once, at ``import mbm``, before any compiled module is imported:

* :func:`check_sources` drops this package's cached kernels when any of its sources
  changed.  numba's cache (``cache=True``) keys a kernel on its own file only: a kernel
  whose callee in another module was edited loads stale machine code (or fails with
  ``NRT_adapt_ndarray_to_python ... descr is NULL``).  A digest of every ``mbm/**/*.py``
  is kept beside the cache files; when it differs, the ``*.nbi`` / ``*.nbc`` files of
  the package are deleted and recompiled on their next call.  ``MBM_KEEP_CACHE=1``
  skips the check.
* :func:`install_compile_notice` registers a listener on numba's ``"numba:compile"``
  event (broadcast only when a kernel is not found in the cache) that writes one line
  to stderr on the first compilation of an mbm kernel in the process, so that a first
  call that compiles for tens of seconds says why.  ``MBM_COMPILE_NOTICE=0`` silences
  it.

Neither ever raises: a read-only installation, an unwritable cache directory or a numba
without the event API leaves ``import mbm`` as it was.
"""

import hashlib
import json
import os
import sys

__all__ = ["cache_dirs", "check_sources", "install_compile_notice", "sources_digest"]

# Name of the digest file kept in each cache directory; numba ignores files that are not
# its own index/data, and one per directory lets each be repaired on its own.
HASH_FILE = "mbm-sources.sha256"
# numba's index and data files (caching.py: IndexDataCacheFile), the only ones removed.
NUMBA_SUFFIXES = (".nbi", ".nbc")
# Folders never hashed (besides hidden ones): bytecode and numba caches, no sources.
SKIP_DIRS = ("__pycache__",)
# Environment variable that skips the check (for a read-only or hand-managed cache).
KEEP_CACHE_ENV = "MBM_KEEP_CACHE"
# Environment variable that silences the compile notice when set to 0 / false / no / off.
NOTICE_ENV = "MBM_COMPILE_NOTICE"
# What the notice says a first call compiles for where its entry point has no measured
# row in FIRST_CALLS_FILE: the span of those rows (docs/first_calls.md).
NOTICE_COST = "typically 5-20 s on 2 cores"
# The measured first call of each entry point (seconds, fresh process, empty cache), written
# by ``python -m benchmarks.first_calls`` beside this module: the notice quotes its entry's.
FIRST_CALLS_FILE = "first_calls.json"
# The entry points as the notice names them, where the function's own name is not what a
# user typed (solve_ivp builds the MBM solver).
ENTRY_WORDS = {"MBM.__init__": "solve_ivp(method=mbm.MBM)", "MBM._step_impl": "solve_ivp(method=mbm.MBM)",
               "Integrator.__init__": "mbm.Integrator", "Integrator.solve": "Integrator.solve"}

# The package root (mbm/), one folder above this module's.
_PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
_FALSE = ("0", "false", "no", "off")


def _env_on(name, default):
    """Whether the environment variable ``name`` is set to a true value.

    Parameters
    ----------
    name : str
        The variable's name.
    default : bool
        The answer when the variable is unset or empty.

    Returns
    -------
    bool
    """
    value = os.environ.get(name, "").strip().lower()
    if not value:
        return default
    return value not in _FALSE


def _source_files(root):
    """The package's Python sources, as sorted ``(relative path, path)`` pairs.

    Parameters
    ----------
    root : str
        The package folder.

    Returns
    -------
    list of tuple of str
        Relative paths use ``/`` so that a digest does not depend on the platform.
    """
    found = []
    stack = [(root, "")]
    while stack:
        folder, rel = stack.pop()
        with os.scandir(folder) as entries:
            for entry in entries:
                name = entry.name
                if entry.is_dir(follow_symlinks=False):
                    if name not in SKIP_DIRS and not name.startswith("."):
                        stack.append((entry.path, rel + name + "/"))
                elif name.endswith(".py"):
                    found.append((rel + name, entry.path))
    found.sort()
    return found


def sources_digest(root=_PACKAGE_ROOT, files=None):
    """SHA-256 over the sorted relative paths and contents of ``root/**/*.py``.

    Contents are hashed every time rather than mtimes and sizes first: the whole
    package (~650 kB) hashes in about a millisecond, and a stat signature would miss
    an edit that keeps size and mtime (``cp -p``, ``tar``, ``rsync -t``, a same-size
    edit within the file system's timestamp resolution).

    Parameters
    ----------
    root : str, optional
        The package folder; this package's by default.
    files : list of tuple of str, optional
        ``_source_files(root)``, when the caller has it already.

    Returns
    -------
    str
        The hexadecimal digest.
    """
    digest = hashlib.sha256()
    for rel, path in _source_files(root) if files is None else files:
        with open(path, "rb") as f:
            data = f.read()
        # Length-prefixed so that no two different trees give the same byte stream.
        digest.update(b"%d:%s\0%d:" % (len(rel), rel.encode("utf-8"), len(data)))
        digest.update(data)
    return digest.hexdigest()


def _usable_dir(path):
    """Whether numba could cache into ``path`` (created if missing, as numba does).

    numba's locator (``_CacheLocator.ensure_cache_path``) creates the folder and writes
    a temporary file into it; ``os.access`` gives the same answer without the write.
    """
    try:
        os.makedirs(path, exist_ok=True)
    except OSError:
        return False
    return os.access(path, os.W_OK | os.X_OK)


def cache_dirs(source_dirs, cache_dir=None, user_cache_dir=None):
    """Where numba caches the kernels of each source folder, as its locators decide.

    Mirrors ``numba.core.caching._CacheImpl._locator_classes`` for a plain source file:
    ``UserProvidedCacheLocator`` (``$NUMBA_CACHE_DIR/<folder name>_<sha1 of the
    folder's absolute path>``) when ``NUMBA_CACHE_DIR`` is set and usable, else
    ``InTreeCacheLocator`` (``<folder>/__pycache__``) when writable, else
    ``UserWideCacheLocator`` (numba's per-user cache folder, same sub-path as the
    first).  A custom ``NUMBA_CACHE_LOCATOR_CLASSES`` is not followed.

    Parameters
    ----------
    source_dirs : iterable of str
        Folders holding the package's modules.
    cache_dir : str, optional
        numba's ``config.CACHE_DIR`` (``NUMBA_CACHE_DIR``); read from numba if None.
    user_cache_dir : str, optional
        numba's user-wide cache folder; read from numba if None and needed.

    Returns
    -------
    list of str
        One cache folder per source folder that has a usable one (created if missing).
    """
    if cache_dir is None:
        from numba.core import config

        cache_dir = config.CACHE_DIR
    found = []
    for folder in source_dirs:
        folder = os.path.abspath(folder)
        # caching._CacheLocator.get_suitable_cache_subpath
        subpath = "%s_%s" % (os.path.basename(folder), hashlib.sha1(folder.encode()).hexdigest())
        candidates = []
        if cache_dir:
            candidates.append(os.path.join(cache_dir, subpath))
        candidates.append(os.path.join(folder, "__pycache__"))
        for i, path in enumerate(candidates + [None]):
            if path is None:
                if user_cache_dir is None:
                    from numba.misc.appdirs import AppDirs

                    user_cache_dir = AppDirs(appname="numba", appauthor=False).user_cache_dir
                path = os.path.join(user_cache_dir, subpath)
            if _usable_dir(path):
                found.append(path)
                break
    return found


def _numba_files(folder):
    """The numba index and data files directly in ``folder``."""
    with os.scandir(folder) as entries:
        return [e.path for e in entries if e.name.endswith(NUMBA_SUFFIXES)]


def _refresh(folder, digest):
    """Empty ``folder`` of numba files unless its digest file holds ``digest``; record it.

    The digest is written only after every removal succeeded, so that a failed purge
    is retried at the next import.
    """
    hash_path = os.path.join(folder, HASH_FILE)
    try:
        with open(hash_path, encoding="ascii") as f:
            stored = f.read().strip()
    except (OSError, ValueError):
        stored = None
    if stored == digest:
        return
    for path in _numba_files(folder):
        try:
            os.remove(path)
        except FileNotFoundError:  # another process purged it first
            pass
    # Written beside and renamed so that a concurrent import never reads half a digest.
    tmp = "%s.%d.tmp" % (hash_path, os.getpid())
    try:
        with open(tmp, "w", encoding="ascii") as f:
            f.write(digest + "\n")
        os.replace(tmp, hash_path)
    except OSError:
        try:
            os.remove(tmp)
        except OSError:
            pass
        raise


def check_sources(root=_PACKAGE_ROOT):
    """Drop this package's numba cache files if any of its sources changed.

    Compares :func:`sources_digest` with the digest stored in each cache folder of
    :func:`cache_dirs`; where it differs, or is missing (an older cache, or a first
    run), removes that folder's ``*.nbi`` / ``*.nbc`` files and stores the new digest.
    Skipped when ``MBM_KEEP_CACHE`` is set to a true value.

    Parameters
    ----------
    root : str, optional
        The package folder; this package's by default.

    Returns
    -------
    bool
        True if every cache folder was checked, False if the check was skipped or an
        ``OSError`` (read-only installation, unwritable cache) stopped it somewhere:
        ``import mbm`` goes on either way, with that part of numba's cache as it is.
    """
    if _env_on(KEEP_CACHE_ENV, False):
        return False
    try:
        files = _source_files(root)
        digest = sources_digest(root, files)
        folders = cache_dirs(sorted({os.path.dirname(path) for _, path in files}))
    except OSError:
        return False
    complete = True
    for folder in folders:
        # Each folder on its own: one that cannot be written does not keep the others stale.
        try:
            _refresh(folder, digest)
        except OSError:
            complete = False
    return complete


def _entry_point():
    """The mbm function the caller called (the outermost mbm frame on the stack, the
    compile machinery's own and mbm.validate's wrappers apart), by its qualified name,
    e.g. ``"iv_curve"`` or ``"MBM.__init__"``; None where there is none."""
    frame, name = sys._getframe(1), None
    while frame is not None:
        module = frame.f_globals.get("__name__", "")
        code = frame.f_code.co_qualname
        if ((module == "mbm" or module.startswith("mbm.")) and not module.startswith(("mbm.compile", "mbm.validate"))
                and not code.startswith("<")):
            name = code
        frame = frame.f_back
    return name


def first_call_seconds(path=None):
    """The measured first call of each entry point, {qualified name: seconds}.

    Parameters
    ----------
    path : str, optional
        The JSON file (default :data:`FIRST_CALLS_FILE` beside this module).

    Returns
    -------
    dict
        Empty where the file is missing or unreadable (the notice then says
        :data:`NOTICE_COST`).
    """
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), FIRST_CALLS_FILE) if path is None else path
    try:
        with open(path, encoding="utf-8") as fh:
            entries = json.load(fh)["entries"]
        return {str(k): float(v) for k, v in entries.items()}
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return {}


def notice_text(entry, kernel, where, measured=None):
    """The compile notice's line (see :func:`install_compile_notice`).

    Parameters
    ----------
    entry : str or None
        The entry point called (:func:`_entry_point`), None from outside any.
    kernel : str
        The kernel being compiled, named where there is no entry point.
    where : str or None
        The cache folder, None where the kernel is not cached.
    measured : dict, optional
        {entry: seconds} (default :func:`first_call_seconds`).
    """
    measured = first_call_seconds() if measured is None else measured
    saved = ("once: later calls load them from %s" % where) if where else "not cached: each process compiles"
    if entry is None:
        return ("mbm: compiling numba kernels for %s (the first call after installing or upgrading mbm; "
                "%s, %s)\n" % (kernel, NOTICE_COST, saved))
    cost = ("about %.0f s on 2 cores, measured" % measured[entry]) if entry in measured else NOTICE_COST
    return ("mbm: the first call of %s compiles mbm's numba kernels (after installing or upgrading mbm; "
            "%s; %s)\n" % (ENTRY_WORDS.get(entry, entry), cost, saved))


def _install_listener():
    """Register the notice's listener on ``"numba:compile"``; returns it."""
    from numba.core import event

    class _CompileNotice(event.Listener):
        """Writes one line on the first compilation of an mbm kernel, then stays quiet."""

        done = False

        def on_start(self, ev):
            if self.done:
                return
            dispatcher = (ev.data or {}).get("dispatcher")
            py_func = getattr(dispatcher, "py_func", None)
            module = getattr(py_func, "__module__", None) or ""
            if module != "mbm" and not module.startswith("mbm."):
                return
            where = getattr(getattr(dispatcher, "_cache", None), "cache_path", None)
            if where is None and module == "mbm.events.functions":
                # The locator compiled for a user's event function (about 1 s, stated
                # in mbm.events.functions): not the first call's compile the notice is about.
                return
            # A flag, not unregister: numba's broadcast iterates the listener list, and
            # removing from it mid-iteration would skip the next listener's event.
            self.done = True
            text = notice_text(_entry_point(), "%s.%s" % (module, getattr(py_func, "__qualname__", "?")), where)
            try:
                sys.stderr.write(text)
                sys.stderr.flush()
            except (OSError, ValueError, AttributeError):  # closed or missing stderr
                pass

        def on_end(self, ev):
            pass

    listener = _CompileNotice()
    event.register("numba:compile", listener)
    return listener


def install_compile_notice():
    """Say on stderr, once per process, that an mbm kernel is being compiled.

    A first call from an empty cache compiles for tens of seconds; the line names the
    kernel and where its compiled code will be cached.  numba broadcasts
    ``"numba:compile"`` only for a signature that is neither loaded nor in the disk
    cache, so a warm cache prints nothing.  Silenced by ``MBM_COMPILE_NOTICE=0``.

    Returns
    -------
    numba.core.event.Listener or None
        The registered listener, or None if silenced or numba has no event API.
    """
    if not _env_on(NOTICE_ENV, True):
        return None
    try:
        return _install_listener()
    except (ImportError, AttributeError):
        return None
