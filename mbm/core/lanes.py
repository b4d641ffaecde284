"""The lockstep lanes of :func:`mbm.solve_batch`: LANES scenes per round, one window each.

A batch group (:func:`_lanes`) is a scheduler over the loop's window: LANES scenes
advance one ordinary Taylor window per round in lockstep, the loop's tests, controller
and output steps per lane (the same compiled controller, :mod:`mbm.core.controller`,
and the same cycle watch), the anchors and the first tries' window ends computed for
all lanes at once by lane-wise copies of the one-scene kernels (the same operations per
lane, so the same bits); every other window (a regime's, a failure's, the run's end)
is the loop's own, the lane handing its scene over as a paused run.
"""

import collections
import math
import threading

import numba
import numpy as np

from ..approximants.taylor_simd import (
    HEADER as SIMD_HEADER,
    LANES,
    SIMD_ORDER,
    horner24_lanes,
    taylor24_lanes,
)
from ..compile.jit import INLINE, kernel
from .controller import (
    CONTROLLER_ADAPTIVE,
    _adaptive_window_taylor,
    _first_window_taylor,
    accept_try,
    first_try,
)
from .chains import F_CYCLE, F_DAMPED, F_TAYLOR_SIMD, REACHES, _run_sets, flag_bits, set_flag
from .record import window_control
from .emit import Span, emit_taylor
from .loop import _regime_set, damped_setup, locked_test
from ..regimes.locked import LockSetup
from .window import (
    KIND_TAYLOR,
    _reduce_phi,
    estimate,
    theta_of,
    window_log_eps,
)
from ..regimes.common import REGIME_LOCKED, REGIME_NONE
from ..regimes.cycle import CycleSpan, CycleWatch
from ..regimes.cycle_windows import _TWO_PI, _watch_cycle
from ..status import STATUS_ANCHOR, STATUS_OK
from .event_batch import EVENTS_CAPACITY, lane_events
from .event_watch import trap_allowed, trapped_unreachable, window_may_cross, workspace

# The per-window pieces of a lane are inlined (called, they made a 512-scene batch
# ~16 % slower); the hand-off (once per scene, and the loop's entries behind it) and
# the start are called: numba copies an inlined body's whole variable scope once per
# block at each site, so a large piece inlined costs seconds of a first call.


# Scenes per lane group of run_batch: a group keeps its LANES lanes full from its own
# scenes, so only its last few run with idle lanes; large enough that this tail is a
# few per cent, small enough that the groups balance over the threads.
LANE_GROUP = 256


# _lanes names its eight coefficient rows in one tuple.
assert LANES == 8


# The lockstep state of one lane (_lanes): the scene, the loop's locals (run_entry
# of mbm.core.loop._runner) that change per window, and the constants it derives once per call.
LANE = np.dtype([
    ("scene", np.int64), ("t", np.float64), ("phi", np.float64), ("v", np.float64),
    ("h_abs", np.float64), ("wind", np.float64), ("j", np.int64), ("n_windows", np.int64),
    ("direction", np.float64), ("log_eps", np.float64), ("lk_d", np.float64), ("lk_wl2", np.float64),
    ("lk_g0", np.float64), ("lk_g1", np.float64), ("lk_sd", np.float64), ("lk_q2", np.float64),
    ("can_lock", np.int64), ("can_lock2", np.int64), ("can_cycle", np.int64), ("sec_off", np.float64),
    ("sec_acc", np.float64), ("ready", np.int64), ("h_try", np.float64), ("prior", np.float64),
    ("first", np.int64), ("t_end", np.float64),
])


@numba.njit(**INLINE)
def lane_eligible(r):
    """Whether run record ``r`` can take lockstep windows in the lanes: a fresh undriven
    Taylor run at the vector kernel's degree, adaptive, β > 0, regime switching on (so in
    RS_DAMPED), no window budget and no θ-step limit (everything else runs by the loop
    alone)."""
    c, g = r.control, r.progress
    return (c.kind == KIND_TAYLOR and c.karg == SIMD_ORDER and c.controller == CONTROLLER_ADAPTIVE
            and r.model.drive_amp == 0.0 and r.model.beta > 0.0 and r.switch.regimes != 0 and g.call_windows == 0
            and c.max_dtheta == math.inf and g.n_windows == 0 and r.switch.regime == REGIME_NONE
            and g.status == STATUS_OK)


