"""The moving boundary method as :class:`scipy.integrate.OdeSolver` subclasses.

:class:`MBM` anchors at window starts, (3.29)–(3.31) of the second paper: the
approximant anchored at the state reached at the end of the previous window, the
windows taken by :func:`mbm.core.loop.run`.  :class:`MBMEventPoints` anchors at event
points, (3.32): θ = d or θ' = 0, located by CVODE ("hybrid") or by the formula
itself ("analytic").  Both are ``solve_ivp`` methods; ``MBM(..., anchors="events")``
builds the second.  The solvers know the model (β, γ, ω), the anchor state and an
approximant's kernels; they never look inside a formula.
"""

import functools
import inspect
import math
import sys
import warnings

import numpy as np
from scipy.integrate import DenseOutput, OdeSolver

from . import dense as _dense
from ..events import points as _points
from ..compile import warm as _warm
from ..core import loop, record, window
from ..core.controller import CONTROLLER_ADAPTIVE, plan_windows
from ..status import STATUS_ANCHOR, STATUS_MAX_WINDOWS, STATUS_PAUSED, STATUS_TOO_SMALL
from ..validate import (
    DEFAULT_MAX_WINDOWS,
    check_max_windows,
    check_window_budget,
    check_positive,
    check_tolerances,
    warn_extraneous,
)
from ..approximants import get_approximant
from ..approximants.taylor import HEADER as _TAYLOR_HEADER, N_EXTRA as _TAYLOR_EXTRA
from ..choice import auto_name, auto_reason
from ..model import Pendulum
from .probe import check_model, identify_model
from ..regimes import REGIME_NONE
from ..regimes.summary import run_summary

__all__ = ["MBM", "MBMEventPoints", "MBMDenseOutput", "MBMWindowsDenseOutput"]

# scipy's defaults for rtol and atol (solve_ivp's): MBM uses them when none is given.
DEFAULT_RTOL = 1e-3
DEFAULT_ATOL = 1e-6
# Window length used when neither ``tau`` nor ``first_step`` is given and the
# approximant has no error estimate: one tenth of the small-oscillation period 2π/ω
# keeps the paper's |βτ| ≪ 1 assumption (2.10) for β ≲ 1.
DEFAULT_TAU_PERIODS = 0.1
# Initial size of the per-step window buffers with windows_per_step=None (doubled as
# needed: amortized linear in the number of windows); a bounded step's store is
# allocated whole (at most WINDOWS_PER_STEP windows).
WINDOW_BUFFER = 16
# Most windows per step under windows_per_step="auto" when solve_ivp passes t_eval and
# no events: a step's Python (~10 µs: the step, solve_ivp's search of t_eval, the dense
# output's call) is then a few percent of its windows' (~0.5 µs each, Taylor), and the
# step's window store stays small (256 × 32 words = 64 KiB at Taylor degree 24).
WINDOWS_PER_STEP = 256
# Run-record templates kept, one per option set (kind, controller, tolerances, ...):
# building a record from scratch (record.new_run) costs ~5 µs, copying a template ~0.5.
RECORD_TEMPLATES = 256
# "auto" choices kept (one per β = γ = 0, drive, rtol, atol): the reason's formatting
# is ~1 µs, a visible part of a short run.
AUTO_CHOICES = 256
# Windows one compiled call may take with windows_per_step=None before Python regains
# control (where Ctrl-C is honoured); as mbm.frontends.solve.CALL_WINDOWS.
CALL_WINDOWS = 2**15
# Hybrid event-point mode (3.32): CVODE's tolerances for locating the events and the
# anchor states; tight, because the anchors carry CVODE's error into every window.
HYBRID_RTOL = 1e-10
HYBRID_ATOL = 1e-12
# Analytic event-point mode: longest window searched for the formula's next event,
# in small-oscillation periods (a libration has a turning point every half period;
# a rotation may have none, and then the window ends here).
EVENT_MAX_WINDOW_PERIODS = 1.0

# solve_ivp looks for events only at step ends, so a sign change inside a step and
# back is missed.  When it passes events, each step is one window no longer than this
# fraction of the small-oscillation period 2π/ω and sweeping at most this angle: an
# event function of the motion (θ mod 2π, θ', their combinations) then changes sign
# at most once per step, as it would for scipy's own steps.
EVENTS_WINDOW_PERIODS = 0.125
EVENTS_MAX_DTHETA = math.pi / 4
# How far up the stack solve_ivp's frame is looked for (MBM.__init__ and its helpers).
CALLER_FRAMES = 8

_W_T, _W_THETA, _W_STATUS, _W_NW = (record.WORD[k] for k in ("t", "theta", "status", "n_windows"))
# The words of a run record that differ between runs of one option set (_new_record).
_W_CALL = tuple(record.WORD[k] for k in ("beta", "gamma", "omega", "t", "theta", "v", "t_bound", "h_abs", "phi",
                                       "drive_amp", "drive_freq", "drive_phase"))
