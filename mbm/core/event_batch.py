"""The event watch of :func:`mbm.solve_batch`: each scene's run in chunks of stored
windows, each chunk's events located (:func:`mbm.core.event_watch.locate`) before the
next, as :mod:`mbm.events.compiled` does for one scene, inside one compiled call per group of
scenes (no GIL, so the groups run on threads).

A terminal event stops its scene: the record's status is STATUS_EVENT, its state the
event's, its outputs past the event NaN and a regime taken after the event undone (as
:func:`mbm.solve` reports it); the other scenes are unaffected.  A scene whose locked
window may reach a level (WATCH_LOCKED) is marked in ``again`` with its events
dropped, for the caller to run again without the locked regime.  A scene trapped in
its well out of every event's reach, its outputs written
(:func:`mbm.core.event_watch.trapped_unreachable`), ends before its next chunk, locked
(the lanes test it before each window).
"""

import math

import numba
import numpy as np

from ..compile.jit import kernel
from .event_watch import (WATCH_CROWDED, WATCH_LOCKED, WATCH_OK, Tally, Watch, locate, taylor_events,
                          trap_allowed, trapped_unreachable)
from .chains import _run_sets, flag_bits
from .window import KIND_TAYLOR
from ..regimes.common import REGIME_LOCKED, REGIME_NONE
from ..status import STATUS_CROWDED, STATUS_EVENT, STATUS_OK, STATUS_PAUSED

__all__ = ["scene_events_for", "events_rows_for", "events_entry", "lane_events", "stop_at", "stop_row", "FIRST_CHUNK", "LAST_CHUNK"]

# Windows stored per call of the loop: a scene's first chunk short (a first slip of the
# I-V ensemble lies ~6 windows in, and a terminal event wastes the rest of its chunk;
# 4 pays more calls than it saves), doubling to the last (the store's memory per thread).
FIRST_CHUNK = 8
LAST_CHUNK = 4096
# Events reserved per group before its first scene (the buffers double as they fill).
EVENTS_CAPACITY = 256


@kernel
def _grow(evs, size):
    # The scene column grown to the event buffers' size (locate doubles those).
    if evs.size >= size:
        return evs
    out = np.empty(size, np.int64)
    out[: evs.size] = evs
    return out


@kernel
def stop_at(r, out_i, t_eval, evf, k, n_windows, direction):
    # The scene stopped by its terminal event (row k of evf): status, state, windows,
    # no outputs past the event, no regime taken after it.
    t_stop = evf[k, 0]
    r.progress.status = STATUS_EVENT
    r.progress.n_windows = n_windows
    r.state.t, r.state.theta, r.state.v = t_stop, evf[k, 1], evf[k, 2]
    for j in range(t_eval.size):
        if direction * (t_eval[j] - t_stop) > 0.0:
            for w in range(out_i.shape[0]):
                out_i[w, j] = math.nan
    if r.switch.regime != REGIME_NONE and direction * (r.switch.t_regime - t_stop) > 0.0:
        r.switch.regime = REGIME_NONE
        r.switch.t_regime = math.nan


@kernel
def stop_row(p, i, out_i, t_eval, evf, k, n_windows, direction):
    """:func:`stop_at` for row ``i`` of the records ``p`` (a caller in Python)."""
    stop_at(p[i], out_i, t_eval, evf, k, n_windows, direction)


@kernel
def lane_events(p, lane, i, win, run, events, ws, found):
    """The events of a lane's window, appended as :func:`locate` does; a terminal event
    stops the scene (:func:`stop_at`, the lane freed), a crowded window is
    STATUS_CROWDED.

    ``lane`` = (ln, handed): the lane and the scenes handed off; ``i`` the scene;
    ``win`` = (coef, t_w, t_new, k): the window's coefficients from t_w to t_new, winding
    k (:func:`mbm.core.lanes._lanes_for`); ``run`` = (direction, t_eval, out);
    ``events`` = (ev, caps, hits_all, stored_all): the table, the caps and every scene's
    counts; ``ws`` the :func:`mbm.core.event_watch.workspace`; ``found`` = (evf, evi,
    evs, count).  Returns the grown buffers and count."""
    ln, handed = lane
    coef, t_w, t_new, k = win
    direction, t_eval, out = run
    ev, caps, hits_all, stored_all = events
    evf, evi, evs, count = found
    r = p[i]
    c0 = count
    evf, evi, count, verdict, fired = taylor_events(coef, (t_w, t_new - t_w, k), ev,
                                                    Tally(hits_all[i], stored_all[i], caps),
                                                    Watch(r.model.drive_freq, r.model.drive_phase, direction), ws,
                                                    (evf, evi, count))
    evs = _grow(evs, evi.size)
    evs[c0:count] = i
    if verdict != WATCH_OK or fired:
        if ln.scene == i:
            # Still in its lane: the lane's windows written back, the lane freed.
            r.progress.n_windows = ln.n_windows
            ln.scene = -1
            ln.ready = 0
        handed[i] = 0
        if fired:
            stop_at(r, out[i], t_eval, evf, count - 1, r.progress.n_windows, direction)
        else:
            r.progress.status = STATUS_CROWDED
    return evf, evi, evs, count


