"""THE compiled window loop of the moving boundary method, and its entries.

Every path runs a scene through one body (:func:`_runner`'s entry): :class:`mbm.MBM`
(a step of one or more windows, their formulas stored for the dense output),
:func:`mbm.solve` (outputs at ``t_eval`` or the window ends) and :func:`mbm.solve_batch`
(groups of scenes, :mod:`mbm.core.lanes`).  So the paths take the same windows and give
the same answers bit for bit.

Per window the body chooses the window's source (a regime's stored formula, the locked
closed form, or the approximant anchored at the state reached, under its controller:
:mod:`mbm.core.window`, :mod:`mbm.core.controller`), emits the outputs in the window,
runs the regime watches, and stores the window.  The regimes (:mod:`mbm.regimes`) are
grouped in regime sets (``RS_*``, :func:`regime_set`); the loop has one compiled entry
per regime set (and Taylor degree: the default's or any), the set a constant of the
entry's closure, so numba prunes the other sets' branches and a scene compiles only the
regimes it can reach.  Every (kind, set) of :data:`RUN_TABLE` has its entry
(:data:`RUNNERS`): the kind is read from the record, kind "taylor"'s kernels called
directly and the other kinds' pieces through the table of :mod:`mbm.core.kind_ops`, so
the kinds share the default degree's entries and a further kind compiles only its own
formulas.  A run whose regime set changes
(a switch to a stored period) pauses, and its caller resumes it through the new set's
entry (:func:`run`; in compiled code :func:`mbm.core.chains._run_sets`).

Long horizons (:mod:`mbm.regimes`), each compiled only into the entries of its set:
with ``regimes`` set, before each window the state is tested for the locked regime
(RS_DAMPED); once the bound on the neglected nonlinearity over the rest of the
horizon is within the tolerance (L5), the window (to ``t_bound``, or ``max_step``
long) is the linearized closed form (or the second-order one, L6-L7, where the
window store has room for it), stored with layout ``regimes.LOCKED_TAG``, and
``regime``, ``t_regime`` record the switch.  After each window the return map of
θ ≡ θ_s (mod 2π) is watched (R1, R2); once it has converged for the rest of the
horizon, the windows are the stored period shifted (RS_CYCLE: ``regimes.CYCLE_TAG``,
R3), the period's windows re-taken once from the cycle's anchor at the first such
window of the call and every output looked up in them.  A conservative run (β = 0,
RS_CONSERVATIVE) trapped in a well is tested before its first window (C1-C4): with
its period known to double-double precision, the whole run is one such window.
AC drive (RS_DRIVEN): each window is anchored at its start time by
:func:`anchor_driven`; the stroboscopic samples at t_s + nT_d are watched (S1–S7),
and once their deviations have converged for good the windows are the stored drive
period from the anchor sample (RS_STROBE: ``regimes.STROBE_TAG``, S6), ``regime``
phase-locked.  A run of fixed windows (τ given) of a kind with an error estimate takes
RS_FIXED's entry, which compiles neither a regime nor the adaptive controller.
"""

import collections
import math

import numba
import numpy as np

from ..validate import t_eval_problem
from ..approximants.taylor import taylor_workspace
from ..approximants.taylor_simd import SIMD_ORDER
from ..compile.jit import INLINE, kernel
from .controller import (
    CONTROLLER_ADAPTIVE,
    _adaptive,
    _first,
    _window_end,
    fixed_window,
)
from .emit import Outputs, Span, emit_exact, emit_locked, emit_taylor
from .record import RUN, WORD, start_record, window_control, words_of
from .window import (
    KIND_EXACT,
    KIND_SALAS_TORQUE,
    KIND_SPLIT,
    KIND_TAYLOR,
    Drive,
    Model,
    Start,
    _put,
    _reduce_phi,
    anchor,
    anchor_driven,
    evaluate,
    theta_of,
    window_log_eps,
)
from ..regimes.common import (
    Tolerance,
    REGIME_LIBRATION,
    REGIME_LOCKED,
    REGIME_NONE,
    REGIME_PHASE_LOCKED,
    REGIME_RUNNING,
    REGIMES_PERIODIC,
)
from ..regimes.cycle import CYCLE_WIDTH, CycleAnchor, CycleSpan, CycleWatch, Retake, cycle_coef, section_offset
from ..regimes.cycle_windows import (
    CYCLE_SWITCHED,
    _TWO_PI,
    refine_period,
    _period_store,
    _period_range_taylor,
    _period_value,
    _watch_cycle,
)
from ..regimes.libration import LibrationStart, _libration_test
from ..regimes.locked import (
    LOCKED2_WIDTH,
    LOCKED_WIDTH,
    LockSetup,
    _lock_setup,
    locked_choice,
    locked_coef,
    locked_eval,
    locked_far,
    locked_quick_reject,
)
from ..regimes.strobe import STROBE_WIDTH, StrobeAnchor, StrobeRetake, strobe_coef
from ..regimes.strobe_windows import (
    StrobeClock,
    StrobeSpan,
    _strobe_range_taylor,
    _strobe_setup,
    _strobe_store,
    _strobe_stored,
    _watch_strobe,
)
from ..status import (
    STATUS_ANCHOR,
    STATUS_INTERRUPTED,
    STATUS_MAX_WINDOWS,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_PAUSED,
)



