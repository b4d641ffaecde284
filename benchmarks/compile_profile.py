"""Where a first call's compile time goes: each kernel's own compile time (its callees'
apart), from numba's ``numba:compile`` events, in a fresh process with an empty cache.

    python -m benchmarks.compile_profile [--top 25] [--setup CODE] CODE

CODE runs after ``import math, numpy as np, mbm`` (and ``--setup``, timed apart);
the table lists the kernels CODE compiled, longest first, with the wall time of CODE.
The compile helper (:mod:`mbm.compile.warm`) is off, so that every kernel is compiled here.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

_CHILD = r'''
import json, sys, time
from numba.core import event

own = {}
stack = []


class Listener(event.Listener):
    def on_start(self, ev):
        stack.append([time.perf_counter(), 0.0])

    def on_end(self, ev):
        t0, inner = stack.pop()
        total = time.perf_counter() - t0
        if stack:
            stack[-1][1] += total
        d = (ev.data or {}).get("dispatcher")
        f = getattr(d, "py_func", None)
        name = "%s.%s" % (getattr(f, "__module__", "?"), getattr(f, "__qualname__", "?"))
        n, s = own.get(name, (0, 0.0))
        own[name] = (n + 1, s + total - inner)


import math, numpy as np, mbm
exec(sys.argv[1])
event.register("numba:compile", Listener())
_t0 = time.perf_counter()
exec(sys.argv[2])
print(json.dumps({"wall": time.perf_counter() - _t0, "own": own}))
'''


def profile(code, setup=""):
    """``(wall seconds, {kernel: (compiles, own seconds)})`` of ``code`` run after
    ``setup`` in a fresh interpreter with an empty numba cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, MBM_COMPILE_NOTICE="0", MBM_COMPILE_HELPER="0")
        proc = subprocess.run([sys.executable, "-c", _CHILD, setup, code], env=env, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"the profiled code failed:\n{proc.stderr}")
    data = json.loads(proc.stdout.strip().splitlines()[-1])
    return data["wall"], {k: tuple(v) for k, v in data["own"].items()}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("code")
    ap.add_argument("--setup", default="")
    ap.add_argument("--top", type=int, default=25)
    args = ap.parse_args(argv)
    wall, own = profile(args.code, args.setup)
    rows = sorted(own.items(), key=lambda kv: -kv[1][1])
    print(f"{wall:.2f} s wall, {sum(v[0] for v in own.values())} compiles, "
          f"{sum(v[1] for v in own.values()):.2f} s in them")
    for name, (n, s) in rows[: args.top]:
        print(f"{s:7.3f} s  {n:3d}  {name}")


if __name__ == "__main__":
    main()
