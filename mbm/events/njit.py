"""Events inside your own numba code: :func:`solve_njit_events`, :func:`event_table`.

:func:`mbm.solve_njit` with the built-in events of :mod:`mbm.events.compiled`: the table of
the events is made once in Python (:func:`event_table`) and passed into ``numba.njit``
code, where each call returns the events stored in arrays of a fixed shape, as one
scene of :func:`mbm.solve_batch` reports them.
"""

import math

import numba
import numpy as np

from ..approximants.base import get_approximant
from ..approximants.taylor import HEADER, N_EXTRA
from ..choice import auto_name
from ..core import controller, record, window
from ..core.event_batch import EVENTS_CAPACITY, FIRST_CHUNK, LAST_CHUNK, scene_events_for, stop_at
from ..core.chains import F_DRIVEN, F_PLAIN, F_TAYLOR_SIMD, _run_sets
from ..core.event_watch import EV_ANGLE, EV_VELOCITY, EV_WIDTH
from .compiled import as_events
from ..regimes.common import REGIMES_ALL, REGIMES_OFF, REGIMES_PERIODIC
from ..status import STATUS_NONFINITE, STATUS_PAUSED
from .functions import function_crossings
from ..regimes.cycle import CYCLE_WIDTH

__all__ = ["event_table", "solve_njit_events", "solve_njit_function_events"]

_TAYLOR = get_approximant(auto_name(False))
_KIND, _KARG = window.kind_of(_TAYLOR)
_ORDER = int(_TAYLOR.error_order)
#: The sets a run with regimes off takes (mbm.core.chains.flag_bits): the plain and the
#: driven, the default degree's Taylor entries alone.
_FLAGS = F_TAYLOR_SIMD | F_PLAIN | F_DRIVEN
# The window store's width for the default Taylor series (its coefficients, a cycle's).
_WIDTH = max(HEADER + int(_KARG) + 1 + N_EXTRA, CYCLE_WIDTH)
# The run of one scene through every regime set of the Taylor kind.
_SCENE = scene_events_for((1, 0, 0, 0, 1, 1, 1, 1, 1, 1))
_TWO_PI = 2.0 * math.pi


def event_table(events):
    """The table of built-in events that :func:`solve_njit_events` takes.

    Parameters
    ----------
    events : Event or sequence of Event
        From :func:`mbm.angle_event`, :func:`mbm.velocity_event`,
        :func:`mbm.section_event`.

    Returns
    -------
    ndarray, shape (n_events, 5)
        One row per event (type, value, modulo, direction, terminal count), in the
        order given.

    Raises
    ------
    TypeError
        For anything but built-in events (an event function is taken by
        :func:`mbm.solve` only).
    """
    items = as_events(events, functions=False)
    return np.array([e._row() for e in items], dtype=np.float64).reshape(len(items), EV_WIDTH)


@numba.njit(cache=True)
def _init_taylor(p, run_model, run_state, tol, regimes):
    # p[0] a fresh adaptive run of the default Taylor series (mbm.solve's with events):
    # ``run_model`` a record.RunModel, ``run_state`` a record.RunState, ``tol`` (rtol,
    # atol, max_windows).
    beta, gamma, omega, amp, freq, phase = run_model
    t0, theta0, v0, t_bound = run_state
    rtol, atol, max_windows = tol
    drive = (amp, freq, phase) if amp != 0.0 else (0.0, 0.0, 0.0)
    model = (float(beta), float(gamma), float(omega), float(drive[0]), float(drive[1]), float(drive[2]))
    state = (float(t0), float(theta0), float(v0), float(t_bound))
    control = (_KIND, _KARG, controller.CONTROLLER_ADAPTIVE, -1.0, math.inf, math.inf, float(rtol), float(atol), _ORDER)
    record.init_run(p, 0, model, state, control, np.int64(max_windows), 0, regimes)


@numba.njit(cache=True)
def _window_store():
    # A chunk's window store (LAST_CHUNK windows of the default Taylor series).
    return np.empty(LAST_CHUNK + 1), np.empty((LAST_CHUNK + 1, 2)), np.empty((LAST_CHUNK, _WIDTH))


@numba.njit(cache=True)
def _lock_allowed(ev):
    # mbm.events.compiled.lock_allowed in compiled code.
    for e in range(ev.shape[0]):
        kind = int(ev[e, 0])
        if not (kind == EV_ANGLE or (kind == EV_VELOCITY and ev[e, 1] != 0.0)):
            return False
    return True


@numba.njit(cache=True)
def _arrays(ev, evf, evi, count, max_events, hits):
    # The stored events as one scene of solve_batch reports them (NaN, 0 past a count).
    nev = ev.shape[0]
    t_events = np.full((nev, max_events), np.nan)
    y_events = np.full((nev, max_events, 2), np.nan)
    winding = np.zeros((nev, max_events), np.int64)
    rank = np.zeros(nev, np.int64)
    for q in range(count):
        e = evi[q]
        if rank[e] < max_events:
            t_events[e, rank[e]] = evf[q, 0]
            y_events[e, rank[e], 0], y_events[e, rank[e], 1] = evf[q, 1], evf[q, 2]
            if int(ev[e, 0]) == EV_VELOCITY:
                winding[e, rank[e]] = int(math.floor((evf[q, 1] + math.pi) / _TWO_PI))
            else:
                winding[e, rank[e]] = int(evf[q, 3])
            rank[e] += 1
    return t_events, y_events, winding, hits.copy()


