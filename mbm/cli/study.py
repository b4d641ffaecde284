"""Step-size and accuracy studies behind ``mbm study`` (and ``examples/step_size_study.py``).

A study runs the moving boundary method on one scene for several approximants over a
sweep of the window length τ (or of rtol), measures ``max |θ − θ_ref|`` at the output
times, and fits the order p of ``error ≈ C h^p`` with h the mean window length.

The reference states its own error (:func:`study_reference`): it is checked against a
second, independent integrator, and their largest difference is reported as the
reference's error.  Points within 10× of it are at the reference's floor: marked in
the table and never fitted; the order is fitted over the asymptotic range only, with
its standard error and range (:func:`mbm.cli.orderfit.fit_order`).

Beside the measured error each run through :func:`mbm.solve` states its own estimate,
``max |error_estimate of θ|`` from ``mbm.solve(..., error_estimate=True)``
(:func:`estimate_error`); runs through ``solve_ivp`` (approximants without a compiled
window) have none.
"""

import math
import time

import numpy as np

from . import orderfit
from .. import scenes

__all__ = ["SCENES", "SCENE_TAUS", "integrate", "estimate_error", "heyoka_ld_available", "heyoka_ld_states",
           "study_reference", "run_study", "fit_order", "format_table", "write_csv", "plot_study"]

# name -> (beta, gamma, omega, theta0 [rad], v0, t_end): scenes of mbm.scenes under the
# names `mbm study --scene` takes, with the horizons of docs/convergent.md, so that the
# CLI and the docs measure the same thing.
SCENES = {
    "ex1": scenes.get("ex1").params(),                     # second paper, Example 1 (P2)
    "ex2": scenes.get("ex2").params(),                     # second paper, Example 2 (P3)
    "paper1": scenes.get("paper1").params(),               # first paper, (3.11) (P1)
    "running": scenes.get("running").until(200.0).params(),  # gamma > omega^2: rotation (P5)
    "free": scenes.get("free").params(),                   # third paper, large amplitude
}
# Default τ sweep: halvings from 1 to 1/16 show orders up to ~10 before the
# reference's accuracy is reached.
DEFAULT_TAUS = (1.0, 0.5, 0.25, 0.125, 0.0625)
# Scenes whose default sweep differs.  Running: the Taylor series' radius is ~0.53
# there (mbm.approximants.taylor), so τ ≥ 1/8 is pre-asymptotic for taylor8 (local
# slopes 4.7, 6.0 at τ = 1/4 .. 1/16); ratios 1.5 and 4/3 from 1/16 to 1/128 give
# taylor8 seven points between that and the reference's floor.
SCENE_TAUS = {"running": (1 / 16, 1 / 24, 1 / 32, 1 / 48, 1 / 64, 1 / 96, 1 / 128)}
# Default rtol sweep (rtol = atol): three decades per point pair.
DEFAULT_RTOLS = (1e-3, 1e-5, 1e-7, 1e-9)
# heyoka's tolerance in 80-bit long double (eps 1.08e-19): the tightest it takes, ~1e-17
# absolute on θ ~ 2400 after the running scene's 200 time units.
HEYOKA_LD_TOL = 1e-19
# The tightest tolerance of DOP853 and of mbm (scipy's floor, 100 eps): the reference
# without heyoka, and the check of either reference.  CVODE is not used: at 1e-13 it is
# itself off by 4.2e-9 on the running scene (rtol·|θ| with |θ| ~ 2400).
TIGHT_TOL = 100 * float(np.finfo(float).eps)
# Approximant of the check (mbm's own, adaptive): the most accurate double-precision
# integrator here (2.3e-13 from heyoka on the running scene, DOP853 1.3e-11).
CHECK_APPROXIMANT = "taylor"

def _compiled(name):
    """Whether ``mbm.solve`` (the compiled path) runs approximant ``name``."""
    from ..core import window
    from ..approximants import get_approximant

    return name == "auto" or window.kind_of(get_approximant(name)) is not None


