"""Convergence orders: error against τ for the convergent families, fitted orders
===============================================================================

The figure of the convergence study behind ``docs/convergent.md``, on one scene:
fixed-window runs of classical RK4, two splittings and two Taylor degrees on the second
paper's Example 1 (θ'' + 0.1θ' + sin θ = 0.3, θ₀ = 30°, 0 ≤ t ≤ 80), their largest
error over the integer times against an exact-arithmetic reference computed here (a
Taylor integrator in 128-bit fixed-point integers, ~1e-25, independent of mbm's
kernels; its error as measured against heyoka in long double, ~1e-19, is that check's
own floor), for τ from 4 down to where the error reaches mbm's own round-off.

Each family's order is fitted by the study's rule (:mod:`mbm.cli.orderfit`, as
``mbm study``): points within 10× the reference's own error (measured against heyoka
in long double, or mbm at its tightest tolerance without heyoka) are at its floor, and
points outside the study's fit band are not fitted; the order is the least-squares
slope over the asymptotic range, with its standard error.  Filled markers are the
fitted points, hollow ones the rest.

Usage::

    python convergence_orders.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import math
import os
import sys
from fractions import Fraction
from pathlib import Path

import matplotlib
import numpy as np

import mbm
import mbm.scenes
from mbm.cli import orderfit
from mbm.cli import study as cli_study

matplotlib.use("Agg")  # the figure goes to a PNG file: no display needed
import matplotlib.pyplot as plt  # noqa: E402

# The scene: the second paper's Example 1, the first row of docs/convergent.md.
SCENE = "ex1"
T_END = 80
# A classical baseline, a 4th- and a 6th-order splitting, two Taylor degrees.
METHODS = ("rk4", "split4", "split6", "taylor8", "taylor16")
# The window lengths, coarse to fine (fractions p/q: q windows span p time units).
TAUS = tuple(Fraction(x) for x in ("4", "3", "5/2", "2", "3/2", "5/4", "1", "4/5", "2/3", "4/7", "1/2",
                                   "2/5", "1/3", "2/7", "1/4", "1/5", "1/6", "1/8", "1/10", "1/12", "1/16",
                                   "1/20", "1/24", "1/32", "1/40", "1/48", "1/64", "1/96", "1/128",
                                   "1/192", "1/256"))
# Errors inside this band can be in the asymptotic regime: above mbm's own round-off
# (1e-12 to 1e-10) and below 1e-3, above which the error stops following C τ^p.
FIT_BAND = (1e-11, 1e-3)
# Every method here converges at least linearly: a local slope below 1 is a plateau.
MIN_SLOPE = 1.0
# The reference: 2^-128 per operation, Taylor degree 28 with step 1/16.
BITS, REF_DEGREE, REF_STEP = 128, 28, Fraction(1, 16)


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def reference(beta, gamma, omega, theta0, v0, t_end, h=REF_STEP, degree=REF_DEGREE):
    """(θ_hi, θ_lo, θ'_hi, θ'_lo) at t = 0, 1, …, t_end: the state to ~1e-25 as double-doubles.

    A Taylor integrator in fixed-point integers (every number scaled by 2^BITS).  With
    s = sin θ and c = cos θ carried along (s' = cθ', c' = −sθ'), the scaled Taylor
    coefficients A_k = a_k h^k of θ, S_k of s and C_k of c over one step follow from

        (k+1)(k+2) A_{k+2} = γh² δ_{k0} − βh (k+1) A_{k+1} − ω²h² S_k,
        m S_m = Σ_j j A_j C_{m−j},   m C_m = −Σ_j j A_j S_{m−j},

    and the step sums them: θ(h) = Σ A_k, hθ'(h) = Σ k A_k, s(h) = Σ S_k, c(h) = Σ C_k.
    """
    one = 1 << BITS

    def fix(x):  # an exact binary float or a Fraction, to fixed point
        return round(Fraction(x) * one)

    def hi_lo(x):  # fixed point to a double-double
        f = Fraction(x, one)
        return float(f), float(f - Fraction(float(f)))

    # sin θ₀ and cos θ₀ of the binary θ₀: their series, in exact fractions.
    terms = [Fraction(1)]
    for n in range(1, 60):
        terms.append(terms[-1] * Fraction(theta0) / n)  # θ₀^n / n!
    sin0 = sum((-1) ** (n // 2) * t for n, t in enumerate(terms) if n % 2)
    cos0 = sum((-1) ** (n // 2) * t for n, t in enumerate(terms) if not n % 2)

    H, bh, gh2, wh2 = fix(h), fix(Fraction(beta) * h), fix(Fraction(gamma) * h * h), fix(Fraction(omega) ** 2 * h * h)
    X, V, SIN, COS = fix(theta0), fix(v0), fix(sin0), fix(cos0)
    out = [hi_lo(X) + hi_lo(V)]
    for _ in range(t_end):
        for _ in range(int(1 / h)):
            A, S, C = [X, (V * H) >> BITS], [SIN], [COS]
            for k in range(degree):
                A.append(((gh2 if k == 0 else 0) - ((bh * (k + 1) * A[k + 1] + wh2 * S[k]) >> BITS))
                         // ((k + 1) * (k + 2)))
                m = k + 1
                S.append((sum(j * A[j] * C[m - j] for j in range(1, m + 1)) >> BITS) // m)
                C.append(-(sum(j * A[j] * S[m - j] for j in range(1, m + 1)) >> BITS) // m)
            X, V, SIN, COS = sum(A), (sum(k * a for k, a in enumerate(A)) << BITS) // H, sum(S), sum(C)
        out.append(hi_lo(X) + hi_lo(V))
    return np.array(out)


def rk4_run(beta, gamma, omega, theta0, v0, tau, n, every):
    """Classical RK4 with fixed step τ: the states every ``every`` steps (n steps)."""
    def f(th, v):
        return v, gamma - beta * v - omega * omega * math.sin(th)

    th, v = theta0, v0
    out = [(th, v)]
    for i in range(1, n + 1):
        k1 = f(th, v)
        k2 = f(th + 0.5 * tau * k1[0], v + 0.5 * tau * k1[1])
        k3 = f(th + 0.5 * tau * k2[0], v + 0.5 * tau * k2[1])
        k4 = f(th + tau * k3[0], v + tau * k3[1])
        th = th + tau / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0])
        v = v + tau / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1])
        if i % every == 0:
            out.append((th, v))
    return np.array(out)


def run_method(method, scene, tau, t_end=T_END):
    """Fixed windows τ = p/q of ``method`` ("rk4" or an mbm approximant): the states at
    t = 0, p, 2p, … ≤ t_end (NaN after a failure)."""
    beta, gamma, omega, theta0, v0 = mbm.scenes.get(scene).params()[:5]
    p, q = tau.numerator, tau.denominator
    m = t_end // p
    if method == "rk4":
        return rk4_run(beta, gamma, omega, theta0, v0, float(tau), q * m, q)
    t = np.arange(m + 1) * float(p)
    r = mbm.solve(mbm.Pendulum(beta, gamma, omega), (0.0, t[-1]), [theta0, v0], tau=float(tau),
                  approximant=method, t_eval=t)
    out = np.full((m + 1, 2), np.nan)
    out[: r.t.size] = r.y.T
    return out


def max_error(run, ref, tau):
    """max over the sample times of max(|Δθ|, |Δθ'|) against the reference."""
    r = ref[:: tau.numerator][: run.shape[0]]
    if not np.all(np.isfinite(run)):
        return math.inf
    return float(max(np.max(np.abs((run[:, 0] - r[:, 0]) - r[:, 1])),
                     np.max(np.abs((run[:, 1] - r[:, 2]) - r[:, 3]))))


def sweep(method, scene, ref, stop_below=FIT_BAND[0], taus=TAUS):
    """Errors for τ in ``taus`` (descending), until two in a row are ≤ stop_below or the
    error has stopped decreasing twice (mbm's round-off)."""
    out, below, rising, prev = {}, 0, 0, math.inf
    for tau in taus:
        e = out[tau] = max_error(run_method(method, scene, tau), ref, tau)
        below = below + 1 if e <= stop_below else 0
        rising = rising + 1 if (e >= prev and e < 1e-3) else 0
        prev = min(prev, e)
        if below >= 2 or rising >= 2:
            break
    return out


def reference_error(scene, ref):
    """The reference's own error: max(|Δθ|, |Δθ'|) against heyoka in long double, or
    against mbm at its tightest tolerance without heyoka (as ``mbm study``)."""
    beta, gamma, omega, theta0, v0 = mbm.scenes.get(scene).params()[:5]
    model, t = mbm.Pendulum(beta, gamma, omega), np.arange(ref.shape[0], dtype=float)
    if cli_study.heyoka_ld_available():
        chk, ld = cli_study.heyoka_ld_states(model, [theta0, v0], t), np.longdouble
    else:
        chk, ld = mbm.solve(model, (0.0, t[-1]), [theta0, v0], rtol=cli_study.TIGHT_TOL,
                            atol=cli_study.TIGHT_TOL, t_eval=t).y.T, float
    dth = (chk[:, 0] - ref[:, 0].astype(ld)) - ref[:, 1].astype(ld)
    dv = (chk[:, 1] - ref[:, 2].astype(ld)) - ref[:, 3].astype(ld)
    return float(max(np.max(np.abs(dth)), np.max(np.abs(dv))))


def compute(scene=SCENE, methods=METHODS):
    """The τ sweeps and fitted orders behind the figure.

    Parameters
    ----------
    scene : str, optional
        A scene of :mod:`mbm.scenes`.
    methods : sequence of str, optional
        ``"rk4"``, a splitting or a Taylor degree (an mbm approximant).

    Returns
    -------
    dict
        ``ref_error`` (the reference's own error) and ``curves``: method ->
        dict with ``tau``, ``error`` (lists, τ ascending), ``fit``
        (:class:`mbm.cli.orderfit.OrderFit`).
    """
    ref = reference(*mbm.scenes.get(scene).params()[:5], T_END)
    ref_error = reference_error(scene, ref)
    curves = {}
    for meth in methods:
        errs = sweep(meth, scene, ref)
        taus = sorted(errs)
        tau = [float(t) for t in taus]
        error = [errs[t] for t in taus]
        fit = orderfit.fit_order(tau, error, ref_error, ceil=FIT_BAND[1], err_min=FIT_BAND[0],
                                 min_slope=MIN_SLOPE)
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
    bottom = FIT_BAND[0] * 1e-2
    floor = orderfit.FLOOR_FACTOR * data["ref_error"]
    if floor > bottom:  # else far below the axis (the fixed-point reference: ~1e-19)
        ax.axhline(floor, color="0.4", ls="--", lw=1, label="10× the reference's error")
    ax.axhspan(bottom, FIT_BAND[0], color="0.9", zorder=0)
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
    d, png = main(sys.argv[1] if len(sys.argv) > 1 else None)
    print(f"reference's error: {d['ref_error']:.1e}")
    for m, c in d["curves"].items():
        print(f"{m}: p = {c['fit'].describe()}")
    print("wrote", png)