@numba.njit(cache=True)
def solve_njit_events(beta, gamma, omega, t0, theta0, v0, t_bound, t_eval, out, rtol, atol, max_windows, events,
                      max_events, drive_amplitude=0.0, drive_frequency=0.0, drive_phase=0.0):
    """:func:`mbm.solve_njit` with built-in events, callable from your own ``numba.njit`` code.

    The run and its events are those of ``mbm.solve(Pendulum(beta, gamma, omega,
    drive_amplitude, drive_frequency, drive_phase), (t0, t_bound), [theta0, v0],
    rtol=rtol, atol=atol, t_eval=t_eval, events=..., max_events=max_events)``, bit for
    bit (the Taylor series, also at β = γ = 0), but that a scene trapped out of its
    events' reach with its outputs written ends there, as in :func:`mbm.solve_batch`
    (fewer ``n_windows``; :doc:`/guide/events`).  Arguments are not validated (as a
    compiled kernel's), but for ``max_events``.

    Parameters
    ----------
    beta, gamma, omega : float
        The model θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ).
    t0, theta0, v0, t_bound : float
        Initial time and state, end of the span.
    t_eval : ndarray, shape (m,)
        Output times.
    out : ndarray, shape (2, m)
        Filled with θ, θ' at ``t_eval`` (up to where a failure or a terminal event
        stopped the run; NaN past a terminal event).
    rtol, atol : float
        Tolerances.
    max_windows : int
        Steps (windows) the run may take (past it, ``status`` 4).
    events : ndarray, shape (n_events, 5)
        The events, from :func:`event_table` (made in Python, passed in).
    max_events : int
        Occurrences of each event stored (>= 1); all are counted.
    drive_amplitude, drive_frequency, drive_phase : float, optional
        The AC drive's A, Ω, φ (default 0: none); pass all three or none.

    Returns
    -------
    status : int
        0 on success, 6 at a terminal event, else the code of what stopped the run
        (:doc:`/guide/statuses`).
    n_windows : int
        Steps (windows) taken.
    t_events : ndarray, shape (n_events, max_events)
        Each event's times, NaN past its stored count.
    y_events : ndarray, shape (n_events, max_events, 2)
        The states there.
    winding_events : ndarray of int64, shape (n_events, max_events)
        As :func:`mbm.solve`'s (0 past the count).
    n_events : ndarray of int64, shape (n_events,)
        Each event's occurrences, stored or not.

    Raises
    ------
    ValueError
        If ``max_events`` < 1.

    Examples
    --------
    >>> import math, numba, numpy as np, mbm
    >>> table = mbm.event_table(mbm.angle_event(math.pi, terminal=True))
    >>> @numba.njit
    ... def first_slips(gammas, ev):
    ...     t, out = np.empty(0), np.empty((2, 0))
    ...     res = np.empty(gammas.size)
    ...     for i in range(gammas.size):
    ...         r = mbm.solve_njit_events(0.1, gammas[i], 1.0, 0.0, 0.0, 0.0, 1e3, t, out,
    ...                                   1e-9, 1e-9, 10**7, ev, 1)
    ...         res[i] = r[2][0, 0]
    ...     return res
    """
    if max_events < 1:
        raise ValueError("max_events must be >= 1")
    p = np.empty(1, dtype=record.RUN)
    regimes = REGIMES_ALL if _lock_allowed(events) and drive_amplitude == 0.0 else REGIMES_PERIODIC
    nev = events.shape[0]
    win_t, win_y, win_coef = _window_store()
    caps = np.full(nev, max_events, np.int64)
    cancel = np.zeros(1, dtype=np.int64)
    lock = np.empty(4)
    while True:
        _init_taylor(p, record.RunModel(beta, gamma, omega, drive_amplitude, drive_frequency, drive_phase),
                     record.RunState(t0, theta0, v0, t_bound), (rtol, atol, max_windows), np.int64(regimes))
        hits = np.zeros(nev, np.int64)
        stored = np.zeros(nev, np.int64)
        evf = np.empty((EVENTS_CAPACITY, 4))
        evi = np.empty(EVENTS_CAPACITY, np.int64)
        evs = np.empty(EVENTS_CAPACITY, np.int64)
        out[:] = np.nan
        evf, evi, evs, count, locked = _SCENE(p, 0, (t_eval, out, cancel), events, (hits, stored, caps),
                                              (win_t, win_y, win_coef, lock), (evf, evi, evs, 0))
        if not locked or regimes == REGIMES_PERIODIC:
            break
        regimes = REGIMES_PERIODIC  # a locked window may reach a level: without the locked regime
    t_events, y_events, winding, n_events = _arrays(events, evf, evi, count, max_events, hits)
    return p[0].progress.status, p[0].progress.n_windows, t_events, y_events, winding, n_events