def integrate(model, t_span, y0, t_eval, approximant="auto", tau=None, rtol=1e-6, atol=1e-9):
    """Run MBM through the compiled :func:`mbm.solve` when it can, else ``solve_ivp``.

    Parameters
    ----------
    model : Pendulum
    t_span : (float, float)
    y0 : array_like, shape (2,)
    t_eval : array_like
        Output times.
    approximant : str, optional
    tau : float, optional
        Fixed window length; default: windows from rtol/atol.
    rtol, atol : float, optional

    Returns
    -------
    y : ndarray, shape (2, len(t_eval))
        θ and θ' at ``t_eval``.
    n_windows : int
        Windows used (for the ``solve_ivp`` path with fixed τ: ⌈T/τ⌉; else the
        solver's step count).

    Raises
    ------
    ValueError, ApproximantDomainError
        From the solver, for options it rejects.
    RuntimeError
        If the solver stops before ``t_span[1]``.
    """
    from ..frontends.solve import solve
    from ..frontends.ivp import MBM

    from ..approximants import get_approximant

    if tau is None and approximant != "auto":
        ap = get_approximant(approximant)
        if not ap.exact and ap.error_kernel is None:
            # solve_ivp would only warn and pick windows unrelated to rtol; the compiled
            # path refuses.  Refuse on both paths so the CLI's answer does not depend on it.
            raise ValueError(f"approximant {ap.name!r} has no error estimate: pass tau")
    if _compiled(approximant):
        sol = solve(model, t_span, y0, tau=tau, rtol=rtol, atol=atol,
                         approximant=approximant, t_eval=t_eval)
        n_windows = sol.n_windows
    else:
        from scipy.integrate import solve_ivp

        opts = {} if tau is None else {"tau": tau}
        sol = solve_ivp(model, t_span, y0, method=MBM, approximant=approximant, rtol=rtol,
                        atol=atol, t_eval=t_eval, **opts)
        # Only approximants without an estimate take this path, and they need tau (above).
        n_windows = math.ceil(abs(t_span[1] - t_span[0]) / tau)
    if not sol.success:
        raise RuntimeError(sol.message)
    return np.asarray(sol.y), int(n_windows)


def estimate_error(model, t_span, y0, t_eval, approximant="auto", tau=None, rtol=1e-6, atol=1e-9):
    """The run's own estimate of its error in θ: ``max |error_estimate[0]|``, or None.

    The run of :func:`integrate` with the same arguments, through :func:`mbm.solve` with
    ``error_estimate=True`` (the same windows and ``y``); None where :func:`integrate`
    goes through ``solve_ivp``, which gives no estimate.  :class:`mbm.AccuracyWarning`
    is silenced: a study shows the estimate beside the measured error.

    Parameters
    ----------
    model : Pendulum
    t_span : (float, float)
    y0 : array_like, shape (2,)
    t_eval : array_like
        Output times.
    approximant : str, optional
    tau : float, optional
        Fixed window length; default: windows from rtol/atol.
    rtol, atol : float, optional

    Returns
    -------
    float or None
        The estimate's largest magnitude over ``t_eval``.
    """
    import warnings

    from ..frontends.solve import solve
    from .. import AccuracyWarning

    if not _compiled(approximant):
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        sol = solve(model, t_span, y0, tau=tau, rtol=rtol, atol=atol, approximant=approximant,
                    t_eval=t_eval, error_estimate=True)
    if not sol.success:
        raise RuntimeError(sol.message)
    return float(np.max(np.abs(sol.error_estimate[0])))


def heyoka_ld_available():
    """Whether heyoka imports and ``numpy.longdouble`` is wider than a double."""
    try:
        import heyoka  # noqa: F401
    except ImportError:
        return False
    return np.finfo(np.longdouble).eps < 1e-18


def heyoka_ld_states(model, y0, t):
    """θ, θ' at ``t`` from t = 0 by heyoka's Taylor integrator in long double.

    Parameters
    ----------
    model : Pendulum
        Its AC drive included.
    y0 : array_like, shape (2,)
        θ, θ' at t = 0.
    t : array_like
        Output times, increasing, from 0.

    Returns
    -------
    ndarray of numpy.longdouble, shape (len(t), 2)

    Raises
    ------
    ImportError
        Without heyoka.
    RuntimeError
        If heyoka stops before ``t[-1]``.
    """
    import heyoka as hy

    ld = np.longdouble
    th, v = hy.make_vars("th", "v")
    acc = model.gamma - model.beta * v - model.omega ** 2 * hy.sin(th)
    amp, freq, phase = model.drive
    if amp != 0.0:
        acc = acc + amp * hy.sin(freq * hy.time + phase)
    ta = hy.taylor_adaptive([(th, v), (v, acc)], np.asarray(y0, dtype=ld), fp_type=ld,
                            tol=ld(HEYOKA_LD_TOL), compact_mode=True)
    res = ta.propagate_grid(np.asarray(t, dtype=ld))
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"heyoka stopped early: {res[0]}")
    return np.asarray(res[-1])