@numba.njit(**INLINE)
def _stored_value(kind, rset, coef, per, t, tj):
    """(φ, θ', winding count) of a stored period's window (RS_CYCLE, RS_STROBE) that
    started at ``t``, at time ``tj`` (``per``: the period's windows, starts, ends,
    coefficients and count)."""
    if rset == RS_CYCLE:
        return _period_value(kind, coef, per[0], per[1], per[2], per[3], tj - t)
    return _strobe_stored(kind, coef, per[0], per[1], per[2], per[3], tj)


@kernel
def _store_window(win_t, win_y, win_coef, n, coef, t_new, theta, v):
    """Window ``n`` of the call into the window store: its coefficients (cut or
    zero-padded to the store's width) and the state at its end."""
    width = win_coef.shape[1]
    if width > 0:
        m = min(coef.size, width)
        # Element loops: a slice assignment compiles numpy's broadcast-error
        # machinery (seconds of a cold start) for shapes that agree here.
        for q in range(m):
            win_coef[n, q] = coef[q]
        for q in range(m, width):
            win_coef[n, q] = 0.0
    win_t[n + 1] = t_new
    win_y[n + 1, 0] = theta
    win_y[n + 1, 1] = v


@kernel
def _form_damped(r):
    """The damped set's constants of the model's β, γ, ω into the record's ``damped``
    group (:data:`mbm.core.record.DAMPED`): the locked test's where |γ| < ω² (L1, L4,
    L7's quick term) and the section's (R1)."""
    m, q = r.model, r.damped
    beta, gamma, omega = m.beta, m.gamma, m.omega
    q.dmp_d, q.dmp_wl2, q.dmp_g0, q.dmp_g1, q.dmp_sd, q.dmp_q2, _ = _lock_setup(
        beta, gamma, omega, abs(gamma) < omega * omega, True)
    q.dmp_sec_off = section_offset(gamma, omega)
    # θ'' = sec_acc − βθ' on a section level (sin θ there is sin θ_s): _crossing.
    q.dmp_sec_acc = gamma - omega * omega * math.sin(q.dmp_sec_off)
    q.dmp_beta, q.dmp_gamma, q.dmp_omega = beta, gamma, omega


@kernel
def damped_setup(r, may, width):
    """The damped regimes' constants of an RS_DAMPED run (record ``r``): whether the
    locked regime may apply (L5, where |γ| < ω², its formula fits the window store and
    ``regimes`` is not REGIMES_PERIODIC), the locked test's constants
    (:func:`mbm.regimes.locked._lock_setup`, the last whether the second-order form
    L6-L7 fits), whether the return map is watched (R1-R3), the
    section level's offset θ_s and θ'' = sec_acc − βθ' on it.  The per-model constants
    come from the record's ``damped`` group, formed first where they are not the
    model's (:func:`_form_damped`).  Shared by the loop and the lanes
    (:mod:`mbm.core.lanes`)."""
    m, q = r.model, r.damped
    beta, gamma, omega = m.beta, m.gamma, m.omega
    if not (q.dmp_beta == beta and q.dmp_gamma == gamma and q.dmp_omega == omega):
        _form_damped(r)
    can_lock = (may and r.switch.regimes != REGIMES_PERIODIC and abs(gamma) < omega * omega
                and (width == 0 or width >= LOCKED_WIDTH))
    lk = LockSetup(0.0, 1.0, 0.0, 0.0, 0.0, 0.0, False)
    if can_lock:
        # L6-L7 only where the store has room for the second-order form.
        q2 = q.dmp_q2 if width == 0 or width >= LOCKED2_WIDTH else 0.0
        lk = LockSetup(q.dmp_d, q.dmp_wl2, q.dmp_g0, q.dmp_g1, q.dmp_sd, q2, q2 > 0.0)
    can_cycle = may and (width == 0 or width >= CYCLE_WIDTH)
    if can_cycle:
        return can_lock, lk, can_cycle, q.dmp_sec_off, q.dmp_sec_acc
    return can_lock, lk, can_cycle, 0.0, 0.0  # (no section watched: unused)


_W_DMP = WORD["dmp_beta"]
_DMP_WORDS = RUN.fields["damped"][0].itemsize // 8


@kernel
def _keep_damped(buf):
    """The damped constants a fresh call formed kept in its template (``buf``'s row 0,
    whose model is the run's), so the template's next runs find them formed."""
    tpl, words = buf[0], buf[buf.shape[0] - 1]
    if not (tpl[_W_DMP] == words[_W_DMP] and tpl[_W_DMP + 1] == words[_W_DMP + 1]
            and tpl[_W_DMP + 2] == words[_W_DMP + 2]):
        for i in range(_W_DMP, _W_DMP + _DMP_WORDS):
            tpl[i] = words[i]


