"""The compiled event watch: crossings located on the stored windows' own formulas.

:func:`locate` walks the windows a run stored (``win_t``, ``win_y``, ``win_coef`` of
:func:`mbm.core.loop.run`) and reports every event of the table ``ev`` (one row per
event, :data:`EV_WIDTH` columns, built by :mod:`mbm.events.compiled`) in time order:

* an ordinary Taylor window is a polynomial in the time from its anchor: θ(s) and
  θ'(s) are Σ a_k s^k and its derivative (:mod:`mbm.approximants.taylor`), so a
  crossing of a level is a root of a known polynomial, isolated on the window by the
  Bernstein form and refined to round-off (:mod:`mbm.special.polyroots`); a cheap
  bound (|p(s) − a₀| ≤ Σ_{k≥1} |a_k| |h|^k) skips the levels a window cannot reach;
* a cycle window (the running cycle or a libration, R3) is the stored period shifted:
  the period's events are located once on its own windows and shifted by T_c per turn
  (the winding count by the turn's sign), so counting over 10⁶ time units costs what a
  few periods do, and storing them writes whole turns in one sweep (:func:`_fill_turns`);
* the events a run's cycle windows will store are bounded before they are located
  (:func:`cycle_events_bound`), so the caller reserves the buffers once, and one
  event's rows are split into its result's arrays in one pass (:func:`event_columns`);
* a section event Ωt + φ ≡ phase (mod 2π) is at known times; its state is the
  window's value there.

The state of an event is the dense output's value at its time (the window's formula
at ``t − start``, as :func:`mbm.core.stored.evaluate_windows` gives it); on a cycle
window, the period's value at the event's phase, shifted.
"""

import collections
import math

import numba
import numpy as np

from ..approximants.taylor import HEADER
from ..regimes.cycle import CYC_PERIOD, CYC_SIGN, CYC_T_OFF, CYC_WIND, CYCLE_TAG
from ..regimes.cycle_windows import _period_store
from ..regimes.common import REGIME_NONE, REGIMES_ALL
from ..regimes.locked import LCK_V0, LCK_X0, LOCKED_TAG, _potential, locked_amplitude
from ..compile.jit import INLINE, kernel
from ..special.polyroots import crossings
from .window import KIND_TAYLOR, evaluate, theta_of

__all__ = ["locate", "cycle_events_bound", "event_columns", "taylor_events", "Tally", "Watch", "window_may_cross", "workspace", "trap_allowed", "trapped_unreachable", "EV_ANGLE", "EV_VELOCITY", "EV_SECTION", "EV_WIDTH", "WATCH_OK", "WATCH_CROWDED",
           "WATCH_LOCKED"]

# The event table's rows: (type, value, modulo, direction, terminal count).
EV_ANGLE = 0  # θ ≡ value (mod modulo)
EV_VELOCITY = 1  # θ' = value
EV_SECTION = 2  # Ωt + φ ≡ value (mod 2π)
EV_WIDTH = 5
_TWO_PI = 2.0 * math.pi
# Crossings one window may hold per event and level before the window is refused
# (a window of the controller is far shorter than a turn or a swing: a handful).
WINDOW_CROSSINGS = 64
# The refinement's tolerance in units of the spacing of the doubles at the event's time.
TIME_ULPS = 2.0
_EPS = 2.0 ** -52
# The locked window's margin on its level test, as a multiple of the tolerance scale
# atol + rtol |θ|: the closed form is within SWITCH_SAFETY (0.1) of it from the exact
# motion (L5), so 2 leaves a factor 20.
LOCKED_MARGIN = 2.0
# A trapped scene's margin, in tolerances of its state (trapped_unreachable): the state
# carries the run's global error, which grows past the per-window tolerance over many
# windows; a damped swing lowers the energy far more, so the trap waits a swing at most.
TRAP_MARGIN = 1e3

# locate's verdict on the windows it walked.
WATCH_OK = 1
WATCH_CROWDED = 0  # a window held more crossings than WINDOW_CROSSINGS (or its period failed)
WATCH_LOCKED = -1  # a locked window may reach a level: run the scene without the locked regime


