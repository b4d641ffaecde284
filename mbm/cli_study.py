"""Step-size and accuracy studies behind ``mbm study`` (and ``examples/step_size_study.py``).

A study runs the moving boundary method on one scene for several approximants over a
sweep of the window length τ (or of rtol), measures ``max |θ − θ_ref|`` against CVODE
at the output times, and fits the order p of ``error ≈ C h^p`` with h the mean
window length.
"""

import math
import time

import numpy as np

from . import scenes

__all__ = ["SCENES", "integrate", "run_study", "fit_order", "format_table", "write_csv", "plot_study"]

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
# reference's accuracy (~1e-12) is reached.
DEFAULT_TAUS = (1.0, 0.5, 0.25, 0.125, 0.0625)
# Default rtol sweep (rtol = atol): three decades per point pair.
DEFAULT_RTOLS = (1e-3, 1e-5, 1e-7, 1e-9)
# Errors below this are at the reference's own accuracy (CVODE at 1e-13 is good to
# ~1e-12 on these scenes) and would flatten the fitted slope.
ERR_FLOOR = 1e-11
# Errors above this are pre-asymptotic (the formula is not yet in its convergent regime).
ERR_CEIL = 1e-1
# CVODE tolerances of the reference: as tight as it goes without stalling.
REF_TOL = 1e-13