# Inlined: as a call it costs ~5 us of a ~13 us short locked run (P1, 8 windows).
@numba.njit(**INLINE)
def locked_test(r, y0, y1, off, lk, far):
    """``(order, t_s)`` of the locked closed form from φ = ``y0``, θ' = ``y1`` (L5-L7; order
    0: not locked), ``lk`` the constants of :func:`damped_setup`; once locked the quick
    rejection is skipped.  ``far``: screen by :func:`mbm.regimes.locked.locked_far`
    first (the loop, whose 1/ω_l² is the run's constant; the lanes' is each lane's, a
    quotient per window again, and their pass measured 2-4 % slower with it).  Shared
    by the loop and the lanes."""
    m, c = r.model, r.control
    tols = Tolerance(c.rtol, c.atol)
    locked = r.switch.regime == REGIME_LOCKED
    # The far pre-test first: most windows stop there, with no quotient on their path.
    if far and not locked and locked_far(off + y0, y1, lk, m.omega, tols):
        return 0, 0.0
    if locked or not locked_quick_reject(off + y0, y1, lk, m.omega, tols):
        return locked_choice(m.beta, m.gamma, m.omega, y0, y1, lk, tols, off)
    return 0, 0.0


@numba.njit(**INLINE)
def _regime_setup(kind, rset, r, may, width, t, n_total):
    """Each regime's switch rule where it may apply in set ``rset``: windows from
    rtol/atol, forwards (``may``), room for its formula in the window store (its set's own
    conditions in :func:`regime_set`); every test depends on the record only, so a
    resumed run repeats it.  Returns the damped set's constants (:func:`damped_setup`),
    whether a conservative run takes the libration test (C1-C4: trapped in a well,
    tested once before a fresh run's first window) and the stroboscopic watch's
    constants of a driven one (S1-S7: Taylor, β > 0; not with max_dtheta, the short
    windows of solve_ivp's event search, each of which would re-take a period)."""
    can_lock = can_cycle = False
    lk = LockSetup(0.0, 1.0, 0.0, 0.0, 0.0, 0.0, False)
    sec_off = sec_acc = 0.0
    if rset == RS_DAMPED:
        can_lock, lk, can_cycle, sec_off, sec_acc = damped_setup(r, may, width)
    can_librate = False
    if rset == RS_CONSERVATIVE:
        can_librate = (may and (kind == KIND_TAYLOR or kind == KIND_SPLIT)
                       and abs(r.model.gamma) < r.model.omega * r.model.omega and n_total == 0
                       and r.switch.regime == REGIME_NONE and (width == 0 or width >= CYCLE_WIDTH))
    sp = StrobeClock(0.0, 0.0, 0.0, math.inf)  # T_d hi, lo, e^{−βT_d}, the next sample's time
    if rset == RS_DRIVEN:
        m = r.model
        if (may and r.switch.regimes != REGIMES_PERIODIC and m.beta > 0.0 and m.drive_freq > 0.0
                and kind == KIND_TAYLOR
                and r.control.max_dtheta == math.inf and (width == 0 or width >= STROBE_WIDTH)):
            sp = _strobe_setup(r, t, m.drive_freq, m.beta, n_total)
    c = r.control
    cw = CycleWatch(sec_off, sec_acc, r.model.beta, r.model.gamma, r.model.omega, r.state.t_bound, c.rtol, c.atol)
    return RegimeSetup(can_lock, lk, can_cycle, cw, can_librate, sp)


@numba.njit(**INLINE)
def _stop_before(kind, rset, r, counts, store, cap, seen, cancel):
    """Whether the run stops before its next window: ``(status, regime seen)``, status
    STATUS_OK to go on (``counts``: the windows this call and the run have taken).  A
    regime switch to another set pauses (the run goes on through the new set's entry)."""
    n, n_total = counts
    if n_total >= r.progress.max_windows:
        return STATUS_MAX_WINDOWS, seen
    budget = r.progress.call_windows
    if (budget > 0 and n >= budget) or (store and n >= cap):
        return STATUS_PAUSED, seen
    if r.switch.regime != seen:
        seen = r.switch.regime
        c = r.control
        if regime_set(kind, c.controller, r.switch.regimes, r.model.beta, r.model.drive_amp, seen) != rset:
            return STATUS_PAUSED, seen
    if cancel[0] != 0:
        return STATUS_INTERRUPTED, seen
    return STATUS_OK, seen


#: A window as a source gives it: its status, the anchored coefficients, the end time and
#: state (θ, θ', winding), the length tried and the next proposal, whether it is the
#: locked closed form, and the stored period's windows (passed through; 0 from
#: :func:`_source`, whose caller keeps its own).
Window = collections.namedtuple(
    "Window", ("status", "coef", "t_new", "theta", "v", "k_new", "h_abs", "h_next", "is_locked", "per"))