#: How the windows are swept: the drive's frequency and phase (section events) and the
#: direction of the integration.
Watch = collections.namedtuple("Watch", ("drive_freq", "drive_phase", "direction"))

#: Each event's counts over the run: ``hits`` its occurrences, ``stored`` those appended,
#: ``cap`` at most how many to append (-1: all).
Tally = collections.namedtuple("Tally", ("hits", "stored", "cap"))


@kernel
def _push(evf, evi, count, t, theta, v, m, e):
    # Appends an event (doubling the buffers when full); returns them and the count.
    if count == evi.size:
        evf2 = np.empty((2 * evi.size, 4))
        evi2 = np.empty(2 * evi.size, np.int64)
        for q in range(count):
            for w in range(4):
                evf2[q, w] = evf[q, w]
            evi2[q] = evi[q]
        evf, evi = evf2, evi2
    evf[count, 0], evf[count, 1], evf[count, 2], evf[count, 3] = t, theta, v, m
    evi[count] = e
    return evf, evi, count + 1


@kernel
def _level(value, modulo, m, k):
    # value + modulo·m − 2πk in φ's frame; with modulo = 2π as value + 2π(m − k), exact
    # in m − k however far the run has wound.
    if modulo == _TWO_PI:
        return value + _TWO_PI * (m - k)
    return (value + modulo * m) - _TWO_PI * k


@kernel
def _window_roots(coef, span, ev, watch, ws):
    """The events of the table ``ev`` in one Taylor window (anchor ``coef``; ``span`` =
    (t_w, h, k): length h from t_w, winding k, θ = 2πk + the polynomial): their times
    from the anchor (``ws.out_s``), level counts (``ws.out_m``: θ = value + modulo·m for
    an angle event, the drive turn for a section) and event indices (``ws.out_e``),
    unsorted; returns how many (-1: too many).  ``watch``: a :data:`Watch`, ``ws`` an
    :data:`EventWorkspace`."""
    t_w, h, k = span
    drive_freq, drive_phase, direction = watch
    alpha, beta_v, work, xs, ds, out_s, out_m, out_e = ws
    nd = int(coef[1])
    a = coef[HEADER:]
    hp = 1.0
    r_theta = 0.0
    for q in range(nd + 1):
        alpha[q] = a[q] * hp
        if q > 0:
            r_theta += abs(alpha[q])
        hp *= h
    r_v = 0.0
    velocity = False
    for e in range(ev.shape[0]):
        velocity = velocity or int(ev[e, 0]) == EV_VELOCITY
    if velocity:
        # θ' in the window's unit time, only where a velocity event asks for it (the
        # per-window cost of the lanes' watch).
        inv_h = 1.0 / h if h != 0.0 else 0.0
        for q in range(nd):
            beta_v[q] = (q + 1) * alpha[q + 1] * inv_h
            if q > 0:
                r_v += abs(beta_v[q])
    tscale = max(abs(t_w), abs(t_w + h))
    xtol = TIME_ULPS * _EPS * tscale / abs(h) if h != 0.0 else 0.0
    count = 0
    for e in range(ev.shape[0]):
        typ, value, modulo, want = int(ev[e, 0]), ev[e, 1], ev[e, 2], ev[e, 3]
        if typ == EV_SECTION:
            # Ωt + φ = value + 2πm at t = (value + 2πm − φ)/Ω, in (t_w, t_w + h].
            u0 = (drive_freq * t_w + drive_phase - value) / _TWO_PI
            u1 = (drive_freq * (t_w + h) + drive_phase - value) / _TWO_PI
            dsec = 1.0 if u1 >= u0 else -1.0
            if want != 0.0 and want * dsec < 0.0:
                continue
            m0, m1 = math.floor(min(u0, u1)), math.floor(max(u0, u1)) + 1
            for m in range(int(m0), int(m1) + 1):
                s = (value + _TWO_PI * m - drive_phase) / drive_freq - t_w
                if direction * s > 0.0 and direction * (s - h) <= 0.0:
                    if count == out_s.size:
                        return -1
                    out_s[count], out_m[count], out_e[count] = s, float(m), e
                    count += 1
            continue
        if typ == EV_ANGLE:
            poly, deg, radius = alpha, nd, r_theta
            ml = math.ceil((alpha[0] - radius - _level(value, modulo, 0.0, k)) / modulo) - 1.0
            mh = math.floor((alpha[0] + radius - _level(value, modulo, 0.0, k)) / modulo) + 1.0
        else:
            poly, deg, radius = beta_v, nd - 1, r_v
            ml = mh = 0.0
        m = ml
        while m <= mh:
            c = _level(value, modulo, m, k) if typ == EV_ANGLE else value
            m += 1.0
            if abs(poly[0] - c) > radius * (1.0 + 1e-12) + 1e-300:
                continue  # the window cannot reach this level
            for q in range(deg + 1):
                work[q] = poly[q]
            work[0] = poly[0] - c
            nr = crossings(work, deg, xtol, xs, ds)
            if nr < 0:
                return -1
            for q in range(nr):
                # Direction along the integration: x runs with it.
                if want != 0.0 and want * ds[q] < 0.0:
                    continue
                if count == out_s.size:
                    return -1
                out_s[count], out_m[count], out_e[count] = xs[q] * h, m - 1.0, e
                count += 1
    return count


