"""The compiled path: whole moving-boundary runs with no Python per window.

:func:`solve` runs one scene, :func:`~mbm.frontends.batch.solve_batch` many in parallel
(``numba.prange``).  Both are thin over the loop of :mod:`mbm.core.loop`, the one
:class:`mbm.MBM` calls, so their answers equal the solve_ivp path's bit for bit for
the same options.
"""

import functools
import math

import numba
import numpy as np

from ..compile import warm as _warm
from ..core import chains, loop, record, window
from ..core.controller import CONTROLLER_ADAPTIVE, CONTROLLER_FIXED, plan_windows
from ..status import STATUS_MESSAGES, STATUS_OK, STATUS_PAUSED
from ..validate import (
    DEFAULT_MAX_WINDOWS,
    RTOL_FLOOR,
    _FLOAT64,
    as_t_eval,
    check_max_windows,
    check_positive,
    check_rule,
    check_span,
    check_state,
    check_t_eval,
    check_tolerances,
    check_window_budget,
    t_eval_error,
)
from ..approximants import get_approximant
from ..choice import auto_name, auto_reason
from ..events.compiled import solve_events
from ..model import Pendulum
from ..result import SolveResult
from .. import tangent as _tangent
from ..tangent.transport import transport as _TRANSPORT
from ..regimes import REGIME_NONE
from ..regimes.summary import run_summary

__all__ = ["Integrator", "solve", "solve_njit"]

# Initial capacity of the window-end record when no t_eval is given (doubled as needed).
ENDS_CAPACITY = 64
# The window store's first capacity for the tangent pass (it stores coefficients too): a
# common run fits without a pause to grow it.
TANGENT_CAPACITY = 1024
# Windows one compiled call of solve may take before Python regains control (where
# Ctrl-C is honoured): 2^15 windows are 10–300 ms (0.3 µs a Taylor window, ~10 µs a
# splitting's), and a call costs ~1 µs, so the chunking costs nothing measurable.
CALL_WINDOWS = 2**15
# Integrators mbm.solve keeps for repeated option sets (models × tolerances of a
# sweep or a benchmark loop): building one is most of a short run's fixed cost.
INTEGRATOR_CACHE = 256

_W = record.WORD
_KIND_TAYLOR, _KIND_EXACT = window.KIND_TAYLOR, window.KIND_EXACT
_KIND_SALAS_TORQUE, _KIND_SPLIT = window.KIND_SALAS_TORQUE, window.KIND_SPLIT
_W_H = _W["h_abs"]
_W_STATUS, _W_J, _W_NW, _W_REGIME, _W_T_REGIME = (_W[k] for k in ("status", "j", "n_windows", "regime", "t_regime"))
# The loop entry's arguments a call leaves empty: no outputs, no window store; never
# cancelled (mbm.solve is chunked instead, CALL_WINDOWS).
_NO_T, _NO_OUT, _NO_Y, _NO_COEF = np.empty(0), np.empty((2, 0)), np.empty((0, 2)), np.empty((0, 0))
_NEVER = np.zeros(1, np.int64)
# Bound once: Integrator.solve's fast path reads no module attributes (each read is a
# few percent of its fixed cost).
_PAUSED, _OK, _MESSAGES = STATUS_PAUSED, STATUS_OK, STATUS_MESSAGES
_regime_set = loop.regime_set.py_func
_NDARRAY, _EMPTY, _NAN = np.ndarray, np.empty, math.nan


def compiled(ap):
    """``(approximant, kind, karg)`` of an approximant the compiled loop runs, or a ValueError."""
    kk = window.kind_of(ap)
    if kk is None:
        raise ValueError(
            f"approximant {ap.name!r} has no compiled kernel; mbm.solve runs 'auto', 'taylor*', "
            "'split*', 'belendez' and 'salas-torque' (use solve_ivp(method=mbm.MBM) for the others)"
        )
    return ap, kk[0], kk[1]


@functools.lru_cache(maxsize=64)
def _resolve(name, undamped):
    """:func:`compiled` of a registered name (cached: per-call overhead of :func:`solve`)."""
    return compiled(get_approximant(auto_name(undamped) if name == "auto" else name))