#: What :func:`_regime_setup` derives once per call: the damped set's constants
#: (:func:`damped_setup`; the return map's as its :data:`mbm.regimes.cycle.CycleWatch`
#: ``cw``), whether the libration test applies, the strobe's constants (a
#: :data:`mbm.regimes.strobe_windows.StrobeClock`).
RegimeSetup = collections.namedtuple(
    "RegimeSetup", ("can_lock", "lk", "can_cycle", "cw", "can_librate", "sp"))

#: A window's start: the time, φ and θ' (θ = 2πk + φ), the winding count k and its
#: offset 2πk (θ's scale for the tolerances), the length to try (≤ 0: search it).
At = collections.namedtuple("At", ("t", "phi", "v", "k", "off", "h_abs"))



# The window sources, one per kind of window: run_entry branches on its constant set
# itself (numba prunes a branch on a closure constant before it inlines the calls in
# it; inside an inlined callee, only after that callee's own calls are inlined), so
# an entry inlines the one source it takes.

@numba.njit(**INLINE)
def _source_cycle(kind, simd, r, t, direction, max_step, h_abs, per):
    """The running cycle's window (RS_CYCLE: the stored period shifted, R3), a
    :data:`Window` (``per``: the period's windows, built at the call's first cycle
    window; ``simd``: the default degree's entry, :func:`_runner`)."""
    m, c, y = r.model, r.control, r.cycle
    t_new = _window_end(t, direction, r.state.t_bound, max_step)
    if y.cyc_k == CYCLE_SWITCHED:
        refine_period(kind, r, simd)  # (R4), once per run
    coef = cycle_coef(CycleAnchor(y.cyc_theta, y.cyc_v, y.cyc_T, y.cyc_Tlo, y.cyc_sign, y.cyc_wind), t - y.cyc_t,
                      Retake(m.beta, m.gamma, m.omega, c.rtol, c.atol, c.karg, c.error_order))
    if per[3] == -2:
        per = _period_store(kind, coef, simd)
    th, v, k_new = _period_value(kind, coef, per[0], per[1], per[2], per[3], t_new - t)
    st = STATUS_OK if math.isfinite(th) and math.isfinite(v) else STATUS_NONFINITE
    return Window(st, coef, t_new, th, v, k_new, h_abs, h_abs, False, per)


@numba.njit(**INLINE)
def _source_strobe(kind, r, t, direction, max_step, h_abs, per):
    """The phase-locked window (RS_STROBE: the stored drive period, S6, S7), a
    :data:`Window`."""
    m, c, s = r.model, r.control, r.strobe
    t_new = _window_end(t, direction, r.state.t_bound, max_step)
    coef = strobe_coef(StrobeAnchor(s.str_phi, s.str_v, s.str_k, s.str_ta, s.str_q, s.str_p, s.str_psi),
                       StrobeRetake(m.beta, m.gamma, m.omega, m.drive_amp, m.drive_freq, c.rtol, c.atol, c.karg,
                                    c.error_order))
    if per[3] == -2:
        per = _strobe_store(kind, coef)
    th, v, k_new = _strobe_stored(kind, coef, per[0], per[1], per[2], per[3], t_new)
    st = STATUS_OK if math.isfinite(th) and math.isfinite(v) else STATUS_NONFINITE
    return Window(st, coef, t_new, th, v, k_new, h_abs, h_abs, False, per)


@numba.njit(**INLINE)
def _anchored(kind, rset, simd, r, t, y0, y1, ws):
    """The approximant's coefficients anchored at (t, φ = ``y0``, θ' = ``y1``): with the
    drive's term in RS_DRIVEN; ``simd``: the default degree's entry (:func:`_runner`)."""
    m = r.model
    if rset == RS_DRIVEN:
        return anchor_driven(kind, r.control.karg, Model(m.beta, m.gamma, m.omega),
                             Drive(m.drive_amp, m.drive_freq, m.drive_phase), Start(t, y0, y1), ws[0], ws[1], simd)
    return anchor(kind, r.control.karg, Model(m.beta, m.gamma, m.omega), y0, y1, ws[0], ws[1], simd)


@numba.njit(**INLINE)
def _source_fixed(kind, rset, simd, r, at, ctl, scratch):
    """The window of a fixed length ``min(at.h_abs, ctl.max_step)`` (RS_FIXED, the kinds
    without an estimate, a fixed controller's window), a :data:`Window`."""
    t, y0, y1, k, _, h_abs = at
    ws, per = scratch
    coef = _anchored(kind, rset, simd, r, t, y0, y1, ws)
    if coef[0] != 0.0:
        return Window(STATUS_ANCHOR, coef, t, y0, y1, k, h_abs, h_abs, False, per)
    st, t_new, th, v = fixed_window(kind, coef, t, ctl.direction, ctl.t_bound, min(h_abs, ctl.max_step))
    return Window(st, coef, t_new, th, v, k, h_abs, h_abs, False, per)