@kernel
def _sort_window(out_s, out_m, out_e, count, direction):
    # Insertion sort by time along the integration (a window holds a handful).
    for i in range(1, count):
        s, m, e = out_s[i], out_m[i], out_e[i]
        j = i - 1
        while j >= 0 and direction * (out_s[j] - s) > 0.0:
            out_s[j + 1], out_m[j + 1], out_e[j + 1] = out_s[j], out_m[j], out_e[j]
            j -= 1
        out_s[j + 1], out_m[j + 1], out_e[j + 1] = s, m, e


@kernel
def _period_events(period, ev, kn, ws):
    """The events of a stored period (``period`` = (p_starts, p_coefs, p_n): its windows,
    θ continuous from the anchor) in a turn of winding ``kn``, by phase s in (0, T]: rows
    ``(s, φ, θ', m, e)`` sorted by s (θ = 2πkn + φ), and False where a window held too
    many crossings."""
    p_starts, p_coefs, p_n = period
    out_s, out_m, out_e = ws.out_s, ws.out_m, ws.out_e
    buf = np.empty((16, 5))
    count = 0
    for q in range(p_n):
        s0 = p_starts[q]
        nr = _window_roots(p_coefs[q], (s0, p_starts[q + 1] - s0, kn), ev, Watch(0.0, 0.0, 1.0), ws)
        if nr < 0:
            return buf[:0], False
        _sort_window(out_s, out_m, out_e, nr, 1.0)
        for i in range(nr):
            a, b = evaluate(KIND_TAYLOR, p_coefs[q], out_s[i])
            if count == buf.shape[0]:
                buf2 = np.empty((2 * count, 5))
                for r in range(count):  # element loops: no broadcast machinery compiled
                    for w in range(5):
                        buf2[r, w] = buf[r, w]
                buf = buf2
            buf[count, 0], buf[count, 1], buf[count, 2] = s0 + out_s[i], a, b
            buf[count, 3], buf[count, 4] = out_m[i], float(out_e[i])
            count += 1
    return buf[:count], True


@kernel
def _levels_unreachable(lo, hi, v_max, ev, factor, rtol, atol):
    # Whether no level of ``ev`` lies in θ ∈ [lo, hi] or at |θ'| ≤ v_max (a velocity
    # level within ``factor`` tolerances of v_max counts as reached); a section event
    # counts as reachable.
    for e in range(ev.shape[0]):
        kind, value, modulo = int(ev[e, 0]), ev[e, 1], ev[e, 2]
        if kind == EV_ANGLE:
            m = math.ceil((lo - value) / modulo)
            if value + modulo * m <= hi or value + modulo * (m - 1.0) >= lo:
                return False
        elif kind == EV_VELOCITY:
            if abs(value) <= v_max + factor * (atol + rtol * abs(value)):
                return False
        else:
            return False
    return True


