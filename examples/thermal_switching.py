"""Thermal switching of a Josephson junction: P(I_sw) and the escape rate against 1/T
======================================================================================

A junction at temperature T is the pendulum with Langevin noise,
θ'' + βθ' + sin θ = γ(t) + ξ(t), ⟨ξ(t)ξ(t')⟩ = 2βT δ(t − t') (T = k_B T / E_J).
Left: switching-current histograms under the ramp γ = γ0 + r t at three temperatures
(:func:`mbm.switching_currents`), with the law P(γ) = (k(γ)/r) exp(−∫ k/r dγ) of the
Kramers rate k (:func:`mbm.kramers_rate`) overlaid.  Right: the escape rate out of a
well at fixed bias against 1/T (:func:`mbm.escape_times`), Arrhenius with Kramers'
prefactor.  Self-contained (numpy, matplotlib, mbm).

Usage::

    python thermal_switching.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import math
import os
import sys
from pathlib import Path

import matplotlib
import numpy as np

import mbm

matplotlib.use("Agg")  # the figure goes to a PNG file: no display needed
import matplotlib.pyplot as plt  # noqa: E402

BETA = 1.0
RAMP = 1e-4
GAMMA_START = 0.5
TEMPERATURES = (0.01, 0.02, 0.05)
ESCAPE_GAMMA = 0.6
ESCAPE_TEMPERATURES = (0.08, 0.1, 0.13, 0.17)


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def kramers_histogram(beta, temperature, ramp, g0, grid):
    """The switching density of the Kramers rate integrated over the ramp, on ``grid``."""
    k = np.array([mbm.kramers_rate(beta, g, temperature) for g in grid])
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(grid))]) / ramp
    return k / ramp * np.exp(-cum)


def main(out=None, n=1000, n_escape=300, seed=2026):
    """Run both panels and save ``thermal_switching.png``; returns (data, path)."""
    out = out_dir(out)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    data = {"histograms": {}, "rates": []}
    grid = np.linspace(GAMMA_START, 0.99999, 4000)
    for temp in TEMPERATURES:
        s = mbm.switching_currents(BETA, temp, RAMP, n, seed=seed, gamma_start=GAMMA_START)
        data["histograms"][temp] = s
        line = ax1.hist(s.currents, bins=40, density=True, histtype="step",
                        label=f"T = {temp}: skew {s.skewness:.2f}, kurt {s.kurtosis:.2f}")[2][0]
        ax1.plot(grid, kramers_histogram(BETA, temp, RAMP, GAMMA_START, grid), color=line.get_edgecolor(),
                 ls=":", lw=1.2)
    ax1.set(xlabel=r"switching bias $\gamma_{sw} = I_{sw}/I_c$", ylabel="density",
            title=rf"$P(I_{{sw}})$, $\beta$ = {BETA}, ramp {RAMP:g} (dotted: Kramers)",
            xlim=(0.7, 1.0))
    ax1.legend(fontsize=8, loc="upper left")
    for temp in ESCAPE_TEMPERATURES:
        r = mbm.escape_times(BETA, ESCAPE_GAMMA, temp, n_escape, seed=seed)
        data["rates"].append((temp, r.rate, r.rate / math.sqrt(n_escape),
                              mbm.kramers_rate(BETA, ESCAPE_GAMMA, temp)))
    t, rate, err, kr = (np.array(c) for c in zip(*data["rates"]))
    ax2.errorbar(1 / t, rate, yerr=err, fmt="o", label="mbm.escape_times")
    inv = np.linspace(1 / t.max(), 1 / t.min(), 100)
    ax2.plot(inv, [mbm.kramers_rate(BETA, ESCAPE_GAMMA, 1 / x) for x in inv], "k:", label="Kramers")
    ax2.set(yscale="log", xlabel="1/T", ylabel="escape rate",
            title=rf"escape out of the well, $\beta$ = {BETA}, $\gamma$ = {ESCAPE_GAMMA}")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    path = out / "thermal_switching.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return data, path


if __name__ == "__main__":
    print(main(sys.argv[1] if len(sys.argv) > 1 else None)[1])