@numba.njit(**INLINE)
def _source(kind, rset, simd, r, at, reach, lock, ws):
    """The window from ``at`` (an :data:`At`: t, φ, θ', winding k, its offset, the length to
    try) outside the stored periods: the locked closed form (L2, L5), or the approximant
    anchored at the state under the adaptive controller (a fixed window:
    :func:`_source_fixed`).  ``reach`` = (direction, max_step, log_eps), ``lock`` =
    (can_lock, the LockSetup), ``ws`` the approximant's workspace; all but ``ws`` plain
    scalars, so that the inlined source costs what its arguments one by one did.  Returns
    its :data:`Window` with no stored period (the caller keeps its own)."""
    t, y0, y1, k, off, h_abs = at
    direction, max_step, log_eps = reach
    can_lock, lk = lock
    m, c = r.model, r.control
    beta, gamma, omega = m.beta, m.gamma, m.omega
    rtol, atol, error_order = c.rtol, c.atol, c.error_order
    t_bound = r.state.t_bound
    lk_order, lk_ts = 0, 0.0
    if rset == RS_DAMPED and can_lock:
        lk_order, lk_ts = locked_test(r, y0, y1, off, lk, True)
    if rset == RS_DAMPED and lk_order > 0:  # (the other sets' entries compile no locked window)
        coef = locked_coef(beta, lk.wl2, lk_ts, y0, y1, gamma, lk_order)
        t_new = _window_end(t, direction, t_bound, max_step)
        th, v = locked_eval(coef, t_new - t)
        if r.switch.regime != REGIME_LOCKED:
            r.switch.regime = REGIME_LOCKED
            r.switch.t_regime = t
        st = STATUS_OK if math.isfinite(th) and math.isfinite(v) else STATUS_NONFINITE
        return Window(st, coef, t_new, th, v, k, h_abs, h_abs, True, 0)
    coef = _anchored(kind, rset, simd, r, t, y0, y1, ws)
    if coef[0] != 0.0:
        return Window(STATUS_ANCHOR, coef, t, y0, y1, k, h_abs, h_abs, False, 0)
    ctl = window_control(direction, t_bound, max_step, rtol, atol, error_order, log_eps)
    if h_abs <= 0.0:
        h_abs = _first(kind, coef, t, y0, y1, off, omega, ctl)
    st, t_new, th, v, h_next = _adaptive(kind, coef, t, y0, y1, off, h_abs, ctl)
    return Window(st, coef, t_new, th, v, k, h_abs, h_next, False, 0)


@numba.njit(**INLINE)
def _emit_stored(kind, rset, coef, per, ends, j, direction, outs):
    """The outputs in (t, t_new] of a stored period's window (RS_CYCLE, RS_STROBE;
    ``coef``, ``per`` the window's coefficients and the stored period; ``ends`` = (t,
    t_new, θ, θ', winding) its span and end state); returns the next output index."""
    t, t_new, th, v, k_new = ends
    t_eval, out_theta, out_v, out_w, wrapped = outs
    if kind == KIND_TAYLOR:
        # The block in one call, its sorted times walking the stored period's windows
        # (an output at t_new is the lookup that gave the end state: the same bits).
        j2 = j
        while j2 < t_eval.size and (direction * (t_eval[j2] - t_new) <= 0.0):
            j2 += 1
        if j2 > j and rset == RS_STROBE:
            _strobe_range_taylor(coef, per, outs, j, j2)
        elif j2 > j:
            _period_range_taylor(coef, per, outs, j, j2, t)
        return j2
    while j < t_eval.size and (direction * (t_eval[j] - t_new) <= 0.0):
        if t_eval[j] == t_new:
            _put(out_theta, out_w, wrapped, j, k_new, th)
            out_v[j] = v
        else:
            a, b, kc = _stored_value(kind, rset, coef, per, t, t_eval[j])
            _put(out_theta, out_w, wrapped, j, kc, a)
            out_v[j] = b
        j += 1
    return j


@numba.njit(**INLINE)
def _emit_formula(kind, rset, coef, ends, k, j, direction, outs):
    """The outputs in (t, t_new] of the approximant's window or the locked form's
    (RS_DAMPED; ``coef`` its coefficients, ``ends`` = (t, t_new, θ, θ', is_locked), ``k``
    its winding count); returns the next output index.  (Apart from
    :func:`_emit_stored`: an inlined callee's calls are inlined before its pruned
    branches are dropped.)  The window's values travel as floats beside its one array:
    a tuple holding arrays costs their reference counts at every window."""
    t, t_new, th, v, is_locked = ends
    t_eval, out_theta, out_v, out_w, wrapped = outs
    if kind == KIND_TAYLOR and not is_locked:
        return emit_taylor(coef, Span(t, t_new, direction, k), t_eval, j, out_theta, out_v, out_w, wrapped)
    if kind == KIND_EXACT and rset == RS_FIXED:
        return emit_exact(coef, Span(t, t_new, direction, k), j, th, v, outs)
    if rset == RS_DAMPED and is_locked:
        return emit_locked(coef, Span(t, t_new, direction, k), t_eval, j, out_theta, out_v, out_w, wrapped)
    while j < t_eval.size and (direction * (t_eval[j] - t_new) <= 0.0):
        if t_eval[j] == t_new:
            _put(out_theta, out_w, wrapped, j, k, th)
            out_v[j] = v
        else:
            a, b = evaluate(kind, coef, t_eval[j] - t)
            _put(out_theta, out_w, wrapped, j, k, a)
            out_v[j] = b
        j += 1
    return j


