"""Sweep throughput: a 2-worker Dask LocalCluster against in-process ``solve_batch``.

The scenes of a (β, γ) grid, θ₀ = θ'₀ = 0, 0 ≤ t ≤ 1000, ``reduce="mean_velocity"``
(the issue's 10⁶-scene target, scaled down to what this 2-core machine does in
minutes), run four ways on the same cores:

* ``solve_batch``: one in-process :func:`mbm.solve_batch` over all N scenes with the
  two output times the reduction needs (the baseline; numba's threads on every core);
* ``sweep``: :func:`mbm.sweep` unchunked (in-process, batches of
  ``LOCAL_BATCH`` scenes);
* ``sweep, dask threads``: chunked, on dask's threaded scheduler in this process;
* ``sweep, LocalCluster``: chunked, on ``LocalCluster(n_workers=2,
  threads_per_worker=1, processes=True)``, numba limited to 1 thread a worker
  (``NUMBA_NUM_THREADS=1`` in the nanny's pre-spawn environment).

Throughput is scenes per second of wall time (one run each, warm: kernels loaded and
workers started before timing).  Memory is the peak resident set during the run above
the resident set just before it (sampled every 5 ms by a thread): of a fresh
subprocess for each in-process path, of each worker for the cluster.  (Not tracemalloc: it hooks the allocator that
numba's runtime uses too, and slowed the kernels 2.7x here.)

Usage, from the root of a checkout::

    python benchmarks/sweep_bench.py [--sizes 10000 100000] [--out docs/sweeps_bench.md]
"""

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

# The horizon of the target (t ≤ 1000).
T_END = 1000.0
# The grid: β from weakly damped to overdamped, γ across locking (γ < 1) and running.
BETA_RANGE = (0.05, 1.0)
GAMMA_RANGE = (0.0, 1.6)
# Chunks per cluster run: enough that 2 workers balance (costs vary ~100x between
# locked and running scenes) and few enough that per-task overhead (~1 ms) is nothing.
N_CHUNKS = 25
# Repeats (best wall time kept) for sizes up to EXTRA_PATHS_MAX: one run on a shared
# machine varies by ±30 %; the larger sizes run once (minutes each).
REPEATS = 3
# Paths run only up to this many scenes (the extra in-process ones; ~1 min each at 10⁵).
EXTRA_PATHS_MAX = 10_000
ROOT = Path(__file__).resolve().parents[1]


def grid_shape(n):
    """(n_beta, n_gamma) with n_beta · n_gamma = n, n_beta the largest divisor ≤ √n."""
    k = int(math.isqrt(n))
    while n % k:
        k -= 1
    return k, n // k


def grid(n):
    """The β and γ coordinates of an n-scene grid."""
    nb, ng = grid_shape(n)
    return np.linspace(*BETA_RANGE, nb), np.linspace(*GAMMA_RANGE, ng)


# How often the memory sampler reads the resident set (s): the large arrays of a run
# live from its start to its end, so a coarse interval still sees the peak.
SAMPLE_S = 0.005


class RssSampler:
    """Peak resident set of this process over a block, sampled by a thread."""

    def __init__(self):
        import psutil

        self._proc = psutil.Process()
        self.base = self.peak = self._proc.memory_info().rss
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self):
        while not self._stop.wait(SAMPLE_S):
            self.peak = max(self.peak, self._proc.memory_info().rss)

    def stop(self):
        """Stop sampling; the peak growth above the start, in bytes."""
        self._stop.set()
        self._thread.join()
        self.peak = max(self.peak, self._proc.memory_info().rss)
        return self.peak - self.base


def _start_sampler(dask_worker):
    # On a worker (client.run passes the Worker): sample its RSS until _stop_sampler.
    dask_worker.mbm_rss_sampler = RssSampler()


def _stop_sampler(dask_worker):
    return dask_worker.mbm_rss_sampler.stop()