def _approximant(approximant, model):
    undamped = model.beta == 0.0 and model.gamma == 0.0 and not model.driven
    if isinstance(approximant, str):
        return _resolve(approximant, undamped)
    return compiled(get_approximant(approximant))


def _plan(ap, tau, max_step, t0, t1):
    if tau is not None:
        tau = check_positive("tau", tau)
    plan = plan_windows(ap, tau, max_step, abs(t1 - t0))
    if plan is None:
        raise ValueError(f"approximant {ap.name!r} has no error estimate: pass tau")
    return plan


@functools.lru_cache(maxsize=256)
def _auto_reason(undamped, rtol, atol, driven=False):
    # Cached: formatting the sentence on every call was a visible part of the fixed cost.
    return auto_reason(undamped, rtol, atol, driven)


def _reason(model, rtol, atol, approximant):
    if isinstance(approximant, str) and approximant == "auto":
        if model.driven:
            return _auto_reason(False, float(rtol), float(atol), True)
        return _auto_reason(model.beta == 0.0 and model.gamma == 0.0, float(rtol), float(atol))
    return "chosen by the caller"


# The types of a state's entries taken without check_state's conversion (bool, str,
# complex and the rest go through it).
_REAL_TYPES = (float, int, np.float64)


def _state(y0):
    """(θ₀, θ̇₀) as floats: a fast path for a list, tuple or array of two finite reals."""
    if type(y0) is np.ndarray and y0.shape == (2,) and y0.dtype is _FLOAT64:
        theta0, v0 = float(y0[0]), float(y0[1])
        if math.isfinite(theta0) and math.isfinite(v0):
            return theta0, v0
    elif type(y0) in (list, tuple) and len(y0) == 2:
        theta0, v0 = y0
        if type(theta0) in _REAL_TYPES and type(v0) in _REAL_TYPES:
            theta0, v0 = float(theta0), float(v0)
            if math.isfinite(theta0) and math.isfinite(v0):
                return theta0, v0
    y = check_state("y0", y0)  # raises, naming what is wrong
    return float(y[0]), float(y[1])


# Integrator.solve calls the loop's entry itself (loop.RUNNERS: one compiled entry per
# kind and regime set, shared with solve_ivp's MBM), with a buffer of two rows of
# float64 words: row 0 the Integrator's template record, row 1 the call's record.  A
# fresh call checks t_eval (as check_t_eval; nothing is run when it fails), copies the
# template into row 1, sets the span, the state and the first window and runs the loop
# (mbm.core.loop._runner); a resumed one goes on from row 1 as it stands.  The status,
# counts and regime are read back from row 1's int64 view.  One dispatch per call:
# benchmarks/overheads.py.


def _entry_of(words):
    # The entry that runs the record in ``words`` (float64 words of a RUN) now.
    return loop.runner_for(words.view(record.RUN)[0])


def _entry_at(integrator, regime):
    # The entry of an Integrator's run once it is in ``regime`` (the record's other
    # fields that choose the set are the Integrator's, fixed): the regime's set's entry.
    return loop.entry_for(integrator._kind, _regime_set(*integrator._set_fields, regime), integrator._karg)


# The keys of a result, in their order (its repr's); the constant ones are filled in
# per Integrator (Integrator._base).
_RESULT_KEYS = ("t", "y", "success", "status", "message", "n_windows", "approximant", "reason",
                "regime", "t_regime", "period", "mean_velocity", "winding")


