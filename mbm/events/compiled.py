"""Events of the compiled runs: phase slips, turning points and drive sections.

The built-in events (:func:`angle_event`, :func:`velocity_event`, :func:`section_event`)
are located by :func:`mbm.solve` and :meth:`mbm.Integrator.solve` (``events=``) on the
windows' own formulas, inside compiled code (:mod:`mbm.core.event_watch`): a Taylor
window is a polynomial, so every crossing in it is isolated from its coefficients (not
from samples that can miss a pair) and refined to round-off; on a running cycle or a
libration the stored period's events are shifted by the period per turn.  The result
carries ``t_events``, ``y_events`` (as scipy's ``OdeResult``: one array per event) and
``winding_events``.

The run is the approximant's windows and the stored-period regimes (running cycle,
libration).  The locked regime is taken too where every event is an angle event or a
velocity event at a level other than 0, in an undriven scene (:func:`lock_allowed`):
its window holds no event when the level lies outside the amplitude bound of the
exact motion (:func:`mbm.core.event_watch.locked_unreachable`), and where it may not,
the run is taken again without it.  The phase-locked regime is not taken while events
are watched (its closed form is not a polynomial), so a driven scene runs its Taylor
windows to the end.
"""

import math
import numbers

import numpy as np

from ..core import controller, loop, record, window
from ..validate import as_t_eval, check_real, t_eval_error, t_eval_problem
from ..approximants.taylor import HEADER as _HEADER, N_EXTRA as _N_EXTRA
from ..core.event_watch import (EV_ANGLE, EV_SECTION, EV_VELOCITY, EV_WIDTH, WATCH_CROWDED, WATCH_LOCKED, WATCH_OK,
                                cycle_events_bound, event_columns, locate)
from ..regimes import REGIME_NAMES, REGIME_NONE
from ..regimes.summary import RunSummary, run_summary
from ..regimes.common import REGIMES_ALL, REGIMES_OFF, REGIMES_PERIODIC
from ..regimes.cycle import CYCLE_WIDTH
from .functions import event_function_options, function_crossings, is_event_function
from ..result import SolveResult
from ..status import STATUS_EVENT, STATUS_MESSAGES, STATUS_OK, STATUS_PAUSED

__all__ = ["Event", "angle_event", "velocity_event", "section_event", "solve_events"]

# Windows stored per compiled call while events are watched: the first call short (a
# terminal event early in the run wastes few windows past it), doubling to the last.
FIRST_CHUNK = 64
LAST_CHUNK = 4096
# Events reserved before the first call (the buffer doubles as it fills).
EVENTS_CAPACITY = 64
_TWO_PI = 2.0 * math.pi
_W = record.WORD


class Event:
    """A built-in event of the compiled runs (made by :func:`angle_event`,
    :func:`velocity_event` or :func:`section_event`, which check their arguments).

    Parameters
    ----------
    kind : {"angle", "velocity", "section"}
    value : float
        The level (an angle, a velocity or a drive phase).
    modulo : float
        The angle's period (2π for the section; ``inf`` for a velocity).
    direction : float
        scipy's meaning: > 0 only crossings from below, < 0 only from above, 0 both,
        along the integration.
    terminal : bool or int
        scipy's meaning: True stops the run at the first occurrence, an int n at the
        n-th.
    """

    __slots__ = ("kind", "value", "modulo", "direction", "terminal")

    def __init__(self, kind, value, modulo, direction, terminal):
        self.kind, self.value, self.modulo = kind, value, modulo
        self.direction, self.terminal = direction, terminal

    def __repr__(self):
        return (f"Event(kind={self.kind!r}, value={self.value!r}, modulo={self.modulo!r}, "
                f"direction={self.direction!r}, terminal={self.terminal!r})")

    def _row(self):
        typ = {"angle": EV_ANGLE, "velocity": EV_VELOCITY, "section": EV_SECTION}[self.kind]
        stops = float(self.terminal) if self.terminal is not False else 0.0
        return (typ, self.value, self.modulo, float(np.sign(self.direction)), stops)