@kernel
def locked_unreachable(theta, c, ev, lock):
    """Whether no event of ``ev`` can occur in a locked window (coefficients ``c``, its
    start's angle ``theta``) however long: the exact motion keeps |θ − θ*| ≤ A and
    |θ'| ≤ sqrt(2H₀) (its energy H decreases, L3) and the closed form is within the
    tolerance of it (L5), so a level outside those bounds by LOCKED_MARGIN tolerances
    is never crossed.  ``lock`` is (γ, ω, rtol, atol); a section event (a driven scene,
    never locked) counts as reachable."""
    gamma, omega, rtol, atol = lock[0], lock[1], lock[2], lock[3]
    w2 = omega * omega
    d = math.asin(gamma / w2)
    x0, v0 = c[LCK_X0], c[LCK_V0]
    ts, amp = locked_amplitude(gamma, omega, theta, v0, d)
    if not (amp < math.inf):
        return False
    margin = LOCKED_MARGIN * (atol + rtol * (abs(ts) + amp))
    v_max = math.sqrt(2.0 * max(0.0, 0.5 * v0 * v0 + _potential(w2, gamma, d, x0))) * (1.0 + 1e-8)
    return _levels_unreachable(ts - amp - margin, ts + amp + margin, v_max, ev, LOCKED_MARGIN, rtol, atol)


@kernel
def trap_allowed(r, direction, j, n_out):
    """Whether run record ``r`` may end where it is trapped (:func:`trapped_unreachable`):
    forwards, undriven, β > 0, |γ| < ω², with the locked regime allowed for its events
    (``regimes`` REGIMES_ALL: :func:`mbm.events.compiled.lock_allowed`), no regime taken yet
    and its ``n_out`` outputs all written (``j`` of them are: the record's, or a lane's
    own count while the lane holds the run)."""
    m = r.model
    return (direction > 0.0 and m.drive_amp == 0.0 and m.beta > 0.0 and abs(m.gamma) < m.omega * m.omega
            and r.switch.regimes == REGIMES_ALL and r.switch.regime == REGIME_NONE and j >= n_out)


@kernel
def trapped_unreachable(theta, v, ev, gamma, omega, rtol, atol, d):
    """Whether the exact motion from (θ, θ') = (``theta``, ``v``) of an undriven scene
    with β > 0 (forwards; ``d`` = arcsin(γ/ω²)) stays in its well and never reaches a
    level of ``ev``: its energy H, raised by TRAP_MARGIN tolerances for the state's own
    error, is below both barriers, so |θ − θ*| ≤ A and |θ'| ≤ sqrt(2H) for ever (L3), and
    every level lies outside those bounds by TRAP_MARGIN tolerances.  Such a scene
    tends to θ* (H decreases while θ' ≠ 0, and θ* is the well's only equilibrium): its
    regime is locked, whatever the run's length."""
    w2 = omega * omega
    tol = atol + rtol * (abs(theta) + abs(v))
    v_up = math.sqrt(v * v + 2.0 * TRAP_MARGIN * tol * (w2 + abs(gamma) + abs(v)))
    ts, amp = locked_amplitude(gamma, omega, theta, v_up, d)
    if not (amp < math.inf):
        return False
    margin = TRAP_MARGIN * (atol + rtol * (abs(ts) + amp))
    v_max = math.sqrt(2.0 * max(0.0, 0.5 * v_up * v_up + _potential(w2, gamma, d, theta - ts))) * (1.0 + 1e-8)
    return _levels_unreachable(ts - amp - margin, ts + amp + margin, v_max, ev, TRAP_MARGIN, rtol, atol)