def _solve_batch(beta, gamma):
    import mbm

    b, g = np.meshgrid(beta, gamma, indexing="ij")
    res = mbm.solve_batch(b.ravel(), g.ravel(), 1.0, [0.0, 0.0], (0.0, T_END), [T_END / 2, T_END])
    # sweep's reduce="mean_velocity": exact where the run reached a regime (2π/T_c on
    # the running cycle, 0 once locked), else the two samples' estimate.
    estimate = (res.y[:, 0, 1] - res.y[:, 0, 0]) / (T_END / 2)
    v = np.where(np.isfinite(res.mean_velocity) & res.success, res.mean_velocity, estimate)
    return v.reshape(b.shape)


def _sweep(beta, gamma, chunks=None):
    import dask

    from mbm.junction.sweeps import sweep

    ds = sweep(beta=beta, gamma=gamma, t_span=(0.0, T_END), reduce="mean_velocity", chunks=chunks)
    if chunks is not None:
        with dask.config.set(scheduler="threads"):
            ds = ds.compute()
    return ds.mean_velocity.values


def one(path, n, out):
    """Run one in-process path on an n-scene grid (in a fresh process); save v to ``out``.

    Returns
    -------
    dict
        ``wall`` (s) and ``rss_growth`` (bytes: peak RSS above the RSS before the run).
    """
    from mbm.junction.sweeps import sweep

    sweep(beta=[0.1, 0.2], gamma=[0.3, 1.2], t_span=(0.0, 10.0), reduce="mean_velocity")  # kernels
    beta, gamma = grid(n)
    sampler = RssSampler()
    t = time.perf_counter()
    if path == "solve_batch":
        v = _solve_batch(beta, gamma)
    elif path == "sweep":
        v = _sweep(beta, gamma)
    else:
        v = _sweep(beta, gamma, chunks={"beta": chunk_beta(beta.size)})
    wall = time.perf_counter() - t
    growth = sampler.stop()
    np.save(out, v)
    return {"wall": wall, "rss_growth": growth}


def chunk_beta(n_beta):
    """The β chunk length giving :data:`N_CHUNKS` chunks (each all of γ)."""
    return max(1, math.ceil(n_beta / N_CHUNKS))


def run_subprocess(path, n, tmp):
    """:func:`one` in a fresh interpreter: its own RSS, no earlier run's memory."""
    out = Path(tmp) / f"{path}-{n}.npy"
    cmd = [sys.executable, __file__, "--one", path, str(n), str(out)]
    proc = subprocess.run(cmd, check=True, capture_output=True, text=True)
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    return res["wall"], res["rss_growth"], np.load(out)


def run_cluster(client, beta, gamma, chunks):
    from mbm.junction.sweeps import sweep

    client.run(_start_sampler)
    t = time.perf_counter()
    ds = sweep(beta=beta, gamma=gamma, t_span=(0.0, T_END), reduce="mean_velocity", chunks=chunks).compute()
    wall = time.perf_counter() - t
    growth = client.run(_stop_sampler)
    return wall, growth, ds.mean_velocity.values


