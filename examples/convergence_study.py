"""Regenerate the measurements of ``docs/convergent.md``: orders, error constants, costs
=====================================================================================

Usage::

    python examples/convergence_study.py reference   # (re)write tests/data/convergent_reference.npz
    python examples/convergence_study.py table       # τ sweep, fitted orders, costs (markdown)
    python examples/convergence_study.py estimator   # error-estimate / true local error ratios
    python examples/convergence_study.py work        # work-precision: τ, windows, ms per target
    python examples/convergence_study.py sweep M S   # raw error sweeps of methods M on scenes S
    python examples/convergence_study.py cost        # µs per window, every method and scene
    python examples/convergence_study.py cvode       # CVODE at 1e-12 against the reference

The reference is the fixed-point Taylor integrator of ``tests/data/convergent_fixed_point.py``
(~1e-25, independent of mbm's kernels).  Runs are single-threaded and short; the
whole table takes a few minutes on one core.
"""

import math
import sys
import time
from fractions import Fraction
from pathlib import Path

import numpy as np
from numba import njit

ROOT = Path(__file__).resolve().parents[1]
# The fixed-point reference integrator lives with the test data it writes
# (tests/data/convergent_fixed_point.py, independent of mbm and of the benchmark);
# this script regenerates that data, so it imports it from there.  mbm itself is
# imported as installed (pip install -e .).
sys.path.insert(0, str(ROOT / "tests" / "data"))

import mbm  # noqa: E402
import mbm.scenes  # noqa: E402
from mbm.cli import study as cli_study
from mbm.cli import orderfit  # noqa: E402
from mbm.approximants import splitting, taylor  # noqa: E402

REFERENCE_PATH = ROOT / "tests" / "data" / "convergent_reference.npz"

# name -> (beta, gamma, omega, theta0, v0, t_end).  The six scenes of docs/convergent.md.
SCENES = {
    name: (*mbm.scenes.get(name).params()[:5], t_end)  # the catalogue's scenes, these horizons
    for name, t_end in (("ex1", 80), ("ex2", 80), ("paper1", 20), ("running", 200),
                        ("separatrix", 200), ("longweak", 10000))
}

# The τ values of the table (as fractions: q windows of τ = p/q span p units).
TABLE_TAUS = (Fraction(1, 20), Fraction(1, 10), Fraction(1, 4), Fraction(1, 2), Fraction(1))
# The sweeps' window lengths, coarse to fine: above 1 for the high Taylor degrees,
# whose errors fall by orders of magnitude between τ = 1 and 1/2.
SWEEP_TAUS = tuple(Fraction(x) for x in ("4", "3", "5/2", "2", "3/2", "5/4", "1", "4/5", "2/3", "4/7", "1/2",
                                         "2/5", "1/3", "2/7", "1/4", "1/5", "1/6", "1/8", "1/10",
                                         "1/12", "1/16", "1/20", "1/24", "1/32", "1/40", "1/48",
                                         "1/64", "1/96", "1/128", "1/192", "1/256"))
# Timed runs per cost measurement; the best is kept (the machine is shared, and
# the minimum is the least disturbed run).
COST_REPEATS = 5
# Target of the work-precision column.
TARGET_ERROR = 1e-10
# Errors inside this band can be in the asymptotic regime: above mbm's own round-off
# floor (1e-12 to 1e-10, depending on the scene's conditioning and window count; the
# reference's floor is far lower) and below 1e-3, above which the error stops
# following C τ^p.
FIT_BAND = (1e-11, 1e-3)
# Every method here converges at least linearly: a local slope below 1 is a plateau
# (the separatrix scene's round-off sits at 2e-11 to 6e-11, inside FIT_BAND).
MIN_SLOPE = 1.0


def write_reference(path=REFERENCE_PATH):
    """Compute the fixed-point references of all scenes (samples at integer times)."""
    from convergent_fixed_point import fixed_point_reference

    data = {}
    for name, (b, g, w, th0, v0, t_end) in SCENES.items():
        t0 = time.perf_counter()
        ref = np.array(fixed_point_reference(b, g, w, (th0, v0), t_end))
        print(f"{name}: {ref.shape[0]} samples in {time.perf_counter() - t0:.1f} s", flush=True)
        data[name] = ref
        data[name + "_params"] = np.array([b, g, w, th0, v0, t_end])
    np.savez_compressed(path, **data)


