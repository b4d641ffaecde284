"""Phase-locked to the drive in the loop: the stroboscopic watch and the stored drive period.

After each window of a driven run the loop takes the stroboscopic samples at
t_s + nT_d (:func:`_strobe_samples_taylor`, S1–S7 of :mod:`mbm.regimes.strobe`); once their
deviations have converged for good, the windows are the stored drive period (q drive
periods, S7) from the anchor sample (S6): its windows taken once
(:func:`_strobe_windows_taylor`) and looked up, a block of outputs in one call
(:func:`_strobe_range_taylor`); :func:`_strobe_eval_taylor`, the re-run to one time, is
their reference.
"""

import collections
import math

import numba
import numpy as np

from ..approximants.taylor import drive_phase_sincos, taylor_workspace
from ..core.controller import _adaptive, _first
from ..core.record import window_control
from ..core.window import (
    KIND_TAYLOR,
    TWO_PI_A,
    TWO_PI_B,
    Drive,
    Model,
    Start,
    anchor_driven,
    evaluate,
    window_log_eps,
    wrap,
)
from ..compile.jit import INLINE, kernel
from .common import REGIME_NONE, REGIME_PHASE_LOCKED, SWITCH_SAFETY
from .cycle import CYCLE_MAX_WINDOWS
from .cycle_windows import _TWO_PI
from .stored_block import STORED_BLOCK, block_scratch, block_window, block_write, rate_rows
from .strobe import (
    LOCK_BLOCK,
    LOCK_SLOTS,
    NO_MULTIPLE,
    STROBE_CODE,
    STROBE_DISTINCT,
    STROBE_MAX_PERIODS,
    STROBE_RING,
    StrobeDevs,
    StrobeFits,
    strobe_period,
    strobe_phase,
    strobe_split,
    strobe_split_from,
    strobe_switch,
    strobe_time,
)
from ..status import STATUS_OK

#: The window whose stroboscopic samples are taken: [``t``, ``t_new``], winding count
#: ``k``, ``off`` = 2πk.
StrobeSpan = collections.namedtuple("StrobeSpan", ("t", "t_new", "k", "off"))

#: The drive's clock (S1, S2; :func:`_strobe_setup`): T_d = ``hi`` + ``lo`` in double-double
#: (:func:`mbm.regimes.strobe.strobe_period`), ``det`` = e^{−βT_d} and the next sample's
#: time ``t_next`` (inf: none).
StrobeClock = collections.namedtuple("StrobeClock", ("hi", "lo", "det", "t_next"))

# The stored period's first capacity in windows (doubled as needed): a drive period of
# the n = 1 step of β = 0.2, A = 2, Ω = 1 took 9, 12 and 15 windows at rtol 1e-3, 1e-6
# and 1e-9 (measured), q periods of S7 up to four times that.
STROBE_STORE_START = 64

# Small per-window pieces are inlined into their callers, where the kind is a constant
# (numba prunes the other kinds' branches before compiling); large ones are compiled
# once per kind and called.


