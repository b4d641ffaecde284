"""β, γ and θ₀ from a noisy measured trajectory: the Jacobian from the sensitivities
=================================================================================

A damped, torqued pendulum θ'' + βθ' + sin θ = γ (true β = 0.15, γ = 0.35, started at
rest from θ₀ = 1) is "measured": θ at 81 times over [0, 40] with 0.01 rad of Gaussian
noise.  β, γ and θ₀ are fitted with :func:`scipy.optimize.least_squares`, residuals =
model θ − data, twice:

* with ``jac=`` from the run's own sensitivities: ``mbm.solve(..., sensitivities=("beta",
  "gamma", "theta0"))`` gives ∂(θ, θ')/∂(β, γ, θ₀) at every output, and its θ row is the
  Jacobian of the residuals, exact to the run's tolerance;
* with scipy's default finite-difference Jacobian (``'2-point'``): one more run per
  parameter for every Jacobian, each differencing two runs a step of ~1.5e-8 apart.

Both fits print their values with standard errors (cov = σ̂² (JᵀJ)⁻¹, J at the
solution, σ̂² the residuals' sum of squares over 81 − 3), the number of calls of the
residual and Jacobian functions (each call one :func:`mbm.solve`) and the wall time of
the fit (after a warm-up run, best of a few repeats); then what one run costs plain and
with the sensitivities, and how far the finite differences are from the sensitivities.
Both fits reach the same minimum in as many iterations: the sensitivities halve the runs
(a Jacobian is one run, not one per parameter), though a run with them costs about three
plain ones, so on this small problem the two fits take about the same time.

Usage::

    python fit_trajectory.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import os
import sys
import time
from pathlib import Path

import matplotlib
import numpy as np
from scipy.optimize import least_squares

import mbm

matplotlib.use("Agg")  # the figure goes to a PNG file: no display needed
import matplotlib.pyplot as plt  # noqa: E402

# The fitted parameters, in the order of the fit's vector, with their true values.
NAMES = ("beta", "gamma", "theta0")
TRUE = np.array([0.15, 0.35, 1.0])
# The start of both fits: β twice the truth, γ and θ₀ well off.
START = np.array([0.3, 0.2, 0.7])
# The pendulum starts at rest; the measurement: 81 samples of θ over [0, 40].
V0 = 0.0
T = np.linspace(0.0, 40.0, 81)
# The noise of the measurement (rad, one σ) and the generator's seed.
NOISE = 0.01
SEED = 51
# Tolerances of every run of the fits.
TOL = 1e-10


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def run(p, t=T, sensitivities=None):
    """The pendulum of parameters ``p`` = (β, γ, θ₀), started at rest, at the times ``t``."""
    beta, gamma, theta0 = p
    return mbm.solve(mbm.Pendulum(beta, gamma), (0.0, float(t[-1])), [theta0, V0], t_eval=t,
                     rtol=TOL, atol=TOL, sensitivities=sensitivities)


def measure(noise=NOISE, seed=SEED):
    """The "measured" θ at the times ``T``: the true trajectory plus Gaussian noise."""
    rng = np.random.default_rng(seed)
    return run(TRUE).y[0] + rng.normal(0.0, noise, T.size)


def fit(data, jacobian="sensitivities", start=START):
    """Fit (β, γ, θ₀) to ``data`` (θ at the times ``T``) by least squares.

    ``jacobian``: ``"sensitivities"`` (the run's ∂θ/∂(β, γ, θ₀)) or ``"2-point"``
    (scipy's forward differences).  Returns a dict: the fitted ``value``, its standard
    errors ``err``, the noise ``sigma`` estimated from the residuals, the ``residuals``
    (model − data), the calls of the residual and Jacobian functions (``n_residual``,
    ``n_jacobian``; each one mbm.solve) and scipy's result ``result``.
    """
    calls = {"residual": 0, "jacobian": 0}

    def residuals(p):
        calls["residual"] += 1
        return run(p).y[0] - data

    def jac(p):
        calls["jacobian"] += 1
        return run(p, sensitivities=NAMES).sensitivities[:, 0, :].T  # (samples, parameters)

    result = least_squares(residuals, start, jac=jac if jacobian == "sensitivities" else jacobian)
    if not result.success:
        raise RuntimeError(f"the {jacobian} fit failed: {result.message}")
    dof = data.size - start.size
    sigma = np.sqrt(2.0 * result.cost / dof)  # result.cost = sum(residuals**2) / 2
    cov = sigma**2 * np.linalg.inv(result.jac.T @ result.jac)
    return {"value": result.x, "err": np.sqrt(np.diag(cov)), "sigma": sigma, "residuals": result.fun,
            "n_residual": calls["residual"], "n_jacobian": calls["jacobian"], "result": result}


def timed_fit(data, jacobian, repeats=3):
    """:func:`fit` and its best wall time (s) over ``repeats`` runs (the runs are compiled by then)."""
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        f = fit(data, jacobian)
        best = min(best, time.perf_counter() - t0)
    f["time"] = best
    return f


def _seconds(call):
    t0 = time.perf_counter()
    call()
    return time.perf_counter() - t0


def main(out=None, repeats=10):
    """Measure, fit both ways, print the table and save ``fit_trajectory.png``; returns (fits, path)."""
    data = measure()
    run(START, sensitivities=NAMES)  # warm-up: compile (or load) the kernels before timing
    fits = {j: timed_fit(data, j, repeats) for j in ("sensitivities", "2-point")}

    head = "".join(f"{n:>19s}" for n in NAMES)
    print(f"{'Jacobian':13s}{head}  {'residual calls':>14s}  {'Jacobian calls':>14s}  {'time (ms)':>9s}")
    for j, f in fits.items():
        cols = "".join(f" {v:8.5f} ± {e:7.5f}" for v, e in zip(f["value"], f["err"]))
        print(f"{j:13s}{cols}  {f['n_residual']:>14d}  {f['n_jacobian']:>14d}  {f['time'] * 1e3:>9.1f}")
    print(f"{'truth':13s}" + "".join(f" {v:8.5f}{'':10s}" for v in TRUE).rstrip())
    for j, f in fits.items():
        off = np.abs(f["value"] - TRUE) / f["err"]
        print(f"{j}: " + ", ".join(f"{n} {o:.1f} sigma off" for n, o in zip(NAMES, off))
              + f"; noise from the residuals {f['sigma']:.4f} rad (true {NOISE})")
    # What one call of each function costs, and how far the differences are from the
    # sensitivities at the finite-difference fit's solution.
    fd = fits["2-point"]
    plain = min(_seconds(lambda: run(fd["value"])) for _ in range(20))
    sens = min(_seconds(lambda: run(fd["value"], sensitivities=NAMES)) for _ in range(20))
    exact = run(fd["value"], sensitivities=NAMES).sensitivities[:, 0, :].T
    off = np.max(np.abs(fd["result"].jac - exact)) / np.max(np.abs(exact))
    print(f"one run: {plain * 1e3:.2f} ms plain, {sens * 1e3:.2f} ms with the sensitivities; "
          f"the 2-point Jacobian is off the sensitivities by {off:.1e} of its scale")

    best = fits["sensitivities"]
    dense = np.linspace(T[0], T[-1], 801)
    fig, (ax, res) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, height_ratios=(3, 1))
    ax.plot(T, data, "o", ms=3.5, label=f"measured (σ = {NOISE} rad)")
    ax.plot(dense, run(TRUE, dense).y[0], "-", color="0.5", lw=2.5, alpha=0.6,
            label=r"truth: $\beta$ = {:.2f}, $\gamma$ = {:.2f}, $\theta_0$ = {:.2f}".format(*TRUE))
    b, g, th = best["value"]
    ax.plot(dense, run(best["value"], dense).y[0], "C1-", lw=1,
            label=rf"fit: $\beta$ = {b:.4f}, $\gamma$ = {g:.4f}, $\theta_0$ = {th:.4f}")
    ax.axhline(np.arcsin(TRUE[1]), color="0.5", ls=":", lw=1, label=r"equilibrium $\arcsin\gamma$")
    ax.set(ylabel=r"$\theta$ (rad)",
           title=r"Fitting $\beta$, $\gamma$, $\theta_0$ to a noisy damped, torqued pendulum")
    ax.legend(fontsize=8)
    res.axhspan(-NOISE, NOISE, color="0.9")
    res.axhline(0.0, color="0.5", lw=0.8)
    res.plot(T, -best["residuals"], "o", ms=3.5)
    res.set(xlabel="t", ylabel="data − fit (rad)")
    fig.tight_layout()
    path = out_dir(out) / "fit_trajectory.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return fits, path


if __name__ == "__main__":
    fits, png = main(sys.argv[1] if len(sys.argv) > 1 else None)
    print("wrote", png)