class Integrator:
    """A prepared moving-boundary solver for one model: validated once, solved many times.

    Everything that does not depend on the span or the initial state (the model, the
    tolerances, the approximant, the step-size control) is checked and resolved here,
    so :meth:`solve` costs a few microseconds before its first step.  :func:`solve`
    is the one-shot form (``Integrator(model, ...).solve(t_span, y0, t_eval)``).

    Parameters
    ----------
    model : Pendulum
    rtol, atol : float, optional
        Tolerances, with scipy's meaning (local error per adaptive step, or window,
        against ``atol + rtol·|y|``); rtol below 100 machine epsilons is raised to
        that floor with a warning, as scipy does.
    approximant : str or Approximant, optional
        ``"auto"`` (default: the exact flow when β = γ = 0 without a drive, else the Taylor series) or
        one with a compiled kernel (``taylor*``, ``split*``, ``sbab*``, ``belendez``,
        ``salas-torque``).
    tau : float, optional
        Fixed step (window) length; default: adaptive steps from rtol/atol (one step
        for an exact flow).
    max_step : float, optional
        Longest step (window).
    max_windows : int, optional
        Steps (windows) one run may take (default 10⁷, seconds of compute); past it
        the run stops with the outputs it reached and ``status`` 4 (``MAX_WINDOWS``,
        :doc:`/guide/statuses`).

    Attributes
    ----------
    model : Pendulum
    approximant : Approximant
        The approximant in use ("auto" resolved).
    reason : str
        Why it is used ("auto" records its rule).
    rtol, atol, max_step : float

    Raises
    ------
    ValueError, TypeError
        For invalid arguments (naming the argument), an approximant without a
        compiled kernel or outside the model's domain.

    Examples
    --------
    >>> import numpy as np, mbm
    >>> ig = mbm.Integrator(mbm.Pendulum(0.1, 0.3), rtol=1e-9, atol=1e-9)
    >>> for theta0 in (0.1, 0.2):
    ...     r = ig.solve((0.0, 10.0), [theta0, 0.0], t_eval=np.linspace(0.0, 10.0, 5))
    """

    def __init__(self, model, *, rtol=1e-6, atol=1e-9, approximant="auto", tau=None,
                 max_step=np.inf, max_windows=DEFAULT_MAX_WINDOWS):
        if not isinstance(model, Pendulum):
            raise TypeError(f"model must be an mbm.Pendulum, got {type(model).__name__}")
        self.model = model
        self.rtol, self.atol = check_tolerances(rtol, atol, stacklevel=3)
        self.max_step = check_positive("max_step", max_step, allow_inf=True)
        ap, kind, karg = _approximant(approximant, model)
        ap.check_drive(model)
        ap.check_model(model)
        self.approximant = ap
        self.reason = _reason(model, self.rtol, self.atol, approximant)
        self._tau = None if tau is None else check_positive("tau", tau)
        # The plan of a span of length 0 (only an exact flow's h depends on the span).
        self._plan = _plan(ap, self._tau, self.max_step, 0.0, 0.0)
        self._span_plan = self._tau is None and ap.exact and not math.isfinite(self.max_step)
        controller, h_abs, error_order = self._plan
        self._max_windows = check_max_windows(max_windows)
        beta, gamma, omega = model.params
        amp, freq, phase = model.drive
        template = record.new_run(
            record.RunModel(beta, gamma, omega, amp, freq, phase), record.RunState(0.0, 0.0, 0.0, 0.0),
            record.RunControl(kind=kind, karg=karg, controller=controller, h_abs=h_abs, max_step=self.max_step,
                              max_dtheta=math.inf, rtol=self.rtol, atol=self.atol, error_order=error_order),
            self._max_windows, CALL_WINDOWS)
        # The record's words as float64: each call's compiled entry copies them into
        # words of its own.
        self._words = template.view(np.float64).copy()
        self._kind, self._karg = kind, karg
        # The entry of a fresh run (a regime switch resumes through its set's own).
        self._entry = _entry_of(self._words)
        # From a cold cache, a helper process compiles the kernels beside it (mbm.compile.warm).
        _warm.prefetch("solve", self._entry, None if kind == _KIND_TAYLOR else kind)
        run0 = template[0]
        self._set_fields = (kind, int(run0["control"]["controller"]), int(run0["switch"]["regimes"]),
                            float(run0["model"]["beta"]), float(run0["model"]["drive_amp"]))
        self._h = float(self._words[_W_H])
        # Buffers ready for a call (row 0 these words, row 1 the call's: see _entry_of),
        # taken and put back per call (list pop/append are atomic, so threads sharing
        # an Integrator each get their own).
        self._records = []
        self._coef_stores = []  # the tangent pass's window-coefficient stores (_run_stored)
        # A result's entries that are the same for every call (copied per call: a
        # dict copy and ten stores are cheaper than a dict built from keywords).
        self._base = dict.fromkeys(_RESULT_KEYS)
        self._base.update(approximant=ap.name, reason=self.reason)

    def solve(self, t_span, y0, t_eval=None, wrap=False, events=None, max_events=None, *, error_estimate=False,
              sensitivities=None):
        """Solve from ``y0`` over ``t_span``: what :func:`solve` returns.

        Parameters
        ----------
        t_span : (float, float)
            (t0, t_bound); t_bound < t0 integrates backwards.
        y0 : array_like, shape (2,)
            [θ₀, θ̇₀].
        t_eval : array_like, optional
            Output times, sorted in the direction of integration; default: the end
            of every step.
        wrap : bool, optional
            θ wrapped to (−π, π], with its winding count (see :func:`solve`).
        events : Event, numba.njit function, or sequence of them, optional
            Built-in events, or event functions g(t, θ, θ'), located inside each step
            (see :func:`solve`); needs a Taylor approximant.
        max_events : int, optional
            Occurrences of each event stored (see :func:`solve`); default all.
        error_estimate : bool, optional
            Add ``error_estimate``, an estimate of y_computed − y_true at each output
            (see :func:`solve`).
        sensitivities : sequence of str, optional
            Add ``sensitivities`` ∂y/∂p for these names (see :func:`solve`).

        Returns
        -------
        SolveResult
            See :func:`solve`.
        """
        t0, t1 = check_span(t_span)
        theta0, v0 = _state(y0)
        _check_budget(self, t0, t1, v0)
        tangent = _tangent_request(error_estimate, sensitivities, events)
        if events is not None:
            return solve_events(self, t0, t1, theta0, v0, t_eval, wrap, events, max_events=max_events)
        if max_events is not None:
            raise ValueError("max_events needs events")
        return self._solve(t0, t1, theta0, v0, t_eval, wrap, tangent)

    def _run_stored(self, buf, start, outs, width=0):
        # The run in ``buf`` from ``start`` = (t0, θ0, θ'0, t1, h) with its window ends
        # stored, and with ``width`` > 0 its windows' coefficients, the store grown as it
        # fills (chunked: Ctrl-C gets in between calls); ``outs``: (t_eval, its output
        # rows) or none.  Returns (window ends' times, states, the coefficients' whole
        # store, windows taken).
        t0, theta0, v0, t1, h = start
        te, y = outs
        ints = buf[1].view(np.int64)
        entry, item = self._entry, ints.item
        cap = TANGENT_CAPACITY if width else ENDS_CAPACITY
        win_c = self._coef_store(cap, width)
        cap = max(cap, win_c.shape[0])
        win_t = np.empty(cap + 1)
        win_y = np.empty((cap + 1, 2))
        n = entry(buf, True, start, (te, y, win_t, win_y, win_c, _NEVER))
        if n < 0:
            raise t_eval_error(-n, t0, t1)
        chosen = REGIME_NONE
        while item(_W_STATUS) == _PAUSED:
            if n + 1 == win_t.size:
                win_t = np.concatenate((win_t, np.empty(win_t.size)))
                win_y = np.concatenate((win_y, np.empty((win_y.shape[0], 2))))
                if width:
                    win_c = np.concatenate((win_c, np.empty((win_c.shape[0] + 1, width))))
            regime = item(_W_REGIME)
            if regime != chosen:  # a regime switch: its set's entry
                entry, chosen = _entry_at(self, regime), regime
            n += entry(buf, False, start, (te, y, win_t[n:], win_y[n:], win_c[n:], _NEVER))
        return win_t[: n + 1], win_y[: n + 1], win_c, n

    def _coef_store(self, cap, width):
        # A window-coefficient store of ``width`` columns (0: none): a previous call's
        # (grown to its run's windows: no growth, no fresh pages to fault in; one width
        # per Integrator), else a new one.  Put back by _solve once the pass has read it.
        if width:
            try:
                return self._coef_stores.pop()
            except IndexError:  # none yet, or other threads hold them
                pass
        return np.empty((cap if width else 0, width))

    def _solve(self, t0, t1, theta0, v0, t_eval, wrap, tangent=None):
        # solve with the span and the state checked (float t0, t1, theta0, v0).
        if wrap is not False and wrap is not True:
            if t_eval is not None:
                check_t_eval(t_eval, t0, t1)  # a bad t_eval is named first
            raise ValueError(f"wrap must be True or False, got {wrap!r}")
        if t_eval is None:
            if wrap:
                raise ValueError("wrap=True needs t_eval (the window ends are reported as θ)")
        else:
            te = t_eval
            # as_t_eval's test, inline (the common t_eval passes it: no call)
            if not (type(te) is _NDARRAY and te.ndim == 1 and te.dtype is _FLOAT64 and te.flags.carray):
                te = as_t_eval(t_eval)
            y = _EMPTY((3 if wrap else 2, te.size))
        h = self._h
        if self._span_plan:
            h = plan_windows(self.approximant, None, self.max_step, abs(t1 - t0))[1]
        records = self._records
        try:
            buf, words, ints = records.pop()
        except IndexError:
            buf = np.empty((2, self._words.size))
            buf[0] = self._words
            words, ints = buf[1], buf[1].view(np.int64)
        try:
            item = ints.item
            if t_eval is None or tangent is not None:
                # The window ends stored (the outputs, or the tangent pass's track, which
                # follows a Taylor run's windows on their own coefficients).
                width = 0 if tangent is None else _tangent.coefficient_width(self._kind, self._karg)
                win_t, win_y, store, n = self._run_stored(buf, (t0, theta0, v0, t1, h),
                                                          (_NO_T, _NO_OUT) if t_eval is None else (te, y), width)
                win_c = store[:n]
                if t_eval is None:
                    t, y = win_t, win_y.T
            else:
                entry = self._entry
                start, arrays = (t0, theta0, v0, t1, h), (te, y, _NO_T, _NO_Y, _NO_COEF, _NEVER)
                problem = entry(buf, True, start, arrays)
                if problem < 0:
                    raise t_eval_error(-problem, t0, t1)
                chosen = REGIME_NONE
                while item(_W_STATUS) == _PAUSED:
                    regime = item(_W_REGIME)
                    if regime != chosen:  # a regime switch: its set's entry
                        entry, chosen = _entry_at(self, regime), regime
                    entry(buf, False, start, arrays)
            if t_eval is not None:
                t = te
                j = item(_W_J)
                if j != te.size:
                    t, y = te[:j], y[:, :j]
            status, n_windows = item(_W_STATUS), item(_W_NW)
            t_regime = words.item(_W_T_REGIME)
            summary = run_summary(words, ints)
        finally:
            records.append((buf, words, ints))
        r = SolveResult(self._base)
        if wrap:
            r["winding"] = y[2].astype(np.int64)
            y = y[:2]
        r["t"] = t
        r["y"] = y
        r["success"] = status == _OK
        r["status"] = status
        r["message"] = _MESSAGES[status]
        r["n_windows"] = n_windows
        r["regime"] = summary.regime
        r["t_regime"] = t_regime
        r["period"] = summary.period
        r["mean_velocity"] = summary.mean_velocity
        if tangent is not None:
            _tangent.attach(r, self, tangent, (win_t, win_y, win_c))
            self._coef_stores.append(store)  # read: the next call's store
        return r