def _direction(direction):
    d = check_real("direction", direction)
    return float(np.sign(d))


def _terminal(terminal):
    if terminal is True or terminal is False:
        return terminal
    if isinstance(terminal, numbers.Integral) and not isinstance(terminal, (bool, np.bool_)):
        if terminal < 1:
            raise ValueError(f"terminal must be True, False or an int >= 1, got {terminal!r}")
        return int(terminal)
    raise TypeError(f"terminal must be True, False or an int >= 1, got {terminal!r}")


def angle_event(value, *, modulo=_TWO_PI, direction=0.0, terminal=False):
    """The event θ ≡ ``value`` (mod ``modulo``): a phase slip at each crossing.

    Parameters
    ----------
    value : float
        The angle (e.g. π: θ passes the top, cos(θ/2) = 0 for a junction's phase slip).
    modulo : float, optional
        The angle's period (default 2π); ``winding_events`` of the result gives, per
        crossing, the m with θ = value + modulo·m.
    direction : float, optional
        > 0: only θ increasing through the level; < 0: only decreasing; 0 both.
    terminal : bool or int, optional
        Stop the run at the first (True) or n-th (n) occurrence.

    Returns
    -------
    Event

    Raises
    ------
    TypeError, ValueError
        For a value or modulo that is not a finite real number, modulo ≤ 0, or a bad
        ``terminal``.
    """
    v = check_real("value", value)
    m = check_real("modulo", modulo)
    if m <= 0.0:
        raise ValueError(f"modulo must be > 0, got {modulo!r}")
    return Event("angle", v, m, _direction(direction), _terminal(terminal))


def velocity_event(value, *, direction=0.0, terminal=False):
    """The event θ' = ``value``: turning points at 0, voltage thresholds of a junction.

    Parameters
    ----------
    value : float
        The velocity.
    direction : float, optional
        > 0: only θ' increasing through ``value``; < 0: only decreasing; 0 both.
    terminal : bool or int, optional
        Stop the run at the first (True) or n-th (n) occurrence.

    Returns
    -------
    Event

    Raises
    ------
    TypeError, ValueError
        For a value that is not a finite real number or a bad ``terminal``.
    """
    return Event("velocity", check_real("value", value), math.inf, _direction(direction), _terminal(terminal))


def section_event(phase, *, terminal=False):
    """The stroboscopic section Ωt + φ ≡ ``phase`` (mod 2π) of a driven scene.

    Its times are known (t = (phase + 2πm − φ)/Ω); the state there is the window's.
    ``winding_events`` gives the drive turn m.

    Parameters
    ----------
    phase : float
        The drive's phase at the section.
    terminal : bool or int, optional
        Stop the run at the first (True) or n-th (n) section.

    Returns
    -------
    Event

    Raises
    ------
    TypeError, ValueError
        For a phase that is not a finite real number or a bad ``terminal``; a model
        without a drive is refused when solved.
    """
    return Event("section", check_real("phase", phase), _TWO_PI, 0.0, _terminal(terminal))


def as_events(events, functions=True):
    """A list of events from an :class:`Event`, a ``numba.njit`` event function (where
    ``functions``) or a non-empty sequence of them, or a TypeError."""
    def taken(e):
        return isinstance(e, Event) or (functions and is_event_function(e))

    items = [events] if taken(events) else events
    try:
        items = list(items)
    except TypeError:
        items = None
    if not items or not all(taken(e) for e in items):
        bad = events if items is None or not items else next(e for e in items if not taken(e))
        if is_event_function(bad):
            raise TypeError(
                f"the compiled event table takes the built-in events (mbm.angle_event, mbm.velocity_event, "
                f"mbm.section_event), got the numba.njit function {bad!r}; an event function "
                "g(t, theta, theta_dot) is taken by mbm.solve, Integrator.solve and solve_batch")
        if callable(bad):
            raise TypeError(
                "events are built-in events (mbm.angle_event, mbm.velocity_event, mbm.section_event) "
                f"or numba.njit functions g(t, theta, theta_dot), got the Python callable {bad!r}: "
                "decorate it with numba.njit, or use solve_ivp(method=mbm.MBM, events=g) for g(t, y)")
        raise TypeError(f"events must be an mbm event, a numba.njit event function or a non-empty sequence "
                        f"of them, got {bad!r}")
    return items