def study_reference(model, y0, t):
    """θ_ref at ``t`` from t = 0, and its own error, measured against an independent check.

    The reference is heyoka in long double (:data:`HEYOKA_LD_TOL`) when heyoka is
    installed, else DOP853 at :data:`TIGHT_TOL`; the check is mbm's adaptive
    :data:`CHECK_APPROXIMANT` at :data:`TIGHT_TOL` (different code and arithmetic).
    ``max |reference − check|`` bounds the error of the less accurate of the two, so it
    is a conservative statement of the reference's error (the two would have to err
    alike to hide one).

    Parameters
    ----------
    model : Pendulum
        The scene's equation.
    y0 : array_like, shape (2,)
        θ, θ' at t = 0.
    t : ndarray
        Output times, from 0.

    Returns
    -------
    dict
        ``theta`` (θ_ref at t; long double from heyoka), ``error`` (max |reference −
        check|), ``name`` and ``check_name``.
    """
    from ..frontends.solve import solve
    from ..frontends.reference import reference

    t = np.asarray(t, dtype=float)
    if heyoka_ld_available():
        theta = heyoka_ld_states(model, y0, t)[:, 0]
        name = f"heyoka long double, tol {HEYOKA_LD_TOL:g}"
    else:
        theta = reference(model, (0.0, t[-1]), y0, t_eval=t, rtol=TIGHT_TOL, atol=TIGHT_TOL,
                          solver="dop853").y[0]
        name = f"DOP853, rtol=atol={TIGHT_TOL:.3g} (heyoka not installed)"
    chk = solve(model, (0.0, t[-1]), y0, rtol=TIGHT_TOL, atol=TIGHT_TOL,
                     approximant=CHECK_APPROXIMANT, t_eval=t)
    if not chk.success:
        raise RuntimeError(f"the reference's check failed: {chk.message}")
    error = float(np.max(np.abs(np.asarray(chk.y[0], dtype=theta.dtype) - theta)))
    check_name = f"mbm {CHECK_APPROXIMANT}, rtol=atol={TIGHT_TOL:.3g}"
    return dict(theta=theta, error=error, name=name, check_name=check_name)


def fit_order(h, err, ref_error=0.0):
    """Fitted order of one sweep: :func:`mbm.cli.orderfit.fit_order` (floor, asymptotic range).

    Parameters
    ----------
    h, err : array_like
        Mean window lengths and errors.
    ref_error : float, optional
        The reference's own error (points within 10× of it are not fitted).

    Returns
    -------
    mbm.cli.orderfit.OrderFit
    """
    return orderfit.fit_order(h, err, ref_error)