@numba.njit(cache=True)  # also called from Python
def locate(windows, ev, tally, watch, found, lock):
    """The events of ``n`` stored windows in time order, appended to ``evf`` (rows t, θ,
    θ', m) and ``evi`` (the event's row of ``ev``) from ``count`` on (grown as needed).

    ``windows`` = (starts, start_theta, coefs, n): the windows (``win_t``, ``win_y[:, 0]``,
    ``win_coef`` of :func:`mbm.core.loop.run`); ``tally`` = (hits, stored, cap) and
    ``watch`` = (drive_freq, drive_phase, direction), the fields of :data:`Tally` and
    :data:`Watch` (plain tuples: numba's dispatcher types those fast); ``found`` = (evf,
    evi, count).  ``hits`` counts each event's occurrences over the run (a terminal event's row in
    ``ev[:, 4]`` is the count that stops it, 0 for none); ``stored`` how many of them
    were appended, at most ``cap`` of each (-1: all) besides the terminal one that stops
    the run.  A locked window (the last) holds no event where
    :func:`locked_unreachable` (``lock``: γ, ω, rtol, atol) proves it.  Returns
    ``(evf, evi, count, stop, verdict)``: ``stop`` the window (index) of a terminal
    event, the last event its row (-1: none); ``verdict`` WATCH_OK, WATCH_CROWDED where
    a window held more crossings than :data:`WINDOW_CROSSINGS` or its stored period
    could not be re-taken, WATCH_LOCKED where a locked window may reach a level (the
    caller runs the scene again without the locked regime).
    """
    starts, start_theta, coefs, n = windows
    tally = Tally(tally[0], tally[1], tally[2])
    watch = Watch(watch[0], watch[1], watch[2])
    evf, evi, count = found
    ws = workspace(coefs.shape[1])
    for i in range(n):
        t_w = starts[i]
        h = starts[i + 1] - t_w
        c = coefs[i]
        if c[0] == LOCKED_TAG:
            if not locked_unreachable(start_theta[i], c, ev, lock):
                return evf, evi, count, -1, WATCH_LOCKED
            continue
        if c[0] == CYCLE_TAG:
            evf, evi, count, stop, ok = _cycle_window(c, (t_w, h), ev, tally, ws, (evf, evi, count))
            if not ok or stop:
                return evf, evi, count, i if stop else -1, WATCH_OK if ok else WATCH_CROWDED
            continue
        # The winding count, recovered as the stored evaluator does (its start's θ).
        k = float(round((start_theta[i] - c[HEADER]) / _TWO_PI))
        evf, evi, count, verdict, fired = taylor_events(c, (t_w, h, k), ev, tally, watch, ws, (evf, evi, count))
        if verdict != WATCH_OK or fired:
            return evf, evi, count, i if fired else -1, verdict
    return evf, evi, count, -1, WATCH_OK


@numba.njit(**INLINE)
def window_may_cross(c, h, k, ev):
    """Whether a Taylor window (coefficients ``c``, length ``h``, winding ``k``) may hold
    an event of ``ev``: False only where every level lies outside the window's range
    bound |p(s) − a₀| ≤ Σ_{q≥1} |a_q| |h|^q (and its derivative's), the test
    :func:`_window_roots` makes per level.  Inlined: the lanes ask it per window
    before the call that locates (a call with arrays costs their reference counts)."""
    nd = int(c[1])
    ah = abs(h)
    hp = ah
    r_theta = 0.0
    r_v = 0.0
    for q in range(1, nd + 1):
        r_theta += abs(c[HEADER + q]) * hp
        if q > 1:
            r_v += q * abs(c[HEADER + q]) * (hp / ah)
        hp *= ah
    a0, v0 = c[HEADER], c[HEADER + 1]
    # Slack over _window_roots' own test: relative 1e-9 and a few ulps of the anchor
    # (its radius and θ'(0) are rounded otherwise).
    r_theta = r_theta * (1.0 + 1e-9) + 4.0 * _EPS * abs(a0) + 1e-300
    r_v = r_v * (1.0 + 1e-9) + 4.0 * _EPS * abs(v0) + 1e-300
    for e in range(ev.shape[0]):
        typ, value, modulo = int(ev[e, 0]), ev[e, 1], ev[e, 2]
        if typ == EV_ANGLE:
            m = math.ceil((a0 - r_theta - _level(value, modulo, 0.0, k)) / modulo) - 1.0
            for _ in range(3):
                if abs(a0 - _level(value, modulo, m, k)) <= r_theta:
                    return True
                m += 1.0
            if _level(value, modulo, m, k) <= a0 + r_theta:
                return True  # (a wide window: several levels)
        elif typ == EV_VELOCITY:
            if abs(v0 - value) <= r_v:
                return True
        else:
            return True
    return False


