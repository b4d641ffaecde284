"""Two processes saving new signatures into one numba cache index at once: crossed keys.

    python -m benchmarks.cache_race [--trials 5] [--keys 60]

Each trial forks two processes that, released together, save ``keys`` distinct keys each
(data: the key's own bytes) into one ``numba.core.caching.IndexDataCacheFile`` in a fresh
folder; the parent then loads every key and counts those whose data is another key's.
Run without and with :mod:`mbm.compile.cache_lock` (numba's save and load under a file
lock): the first shows numba's unlocked read-modify-write of the index, the second that
the lock closes it.  Needs ``fcntl`` (POSIX) and the ``fork`` start method.
"""

import argparse
import multiprocessing
import tempfile

KEYS = 60
TRIALS = 5
_BASE = "kernel-1.py311"


def _save_keys(folder, tag, start, keys):
    from numba.core.caching import IndexDataCacheFile

    f = IndexDataCacheFile(folder, _BASE, ("stamp", 1))
    start.wait()
    for i in range(keys):
        f.save((tag, i), f"{tag}{i}".encode())


def crossed(folder, keys=KEYS):
    """Keys whose loaded data is not their own after two processes saved at once."""
    from numba.core.caching import IndexDataCacheFile

    ctx = multiprocessing.get_context("fork")
    start = ctx.Barrier(2)
    procs = [ctx.Process(target=_save_keys, args=(folder, tag, start, keys)) for tag in "ab"]
    for p in procs:
        p.start()
    for p in procs:
        p.join(60)
        if p.exitcode != 0:
            raise RuntimeError(f"a saving process failed (exit code {p.exitcode})")
    f = IndexDataCacheFile(folder, _BASE, ("stamp", 1))
    return [(tag, i) for tag in "ab" for i in range(keys) if f.load((tag, i)) != f"{tag}{i}".encode()]


def _unlocked():
    # numba's own save and load, whether or not `import mbm` wrapped them.
    from numba.core import caching

    cls = caching.IndexDataCacheFile
    return getattr(cls.save, "__wrapped__", cls.save), getattr(cls.load, "__wrapped__", cls.load)


def counts(trials=TRIALS, keys=KEYS):
    """``{"unlocked": [...], "locked": [...]}``: crossed keys per trial, of 2·keys."""
    from numba.core import caching

    from mbm.compile import cache_lock

    cls = caching.IndexDataCacheFile
    wrapped = cls.save, cls.load
    out = {}
    try:
        cls.save, cls.load = _unlocked()
        for name in ("unlocked", "locked"):
            if name == "locked" and not cache_lock.install():
                raise RuntimeError("mbm.compile.cache_lock could not be installed (no fcntl?)")
            out[name] = []
            for _ in range(trials):
                with tempfile.TemporaryDirectory() as folder:
                    out[name].append(len(crossed(folder, keys)))
    finally:
        cls.save, cls.load = wrapped
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m benchmarks.cache_race", description=__doc__.split("\n")[0])
    parser.add_argument("--trials", type=int, default=TRIALS)
    parser.add_argument("--keys", type=int, default=KEYS)
    args = parser.parse_args(argv)
    if args.trials < 1 or args.keys < 1:
        parser.error("--trials and --keys must be >= 1")
    for name, c in counts(args.trials, args.keys).items():
        print(f"{name:9s} crossed keys of {2 * args.keys} per trial: {c}")


if __name__ == "__main__":
    main()