@kernel
def _lane_start(r, i, ln, coefs, lane):
    # The loop's set-up for a fresh run (the undriven Taylor branches).
    ln.scene = i
    ln.t, ln.phi, ln.v, ln.h_abs, ln.wind = r.state.t, r.state.theta, r.state.v, r.control.h_abs, 0.0
    ln.j, ln.n_windows, ln.ready = r.progress.j, 0, 0
    ln.direction = 1.0 if r.state.t_bound >= r.state.t else -1.0
    ln.log_eps = window_log_eps(r.control.rtol)
    beta, gamma, omega = r.model.beta, r.model.gamma, r.model.omega
    # The loop's set-up of RS_DAMPED, without a window store (width 0).
    may = r.switch.regimes != 0 and r.control.controller == CONTROLLER_ADAPTIVE and ln.direction > 0.0
    can_lock, lk, can_cycle, ln.sec_off, ln.sec_acc = damped_setup(r, may, 0)
    ln.lk_d, ln.lk_wl2, ln.lk_g0, ln.lk_g1, ln.lk_sd, ln.lk_q2, can_lock2 = lk
    ln.can_lock, ln.can_lock2, ln.can_cycle = can_lock, can_lock2, can_cycle
    # The header of the lane's coefficient row (taylor.py's layout; the kernel writes
    # the coefficients after it).
    coefs[lane, 0] = 0.0
    coefs[lane, 1] = SIMD_ORDER
    coefs[lane, 2] = beta
    coefs[lane, 3] = gamma
    coefs[lane, 4] = omega


@kernel
def _lane_write_back(r, ln):
    # The lane's state written back to its record as a paused run's; the lane freed.
    r.state.t, r.state.theta, r.state.v, r.control.h_abs = ln.t, theta_of(ln.wind, ln.phi), ln.v, ln.h_abs
    r.winding.phi, r.winding.wind = ln.phi, ln.wind
    r.progress.n_windows = ln.n_windows
    r.progress.j = ln.j
    ln.scene = -1
    ln.ready = 0


@kernel
def _lane_trap(p, ln, n_out, ev):
    # With events: a lane whose scene is trapped in its well below every level of ``ev``,
    # with its outputs written, ends there (mbm.core.event_watch.trapped_unreachable):
    # its regime locked from now, its status OK.
    r = p[ln.scene]
    c = r.control
    if (trap_allowed(r, ln.direction, ln.j, n_out)
            and trapped_unreachable(theta_of(ln.wind, ln.phi), ln.v, ev, r.model.gamma, r.model.omega, c.rtol,
                                    c.atol, ln.lk_d)):
        _lane_write_back(r, ln)
        r.switch.regime = REGIME_LOCKED
        r.switch.t_regime = r.state.t


#: Where a lane's scene goes when it leaves the lanes: the output times and rows, the
#: loop's (empty) window store, the interrupt flag, and the scenes handed to the event
#: watch's loop (empty without events).
HandOff = collections.namedtuple("HandOff", ("t_eval", "out", "win_t", "win_y", "win_coef", "cancel", "handed"))


#: The flags of a lane's scene in the loop (mbm.core.chains.flag_bits): the default
#: degree's Taylor entries of RS_DAMPED and RS_CYCLE.
_HAND_OFF = F_TAYLOR_SIMD | F_DAMPED | F_CYCLE


@kernel
def _lane_hand_off(p, ln, ho):
    # The lane's state written back as a paused run's, and the run finished by the loop
    # (a lane's scene is in RS_DAMPED, or reached RS_CYCLE); with events (``ho.handed``
    # not empty) marked there instead, for the event watch's loop to finish.
    t_eval, out, win_t, win_y, win_coef, cancel, handed = ho
    i = ln.scene
    _lane_write_back(p[i], ln)
    if handed.size:
        handed[i] = 1
        return
    _run_sets(KIND_TAYLOR, _HAND_OFF, p[i:i + 1], (t_eval, out[i], win_t, win_y, win_coef, cancel))


