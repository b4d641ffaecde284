"""Recompute Table 1 of the first paper (Salas 2021) and print it beside the printed values
========================================================================================

θ'' + 2εθ' + sin θ = 0, θ(0) = 0, θ'(0) = θ̇₀, ω = 1, 0 ≤ t ≤ 20; the error is
max abs(θ − θ_ref) with θ_ref from :func:`mbm.reference.reference` (CVODE at 1e-12).

The table's column parameters are not printed.  From the text: the left half sweeps
2ε = 0.02 … 0.4 (11 values) at the Example's θ̇₀ = 0.25 ((3.10); the printed
"Our solution" errors there match the right half at θ̇₀ ≈ 0.25, 2ε = 0.4); the right
half sweeps θ̇₀ = 0.1 … 1.0 at the Example's 2ε = 0.4 ((3.11): x'' + 0.4x' + sin x).

Columns: "johannessen" is (3.9) with the first term of ξ read as θ̇₀⁴ (see
``docs/salas2021.md``); "linear" is the paper's practical elementary solution
f ≈ f′(0)t ("Our solution"); "full" is (2.2) with the exact f of (2.6);
"J-trig" is (3.9) with sin_m.  See ``docs/salas2021.md`` for the comparison.

Run:  python table1_salas2021.py (prints both halves and writes ``out/table1_salas2021.png``:
the recomputed errors beside the printed ones).
"""

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from mbm.approximants.salas2021 import Johannessen, JohannessenTrig, SalasDamped, SalasDampedLinear
from mbm.model import Pendulum
from mbm.frontends.reference import reference

# The printed Table 1 (first paper), columns Error_Johannessen and Error_Our Solution.
TWO_EPS = np.round(np.linspace(0.02, 0.4, 11), 3)
THETA_DOT0 = np.round(np.linspace(0.1, 1.0, 11), 2)
PRINTED_LEFT = {  # 2ε sweep (θ̇₀ = 0.25)
    "johannessen": [1.95881e-5, 5.71511e-5, 9.5238e-5, 1.33938e-4, 1.73344e-4, 2.13556e-4,
                    2.54682e-4, 2.96834e-4, 3.40138e-4, 3.84725e-4, 4.30743e-4],
    "ours": [1.87958e-3, 1.81357e-3, 1.78244e-3, 1.75131e-3, 1.72123e-3, 1.69301e-3,
             1.66726e-3, 1.64445e-3, 1.62493e-3, 1.60896e-3, 1.59671e-3],
}
PRINTED_RIGHT = {  # θ̇₀ sweep (2ε = 0.4)
    "johannessen": [1.2985e-5, 8.90639e-5, 2.85046e-4, 6.57727e-4, 1.2639e-3, 2.16037e-3,
                    3.40393e-3, 5.05137e-3, 7.15949e-3, 9.78509e-3, 1.2985e-2],
    "ours": [1.10576e-4, 7.52433e-4, 2.37698e-3, 5.38544e-3, 1.0106e-2, 1.67728e-2,
             2.55084e-2, 3.63128e-2, 4.9061e-2, 6.51477e-2, 8.67195e-2],
}
LEFT_THETA_DOT0 = 0.25
RIGHT_TWO_EPS = 0.4
T_END = 20.0
# Sampling of [0, T_END] for the max: step 0.005 resolves the maxima of an
# oscillation of period ~2π to a relative 1e-6.
N_T = 4001

APPROXIMANTS = {
    "johannessen": Johannessen(),
    "linear": SalasDampedLinear(),
    "full": SalasDamped(),
    "J-trig": JohannessenTrig(),
}