def _table(ig, items):
    # The compiled watch's table of the built-in events, after the checks that depend
    # on the Integrator.
    if ig._kind != window.KIND_TAYLOR:
        raise ValueError(
            f"events are located on Taylor windows (polynomials); approximant {ig.approximant.name!r} "
            "has none: use approximant='auto' or 'taylor*' (or solve_ivp(method=mbm.MBM, events=...))")
    if any(isinstance(e, Event) and e.kind == "section" for e in items) and not ig.model.driven:
        raise ValueError("section_event needs a driven model (drive_amplitude != 0 and drive_frequency > 0)")
    rows = [e._row() for e in items if isinstance(e, Event)]
    return np.array(rows, dtype=np.float64).reshape(len(rows), EV_WIDTH)


def lock_allowed(ev):
    """Whether the locked regime may be taken while the events of table ``ev`` are
    watched (on an undriven scene): every event an angle event or a velocity event at a
    level other than 0 (turning points, θ' = 0, occur in every locked swing)."""
    kind, value = ev[:, 0], ev[:, 1]
    return bool(np.all((kind == EV_ANGLE) | ((kind == EV_VELOCITY) & (value != 0.0))))


def _event_words(ig, regimes):
    # The Integrator's record with the regimes taken while watching (built once per set).
    cache = ig.__dict__.setdefault("_words_events", {})
    words = cache.get(regimes)
    if words is None:
        words = ig._words.copy()
        words.view(record.RUN)[0]["switch"]["regimes"] = regimes
        cache[regimes] = words
    return words


def check_max_events(max_events):
    """``max_events`` as an int >= 1, or -1 for None (all), else a TypeError/ValueError."""
    if max_events is None:
        return -1
    if not isinstance(max_events, numbers.Integral) or isinstance(max_events, (bool, np.bool_)):
        raise TypeError(f"max_events must be an int >= 1 or None, got {max_events!r}")
    if max_events < 1:
        raise ValueError(f"max_events must be an int >= 1 or None, got {max_events!r}")
    return int(max_events)


def solve_events(ig, t0, t1, theta0, v0, t_eval, wrap, events, *, max_events=None):
    """:meth:`mbm.Integrator.solve` with ``events`` (span and state checked): the run with
    its events located on its windows; returns the result with ``t_events``,
    ``y_events``, ``winding_events`` and ``n_events``."""
    items = as_events(events)
    cap = check_max_events(max_events)
    ev = _table(ig, items)
    if wrap is not False and wrap is not True:
        raise ValueError(f"wrap must be True or False, got {wrap!r}")
    if t_eval is None:
        if wrap:
            raise ValueError("wrap=True needs t_eval (the window ends are reported as θ)")
        te, out = np.empty(0), np.empty((2, 0))
    else:
        te = as_t_eval(t_eval)
        problem = t_eval_problem(te, t0, t1, False)
        if problem:
            raise t_eval_error(problem, t0, t1)
        out = np.empty((3 if wrap else 2, te.size))
    h = ig._h
    if ig._span_plan:
        h = controller.plan_windows(ig.approximant, None, ig.max_step, abs(t1 - t0))[1]
    funcs = [(e, g) + event_function_options(g) for e, g in enumerate(items) if is_event_function(g)]
    if funcs:
        regimes = REGIMES_OFF  # g's events are not a stored period's shifted
    else:
        regimes = REGIMES_ALL if lock_allowed(ev) and not ig.model.driven else REGIMES_PERIODIC
    while True:
        words = _event_words(ig, regimes).copy()
        words[_W["t"]], words[_W["theta"]], words[_W["v"]], words[_W["t_bound"]] = t0, theta0, v0, t1
        words[_W["h_abs"]] = h
        if t_eval is not None:
            out[:] = np.nan
        run = _Run(ig, ev, cap, t0, t1, te, out, p=words.view(record.RUN), items=items, funcs=funcs)
        if run.go() or regimes == REGIMES_PERIODIC:
            return run.result(items, wrap)
        regimes = REGIMES_PERIODIC  # a locked window may reach a level: without the locked regime