@kernel
def _max_step(c, v):
    """The longest window from θ' = ``v``: ``max_step``, and ``max_dtheta``/|θ'| where
    the θ-step is limited (solve_ivp's event search)."""
    if c.max_dtheta < math.inf and v != 0.0:
        return min(c.max_step, c.max_dtheta / abs(v))
    return c.max_step


@kernel
def _finish(r, status, at, n_total, j, outs):
    """The outputs (:data:`Outputs`) of a span of zero length (the initial state), and the
    state reached ``at`` (t, φ, θ', winding count, next window length), the counts and
    the status written back to the record."""
    t, y0, y1, k, h_abs = at
    t_eval, out_theta, out_v, out_w, wrapped = outs
    while j < t_eval.size and n_total == 0 and status != STATUS_PAUSED and t_eval[j] == t:
        _put(out_theta, out_w, wrapped, j, k, y0)
        out_v[j] = y1
        j += 1
    r.state.t, r.state.theta, r.state.v, r.control.h_abs = t, theta_of(k, y0), y1, h_abs
    r.winding.phi, r.winding.wind = y0, k
    r.progress.n_windows = n_total
    r.progress.j = j
    r.progress.status = status


# The entries' contract.  ``run_entry(buf, fresh, start, arrays)`` advances the run in
# ``buf``'s last row (a RUN record's float64 words: mbm.core.record.start_record) window
# by window; ``start`` = (t0, theta0, v0, t1, h), ``arrays`` = (t_eval, out, win_t,
# win_y, win_coef, cancel), plain tuples (a named tuple costs ~9 µs of the dispatcher's
# typing per call from Python).  With ``fresh`` the run is first set up from ``buf``'s
# row 0 (a template record), the span (t0, t1), the state (theta0, v0) and the first
# window's h_abs ``h``, and ``t_eval`` checked (mbm.validate.t_eval_problem: where it
# fails nothing is run and −(its code) returned); otherwise ``start`` is unused and the
# run resumes as it stands.  One compiled entry serves every caller (mbm.MBM,
# mbm.Integrator, the compiled whole runs), so none links the loop into a wrapper of its
# own.
#
# It stops at t_bound (status 0), at a failure (a STATUS_* code), at max_windows, paused
# (STATUS_PAUSED) after call_windows windows, when the window store is full or at a
# switch to another regime set, or interrupted once cancel[0] is set (by another
# thread).  The state reached, the next window length, the counts and the status are
# written back to the record, so a paused run resumes where it stopped.
#
# ``out`` (2 or 3 rows, m) takes θ, θ' at ``t_eval`` from the record's progress.j on
# (three rows: θ wrapped to (−π, π], its winding count in row 2); ``win_t`` (cap + 1,),
# ``win_y`` (cap + 1, 2), ``win_coef`` (cap, width) store the call's windows (start
# times, states, coefficients cut or zero-padded to ``width``; empty: none).  It returns
# the windows this call took.


