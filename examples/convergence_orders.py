"""Convergence orders: error against τ for the convergent families, fitted orders
===============================================================================

The figure of the convergence study behind ``docs/convergent.md``
(``examples/convergence_study.py``), on one scene: fixed-window runs of classical RK4,
two splittings and two Taylor degrees on the second paper's Example 1 (0 ≤ t ≤ 80),
their largest error over the integer times against the fixed-point reference of
``tests/data/convergent_reference.npz`` (~1e-25, independent of mbm's kernels; its
error as measured against heyoka in long double, ~1e-19, is that check's own floor), for
τ from 4 down to where the error reaches mbm's own round-off.

Each family's order is fitted by the study's rule (:mod:`mbm.cli.orderfit`, as
``mbm study``): points within 10× the reference's own error (measured against heyoka
in long double, or mbm at its tightest tolerance without heyoka) are at its floor, and
points outside the study's fit band are not fitted; the order is the least-squares
slope over the asymptotic range, with its standard error.  Filled markers are the
fitted points, hollow ones the rest.

Usage::

    python examples/convergence_orders.py [OUT_DIR]      # or set MBM_EXAMPLES_OUT
"""

from _common import cli_out, out_dir, pyplot

import convergence_study as study

# The scene: the second paper's Example 1, the first row of docs/convergent.md.
SCENE = "ex1"
# A classical baseline, a 4th- and a 6th-order splitting, two Taylor degrees.
METHODS = ("rk4", "split4", "split6", "taylor8", "taylor16")


def compute(scene=SCENE, methods=METHODS):
    """The τ sweeps and fitted orders behind the figure.

    Parameters
    ----------
    scene : str, optional
        A scene of ``convergence_study.SCENES``.
    methods : sequence of str, optional
        ``"rk4"``, a splitting or a Taylor degree, as ``convergence_study.run_method``.

    Returns
    -------
    dict
        ``ref_error`` (the reference's own error) and ``curves``: method ->
        dict with ``tau``, ``error`` (arrays, τ ascending), ``fit``
        (:class:`mbm.cli.orderfit.OrderFit`).
    """
    ref = study.load_reference()
    ref_error = study.reference_error(scene, ref)
    curves = {}
    for meth in methods:
        errs = study.sweep(meth, scene, ref)
        taus = sorted(errs)
        tau = [float(t) for t in taus]
        error = [errs[t] for t in taus]
        fit = study.orderfit.fit_order(tau, error, ref_error, ceil=study.FIT_BAND[1], err_min=study.FIT_BAND[0],
                                       min_slope=study.MIN_SLOPE)
        curves[meth] = {"tau": tau, "error": error, "fit": fit}
    return {"scene": scene, "ref_error": ref_error, "curves": curves}


def plot(data, path):
    """Error against τ on log axes, one line per family, and the reference's floor.

    Parameters
    ----------
    data : dict
        As :func:`compute`.
    path : str or Path
        The PNG to write.
    """
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.8))
    for meth, c in data["curves"].items():
        fit = c["fit"]
        if fit.n > 2:
            label = f"{meth}: p = {fit.order:.2f} ± {fit.stderr:.1g} ({fit.n} points)"
        elif fit.n == 2:
            label = f"{meth}: p ≈ {fit.order:.2f} (2 points, no uncertainty)"
        else:
            label = f"{meth}: no fit"
        (line,) = ax.loglog(c["tau"], c["error"], "-", lw=1, label=label)
        used = list(fit.used)
        ax.loglog([t for t, u in zip(c["tau"], used) if u], [e for e, u in zip(c["error"], used) if u],
                  "o", color=line.get_color(), ms=5)
        ax.loglog([t for t, u in zip(c["tau"], used) if not u], [e for e, u in zip(c["error"], used) if not u],
                  "o", mfc="none", color=line.get_color(), ms=5)
    bottom = study.FIT_BAND[0] * 1e-2
    floor = study.orderfit.FLOOR_FACTOR * data["ref_error"]
    if floor > bottom:  # else far below the axis (the fixed-point reference: ~1e-19)
        ax.axhline(floor, color="0.4", ls="--", lw=1, label="10× the reference's error")
    ax.axhspan(bottom, study.FIT_BAND[0], color="0.9", zorder=0)
    ax.set_ylim(bottom=bottom)
    ax.set_xlabel("window length τ")
    ax.set_ylabel("max error over t = 0, 1, …, 80")
    ax.set_title(f"Convergence on {data['scene']}: filled points fitted; reference's error "
                 f"{data['ref_error']:.0e}; shaded: mbm's round-off", fontsize=9)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(out=None, scene=SCENE, methods=METHODS):
    """Run the sweeps, print the fitted orders and save ``convergence_orders.png``.

    Parameters
    ----------
    out : str or Path, optional
        Output directory.
    scene : str, optional
    methods : sequence of str, optional

    Returns
    -------
    (dict, Path)
        The data of :func:`compute` and the PNG written.
    """
    data = compute(scene, methods)
    path = out_dir(out) / "convergence_orders.png"
    plot(data, path)
    return data, path


if __name__ == "__main__":
    d, png = main(cli_out())
    print(f"reference's error: {d['ref_error']:.1e}")
    for m, c in d["curves"].items():
        print(f"{m}: p = {c['fit'].describe()}")
    print("wrote", png)
