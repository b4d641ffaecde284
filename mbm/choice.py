"""The "auto" approximant: the cheapest approximant that meets the requested tolerance.

The rule, and the measurements behind it (``docs/convergent.md``,
``tests/frontends/test_auto.py``):

* β = γ = 0 and no AC drive: the exact elliptic solution ("belendez", third paper (31) extended to
  every state).  No truncation error, so one window as long as ``max_step`` allows;
  the error is round-off at any horizon.
* otherwise (a driven model too, whatever β and γ: the Taylor family is the one that
  integrates a drive): the convergent family (:data:`CONVERGENT_DEFAULT`) with windows
  chosen from rtol/atol.  The papers' approximants are never the cheapest: they have no
  error estimate (fixed windows) and a model error that re-anchoring does not remove
  (3.2e-3 on the second paper's Example 1, 2.5e-2 on Example 2, 1e-4 to 1e-2 for
  the first paper's), so they meet no tolerance below that, and above it the
  convergent family meets the tolerance with fewer, longer windows at a similar
  cost per window.
"""

__all__ = ["choose_approximant", "auto_name", "auto_reason", "CONVERGENT_DEFAULT", "EXACT_UNDAMPED"]

# The convergent family used by "auto" for β ≠ 0 or γ ≠ 0 (docs/convergent.md: the
# best accuracy per microsecond over its six scenes).
CONVERGENT_DEFAULT = "taylor"
# The exact flow used by "auto" for β = γ = 0.
EXACT_UNDAMPED = "belendez"


def auto_name(undamped):
    """The name "auto" stands for: the exact flow when β = γ = 0 and there is no drive
    (``undamped``), else the convergent family.  The rule alone, without the reason
    text (the compiled path caches it per call signature)."""
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
    undamped = model.beta == 0.0 and model.gamma == 0.0 and not model.driven
    return auto_name(undamped), auto_reason(undamped, rtol, atol, model.driven)


def auto_reason(undamped, rtol, atol, driven=False):
    """The one-sentence reason :func:`choose_approximant` gives, from the facts it uses
    (β = γ = 0 without a drive, whether there is one, and the tolerances); a pure
    function, so callers may cache it."""
    if driven:
        return (
            f"an AC drive: the convergent family {CONVERGENT_DEFAULT!r} (the approximant that "
            f"integrates a drive) with windows from rtol={rtol:g}, atol={atol:g}"
        )
    if auto_name(undamped) == EXACT_UNDAMPED:
        return (
            "beta = gamma = 0: the exact elliptic solution (Belendez et al. (31), any state), "
            "error at round-off, one window as long as max_step allows"
        )
    return (
        f"beta or gamma != 0: the convergent family {CONVERGENT_DEFAULT!r} with windows from "
        f"rtol={rtol:g}, atol={atol:g}; the papers' approximants carry a model error "
        "(2.5e-2 to 1e-4 on the papers' scenes) that re-anchoring does not remove and "
        "have no error estimate"
    )