@numba.njit(**INLINE)
def _lane_before(p, ln, q, ins, ho):
    """The loop's tests before the lane's next window, in its order: a lane whose window
    is not an ordinary Taylor one (the run's end, ``max_windows``, the interrupt flag, a
    non-finite state, the locked form) hands off; else the lane's inputs of the
    across-scene kernel.  Returns whether the lane takes a window this round."""
    r = p[ln.scene]
    t, y0, y1, k = ln.t, ln.phi, ln.v, ln.wind
    if (not (ln.direction * (r.state.t_bound - t) > 0.0) or ln.n_windows >= r.progress.max_windows
            or ho.cancel[0] != 0 or not (math.isfinite(y0) and math.isfinite(y1))):
        _lane_hand_off(p, ln, ho)
        return False
    k, y0 = _reduce_phi(k, y0)
    ln.wind, ln.phi = k, y0
    if ln.can_lock != 0:
        lk = LockSetup(ln.lk_d, ln.lk_wl2, ln.lk_g0, ln.lk_g1, ln.lk_sd, ln.lk_q2, ln.can_lock2 != 0)
        if locked_test(r, y0, y1, k * _TWO_PI, lk, False)[0] > 0:
            _lane_hand_off(p, ln, ho)
            return False
    ins[0, q] = r.model.beta
    ins[1, q] = r.model.gamma
    ins[2, q] = r.model.omega * r.model.omega
    ins[3, q] = math.sin(y0)
    ins[4, q] = math.cos(y0)
    ins[5, q] = y0
    ins[6, q] = y1
    return True


@numba.njit(**INLINE)
def _lane_try(r, ln, coef):
    """The controller's first try of the lane's window (the loop's :func:`first_try`, and
    the first window's search for a fresh run): the length whose end θ, θ' the lane-wise
    Horner evaluates (0: below the floor)."""
    t, y0, y1 = ln.t, ln.phi, ln.v
    off = ln.wind * _TWO_PI
    c = r.control
    ctl = window_control(ln.direction, r.state.t_bound, c.max_step, c.rtol, c.atol, c.error_order, ln.log_eps)
    if ln.h_abs <= 0.0:
        ln.h_abs = _first_window_taylor(coef, t, y0, y1, off, r.model.omega, ctl)
    first, ln.h_try, ln.prior, ln.t_end = first_try(KIND_TAYLOR, coef, t, y0, y1, off, ln.h_abs, ctl)
    # A window below the floor: adaptive_window's own status (_lane_window).
    ln.first = 1 if first else 0
    return ln.t_end - t if first else 0.0


@numba.njit(**INLINE)
def _lane_window(p, ln, coef, h, th, v, ho):
    """The lane's window after the lane-wise Horner (``th``, ``v`` at the try's end, ``h``
    after the start): the loop's test of the first try (:func:`accept_try`), on a
    rejection the compiled controller, the outputs (:func:`emit_taylor`) and the cycle
    watch; a failure or a regime switch hands off (``ho``: :data:`HandOff`).  Returns
    the window's end (NaN: no window taken)."""
    t_eval, out = ho.t_eval, ho.out
    wrapped = out.shape[1] == 3
    i = ln.scene
    r = p[i]
    c = r.control
    t, y0, y1, k = ln.t, ln.phi, ln.v, ln.wind
    off = k * _TWO_PI
    accepted, t_new, h_next = False, ln.t_end, 0.0
    ctl = window_control(ln.direction, r.state.t_bound, c.max_step, c.rtol, c.atol, c.error_order, ln.log_eps)
    if ln.first != 0:
        accepted, h_next = accept_try(estimate(KIND_TAYLOR, coef, h), (y0, y1), (th, v), off, ln.prior, ln.h_try,
                                      ctl)
    if not accepted:
        # Rejected (or below the floor): adaptive_window itself, from the start.
        st, t_new, th, v, h_next = _adaptive_window_taylor(coef, t, y0, y1, off, ln.h_abs, ctl)
        if st != STATUS_OK:
            _lane_hand_off(p, ln, ho)
            return math.nan
    j = ln.j
    if j < t_eval.size and ln.direction * (t_eval[j] - t_new) <= 0.0:
        # (The views of out made only for a window that has outputs.)
        out_theta = out[i, 0]
        ln.j = emit_taylor(coef, Span(t, t_new, ln.direction, k), t_eval, j, out_theta, out[i, 1],
                           out[i, 2] if wrapped else out_theta, wrapped)
    if ln.can_cycle != 0 and r.switch.regime == REGIME_NONE:
        m = r.model
        _watch_cycle(KIND_TAYLOR, r, coef, CycleSpan(t, t_new, y0, th, v, k, off),
                     CycleWatch(ln.sec_off, ln.sec_acc, m.beta, m.gamma, m.omega, r.state.t_bound, c.rtol, c.atol))
    ln.t, ln.phi, ln.v, ln.h_abs = t_new, th, v, h_next
    ln.n_windows += 1
    if r.switch.regime != REGIME_NONE:
        _lane_hand_off(p, ln, ho)
    return t_new


