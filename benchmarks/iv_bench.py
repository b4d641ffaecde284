"""The junction I–V benchmark: ``mbm.iv_curve`` against the same protocol on DOP853.

A 301-point up-and-down sweep at β = 0.2 (0 → 1.5 → 0, 151 points each way, the
bias currents bisected to 1e-4).  The peer is what a user writes with scipy: the same
protocol (state carried from point to point, settle, then ⟨θ'⟩ = 2π/T_c from three
passages through θ ≡ arcsin γ located on the dense output, the currents bisected the
same way) with ``solve_ivp(method="DOP853", dense_output=True)`` at rtol = atol = 1e-11
in place of MBM.  Both curves' ⟨θ'⟩ are checked against heyoka in 80-bit long double
(tol 1e-19) at every running point, from the same start states; times are the whole
sweep (one run each: a sweep is seconds to minutes).

Usage, from the root of a checkout::

    python -m benchmarks.iv_bench [--points 151] [--out docs/iv_benchmark.md]
"""

import argparse
import math
import platform
import time
from pathlib import Path

import numpy as np

import mbm
from mbm.junction import iv as junction

__all__ = ["run", "render", "main"]

BETA = 0.2
GAMMA_MAX = 1.5
DOP_TOL = 1e-11


def _dop_run(model, y, span):
    from scipy.integrate import solve_ivp

    sol = solve_ivp(model, (0.0, span), y, method="DOP853", rtol=DOP_TOL, atol=DOP_TOL, dense_output=True)
    if not sol.success:
        raise RuntimeError(sol.message)
    return sol


def _dop853_curve(beta, gamma, current_tol):
    return junction.iv_curve(beta, gamma, current_tol=current_tol, integrate=_dop_run)


def _heyoka_reference(beta, curve):
    import heyoka as hy

    L = np.longdouble
    x, v = hy.make_vars("x", "v")
    sys_ = [(x, v), (v, hy.par[1] - hy.par[0] * v - hy.par[2] * hy.sin(x))]
    plain = hy.taylor_adaptive(sys_, np.zeros(2, dtype=L), pars=np.zeros(3, dtype=L), tol=L(1e-19), fp_type=L)
    events = hy.taylor_adaptive(sys_, np.zeros(2, dtype=L), pars=np.zeros(4, dtype=L), tol=L(1e-19), fp_type=L,
                                t_events=[hy.t_event(x - hy.par[3], fp_type=L)])
    ref = np.full(curve.gamma.size, np.nan)
    for i, (g, y0, regime) in enumerate(zip(curve.gamma, curve.start_state, curve.regime)):
        if regime != junction.RUNNING:
            continue
        plain.pars[:] = [beta, g, 1.0]
        plain.state[:] = y0
        plain.time = L(0)
        plain.propagate_until(L(60.0 / beta))
        d = math.asin(g) if abs(g) <= 1.0 else math.copysign(math.pi / 2, g)
        k = math.floor((float(plain.state[0]) - d) / (2 * math.pi)) + 1
        events.pars[:] = [beta, g, 1.0, 0.0]
        events.state[:] = plain.state
        events.time = L(0)
        times = []
        for j in range(3):
            events.pars[3] = L(d) + 2 * L(math.pi) * (k + j)
            events.propagate_until(L(1e5))
            times.append(events.time)
        ref[i] = float(L(4) * L(math.pi) / (times[2] - times[0]))
    return ref


def run(points=151, beta=BETA, current_tol=1e-4):
    """Both sweeps, timed, and their ⟨θ'⟩ errors against heyoka long double.

    Returns
    -------
    dict
    """
    up = np.linspace(0.0, GAMMA_MAX, points)
    gamma = np.r_[up, up[::-1]]
    junction.iv_curve(beta, gamma[:3])  # compile MBM's kernels outside the timing
    t0 = time.perf_counter()
    mbm_curve = junction.iv_curve(beta, gamma, current_tol=current_tol)
    t_mbm = time.perf_counter() - t0
    t0 = time.perf_counter()
    dop_curve = _dop853_curve(beta, gamma, current_tol)
    t_dop = time.perf_counter() - t0
    out = {"points": int(gamma.size), "beta": beta, "current_tol": current_tol,
           "mbm_seconds": t_mbm, "dop853_seconds": t_dop, "speedup": t_dop / t_mbm}
    for name, c in (("mbm", mbm_curve), ("dop853", dop_curve)):
        ref = _heyoka_reference(beta, c)
        err = np.abs(c.mean_velocity - ref)
        out[f"{name}_max_error"] = float(np.nanmax(err)) if np.isfinite(ref).any() else float("nan")
        out[f"{name}_switching"] = c.switching_current
        out[f"{name}_retrapping"] = c.retrapping_current
        out[f"{name}_regimes_equal"] = bool(np.array_equal(c.regime, mbm_curve.regime))
    return out


def render(r):
    """Markdown of :func:`run`'s result."""
    return "\n".join([
        "# Junction I–V benchmark",
        "",
        f"`python -m benchmarks.iv_bench --points {r['points'] // 2}` — {platform.processor() or platform.machine()}, "
        f"{platform.python_version()}, mbm {mbm.__version__}.",
        "",
        f"{r['points']}-point up-and-down sweep at β = {r['beta']}, currents bisected to {r['current_tol']}; "
        "the same protocol on each integrator (one run each, MBM's compile excluded); "
        "⟨θ'⟩ error = max over running points against heyoka long double from the same start states.",
        "",
        "| integrator | time (s) | max ⟨θ'⟩ error | switching | retrapping |",
        "|---|---:|---:|---:|---:|",
        f"| mbm (iv_curve) | {r['mbm_seconds']:.2f} | {r['mbm_max_error']:.1e} | {r['mbm_switching']:.5f} | "
        f"{r['mbm_retrapping']:.5f} |",
        f"| scipy DOP853, rtol = atol = {DOP_TOL:g} | {r['dop853_seconds']:.2f} | {r['dop853_max_error']:.1e} | "
        f"{r['dop853_switching']:.5f} | {r['dop853_retrapping']:.5f} |",
        "",
        f"MBM is {r['speedup']:.1f}× faster at {'equal' if r['dop853_regimes_equal'] else 'different'} regimes.",
        "",
    ])


def main(argv=None):
    """``python -m benchmarks.iv_bench``: run, print and optionally write the Markdown."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks.iv_bench", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--points", type=int, default=151, help="bias points each way (default 151)")
    ap.add_argument("--out", default=None, help="write the Markdown here")
    args = ap.parse_args(argv)
    text = render(run(points=args.points))
    print(text)
    if args.out:
        Path(args.out).write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