# The drive is Taylor's only: one compiled copy, called (a whole controller re-run; inlined,
# numba would copy its large body at each site).
@kernel
def _strobe_eval_taylor(c, t):
    """A phase-locked window (coefficients: regimes.strobe_coef) at time ``t`` (S6).

    ``t`` is the absolute time (not from the window's start): t − t_a is formed
    exactly.  Returns ``(φ, θ', k)``: θ = 2πk + φ (:func:`theta_of`), k the anchor's
    winding count, the turns of the re-run so far and p per period passed.
    """
    phi_a, v_a, k_a, t_a, q, turns, psi = c[1], c[2], c[3], c[4], c[5], c[6], c[7]
    beta, gamma, omega, amp, freq, rtol, atol = c[8], c[9], c[10], c[11], c[12], c[13], c[14]
    code = int(c[15])
    karg = code % STROBE_CODE
    error_order = code // STROBE_CODE
    log_eps = window_log_eps(rtol)
    p_hi, p_lo = strobe_period(freq, q)
    n, s = strobe_split(t, t_a, p_hi, p_lo)
    tt, kk, a0, a1, h = 0.0, 0.0, phi_a, v_a, -1.0
    ws_coef, ws_scratch = taylor_workspace(karg)
    for _ in range(CYCLE_MAX_WINDOWS):
        if not (-math.pi <= a0 <= math.pi):
            kk, a0 = wrap(kk, a0)
        # The tolerance scale of the anchor's period, the same in every period.
        off = (k_a + kk) * _TWO_PI
        # The drive at t_a + tt: phase Ω·tt + ψ_a (S6).
        coef = anchor_driven(KIND_TAYLOR, karg, Model(beta, gamma, omega), Drive(amp, freq, psi), Start(tt, a0, a1),
                             ws_coef, ws_scratch)
        if coef[0] != 0.0:
            break
        ctl = window_control(1.0, p_hi, math.inf, rtol, atol, error_order, log_eps)
        if h <= 0.0:
            h = _first(KIND_TAYLOR, coef, tt, a0, a1, off, omega, ctl)
        st, t_new, th, v, h_next = _adaptive(KIND_TAYLOR, coef, tt, a0, a1, off, h, ctl)
        if st != STATUS_OK:
            break
        if t_new >= s:
            if t_new != s:
                th, v = evaluate(KIND_TAYLOR, coef, s - tt)
            return th, v, k_a + kk + turns * n
        tt, a0, a1, h = t_new, th, v, h_next
    return math.nan, math.nan, 0.0


@numba.njit(**INLINE)
def _strobe_value(kind, c, t):
    """:func:`_strobe_eval_taylor` of kind ``kind`` through its compiled entry (Taylor only)."""
    if kind == KIND_TAYLOR:
        return _strobe_eval_taylor(c, t)
    return math.nan, math.nan, 0.0


@kernel
def _strobe_windows_taylor(c):
    """The windows of a phase-locked window's stored period (coefficients:
    regimes.strobe_coef), taken once from its anchor as :func:`_strobe_eval_taylor`
    re-takes them (S6): the same anchors, controller and span [0, qT_d], so a value
    looked up in them (:func:`_strobe_lookup_taylor`) is that function's to the bit.

    Returns
    -------
    starts : ndarray, shape (n + 1,)
        Window starts from the anchor's time.
    ends : ndarray, shape (n + 1, 3)
        Row i + 1: the state (φ, θ') at the end of window i, as its step left it;
        column 2 of row i: the re-run's turns at window i's start (its φ wrapped).
    coefs : ndarray, shape (n, width)
        The windows' coefficient vectors.
    n : int
        Windows stored: the re-run's, up to the one that reaches qT_d or the one
        before a failure (then starts[n] < qT_d and later times are NaN).
    """
    phi_a, v_a, q, psi = c[1], c[2], c[5], c[7]
    beta, gamma, omega, amp, freq, rtol, atol = c[8], c[9], c[10], c[11], c[12], c[13], c[14]
    code = int(c[15])
    karg = code % STROBE_CODE
    error_order = code // STROBE_CODE
    log_eps = window_log_eps(rtol)
    p_hi, _ = strobe_period(freq, q)
    cap = STROBE_STORE_START
    starts = np.empty(cap + 1)
    ends = np.empty((cap + 1, 3))
    coefs = np.empty((0, 0))
    tt, kk, a0, a1, h = 0.0, 0.0, phi_a, v_a, -1.0
    starts[0], ends[0, 0], ends[0, 1], ends[0, 2] = 0.0, phi_a, v_a, 0.0
    ws_coef, ws_scratch = taylor_workspace(karg)
    for n in range(CYCLE_MAX_WINDOWS):
        if not (-math.pi <= a0 <= math.pi):
            kk, a0 = wrap(kk, a0)
        off = (c[3] + kk) * _TWO_PI
        coef = anchor_driven(KIND_TAYLOR, karg, Model(beta, gamma, omega), Drive(amp, freq, psi), Start(tt, a0, a1),
                             ws_coef, ws_scratch)
        if coef[0] != 0.0:
            return starts, ends, coefs, n
        ctl = window_control(1.0, p_hi, math.inf, rtol, atol, error_order, log_eps)
        if h <= 0.0:
            h = _first(KIND_TAYLOR, coef, tt, a0, a1, off, omega, ctl)
        st, t_new, th, v, h_next = _adaptive(KIND_TAYLOR, coef, tt, a0, a1, off, h, ctl)
        if st != STATUS_OK:
            return starts, ends, coefs, n
        if n == 0:
            coefs = np.empty((cap, coef.size))
        if n == cap:
            starts, ends, coefs = _grown(starts, ends, coefs, n)
            cap = 2 * cap
        # Element loops: a slice assignment compiles numpy's broadcast-error machinery.
        for w in range(coef.size):
            coefs[n, w] = coef[w]
        ends[n, 2] = kk
        starts[n + 1], ends[n + 1, 0], ends[n + 1, 1], ends[n + 1, 2] = t_new, th, v, kk
        if t_new >= p_hi:
            return starts, ends, coefs, n + 1
        tt, a0, a1, h = t_new, th, v, h_next
    return starts, ends, coefs, CYCLE_MAX_WINDOWS