(_W_BETA, _W_GAMMA, _W_OMEGA, _, _, _W_V, _W_TBOUND, _W_H, _W_PHI, _W_AMP, _W_FREQ, _W_PHASE) = _W_CALL
assert record.WORD["v"] == _W_THETA + 1  # θ, θ' adjacent: the state is one slice of the record
_W_REGIME, _W_T_REGIME = record.WORD["regime"], record.WORD["t_regime"]

_PAUSED = STATUS_PAUSED
_NO_TIMES = np.empty(0)
_NO_OUT = np.empty((2, 0))
_NEVER = np.zeros(1, dtype=np.int64)
_NO_START = (0.0, 0.0, 0.0, 0.0, 0.0)  # a resumed run's (unused: mbm.core.loop's entries' contract)


class _MBMBase(OdeSolver):
    """What both anchorings share: validation, the model, the approximant.

    Attributes
    ----------
    model : Pendulum
        The identified or given model.
    approximant : Approximant
        The approximant in use.
    approximant_choice : (str, str)
        Its name and why ("auto" records the reason for its choice).
    max_step, rtol, atol : float
        As given (rtol raised to 100 eps with a warning, as scipy does).
    nfev : int
        Calls of ``fun`` (probing only).
    njev, nlu : int
        Always 0.
    """

    def __init__(self, fun, t0, y0, t_bound, *, approximant, model, max_step, rtol, atol, vectorized,
                 extraneous):
        for name in ("error_estimate", "sensitivities"):
            if name in extraneous:
                raise ValueError(
                    f"{name} is not available through solve_ivp, which builds its own result: use "
                    f"mbm.solve(model, t_span, y0, t_eval=..., {name}=...) or mbm.Integrator(model).solve(...), "
                    "which take the same windows and give the same y bit for bit")
        warn_extraneous(extraneous, stacklevel=4)
        super().__init__(fun, t0, y0, t_bound, vectorized, support_complex=False)
        if self.y.shape != (2,):
            raise ValueError(f"y0 must have shape (2,) (theta, theta'), got shape {self.y.shape}")
        theta0, v0 = self.y.tolist()
        if not (math.isfinite(theta0) and math.isfinite(v0)):
            raise ValueError(f"y0 must be finite, got {self.y!r}")
        if not (math.isfinite(t0) and math.isfinite(t_bound)):
            raise ValueError(f"t0 and t_bound must be finite, got {t0!r}, {t_bound!r}")
        self.max_step = check_positive("max_step", max_step, allow_inf=True)
        self.rtol, self.atol = check_tolerances(
            DEFAULT_RTOL if rtol is None else rtol, DEFAULT_ATOL if atol is None else atol, stacklevel=4
        )
        if model is None:
            model, nprobe = identify_model(fun, t0=float(t0), t_bound=float(t_bound))
        elif not isinstance(model, Pendulum):
            raise TypeError(f"model must be an mbm.Pendulum, got {type(model).__name__}")
        else:
            nprobe = check_model(fun, model, t0=float(t0), t_bound=float(t_bound))
        self.nfev += nprobe
        self.model = model
        if isinstance(approximant, str) and approximant == "auto":
            approximant, reason = _auto_choice(model.beta == 0.0 and model.gamma == 0.0 and not model.driven,
                                               model.driven, self.rtol, self.atol)
        else:
            reason = "chosen by the caller"
        self.approximant = get_approximant(approximant)
        self.approximant.check_drive(model)
        self.approximant.check_model(model)
        self.approximant_choice = (self.approximant.name, reason)
        # The formula of the last step (its dense output), set by _step_impl.
        self._coef = None

    def _anchor_at(self, y):
        """Coefficients anchored at state ``y``, or ``(None, message)``."""
        ap = self.approximant
        coef = ap.anchor_coefficients(self.model, y[0], y[1], self.t)
        if coef[0] != 0:
            msg = ap.status_messages.get(int(coef[0]), f"status {int(coef[0])}")
            return None, f"approximant {ap.name!r} cannot be anchored at t={self.t!r}: {msg}"
        return coef, None

    def _window_end(self, h_abs):
        t_new = self.t + self.direction * h_abs
        if self.direction * (t_new - self.t_bound) > 0:
            t_new = self.t_bound
        return t_new

    def _accept_window(self, coef, t, t_new, theta, v):
        # One Python-driven window: accept it, or fail cleanly (never NaN).
        if not (math.isfinite(theta) and math.isfinite(v)):
            return False, (
                f"approximant {self.approximant.name!r} produced a non-finite state over "
                f"the window [{t!r}, {t_new!r}]: the motion left its domain"
            )
        self._coef = coef
        self.t = t_new
        self.y = np.array([theta, v])
        return True, None

    def _dense_output_impl(self):
        return MBMDenseOutput(self.t_old, self.t, self.approximant, self._coef)