class _Run:
    """One run with its event watch: the compiled loop in chunks of stored windows, each
    chunk's events located before the next (a terminal event stops it).  ``funcs``:
    the event functions among ``items`` as (index, g, direction, terminal count); with
    them the windows are the approximant's (no regime) and each chunk's events of every
    kind are merged in time order (:meth:`_merge`)."""

    def __init__(self, ig, ev, cap, t0, t1, te, out, *, p, items, funcs):
        self.ig, self.ev, self.t0, self.t1, self.te, self.out, self.p = ig, ev, t0, t1, te, out, p
        self.direction = 1.0 if t1 >= t0 else -1.0
        self.width = max(_HEADER + int(p[0]["control"]["karg"]) + 1 + _N_EXTRA, CYCLE_WIDTH)
        self.evf = np.empty((EVENTS_CAPACITY, 4))
        self.evi = np.empty(EVENTS_CAPACITY, np.int64)
        self.count = 0
        n_items = len(items)
        self.hits = np.zeros(n_items, np.int64)
        self.stored = np.zeros(n_items, np.int64)
        self.cap = np.full(n_items, cap, np.int64)
        # The built-in events' rows of ``items`` (ev's rows in order) and their terminal counts.
        self.builtin = np.array([e for e, item in enumerate(items) if isinstance(item, Event)], np.int64)
        self.terminal = np.zeros(n_items)
        self.terminal[self.builtin] = ev[:, 4]
        self.funcs = funcs
        for e, _, _, stops in funcs:
            self.terminal[e] = stops
        self.refs = [np.zeros(4) for _ in funcs]
        # With functions, the built-in events are located all, none terminal (_merge).
        self.ev_all = ev.copy()
        self.ev_all[:, 4] = 0.0
        self.ends_t, self.ends_y = [], []
        self.stopped = False
        self.windows_before = 0

    def go(self):
        """Run to the end or the terminal event; False where a locked window may reach
        an event's level (the run is then to be taken without the locked regime)."""
        p, r = self.p, self.p[0]
        cap = FIRST_CHUNK
        while True:
            win_t, win_y = np.empty(cap + 1), np.empty((cap + 1, 2))
            win_coef = np.empty((cap, self.width))
            runner = loop.runner_for(r)
            before = int(r["progress"]["n_windows"])
            n = runner(record.words_of(p), False, (0.0, 0.0, 0.0, 0.0, 0.0),
                       (self.te, self.out, win_t, win_y, win_coef, np.zeros(1, np.int64)))
            start_theta = np.ascontiguousarray(win_y[: n + 1, 0])
            last = int(r["progress"]["status"]) != STATUS_PAUSED
            if self.funcs:
                stop, ok = self._merge(win_t, start_theta, win_coef, n, not self.ends_t, last)
            else:
                stop, ok = self._locate(win_t, start_theta, win_coef, n)
            if ok == WATCH_LOCKED:
                return False
            if ok == WATCH_CROWDED:
                raise RuntimeError("a window held more crossings of one level than the event watch takes "
                                   "(WINDOW_CROSSINGS); pass a smaller max_step")
            first = 0 if not self.ends_t else 1
            if stop >= 0:
                self.stopped = True
                self.windows_before = before + stop + 1
                self.ends_t.append(win_t[first: stop + 1].copy())
                self.ends_y.append(win_y[first: stop + 1].copy())
                return True
            self.ends_t.append(win_t[first: n + 1].copy())
            self.ends_y.append(win_y[first: n + 1].copy())
            if last:
                return True
            cap = min(2 * cap, LAST_CHUNK)

    def _locate(self, win_t, start_theta, win_coef, n, *, ev=None, hits=None, stored=None, cap=None):
        # The built-in events of n windows (locate): (stop window, verdict).
        model = self.ig.model
        lock = np.array([model.gamma, model.omega, self.ig.rtol, self.ig.atol])
        tally = (self.hits if hits is None else hits, self.stored if stored is None else stored,
                 self.cap if cap is None else cap)
        ev = self.ev if ev is None else ev
        windows = (win_t, start_theta, win_coef, n)
        self._reserve(self.count + cycle_events_bound(windows, ev, tally))
        self.evf, self.evi, self.count, stop, ok = locate(
            windows, ev, tally,
            (model.drive_frequency, model.drive_phase, self.direction), (self.evf, self.evi, self.count), lock)
        return stop, ok

    def _reserve(self, need):
        # The event buffers grown to ``need`` rows at once (numpy's allocation: the stored
        # cycle's events are written in one sweep, not pushed one by one).
        if need > self.evi.size:
            evf, evi = np.empty((need, 4)), np.empty(need, np.int64)
            evf[: self.count], evi[: self.count] = self.evf[: self.count], self.evi[: self.count]
            self.evf, self.evi = evf, evi

    def _merge(self, win_t, start_theta, win_coef, n, first, last):
        # Every event of n windows, built-in (all, none terminal) and g's, in time order;
        # then counted, capped and stopped at the terminal one: (stop window, verdict).
        rows = []
        if self.builtin.size:
            c0 = self.count
            zeros = np.zeros(self.ev.shape[0], np.int64)
            _, ok = self._locate(win_t, start_theta, win_coef, n, ev=self.ev_all, hits=zeros, stored=zeros.copy(),
                                 cap=np.full_like(zeros, -1))
            if ok != WATCH_OK:
                return -1, ok
            found = self.evf[c0: self.count]
            rows.append(np.column_stack((found, self.builtin[self.evi[c0: self.count]])))
            self.count = c0
        for (e, g, want, _), ref in zip(self.funcs, self.refs):
            found, m = function_crossings(g, want, (win_t, start_theta, win_coef, n), ref, first, last)
            if m < 0:
                raise ValueError(f"the event function {g!r} returned a non-finite value at t={found[0, 0]!r}")
            found = found[:m].copy()
            found[:, 3] = np.nan
            rows.append(np.column_stack((found, np.full(m, float(e)))))
        rows = np.concatenate(rows) if rows else np.empty((0, 5))
        return self._count(rows[np.lexsort((rows[:, 4], self.direction * rows[:, 0]))], win_t, n)

    def _count(self, rows, win_t, n):
        # Rows (t, θ, θ', m, e) in time order counted into hits, stored up to the caps
        # and cut at the first terminal occurrence: (stop window or -1, WATCH_OK).
        e = rows[:, 4].astype(np.int64)
        rank = np.zeros(e.size, np.int64)
        for q in np.unique(e):
            sel = e == q
            rank[sel] = self.hits[q] + np.arange(np.count_nonzero(sel))
        stops = self.terminal[e]
        fires = np.flatnonzero((stops > 0.0) & (rank + 1 >= stops))
        stop = -1
        if fires.size:
            rows, e, rank = rows[: fires[0] + 1], e[: fires[0] + 1], rank[: fires[0] + 1]
            d = self.direction
            stop = int(np.clip(np.searchsorted(d * win_t[: n + 1], d * rows[-1, 0], side="left") - 1, 0, n - 1))
        np.add.at(self.hits, e, 1)
        keep = (self.cap[e] < 0) | (rank < self.cap[e])
        if stop >= 0:
            keep[-1] = True
        np.add.at(self.stored, e[keep], 1)
        new = rows[keep]
        self.evf = np.concatenate((self.evf[: self.count], new[:, :4]))
        self.evi = np.concatenate((self.evi[: self.count], new[:, 4].astype(np.int64)))
        self.count = self.evf.shape[0]
        return stop, WATCH_OK

    def result(self, items, wrap):
        ig, r = self.ig, self.p[0]
        status = int(r["progress"]["status"])
        n_windows = int(r["progress"]["n_windows"])
        regime, t_regime = int(r["switch"]["regime"]), float(r["switch"]["t_regime"])
        evf, evi = self.evf[: self.count], self.evi[: self.count]
        if self.te.size:
            j = int(r["progress"]["j"])
            t, y = self.te[:j], self.out[:, :j]
        else:
            t = np.concatenate(self.ends_t)
            y = np.concatenate(self.ends_y).T
        if self.stopped:
            t_stop = evf[-1, 0]
            status, n_windows = STATUS_EVENT, self.windows_before
            if self.te.size:
                keep = int(np.count_nonzero(self.direction * (t - t_stop) <= 0.0))
                t, y = t[:keep], y[:, :keep]
            else:
                t = np.append(t, t_stop)
                y = np.concatenate((y, evf[-1:, 1:3].T), axis=1)
            if regime != REGIME_NONE and self.direction * (t_regime - t_stop) > 0.0:
                regime, t_regime = REGIME_NONE, math.nan  # switched after the event
        summary = run_summary(self.p.view(np.float64))
        if self.stopped and regime == REGIME_NONE:
            # The record may have run past a terminal event: only a switch before it counts.
            summary = RunSummary(REGIME_NAMES[REGIME_NONE], math.nan, math.nan)
        res = SolveResult(ig._base)
        if wrap:
            res["winding"] = y[2].astype(np.int64)
            y = y[:2]
        res.update(t=t, y=y, success=status in (STATUS_OK, STATUS_EVENT), status=status,
                   message=STATUS_MESSAGES[status], n_windows=n_windows, regime=summary.regime,
                   t_regime=t_regime, period=summary.period, mean_velocity=summary.mean_velocity)
        res["t_events"], res["y_events"], res["winding_events"] = [], [], []
        res["n_events"] = self.hits.copy()
        for e, item in enumerate(items):
            # One event's rows, in one compiled pass; a terminal event past the cap is only the stop.
            k = int(self.stored[e]) if self.cap[e] < 0 else int(min(self.stored[e], self.cap[e]))
            cols = (np.empty(k), np.empty((k, 2)), np.empty(k, np.int64))
            from_theta = not isinstance(item, Event) or item.kind == "velocity"  # θ's winding count
            k = event_columns((evf, evi, self.count), e, cols, from_theta)
            res["t_events"].append(cols[0][:k])
            res["y_events"].append(cols[1][:k])
            res["winding_events"].append(cols[2][:k])
        return res


