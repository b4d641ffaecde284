"""Current–voltage curve of a Josephson junction in the RCSJ model, with hysteresis
================================================================================

In reduced units the resistively and capacitively shunted junction is the damped,
torqued pendulum θ'' + βθ' + sin θ = γ (θ the phase, ⟨θ'⟩ the dc voltage, γ = I/I_c,
β = 1/√β_c).  The bias is swept 0 → 2 → 0 at β = 0.1 with :func:`mbm.iv_curve`: each
point starts where the previous one ended, ⟨θ'⟩ = 2π/T_c on the running cycle, and the
switching (≈ 1, where the equilibrium disappears) and retrapping (≈ 4β/π) currents are
bisected to 1e-4.

Usage::

    python josephson_iv.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import math
import os
import sys
from pathlib import Path

import matplotlib
import numpy as np

import mbm

matplotlib.use("Agg")  # the figures go to PNG files: no display needed
import matplotlib.pyplot as plt  # noqa: E402

BETA = 0.1


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def main(out=None, beta=BETA, points=81):
    """Compute the up-and-down I–V curve and save ``josephson_iv.png``; returns (curve, path)."""
    up = np.linspace(0.0, 2.0, points)
    curve = mbm.iv_curve(beta, np.r_[up, up[::-1]])
    ax = curve.plot(plt.subplots(figsize=(7.5, 5))[1])
    ax.axhline(4 * beta / math.pi, color="0.5", ls=":", lw=0.8, label=rf"$4\beta/\pi$ = {4 * beta / math.pi:.4f}")
    ax.legend(fontsize=8, loc="lower right")
    path = out_dir(out) / "josephson_iv.png"
    ax.figure.tight_layout()
    ax.figure.savefig(path, dpi=110)
    plt.close(ax.figure)
    return curve, path


if __name__ == "__main__":
    curve, png = main(sys.argv[1] if len(sys.argv) > 1 else None)
    print(f"beta = {curve.beta:g}: switching {curve.switching_current:.4f}, retrapping "
          f"{curve.retrapping_current:.4f} (4 beta / pi = {4 * curve.beta / math.pi:.4f})")
    print("wrote", png)