class MBM(_MBMBase):
    """Moving boundary method for θ'' + βθ' + ω² sin θ = γ, a drop-in `solve_ivp` method.

    The solution is advanced in steps that the method calls *windows*: at each
    window's start an analytic approximant is anchored at the current state (θ, θ'),
    and the state at the window's end is the formula's value there (the second
    paper's (3.29)–(3.31)).  The dense output on a window is that analytic formula.
    The step (window) lengths are adaptive, chosen from rtol/atol by the
    approximant's error estimate, or fixed at ``tau``, or (an exact flow) as long as
    ``max_step`` allows.

    Parameters
    ----------
    fun : callable
        Right-hand side ``fun(t, y)``: an :class:`mbm.Pendulum`, or any callable of
        the family, whose β, γ, ω and AC drive A sin(Ωt + φ) are identified by
        probing (see :func:`mbm.identify_model`).  A callable outside
        the family raises ``ValueError``.
    t0 : float
        Initial time.
    y0 : array_like, shape (2,)
        Initial state [θ₀, θ̇₀].
    t_bound : float
        Boundary time; the last step is cut to land on it exactly.
    tau : float, optional
        Fixed step (window) length τ > 0 (capped by ``max_step``).  Default: adaptive
        steps from rtol/atol when the approximant has an error estimate; one step as
        long as ``max_step`` allows for an exact flow; otherwise ``first_step`` if
        given, else ``0.1 · 2π/ω`` (with a warning if rtol/atol were given: they cannot
        change such fixed steps).
    approximant : str or Approximant, optional
        ``"auto"`` (default: the exact flow when β = γ = 0 without a drive, else the Taylor series)
        or a registered name (:func:`mbm.approximant_names`).
    model : Pendulum, optional
        The model; ``fun`` is checked against it (a ``ValueError`` names the
        parameters that differ).
    anchors : {"windows", "events"}, optional
        ``"windows"`` (default): this class.  ``"events"``: anchor at event points
        (3.32), an :class:`MBMEventPoints` is built instead, with the options it takes
        (``events_from="cvode"`` or ``"approximant"``: where the event points come
        from).
    windows_per_step : int, None or "auto", optional
        MBM's own steps (windows) per solve_ivp step.  ``"auto"`` (default): up to
        256 when solve_ivp passes ``t_eval`` and no
        ``events`` (less Python per window, and a step's window store stays
        bounded); one when it passes ``events`` or no ``t_eval`` (solve_ivp then
        reports every window end, as it reports every step of its own methods), or
        when the solver is stepped by hand.  An integer: at most that many.
        ``None``: all windows to ``t_bound`` in one step (least Python; the store,
        and the dense output, cover the whole run).  The windows, and so every
        output, are the same bits whatever the grouping.  solve_ivp looks for
        ``events`` only at step ends: when it passes events, MBM needs one window
        per step (``windows_per_step`` 1 or ``"auto"``, else ``ValueError``) and
        keeps every window within 1/8 of the period 2π/ω and an angle of π/4, so
        that an event function of the motion changes sign at most once per step (an
        exact flow's single window is cut into such steps).
    max_step : float, optional
        Largest step (window) allowed (default inf).
    first_step : float, optional
        First adaptive step (default: searched from the estimate), or τ for an
        approximant without an estimate when ``tau`` is not given.
    rtol, atol : float, optional
        Tolerances (default 1e-3, 1e-6, scipy's): local error per step (window)
        against ``atol + rtol·|y|``; rtol below 100 machine epsilons is raised to it
        with a warning, as scipy does.
    max_windows : int, optional
        Steps (windows) the whole run may take (default 10⁷); past it the solver
        fails with a message.  A run that would certainly take more than 100 times as
        many (a torque abs(γ) far above ω², a tiny ``tau``) is refused at
        construction with a ``ValueError`` naming the parameter causing it.
    vectorized : bool, optional
        Accepted for the interface; MBM does not call ``fun`` after probing.
    **extraneous
        Other options are ignored with a warning, as scipy's methods do.

    Attributes
    ----------
    model : Pendulum
        The identified or given model.
    approximant : Approximant
        The approximant in use.
    approximant_choice : (str, str)
        Its name and why ("auto" records the reason for its choice).
    max_step, rtol, atol : float
        As given (rtol raised to 100 eps with a warning, as scipy does).
    nfev : int
        Calls of ``fun`` (probing only).
    njev, nlu : int
        Always 0.
    adaptive : bool
        Whether the step lengths come from rtol/atol.
    tau : float or None
        The fixed step (window) length in use (None when adaptive).
    windows_per_step : int or None
        The windows per step in use (``"auto"`` resolved).
    for_events : bool
        Whether solve_ivp passed ``events`` (windows kept short, see above).
    n_windows : int
        Steps (windows) taken so far.
    regime : str or None
        The long-horizon regime the run switched to (``"locked"``, ``"running"``,
        ``"libration"`` or, driven, ``"phase-locked"``, see :doc:`/guide/regimes`; the
        dense output beyond it is the closed form or the stored period, shifted), or None.
    t_regime : float
        When it switched (nan before).
    period, mean_velocity : float
        The running cycle's T_c and ⟨θ'⟩ = ±2π/T_c; a libration's period and 0;
        phase-locked, q·2π/Ω and (p/q)Ω, p turns per q drive periods (nan otherwise;
        mean_velocity 0 when locked).
    """

    def __new__(cls, *args, anchors="windows", **kwargs):
        if anchors == "events" and cls is MBM:
            return MBMEventPoints(*args, **kwargs)
        if anchors not in ("windows", "events"):
            raise ValueError(f"anchors must be 'windows' or 'events', got {anchors!r}")
        return super().__new__(cls)

    def __init__(self, fun, t0, y0, t_bound, *, tau=None, approximant="auto", model=None,
                 anchors="windows", windows_per_step="auto", max_step=np.inf, first_step=None,
                 rtol=None, atol=None, max_windows=DEFAULT_MAX_WINDOWS, vectorized=False,
                 **extraneous):
        tol_given = rtol is not None or atol is not None
        super().__init__(fun, t0, y0, t_bound, approximant=approximant, model=model, max_step=max_step, rtol=rtol,
                         atol=atol, vectorized=vectorized, extraneous=extraneous)
        if first_step is not None:
            first_step = check_positive("first_step", first_step)
        if tau is not None:
            tau = min(check_positive("tau", tau), self.max_step)
        wps = _check_windows_per_step(windows_per_step)
        self._kind = window.kind_of(self.approximant)
        # Kind "taylor" at its default degree (its dense output's own entries).
        self._simd = (self._kind is not None and self._kind[0] == window.KIND_TAYLOR
                      and self._kind[1] == _dense.SIMD_ORDER)
        #: Whether solve_ivp passed events: then each step is one short window.
        caller = _caller_solve_ivp()
        self.for_events = caller is not None and caller.get("events") is not None
        if wps == "auto":
            # Every window end a step when solve_ivp reports the step ends (no t_eval) or
            # looks for events, or when no solve_ivp drives this solver.
            wps = WINDOWS_PER_STEP if caller is not None and caller.get("t_eval") is not None \
                and not self.for_events else 1
        self.windows_per_step = wps
        max_dtheta, run_max_step = math.inf, self.max_step
        if self.for_events:
            if self.windows_per_step != 1:
                raise ValueError(
                    f"windows_per_step={windows_per_step!r} with events: solve_ivp looks for "
                    "events only at step ends and would miss those inside a step of several "
                    "windows; use windows_per_step=1 or 'auto' (the default) with events"
                )
            max_dtheta = EVENTS_MAX_DTHETA
            run_max_step = min(self.max_step, EVENTS_WINDOW_PERIODS * 2 * math.pi / self.model.omega)
            if tau is not None:
                tau = min(tau, run_max_step)
        check_window_budget(self.model.beta, self.model.gamma, self.model.omega, self.model.drive_amplitude,
                            float(t0), float(t_bound), float(self.y[1]), tau, max_step=run_max_step,
                            max_windows=check_max_windows(max_windows), exact=self.approximant.exact)
        plan = plan_windows(self.approximant, tau, run_max_step, abs(t_bound - t0))
        if plan is None:
            if tol_given:
                warnings.warn(
                    f"approximant {self.approximant.name!r} has no error estimate: rtol and "
                    "atol do not change its windows; pass tau, or use an error-controlled "
                    "approximant (see mbm.approximant_names())",
                    stacklevel=3,
                )
            tau = first_step if first_step is not None else DEFAULT_TAU_PERIODS * 2 * math.pi / self.model.omega
            plan = plan_windows(self.approximant, min(tau, run_max_step), run_max_step, 0.0)
        controller, h_abs, error_order = plan
        self.adaptive = controller == CONTROLLER_ADAPTIVE
        self.tau = None if self.adaptive else h_abs
        if self.adaptive and first_step is not None:
            h_abs = min(first_step, run_max_step)
        self.n_windows = 0
        self.regime, self.t_regime = None, math.nan
        self.period = self.mean_velocity = math.nan
        # The run record of the compiled loop (None: windows driven from Python, one
        # per step, for approximants without a compiled kind), and its words as float64
        # and int64 (fast field access).
        self._run = self._words = self._ints = self._buf = None
        # Width of the window store (the approximant's coefficient vector), the window
        # store's size for the next step, and the last step's windows (starts, θ at the
        # starts, coefficients, count) for its dense output.
        self._width = None
        self._store_size = None
        self._windows = None
        if self._kind is not None:
            # A step's whole store at once where it is bounded (a step that fills it pauses to
            # grow it: a pause and a copy each time).
            self._store_size = min(wps, WINDOWS_PER_STEP) if wps else WINDOW_BUFFER
            theta0, v0 = self.y.tolist()
            self._words = _new_record(
                self.model, record.RunState(float(self.t), theta0, v0, float(self.t_bound)),
                record.RunControl(kind=self._kind[0], karg=self._kind[1], controller=controller, h_abs=h_abs,
                                  max_step=run_max_step, max_dtheta=max_dtheta, rtol=self.rtol, atol=self.atol,
                                  error_order=error_order),
                check_max_windows(max_windows), 0 if wps else CALL_WINDOWS,
            )
            self._run = np.ndarray(1, record.RUN, self._words)
            self._buf = self._words.reshape(1, -1)  # as the loop's entries take the record
            self._ints = np.ndarray(self._words.shape, np.int64, self._words)
            # The entry of the run's regime set (loop.runner_for), chosen again after a
            # pause: a regime switch resumes through its own set's entry.
            self._runner = loop.runner_for(self._run[0])
            # From a cold cache, a helper process compiles the kernels beside it (mbm.compile.warm).
            _warm.prefetch("ivp", self._runner, None if self._kind[0] == window.KIND_TAYLOR else self._kind[0])
            # After the helper's start: the width may compile the kind's anchor kernel.
            self._width = _coefficient_width(self.approximant, self._kind[1], self.model, self.y)

    def _step_impl(self):
        if self._run is None:
            return self._python_window()
        p, words, ints, run = self._run, self._words, self._ints, self._runner
        buf = self._buf
        # The store: windows_per_step windows at most (None: unbounded), from a size that
        # doubles while the loop fills it (a short run allocates little).
        limit = self.windows_per_step
        size = self._store_size if limit is None or limit > WINDOW_BUFFER else limit
        win_t = np.empty(size + 1)
        win_y = np.empty((size + 1, 2))
        win_coef = np.empty((size, self._width))
        n = run(buf, False, _NO_START, (_NO_TIMES, _NO_OUT, win_t, win_y, win_coef, _NEVER))
        # Paused with the store full (or, windows_per_step=None, after CALL_WINDOWS):
        # go on in a larger store (twice the windows so far and a buffer more), up to
        # the limit.
        while ints.item(_W_STATUS) == _PAUSED and (limit is None or n < limit):
            if n == size:
                size = 2 * (n + WINDOW_BUFFER) if limit is None else min(2 * (n + WINDOW_BUFFER), limit)
                win_t = np.concatenate((win_t[: n + 1], np.empty(size - n)))
                win_y = np.concatenate((win_y[: n + 1], np.empty((size - n, 2))))
                win_coef = np.concatenate((win_coef[:n], np.empty((size - n, self._width))))
            run = self._runner = loop.runner_for(p[0])
            n += run(buf, False, _NO_START, (_NO_TIMES, _NO_OUT, win_t[n:], win_y[n:], win_coef[n:], _NEVER))
        self._store_size = size
        self.n_windows = ints.item(_W_NW)
        self.regime, self.period, self.mean_velocity = run_summary(words)
        self.t_regime = words.item(_W_T_REGIME)
        if n == 0:
            return False, self._failure(ints.item(_W_STATUS))
        # θ at the starts: a view of the store's column (the evaluator takes strides).
        self._windows = (win_t[: n + 1], win_y[: n + 1, 0], win_coef[:n], n)
        self.t = words.item(_W_T)
        self.y = words[_W_THETA:_W_THETA + 2].copy()
        # A failure after some accepted windows ends this step early; the next step reports it.
        return True, None

    def _failure(self, status):
        ap = self.approximant
        if status == STATUS_ANCHOR:
            coef, msg = self._anchor_at(self.y)
            return msg or f"approximant {ap.name!r} cannot be anchored at t={self.t!r}"
        if status == STATUS_TOO_SMALL:
            return (
                f"required window at t={self.t!r} is below the spacing of floating point "
                f"numbers: approximant {ap.name!r} cannot meet rtol={self.rtol!r}, "
                f"atol={self.atol!r} here"
            )
        if status == STATUS_MAX_WINDOWS:
            return (
                f"max_windows={int(self._run[0]['progress']['max_windows'])} windows taken at t={self.t!r} "
                "before t_bound: raise max_windows for a longer run"
            )
        return (
            f"approximant {ap.name!r} produced a non-finite state over the window starting "
            f"at t={self.t!r}: the motion left its domain"
        )

    def _python_window(self):
        # Approximants outside the compiled kinds: one fixed window per step.
        coef, msg = self._anchor_at(self.y)
        if coef is None:
            return False, msg
        t = self.t
        t_new = self._window_end(self.tau)
        theta, v = self.approximant.eval_kernel(coef, t_new - t)
        self.n_windows += 1
        return self._accept_window(coef, t, t_new, theta, v)

    def _dense_output_impl(self):
        if self._run is not None:
            starts, start_theta, coefs, n = self._windows
            return MBMWindowsDenseOutput(self.t_old, self.t, self._kind[0], starts, start_theta, coefs, n,
                                         direction=self.direction, regime=self._ints.item(_W_REGIME),
                                         simd=self._simd)
        return MBMDenseOutput(self.t_old, self.t, self.approximant, self._coef)


