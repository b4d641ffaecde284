"""The "auto" approximant: the cheapest approximant that meets the requested tolerance.

The rule, and the measurements behind it (``docs/convergent.md``,
``tests/test_auto.py``):

* β = γ = 0: the exact elliptic solution ("belendez", third paper (31) extended to
  every state).  No truncation error, so one window as long as ``max_step`` allows;
  the error is round-off at any horizon.
* otherwise: the convergent family (:data:`CONVERGENT_DEFAULT`) with windows chosen
  from rtol/atol.  The papers' approximants are never the cheapest: they have no
  error estimate (fixed windows) and a model error that re-anchoring does not remove
  (3.2e-3 on the second paper's Example 1, 2.5e-2 on Example 2, 1e-4 to 1e-2 for
  the first paper's), so they meet no tolerance below that, and above it the
  convergent family meets the tolerance with fewer, longer windows at a similar
  cost per window.
"""

__all__ = ["choose_approximant", "auto_name", "CONVERGENT_DEFAULT", "EXACT_UNDAMPED"]

# The convergent family used by "auto" for β ≠ 0 or γ ≠ 0 (docs/convergent.md: the
# best accuracy per microsecond over the accuracy issue's scenes).
CONVERGENT_DEFAULT = "taylor"
# The exact flow used by "auto" for β = γ = 0.
EXACT_UNDAMPED = "belendez"


def auto_name(undamped):
    """The name "auto" stands for: the exact flow when β = γ = 0 (``undamped``), else
    the convergent family.  The rule alone, without the reason text (the compiled
    path caches it per call signature)."""
    return EXACT_UNDAMPED if undamped else CONVERGENT_DEFAULT


def choose_approximant(model, y0, rtol, atol):
    """Pick the approximant "auto" stands for.

    Parameters
    ----------
    model : Pendulum
    y0 : array_like, shape (2,)
        Initial state (unused by the present rule; part of the interface so that a
        state-dependent rule needs no change of callers).
    rtol, atol : float
        Requested tolerances.

    Returns
    -------
    name : str
        A registered approximant name.
    reason : str
        Why, in one sentence.
    """
    name = auto_name(model.beta == 0.0 and model.gamma == 0.0)
    if name == EXACT_UNDAMPED:
        return name, (
            "beta = gamma = 0: the exact elliptic solution (Belendez et al. (31), any state), "
            "error at round-off, one window as long as max_step allows"
        )
    return name, (
        f"beta or gamma != 0: the convergent family {CONVERGENT_DEFAULT!r} with windows from "
        f"rtol={rtol:g}, atol={atol:g}; the papers' approximants carry a model error "
        "(2.5e-2 to 1e-4 on the papers' scenes) that re-anchoring does not remove and "
        "have no error estimate"
    )
