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

from . import events as _events
from . import kernels as _kernels
from .approximants import get_approximant
from .choice import choose_approximant
from .problem import Pendulum, identify_model

__all__ = ["MBM", "MBMDenseOutput", "MBMWindowsDenseOutput"]

# scipy's RK methods refuse rtol below 100 eps (round-off dominates the estimate);
# so does MBM's window control.
RTOL_FLOOR = 100 * np.finfo(float).eps

# Window length used when neither ``tau`` nor ``first_step`` is given and the
# approximant has no error estimate: one tenth of the small-oscillation period 2π/ω
# keeps the paper's |βτ| ≪ 1 assumption (2.10) for β ≲ 1.
DEFAULT_TAU_PERIODS = 0.1
# Initial size of the per-step window buffers (grown by doubling when a step holds
# more windows).
WINDOW_BUFFER = 16
# Hybrid event-point mode (3.32): CVODE's tolerances for locating the events and the
# anchor states; tight, because the anchors carry CVODE's error into every window.
HYBRID_RTOL = 1e-10
HYBRID_ATOL = 1e-12
# Analytic event-point mode: longest window searched for the formula's next event,
# in small-oscillation periods (a libration has a turning point every half period;
# a rotation may have none, and then the window ends here).
EVENT_MAX_WINDOW_PERIODS = 1.0


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
        approximant="auto",
        model=None,
        anchors="windows",
        events_from="cvode",
        windows_per_step=1,
        max_step=np.inf,
        first_step=None,
        rtol=None,
        atol=None,
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
        tol_given = rtol is not None or atol is not None
        self.rtol = _positive("rtol", 1e-3 if rtol is None else rtol)
        self.atol = _positive("atol", 1e-6 if atol is None else atol)
        if self.rtol < RTOL_FLOOR:
            warnings.warn(f"rtol={self.rtol!r} is below {RTOL_FLOOR:.3g}; using {RTOL_FLOOR:.3g}", stacklevel=2)
            self.rtol = RTOL_FLOOR
        if model is None:
            model, nprobe = identify_model(fun, t0=float(t0))
            self.nfev += nprobe
        elif not isinstance(model, Pendulum):
            raise TypeError(f"model must be an mbm.Pendulum, got {type(model).__name__}")
        self.model = model
        if isinstance(approximant, str) and approximant == "auto":
            approximant, reason = choose_approximant(model, self.y, self.rtol, self.atol)
        else:
            reason = "chosen by the caller"
        self.approximant = get_approximant(approximant)
        self.approximant.check_model(model)
        #: (name, reason) of the approximant in use; "auto" records why it chose it.
        self.approximant_choice = (self.approximant.name, reason)
        self._beta, self._gamma, self._omega = model.params
        self._coef = None
        self._run = None
        self._kind = _kernels.kind_of(self.approximant)
        exact = bool(getattr(self.approximant, "exact", False))
        has_estimate = getattr(self.approximant, "error_kernel", None) is not None
        self.adaptive = tau is None and has_estimate and not exact and self._kind is not None
        if first_step is not None:
            first_step = _positive("first_step", first_step)
        if anchors not in ("windows", "events"):
            raise ValueError(f"anchors must be 'windows' or 'events', got {anchors!r}")
        if events_from not in ("cvode", "approximant"):
            raise ValueError(f"events_from must be 'cvode' or 'approximant', got {events_from!r}")
        if windows_per_step is None:
            self.windows_per_step = None
        else:
            if isinstance(windows_per_step, bool) or not isinstance(windows_per_step, (int, np.integer)) or windows_per_step < 1:
                raise ValueError(f"windows_per_step must be an integer >= 1 or None, got {windows_per_step!r}")
            self.windows_per_step = int(windows_per_step)
        self.anchors = anchors
        self.events_from = events_from if anchors == "events" else None
        if anchors == "events":
            self._setup_events(float(t0), float(t_bound))
            self.adaptive = False
            self.tau = None
            return
        if exact and tau is None:
            # An exact flow has no truncation error: one window as long as max_step allows.
            self.tau = self.max_step if math.isfinite(self.max_step) else (abs(t_bound - t0) or 1.0)
        elif self.adaptive:
            self.tau = None
        else:
            if tau is None:
                if tol_given:
                    warnings.warn(
                        f"approximant {self.approximant.name!r} has no error estimate: rtol and "
                        "atol do not change its windows; pass tau, or use an error-controlled "
                        "approximant (see mbm.approximant_names())",
                        stacklevel=2,
                    )
                tau = first_step if first_step is not None else DEFAULT_TAU_PERIODS * 2 * math.pi / model.omega
            self.tau = min(_positive("tau", tau), self.max_step)
        # Next window length for the compiled controller (≤ 0: search from the estimate).
        self._h_abs = self.tau if not self.adaptive else (min(first_step, self.max_step) if first_step else -1.0)
        self._order = int(self.approximant.order) if self.adaptive else 1

    def _setup_events(self, t0, t_bound):
        ap = self.approximant
        kind = ap.anchors
        d = _events.event_function_d(self.model, ap)
        if kind == "any":
            kinds = ("crossing", "turning") if d is not None else ("turning",)
        elif kind == "zero-crossing":
            if d is None:
                raise ValueError(
                    f"approximant {ap.name!r} anchors only at zero crossings theta = d, and "
                    f"d does not exist for gamma/omega**2 = {self._gamma / self._omega**2!r}"
                )
            kinds = ("crossing",)
        elif kind == "turning-point":
            kinds = ("turning",)
        else:
            raise ValueError(f"approximant {ap.name!r} declares unknown anchors {kind!r}")
        # The first window anchors at y0 itself: it must be an anchor the approximant accepts.
        y0 = self.y
        if kind == "zero-crossing" and abs(y0[0] - d) > _events.ON_SURFACE_TOL:
            raise ValueError(
                f"approximant {ap.name!r} anchors only at zero crossings theta = d = {d!r}; "
                f"y0[0] = {y0[0]!r} is not one"
            )
        if kind == "turning-point" and abs(y0[1]) > _events.ON_SURFACE_TOL:
            raise ValueError(
                f"approximant {ap.name!r} anchors only at turning points theta' = 0; "
                f"y0[1] = {y0[1]!r} is not one"
            )
        self._event_d = d
        self._event_kinds = kinds
        self._event_queue = None
        if self.events_from == "cvode" and t_bound != t0:
            te, ye, _ = _events.hybrid_event_points(
                self.model, (t0, t_bound), y0, d, kinds=kinds, rtol=HYBRID_RTOL, atol=HYBRID_ATOL
            )
            self._event_queue = (list(te), [np.array(y) for y in ye])
            self._event_index = 0

    def _events_step(self):
        ap = self.approximant
        t = self.t
        if self.events_from == "cvode":
            te, ye = self._event_queue
            i = self._event_index
            if i < len(te) and self.direction * (te[i] - t) > 0:
                t_new = te[i]
            else:
                t_new = self.t_bound
            if self.direction * (t_new - t) > self.max_step:
                t_new = t + self.direction * self.max_step
            coef, msg = self._anchor()
            if coef is None:
                return False, msg
            h = t_new - t
            theta, v = ap.eval_kernel(coef, h)
            if i < len(te) and t_new == te[i]:
                # (3.32): the next window anchors at the numerical solution's state
                # φ(τ_n), not at this window's end value — the method's jump.
                self._next_anchor = ye[i]
                self._event_index = i + 1
            else:
                self._next_anchor = None
        else:
            coef, msg = self._anchor()
            if coef is None:
                return False, msg
            span = abs(self.t_bound - t)
            t_max = min(span, self.max_step, EVENT_MAX_WINDOW_PERIODS * 2 * math.pi / self._omega)
            te, _ = _events.next_event_analytic(
                ap.eval_kernel, coef, self._event_d, self._event_kinds,
                self.direction * t_max, int(self.direction), omega=self._omega,
            )
            if math.isfinite(te):
                t_new = t + te
            else:
                t_new = self._window_end(t_max)
            h = t_new - t
            theta, v = ap.eval_kernel(coef, h)
        return self._accept_window(coef, t, t_new, theta, v)

    def _accept_window(self, coef, t, t_new, theta, v):
        # One window of a Python-driven mode: accept it, or fail cleanly (never NaN).
        if not (math.isfinite(theta) and math.isfinite(v)):
            return False, (
                f"approximant {self.approximant.name!r} produced a non-finite state over "
                f"the window [{t!r}, {t_new!r}]: the motion left its domain"
            )
        self._coef = coef
        self.t = t_new
        self.y = np.array([theta, v])
        return True, None

    def _anchor(self):
        ap = self.approximant
        y = self.y
        nxt = getattr(self, "_next_anchor", None)
        if nxt is not None:
            y = nxt
        coef = ap.anchor_kernel(self._beta, self._gamma, self._omega, y[0], y[1])
        if coef[0] != 0:
            msg = ap.status_messages.get(int(coef[0]), f"status {int(coef[0])}")
            return None, f"approximant {ap.name!r} cannot be anchored at t={self.t!r}: {msg}"
        return coef, None

    def _window_end(self, h_abs):
        t_new = self.t + self.direction * h_abs
        if self.direction * (t_new - self.t_bound) > 0:
            t_new = self.t_bound
        return t_new

    def _step_impl(self):
        if self.anchors == "events":
            return self._events_step()
        if self._kind is None:
            return self._python_window()
        kind, karg = self._kind
        nmax = self.windows_per_step or WINDOW_BUFFER
        starts = np.empty(nmax + 1)
        coefs = np.empty((nmax, self._coef_width()))
        st, n, t, th, v, h_abs = _kernels.advance(
            kind, karg, self._order, self._beta, self._gamma, self._omega, self.t, self.y[0],
            self.y[1], float(self.direction), float(self.t_bound), float(self._h_abs),
            self.max_step, self.rtol, self.atol, self.adaptive, float(self.t_bound), nmax,
            starts, coefs,
        )
        # windows_per_step=None: keep going in compiled chunks until t_bound, doubling
        # the buffers (amortized linear in the number of windows).
        while st == 0 and self.windows_per_step is None and t != self.t_bound:
            if n + nmax > coefs.shape[0]:
                cap = 2 * (n + nmax)
                starts = np.concatenate((starts[: n + 1], np.empty(cap - n)))
                coefs = np.concatenate((coefs[:n], np.empty((cap - n, coefs.shape[1]))))
            st, m, t, th, v, h_abs = _kernels.advance(
                kind, karg, self._order, self._beta, self._gamma, self._omega, t, th, v,
                float(self.direction), float(self.t_bound), h_abs, self.max_step, self.rtol,
                self.atol, self.adaptive, float(self.t_bound), nmax, starts[n:], coefs[n:],
            )
            n += m
        if n == 0:
            return False, self._failure(st)
        self._run = (starts[: n + 1], coefs[:n], n)
        self._h_abs = h_abs
        self.t = t
        self.y = np.array([th, v])
        # A failure after some accepted windows ends this step early; the next step reports it.
        return True, None

    def _coef_width(self):
        # Widest coefficient vector of this approximant: anchor once at the current state.
        kind, karg = self._kind
        if not hasattr(self, "_width"):
            self._width = _kernels.anchor(kind, karg, self._beta, self._gamma, self._omega, self.y[0], self.y[1]).size
        return self._width

    def _failure(self, st):
        ap = self.approximant
        if st == _kernels.STATUS_ANCHOR:
            coef, msg = self._anchor()
            return msg or f"approximant {ap.name!r} cannot be anchored at t={self.t!r}"
        if st == _kernels.STATUS_TOO_SMALL:
            return (
                f"required window at t={self.t!r} is below the spacing of floating point "
                f"numbers: approximant {ap.name!r} cannot meet rtol={self.rtol!r}, "
                f"atol={self.atol!r} here"
            )
        return (
            f"approximant {ap.name!r} produced a non-finite state over the window starting "
            f"at t={self.t!r}: the motion left its domain"
        )

    def _python_window(self):
        # Approximants outside the compiled kinds: one fixed window per step.
        coef, msg = self._anchor()
        if coef is None:
            return False, msg
        t = self.t
        t_new = self._window_end(self.tau)
        theta, v = self.approximant.eval_kernel(coef, t_new - t)
        return self._accept_window(coef, t, t_new, theta, v)

    def _dense_output_impl(self):
        if self._run is not None and self.anchors == "windows":
            starts, coefs, n = self._run
            return MBMWindowsDenseOutput(self.t_old, self.t, self._kind[0], starts, coefs, n, self.direction)
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


class MBMWindowsDenseOutput(DenseOutput):
    """Dense output of a step made of one or more windows: each window's anchored formula.

    Exact at both ends of the step: ``sol(t_old)`` is the first anchor and ``sol(t)``
    repeats the evaluation that produced the step's end state.
    """

    def __init__(self, t_old, t, kind, starts, coefs, n, direction):
        super().__init__(t_old, t)
        self.kind = kind
        self.starts = starts
        self.coefs = coefs
        self.n = n
        self.direction = float(direction)

    def _call_impl(self, t):
        tt = np.ascontiguousarray(np.atleast_1d(np.asarray(t, dtype=np.float64)))
        th = np.empty_like(tt)
        v = np.empty_like(tt)
        _kernels.evaluate_windows(self.kind, self.starts, self.coefs, self.n, self.direction, tt, th, v)
        if np.ndim(t) == 0:
            return np.array([th[0], v[0]])
        return np.vstack((th, v))