def solve(model, t_span, y0, *, tau=None, rtol=1e-6, atol=1e-9, approximant="auto",
          t_eval=None, max_step=np.inf, max_windows=DEFAULT_MAX_WINDOWS, wrap=False, events=None,
          max_events=None, temperature=None, seed=None, dt=None, error_estimate=False, sensitivities=None):
    """Solve one scene by the moving boundary method, the whole run compiled.

    The one-shot form of :class:`Integrator` (build one for many runs of one model).

    Parameters
    ----------
    model : Pendulum
    t_span : (float, float)
        (t0, t_bound); t_bound < t0 integrates backwards.
    y0 : array_like, shape (2,)
        [θ₀, θ̇₀].
    tau : float, optional
        Fixed step (window) length; default: adaptive steps from rtol/atol.
    rtol, atol : float, optional
        Tolerances, with scipy's meaning (local error per adaptive step, or window,
        against ``atol + rtol·|y|``); rtol below 100 machine epsilons is raised to
        that floor with a warning, as scipy does.
    approximant : str, optional
        ``"auto"`` (default) or a compiled one (``taylor*``, ``split*``, ``sbab*``, ``belendez``, ``salas-torque``).
    t_eval : array_like, optional
        Output times, sorted in the direction of integration; default: every step's end.
    max_step : float, optional
        Longest step (window).
    max_windows : int, optional
        Steps (windows) the run may take (default 10⁷, seconds of compute); past it the
        run stops with its outputs so far and ``status`` 4 (:doc:`/guide/statuses`).  A
        run certain to take 100 times as many (abs(γ) ≫ ω², a tiny ``tau``) is refused.
    wrap : bool, optional
        Report θ wrapped to (−π, π] (``y[0]``) with its winding count ``winding``
        (θ = 2π·winding + y[0]; needs ``t_eval``), at full precision however far wound.
    events : Event, numba.njit function, or sequence of them, optional
        Built-in events (:func:`mbm.angle_event`, :func:`mbm.velocity_event`,
        :func:`mbm.section_event`) or a ``numba.njit`` g(t, θ, θ') (an event where it
        changes sign), located inside the compiled run to round-off, with scipy's
        ``direction`` and ``terminal`` (a terminal event ends the run there: ``status``
        6, ``EVENT``); an event exactly at t0 is not reported.  They need the Taylor
        series ("auto" takes it; another approximant is a ValueError).  How they meet
        the settled motions, and their first call's compile: :doc:`/guide/events`.
    max_events : int, optional
        Occurrences of each event stored (the first ``max_events``; all are counted in
        ``n_events``); default None: all.  Past it a settled cycle's turns are counted
        whole, so counting slips over 10⁶ time units costs what 10³ do.
    temperature, seed, dt : float, int, float, optional
        T > 0: a Langevin path (noise 2βT) at the fixed step ``dt`` from ``seed``
        (:doc:`/guide/noise`); None or 0: the run above.
    error_estimate : bool, optional
        Add ``error_estimate`` (the shape of ``y``), an estimate of y_computed − y_true at
        each output (:doc:`/theory/error_estimate`), and warn (:class:`mbm.AccuracyWarning`)
        past 10 times ``atol + rtol·|y|``.  The same steps and ``y``, bit for bit.
    sensitivities : sequence of str, optional
        Any of ``"theta0"``, ``"v0"``, ``"beta"``, ``"gamma"``, ``"omega"``,
        ``"drive_amplitude"``, ``"drive_frequency"``, ``"drive_phase"``: add
        ``sensitivities`` (len(names), 2, n), ∂(θ, θ')/∂p at each output along the
        computed run, and ``sensitivity_names``.  Not with ``events`` or a temperature.

    Returns
    -------
    SolveResult
        ``t``, ``y`` (shape (2, n)), ``success``, ``status`` (0 ok, else the code of
        what stopped the run, :doc:`/guide/statuses`), ``message`` (the same in words),
        ``n_windows`` (steps taken), ``approximant`` and
        ``reason`` (what "auto" chose and why), ``regime`` (``"locked"``,
        ``"running"``, ``"libration"`` or ``"phase-locked"`` (a Shapiro step) when the
        run switched to a settled motion's closed form or stored period,
        :doc:`/guide/regimes`, or locked to a drive unswitched; else None), ``t_regime``
        (when; nan if never), ``period`` and ``mean_velocity`` (T_c and ±2π/T_c running;
        a libration's period and 0; phase-locked q·2π/Ω (nan: chaotic within the step)
        and (p/q)Ω; nan and 0 locked; nan otherwise),
        ``winding`` (int64, shape (n,), with ``wrap=True``; else None).
        With ``events``: ``t_events`` and ``y_events`` (a list with one array per
        event, of shapes (k,) and (k, 2), as scipy's) and ``winding_events`` (int64
        arrays: m with θ = value + modulo·m of an angle event, the drive turn of a
        section, θ's winding count round(θ/2π) of a velocity event or a function)
        and ``n_events`` (int64, shape (n_events,): occurrences, stored or not).
        On a failure ``t``, ``y`` hold the outputs reached before it.

    Raises
    ------
    ValueError, TypeError
        Invalid arguments, named (TypeError: not a real number); an approximant without
        a compiled kernel; a run certain to take 100 times ``max_windows`` steps (naming
        the parameter causing it).
    """
    if not isinstance(model, Pendulum):
        raise TypeError(f"model must be an mbm.Pendulum, got {type(model).__name__}")
    (t0, t1), (theta0, v0) = check_span(t_span), _state(y0)
    if temperature is not None and check_rule("temperature", temperature, (">=0", ">= 0")) > 0.0:
        return _langevin(model, (t0, t1, theta0, v0), (temperature, seed, dt), t_eval, tau=tau, wrap=wrap,
                         events=events, error_estimate=error_estimate, sensitivities=sensitivities)
    ig = _solver_for(model, rtol, atol, approximant, tau, max_step, max_windows, events is not None)
    _check_budget(ig, t0, t1, v0)
    tangent = _tangent_request(error_estimate, sensitivities, events)
    if events is not None:
        return solve_events(ig, t0, t1, theta0, v0, t_eval, wrap, events, max_events=max_events)
    if max_events is not None:
        raise ValueError("max_events needs events")
    return ig._solve(t0, t1, theta0, v0, t_eval, wrap, tangent)  # span and state checked above