@kernel
def taylor_events(c, span, ev, tally, watch, ws, found):
    """The events of one Taylor window (coefficients ``c``; ``span`` = (t_w, h, k): from
    t_w, length h, winding k) in time order, counted in the :data:`Tally` and appended to
    ``found`` = (evf, evi, count) as :func:`locate` does (``watch`` a :data:`Watch`,
    ``ws`` its :func:`workspace`).  Returns ``(evf, evi, count, verdict, fired)``:
    ``fired`` whether a terminal event stopped the run (its row the last)."""
    t_w, k = span[0], span[2]
    hits, stored, cap = tally
    evf, evi, count = found
    out_s, out_m, out_e = ws.out_s, ws.out_m, ws.out_e
    nr = _window_roots(c, span, ev, watch, ws)
    if nr < 0:
        return evf, evi, count, WATCH_CROWDED, False
    _sort_window(out_s, out_m, out_e, nr, watch.direction)
    for q in range(nr):
        e = out_e[q]
        hits[e] += 1
        fire = ev[e, 4] > 0.0 and hits[e] >= ev[e, 4]
        if fire or cap[e] < 0 or stored[e] < cap[e]:
            t = t_w + out_s[q]
            a, b = evaluate(KIND_TAYLOR, c, t - t_w)  # the dense output at t
            evf, evi, count = _push(evf, evi, count, t, theta_of(k, a), b, out_m[q], e)
            stored[e] += 1
        if fire:
            return evf, evi, count, WATCH_OK, True
    return evf, evi, count, WATCH_OK, False


#: The scratch arrays of :func:`taylor_events` (:func:`workspace`).
EventWorkspace = collections.namedtuple("EventWorkspace", ("alpha", "beta_v", "work", "xs", "ds", "out_s", "out_m",
                                                           "out_e"))


@kernel
def workspace(nd_max):
    """The scratch arrays of :func:`taylor_events` for windows of up to ``nd_max``
    coefficients, an :data:`EventWorkspace`."""
    return EventWorkspace(np.empty(nd_max), np.empty(nd_max), np.empty(nd_max), np.empty(WINDOW_CROSSINGS),
                          np.empty(WINDOW_CROSSINGS), np.empty(WINDOW_CROSSINGS), np.empty(WINDOW_CROSSINGS),
                          np.empty(WINDOW_CROSSINGS, np.int64))