def _caller_solve_ivp():
    """The local variables of the scipy ``solve_ivp`` call building this solver, or None.

    solve_ivp does not hand its ``events`` and ``t_eval`` to its method; MBM reads
    them from solve_ivp's frame: ``events`` so that it keeps its steps short enough
    for them (never dropping one silently), ``t_eval`` to know whether solve_ivp
    reports the step ends (``windows_per_step="auto"``).  tests/frontends/test_solver.py and
    tests/frontends/test_steps.py check that this works on the installed scipy.
    """
    frame = sys._getframe(1)
    for _ in range(CALLER_FRAMES):
        frame = frame.f_back
        if frame is None:
            return None
        code = frame.f_code
        if code.co_name == "solve_ivp" and "scipy" in code.co_filename:
            return frame.f_locals
    return None


def _check_windows_per_step(windows_per_step):
    if windows_per_step is None or (isinstance(windows_per_step, str) and windows_per_step == "auto"):
        return windows_per_step
    if (isinstance(windows_per_step, bool) or not isinstance(windows_per_step, (int, np.integer))
            or windows_per_step < 1):
        raise ValueError(
            f"windows_per_step must be an integer >= 1, None or 'auto', got {windows_per_step!r}"
        )
    return int(windows_per_step)


@functools.lru_cache(maxsize=AUTO_CHOICES)
def _auto_choice(undamped, driven, rtol, atol):
    """:func:`mbm.choice.choose_approximant`'s ``(name, reason)``, from the facts its
    rule reads (β = γ = 0 without a drive, the drive, the tolerances); cached, as
    :func:`mbm.choice.auto_reason` allows: formatting the reason is ~1 µs a call."""
    return auto_name(undamped), auto_reason(undamped, rtol, atol, driven)