def batch_table(events, max_events, kinds, amp, freq, names):
    """The event table and cap of :func:`mbm.solve_batch`'s ``events``, ``max_events``
    (every scene on Taylor windows, and driven for a section event), or a
    TypeError/ValueError naming the first scene that cannot take them."""
    cap = check_max_events(max_events)
    if events is None:
        if cap >= 0:
            raise ValueError("max_events needs events")
        return None, cap, None
    items = as_events(events)
    bad = np.flatnonzero(kinds != window.KIND_TAYLOR)
    if bad.size:
        raise ValueError(
            f"events are located on Taylor windows (polynomials); scene {bad[0]}'s approximant "
            f"{names[bad[0]]!r} has none: use approximant='auto' or 'taylor*'")
    if any(isinstance(e, Event) and e.kind == "section" for e in items):
        bad = np.flatnonzero((amp == 0.0) | (freq <= 0.0))
        if bad.size:
            raise ValueError(f"section_event needs driven scenes (drive_amplitude != 0 and drive_frequency > 0); "
                             f"scene {bad[0]} is not")
    rows = [e._row() for e in items if isinstance(e, Event)]
    return np.array(rows, dtype=np.float64).reshape(len(rows), EV_WIDTH), cap, items


def run_batch_events(p, te, out, order, ev, cap, cancel, fresh):
    """The batch's scenes run with the event watch, in groups on threads: the scenes the
    lanes take (:func:`mbm.core.lanes.lane_eligible`) by the lanes with events, finished
    (after a hand-off) and the others by the loop in stored chunks
    (:mod:`mbm.core.event_batch`).  The locked regime is taken where
    :func:`lock_allowed` (undriven scenes; those whose locked window may reach a level
    run again without it, their records from ``fresh(rows)``).  Returns the stored events
    (rows t, θ, θ', m; event; scene) and the counts (N, n_events)."""
    from ..core import event_batch
    from ..core import lanes

    undriven = p["model"]["drive_amp"] == 0.0
    p["switch"]["regimes"] = np.where(undriven & lock_allowed(ev), REGIMES_ALL, REGIMES_PERIODIC)
    width = max(_HEADER + int(p["control"]["karg"].max()) + 1 + _N_EXTRA, CYCLE_WIDTH)
    hits = np.zeros((p.size, ev.shape[0]), np.int64)
    stored = np.zeros_like(hits)
    again = np.zeros(p.size, np.int64)
    handed = np.zeros(p.size, np.int64)
    found = []
    ids = np.asarray(order, dtype=np.int64)

    def rows(ids):
        entry = event_batch.events_entry(lanes.batch_flags(p[ids] if ids.size < p.size else p))
        return [lambda g=g: entry(p, g, (te, out, cancel), ev, (cap, hits, stored), width, again)
                for g in lanes.groups(ids)]

    while ids.size:
        in_lanes = lanes.eligible_rows(p)[ids]
        tasks = [lambda g=g: lanes.run_lanes_events(p, g, te, out, cancel,
                                                         lanes.LaneEvents(ev, cap, hits, stored, handed))
                 for g in lanes.groups(ids[in_lanes])]
        if not in_lanes.all():
            tasks += rows(ids[~in_lanes])
        found += lanes.run_tasks(tasks, cancel)
        cont = np.flatnonzero(handed)
        handed[:] = 0
        if cont.size:
            found += lanes.run_tasks(rows(cont), cancel)
        ids = np.flatnonzero(again)
        if ids.size:
            # A scene whose locked window may reach a level: from its start, without it.
            found = [tuple(a[again[f[2]] == 0] for a in f) for f in found]
            p[ids] = fresh(ids)
            p["switch"]["regimes"][ids] = REGIMES_PERIODIC
            out[ids] = np.nan
            hits[ids] = 0
            stored[ids] = 0
            again[:] = 0
    evf = np.concatenate([f[0] for f in found]) if found else np.empty((0, 4))
    evi = np.concatenate([f[1] for f in found]) if found else np.empty(0, np.int64)
    evs = np.concatenate([f[2] for f in found]) if found else np.empty(0, np.int64)
    return evf, evi, evs, hits