def load_reference(path=REFERENCE_PATH):
    """dict scene -> array (n, 4) of (theta_hi, theta_lo, v_hi, v_lo) at t = 0, 1, 2, ..."""
    with np.load(path) as f:
        return {k: f[k] for k in f.files if not k.endswith("_params")}


def _grid(tau):
    """τ = p/q (a Fraction): q windows span p time units, so the run is sampled every
    q windows and compared with the reference's rows 0, p, 2p, ..."""
    tau = Fraction(tau).limit_denominator(1000)
    return tau.numerator, tau.denominator


def max_error(run, ref, tau, model=(0.0, 0.0, 1.0)):
    """Max over the sample times of max(|Δθ|, |Δθ'|) against the reference.

    ``run[j]`` is the state at the exact time j·p (see :func:`fixed_window_run`).
    """
    p, q = _grid(tau)
    r = ref[::p]
    n = min(run.shape[0], r.shape[0])
    if not np.all(np.isfinite(run[:n])):
        return math.inf
    eth = (run[:n, 0] - r[:n, 0]) - r[:n, 1]
    ev = (run[:n, 1] - r[:n, 2]) - r[:n, 3]
    return float(max(np.max(np.abs(eth)), np.max(np.abs(ev))))


def run_method(method, scene, tau, t_end=None):
    """Fixed-window run of ``method`` ("taylorN", "split*", "rk4") with τ = p/q,
    sampled every q windows (every p time units) up to the last multiple of p ≤ t_end."""
    b, g, w, th0, v0, t_all = SCENES[scene]
    t_end = t_all if t_end is None else t_end
    p, q = _grid(tau)
    nwin = q * (int(t_end) // p)
    h = float(Fraction(p, q))
    if method == "rk4":
        return rk4_fixed_run(b, g, w, th0, v0, h, nwin, q)
    return fixed_window_run(method, b, g, w, th0, v0, h, nwin, q)


def fixed_window_run(method, b, g, w, th0, v0, h, nwin, q):
    """States every q windows of length h (rows after a failure NaN), by mbm.solve.

    Sampled at the exact times k·p, p = round(q·h) (an integer): the outputs come from
    the windows' formulas at those times, so no drift of the window ends' times (the
    rounding of t + h summed over the run) enters the comparison.
    """
    m = nwin // q
    t = np.arange(m + 1) * float(round(q * h))
    r = mbm.solve(mbm.Pendulum(b, g, w), (0.0, t[-1]), [th0, v0], tau=h, approximant=method, t_eval=t)
    out = np.full((m + 1, 2), np.nan)
    out[: r.t.size] = r.y.T
    return out


@njit(cache=True)
def rk4_fixed_run(beta, gamma, omega, theta0, v0, h, n, every):
    """Classical RK4 with fixed step, for comparison (the benchmark issue's baseline)."""
    out = np.full((n // every + 1, 2), np.nan)
    out[0, 0] = theta0
    out[0, 1] = v0
    w2 = omega * omega
    th, v = theta0, v0
    for i in range(1, n + 1):
        k1t = v
        k1v = gamma - beta * v - w2 * math.sin(th)
        k2t = v + 0.5 * h * k1v
        k2v = gamma - beta * k2t - w2 * math.sin(th + 0.5 * h * k1t)
        k3t = v + 0.5 * h * k2v
        k3v = gamma - beta * k3t - w2 * math.sin(th + 0.5 * h * k2t)
        k4t = v + h * k3v
        k4v = gamma - beta * k4t - w2 * math.sin(th + h * k3t)
        th = th + h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t)
        v = v + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
        if i % every == 0:
            out[i // every, 0] = th
            out[i // every, 1] = v
    return out


def reference_error(scene, ref):
    """The fixed-point reference's own error: max over its samples of max(|Δθ|, |Δθ'|)
    against heyoka in long double (tol 1e-19), or against mbm at its tightest tolerance
    without heyoka (:func:`mbm.cli.study.study_reference`'s references)."""
    b, g, w, th0, v0, t_end = SCENES[scene]
    model = mbm.Pendulum(b, g, w)
    t = np.arange(ref[scene].shape[0], dtype=float)
    r = ref[scene]
    if cli_study.heyoka_ld_available():
        chk = cli_study.heyoka_ld_states(model, [th0, v0], t)
        ld = np.longdouble
        dth = (chk[:, 0] - r[:, 0].astype(ld)) - r[:, 1].astype(ld)
        dv = (chk[:, 1] - r[:, 2].astype(ld)) - r[:, 3].astype(ld)
    else:
        chk = mbm.solve(model, (0.0, t[-1]), [th0, v0], rtol=cli_study.TIGHT_TOL, atol=cli_study.TIGHT_TOL,
                        t_eval=t).y.T
        dth = (chk[:, 0] - r[:, 0]) - r[:, 1]
        dv = (chk[:, 1] - r[:, 2]) - r[:, 3]
    return float(max(np.max(np.abs(dth)), np.max(np.abs(dv))))


def fit_order(taus, errs, ref_error=0.0):
    """Order p ± its standard error and constant C of err ≈ C τ^p, and the points fitted.

    :func:`mbm.cli.orderfit.fit_order` (the rule of ``mbm study``): errors within 10× the
    reference's error are at its floor, errors outside FIT_BAND are left out (below:
    mbm's own round-off, far above the fixed-point reference's error; above: no
    C τ^p regime), then the longest run of consecutive τ whose local slopes agree and
    are at least MIN_SLOPE is fitted by least squares.  C is the geometric mean of err/τ^p over that run.
    Returns (p, stderr, C, number of points); p and C NaN with fewer than 2 points.
    """
    fit = orderfit.fit_order(taus, errs, ref_error, ceil=FIT_BAND[1], err_min=FIT_BAND[0], min_slope=MIN_SLOPE)
    if not math.isfinite(fit.order):
        return math.nan, math.nan, math.nan, fit.n
    t, e = np.asarray(taus, dtype=float)[fit.used], np.asarray(errs, dtype=float)[fit.used]
    c = float(np.exp(np.mean(np.log(e) - fit.order * np.log(t))))
    return fit.order, fit.stderr, c, fit.n


def sweep(method, scene, ref, stop_below=1e-11, taus=SWEEP_TAUS):
    """Errors for τ in ``taus`` (descending); stops once two consecutive errors are
    ≤ stop_below or the error has stopped decreasing twice (round-off floor)."""
    model = SCENES[scene][:3]
    out = {}
    below = 0
    rising = 0
    prev = math.inf
    for tau in taus:
        e = max_error(run_method(method, scene, tau), ref[scene], tau, model)
        out[tau] = e
        below = below + 1 if e <= stop_below else 0
        rising = rising + 1 if (e >= prev and e < 1e-3) else 0
        prev = min(prev, e)
        if below >= 2 or rising >= 2:
            break
    return out


def cost_per_window(method, scene, tau=0.125, min_time=0.2):
    """Warm cost of one window (µs): best of COST_REPEATS timed fixed-window runs of ≥ min_time/3 s each."""
    b, g, w, th0, v0, t_all = SCENES[scene]
    run_method(method, scene, tau, t_end=1)  # compile / warm
    nwin = 1000
    while True:
        t0 = time.perf_counter()
        _timed_run(method, b, g, w, th0, v0, tau, nwin)
        dt = time.perf_counter() - t0
        if dt >= min_time / 3:
            break
        nwin *= 4
    best = math.inf
    for _ in range(COST_REPEATS):
        t0 = time.perf_counter()
        _timed_run(method, b, g, w, th0, v0, tau, nwin)
        best = min(best, time.perf_counter() - t0)
    return best / nwin * 1e6


def _timed_run(method, b, g, w, th0, v0, tau, nwin):
    if method == "rk4":
        rk4_fixed_run(b, g, w, th0, v0, tau, nwin, nwin)
    else:
        mbm.solve(mbm.Pendulum(b, g, w), (0.0, nwin * tau), [th0, v0], tau=tau, approximant=method,
                  t_eval=[nwin * tau])


def table(methods, scenes=tuple(SCENES), out=sys.stdout):
    """Markdown table: order fit, constant, errors at TABLE_TAUS, cost, work to TARGET_ERROR."""
    ref = load_reference()
    ref_err = {sc: reference_error(sc, ref) for sc in scenes}
    out.write("reference's error (fixed point against " + ("heyoka long double" if cli_study.heyoka_ld_available()
              else "mbm at its tightest") + "): "
              + ", ".join(f"{sc} {e:.1e}" for sc, e in ref_err.items()) + "\n\n")
    out.write(
        "| method | scene | fitted p ± se (pts) | C | "
        + " | ".join(f"τ={float(t):g}" for t in TABLE_TAUS)
        + f" | µs/window | largest τ with err ≤ {TARGET_ERROR:g} | ms to reach it |\n"
    )
    out.write("|" + "---|" * (7 + len(TABLE_TAUS)) + "\n")
    for meth in methods:
        for sc in scenes:
            errs = sweep(meth, sc, ref)
            model = SCENES[sc][:3]
            for t in TABLE_TAUS:
                if t not in errs:
                    errs[t] = max_error(run_method(meth, sc, t), ref[sc], t, model)
            taus = sorted(errs)
            p, se, c, npts = fit_order([float(t) for t in taus], [errs[t] for t in taus], ref_err[sc])
            us = cost_per_window(meth, sc)
            ok = [t for t in taus if errs[t] <= TARGET_ERROR]
            if ok:
                best = max(ok)
                ms = SCENES[sc][5] / float(best) * us * 1e-3
                reach = f"{best} | {ms:.3g}"
            else:
                reach = f"not reached (best {min(errs.values()):.1e}) | -"
            out.write(
                f"| {meth} | {sc} | {p:.2f} ± {se:.2g} ({npts}) | {c:.2g} | "
                + " | ".join(f"{errs[t]:.1e}" for t in TABLE_TAUS)
                + f" | {us:.2f} | {reach} |\n"
            )
            out.flush()


WORK_TARGETS = (1e-6, 1e-8, 1e-10, 1e-12)


def work_precision(methods, scenes=tuple(SCENES), targets=WORK_TARGETS, out=sys.stdout):
    """Markdown table: for each target, the largest sweep τ reaching it and the kernel time.

    Time = (horizon / τ) windows × the warm µs/window of :func:`cost_per_window`
    (numba loop, no solve_ivp overhead); "windows" is what a solve_ivp run pays
    its per-step Python overhead on.
    """
    ref = load_reference()
    out.write("| method | scene | " + " | ".join(f"{t:g}: τ, windows, ms" for t in targets) + " |\n")
    out.write("|" + "---|" * (2 + len(targets)) + "\n")
    for meth in methods:
        for sc in scenes:
            errs = sweep(meth, sc, ref, stop_below=min(targets) / 10)
            us = cost_per_window(meth, sc)
            cells = []
            for tgt in targets:
                ok = [t for t in errs if errs[t] <= tgt]
                if not ok:
                    cells.append("-")
                    continue
                best = max(ok)
                nwin = SCENES[sc][5] / float(best)
                cells.append(f"{best}, {nwin:.0f}, {nwin * us * 1e-3:.3g}")
            out.write(f"| {meth} | {sc} | " + " | ".join(cells) + " |\n")
            out.flush()


def exact_local(scene, theta0, v0, h):
    """The true state at h from (θ₀, θ̇₀) (exact doubles), by the fixed-point integrator."""
    from convergent_fixed_point import local_step

    return local_step(*SCENES[scene][:3], theta0, v0, h)


def _approximant(name):
    """Registered approximant by name; works while other paper modules are incomplete."""
    from mbm.approximants import base

    try:
        return base.get_approximant(name)
    except ImportError:
        return base._REGISTRY[name]()


# Local errors below this many ulps of the anchor state are round-off, where an
# estimate/true ratio means nothing.
ESTIMATOR_ULPS_FLOOR = 100
# Local errors above this are not a usable window for any tolerance.
ESTIMATOR_MAX_ERROR = 1e-2
ESTIMATOR_HS = (0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0)


def estimator_ratios(name, scene, n_anchors=12, hs=ESTIMATOR_HS):
    """Ratios err_estimate / true local error (θ and θ' separately) along the reference.

    Anchors are n_anchors reference states evenly spread over the scene's horizon
    (capped at t = 200).  Ratios are kept where the true error lies between
    ESTIMATOR_ULPS_FLOOR ulps of the anchor state and ESTIMATOR_MAX_ERROR.
    """
    ap = _approximant(name)
    b, g, w = SCENES[scene][:3]
    ref = load_reference()[scene]
    idx = np.linspace(0, min(len(ref) - 1, 200), n_anchors).astype(int)
    out = []
    for i in idx:
        th0, v0 = float(ref[i, 0]), float(ref[i, 2])
        floor = ESTIMATOR_ULPS_FLOOR * np.spacing(max(abs(th0), abs(v0), 1.0))
        coef = ap.anchor_kernel(b, g, w, th0, v0)
        for h in hs:
            (a, al), (vv, vl) = exact_local(scene, th0, v0, h)
            th, v = ap.eval_kernel(coef, h)
            et, ev = ap.error_kernel(coef, h)
            for est, true in ((et, abs((th - a) - al)), (ev, abs((v - vv) - vl))):
                if floor <= true <= ESTIMATOR_MAX_ERROR:
                    out.append((h, true, est / true))
    return np.array(out).reshape(-1, 3)


if __name__ == "__main__":
    cmd = sys.argv[1] if len(sys.argv) > 1 else "table"
    if cmd == "reference":
        write_reference()
    elif cmd == "sweep":
        ref = load_reference()
        for meth in sys.argv[2].split(","):
            for sc in (sys.argv[3].split(",") if len(sys.argv) > 3 else SCENES):
                errs = sweep(meth, sc, ref)
                taus = sorted(errs)
                p, se, c, k = fit_order([float(t) for t in taus], [errs[t] for t in taus],
                                        reference_error(sc, ref))
                print(meth, sc, f"p={p:.2f} ± {se:.2g} ({k}) C={c:.2g}",
                      " ".join(f"{t}:{errs[t]:.1e}" for t in taus[::-1]), flush=True)
    elif cmd == "estimator":
        print("| approximant | scene | windows | min | median | 90th pct | max |")
        print("|---|---|---|---|---|---|---|")
        names = sys.argv[2].split(",") if len(sys.argv) > 2 else (
            ["taylor8", "taylor16", "taylor24", "split4", "split4bm", "split6"])
        for nm in names:
            for sc in SCENES:
                r = estimator_ratios(nm, sc)
                if r.size == 0:
                    print(f"| {nm} | {sc} | 0 | - | - | - | - |")
                    continue
                q = r[:, 2]
                print(f"| {nm} | {sc} | {q.size} | {q.min():.2f} | {np.median(q):.2f} | "
                      f"{np.percentile(q, 90):.2f} | {q.max():.2g} |", flush=True)
    elif cmd == "cvode":
        # How far mbm.reference (CVODE, rtol = atol = 1e-12) is from the fixed-point reference.
        from mbm import Pendulum
        from mbm.frontends.reference import reference

        ref = load_reference()
        print("| scene | max abs Δθ | max abs Δθ' |")
        print("|---|---|---|")
        for sc, (b, g, w, th0, v0, t_end) in SCENES.items():
            r = reference(Pendulum(b, g, w), (0.0, float(t_end)), [th0, v0],
                          t_eval=np.arange(t_end + 1.0))
            R = ref[sc]
            print(f"| {sc} | {np.abs(r.y[0] - R[:, 0] - R[:, 1]).max():.1e} | "
                  f"{np.abs(r.y[1] - R[:, 2] - R[:, 3]).max():.1e} |", flush=True)
    elif cmd == "cost":
        meths = sys.argv[2].split(",") if len(sys.argv) > 2 else (
            ["rk4"] + list(splitting.SPLIT_METHODS) + [f"taylor{n}" for n in taylor.TAYLOR_ORDERS])
        print("| method | " + " | ".join(SCENES) + " |")
        print("|---|" + "---|" * len(SCENES))
        for meth in meths:
            print(f"| {meth} | " + " | ".join(f"{cost_per_window(meth, sc):.2f}" for sc in SCENES)
                  + " |", flush=True)
    elif cmd == "work":
        meths = sys.argv[2].split(",") if len(sys.argv) > 2 else (
            ["rk4", "split4bm", "split6"] + [f"taylor{n}" for n in taylor.TAYLOR_ORDERS])
        work_precision(meths)
    elif cmd == "table":
        meths = sys.argv[2].split(",") if len(sys.argv) > 2 else (
            ["rk4", "split2", "split4", "split4bm", "split6", "split8", "sbab2", "sbab3"]
            + [f"taylor{n}" for n in taylor.TAYLOR_ORDERS]
        )
        scs = sys.argv[3].split(",") if len(sys.argv) > 3 else tuple(SCENES)
        table(meths, scs)
    else:
        raise SystemExit(f"unknown command {cmd!r}")