# Coefficient-vector sizes by (anchor kernel, kind argument), see _coefficient_width.
_WIDTHS = {}
# Run-record templates by option set, see _new_record.
_TEMPLATES = {}


def _coefficient_width(approximant, karg, model, y):
    """Columns of the window store: the size of the approximant's coefficient vector.

    The Taylor kinds' size is their layout's; the other kinds are anchored once per
    (anchor kernel, kind argument) at the state ``y`` first asked for: a compiled
    kind's coefficient vector has a size set by its degree alone, whatever the model
    and state (tests/frontends/test_steps.py checks every registered one).
    """
    if window.kind_of(approximant)[0] == window.KIND_TAYLOR:
        # The Taylor layout (taylor.py): the header, then a_0 .. a_{N + N_EXTRA}; stated
        # rather than anchored, so a first solve_ivp does not compile an anchor kernel
        # only to measure it.
        return _TAYLOR_HEADER + karg + 1 + _TAYLOR_EXTRA
    kernel = approximant.anchor_kernel
    # Keyed by id (a numba dispatcher hashes slowly); the entry holds the kernel, so
    # its id is not reused while the entry lives.
    entry = _WIDTHS.get((id(kernel), karg))
    if entry is None or entry[0] is not kernel:
        beta, gamma, omega = model.params
        entry = (kernel, int(kernel(beta, gamma, omega, y[0], y[1]).size))
        _WIDTHS[(id(kernel), karg)] = entry
    return entry[1]


