"""Command line of mbm (the ``mbm`` console script, also ``python -m mbm``): :func:`main` and its subcommands.

Subcommands: ``demo`` (the second paper's Example 1, error and time), ``solve`` (one
scene to CSV/NPZ, optional PNG), ``study`` (a step-size / accuracy study with fitted
orders), ``iv`` (a Josephson-junction I–V sweep with its switching and retrapping
currents; with a drive, ``--steps`` prints the Shapiro steps' table).  ``bench`` only
says where the work-precision benchmark went: it runs from a checkout, ``python -m
benchmarks``.
"""

import argparse
import math
import sys
import time

import numpy as np

#: ``python -m mbm --help``'s description: the module docstring's content in plain text
#: (a terminal shows reStructuredText's quotes and roles as typed).
HELP = """mbm integrates theta'' + beta theta' + omega^2 sin(theta) = gamma (+ A sin(Omega t + phi))
by the moving boundary method.

Subcommands: demo (the second paper's Example 1, error and time), solve (one scene to
CSV/NPZ, optional PNG), study (a step-size / accuracy study with fitted orders), iv (a
Josephson-junction I-V sweep with its switching and retrapping currents; with a drive,
--steps prints the Shapiro steps' table).  bench only says where the work-precision
benchmark went: it runs from a checkout, python -m benchmarks.
"""

__all__ = ["main", "demo", "solve_command", "study_command", "iv_command", "steps_command", "parse_angle"]

# Repetitions of each timed solve in the demo: the median of a few runs keeps one
# slow run (page faults, another process) out of the figure.
DEMO_REPEATS = 5
# `mbm solve --plot`: phase-portrait samples per turn of θ (a rotation drawn by 64
# points per 2π shows no aliasing), and at most this many in all.
PORTRAIT_SAMPLES_PER_TURN = 64
PORTRAIT_MAX_SAMPLES = 200_000


def _median_time(fn, repeats=DEMO_REPEATS):
    times = []
    out = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), out


def demo(rtol=1e-9, out=sys.stdout):
    """Solve the second paper's Example 1 with MBM; print error against CVODE and timings.

    Example 1: β = 0.1, γ = 0.3, θ₀ = 30°, θ̇₀ = 0, 0 ≤ t ≤ 80, 201 output times.
    Runs MBM's default ("auto") through solve_ivp and through the compiled
    :func:`mbm.solve`, the paper's own ℘ approximant with τ = 0.25, and scipy's DOP853
    at the same rtol/atol, all in this process.

    Parameters
    ----------
    rtol : float
        rtol = atol for MBM and DOP853.
    out : file-like
        Where to print.

    Returns
    -------
    dict
        Errors and median times, keyed by solver.
    """
    from scipy.integrate import solve_ivp

    import mbm
    from mbm.compile import warm as _warm

    # From a cold cache: one helper compiles both solve_ivp paths' kernels (auto's, then
    # salas-torque's) beside this process, the second while this one is still on the first.
    _warm.prefetch_keys(_warm.DEMO_KEYS)
    model = mbm.Pendulum(beta=0.1, gamma=0.3)
    y0 = [math.radians(30.0), 0.0]
    t_span = (0.0, 80.0)
    t_eval = np.linspace(*t_span, 201)
    t0 = time.perf_counter()
    ref = mbm.reference(model, t_span, y0, t_eval=t_eval, rtol=1e-13, atol=1e-13)
    t_ref = time.perf_counter() - t0
    runs = {
        "MBM auto, solve_ivp": lambda: solve_ivp(
            model, t_span, y0, method=mbm.MBM, rtol=rtol, atol=rtol, t_eval=t_eval,
            windows_per_step=None,
        ),
        "MBM auto, mbm.solve": lambda: mbm.solve(model, t_span, y0, rtol=rtol, atol=rtol, t_eval=t_eval),
        "MBM salas-torque tau=0.25": lambda: solve_ivp(
            model, t_span, y0, method=mbm.MBM, approximant="salas-torque", tau=0.25, t_eval=t_eval,
            windows_per_step=None,
        ),
        "scipy DOP853": lambda: solve_ivp(model, t_span, y0, method="DOP853", rtol=rtol, atol=rtol, t_eval=t_eval),
    }
    results = {}
    first = {}
    for name, fn in runs.items():
        t0 = time.perf_counter()
        fn()  # first call: numba compile or cache load, reported apart
        first[name] = time.perf_counter() - t0
        t_med, sol = _median_time(fn)
        results[name] = (float(np.max(np.abs(sol.y[0] - ref.y[0]))), t_med)
    single = mbm.get_approximant("salas-torque").anchor(model, *y0)
    err_single = float(np.max(np.abs(single(t_eval)[0] - ref.y[0])))
    p = lambda *a: print(*a, file=out)  # noqa: E731
    p("mbm demo: the second paper's Example 1, theta'' + 0.1 theta' + sin(theta) = 0.3,")
    p("          theta(0) = 30 deg, theta'(0) = 0, 0 <= t <= 80; error = max|theta - theta_ref|")
    p(f"          over {t_eval.size} times against CVODE at rtol = atol = 1e-13 ({t_ref * 1e3:.0f} ms)")
    p(f"          rtol = atol = {rtol:g}; times are medians of {DEMO_REPEATS} runs")
    p("")
    p(f"  {'solver':<30s} {'error':>10s} {'time':>11s} {'first call':>11s}")
    for name, (err, t_med) in results.items():
        p(f"  {name:<30s} {err:10.2e} {t_med * 1e3:8.3f} ms {first[name]:9.2f} s")
    p(f"  {'single (4.33), no re-anchoring':<30s} {err_single:10.2e}")
    p("")
    p("  'auto' picked the convergent Taylor family here (beta, gamma != 0); the paper's")
    p("  cubic approximant levels off at its model error (3.2e-3) however small tau is.")
    results["single"] = (err_single, float("nan"))
    return results