def _runner(rset, simd=False):
    """The loop's compiled entry for regime set ``rset`` (:func:`regime_set`), any kind.

    The set is a constant of the closure: numba prunes the other sets' branches before
    it compiles, and caches each closure apart.  The kind is read from the record (kind
    "taylor"'s kernels called directly, the others' through :mod:`mbm.core.kind_ops`).
    ``simd``: kind "taylor" at the default degree SIMD_ORDER alone, anchored by the
    vector kernel (no loop form of the recurrence compiled; another degree would end
    STATUS_ANCHOR: :func:`entry_for` chooses), the entry the other kinds share."""

    @numba.njit(cache=True)
    def run_entry(buf, fresh, start, arrays):
        """Advance the run in ``buf``'s last row window by window (the entries' contract above
        :func:`_runner`); returns the windows taken, or −(the t_eval problem's code)."""
        t0, theta0, v0, t1, h = start
        t_eval, out, win_t, win_y, win_coef, cancel = arrays
        if fresh:
            problem = t_eval_problem(t_eval, t0, t1, False)
            if problem != 0:
                return -problem
        p = start_record(buf, fresh, t0, theta0, v0, t1, h)
        r = p[0]
        kind = r.control.kind
        t, y0, y1, t_bound = r.state.t, r.state.theta, r.state.v, r.state.t_bound
        h_abs = r.control.h_abs
        log_eps = window_log_eps(r.control.rtol)
        direction = 1.0 if t_bound >= t else -1.0
        store, cap, width = win_t.size > 0, win_t.size - 1, win_coef.shape[1]
        wrapped = out.shape[0] == 3  # θ wrapped to (−π, π] and its winding count in a third row
        outs = Outputs(t_eval, out[0], out[1], out[2] if wrapped else out[0], wrapped)
        # n typed int64 from the start (a literal 0 compiles _store_window a second time).
        j, n, n_total, status = r.progress.j, np.int64(0), r.progress.n_windows, STATUS_OK
        # θ = 2πk + φ (TWO_PI_A): y0 holds φ, k the winding (0 fresh, else where it stopped).
        k = 0.0
        if n_total > 0:
            k, y0 = r.winding.wind, r.winding.phi
        if store:
            win_t[0], win_y[0, 0], win_y[0, 1] = t, theta_of(k, y0), y1
        may = r.switch.regimes != 0 and r.control.controller == CONTROLLER_ADAPTIVE and direction > 0.0
        rs = _regime_setup(kind, rset, r, may, width, t, n_total)
        can_cycle, cw, can_librate, sp = rs.can_cycle, rs.cw, rs.can_librate, rs.sp
        if rset == RS_DAMPED and fresh:
            _keep_damped(buf)
        ws = taylor_workspace(r.control.karg)  # one coefficient workspace for the call's windows
        per = (np.empty(0), np.empty((0, 2)), np.empty((0, 0)), -2)  # the stored period (R3)
        scratch = (ws, per)  # once per call: per window, a tuple of arrays costs their refcounts
        sp_next = sp.t_next
        seen = -1  # the regime last checked against this entry's set (-1: the first window checks)
        while direction * (t_bound - t) > 0.0:
            status, seen = _stop_before(kind, rset, r, (n, n_total), store, cap, seen, cancel)
            if status != STATUS_OK:
                break
            max_step = _max_step(r.control, y1)
            if kind == KIND_TAYLOR or kind == KIND_SPLIT:  # WRAPPING_KINDS
                k, y0 = _reduce_phi(k, y0)
            off = k * _TWO_PI  # θ's scale for the tolerances (scipy's rtol·|θ| of the whole angle)
            if rset == RS_CONSERVATIVE and can_librate:
                can_librate = False
                _libration_test(r, LibrationStart(t, y0, y1, k, off), r.model.gamma, r.model.omega, t_bound,
                                Tolerance(r.control.rtol, r.control.atol))
                if r.switch.regime != REGIME_NONE:
                    status = STATUS_PAUSED  # the rest of the run is the stored period: RS_CYCLE's entry
                    break
            if rset == RS_CYCLE:  # (each branch on the constants inlines only its own callees)
                st, coef, t_new, th, v, k_new, h_abs, h_next, is_locked, per = _source_cycle(
                    kind, simd, r, t, direction, max_step, h_abs, per)
            elif rset == RS_STROBE:
                st, coef, t_new, th, v, k_new, h_abs, h_next, is_locked, per = _source_strobe(
                    kind, r, t, direction, max_step, h_abs, per)
            elif (rset == RS_FIXED or (rset != RS_DAMPED and rset != RS_CONSERVATIVE  # (adaptive: regime_set)
                                       and (kind == KIND_EXACT or kind == KIND_SALAS_TORQUE
                                            or r.control.controller != CONTROLLER_ADAPTIVE))):
                c = r.control
                ctl = window_control(direction, t_bound, max_step, c.rtol, c.atol, c.error_order, log_eps)
                st, coef, t_new, th, v, k_new, h_abs, h_next, is_locked, per = _source_fixed(
                    kind, rset, simd, r, At(t, y0, y1, k, off, h_abs), ctl, scratch)
            else:
                st, coef, t_new, th, v, k_new, h_abs, h_next, is_locked, _ = _source(
                    kind, rset, simd, r, At(t, y0, y1, k, off, h_abs), (direction, max_step, log_eps),
                    (rs.can_lock, rs.lk), ws)
            if st != STATUS_OK:
                status = st
                break
            if rset == RS_CYCLE or rset == RS_STROBE:
                j = _emit_stored(kind, rset, coef, per, (t, t_new, th, v, k_new), j, direction, outs)
            else:  # (k_new = k outside the stored periods)
                j = _emit_formula(kind, rset, coef, (t, t_new, th, v, is_locked), k, j, direction, outs)
            if rset == RS_DAMPED and not is_locked and can_cycle and r.switch.regime == REGIME_NONE:
                _watch_cycle(kind, r, coef, CycleSpan(t, t_new, y0, th, v, k, off), cw)
            if rset == RS_DRIVEN and sp_next <= t_new and r.switch.regime == REGIME_NONE:
                sp_next = _watch_strobe(kind, p, coef, StrobeSpan(t, t_new, k, off), sp, n_total)
            if store:
                _store_window(win_t, win_y, win_coef, n, coef, t_new, theta_of(k_new, th), v)
            t, y0, y1, h_abs, k = t_new, th, v, h_next, k_new
            n += 1
            n_total += 1
        _finish(r, status, (t, y0, y1, k, h_abs), n_total, j, outs)
        return n

    return run_entry


# Regime sets: which regimes an entry of the loop compiles (numba prunes the other
# sets' branches, so a scene class pays only for the regimes it can reach).
RS_PLAIN = 0  # no regime: regimes off, β < 0, or a kind without an estimate (fixed windows)


RS_DAMPED = 1  # undriven, β > 0: the locked regime (L1-L7) and the return map's watch (R1, R2)