def _tangent_request(error_estimate, sensitivities, events):
    # The tangent pass's request (mbm.tangent.request), or None; not with events.
    if error_estimate is False and sensitivities is None:
        return None
    req = _tangent.request(error_estimate, sensitivities)
    if req is not None and events is not None:
        raise ValueError("error_estimate and sensitivities are not supported with events")
    if req is not None:  # a cold pass compiled by the helper beside the run's own compile
        _warm.prefetch("tangent", _TRANSPORT)
    return req


def _langevin(model, start, noise, t_eval, *, tau, wrap, events, error_estimate=False, sensitivities=None):
    # mbm.solve with a temperature > 0 (noise: temperature, seed, dt): mbm.noise.paths,
    # loaded on first use.
    temperature, seed, dt = noise
    for name, value in (("tau", tau), ("wrap", wrap), ("events", events), ("error_estimate", error_estimate),
                        ("sensitivities", sensitivities)):
        if value is not None and value is not False:
            raise ValueError(f"{name} is not supported with a temperature > 0 (a Langevin path)")
    from ..noise.paths import solve_langevin

    t0, t1, theta0, v0 = start
    return solve_langevin(model, t0, t1, theta0, v0, temperature=temperature, seed=seed, dt=dt,
                          t_eval=t_eval)