@numba.njit(cache=True)
def _record(rows, m, hits, max_events, terminal, t_events, y_events):
    # The m events of rows (t, θ, θ', window) counted after hits, the first max_events
    # stored: (the count, the row of the terminal one or -1).
    for q in range(m):
        if hits < max_events:
            t_events[hits], y_events[hits, 0], y_events[hits, 1] = rows[q, 0], rows[q, 1], rows[q, 2]
        hits += 1
        if terminal > 0 and hits >= terminal:
            return hits, q
    return hits, -1


@numba.njit
def solve_njit_function_events(beta, gamma, omega, t0, theta0, v0, t_bound, t_eval, out, rtol, atol, max_windows,
                               g, direction, terminal, max_events, drive_amplitude=0.0, drive_frequency=0.0,
                               drive_phase=0.0):
    """:func:`mbm.solve_njit` with an event function ``g(t, theta, theta_dot)`` of your own
    (a ``numba.njit`` function), callable from ``numba.njit`` code.

    The run and its events are those of ``mbm.solve(..., events=g, max_events=max_events)``
    with ``g.direction = direction`` and ``g.terminal = terminal``, bit for bit (the
    Taylor series; the run never switches to a settled regime: :doc:`/guide/events`).  Arguments are not validated,
    but for ``max_events``.  Compiled for each ``g`` in each new process and not cached
    (numba cannot cache a kernel that takes a function, nor a caller of it): about
    3.5 s per function on 2 cores (``python -m benchmarks.compile_profile``), as the
    whole loop is optimised again with it; ``mbm.solve(..., events=g)`` compiles only
    its locator (about 1.2 s).

    Parameters
    ----------
    beta, gamma, omega : float
        The model θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ).
    t0, theta0, v0, t_bound : float
        Initial time and state, end of the span.
    t_eval : ndarray, shape (m,)
        Output times.
    out : ndarray, shape (2, m)
        Filled with θ, θ' at ``t_eval`` (NaN past a terminal event or a failure).
    rtol, atol : float
        Tolerances.
    max_windows : int
        Steps (windows) the run may take (past it, ``status`` 4).
    g : numba.njit function
        The event function g(t, θ, θ') -> float.
    direction : float
        scipy's: > 0 only g rising through 0, < 0 only falling, 0 both.
    terminal : int
        Stop at the ``terminal``-th event (0: never).
    max_events : int
        Events stored (>= 1); all are counted.
    drive_amplitude, drive_frequency, drive_phase : float, optional
        The AC drive's A, Ω, φ (default 0: none); pass all three or none.

    Returns
    -------
    status : int
        0 on success, 6 at a terminal event, 3 where g was not finite, else the code
        of what stopped the run (:doc:`/guide/statuses`).
    n_windows : int
        Steps (windows) taken.
    t_events : ndarray, shape (max_events,)
        The events' times, NaN past the stored count.
    y_events : ndarray, shape (max_events, 2)
        The states there.
    n_events : int
        The events' count, stored or not.

    Raises
    ------
    ValueError
        If ``max_events`` < 1.
    """
    if max_events < 1:
        raise ValueError("max_events must be >= 1")
    p = np.empty(1, dtype=record.RUN)
    _init_taylor(p, record.RunModel(beta, gamma, omega, drive_amplitude, drive_frequency, drive_phase),
                 record.RunState(t0, theta0, v0, t_bound), (rtol, atol, max_windows), np.int64(REGIMES_OFF))
    r = p[0]
    win_t, win_y, win_coef = _window_store()
    cancel = np.zeros(1, dtype=np.int64)
    t_events = np.full(max_events, np.nan)
    y_events = np.full((max_events, 2), np.nan)
    stop = np.empty((1, 4))
    ref = np.zeros(4)
    sign = 1.0 if t_bound >= t0 else -1.0
    out[:] = np.nan
    hits = 0
    chunk = FIRST_CHUNK
    first = True
    while True:
        before = r.progress.n_windows
        # Regimes off: the plain (or driven) entry of the Taylor kind alone, at the
        # default degree (mbm.core.chains._dispatch_flagged).
        n = _run_sets(_KIND, _FLAGS, p, (t_eval, out, win_t[: chunk + 1], win_y[: chunk + 1], win_coef[:chunk], cancel))
        last = r.progress.status != STATUS_PAUSED
        rows, m = function_crossings(g, direction, (win_t, np.ascontiguousarray(win_y[: n + 1, 0]), win_coef, n), ref,
                                     first, last)
        first = False
        if m < 0:
            r.progress.status = STATUS_NONFINITE
            break
        hits, q = _record(rows, m, hits, max_events, terminal, t_events, y_events)
        if q >= 0:
            stop[0, 0], stop[0, 1], stop[0, 2], stop[0, 3] = rows[q, 0], rows[q, 1], rows[q, 2], 0.0
            stop_at(r, out, t_eval, stop, 0, before + int(rows[q, 3]) + 1, sign)
            break
        if last:
            break
        chunk = min(2 * chunk, LAST_CHUNK)
    return r.progress.status, r.progress.n_windows, t_events, y_events, hits