def _lanes_for(watch):
    """The lanes' scheduler, without (``watch`` False) or with the event watch (a
    constant of the closure: the other's branches are pruned, each closure cached apart)."""

    @numba.njit(cache=True, nogil=True)
    def run_lanes(p, ids, t_eval, out, cancel, events):
        """Run the scenes ``ids`` of ``p`` (output rows ``out[ids]``), LANES at a time in lockstep.

        Each lockstep round takes one window of every lane: the loop's window for an
        ordinary Taylor window (its tests, controller and output steps, in its order: the
        loop's own functions), with the anchors of all lanes in one call of the
        across-scene kernel (:func:`mbm.approximants.taylor_simd.taylor24_lanes`, each lane's
        coefficients the bits of the one-scene kernel) and the first tries' ends in one
        lane-wise Horner.  A lane whose next window is anything else hands its state to the
        loop as a paused run's, which finishes the scene, and the lane takes the next scene.
        So every scene's windows, outputs and record are those of the loop alone.  Only
        scenes that are :func:`lane_eligible` are run (run_batch sends the others to
        :func:`_rows_for`'s entry); another is STATUS_ANCHOR.  Compiled once: it takes the
        loop's entries of Taylor's RS_DAMPED and RS_CYCLE only.

        With the watch, the events (``events``, a :data:`LaneEvents`: the specs ``ev``, at
        most ``cap`` of each stored, -1: all) are located on each window's polynomial as :func:`mbm.core.event_watch.locate`
        does (counts in ``hits_all``, ``stored_all``); a terminal event stops its scene
        (:func:`mbm.core.event_batch.stop_at`), a trapped scene ends before its next
        window (:func:`_lane_trap`; the event watch's loop tests it before each chunk of
        windows, so there such a scene may take a few windows more), and a scene handed
        off is marked in ``handed`` for the event watch's loop to finish.  Returns the stored events
        (rows t, θ, θ', m; event; scene), empty without the watch.
        """
        ev, cap, hits_all, stored_all, handed = events
        ho = HandOff(t_eval, out, np.empty(0), np.empty((0, 2)), np.empty((0, 0)), cancel, handed)
        caps = np.full(ev.shape[0], cap, np.int64)
        n_buf = EVENTS_CAPACITY if watch else 0
        evf, evi, evs, count = np.empty((n_buf, 4)), np.empty(n_buf, np.int64), np.empty(n_buf, np.int64), 0
        ws = workspace(SIMD_HEADER + SIMD_ORDER + 3)
        lanes = np.zeros(LANES, dtype=LANE)
        ins = np.zeros((7, LANES))
        ins[2, :] = 1.0
        ins[4, :] = 1.0
        coefs = np.zeros((LANES, SIMD_HEADER + SIMD_ORDER + 3))
        soa = np.zeros((SIMD_ORDER + 3, LANES))
        hs = np.zeros(LANES)
        hv = np.zeros((2, LANES))
        for q in range(LANES):
            lanes[q].scene = -1
        # The lanes' coefficient rows, as views made once.
        rows = (coefs[0], coefs[1], coefs[2], coefs[3], coefs[4], coefs[5], coefs[6], coefs[7])
        nxt = 0
        while True:
            live = 0
            for q in range(LANES):
                ln = lanes[q]
                while ln.scene < 0 and nxt < ids.size:
                    i = ids[nxt]
                    nxt += 1
                    if lane_eligible(p[i]):
                        _lane_start(p[i], i, ln, coefs, q)
                    else:
                        # (run_batch sends the lanes only scenes that are lane_eligible)
                        p[i].progress.status = STATUS_ANCHOR
                ln.ready = 1 if ln.scene >= 0 and _lane_before(p, ln, q, ins, ho) else 0
                if watch and ln.ready != 0 and ln.can_lock != 0:
                    _lane_trap(p, ln, t_eval.size, ev)
                live += ln.ready
            if live == 0:
                if nxt >= ids.size:
                    break
                continue
            taylor24_lanes(ins, coefs, soa)
            for q in range(LANES):
                ln = lanes[q]
                hs[q] = _lane_try(p[ln.scene], ln, rows[q]) if ln.ready != 0 else 0.0
            horner24_lanes(soa, hs, hv)
            for q in range(LANES):
                ln = lanes[q]
                if ln.ready != 0:
                    ln.ready = 0
                    i, t_w, k, direction = ln.scene, ln.t, ln.wind, ln.direction
                    t_new = _lane_window(p, ln, rows[q], hs[q], hv[0, q], hv[1, q], ho)
                    if watch and t_new == t_new and window_may_cross(rows[q], t_new - t_w, k, ev):
                        evf, evi, evs, count = lane_events(p, (ln, handed), i, (rows[q], t_w, t_new, k),
                                                           (direction, t_eval, out), (ev, caps, hits_all, stored_all),
                                                           ws, (evf, evi, evs, count))
        return evf[:count].copy(), evi[:count].copy(), evs[:count].copy()

    return run_lanes


