"""β from a measured I–V curve: a least-squares fit with uncertainties
===================================================================

A junction of I_c = 10 µA, R = 10 Ω and C = 1 pF (β_c = 3.04, β = 1/√β_c = 0.574) is
"measured": its I–V curve swept down from 25 µA by :func:`mbm.iv_curve` (the running
branch, down to the retrapping current, then zero voltage), converted to volts by
:class:`mbm.Junction`, with 0.3 µV of Gaussian noise added.  :func:`mbm.fit_iv` fits
β, I_c and R to the running points (the zero-voltage ones carry no information on its
shape and are left out) and states their standard errors; the fitted β is compared
with the truth.

Usage::

    python fit_iv_curve.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import os
import sys
from pathlib import Path

import matplotlib
import numpy as np

import mbm

matplotlib.use("Agg")  # the figure goes to a PNG file: no display needed
import matplotlib.pyplot as plt  # noqa: E402

# The "measured" junction: 10 µA, 10 Ω, 1 pF.
TRUE = mbm.Junction(I_c=10e-6, R=10.0, C=1e-12)
# The down sweep: 25 µA to 3 µA (the retrapping current is ≈ 6.7 µA).
CURRENTS = np.linspace(25e-6, 3e-6, 23)
# The voltmeter's noise (V, one σ) and the generator's seed.
NOISE = 0.3e-6
SEED = 2026


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def measure(junction=TRUE, currents=CURRENTS, noise=NOISE, seed=SEED):
    """A noisy down sweep of ``junction``'s I–V curve: (current in A, voltage in V).

    Started running (θ' above the top speed γ/β of the running cycle), each bias point
    from the state the previous one ended in, as a measurement sweeps the bias.
    """
    gamma = junction.gamma(currents)
    curve = mbm.iv_curve(junction.beta, gamma, theta_dot0=gamma[0] / junction.beta + 1.0)
    rng = np.random.default_rng(seed)
    return currents, junction.voltage(curve.mean_velocity) + rng.normal(0.0, noise, currents.size)


def model_curve(junction, currents):
    """The running branch of ``junction`` swept down over ``currents`` (A): volts."""
    gamma = junction.gamma(currents)
    curve = mbm.iv_curve(junction.beta, gamma, theta_dot0=gamma[0] / junction.beta + 1.0)
    return junction.voltage(curve.mean_velocity)


def main(out=None):
    """Measure, fit, print the fitted parameters and save ``fit_iv_curve.png``; returns (fit, path)."""
    current, voltage = measure()
    fit = mbm.fit_iv(current, voltage, beta0=0.4)
    for name, value, err, truth in (("beta", fit.beta, fit.beta_err, TRUE.beta),
                                    ("beta_c", fit.beta_c, fit.beta_c_err, TRUE.beta_c),
                                    ("I_c (uA)", fit.I_c * 1e6, fit.I_c_err * 1e6, TRUE.I_c * 1e6),
                                    ("R (Ohm)", fit.R, fit.R_err, TRUE.R)):
        print(f"{name:9s} = {value:.4f} +/- {err:.4f}   (true {truth:.4f}: "
              f"{abs(value - truth) / err:.1f} sigma off)")
    print(f"noise estimated from the residuals: {fit.sigma * 1e6:.2f} uV (true {NOISE * 1e6:.2f} uV)")

    dense = np.linspace(current[0], current[-1], 81)
    fig, (ax, res) = plt.subplots(2, 1, figsize=(7, 6), sharex=True, height_ratios=(3, 1))
    ax.errorbar(current[fit.fitted] * 1e6, voltage[fit.fitted] * 1e6, yerr=NOISE * 1e6, fmt="o", ms=4,
                label="measured (fitted)")
    ax.plot(current[~fit.fitted] * 1e6, voltage[~fit.fitted] * 1e6, "o", mfc="none", color="C0",
            label="measured (zero voltage: not fitted)")
    ax.plot(dense * 1e6, model_curve(fit.junction, dense) * 1e6, "C1-",
            label=rf"fit: $\beta$ = {fit.beta:.3f} ± {fit.beta_err:.3f}, $I_c$ = {fit.I_c * 1e6:.2f} µA, "
                  rf"$R$ = {fit.R:.3f} Ω")
    ax.plot(dense * 1e6, dense * TRUE.R * 1e6, ":", color="0.5", lw=1, label="ohmic line $V = IR$ (true R)")
    ax.set(ylabel="V (µV)", title=rf"Fitting the RCSJ model to a noisy down sweep (true $\beta$ = {TRUE.beta:.3f})")
    ax.legend(fontsize=8, loc="upper left")
    res.axhline(0.0, color="0.5", lw=0.8)
    res.errorbar(current[fit.fitted] * 1e6, -fit.residuals * 1e6, yerr=NOISE * 1e6, fmt="o", ms=4)
    res.set(xlabel="I (µA)", ylabel="data − fit (µV)")
    fig.tight_layout()
    path = out_dir(out) / "fit_iv_curve.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return fit, path


if __name__ == "__main__":
    fit, png = main(sys.argv[1] if len(sys.argv) > 1 else None)
    print("wrote", png)