def _solver_for(model, rtol, atol, approximant, tau, max_step, max_windows, watched):
    # The Integrator of mbm.solve's options.
    if watched and isinstance(approximant, str) and approximant == "auto":
        # The events are located on Taylor windows: "auto" is the Taylor series.
        approximant = auto_name(False)
    if (type(approximant) is str and type(rtol) is float and type(atol) is float
            and rtol >= RTOL_FLOOR and (tau is None or type(tau) is float)):
        # The common call: an Integrator per option set, cached (an Integrator is not
        # changed by solving; a warning-raising rtol is never cached, so it warns each time).
        return _integrator(model, rtol, atol, approximant, tau, max_step, max_windows)
    return Integrator(model, rtol=rtol, atol=atol, approximant=approximant, tau=tau,
                      max_step=max_step, max_windows=max_windows)


def _check_budget(ig, t0, t1, v0):
    # check_window_budget for a run of ig (a run far past max_windows is refused).
    m = ig.model
    check_window_budget(m.beta, m.gamma, m.omega, m.drive_amplitude, t0, t1, v0, ig._tau, max_step=ig.max_step,
                        max_windows=ig._max_windows, exact=ig.approximant.exact)


@functools.lru_cache(maxsize=INTEGRATOR_CACHE)
def _integrator(model, rtol, atol, approximant, tau, max_step, max_windows):
    # Arguments are hashable here; a call that raises is not cached (lru_cache).
    return Integrator(model, rtol=rtol, atol=atol, approximant=approximant, tau=tau,
                      max_step=max_step, max_windows=max_windows)