def run_batch_functions(p, te, out, order, ev, cap, items, drive):
    """The batch's scenes run one by one as :func:`mbm.solve` runs a scene with event
    functions among ``items`` (no regime; :class:`_Run`, the loop in chunks and g's
    locator, both compiled), so each scene's events are mbm.solve's bit for bit; a
    terminal event stops its scene as :func:`mbm.core.event_batch.stop_at` does.
    Returns the stored events and the counts as :func:`run_batch_events`."""
    from ..core.event_batch import stop_row

    funcs = [(e, g) + event_function_options(g) for e, g in enumerate(items) if is_event_function(g)]
    p["switch"]["regimes"] = REGIMES_OFF
    hits = np.zeros((p.size, len(items)), np.int64)
    found = []
    for i in order:
        r = p[i]
        m, c = r["model"], r["control"]
        scene = _Scene(int(c["kind"]), float(m["gamma"]), float(m["omega"]), float(drive[1][i]),
                       float(drive[2][i]), float(c["rtol"]), float(c["atol"]))
        run = _Run(scene, ev, cap, float(r["state"]["t"]), float(r["state"]["t_bound"]), te, out[i],
                   p=p[i: i + 1], items=items, funcs=funcs)
        run.go()
        if run.stopped:
            stop_row(p, i, out[i], te, run.evf, np.int64(run.count - 1), np.int64(run.windows_before), run.direction)
        hits[i] = run.hits
        found.append((run.evf[: run.count].copy(), run.evi[: run.count].copy(), np.full(run.count, i, np.int64)))
    evf = np.concatenate([f[0] for f in found]) if found else np.empty((0, 4))
    evi = np.concatenate([f[1] for f in found]) if found else np.empty(0, np.int64)
    evs = np.concatenate([f[2] for f in found]) if found else np.empty(0, np.int64)
    return evf, evi, evs, hits