def _git_state():
    """The commit measured, and whether mbm/ differed from it (uncommitted edits)."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True,
                              text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "mbm"], cwd=ROOT, capture_output=True,
                               text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "commit unknown"
    return f"commit {head}" + (" with uncommitted changes in mbm/" if dirty else "")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000])
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "sweeps_bench.md")
    parser.add_argument("--one", nargs=3, metavar=("PATH", "N", "OUT"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.one:
        print(json.dumps(one(args.one[0], int(args.one[1]), args.one[2])))
        return

    import dask
    import distributed
    import numba

    import mbm
    from mbm.junction.sweeps import LOCAL_BATCH, sweep

    load_before = os.getloadavg()
    sweep(beta=[0.1, 0.2], gamma=[0.3, 1.2], t_span=(0.0, 10.0), reduce="mean_velocity")  # kernels
    rows = []
    results = {}
    tmp = tempfile.mkdtemp(prefix="sweep-bench-")
    with dask.config.set({"distributed.nanny.pre-spawn-environ.NUMBA_NUM_THREADS": 1}):
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                           dashboard_address=None, silence_logs=50)
    client = distributed.Client(cluster)
    try:
        # Warm the workers: import mbm, load the cached kernels.
        sweep(beta=[0.1, 0.2], gamma=[0.3, 1.2], t_span=(0.0, 10.0), reduce="mean_velocity", chunks=1).compute()
        # Interleaved per size (the machine is shared: compared runs should see the same load).
        for n in args.sizes:
            repeats = REPEATS if n <= EXTRA_PATHS_MAX else 1
            beta, gamma = grid(n)
            cb = chunk_beta(beta.size)
            best = {}  # path -> [least wall time, greatest memory (per worker: a list)]

            def keep(path, wall, mem):
                old = best.setdefault(path, [math.inf, None])
                old[0] = min(old[0], wall)
                old[1] = mem if old[1] is None else np.maximum(old[1], mem)

            for _ in range(repeats):
                wall, mem, ref = run_subprocess("solve_batch", n, tmp)
                keep("solve_batch", wall, mem)
                wall, growth, v = run_cluster(client, beta, gamma, {"beta": cb})
                assert v.tobytes() == ref.tobytes()
                keep("cluster", wall, np.array(sorted(growth.values())))
                if n <= EXTRA_PATHS_MAX:
                    for path in ("sweep", "threads"):
                        w, m, v = run_subprocess(path, n, tmp)
                        assert v.tobytes() == ref.tobytes()
                        keep(path, w, m)
            label = f"best of {repeats}" if repeats > 1 else "one run"
            mb = lambda x: f"{x / 1e6:.1f} MB"  # noqa: E731
            rows.append((n, f"solve_batch, in-process, 2 numba threads ({label})", best["solve_batch"][0],
                         mb(best["solve_batch"][1])))
            if "sweep" in best:
                rows.append((n, f"sweep, unchunked, batches of {LOCAL_BATCH} ({label})", best["sweep"][0],
                             mb(best["sweep"][1])))
                rows.append((n, f"sweep, chunks beta={cb}, dask threads in-process ({label})",
                             best["threads"][0], mb(best["threads"][1])))
            rows.append((n, f"sweep, chunks beta={cb} ({cb * gamma.size} scenes), LocalCluster 2 workers x 1 "
                         f"thread ({label})", best["cluster"][0],
                         " / ".join(mb(g) for g in best["cluster"][1]) + " per worker"))
            results[(n, "solve_batch")] = best["solve_batch"][0]
            results[(n, "cluster")] = best["cluster"][0]
    finally:
        client.close()
        cluster.close()
    load_after = os.getloadavg()

    lines = [
        "# Sweep benchmark: LocalCluster against in-process solve_batch",
        "",
        "Generated by `python benchmarks/sweep_bench.py` (the machine is shared with other",
        "work, see the load average: expect ±30 % noise).  Scenes: a (β, γ) grid, β ∈ [0.05, 1],",
        "γ ∈ [0, 1.6], θ₀ = θ'₀ = 0,",
        f"0 ≤ t ≤ {T_END:g}, `reduce=\"mean_velocity\"` (outputs at T/2 and T only).  Every path",
        "gave the same mean velocities bit for bit (asserted).",
        "",
        f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} logical cores, "
        f"Python {platform.python_version()}, numpy {np.__version__}, numba {numba.__version__}, "
        f"dask {dask.__version__}, distributed {distributed.__version__}, mbm {mbm.__version__}; "
        f"load average before {load_before[0]:.2f}, after {load_after[0]:.2f}; "
        f"run {time.strftime('%Y-%m-%dT%H:%M:%S')}; {_git_state()}.",
        "",
        "| scenes | path | wall s | scenes/s | peak RSS growth |",
        "|---:|---|---:|---:|---|",
    ]
    for n, path, wall, mem in rows:
        lines.append(f"| {n} | {path} | {wall:.2f} | {n / wall:,.0f} | {mem} |")
    lines += ["", "Throughput of the 2-worker LocalCluster relative to in-process `solve_batch`:", ""]
    for n in args.sizes:
        ratio = results[(n, "solve_batch")] / results[(n, "cluster")]
        lines.append(f"- {n} scenes: {ratio:.2f}x")
    lines += [
        "",
        "Wall time: the least of the repeats.  Memory: the peak resident set during the run",
        "above the one before it, the most over the repeats (a fresh process per in-process",
        "path; each worker for the cluster, which ran all sizes in the same workers).",
        "",
    ]
    args.out.write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