def run_study(scene, approximants, taus=None, rtols=None, n_out=201, show_progress=True):
    """Errors and costs of MBM over a τ (or rtol) sweep, with fitted orders.

    Parameters
    ----------
    scene : tuple or mbm.scenes.Scene
        ``(beta, gamma, omega, theta0, v0, t_end)`` (θ₀ in radians), e.g. a value of
        :data:`SCENES`, or a catalogue scene (from t = 0).
    approximants : sequence of str
        Approximant names (see :func:`mbm.approximant_names`) or ``"auto"``.
    taus : sequence of float, optional
        Window lengths; the default sweep when neither taus nor rtols is given.
    rtols : sequence of float, optional
        rtol = atol values (adaptive windows) instead of a τ sweep.
    n_out : int, optional
        Output times on [0, t_end] where the error is measured.
    show_progress : bool, optional
        Draw a progress bar on stderr (only if it is a terminal).

    Returns
    -------
    dict
        ``knob`` ("tau" or "rtol"), ``values``, ``t``, ``ref`` (θ_ref at t, float64),
        ``ref_error``, ``ref_name``, ``check_name`` (:func:`study_reference`),
        ``rows`` (list of dicts: approximant, value, windows, h, error, estimate (the
        run's own, :func:`estimate_error`; None without one), time_s, note, floor (at
        the reference's floor), fitted (in the order fit)),
        ``fits`` ({approximant: :class:`mbm.cli.orderfit.OrderFit`}), ``orders``
        ({approximant: fitted order}), ``n_fit`` ({approximant: points in the fit}),
        ``scene`` and ``curves`` ({approximant: (value, |θ − θ_ref| at t)} at the
        middle knob value).
    """
    from ..junction.progress import Progress
    from ..model import Pendulum

    if taus is not None and rtols is not None:
        raise ValueError("give taus or rtols, not both")
    if isinstance(scene, scenes.Scene):
        if scene.t_span[0] != 0.0:
            raise ValueError(f"a study runs from t = 0; scene {scene.name} starts at {scene.t_span[0]}")
        scene = scene.params()
    knob = "rtol" if rtols is not None else "tau"
    values = [float(v) for v in (rtols if rtols is not None else (taus or DEFAULT_TAUS))]
    beta, gamma, omega, th0, v0, t_end = (float(x) for x in scene)
    model = Pendulum(beta=beta, gamma=gamma, omega=omega)
    t = np.linspace(0.0, t_end, int(n_out))
    refd = study_reference(model, [th0, v0], t)
    ref = refd["theta"]
    rows, curves = [], {}
    mid = values[len(values) // 2]
    bar = Progress(len(values) * len(approximants), "study", enabled=None if show_progress else False)
    with bar:
        for name in approximants:
            for v in values:
                rows.append(_study_point(model, (th0, v0), t, ref, name, knob, v, first=v == values[0]))
                if v == mid and "curve" in rows[-1]:
                    curves[name] = (v, rows[-1].pop("curve"))
                rows[-1].pop("curve", None)
                bar.update()
    fits = {}
    for name in approximants:
        rs = [r for r in rows if r["approximant"] == name]
        fits[name] = fit_order([r["h"] for r in rs], [r["error"] for r in rs], refd["error"])
        for r, fl, used in zip(rs, fits[name].floor, fits[name].used):
            r.update(floor=bool(fl), fitted=bool(used))
    return dict(knob=knob, values=values, t=t, ref=np.asarray(ref, dtype=float), ref_error=refd["error"],
                ref_name=refd["name"], check_name=refd["check_name"], rows=rows, fits=fits,
                orders={k: f.order for k, f in fits.items()}, n_fit={k: f.n for k, f in fits.items()},
                curves=curves, scene=(beta, gamma, omega, th0, v0, t_end))


def _study_point(model, y0, t, ref, name, knob, v, first):
    """One row of a study: run ``name`` at knob value ``v``, time it, measure its error.

    ``first``: run once untimed before (numba compilation or cache loading is not the
    cost of a window and would swamp the first row's time).  The row carries the error
    curve under ``"curve"`` (|θ − θ_ref| at t) when the run succeeded.  The estimate
    comes from one more run, untimed: the time is the plain run's.
    """
    t_end = float(t[-1])
    kw = {"tau": v} if knob == "tau" else {"rtol": v, "atol": v}
    row = dict(approximant=name, value=v, windows=0, h=float("nan"),
               error=float("nan"), estimate=None, time_s=float("nan"), note="")
    try:
        if first:
            integrate(model, (0.0, t_end), list(y0), t, approximant=name, **kw)
        c = time.perf_counter()
        y, n_w = integrate(model, (0.0, t_end), list(y0), t, approximant=name, **kw)
        row["time_s"] = time.perf_counter() - c
        # In the reference's precision (long double from heyoka): θ ~ 2400 on the
        # running scene, where rounding θ_ref to a double would add 2.3e-13.
        e = np.abs(np.asarray(y[0], dtype=ref.dtype) - ref).astype(float)
        row.update(windows=n_w, h=t_end / max(n_w, 1), error=float(np.max(e)), curve=e,
                   estimate=estimate_error(model, (0.0, t_end), list(y0), t, approximant=name, **kw))
    except (ValueError, RuntimeError, ArithmeticError) as exc:
        # A domain error or an option the approximant rejects is a result of
        # the study (e.g. no error estimate for an rtol sweep), not a crash.
        row["note"] = str(exc).split("\n")[0][:120]
    return row


def format_table(study):
    """The study as a plain-text table, then one line of fitted orders per approximant.

    Parameters
    ----------
    study : dict
        From :func:`run_study`.

    Returns
    -------
    str
    """
    beta, gamma, omega, th0, v0, t_end = study["scene"]
    knob = study["knob"]
    floor = orderfit.FLOOR_FACTOR * study["ref_error"]
    lines = [
        f"scene: beta={beta:g} gamma={gamma:g} omega={omega:g} theta0={th0:.6g} rad "
        f"v0={v0:g} 0<=t<={t_end:g}; error = max|theta - theta_ref| over {study['t'].size} times",
        f"reference: {study['ref_name']}; its error, max|reference - check| with the check "
        f"{study['check_name']}: {study['ref_error']:.2g}",
        "estimate = the run's own, max|error_estimate of theta| (mbm.solve(..., error_estimate=True)); "
        "— for a run through solve_ivp",
        f"{'approximant':<20s} {knob:>9s} {'windows':>8s} {'mean h':>9s} {'error':>10s} {'estimate':>10s} "
        f"{'time ms':>9s}",
    ]
    for r in study["rows"]:
        if r["note"]:
            lines.append(f"{r['approximant']:<20s} {r['value']:9.3g} {'-':>8s} {'-':>9s} "
                         f"{'failed':>10s} {'-':>10s}   {r['note']}")
            continue
        mark = ("   * at the reference's floor" if r.get("floor")
                else "   fitted" if r.get("fitted")
                else f"   not fitted (error >= {orderfit.ERR_CEIL:g})" if r["error"] >= orderfit.ERR_CEIL
                else "   not fitted (outside the asymptotic range)")
        est = "—" if r["estimate"] is None else f"{r['estimate']:.2e}"
        lines.append(f"{r['approximant']:<20s} {r['value']:9.3g} {r['windows']:8d} {r['h']:9.3g} "
                     f"{r['error']:10.2e} {est:>10s} {r['time_s'] * 1e3:9.2f}{mark}")
    lines.append("")
    lines.append("fitted order p of error ~ C h^p (h = mean window; least squares ± its standard error)")
    lines.append(
        f"  over the asymptotic range: errors <= {orderfit.FLOOR_FACTOR:g} x the reference's ({floor:.2g}) "
        f"and >= {orderfit.ERR_CEIL:g} left out, then the longest run of consecutive h whose")
    lines.append(f"  local slopes agree within max({orderfit.SLOPE_TOL_ABS:g}, {orderfit.SLOPE_TOL_REL:g} p):")
    for name, fit in study["fits"].items():
        lines.append(f"  order {name:<20s} {fit.describe()}")
    return "\n".join(lines)


def write_csv(study, path):
    """Write the study's rows as CSV (approximant, knob value, windows, h, error, the run's
    error estimate (empty without one), time, whether at the reference's floor and in the
    fit, the fitted order and its standard error, the reference's error).

    Parameters
    ----------
    study : dict
        From :func:`run_study`.
    path : str or Path
    """
    import csv

    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["approximant", study["knob"], "windows", "mean_h", "error", "error_estimate", "time_s",
                    "at_floor", "in_fit", "fitted_order", "order_stderr", "reference_error", "note"])
        for r in study["rows"]:
            fit = study["fits"][r["approximant"]]
            est = "" if r["estimate"] is None else repr(r["estimate"])
            w.writerow([r["approximant"], repr(r["value"]), r["windows"], repr(r["h"]), repr(r["error"]), est,
                        repr(r["time_s"]), int(r.get("floor", False)), int(r.get("fitted", False)),
                        repr(fit.order), repr(fit.stderr), repr(study["ref_error"]), r["note"]])