# Suffixes `mbm solve --out` understands; anything else is rejected by name.
OUT_SUFFIXES = (".csv", ".npz")
# Suffixes of an angle given in degrees ("30deg", "30°"); plain numbers are radians.
DEG_SUFFIXES = ("deg", "°", "d")


def parse_angle(text):
    """Parse ``--theta0``: a number (radians) or a number with a ``deg`` suffix.

    Parameters
    ----------
    text : str
        E.g. ``"0.5"``, ``"30deg"``, ``"30°"``.

    Returns
    -------
    (float, bool)
        The number and whether it was marked as degrees.

    Raises
    ------
    argparse.ArgumentTypeError
        If it is not a finite number (argparse then names the argument).
    """
    s = str(text).strip().lower()
    deg = False
    for suf in DEG_SUFFIXES:
        if s.endswith(suf) and s[: -len(suf)].strip():
            s, deg = s[: -len(suf)].strip(), True
            break
    try:
        x = float(s)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an angle: {text!r} (a number in radians, or e.g. 30deg)") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"angle must be finite, got {text!r}")
    return x, deg


def _finite(text):
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a real number, got {text!r}") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"must be finite, got {text!r}")
    return x


def _positive(text):
    x = _finite(text)
    if not x > 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text!r}")
    return x


def _count(text):
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer: {text!r}") from None
    if n < 2:
        raise argparse.ArgumentTypeError(f"must be >= 2, got {text!r}")
    return n