def _new_record(model, start, control, max_windows, call_windows):
    """The float64 words of a fresh run record: those of :func:`mbm.core.record.new_run`'s record,
    bit for bit (tests/frontends/test_steps.py).

    ``start`` is the run's :class:`~mbm.core.record.RunState`, ``control`` its
    :class:`~mbm.core.record.RunControl`.  The words set by the option set (kind,
    controller, tolerances, budgets, whether there is a drive: regimes off) are copied
    from a template that new_run builds once per option set (:data:`RECORD_TEMPLATES`
    kept); the words of this run (``_W_CALL``: the model, t0, the state, t_bound, the
    first window, φ = θ₀ and the drive) are set.
    """
    amp, freq, phase = model.drive
    # The option set's key: the control group less this run's first window (h_abs), as
    # slices (a named tuple's _replace costs a microsecond a call).
    key = (control[:3], control[4:], max_windows, call_windows, amp != 0.0)
    template = _TEMPLATES.get(key)
    if template is None:
        if len(_TEMPLATES) >= RECORD_TEMPLATES:
            _TEMPLATES.clear()
        options = control._replace(h_abs=0.0)
        template = record.new_run(
            record.RunModel(0.0, 0.0, 1.0, drive_amp=1.0 if amp != 0.0 else 0.0), record.RunState(0.0, 0.0, 0.0, 0.0),
            options, max_windows, call_windows=call_windows,
        ).view(np.float64).copy()
        _TEMPLATES[key] = template
    words = template.copy()
    # One item at a time: cheaper than a fancy-indexed assignment of the twelve.
    words[_W_BETA], words[_W_GAMMA], words[_W_OMEGA] = model.params
    words[_W_T], words[_W_THETA], words[_W_V], words[_W_TBOUND] = start
    words[_W_H], words[_W_PHI] = control.h_abs, start.theta
    words[_W_AMP], words[_W_FREQ], words[_W_PHASE] = amp, freq, phase
    return words