def plot_study(study, path):
    """Save error against h (log-log; points at the reference's floor hollow, the floor
    dotted) and error against time (at the middle knob value).

    Parameters
    ----------
    study : dict
        From :func:`run_study`.
    path : str or Path
        PNG file.

    Raises
    ------
    ImportError
        If matplotlib is not installed.
    """
    import matplotlib

    matplotlib.use("Agg")  # files only: no display needed, none assumed
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for name, fit in study["fits"].items():
        rs = [r for r in study["rows"] if r["approximant"] == name and not r["note"]]
        if not rs:
            continue
        lab = f"{name} (p={fit.order:.2f})" if math.isfinite(fit.order) else name
        line, = ax1.loglog([r["h"] for r in rs], [max(r["error"], 1e-17) for r in rs], "o-", label=lab)
        fl = [r for r in rs if r.get("floor")]
        if fl:  # floor points hollow: not fitted
            ax1.loglog([r["h"] for r in fl], [max(r["error"], 1e-17) for r in fl], "o", mfc="white",
                       color=line.get_color())
    ax1.axhline(orderfit.FLOOR_FACTOR * study["ref_error"], color="0.6", ls=":", lw=1,
                label=f"{orderfit.FLOOR_FACTOR:g}x the reference's error")
    ax1.set_xlabel("mean window h" + (" (= tau)" if study["knob"] == "tau" else ""))
    ax1.set_ylabel(r"max $|\theta-\theta_{ref}|$")
    ax1.set_title(f"error against window length ({study['knob']} sweep)")
    ax1.legend(fontsize=8)
    for name, (v, e) in study["curves"].items():
        ax2.semilogy(study["t"], np.maximum(e, 1e-17), lw=1, label=f"{name}, {study['knob']}={v:g}")
    ax2.set_xlabel("t")
    ax2.set_ylabel(r"$|\theta-\theta_{ref}|$")
    ax2.set_title("error against time")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