#: The lanes without events (run_batch, called with :func:`no_events`) and with the
#: event watch (mbm.events.compiled).
_run_lanes = _lanes_for(False)
run_lanes_events = _lanes_for(True)


#: The event arguments of the lanes (:func:`_lanes_for`): the event specs, how many of
#: each to store (-1: all), the counts found and stored per scene and event, and the
#: scenes handed to the event watch's loop.
LaneEvents = collections.namedtuple("LaneEvents", ("ev", "cap", "hits", "stored", "handed"))


def no_events():
    """The :data:`LaneEvents` of :func:`_run_lanes` for a batch without events (an empty
    ``handed``: a lane hands its scene to the loop)."""
    counts = np.empty((0, 0), np.int64)
    return LaneEvents(np.empty((0, 5)), -1, counts, counts, np.empty(0, np.int64))


def _rows_for(flags):
    """The compiled run of the scenes that do not take the lanes, for a batch whose
    scenes' kinds and regime sets are ``flags`` (:func:`batch_flags`): constants of the
    closure (as one int, :func:`mbm.core.chains.flag_bits`), so only those kinds' and
    sets' entries are compiled (each closure cached apart)."""
    bits = flag_bits(flags)

    @numba.njit(cache=True, nogil=True)
    def run_rows(p, ids, t_eval, out, cancel):
        """Run the scenes ``ids`` of ``p`` (output rows ``out[ids]``) one by one by the loop."""
        win_t, win_y, win_coef = np.empty(0), np.empty((0, 2)), np.empty((0, 0))
        for i in ids:
            _run_sets(p[i].control.kind, bits, p[i:i + 1], (t_eval, out[i], win_t, win_y, win_coef, cancel))
        return 0

    return run_rows


#: Every kind and regime set flagged: a batch of any records.
ALL_FLAGS = (3,) + (1,) * 9


#: The compiled runs of the scenes outside the lanes, per flags met so far (:func:`_rows_for`).
ROWS_ENTRIES = {}


def rows_entry(flags):
    """The compiled run of scenes outside the lanes for ``flags`` (made at its first use)."""
    entry = ROWS_ENTRIES.get(flags)
    if entry is None:
        entry = ROWS_ENTRIES[flags] = _rows_for(flags)
    return entry


def eligible_rows(p):
    """:func:`lane_eligible` of every record of ``p``, as a boolean array (numpy)."""
    c, g, w, m = p["control"], p["progress"], p["switch"], p["model"]
    return ((c["kind"] == KIND_TAYLOR) & (c["karg"] == SIMD_ORDER) & (c["controller"] == CONTROLLER_ADAPTIVE)
            & (m["drive_amp"] == 0.0) & (m["beta"] > 0.0) & (w["regimes"] != 0) & (g["call_windows"] == 0)
            & (c["max_dtheta"] == math.inf) & (g["n_windows"] == 0) & (w["regime"] == REGIME_NONE)
            & (g["status"] == STATUS_OK))