def _compiled(name):
    """Whether ``mbm.solve`` (the compiled path) runs approximant ``name``."""
    from . import loop
    from .approximants import get_approximant

    return name == "auto" or loop.kind_of(get_approximant(name)) is not None


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
    from . import fast
    from .solver import MBM

    from .approximants import get_approximant

    if tau is None and approximant != "auto":
        ap = get_approximant(approximant)
        if not ap.exact and ap.error_kernel is None:
            # solve_ivp would only warn and pick windows unrelated to rtol; the compiled
            # path refuses.  Refuse on both paths so the CLI's answer does not depend on it.
            raise ValueError(f"approximant {ap.name!r} has no error estimate: pass tau")
    if _compiled(approximant):
        sol = fast.solve(model, t_span, y0, tau=tau, rtol=rtol, atol=atol,
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


def fit_order(h, err):
    """Least-squares slope of log(err) against log(h), over the asymptotic points.

    Parameters
    ----------
    h, err : array_like
        Mean window lengths and errors; points with err outside
        (:data:`ERR_FLOOR`, :data:`ERR_CEIL`) or non-finite are left out.

    Returns
    -------
    float
        The fitted order p of err ≈ C h^p, NaN with fewer than two usable points
        or a single distinct h.
    """
    h = np.asarray(h, dtype=float)
    err = np.asarray(err, dtype=float)
    ok = np.isfinite(h) & np.isfinite(err) & (err > ERR_FLOOR) & (err < ERR_CEIL) & (h > 0)
    if ok.sum() < 2 or np.unique(h[ok]).size < 2:
        return float("nan")
    return float(np.polyfit(np.log(h[ok]), np.log(err[ok]), 1)[0])


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
        ``knob`` ("tau" or "rtol"), ``values``, ``t``, ``ref`` (θ_ref at t),
        ``rows`` (list of dicts: approximant, value, windows, h, error, time_s, note),
        ``orders`` ({approximant: fitted order}), ``n_fit`` ({approximant: points in
        the fit}), ``scene`` and ``curves``
        ({approximant: (value, |θ − θ_ref| at t)} at the middle knob value).
    """
    from .cli_progress import Progress
    from .problem import Pendulum
    from .references import reference

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
    ref = reference(model, (0.0, t_end), [th0, v0], t_eval=t, rtol=REF_TOL, atol=REF_TOL).y[0]
    rows, curves = [], {}
    mid = values[len(values) // 2]
    bar = Progress(len(values) * len(approximants), "study", enabled=None if show_progress else False)
    with bar:
        for name in approximants:
            for v in values:
                kw = {"tau": v} if knob == "tau" else {"rtol": v, "atol": v}
                row = dict(approximant=name, value=v, windows=0, h=float("nan"),
                           error=float("nan"), time_s=float("nan"), note="")
                try:
                    if v == values[0]:
                        # Untimed first run: numba compilation or cache loading is not
                        # the cost of a window and would swamp the first row's time.
                        integrate(model, (0.0, t_end), [th0, v0], t, approximant=name, **kw)
                    c = time.perf_counter()
                    y, n_w = integrate(model, (0.0, t_end), [th0, v0], t, approximant=name, **kw)
                    row["time_s"] = time.perf_counter() - c
                    e = np.abs(y[0] - ref)
                    row.update(windows=n_w, h=t_end / max(n_w, 1), error=float(np.max(e)))
                    if v == mid:
                        curves[name] = (v, e)
                except (ValueError, RuntimeError, ArithmeticError) as exc:
                    # A domain error or an option the approximant rejects is a result of
                    # the study (e.g. no error estimate for an rtol sweep), not a crash.
                    row["note"] = str(exc).split("\n")[0][:120]
                rows.append(row)
                bar.update()
    orders = {
        name: fit_order([r["h"] for r in rows if r["approximant"] == name],
                        [r["error"] for r in rows if r["approximant"] == name])
        for name in approximants
    }
    # How many points each fit used: a slope from two points deserves less trust.
    n_fit = {
        name: int(sum(1 for r in rows if r["approximant"] == name and np.isfinite(r["error"])
                      and ERR_FLOOR < r["error"] < ERR_CEIL))
        for name in approximants
    }
    return dict(knob=knob, values=values, t=t, ref=ref, rows=rows, orders=orders, n_fit=n_fit, curves=curves,
                scene=(beta, gamma, omega, th0, v0, t_end))


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
    lines = [
        f"scene: beta={beta:g} gamma={gamma:g} omega={omega:g} theta0={th0:.6g} rad "
        f"v0={v0:g} 0<=t<={t_end:g}; error = max|theta - theta_ref| over {study['t'].size} times "
        f"(CVODE {REF_TOL:g})",
        f"{'approximant':<20s} {knob:>9s} {'windows':>8s} {'mean h':>9s} {'error':>10s} {'time ms':>9s}",
    ]
    for r in study["rows"]:
        if r["note"]:
            lines.append(f"{r['approximant']:<20s} {r['value']:9.3g} {'-':>8s} {'-':>9s} "
                         f"{'failed':>10s}   {r['note']}")
        else:
            lines.append(f"{r['approximant']:<20s} {r['value']:9.3g} {r['windows']:8d} {r['h']:9.3g} "
                         f"{r['error']:10.2e} {r['time_s'] * 1e3:9.2f}")
    lines.append("")
    lines.append(f"fitted order p of error ~ C h^p (h = mean window; errors in ({ERR_FLOOR:g}, {ERR_CEIL:g})):")
    for name, p in study["orders"].items():
        n = study.get("n_fit", {}).get(name)
        txt = (f"{p:.2f}" + (f"  (fit over {n} points)" if n is not None else "")
               if math.isfinite(p) else "n/a (fewer than two points in range)")
        lines.append(f"  order {name:<20s} {txt}")
    return "\n".join(lines)


def write_csv(study, path):
    """Write the study's rows as CSV (approximant, knob value, windows, h, error, time, order).

    Parameters
    ----------
    study : dict
        From :func:`run_study`.
    path : str or Path
    """
    import csv

    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["approximant", study["knob"], "windows", "mean_h", "error", "time_s", "fitted_order", "note"])
        for r in study["rows"]:
            w.writerow([r["approximant"], repr(r["value"]), r["windows"], repr(r["h"]), repr(r["error"]),
                        repr(r["time_s"]), repr(study["orders"][r["approximant"]]), r["note"]])


def plot_study(study, path):
    """Save error against h (log-log) and error against time (at the middle knob value).

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
    for name, p in study["orders"].items():
        rs = [r for r in study["rows"] if r["approximant"] == name and not r["note"]]
        if not rs:
            continue
        lab = f"{name} (p={p:.2f})" if math.isfinite(p) else name
        ax1.loglog([r["h"] for r in rs], [max(r["error"], 1e-17) for r in rs], "o-", label=lab)
    ax1.axhline(ERR_FLOOR, color="0.6", ls=":", lw=1)
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