_AUTO_TAYLOR = window.kind_of(get_approximant(auto_name(False)))
_AUTO_TAYLOR_ORDER = int(get_approximant(auto_name(False)).error_order)
_AUTO_EXACT = window.kind_of(get_approximant(auto_name(True)))


@numba.njit(cache=True)
def solve_njit(beta, gamma, omega, t0, theta0, v0, t_bound, t_eval, out, rtol, atol, max_windows,
               drive_amplitude=0.0, drive_frequency=0.0, drive_phase=0.0):
    """A whole run with approximant "auto", callable from your own ``numba.njit`` code.

    The exact flow when β = γ = 0 without a drive (one step), else the default Taylor
    series with adaptive steps from rtol/atol: the steps and outputs of
    ``mbm.solve(Pendulum(beta, gamma, omega, drive_amplitude, drive_frequency,
    drive_phase), (t0, t_bound), [theta0, v0], rtol=rtol, atol=atol, t_eval=t_eval)``,
    bit for bit.  Arguments are not validated (as a compiled kernel's): β ≥ 0, ω > 0,
    Ω ≥ 0, finite values, rtol ≥ 100 eps, ``t_eval`` sorted within the span.

    Parameters
    ----------
    beta, gamma, omega : float
        The model θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ).
    t0, theta0, v0, t_bound : float
        Initial time and state, end of the span.
    t_eval : ndarray, shape (m,)
        Output times.
    out : ndarray, shape (2, m)
        Filled with θ, θ' at ``t_eval`` (up to where a failure stopped the run).
    rtol, atol : float
        Tolerances.
    max_windows : int
        Steps (windows) the run may take (past it, ``status`` 4).
    drive_amplitude, drive_frequency, drive_phase : float, optional
        The AC drive's A, Ω, φ (default 0: none).  Pass all three or none: numba
        compiles one signature per number of arguments given.

    Returns
    -------
    status : int
        0 on success, else the code of what stopped the run (:doc:`/guide/statuses`).
    n_windows : int
        Steps (windows) taken.

    Examples
    --------
    >>> import numba, numpy as np, mbm
    >>> @numba.njit
    ... def final_angles(gammas, t_end):
    ...     t = np.array([t_end])
    ...     out = np.empty((2, 1))
    ...     res = np.empty(gammas.size)
    ...     for i in range(gammas.size):
    ...         mbm.solve_njit(0.1, gammas[i], 1.0, 0.0, 0.0, 0.0, t_end, t, out, 1e-8, 1e-8, 10**7)
    ...         res[i] = out[0, 0]
    ...     return res
    """
    p = np.empty(1, dtype=record.RUN)
    drive = (drive_amplitude, drive_frequency, drive_phase) if drive_amplitude != 0.0 else (0.0, 0.0, 0.0)
    model = (float(beta), float(gamma), float(omega), float(drive[0]), float(drive[1]), float(drive[2]))
    state = (float(t0), float(theta0), float(v0), float(t_bound))
    win_t = np.empty(0)
    win_y = np.empty((0, 2))
    win_coef = np.empty((0, 0))
    never = np.zeros(1, dtype=np.int64)
    if beta == 0.0 and gamma == 0.0 and drive_amplitude == 0.0:
        # plan_windows for an exact flow and max_step = inf: one window of the span.
        span = abs(t_bound - t0)
        control = (_AUTO_EXACT[0], _AUTO_EXACT[1], CONTROLLER_FIXED, span if span > 0.0 else 1.0,
                   math.inf, math.inf, float(rtol), float(atol), 0)
        record.init_run(p, 0, model, state, control, np.int64(max_windows), 0, 1)
        chains.run_exact(p, t_eval, out, win_t, win_y, win_coef, never)
    else:
        control = (_AUTO_TAYLOR[0], _AUTO_TAYLOR[1], CONTROLLER_ADAPTIVE, -1.0, math.inf, math.inf,
                   float(rtol), float(atol), _AUTO_TAYLOR_ORDER)
        record.init_run(p, 0, model, state, control, np.int64(max_windows), 0, 1)
        chains.run_taylor(p, t_eval, out, win_t, win_y, win_coef, never)
    return p[0].progress.status, p[0].progress.n_windows
