"""Tight, independent numerical solutions of the pendulum family, for checking approximants.

:func:`reference` integrates  θ'' + β θ' + ω² sin θ = γ,  y = [θ, θ'],  with a
general-purpose integrator that knows nothing of the analytic approximants:

``"cvode"`` (default)
    SUNDIALS CVODE through scikit-sundae, variable-order Adams–Moulton (orders
    1–12) with the analytic Jacobian.  The problem is not stiff (the Jacobian's
    eigenvalues are −β/2 ± √(β²/4 − ω² cos θ), of size ω), so the high-order
    Adams family is the most economical choice at tolerances near 1e-12.
``"ida"``
    SUNDIALS IDA (BDF, orders 1–5) on the residual form
    F(t, y, y') = y' − f(t, y) = 0 with the consistent initial slope
    y'(t₀) = f(t₀, y₀).  A different method family from CVODE's Adams, which
    makes the pair a useful cross-check.
``"dop853"``
    :func:`scipy.integrate.solve_ivp` with the explicit Runge–Kutta DOP853.

All three share one calling convention and return a
:class:`scipy.optimize.OptimizeResult` shaped like ``solve_ivp``'s result.
"""

import collections
import math

import numpy as np
# scipy.integrate and scipy.optimize are imported where used: `import mbm` (which
# imports this module) stays free of their ~0.5 s import.

from ..validate import check_span, check_state, check_t_eval, check_tolerances
from ..model import Pendulum

__all__ = ["reference", "REFERENCE_SOLVERS"]

# Names accepted by ``solver``; the order is the documentation order.
REFERENCE_SOLVERS = ("cvode", "ida", "dop853")

# Highest order of CVODE's Adams–Moulton family (SUNDIALS' maximum): at 1e-12 the
# high orders are what keep the step count near 3–30 steps per unit of ω t.
CVODE_ADAMS_MAX_ORDER = 12

# Step budget per output interval of CVODE/IDA (SUNDIALS' default of 500 is far
# too small): an undamped run at 1e-12 needs about 30 Adams steps (a few hundred
# BDF steps) per unit of ω t, so 1e9 covers horizons of 1e6 and beyond; the real
# limit on a long horizon is run time, not this cap.
MAX_NUM_STEPS = 10**9

# reference's arguments, checked and normalised (_validate).
_Arguments = collections.namedtuple("_Arguments", ("solver", "t0", "tf", "y0", "t_eval", "rtol", "atol"))


def _validate(model, t_span, y0, t_eval, rtol, atol, solver):
    """Check and normalise the arguments of :func:`reference`."""
    if not isinstance(model, Pendulum):
        raise TypeError(f"model must be a mbm.Pendulum, got {type(model).__name__}")
    if not isinstance(solver, str) or solver.lower() not in REFERENCE_SOLVERS:
        raise ValueError(f"solver must be one of {REFERENCE_SOLVERS}, got {solver!r}")
    solver = solver.lower()
    t0, tf = check_span(t_span, allow_empty=False)
    y0 = check_state("y0", y0)
    rtol, atol = check_tolerances(rtol, atol, stacklevel=4)
    if t_eval is not None:
        t_eval = check_t_eval(t_eval, t0, tf, strict=True)
        if t_eval.size == 0:
            raise ValueError("t_eval must be None or contain at least one time")
    return _Arguments(solver, t0, tf, y0, t_eval, rtol, atol)


def _output_grid(t0, tf, t_eval):
    """Times to hand to SUNDIALS' ``solve`` and where ``t_eval`` sits in them.

    SUNDIALS wants a strictly monotonic grid starting at ``t0``, and reads a grid of
    length 2 as "save every internal step"; the endpoints are added, duplicates
    dropped, and a midpoint inserted when only the endpoints remain, so that the
    rows of the result are exactly the grid.
    """
    sgn = 1.0 if tf > t0 else -1.0
    grid = sgn * np.unique(sgn * np.concatenate(([t0], t_eval, [tf])))
    if len(grid) == 2:
        grid = np.array([t0, 0.5 * (t0 + tf), tf])
    idx = np.searchsorted(sgn * grid, sgn * t_eval)
    return grid, idx


def _sundials_result(res, t_eval, idx):
    """Convert an sksundae result (y of shape (n, 2)) to the solve_ivp-like OptimizeResult."""
    t = np.asarray(res.t, dtype=float)
    y = np.asarray(res.y, dtype=float).reshape(len(t), -1).T
    success = bool(res.success)
    if t_eval is not None:
        if success and len(t) > idx[-1]:
            t, y = t[idx], y[:, idx]
        else:
            # partial run: keep the requested times that were reached
            success = False
            keep = np.flatnonzero(np.isin(t, t_eval))
            t, y = t[keep], y[:, keep]
    nfev = getattr(res, "nfev", None)
    njev = getattr(res, "njev", None)
    from scipy.optimize import OptimizeResult

    return OptimizeResult(
        t=t,
        y=y,
        success=success,
        status=0 if success else -1,
        message=str(res.message),
        nfev=-1 if nfev is None else int(nfev),
        njev=-1 if njev is None else int(njev),
        solver="",
    )


def cvode_adams(model, rtol, atol, **options):
    """A scikit-sundae CVODE solver of ``model``: Adams–Moulton up to order 12 with the
    analytic Jacobian and the step budget :data:`MAX_NUM_STEPS` (``options``, e.g. an
    event function, are passed on)."""
    from sksundae.cvode import CVODE

    rhs, jac = model.sundials_callbacks()
    return CVODE(rhs, method="Adams", rtol=rtol, atol=atol, max_order=CVODE_ADAMS_MAX_ORDER,
                 max_num_steps=MAX_NUM_STEPS, jacfn=jac, **options)


