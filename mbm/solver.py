"""`MBM`: the moving boundary method as a :class:`scipy.integrate.OdeSolver`.

Window control only: the solver knows the model (β, γ, ω), the anchor state at the
start of each window and an approximant's kernels; it never looks inside a formula.
Re-anchoring follows (3.29)–(3.31) of the second paper: the approximant anchored at
the state reached at the end of the previous window.
"""

import math
import warnings

import numpy as np
from scipy.integrate import DenseOutput, OdeSolver

from .approximants import get_approximant
from .problem import Pendulum, identify_model

__all__ = ["MBM", "MBMDenseOutput"]

# Window length used when neither ``tau`` nor ``first_step`` is given: one tenth of
# the small-oscillation period 2π/ω keeps the paper's |βτ| ≪ 1 assumption (2.10)
# for β ≲ 1 and resolves the motion without many windows.
DEFAULT_TAU_PERIODS = 0.1


def _warn_extraneous(extraneous):
    if extraneous:
        warnings.warn(
            "The following arguments have no effect for the MBM solver: "
            + ", ".join(f"`{x}`" for x in extraneous),
            stacklevel=3,
        )


def _positive(name, value, allow_inf=False):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a positive real number, got {value!r}") from None
    if not (v > 0.0) or math.isnan(v) or (math.isinf(v) and not allow_inf):
        raise ValueError(
            f"{name} must be a positive {'number' if allow_inf else 'finite number'}, "
            f"got {value!r}"
        )
    return v


class MBM(OdeSolver):
    """Moving boundary method for θ'' + βθ' + ω² sin θ = γ, a drop-in `solve_ivp` method.

    The solution is advanced over windows of length τ; at each window start an
    analytic approximant is anchored at the current state (θ, θ'), and the state at
    the window end is the formula's value there (the second paper's (3.29)–(3.31)).
    The dense output on a window is that analytic formula.

    Parameters
    ----------
    fun : callable
        Right-hand side ``fun(t, y)``: an :class:`mbm.Pendulum`, or any callable of
        the family, whose β, γ, ω are identified by probing (see
        :func:`mbm.problem.identify_model`).  A callable outside the family raises
        ``ValueError``.
    t0 : float
        Initial time.
    y0 : array_like, shape (2,)
        Initial state [θ₀, θ̇₀].
    t_bound : float
        Boundary time; the last window is cut to land on it exactly.
    tau : float, optional
        Window length τ > 0.  Default: ``first_step`` if given, else
        ``0.1 · 2π/ω``.  Capped by ``max_step``.
    approximant : str or Approximant, optional
        Name of a registered approximant (see :func:`mbm.approximant_names`);
        default ``"salas-torque"``.
    model : Pendulum, optional
        The model; skips probing ``fun``.
    max_step : float, optional
        Largest window allowed (default inf).
    first_step : float, optional
        Used as τ when ``tau`` is not given.
    rtol, atol : float, optional
        Accepted for the solve_ivp interface and validated; with a fixed τ they do
        not change the windows.
    vectorized : bool, optional
        Accepted for the interface; MBM does not call ``fun`` after probing.
    **extraneous
        Other options are ignored with a warning, as scipy's methods do.

    Attributes
    ----------
    model : Pendulum
        The identified or given model.
    approximant : Approximant
    tau : float
        The window length in use.
    nfev : int
        Calls of ``fun`` (probing only).
    njev, nlu : int
        Always 0.
    """

    def __init__(
        self,
        fun,
        t0,
        y0,
        t_bound,
        tau=None,
        approximant="salas-torque",
        model=None,
        max_step=np.inf,
        first_step=None,
        rtol=1e-3,
        atol=1e-6,
        vectorized=False,
        **extraneous,
    ):
        _warn_extraneous(extraneous)
        super().__init__(fun, t0, y0, t_bound, vectorized, support_complex=False)
        if self.y.shape != (2,):
            raise ValueError(f"y0 must have shape (2,) (theta, theta'), got shape {self.y.shape}")
        if not np.all(np.isfinite(self.y)):
            raise ValueError(f"y0 must be finite, got {self.y!r}")
        if not (math.isfinite(t0) and math.isfinite(t_bound)):
            raise ValueError(f"t0 and t_bound must be finite, got {t0!r}, {t_bound!r}")
        self.max_step = _positive("max_step", max_step, allow_inf=True)
        self.rtol = _positive("rtol", rtol)
        self.atol = _positive("atol", atol)
        if model is None:
            model, nprobe = identify_model(fun, t0=float(t0))
            self.nfev += nprobe
        elif not isinstance(model, Pendulum):
            raise TypeError(f"model must be an mbm.Pendulum, got {type(model).__name__}")
        self.model = model
        self.approximant = get_approximant(approximant)
        self.approximant.check_model(model)
        if tau is None:
            tau = first_step if first_step is not None else DEFAULT_TAU_PERIODS * 2 * math.pi / model.omega
            name = "first_step" if first_step is not None else "tau"
        else:
            name = "tau"
        self.tau = min(_positive(name, tau), self.max_step)
        self._coef = None
        self._beta, self._gamma, self._omega = model.params

    def _step_impl(self):
        t = self.t
        t_new = t + self.direction * self.tau
        if self.direction * (t_new - self.t_bound) > 0:
            t_new = self.t_bound
        h = t_new - t
        ap = self.approximant
        coef = ap.anchor_kernel(self._beta, self._gamma, self._omega, self.y[0], self.y[1])
        if coef[0] != 0:
            msg = ap.status_messages.get(int(coef[0]), f"status {int(coef[0])}")
            return False, f"approximant {ap.name!r} cannot be anchored at t={t!r}: {msg}"
        theta, v = ap.eval_kernel(coef, h)
        if not (math.isfinite(theta) and math.isfinite(v)):
            return False, (
                f"approximant {ap.name!r} produced a non-finite state over the window "
                f"[{t!r}, {t_new!r}]: the motion left its domain"
            )
        self._coef = coef
        self.t = t_new
        self.y = np.array([theta, v])
        return True, None

    def _dense_output_impl(self):
        return MBMDenseOutput(self.t_old, self.t, self.approximant, self._coef)


class MBMDenseOutput(DenseOutput):
    """Dense output of one MBM window: the anchored analytic formula itself.

    Exact at both window ends: ``sol(t_old)`` is the anchor and ``sol(t)`` repeats
    the evaluation that produced the step's end state.
    """

    def __init__(self, t_old, t, approximant, coef):
        super().__init__(t_old, t)
        self.approximant = approximant
        self.coef = coef

    def _call_impl(self, t):
        # t − t_old is formed exactly as in _step_impl, so sol(t) == y at t = self.t.
        s = np.asarray(t, dtype=np.float64) - self.t_old
        if s.ndim == 0:
            a, b = self.approximant.eval_kernel(self.coef, float(s))
            return np.array([a, b])
        s = np.ascontiguousarray(s)
        th = np.empty_like(s)
        v = np.empty_like(s)
        self.approximant.eval_array_kernel(self.coef, s, th, v)
        return np.vstack((th, v))