def _positive_list(text):
    try:
        xs = [float(x) for x in str(text).split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a comma-separated list of numbers: {text!r}") from None
    if not xs or not all(math.isfinite(x) and x > 0 for x in xs):
        raise argparse.ArgumentTypeError(f"need positive finite numbers, got {text!r}")
    return xs


def _approximant(text):
    import mbm

    names = ["auto", *mbm.approximant_names()]
    if text not in names:
        raise argparse.ArgumentTypeError(f"unknown approximant {text!r}; choose from {', '.join(names)}")
    return text


def _approximant_list(text):
    return [_approximant(x.strip()) for x in str(text).split(",") if x.strip()]


def _require_matplotlib(parser, option):
    """Import matplotlib with the Agg backend, or stop with an error naming ``option``."""
    try:
        import matplotlib
    except ImportError:
        parser.error(f"{option} needs matplotlib, which is not installed (pip install matplotlib)")
    matplotlib.use("Agg")  # writes files only: no display is needed or assumed


def solve_command(beta, gamma, omega, theta0, v0, t_end, *, tau=None, approximant="auto",
                  rtol=1e-6, atol=1e-9, n_out=201, out=None, plot=None, stdout=None):
    """Solve one scene and write θ, θ' at ``n_out`` times (the ``mbm solve`` command).

    Parameters
    ----------
    beta, gamma, omega : float
        θ'' + βθ' + ω² sin θ = γ.
    theta0, v0 : float
        Initial state (θ₀ in radians).
    t_end : float
        End time (> 0); output on ``linspace(0, t_end, n_out)``.
    tau, approximant, rtol, atol
        As for :func:`mbm.solve`; approximants without a compiled kernel run through
        ``solve_ivp(method=mbm.MBM)``.
    n_out : int
    out : str or Path, optional
        ``.csv`` (columns ``t,theta,theta_dot``) or ``.npz`` (arrays ``t``, ``theta``,
        ``theta_dot`` and the scene's parameters); default: CSV on ``stdout``.
    plot : str or Path, optional
        PNG of θ(t) and the phase portrait (needs matplotlib).
    stdout : file-like, optional
        Default: ``sys.stdout`` at call time (so that redirection is honoured).

    Returns
    -------
    (ndarray, ndarray)
        ``t`` and ``y`` (shape (2, n_out)).
    """
    from pathlib import Path

    import mbm
    from mbm.cli.study import integrate

    stdout = sys.stdout if stdout is None else stdout
    model = mbm.Pendulum(beta=beta, gamma=gamma, omega=omega)
    t = np.linspace(0.0, t_end, n_out)
    y, _ = integrate(model, (0.0, t_end), [theta0, v0], t, approximant=approximant, tau=tau,
                     rtol=rtol, atol=atol)
    if out is None:
        _write_csv(stdout, t, y)
    elif str(out).lower().endswith(".npz"):
        np.savez(out, t=t, theta=y[0], theta_dot=y[1], beta=beta, gamma=gamma, omega=omega,
                 theta0=theta0, v0=v0, approximant=approximant)
    else:
        with open(out, "w", newline="") as f:
            _write_csv(f, t, y)
    # Phase slips: net 2π turns over the run (the junction's count of voltage pulses).
    slips = int(round((y[0, -1] - y[0, 0]) / (2.0 * math.pi)))
    v_mean = _mean_velocity_label(model, t_end, [theta0, v0], t, y, approximant=approximant, tau=tau, rtol=rtol,
                                  atol=atol)
    print(f"phase slips (net 2*pi turns): {slips}" + (f"; mean velocity {v_mean}" if v_mean else ""),
          file=sys.stderr)
    if plot is not None:
        import matplotlib.pyplot as plt

        fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
        a1.plot(t, y[0], lw=1.2)
        a1.set_xlabel("t")
        a1.set_ylabel(r"$\theta$")
        title = rf"$\beta$={beta:g}, $\gamma$={gamma:g}, $\omega$={omega:g}; {slips} phase slips"
        if v_mean:
            title += rf", $\langle\theta'\rangle$ {v_mean}"
        a1.set_title(title, fontsize=9)
        # On the cylinder: θ wrapped to (−π, π], the line broken where it wraps, sampled
        # densely enough (PORTRAIT_SAMPLES_PER_TURN) that a fast rotation is not aliased.
        n_plot = int(min(PORTRAIT_MAX_SAMPLES, max(n_out, PORTRAIT_SAMPLES_PER_TURN * (abs(slips) + 1))))
        tp = np.linspace(0.0, t_end, n_plot)
        yp = y if n_plot == n_out else integrate(model, (0.0, t_end), [theta0, v0], tp, approximant=approximant,
                                                 tau=tau, rtol=rtol, atol=atol)[0]
        wrapped = np.remainder(yp[0] + math.pi, 2.0 * math.pi) - math.pi
        jumps = np.flatnonzero(np.abs(np.diff(wrapped)) > math.pi)
        a2.plot(np.insert(wrapped, jumps + 1, np.nan), np.insert(yp[1], jumps + 1, np.nan), lw=0.6)
        a2.set_xlim(-math.pi, math.pi)
        a2.set_xlabel(r"$\theta$ (mod $2\pi$)")
        a2.set_ylabel(r"$\theta'$")
        a2.set_title("phase portrait on the cylinder")
        fig.tight_layout()
        fig.savefig(Path(plot), dpi=110)
        plt.close(fig)
    return t, y


def _mean_velocity_label(model, t_end, y0, t, y, *, approximant, tau, rtol, atol):
    """⟨θ'⟩ for a running state: exact (2π/T_c) where the compiled run reached the cycle,
    else "≈" the second half's (θ(T) − θ(T/2))/(T/2); "" when θ moved less than 2π there."""
    import mbm

    mid = np.searchsorted(t, 0.5 * t_end)
    if abs(y[0, -1] - y[0, mid]) < 2.0 * math.pi:
        return ""
    if tau is None and approximant == "auto":
        r = mbm.solve(model, (0.0, t_end), y0, rtol=rtol, atol=atol, t_eval=[t_end])
        if r.regime == "running":
            return f"= {r.mean_velocity:.10g} (limit cycle)"
    return f"≈ {(y[0, -1] - y[0, mid]) / (t[-1] - t[mid]):.6g}"


def _write_csv(f, t, y):
    f.write("t,theta,theta_dot\n")
    for ti, a, b in zip(t, y[0], y[1]):
        f.write(f"{float(ti)!r},{float(a)!r},{float(b)!r}\n")


def study_command(scene, approximants, taus=None, rtols=None, n_out=201, csv=None, plot=None,
                  stdout=None):
    """Run a step-size study and print its table (the ``mbm study`` command).

    Parameters
    ----------
    scene : tuple
        ``(beta, gamma, omega, theta0, v0, t_end)``.
    approximants : list of str
    taus, rtols : list of float, optional
        The sweep (see :func:`mbm.cli.study.run_study`).
    n_out : int
    csv, plot : str or Path, optional
        Where to write the rows (CSV) and the figure (PNG).
    stdout : file-like, optional
        Default: ``sys.stdout`` at call time.

    Returns
    -------
    dict
        The study (:func:`mbm.cli.study.run_study`).
    """
    from mbm.cli import study as cli_study

    stdout = sys.stdout if stdout is None else stdout
    study = cli_study.run_study(scene, approximants, taus=taus, rtols=rtols, n_out=n_out)
    print(cli_study.format_table(study), file=stdout)
    if csv:
        cli_study.write_csv(study, csv)
    if plot:
        cli_study.plot_study(study, plot)
    return study


# What `mbm bench` says: the benchmark is not part of the installed package.
BENCH_MOVED = (
    "mbm bench: the work-precision benchmark is not part of the installed package; it runs "
    "from a checkout of the repository: `python -m benchmarks --help` in its root (the tables; "
    "`python -m benchmarks extras` for the undamped t = 1e6 run, the I-V ensemble and the fixed "
    "costs; `pip install -e '.[bench]'` adds its optional peers)."
)


def iv_command(beta, gamma_max, points, *, omega=1.0, current_tol=1e-4, csv=None, plot=None, out=None,
               drive_amplitude=0.0, drive_frequency=0.0, drive_phase=0.0, differential=False):
    """``mbm iv``: an up-and-down I–V sweep 0 → gamma_max → 0; print the currents, write CSV/PNG
    (with an AC drive A sin(Ωt + φ) on every bias point where ``drive_amplitude`` ≠ 0; with
    ``differential``, d⟨θ'⟩/dγ at every point too, printed at the top of the sweep).

    Returns
    -------
    mbm.IVCurve
    """
    import mbm

    out = sys.stdout if out is None else out

    up = np.linspace(0.0, gamma_max, points)
    curve = mbm.iv_curve(beta, np.r_[up, up[::-1]], omega=omega, current_tol=current_tol,
                         drive_amplitude=drive_amplitude, drive_frequency=drive_frequency,
                         drive_phase=drive_phase, progress=True, differential=differential)
    print(f"beta = {beta:g}, omega = {omega:g}, {2 * points} bias points", file=out)
    if differential:
        print(f"differential resistance d<theta'>/dgamma at gamma = {gamma_max:g}: "
              f"{float(curve.dvoltage_dgamma[points - 1]):.6g} (every point's in the CSV)", file=out)
    if drive_amplitude != 0.0:
        print(f"AC drive A = {drive_amplitude:g}, Omega = {drive_frequency:g}, phi = {drive_phase:g}", file=out)
    for name, value, (lo, hi), settled in (
            ("switching current ", curve.switching_current, curve.switching_bracket, curve.switching_settled),
            ("retrapping current", curve.retrapping_current, curve.retrapping_bracket, curve.retrapping_settled)):
        line = f"{name} {value:.6g}" + (f"  in [{lo:.8g}, {hi:.8g}]" if math.isfinite(value) else "")
        if not settled:
            line += "  (probes changed voltage state between blocks: the bracket may be off by more than it says)"
        print(line, file=out)
    # iv_curve's warnings go to stderr; the report on stdout says the same, for a saved report.
    bad = np.flatnonzero(~curve.converged)
    if bad.size:
        where = ", ".join(f"{float(x):.6g}" for x in curve.gamma[bad])
        print(f"not settled: {bad.size} of {curve.gamma.size} points (velocity_tol = {curve.velocity_tol:g}), "
              f"gamma = [{where}]; converged False in the CSV", file=out)
    if csv:
        curve.to_csv(csv)
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        ax = curve.plot()
        ax.figure.tight_layout()
        ax.figure.savefig(plot, dpi=110)
        plt.close(ax.figure)
    return curve


def steps_command(beta, gamma_max, points, *, omega=1.0, current_tol=1e-4, csv=None, plot=None, out=None,
                  drive_amplitude=0.0, drive_frequency=0.0, drive_phase=0.0):
    """``mbm iv --steps``: the Shapiro steps over [0, gamma_max] (:func:`mbm.shapiro_steps`,
    ``points`` grid points), their edges bisected to ``current_tol``; print the step
    table, write CSV/PNG.

    Returns
    -------
    mbm.junction.shapiro.ShapiroSteps
    """
    import mbm

    out = sys.stdout if out is None else out
    steps = mbm.shapiro_steps(beta, (0.0, gamma_max), amplitude=drive_amplitude, frequency=drive_frequency,
                              omega=omega, phase=drive_phase, current_tol=current_tol, points=points)
    print(f"beta = {beta:g}, omega = {omega:g}, AC drive A = {drive_amplitude:g}, Omega = {drive_frequency:g}, "
          f"phi = {drive_phase:g}; Shapiro steps over gamma in [0, {gamma_max:g}] ({points} grid points, "
          f"edges to {current_tol:g})", file=out)
    print(steps.table(), file=out)
    if csv:
        steps.to_csv(csv)
    if plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        ax = steps.plot()
        ax.figure.tight_layout()
        ax.figure.savefig(plot, dpi=110)
        plt.close(ax.figure)
    return steps


def _bench(argv):
    """``mbm bench ARGS``: say where the benchmark went; exit status 2."""
    print(BENCH_MOVED, file=sys.stderr)
    return 2


def _build_parser():
    from mbm.cli.study import DEFAULT_TAUS, SCENES

    parser = argparse.ArgumentParser(prog="mbm", description=HELP,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p_demo = sub.add_parser("demo", help="solve the second paper's Example 1, print error and time")
    p_demo.add_argument("--rtol", type=float, default=1e-9, help="rtol = atol (default 1e-9)")

    p = sub.add_parser("solve", help="solve one scene; write CSV or NPZ (and a PNG)",
                       description="Solve theta'' + beta theta' + omega^2 sin(theta) = gamma by MBM "
                       "and write t, theta, theta_dot at --n-out times on [0, --t-end].")
    p.add_argument("--beta", type=_finite, default=0.0, help="damping beta (default 0)")
    p.add_argument("--gamma", type=_finite, default=0.0, help="torque gamma (default 0)")
    p.add_argument("--omega", type=_positive, default=1.0, help="natural frequency omega (default 1)")
    p.add_argument("--theta0", type=parse_angle, default=(0.0, False),
                   help="initial angle: radians, or degrees with --degrees or a 'deg' suffix (30deg)")
    p.add_argument("--degrees", action="store_true", help="read --theta0 in degrees")
    p.add_argument("--v0", type=_finite, default=0.0, help="initial angular velocity (default 0)")
    p.add_argument("--t-end", type=_positive, default=80.0, help="end time (default 80)")
    p.add_argument("--tau", type=_positive, default=None, help="fixed window length (default: from rtol/atol)")
    p.add_argument("--approximant", type=_approximant, default="auto", help="approximant name (default auto)")
    p.add_argument("--rtol", type=_positive, default=1e-6, help="relative tolerance (default 1e-6)")
    p.add_argument("--atol", type=_positive, default=1e-9, help="absolute tolerance (default 1e-9)")
    p.add_argument("--n-out", type=_count, default=201, help="number of output times (default 201)")
    p.add_argument("--out", default=None, help="output file, .csv or .npz (default: CSV on stdout)")
    p.add_argument("--plot", default=None, metavar="PNG", help="also save theta(t) and the phase portrait")

    q = sub.add_parser("study", help="step-size / accuracy study: table, fitted orders, plots",
                       description="Sweep tau (or rtol) for chosen approximants on one scene; print "
                       "error, the run's own error estimate (mbm.solve(..., error_estimate=True); "
                       "'—' for a run through solve_ivp), windows and time per point and the fitted "
                       "order of error ~ C h^p.",
                       epilog="scenes (beta, gamma, omega, theta0 [deg], v0, t_end):\n" + "\n".join(
                           f"  {k:<8s} {b:g}, {g:g}, {w:g}, {math.degrees(th):g}, {v:g}, {te:g}"
                           for k, (b, g, w, th, v, te) in SCENES.items()),
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    q.add_argument("--scene", choices=sorted(SCENES), default="ex1",
                   help="scene (default ex1: beta=0.1, gamma=0.3, theta0=30deg, 0<=t<=80)")
    q.add_argument("--approximants", type=_approximant_list, default=["taylor8", "split4", "salas-torque"],
                   help="comma-separated approximants (default taylor8,split4,salas-torque)")
    g = q.add_mutually_exclusive_group()
    g.add_argument("--taus", type=_positive_list, default=None,
                   help="comma-separated window lengths (default " + ",".join(f"{x:g}" for x in DEFAULT_TAUS)
                   + "; running: 1/16 to 1/128, as the Taylor radius there is ~0.53)")
    g.add_argument("--rtols", type=_positive_list, default=None,
                   help="comma-separated rtol = atol values: adaptive windows instead of a tau sweep")
    q.add_argument("--n-out", type=_count, default=201, help="output times where the error is measured")
    q.add_argument("--csv", default=None, help="write the rows to this CSV file")
    q.add_argument("--plot", default=None, metavar="PNG", help="save error-vs-h and error-vs-time plots")

    r = sub.add_parser("iv", help="Josephson-junction I-V curve (up and down sweep), switching and "
                                  "retrapping currents; CSV and PNG")
    r.add_argument("--beta", type=_positive, required=True, help="damping beta > 0 (1/sqrt(beta_c))")
    r.add_argument("--gamma-max", type=_positive, default=1.5, help="top of the bias sweep (default 1.5)")
    r.add_argument("--points", type=_count, default=151, help="bias points each way (default 151)")
    r.add_argument("--omega", type=_positive, default=1.0, help="omega (default 1)")
    r.add_argument("--current-tol", type=_positive, default=1e-4,
                   help="bisection width of the currents (default 1e-4)")
    r.add_argument("--drive-amplitude", type=_finite, default=0.0,
                   help="AC drive amplitude A: bias gamma + A sin(Omega t + phi) (default 0: none)")
    r.add_argument("--drive-frequency", type=_finite, default=0.0, help="AC drive angular frequency Omega > 0")
    r.add_argument("--drive-phase", type=_finite, default=0.0, help="AC drive phase phi (default 0)")
    r.add_argument("--steps", action="store_true",
                   help="with a drive: the Shapiro steps over [0, gamma-max] instead of the sweep, each edge "
                        "bisected to --current-tol on a grid of --points (mbm.shapiro_steps); prints the table")
    r.add_argument("--differential", action="store_true",
                   help="also d<theta'>/dgamma at every point (the differential resistance, in units of R; "
                        "a CSV column)")
    r.add_argument("--csv", default=None, help="write gamma, mean velocity, regime, period, converged "
                                               "(--steps: one row per step)")
    r.add_argument("--plot", default=None, metavar="PNG", help="save the I-V plot")

    sub.add_parser("bench", help="moved: run `python -m benchmarks` from a checkout",
                   add_help=False)
    return parser


def main(argv=None):
    """Entry point of the ``mbm`` command.

    Parameters
    ----------
    argv : list of str, optional
        Arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "bench":
        # Whatever follows "bench" (the benchmark's own options): say where it runs now.
        return _bench(argv[1:])
    parser = _build_parser()
    args = parser.parse_args(argv)
    if args.command == "demo":
        if not (args.rtol > 0 and math.isfinite(args.rtol)):
            parser.error("--rtol must be a positive number")
        demo(rtol=args.rtol)
    elif args.command == "solve":
        if args.out is not None and not str(args.out).lower().endswith(OUT_SUFFIXES):
            parser.error(f"--out must end in .csv or .npz, got {args.out!r}")
        if args.plot is not None:
            _require_matplotlib(parser, "--plot")
        th, deg = args.theta0
        theta0 = math.radians(th) if (deg or args.degrees) else th
        try:
            solve_command(args.beta, args.gamma, args.omega, theta0, args.v0, args.t_end, tau=args.tau,
                          approximant=args.approximant, rtol=args.rtol, atol=args.atol,
                          n_out=args.n_out, out=args.out, plot=args.plot)
        except (ValueError, RuntimeError, ArithmeticError) as exc:
            # The solver names the offending option (e.g. "pass tau"): report it the argparse way.
            parser.error(f"solve failed: {exc}")
        if args.out:
            print(f"wrote {args.out}" + (f" and {args.plot}" if args.plot else ""), file=sys.stderr)
    elif args.command == "study":
        if args.plot is not None:
            _require_matplotlib(parser, "--plot")
        from mbm.cli.study import SCENE_TAUS, SCENES

        taus = args.taus if args.taus is not None or args.rtols is not None else SCENE_TAUS.get(args.scene)
        study_command(SCENES[args.scene], args.approximants, taus=taus, rtols=args.rtols,
                      n_out=args.n_out, csv=args.csv, plot=args.plot)
    elif args.command == "iv":
        if args.plot is not None:
            _require_matplotlib(parser, "--plot")
        if args.steps and args.drive_amplitude == 0.0:
            parser.error("--steps needs a drive: --drive-amplitude A != 0 and --drive-frequency Omega > 0")
        if args.steps and args.differential:
            parser.error("--differential is for the I-V sweep, not --steps")
        extra = {"differential": True} if args.differential else {}
        try:
            (steps_command if args.steps else iv_command)(
                args.beta, args.gamma_max, args.points, omega=args.omega, current_tol=args.current_tol,
                csv=args.csv, plot=args.plot, drive_amplitude=args.drive_amplitude,
                drive_frequency=args.drive_frequency, drive_phase=args.drive_phase, **extra)
        except ValueError as exc:
            parser.error(str(exc))
    elif args.command == "bench":  # reached only via an unusual argv order
        return _bench([])
    return 0