def max_errors(two_eps, theta_dot0, t_end=T_END, n_t=N_T):
    """Max |θ − θ_ref| over [0, t_end] for each approximant anchored at (0, θ̇₀).

    Parameters
    ----------
    two_eps : float
        2ε = β.
    theta_dot0 : float
        θ'(0).
    t_end : float, optional
        Horizon (the paper's T = 20).
    n_t : int, optional
        Number of sample times.

    Returns
    -------
    dict
        Approximant label -> max error.
    """
    model = Pendulum(beta=two_eps)
    t = np.linspace(0.0, t_end, n_t)
    ref = reference(model, (0.0, t_end), [0.0, theta_dot0], t_eval=t).y[0]
    return {
        label: float(np.abs(ap.anchor(model, 0.0, theta_dot0)(t)[0] - ref).max())
        for label, ap in APPROXIMANTS.items()
    }


def table1():
    """Both halves of Table 1 recomputed: (left rows, right rows), each a list of dicts."""
    left = [max_errors(b, LEFT_THETA_DOT0) for b in TWO_EPS]
    right = [max_errors(RIGHT_TWO_EPS, v) for v in THETA_DOT0]
    return left, right


def _print_half(title, params, rows, printed):
    print(title)
    print(f"{'':>6} {'Johannessen':>23} {'elementary (Our solution)':>34} {'':>10}")
    print(
        f"{'':>6} {'printed':>11} {'ours':>11} {'printed':>11} {'ours lin':>11} "
        f"{'ours full':>11} {'J-trig':>10}"
    )
    for p, row, pj, po in zip(params, rows, printed["johannessen"], printed["ours"]):
        print(
            f"{p:6.3f} {pj:11.4g} {row['johannessen']:11.4g} {po:11.4g} {row['linear']:11.4g} "
            f"{row['full']:11.4g} {row['J-trig']:10.4g}"
        )


def out_dir(path=None):
    """The folder the PNG goes to (created): ``path``, else ``$MBM_EXAMPLES_OUT``, else ``./out``."""
    d = Path(path or os.environ.get("MBM_EXAMPLES_OUT") or "out")
    d.mkdir(parents=True, exist_ok=True)
    return d


def plot(left, right, path):
    """Both halves: the recomputed errors (lines) over the printed ones (markers); saves ``path``."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    halves = ((axes[0], TWO_EPS, left, PRINTED_LEFT, f"2ε  (θ̇₀ = {LEFT_THETA_DOT0})"),
              (axes[1], THETA_DOT0, right, PRINTED_RIGHT, f"θ̇₀  (2ε = {RIGHT_TWO_EPS})"))
    for ax, x, rows, printed, label in halves:
        ax.semilogy(x, [r["johannessen"] for r in rows], "C0-", label="Johannessen (3.9), recomputed")
        ax.semilogy(x, printed["johannessen"], "C0o", mfc="none", label="Johannessen, printed")
        ax.semilogy(x, [r["linear"] for r in rows], "C1-", label="elementary (Our solution), recomputed")
        ax.semilogy(x, printed["ours"], "C1s", mfc="none", label="elementary, printed")
        ax.semilogy(x, [r["full"] for r in rows], "C2--", label="(2.2) with the exact f")
        ax.set_xlabel(label)
    axes[0].set_ylabel(f"max |θ − θ_ref|, 0 ≤ t ≤ {T_END:g}")
    axes[0].legend(fontsize=7)
    fig.suptitle("Table 1 of Salas (2021), recomputed")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(out=None):
    """Print both halves of Table 1 beside the printed values and save ``table1_salas2021.png``.

    Returns
    -------
    ((list, list), Path)
        The recomputed halves (:func:`table1`) and the PNG written.
    """
    left, right = table1()
    _print_half(f"2ε sweep, θ̇₀ = {LEFT_THETA_DOT0}, ω = 1, 0 ≤ t ≤ {T_END:g}", TWO_EPS, left, PRINTED_LEFT)
    print()
    _print_half(f"θ̇₀ sweep, 2ε = {RIGHT_TWO_EPS}, ω = 1, 0 ≤ t ≤ {T_END:g}", THETA_DOT0, right, PRINTED_RIGHT)
    return (left, right), plot(left, right, out_dir(out) / "table1_salas2021.png")


if __name__ == "__main__":
    main()