def batch_flags(p):
    """The kinds (taylor, exact, salas-torque, split) and regime sets (RS index) the
    records ``p`` start in or may reach (:data:`mbm.core.chains.REACHES`), as ten flags:
    0/1, but the Taylor kind's 1 (degrees other than SIMD_ORDER), 2 (SIMD_ORDER alone:
    the default degree's entries) or 3 (both), as :func:`mbm.core.chains._dispatch_flagged`
    takes it."""
    c, w, m = p["control"], p["switch"], p["model"]
    kinds = [0, 0, 0, 0]
    sets = [0] * 6
    rows = zip(c["kind"].tolist(), c["controller"].tolist(), w["regimes"].tolist(),
               np.sign(m["beta"]).tolist(), (m["drive_amp"] != 0.0).tolist(), w["regime"].tolist(),
               (c["karg"] == SIMD_ORDER).tolist())
    for kind, controller, regimes, beta_sign, driven, regime, simd in set(rows):
        if kind == KIND_TAYLOR:
            kinds[kind] |= 2 if simd else 1
        elif 0 <= kind < 4:
            kinds[kind] = 1
        rset = _regime_set(kind, controller, regimes, beta_sign, 1.0 if driven else 0.0, regime)
        for s in (rset,) + REACHES[rset]:
            sets[set_flag(s)] = 1
    return tuple(kinds) + tuple(sets)


def run_batch(p, t_eval, out, order, cancel, flags=None, eligible=None):
    """:func:`mbm.core.loop.run` for every row of ``p``, in the order ``order``, on
    ``numba.get_num_threads()`` threads.

    The scenes that are :func:`lane_eligible` run in groups of LANE_GROUP by the lanes
    (:func:`_run_lanes`, LANES scenes in lockstep, every scene's result that of the loop
    alone), the others in groups by the loop (:func:`_rows_for` of their kinds and
    regime sets, ``flags``, default :func:`batch_flags` of those rows); each thread
    takes the next group.  Both run without the GIL, so a caller may run this in a
    thread and set ``cancel[0]`` to stop every scene at its next window.  ``out`` has
    shape (N, 2, m), or (N, 3, m) for θ wrapped with its winding count.  ``eligible``
    is :func:`eligible_rows` of ``p`` where the caller has it already.
    """
    order = np.asarray(order, dtype=np.int64)
    lanes = (eligible_rows(p) if eligible is None else eligible)[order]
    others = order[~lanes]
    none = no_events()
    tasks = [lambda ids=ids: _run_lanes(p, ids, t_eval, out, cancel, none) for ids in groups(order[lanes])]
    if others.size:
        entry = rows_entry(batch_flags(p[others]) if flags is None else tuple(flags))
        tasks += [lambda ids=ids: entry(p, ids, t_eval, out, cancel) for ids in groups(others)]
    run_tasks(tasks, cancel)


def run_tasks(tasks, cancel):
    """Call every task of ``tasks`` (callables of no argument, each a compiled call
    without the GIL) on ``numba.get_num_threads()`` threads, each thread taking the
    next task; returns their results in the tasks' order.  A task's exception sets
    ``cancel[0]`` (the other tasks stop at their next window) and is raised here."""
    results = [None] * len(tasks)
    n_threads = min(numba.get_num_threads(), len(tasks))
    if n_threads <= 1:
        for q, task in enumerate(tasks):
            results[q] = task()
        return results
    todo = iter(enumerate(tasks))
    lock = threading.Lock()
    failure = []

    def work():
        try:
            while True:
                with lock:
                    item = next(todo, None)
                if item is None:
                    return
                results[item[0]] = item[1]()
        except BaseException as exc:  # pragma: no cover - re-raised below
            failure.append(exc)
            cancel[0] = 1

    threads = [threading.Thread(target=work, name=f"mbm-batch-{i}", daemon=True) for i in range(n_threads)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    if failure:
        raise failure[0]
    return results


def groups(ids):
    """Contiguous groups of LANE_GROUP scenes of ``ids``."""
    return [ids[g:g + LANE_GROUP] for g in range(0, ids.size, LANE_GROUP)]