@kernel
def _turns_to_skip(rows, ev, tally, n_turns):
    """Whole turns of a cycle window that can be counted without being walked: 0 while
    an event still stores its occurrences, else at most ``n_turns``, fewer where a
    terminal event would fire in them.  Adds their occurrences to the :data:`Tally`'s hits."""
    hits, stored, cap = tally
    n_ev = ev.shape[0]
    for e in range(n_ev):
        if cap[e] < 0 or stored[e] < cap[e]:
            return 0
    if n_turns == 0:
        return 0
    per = np.zeros(n_ev, np.int64)
    for q in range(rows.shape[0]):
        per[int(rows[q, 4])] += 1
    skip = n_turns
    for e in range(n_ev):
        if ev[e, 4] > 0.0 and per[e] > 0:
            # hits + per·skip stays below the terminal count: the turn it fires in is walked.
            skip = min(skip, max(0, (int(ev[e, 4]) - 1 - hits[e]) // per[e]))
    for e in range(n_ev):
        hits[e] += per[e] * skip
    return skip


#: A cycle window's turns as :func:`_fill_turns` reads them: the stored period, the
#: window's start time ``t_w``, its phase ``tau0`` there (t_off) and its length ``h``, and
#: the winding of turn 0 and its sign per turn.
Turns = collections.namedtuple("Turns", ("period", "t_w", "tau0", "h", "wind", "sign"))


@kernel
def _block_turns(rows, ev, tally, n_turns):
    """Whole turns (at most ``n_turns``) whose events :func:`_fill_turns` can write in one
    sweep: in them every event stores all its occurrences or none (the :data:`Tally`'s
    cap) and no terminal event fires.  Returns (turns, occurrences of each event per turn)."""
    hits, stored, cap = tally
    n_ev = ev.shape[0]
    per = np.zeros(n_ev, np.int64)
    for q in range(rows.shape[0]):
        per[int(rows[q, 4])] += 1
    b = n_turns
    for e in range(n_ev):
        if per[e] == 0:
            continue
        if ev[e, 4] > 0.0:
            # hits + per·b stays below the terminal count: the turn it fires in is walked.
            b = min(b, max(0, (int(ev[e, 4]) - 1 - hits[e]) // per[e]))
        if cap[e] >= 0 and stored[e] < cap[e]:
            b = min(b, (cap[e] - stored[e]) // per[e])
    return b, per


@kernel
def _fill_turns(rows, ev, tally, per, turns, first, b, out):
    """Write the events of turns ``first`` … ``first + b − 1`` of a cycle window at once
    (:func:`_block_turns` chose b; ``per``: each event's rows per turn): the stored
    period's rows shifted by T_c and the winding per turn, the values
    :func:`_cycle_window`'s walk writes, bit for bit.  The :data:`Tally` advanced;
    ``out`` = (evf, evi, count), grown once.  Stops early at a turn whose first or last
    row falls outside the window (its ends, in rounding).  Returns (evf, evi, count,
    turns written)."""
    hits, stored, cap = tally
    evf, evi, count = out
    n_ev, nr = ev.shape[0], rows.shape[0]
    if nr == 0:
        return evf, evi, count, b
    store = np.empty(n_ev, np.bool_)
    per_turn = 0
    for e in range(n_ev):
        store[e] = cap[e] < 0 or stored[e] < cap[e]
        if store[e]:
            per_turn += per[e]
    if count + b * per_turn > evi.size:  # one allocation for the block
        size = max(count + b * per_turn, 2 * evi.size)
        evf2, evi2 = np.empty((size, 4)), np.empty(size, np.int64)
        evf2[:count] = evf[:count]
        evi2[:count] = evi[:count]
        evf, evi = evf2, evi2
    done = 0
    while done < b:
        turn = float(first + done)
        kn = turns.wind + turns.sign * turn
        base = turn * turns.period - turns.tau0
        if base + rows[0, 0] <= 0.0 or base + rows[nr - 1, 0] > turns.h:
            break
        for q in range(nr):
            e = int(rows[q, 4])
            if store[e]:
                m = rows[q, 3] + kn if int(ev[e, 0]) == EV_ANGLE else rows[q, 3]
                evf[count, 0], evf[count, 1] = turns.t_w + (base + rows[q, 0]), theta_of(kn, rows[q, 1])
                evf[count, 2], evf[count, 3] = rows[q, 2], m
                evi[count] = e
                count += 1
        done += 1
    for e in range(n_ev):
        hits[e] += per[e] * done
        if store[e]:
            stored[e] += per[e] * done
    return evf, evi, count, done


@kernel
def _cycle_window(c, span, ev, tally, ws, found):
    """The events of a cycle window (``span`` = (t_w, h): from t_w, length h): its stored
    period's, shifted by T_c and its winding per turn, counted in the :data:`Tally` and
    appended to ``found`` = (evf, evi, count); once no event stores more (cap), whole
    turns are counted, not walked.  Returns ``(evf, evi, count, stop, ok)``."""
    t_w, h = span
    hits, stored, cap = tally
    evf, evi, count = found
    period, t_off, sign, wind = c[CYC_PERIOD], c[CYC_T_OFF], c[CYC_SIGN], c[CYC_WIND]
    p_starts, p_ends, p_coefs, p_n = _period_store(KIND_TAYLOR, c)
    if p_n < 1:
        return evf, evi, count, False, False
    # Velocity events and angles modulo 2π fall at the same phases in every turn.
    shiftable = True
    for e in range(ev.shape[0]):
        if int(ev[e, 0]) == EV_ANGLE and ev[e, 2] != _TWO_PI:
            shiftable = False
    period_windows = (p_starts, p_coefs, p_n)
    rows, ok = _period_events(period_windows, ev, 0.0, ws)
    if not ok:
        return evf, evi, count, False, False
    tau0, tau1 = t_off, t_off + h
    turn = float(math.floor(tau0 / period))
    n1 = float(math.floor(tau1 / period))
    while turn <= n1:
        if shiftable and turn * period > tau0:
            # Turns turn .. n1 - 2 lie inside the window whole (the last two are walked:
            # their ends meet the window's end in rounding).
            turn += float(_turns_to_skip(rows, ev, tally, max(0, int(n1 - 1.0 - turn))))
            b, per = _block_turns(rows, ev, tally, max(0, int(n1 - 1.0 - turn)))
            if b > 0:
                evf, evi, count, done = _fill_turns(rows, ev, tally, per, Turns(period, t_w, tau0, h, wind, sign),
                                                    int(turn), b, (evf, evi, count))
                turn += float(done)
        kn = wind + sign * turn
        if not shiftable:
            rows, ok = _period_events(period_windows, ev, kn, ws)
            if not ok:
                return evf, evi, count, False, False
        base = turn * period - tau0
        for q in range(rows.shape[0]):
            dt = base + rows[q, 0]
            if dt <= 0.0 or dt > h:
                continue
            e = int(rows[q, 4])
            m = rows[q, 3]
            if int(ev[e, 0]) == EV_ANGLE and shiftable:
                m += kn  # θ = value + 2π(m' + k_n)
            hits[e] += 1
            fire = ev[e, 4] > 0.0 and hits[e] >= ev[e, 4]
            if fire or cap[e] < 0 or stored[e] < cap[e]:
                evf, evi, count = _push(evf, evi, count, t_w + dt, theta_of(kn, rows[q, 1]), rows[q, 2], m, e)
                stored[e] += 1
            if fire:
                return evf, evi, count, True, True
        turn += 1.0
    return evf, evi, count, False, True


@numba.njit(cache=True)  # called from Python
def cycle_events_bound(windows, ev, tally):
    """At most how many events :func:`locate` appends on the cycle windows among
    ``windows`` (as :func:`locate` takes them): per window, each event's rows in one turn
    of its stored period times the turns the window meets, no more than the :data:`Tally`
    lets it store (its cap, and its terminal count, past which the run stops).  The
    caller reserves the buffers from it (numpy's allocation, not grown turn by turn); a
    window whose turns differ (an angle modulo other than 2π) may exceed it, and the
    buffers then grow as :func:`locate` grows them."""
    starts, _, coefs, n = windows
    hits, stored, cap = tally
    n_ev = ev.shape[0]
    total = 0
    ws = workspace(coefs.shape[1])
    for i in range(n):
        c = coefs[i]
        if c[0] != CYCLE_TAG:
            continue
        p_starts, _, p_coefs, p_n = _period_store(KIND_TAYLOR, c)
        if p_n < 1:
            continue
        rows, ok = _period_events((p_starts, p_coefs, p_n), ev, 0.0, ws)
        if not ok:
            continue
        per = np.zeros(n_ev, np.int64)
        for q in range(rows.shape[0]):
            per[int(rows[q, 4])] += 1
        period, tau0 = c[CYC_PERIOD], c[CYC_T_OFF]
        turns = int(math.floor((tau0 + starts[i + 1] - starts[i]) / period) - math.floor(tau0 / period)) + 1
        for e in range(n_ev):
            if ev[e, 4] > 0.0 and per[e] > 0:
                turns = min(turns, max(0, (int(ev[e, 4]) - hits[e]) // per[e] + 1))
        for e in range(n_ev):
            k = turns * per[e]
            if cap[e] >= 0:
                k = min(k, max(0, cap[e] - stored[e]) + 1)
            total += k
    return total


@numba.njit(cache=True)  # called from Python
def event_columns(found, e, cols, from_theta):
    """The rows of event ``e`` among ``found`` = (evf, evi, count), in time order, split
    into ``cols`` = (t (k,), y (k, 2), winding (k,) int64) until those are full: t, (θ,
    θ'), and the row's level count m, or θ's winding count ⌊(θ + π)/2π⌋ where
    ``from_theta`` (a velocity event, an event function).  Returns the rows written."""
    evf, evi, count = found
    t, y, wind = cols
    k = 0
    for q in range(count):
        if k == t.size:
            break
        if evi[q] != e:
            continue
        t[k], y[k, 0], y[k, 1] = evf[q, 0], evf[q, 1], evf[q, 2]
        if from_theta:
            wind[k] = np.int64(math.floor((evf[q, 1] + math.pi) / _TWO_PI))
        else:
            wind[k] = np.int64(evf[q, 3])
        k += 1
    return k