RS_CONSERVATIVE = 2  # undriven, β = 0: the libration test (C1-C4)


RS_DRIVEN = 3  # an AC drive: the driven anchor and the stroboscopic watch (S1-S7)


RS_CYCLE = 4  # in the running cycle or a libration: the stored period's windows (R3)


RS_STROBE = 5  # phase-locked to the drive: the stored drive period's windows (S6, S7)


RS_FIXED = 6  # fixed windows (τ given, or a kind without an estimate), undriven: no regime, no adaptive controller


@kernel
def regime_set(kind, controller, regimes, beta, amp, regime):
    """The regime set (``RS_*``) of a run record's fields: the entry that runs it.

    A run's set changes only at a regime switch (to RS_CYCLE or RS_STROBE), where the
    loop pauses so that the caller resumes it through the new set's entry.  The kinds
    without an error estimate run fixed windows and take no regime (RS_FIXED's entry,
    which compiles no adaptive controller).
    """
    if kind == KIND_EXACT or kind == KIND_SALAS_TORQUE:
        return RS_DRIVEN if amp != 0.0 else RS_FIXED
    if regime == REGIME_RUNNING or regime == REGIME_LIBRATION:
        return RS_CYCLE
    if regime == REGIME_PHASE_LOCKED and kind == KIND_TAYLOR:
        return RS_STROBE
    if amp != 0.0:
        return RS_DRIVEN
    if controller != CONTROLLER_ADAPTIVE:
        return RS_FIXED  # its entry compiles no adaptive controller
    if regimes == 0 or beta < 0.0:
        return RS_PLAIN
    return RS_DAMPED if beta > 0.0 else RS_CONSERVATIVE


#: Every (kind, regime set) the loop has an entry for: those regime_set can return.
RUN_TABLE = tuple(
    [(KIND_TAYLOR, s) for s in (RS_PLAIN, RS_DAMPED, RS_CONSERVATIVE, RS_DRIVEN, RS_CYCLE, RS_STROBE, RS_FIXED)]
    + [(KIND_SPLIT, s) for s in (RS_PLAIN, RS_DAMPED, RS_CONSERVATIVE, RS_DRIVEN, RS_CYCLE, RS_FIXED)]
    + [(kd, s) for kd in (KIND_EXACT, KIND_SALAS_TORQUE) for s in (RS_FIXED, RS_DRIVEN)]
)


#: The entries of kind "taylor" at its default degree SIMD_ORDER, per regime set, which
#: the other kinds share (:func:`_runner`).
SIMD_RUNNERS = {rset: _runner(rset, True) for kind, rset in RUN_TABLE if kind == KIND_TAYLOR}

#: The loop's entry for each (kind id, regime set) of RUN_TABLE: kind "taylor" of any
#: degree its own, the other kinds SIMD_RUNNERS'.
RUNNERS = {(kind, rset): _runner(rset) if kind == KIND_TAYLOR else SIMD_RUNNERS[rset] for kind, rset in RUN_TABLE}


def entry_for(kind, rset, karg):
    """The compiled entry that runs a record of kind id ``kind``, regime set ``rset`` and
    kind argument ``karg`` (:data:`SIMD_RUNNERS` at the default Taylor degree, else
    :data:`RUNNERS`), or None for a pair without an entry."""
    if kind == KIND_TAYLOR and karg == SIMD_ORDER:
        return SIMD_RUNNERS.get(rset)
    return RUNNERS.get((kind, rset))



_regime_set = regime_set.py_func


def set_of(r):
    """The regime set of run record ``r`` (a record, or a row of a RUN array), in Python."""
    c, w = r["control"], r["switch"]
    return _regime_set(int(c["kind"]), int(c["controller"]), int(w["regimes"]), float(r["model"]["beta"]),
                       float(r["model"]["drive_amp"]), int(w["regime"]))


def runner_for(r):
    """The compiled entry (:func:`entry_for`) that runs record ``r`` now."""
    return entry_for(int(r["control"]["kind"]), set_of(r), int(r["control"]["karg"]))


#: The start (t0, θ0, θ'0, t1, h) of an entry's call that resumes a run (unused there).
_NO_START = (0.0, 0.0, 0.0, 0.0, 0.0)


def run(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """Advance the run ``p[0]``: the entry of its kind and regime set (:data:`RUNNERS`,
    ``run_entry`` of :func:`_runner`), resumed through the new set's entry after a regime
    switch, so that only the sets a run reaches are compiled.  Returns the windows taken.
    """
    n = 0
    progress = p["progress"]
    buf = words_of(p)
    while True:
        rset = set_of(p[0])
        entry = entry_for(int(p[0]["control"]["kind"]), rset, int(p[0]["control"]["karg"]))
        if entry is None:
            progress["status"][0] = STATUS_ANCHOR
            return n
        n += entry(buf, False, _NO_START, (t_eval, out, win_t[n:], win_y[n:], win_coef[n:], cancel))
        if progress["status"][0] != STATUS_PAUSED or set_of(p[0]) == rset:
            return n