@kernel
def _grown(starts, ends, coefs, n):
    """The store's arrays at twice their capacity, the first ``n`` windows kept."""
    cap = 2 * n
    starts2 = np.empty(cap + 1)
    ends2 = np.empty((cap + 1, 3))
    coefs2 = np.empty((cap, coefs.shape[1]))
    for i in range(n + 1):
        starts2[i] = starts[i]
        for w in range(3):
            ends2[i, w] = ends[i, w]
    for i in range(n):
        for w in range(coefs.shape[1]):
            coefs2[i, w] = coefs[i, w]
    return starts2, ends2, coefs2


@numba.njit(**INLINE)
def _strobe_at(c, per, p_hi, p_lo, t, i):
    """``(φ, θ', k, i)``: :func:`_strobe_eval_taylor`'s value at ``t`` from the stored
    period ``per`` (:func:`_strobe_windows_taylor`'s starts, ends, coefs, n; ``p_hi``,
    ``p_lo``: qT_d, regimes.strobe_period) and the window it came from (``i`` the
    window to search from, :func:`mbm.regimes.stored_block.block_window`)."""
    starts, ends, coefs, n = per
    m, s = strobe_split(t, c[4], p_hi, p_lo)
    i = block_window(starts, n, s, i)
    if i >= n:
        return math.nan, math.nan, 0.0, 0
    if starts[i + 1] == s:
        th, v = ends[i + 1, 0], ends[i + 1, 1]
    else:
        th, v = evaluate(KIND_TAYLOR, coefs[i], s - starts[i])
    return th, v, c[3] + ends[i, 2] + c[6] * m, i


@kernel
def _strobe_lookup_taylor(c, starts, ends, coefs, n, t):
    """:func:`_strobe_at` of one time (the walk's start unknown: bisection)."""
    p_hi, p_lo = strobe_period(c[12], c[5])
    th, v, k, _ = _strobe_at(c, (starts, ends, coefs, n), p_hi, p_lo, t, 0)
    return th, v, k


@kernel
def _strobe_range_taylor(c, per, outs, lo, hi):
    """:func:`_strobe_at` at the times ``outs[0][lo:hi]`` (``outs``: the loop's Outputs
    record, t_eval, θ, θ', winding and wrapped rows) from the stored period ``per``,
    the same bits, a block at a time (:mod:`mbm.regimes.stored_block`)."""
    t_eval = outs[0]
    starts, ends, _, n = per
    p_hi, p_lo = strobe_period(c[12], c[5])
    blk = block_scratch()
    rates = rate_rows(per)
    sb, wb, kb = blk[0], blk[1], blk[2]
    i = 0
    known = NO_MULTIPLE
    for b0 in range(lo, hi, STORED_BLOCK):
        m = min(STORED_BLOCK, hi - b0)
        for q in range(m):
            periods, s, known = strobe_split_from(t_eval[b0 + q], c[4], (p_hi, p_lo), known)
            i = block_window(starts, n, s, i)
            sb[q], wb[q] = s, i
            kb[q] = c[3] + ends[min(i, n), 2] + c[6] * periods
        block_write(per, rates, blk, m, b0, outs)


@numba.njit(**INLINE)
def _strobe_store(kind, c):
    """:func:`_strobe_windows_taylor` of kind ``kind`` (Taylor only; no window otherwise)."""
    if kind == KIND_TAYLOR:
        return _strobe_windows_taylor(c)
    return np.empty(1), np.empty((1, 3)), np.empty((0, 0)), 0


