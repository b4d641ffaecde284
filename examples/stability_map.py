"""A (β, γ) stability map of the driven, damped pendulum: ⟨θ'⟩ from rest and launched
==================================================================================

θ'' + βθ' + sin θ = γ (the RCSJ model of a Josephson junction: ⟨θ'⟩ is its dc
voltage) over a grid of damping β and torque γ, from two initial states: at rest
(θ'₀ = 0) and launched (θ'₀ = :data:`LAUNCH`).  One :func:`mbm.sweep` call computes the
whole grid with ``reduce=["mean_velocity", "regime"]``: no time series is stored.

* Above γ = 1 no equilibrium exists: every scene runs, ⟨θ'⟩ ≈ γ/β for small β.
* Between the retrapping current (γ_r ≈ 4β/π for small β: the work 2πγ of a turn pays
  the damping 8β along the separatrix) and 1 the pendulum is bistable: the scenes
  started at rest lock, the launched ones keep running.  The two panels differ exactly
  there, the hysteresis of the junction's I–V curve (``examples/josephson_iv.py``).
* Except at small β from rest: the first swing from θ = 0 clears the barrier at
  π − arcsin γ when γ(π − arcsin γ) − √(1 − γ²) ≥ 1, i.e. γ ≳ 0.725 undamped, and a
  weakly damped pendulum then keeps running: the step in the left panel.

Usage::

    python stability_map.py [OUT_DIR]   # PNGs to OUT_DIR, else $MBM_EXAMPLES_OUT, else ./out
"""

import os
import sys
from pathlib import Path

import matplotlib
import numpy as np

from mbm.junction.sweeps import sweep

matplotlib.use("Agg")  # the figures go to PNG files: no display needed
import matplotlib.pyplot as plt  # noqa: E402

# Damping range: from the weakly damped (strong hysteresis) to β = 1, where the
# bistable band has closed to a sliver below γ = 1.
BETA_RANGE = (0.05, 1.0)
# Torque range: past γ = 1 (no equilibrium left) far enough to see ⟨θ'⟩ grow as γ/β.
GAMMA_RANGE = (0.0, 1.6)
# The launched initial velocity: above γ/β for most of the grid, so a launched scene
# starts beyond the running cycle and decays onto it where the cycle exists.
LAUNCH = 5.0
# Top of the colour scale: ⟨θ'⟩ ≈ γ/β reaches 32 at β = 0.05, but the bistable band
# near the retrapping current runs at ⟨θ'⟩ ~ 1–5; above 8 the scale saturates.
V_MAX = 8.0
# Horizon: the slowest transient, e^{-βt/2} at β = 0.05, has decayed by e^{-10} at
# t = 400, so the second half [T/2, T] sees the settled regime.
T_END = 400.0


def out_dir(path=None):
    """The folder the PNGs go to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def main(out=None, n_beta=60, n_gamma=80, t_end=T_END, chunks=None):
    """Sweep the grid and draw the two ⟨θ'⟩ maps into ``stability_map.png``.

    Parameters
    ----------
    out : str or Path, optional
        Output directory (default ``examples/out/``).
    n_beta, n_gamma : int
        Grid size.
    t_end : float
        Horizon; ⟨θ'⟩ is taken over [t_end/2, t_end].
    chunks : int or dict, optional
        Passed to :func:`mbm.sweep` (compute on the active Dask scheduler).

    Returns
    -------
    (xarray.Dataset, Path)
        The sweep and the PNG written.
    """
    ds = sweep(beta=np.linspace(*BETA_RANGE, n_beta), gamma=np.linspace(*GAMMA_RANGE, n_gamma),
               theta_dot0=[0.0, LAUNCH], t_span=(0.0, t_end), reduce=["mean_velocity", "regime"],
               chunks=chunks)
    ds = ds.compute()
    grid = ds.mean_velocity.plot(x="beta", y="gamma", col="theta_dot0", cmap="magma", vmin=0.0, vmax=V_MAX,
                                 cbar_kwargs={"label": "⟨θ'⟩ over [T/2, T]", "extend": "max"})
    beta = ds.beta.values
    for ax in grid.axs.flat:
        ax.plot(beta, np.minimum(4 * beta / np.pi, 1.0), "w--", lw=1, label="4β/π (retrapping, small β)")
        ax.axhline(1.0, color="w", lw=1, ls=":", label="γ = 1 (switching)")
        ax.set_ylim(*GAMMA_RANGE)
    grid.axs.flat[0].legend(loc="lower right", fontsize=7)
    grid.fig.suptitle("θ'' + βθ' + sin θ = γ: mean velocity from rest (left) and launched (right)", y=1.02)
    png = out_dir(out) / "stability_map.png"
    grid.fig.savefig(png, dpi=120, bbox_inches="tight")
    plt.close(grid.fig)
    return ds, png


if __name__ == "__main__":
    _, path = main(sys.argv[1] if len(sys.argv) > 1 else None)
    print(path)
