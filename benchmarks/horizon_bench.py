"""Long horizons: the cost of T = 1e6 against T = 1e3 once a scene reaches its attractor.

For each scene: the median time of ``mbm.solve`` and of ``solve_ivp(method=mbm.MBM,
windows_per_step=None)`` with 201 outputs at rtol = atol = 1e-10, at T = 1e3 and 1e6,
the windows taken and where the run switched (``regime``, ``t_regime``); and the error
at T = 2e4, rtol = atol = 1e-12, max|θ − θ_ref| / max(1, |θ_ref|) over 201 outputs
against heyoka in 80-bit long double (tol 1e-19).

Usage, from the root of a checkout::

    python -m benchmarks.horizon_bench [--out docs/horizons.md] [--repeats 3]
"""

import argparse
import platform
import time
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import mbm

__all__ = ["SCENES", "run", "render", "main"]

# name -> (beta, gamma, omega, theta0, theta_dot0): the long-horizon issue's scenes.
SCENES = {
    "P4 (β 0.01, γ 0.3, θ₀ 1)": (0.01, 0.3, 1.0, 1.0, 0.0),
    "P1 (β 0.4, θ̇₀ 0.25)": (0.4, 0.0, 1.0, 0.0, 0.25),
    "torqued locked (β 0.3, γ 0.5, θ₀ 2)": (0.3, 0.5, 1.0, 2.0, 0.0),
    "damped untorqued (β 0.02, ω 2, θ₀ 3)": (0.02, 0.0, 2.0, 3.0, 0.0),
    "P5 running (β 0.1, γ 1.2)": (0.1, 1.2, 1.0, 0.0, 0.0),
    "bistable running (β 0.1, γ 0.5, θ̇₀ 3)": (0.1, 0.5, 1.0, 0.0, 3.0),
}
TOL = 1e-10
TOL_ACCURACY = 1e-12
T_ACCURACY = 2e4


def _median(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def _heyoka_ld(beta, gamma, omega, y0, t):
    import heyoka as hy

    L = np.longdouble
    x, v = hy.make_vars("x", "v")
    sys_ = [(x, v), (v, L(gamma) - L(beta) * v - L(omega) ** 2 * hy.sin(x))]
    ta = hy.taylor_adaptive(sys_, np.array(y0, dtype=L), tol=L(1e-19), fp_type=L)
    out = ta.propagate_grid(np.asarray(t, dtype=L))
    return np.asarray(out[-1][:, 0], dtype=float)


def run(repeats=3):
    """Measure every scene; returns a list of row dicts."""
    rows = []
    for name, (b, g, w, th, v) in SCENES.items():
        model = mbm.Pendulum(b, g, w)
        row = {"scene": name}
        for T in (1e3, 1e6):
            te = np.linspace(0.0, T, 201)
            r = mbm.solve(model, (0.0, T), [th, v], rtol=TOL, atol=TOL, t_eval=te)  # also compiles
            row[f"windows_{T:g}"] = r.n_windows
            row[f"regime_{T:g}"] = (r.regime, r.t_regime)
            row[f"solve_{T:g}"] = _median(
                lambda: mbm.solve(model, (0.0, T), [th, v], rtol=TOL, atol=TOL, t_eval=te), repeats)
            row[f"ivp_{T:g}"] = _median(
                lambda: solve_ivp(model, (0.0, T), [th, v], method=mbm.MBM, rtol=TOL, atol=TOL, t_eval=te,
                                  windows_per_step=None), repeats)
        te = np.linspace(0.0, T_ACCURACY, 201)
        r = mbm.solve(model, (0.0, T_ACCURACY), [th, v], rtol=TOL_ACCURACY, atol=TOL_ACCURACY, t_eval=te)
        ref = _heyoka_ld(b, g, w, [th, v], te)
        row["error_2e4"] = float(np.max(np.abs(r.y[0] - ref) / np.maximum(1.0, np.abs(ref))))
        rows.append(row)
    return rows


def render(rows):
    """Markdown of :func:`run`'s rows."""
    lines = [
        "# Long horizons",
        "",
        "`python -m benchmarks.horizon_bench` — "
        f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, mbm {mbm.__version__}.",
        "",
        f"201 outputs, rtol = atol = {TOL:g}; median times (ms); the error at T = {T_ACCURACY:g}, "
        f"rtol = atol = {TOL_ACCURACY:g}, is max|θ − θ_ref| / max(1, |θ_ref|) against heyoka in long double.",
        "",
        "| scene | mbm.solve T=1e3 → 1e6 (ms) | ratio | windows | solve_ivp T=1e3 → 1e6 (ms) | ratio | "
        "regime, switched at | error at 2e4 |",
        "|---|---|---:|---|---|---:|---|---:|",
    ]
    for r in rows:
        reg, t_reg = r["regime_1e+06"]
        lines.append(
            f"| {r['scene']} | {1e3 * r['solve_1000']:.3f} → {1e3 * r['solve_1e+06']:.3f} | "
            f"{r['solve_1e+06'] / r['solve_1000']:.2f} | {r['windows_1000']} → {r['windows_1e+06']} | "
            f"{1e3 * r['ivp_1000']:.2f} → {1e3 * r['ivp_1e+06']:.2f} | {r['ivp_1e+06'] / r['ivp_1000']:.2f} | "
            f"{reg}, {t_reg:.4g} | {r['error_2e4']:.1e} |")
    lines.append("")
    return "\n".join(lines)


def main(argv=None):
    """``python -m benchmarks.horizon_bench``: run, print, optionally write the Markdown."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks.horizon_bench", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    text = render(run(args.repeats))
    print(text)
    if args.out:
        Path(args.out).write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