@numba.njit(**INLINE)
def _strobe_stored(kind, c, starts, ends, coefs, n, t):
    """:func:`_strobe_lookup_taylor` of kind ``kind`` (Taylor only)."""
    if kind == KIND_TAYLOR:
        return _strobe_lookup_taylor(c, starts, ends, coefs, n, t)
    return math.nan, math.nan, 0.0


@kernel
def _strobe_samples_taylor(p, coef, span, clock, n_total):
    """The stroboscopic samples of the window ``span`` (a :data:`StrobeSpan`: [t, t_new],
    formula ``coef``, winding count k, off = 2πk) and the switch rule at each
    (mbm.regimes, S1-S7): the run record ``p[0]`` keeps the samples' state and, on a
    switch, the anchor.  ``clock``: a :data:`StrobeClock`, T_d (regimes.strobe_period)
    and e^{−βT_d} (its t_next unread); ``n_total``: the run's windows before this one.  Returns the next
    sample's time (after t_new)."""
    t, t_new, k, off = span.t, span.t_new, span.k, span.off
    sp_hi, sp_lo, sp_det = clock.hi, clock.lo, clock.det
    r = p[0]
    sb = r.strobe
    beta, gamma, omega = r.model.beta, r.model.gamma, r.model.omega
    amp, freq, phase = r.model.drive_amp, r.model.drive_freq, r.model.drive_phase
    rtol, atol = r.control.rtol, r.control.atol
    while True:
        tn, rn = strobe_time(sb.str_t0, float(sb.str_n), sp_hi, sp_lo)
        if not (tn <= t_new):
            return tn
        a, b = evaluate(KIND_TAYLOR, coef, tn - t)
        # (S1): carried to the exact time t_s + nT_d, to first order.
        su, _ = drive_phase_sincos(freq, phase, tn)
        acc = (gamma + amp * su) - beta * b - omega * omega * math.sin(a)
        ac, bc = a + b * rn, b + acc * rn
        if sb.str_n >= 2:
            # (S1): the deviation over the last drive period, p turns.
            dphi = ac - sb.str_phi
            m = np.floor(dphi / _TWO_PI + 0.5)
            turns = (k - sb.str_k) + m
            dth = (dphi - m * TWO_PI_A) - m * TWO_PI_B
            dv = bc - sb.str_v
            tau = math.nan
            if sb.str_m >= 3 and turns == sb.str_p:
                # (S5): the switch rule; the anchor is this sample at t_n itself.
                scale = SWITCH_SAFETY * min(atol + rtol * abs(b), omega * (atol + rtol * abs(off + a)))
                ok, tau, sb.str_rho, _, _ = strobe_switch(
                    StrobeDevs((sb.str_d3t, sb.str_d3v), (sb.str_d2t, sb.str_d2v), (sb.str_d1t, sb.str_d1v), (dth, dv)),
                    sp_det, omega, scale, StrobeFits(sb.str_tau1, sb.str_tau2, sb.str_rho))
                # (S6): a period the stored re-run can take (it stops at CYCLE_MAX_WINDOWS).
                if ok and n_total + 1 - sb.str_nw <= CYCLE_MAX_WINDOWS // 2:
                    r.switch.regime = REGIME_PHASE_LOCKED
                    r.switch.t_regime = t_new
                    sb.str_ta, sb.str_psi = tn, strobe_phase(freq, phase, tn)
                    sb.str_k, sb.str_phi, sb.str_v = k, a, b
                    sb.str_n += 1
                    return math.inf
            if sb.str_m > 0 and turns == sb.str_p:
                sb.str_d3t, sb.str_d3v = sb.str_d2t, sb.str_d2v
                sb.str_d2t, sb.str_d2v = sb.str_d1t, sb.str_d1v
                sb.str_m = min(sb.str_m + 1, 3)
            else:
                sb.str_p, sb.str_m, sb.str_rho = turns, 1, math.nan
            sb.str_d1t, sb.str_d1v = dth, dv
            sb.str_tau2, sb.str_tau1 = sb.str_tau1, tau
        # (S7): the maps P^q, q = 2 .. STROBE_MAX_PERIODS (q = 1 first, above).
        scale = SWITCH_SAFETY * min(atol + rtol * abs(b), omega * (atol + rtol * abs(off + a)))
        qs, ps = _strobe_subharmonic(p, k, ac, bc, scale, sp_hi, n_total)
        if qs > 0:
            r.switch.regime = REGIME_PHASE_LOCKED
            r.switch.t_regime = t_new
            sb.str_ta, sb.str_psi = tn, strobe_phase(freq, phase, tn)
            sb.str_k, sb.str_phi, sb.str_v = k, a, b
            sb.str_p, sb.str_q = ps, float(qs)
            sb.str_n += 1
            return math.inf
        slot = 4 * (sb.str_n % STROBE_RING)
        sb.str_ring[slot] = k
        sb.str_ring[slot + 1] = ac
        sb.str_ring[slot + 2] = bc
        sb.str_ring[slot + 3] = float(n_total + 1)
        sb.str_k, sb.str_phi, sb.str_v = k, ac, bc
        _lock_watch(sb, k, ac)
        sb.str_n += 1
        sb.str_nw = n_total + 1