class _Scene:
    """What :class:`_Run` reads of an Integrator, for a scene of a batch."""

    __slots__ = ("_kind", "model", "rtol", "atol")

    def __init__(self, kind, gamma, omega, drive_frequency, drive_phase, rtol, atol):
        self._kind, self.rtol, self.atol = kind, rtol, atol
        self.model = _SceneModel(gamma, omega, drive_frequency, drive_phase)


class _SceneModel:
    __slots__ = ("gamma", "omega", "drive_frequency", "drive_phase")

    def __init__(self, gamma, omega, drive_frequency, drive_phase):
        self.gamma, self.omega, self.drive_frequency, self.drive_phase = gamma, omega, drive_frequency, drive_phase


def batch_event_arrays(items, cap, evf, evi, evs, hits):
    """``t_events`` (N, n_events, K), ``y_events`` (N, n_events, K, 2) NaN past each
    stored count, ``winding_events`` (N, n_events, K) int64 (0 past the count) and
    ``n_events`` (N, n_events): K is ``cap``, or the most events any scene stored."""
    n, nev = hits.shape
    order = np.lexsort((np.arange(evi.size), evi, evs))  # by scene, event, then time
    evf, evi, evs = evf[order], evi[order], evs[order]
    new = np.ones(evi.size, bool)
    new[1:] = (evs[1:] != evs[:-1]) | (evi[1:] != evi[:-1])
    start = np.maximum.accumulate(np.where(new, np.arange(evi.size), 0)) if evi.size else np.empty(0, np.int64)
    rank = np.arange(evi.size) - start
    k = cap if cap >= 0 else (int(rank.max()) + 1 if rank.size else 0)
    keep = rank < k  # a terminal event past the cap is only the stop
    evf, evi, evs, rank = evf[keep], evi[keep], evs[keep], rank[keep]
    t_events = np.full((n, nev, k), np.nan)
    y_events = np.full((n, nev, k, 2), np.nan)
    winding = np.zeros((n, nev, k), np.int64)
    t_events[evs, evi, rank] = evf[:, 0]
    y_events[evs, evi, rank] = evf[:, 1:3]
    velocity = np.array([not isinstance(e, Event) or e.kind == "velocity" for e in items])[evi]
    winding[evs, evi, rank] = np.where(velocity, np.floor((evf[:, 1] + math.pi) / _TWO_PI), evf[:, 3])
    return t_events, y_events, winding, hits