def _solve_cvode(model, t0, tf, y0, t_eval, rtol, atol):
    solver = cvode_adams(model, rtol, atol)
    if t_eval is None:
        return _sundials_result(solver.solve([t0, tf], y0), None, None)
    grid, idx = _output_grid(t0, tf, t_eval)
    return _sundials_result(solver.solve(grid, y0), t_eval, idx)


def _solve_ida(model, t0, tf, y0, t_eval, rtol, atol):
    from sksundae.ida import IDA

    rhs, jac = model.sundials_callbacks()
    f = np.empty(2)
    jf = np.empty((2, 2))

    def resfn(t, y, yp, res):
        # F(t, y, y') = y' − f(t, y)
        rhs(t, y, f)
        res[0] = yp[0] - f[0]
        res[1] = yp[1] - f[1]

    def jacfn(t, y, yp, res, cj, jj):
        # dF/dy + cj dF/dy' = −J + cj I
        jac(t, y, None, jf)
        jj[0, 0] = cj - jf[0, 0]
        jj[0, 1] = -jf[0, 1]
        jj[1, 0] = -jf[1, 0]
        jj[1, 1] = cj - jf[1, 1]

    yp0 = np.empty(2)
    rhs(t0, y0, yp0)  # consistent initial slope: F(t0, y0, yp0) = 0 exactly
    solver = IDA(resfn, rtol=rtol, atol=atol, max_num_steps=MAX_NUM_STEPS, jacfn=jacfn)
    if t_eval is None:
        return _sundials_result(solver.solve([t0, tf], y0, yp0), None, None)
    grid, idx = _output_grid(t0, tf, t_eval)
    return _sundials_result(solver.solve(grid, y0, yp0), t_eval, idx)


def _solve_dop853(model, t0, tf, y0, t_eval, rtol, atol):
    from scipy.integrate import solve_ivp
    from scipy.optimize import OptimizeResult

    sol = solve_ivp(
        model.fun, (t0, tf), y0, method="DOP853", t_eval=t_eval, rtol=rtol, atol=atol
    )
    return OptimizeResult(
        t=sol.t,
        y=sol.y,
        success=bool(sol.success),
        status=int(sol.status),
        message=str(sol.message),
        nfev=int(sol.nfev),
        njev=0,
        solver="",
    )


_DISPATCH = {"cvode": _solve_cvode, "ida": _solve_ida, "dop853": _solve_dop853}


def reference(model, t_span, y0, t_eval=None, rtol=1e-12, atol=1e-12, solver="cvode"):
    """Integrate a pendulum model tightly with an independent general-purpose solver.

    Parameters
    ----------
    model : Pendulum
        The equation θ'' + β θ' + ω² sin θ = γ.
    t_span : pair of float
        ``(t0, tf)``, finite, ``t0 != tf``; ``tf < t0`` integrates backward.
    y0 : array_like, shape (2,)
        Initial state ``[θ(t0), θ'(t0)]``, finite.
    t_eval : array_like or None, optional
        Times at which to return the solution, inside ``t_span`` and strictly
        monotonic in the direction of integration.  ``None`` (default) returns
        the integrator's own accepted steps, ``t0`` and ``tf`` included (the
        natural output of all three solvers; the steps are dense where the
        motion is fast).
    rtol, atol : float, optional
        Relative and absolute local error tolerances (default 1e-12 each);
        positive; rtol below 100 eps is raised to it with a warning (scipy's rule).
        The global error of a long run grows
        with the horizon; it is the caller's job to check it (e.g. by comparing
        two solvers).
    solver : {"cvode", "ida", "dop853"}, optional
        ``"cvode"``: SUNDIALS CVODE, Adams–Moulton with the analytic Jacobian
        (default; the problem is non-stiff).  ``"ida"``: SUNDIALS IDA (BDF) on
        the residual F(t, y, y') = y' − f(t, y) with y'(t0) = f(t0, y0).
        ``"dop853"``: :func:`scipy.integrate.solve_ivp` with DOP853.

    Returns
    -------
    OptimizeResult
        With fields ``t`` (shape (n,)), ``y`` (shape (2, n)), ``success``,
        ``status`` (0 on success, negative on failure), ``message``, ``nfev``
        and ``njev`` (−1 where the solver does not report them), like the
        result of :func:`scipy.integrate.solve_ivp`.  On failure ``t``/``y``
        hold what was reached.

    Raises
    ------
    ValueError
        If ``solver`` is unknown, ``y0`` is not a finite array of shape (2,),
        ``t_span`` is not a finite pair with ``t0 != tf``, ``rtol``/``atol`` are
        not positive and finite, or ``t_eval`` is empty, not finite, outside
        ``t_span`` or not strictly monotonic in the direction of integration.
    TypeError
        If ``model`` is not a :class:`~mbm.Pendulum`.

    Examples
    --------
    >>> import numpy as np
    >>> from mbm import Pendulum
    >>> from mbm import reference
    >>> sol = reference(Pendulum(beta=0.1, gamma=0.3), (0.0, 10.0), [np.pi / 6, 0.0],
    ...                 t_eval=[0.0, 5.0, 10.0])
    >>> sol.y.shape
    (2, 3)
    """
    solver, t0, tf, y0, t_eval, rtol, atol = _validate(
        model, t_span, y0, t_eval, rtol, atol, solver
    )
    out = _DISPATCH[solver](model, t0, tf, y0, t_eval, rtol, atol)
    out.solver = solver
    return out