@kernel
def _lock_watch(sb, k, phi):
    """(S8): add the sample θ = 2πk + φ to the lock watch's block
    means of θ − θ_first (the record's strobe group ``sb``); a full history merges its
    neighbours, so its blocks double."""
    if sb.lk_nb == 0 and sb.lk_cnt == 0 and sb.lk_lvl == 0:
        sb.lk_k0, sb.lk_phi0 = k, phi
    sb.lk_acc += (k - sb.lk_k0) * _TWO_PI + (phi - sb.lk_phi0)
    sb.lk_cnt += 1
    if sb.lk_cnt < (LOCK_BLOCK << sb.lk_lvl):
        return
    sb.lk_means[sb.lk_nb] = sb.lk_acc / sb.lk_cnt
    sb.lk_nb += 1
    sb.lk_acc, sb.lk_cnt = 0.0, 0
    if sb.lk_nb == LOCK_SLOTS:
        for i in range(LOCK_SLOTS // 2):
            sb.lk_means[i] = 0.5 * (sb.lk_means[2 * i] + sb.lk_means[2 * i + 1])
        sb.lk_nb = LOCK_SLOTS // 2
        sb.lk_lvl += 1


# _strobe_dev and _strobe_subharmonic are called, not inlined: they are kind-free, run once
# per drive period of a driven run, and inlined at their call sites they add about a
# quarter to run_taylor's compile from an empty cache.
@kernel
def _strobe_dev(r, n, i, d, k, phi, v):
    """``(turns, Δθ, Δθ')`` of z_i − z_{i−d} (S1's arithmetic; S7): samples before the
    current one, index ``n`` (state ``k``, ``phi``, ``v``), from the record's ring."""
    ring = r.strobe.str_ring
    if i == n:
        k1, f1, v1 = k, phi, v
    else:
        s1 = 4 * (i % STROBE_RING)
        k1, f1, v1 = ring[s1], ring[s1 + 1], ring[s1 + 2]
    s0 = 4 * ((i - d) % STROBE_RING)
    dphi = f1 - ring[s0 + 1]
    m = np.floor(dphi / _TWO_PI + 0.5)
    turns = (k1 - ring[s0]) + m
    return turns, (dphi - m * TWO_PI_A) - m * TWO_PI_B, v1 - ring[s0 + 2]


@kernel
def _strobe_subharmonic(p, k, phi, v, scale, sp_hi, n_total):
    """The switch rule of the maps P^q, q = 2 .. STROBE_MAX_PERIODS, at the current
    sample (index ``str_n``, state ``k``, ``phi``, ``v`` carried to the exact time;
    mbm.regimes S7), smallest q first: ``(q, p)`` of the orbit to switch to, or (0, 0).
    ``scale``: S5's at this sample; ``sp_hi``: T_d; ``n_total``: the run's windows
    before this window.  Updates the fits' state of every q tested."""
    r = p[0]
    sb = r.strobe
    beta, omega = r.model.beta, r.model.omega
    n = sb.str_n
    for q in range(2, STROBE_MAX_PERIODS + 1):
        if n < 4 * q + 1:
            break
        # The last four deviations of P^q, z_i − z_{i−q}, i = n − 3q, .., n.
        p3, d3t, d3v = _strobe_dev(r, n, n - 3 * q, q, k, phi, v)
        p2, d2t, d2v = _strobe_dev(r, n, n - 2 * q, q, k, phi, v)
        p1, d1t, d1v = _strobe_dev(r, n, n - q, q, k, phi, v)
        p0, ct, cv = _strobe_dev(r, n, n, q, k, phi, v)
        tau, bound, ok = math.nan, math.inf, False
        if p3 == p0 and p2 == p0 and p1 == p0:
            # (S7): S3-S5 on P^q, det DP^q = e^{−βqT_d} exactly.
            det = math.exp(-beta * (q * sp_hi))
            ok, tau, sb.str_qrho[q], _, bound = strobe_switch(
                StrobeDevs((d3t, d3v), (d2t, d2v), (d1t, d1v), (ct, cv)), det, omega, scale,
                StrobeFits(sb.str_qtau1[q], sb.str_qtau2[q], sb.str_qrho[q]))
            # (S6): q periods the stored re-run can take.
            nw = sb.str_ring[4 * ((n - q) % STROBE_RING) + 3]
            ok = ok and n_total + 1 - nw <= CYCLE_MAX_WINDOWS // 2
            base = q * STROBE_MAX_PERIODS
            for d in range(1, q):
                # (S7): every other class within the scale of its limit, and the classes
                # d periods apart with distinct limits, for every d | q, d < q.
                b_d = sb.str_qb[base + (n - d) % q]
                ok = ok and b_d <= scale
                if ok and q % d == 0:
                    _, sdt, sdv = _strobe_dev(r, n, n, d, k, phi, v)
                    sep = math.sqrt((omega * sdt) ** 2 + sdv * sdv)
                    ok = sep - bound - b_d > STROBE_DISTINCT * scale
        else:
            sb.str_qrho[q] = math.nan
            # Not (yet) the linear map's deviations: this class's last bound is void.
            sb.str_qb[q * STROBE_MAX_PERIODS + n % q] = math.inf
        sb.str_qtau2[q] = sb.str_qtau1[q]
        sb.str_qtau1[q] = tau
        if bound < math.inf:
            # (S7): a tail bound covers every later sample of its class, so a class's
            # last finite one stands until its next.
            sb.str_qb[q * STROBE_MAX_PERIODS + n % q] = bound
        if ok:
            return q, p0
    return 0, 0.0


@kernel
def _strobe_setup(r, t, freq, beta, n_total):
    """The stroboscopic watch's constants of a driven run (S1-S7), a :data:`StrobeClock`
    (T_d hi, T_d lo, e^{−βT_d}, the next sample's time); a fresh run sets the samples'
    origin."""
    sb = r.strobe
    sp_hi, sp_lo = strobe_period(freq, 1.0)
    sp_det = math.exp(-beta * sp_hi)  # (S2): det DP, exactly e^{−βT_d}
    if n_total == 0:
        sb.str_t0, sb.str_n, sb.str_m = t, 1, 0
        sb.str_tau1, sb.str_tau2, sb.str_rho = math.nan, math.nan, math.nan
        # (S7): the maps P^q, q > 1.
        sb.str_q = 1.0
        for q in range(STROBE_MAX_PERIODS + 1):
            sb.str_qtau1[q], sb.str_qtau2[q], sb.str_qrho[q] = math.nan, math.nan, math.nan
        for q in range((STROBE_MAX_PERIODS + 1) * STROBE_MAX_PERIODS):
            sb.str_qb[q] = math.inf
    sp_next = math.inf
    if r.switch.regime == REGIME_NONE:
        sp_next = strobe_time(sb.str_t0, float(sb.str_n), sp_hi, sp_lo)[0]
    return StrobeClock(sp_hi, sp_lo, sp_det, sp_next)


@numba.njit(**INLINE)
def _watch_strobe(kind, p, coef, span, clock, n_total):
    """:func:`_strobe_samples_taylor` through its compiled entry (Taylor only: the only kind
    that integrates a drive; no sample otherwise)."""
    if kind == KIND_TAYLOR:
        return _strobe_samples_taylor(p, coef, span, clock, n_total)
    return math.inf