def scene_events_for(flags):
    """The compiled run with events of one scene (Taylor windows), for the regime sets
    flagged in ``flags`` (:func:`mbm.core.lanes.batch_flags`; constants of the closure,
    so only those sets' entries are compiled, each closure cached apart)."""
    bits = flag_bits(tuple(flags[:1]) + (0, 0, 0) + tuple(flags[4:]))  # kind "taylor" alone

    @numba.njit(cache=True, nogil=True)
    def run_scene_events(p, i, run, ev, tally, store, found):
        """Run scene ``i`` of ``p`` (fresh, or paused by the lanes) in chunks of stored
        windows, locating the events ``ev`` of each and appending them to ``found``.

        ``run`` = (t_eval, out_i, cancel); ``tally`` = (hits, stored, caps): its counts
        so far and on, at most caps of each stored (-1: all); ``store`` = (win_t, win_y,
        win_coef, lock): the windows' store (:data:`LAST_CHUNK` long) and a scratch of 4;
        ``found`` = (evf, evi, evs, count).  Returns the buffers, the count and whether
        the scene is to be run again without the locked regime (its events then dropped)."""
        t_eval, out_i, cancel = run
        hits, stored, caps = tally
        win_t, win_y, win_coef, lock = store
        evf, evi, evs, count = found
        r = p[i]
        lock[0], lock[1], lock[2], lock[3] = r.model.gamma, r.model.omega, r.control.rtol, r.control.atol
        first = count
        direction = 1.0 if r.state.t_bound >= r.state.t else -1.0
        chunk = FIRST_CHUNK
        while True:
            if trap_allowed(r, direction, r.progress.j, t_eval.size) and trapped_unreachable(
                    r.state.theta, r.state.v, ev, r.model.gamma, r.model.omega, r.control.rtol, r.control.atol,
                    math.asin(r.model.gamma / (r.model.omega * r.model.omega))):
                # Trapped below every level, its outputs written: it ends here, locked.
                r.progress.status = STATUS_OK
                r.switch.regime = REGIME_LOCKED
                r.switch.t_regime = r.state.t
                break
            before = r.progress.n_windows
            n = _run_sets(KIND_TAYLOR, bits, p[i:i + 1],
                          (t_eval, out_i, win_t[: chunk + 1], win_y[: chunk + 1], win_coef[:chunk], cancel))
            c0 = count
            evf, evi, count, stop, ok = locate((win_t, np.ascontiguousarray(win_y[: n + 1, 0]), win_coef, n), ev,
                                               (hits, stored, caps),
                                               (r.model.drive_freq, r.model.drive_phase, direction),
                                               (evf, evi, count), lock)
            evs = _grow(evs, evi.size)
            evs[c0:count] = i
            if ok == WATCH_LOCKED:
                return evf, evi, evs, first, True
            if ok == WATCH_CROWDED:
                r.progress.status = STATUS_CROWDED
                break
            if stop >= 0:
                stop_at(r, out_i, t_eval, evf, count - 1, before + stop + 1, direction)
                break
            if r.progress.status != STATUS_PAUSED:
                break
            chunk = min(2 * chunk, LAST_CHUNK)
        return evf, evi, evs, count, False

    return run_scene_events


def events_rows_for(flags):
    """The compiled run with events of the scenes ``ids`` (Taylor windows), for the
    regime sets flagged in ``flags`` (:func:`scene_events_for`)."""
    run_scene_events = scene_events_for(flags)

    @numba.njit(cache=True, nogil=True)
    def run_rows_events(p, ids, run, ev, counts, width, again):
        """Run the scenes ``ids`` of ``p`` (fresh, or paused by the lanes) watching the
        events ``ev``.  ``run`` = (t_eval, out, cancel); ``counts`` = (cap, hits_all,
        stored_all): at most cap of each event stored per scene (-1: all), scene i's
        counts so far and on ``hits_all[i]``, ``stored_all[i]``; ``width``: the windows'
        coefficient rows; ``again[i]`` is set to 1 where the scene is to be run without
        the locked regime.  Returns the stored events: rows (t, θ, θ', m), event index,
        scene."""
        t_eval, out, cancel = run
        cap, hits_all, stored_all = counts
        evf = np.empty((EVENTS_CAPACITY, 4))
        evi = np.empty(EVENTS_CAPACITY, np.int64)
        evs = np.empty(EVENTS_CAPACITY, np.int64)
        count = 0
        caps = np.full(ev.shape[0], cap, np.int64)
        win_t = np.empty(LAST_CHUNK + 1)
        win_y = np.empty((LAST_CHUNK + 1, 2))
        win_coef = np.empty((LAST_CHUNK, width))
        lock = np.empty(4)
        for i in ids:
            evf, evi, evs, count, locked = run_scene_events(p, i, (t_eval, out[i], cancel), ev,
                                                            (hits_all[i], stored_all[i], caps),
                                                            (win_t, win_y, win_coef, lock), (evf, evi, evs, count))
            if locked:
                again[i] = 1
        return evf[:count].copy(), evi[:count].copy(), evs[:count].copy()

    return run_rows_events


#: The compiled runs with events, per flags met so far (:func:`events_rows_for`).
EVENTS_ENTRIES = {}


def events_entry(flags):
    """The compiled run with events for ``flags`` (made at its first use)."""
    entry = EVENTS_ENTRIES.get(flags)
    if entry is None:
        entry = EVENTS_ENTRIES[flags] = events_rows_for(flags)
    return entry