def _init_signature(cls):
    """``cls.__init__``'s signature without ``self``: what ``cls(...)`` takes."""
    sig = inspect.signature(cls.__init__)
    return sig.replace(parameters=list(sig.parameters.values())[1:])


# MBM.__new__ takes (*args, **kwargs) to route anchors="events": state the options of
# __init__ for help(), Sphinx and numpydoc.
MBM.__signature__ = _init_signature(MBM)


class MBMEventPoints(_MBMBase):
    """The event-point moving boundary method (3.32), a `solve_ivp` method.

    Steps (windows) end where θ = d (the approximant's zero-crossing surface, the
    papers' event points) or θ' = 0, as the approximant's ``anchors`` allow.  ``events_from="cvode"`` (hybrid): the event points and the anchor states
    there come from CVODE, so each window anchors at the numerical solution's state
    φ(τ_n) (the dense output jumps there by the previous window's error);
    ``"approximant"``: each window's formula finds its own next event and the next
    window anchors at the formula's state there.

    Parameters
    ----------
    fun, t0, y0, t_bound, approximant, model
        As in :class:`MBM`.
    anchors : {"events"}, optional
        Accepted so that ``MBM(..., anchors="events")`` and this class take the same
        options.
    events_from : {"cvode", "approximant"}, optional
        Where the event points come from (default ``"cvode"``).
    max_step, rtol, atol, vectorized, **extraneous
        As in :class:`MBM` (rtol and atol are validated; the windows do not depend on
        them).

    Attributes
    ----------
    model, approximant, approximant_choice, max_step, rtol, atol, nfev, njev, nlu
        See :class:`MBM`.
    events_from : str
    n_windows : int
        Windows taken so far.
    """

    def __init__(self, fun, t0, y0, t_bound, *, approximant="auto", model=None, anchors="events",
                 events_from="cvode", max_step=np.inf, rtol=None, atol=None, vectorized=False,
                 **extraneous):
        if anchors != "events":
            raise ValueError(f"MBMEventPoints anchors at events, got anchors={anchors!r}")
        if events_from not in ("cvode", "approximant"):
            raise ValueError(f"events_from must be 'cvode' or 'approximant', got {events_from!r}")
        super().__init__(fun, t0, y0, t_bound, approximant=approximant, model=model, max_step=max_step, rtol=rtol,
                         atol=atol, vectorized=vectorized, extraneous=extraneous)
        if self.model.driven:
            raise ValueError(
                f"anchors='events' cannot take the AC drive (drive_amplitude="
                f"{self.model.drive_amplitude!r}): its event points and windows assume the "
                "autonomous equation; use anchors='windows' (the default) with approximant "
                "'taylor' or 'auto'"
            )
        self.events_from = events_from
        self.n_windows = 0
        self._event_d, self._event_kinds = self._surfaces()
        # The state the next window anchors at when it is not the last window's end
        # (hybrid mode: CVODE's state at the event point).
        self._next_anchor = None
        self._event_times, self._event_states = [], []
        self._event_index = 0
        if events_from == "cvode" and t_bound != t0:
            te, ye, _ = _points.hybrid_event_points(
                self.model, (float(t0), float(t_bound)), self.y, self._event_d, kinds=self._event_kinds,
                rtol=HYBRID_RTOL, atol=HYBRID_ATOL,
            )
            self._event_times, self._event_states = list(te), [np.array(y) for y in ye]

    def _surfaces(self):
        """The event surface d and kinds the approximant anchors at; y0 must be one."""
        ap = self.approximant
        kind = ap.anchors
        d = _points.event_function_d(self.model, ap)
        if kind == "any":
            kinds = ("crossing", "turning") if d is not None else ("turning",)
        elif kind == "zero-crossing":
            if d is None:
                raise ValueError(
                    f"approximant {ap.name!r} anchors only at zero crossings theta = d, and "
                    f"d does not exist for gamma/omega**2 = {self.model.gamma / self.model.omega**2!r}"
                )
            kinds = ("crossing",)
        elif kind == "turning-point":
            kinds = ("turning",)
        else:
            raise ValueError(f"approximant {ap.name!r} declares unknown anchors {kind!r}")
        # The first window anchors at y0 itself: it must be an anchor the approximant accepts.
        y0 = self.y
        if kind == "zero-crossing" and abs(y0[0] - d) > _points.ON_SURFACE_TOL:
            raise ValueError(
                f"approximant {ap.name!r} anchors only at zero crossings theta = d = {d!r}; "
                f"y0[0] = {y0[0]!r} is not one"
            )
        if kind == "turning-point" and abs(y0[1]) > _points.ON_SURFACE_TOL:
            raise ValueError(
                f"approximant {ap.name!r} anchors only at turning points theta' = 0; "
                f"y0[1] = {y0[1]!r} is not one"
            )
        return d, kinds

    def _step_impl(self):
        ap = self.approximant
        t = self.t
        coef, msg = self._anchor_at(self.y if self._next_anchor is None else self._next_anchor)
        if coef is None:
            return False, msg
        if self.events_from == "cvode":
            te, ye, i = self._event_times, self._event_states, self._event_index
            t_new = te[i] if i < len(te) and self.direction * (te[i] - t) > 0 else self.t_bound
            if self.direction * (t_new - t) > self.max_step:
                t_new = t + self.direction * self.max_step
            if i < len(te) and t_new == te[i]:
                # (3.32): the next window anchors at the numerical solution's state
                # φ(τ_n), not at this window's end value — the method's jump.
                self._next_anchor = ye[i]
                self._event_index = i + 1
            else:
                self._next_anchor = None
        else:
            span = abs(self.t_bound - t)
            t_max = min(span, self.max_step, EVENT_MAX_WINDOW_PERIODS * 2 * math.pi / self.model.omega)
            te, _ = _points.next_event_analytic(
                ap.eval_kernel, coef, self._event_d, self._event_kinds,
                self.direction * t_max, int(self.direction), omega=self.model.omega,
            )
            t_new = t + te if math.isfinite(te) else self._window_end(t_max)
        theta, v = ap.eval_kernel(coef, t_new - t)
        self.n_windows += 1
        return self._accept_window(coef, t, t_new, theta, v)


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
    repeats the evaluation that produced the step's end state.  Evaluated by
    :mod:`mbm.frontends.dense` (the values of :func:`mbm.core.stored.evaluate_windows`, bit for bit).

    Parameters
    ----------
    t_old, t : float
        The step's start and end.
    kind : int
        The windows' kind id (:data:`mbm.core.window.COMPILED_KINDS`).
    starts : ndarray, shape (n + 1,)
        Window starts and the last window's end.
    start_theta : ndarray, shape (n + 1,)
        θ at ``starts`` (a strided view is accepted).
    coefs : ndarray, shape (n, width)
        The windows' coefficient vectors.
    n : int
        Windows.
    direction : float
        +1 or −1.
    regime : int, optional
        The run's regime code (``mbm.regimes.REGIME_*``) at the step's end: which
        stored period its windows may hold (default: none).
    simd : bool, optional
        Whether the run is of kind "taylor" at its default degree (its stored period is
        then re-taken by the vector kernel; default False: any degree).
    """

    def __init__(self, t_old, t, kind, starts, start_theta, coefs, n, *, direction, regime=REGIME_NONE, simd=False):
        super().__init__(t_old, t)
        self.kind = kind
        self.starts = starts
        self.start_theta = start_theta
        self.coefs = coefs
        self.n = n
        self.direction = float(direction)
        self._into, self._at = _dense.evaluators(kind, _dense.dense_set(regime), simd)

    def _call_impl(self, t):
        if t.ndim == 0:
            return self._at(self.kind, self.starts, self.start_theta, self.coefs, self.n, self.direction, float(t))
        t = np.ascontiguousarray(t, dtype=np.float64)
        out = np.empty((2, t.size))
        self._into(self.kind, self.starts, self.start_theta, self.coefs, self.n, self.direction, t, out)
        return out
