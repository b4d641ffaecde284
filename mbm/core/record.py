"""The run record: the scalars of one run of the compiled window loop, one dtype.

A record of dtype :data:`RUN` (a numpy structured array of length 1, or one row per
scene in a batch) holds a run's model, state, controller options, budget, progress,
winding and each regime's state.  The loop (:mod:`mbm.core.loop`) reads it, advances,
and writes the state reached back, so a caller may resume a run where it stopped.
:func:`new_run` is the one initialiser of a fresh record.
"""

import collections
import math
from typing import NamedTuple

import numba
import numpy as np

from ..regimes.common import REGIME_NONE
from ..regimes.strobe import LOCK_SLOTS, STROBE_MAX_PERIODS, STROBE_RING
from ..compile.jit import INLINE, kernel

def _group(*fields):
    return np.dtype(list(fields), align=True)


_F, _I = np.float64, np.int64
_STROBE_Q = STROBE_MAX_PERIODS + 1  # per q = 1..STROBE_MAX_PERIODS (index q; 0 unused)

#: The model θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ) (A = 0: no drive; a driven run
#: anchors by anchor_driven at each window's start and of the regimes takes only the
#: phase-locked one).
MODEL = _group(("beta", _F), ("gamma", _F), ("omega", _F),
               ("drive_amp", _F), ("drive_freq", _F), ("drive_phase", _F))

#: The state: the run's position on entry, the state reached on return (θ and θ'
#: adjacent: the state is one slice of the record's words).
STATE = _group(("t", _F), ("theta", _F), ("v", _F), ("t_bound", _F))

#: The winding (TWO_PI_A): θ = 2π·wind + phi, the state a resumed run continues from
#: (state.theta is its value, rounded); a fresh run (n_windows = 0) starts from theta.
WINDING = _group(("phi", _F), ("wind", _F))

#: The approximant (COMPILED_KINDS id and its integer argument) and its controller:
#: CONTROLLER_FIXED or CONTROLLER_ADAPTIVE; h_abs the next window length (τ when fixed;
#: the adaptive proposal, ≤ 0 to search it from the estimate); error_order sets the
#: adaptive exponent −1/(error_order + 1); a window starting at speed θ' is at most
#: max_dtheta/|θ'| long (inf: no limit; set when solve_ivp looks for events).
CONTROL = _group(("kind", _I), ("karg", _I), ("controller", _I), ("h_abs", _F), ("max_step", _F),
                 ("max_dtheta", _F), ("rtol", _F), ("atol", _F), ("error_order", _I))

#: Budget and progress: windows the whole run may take (STATUS_MAX_WINDOWS past it),
#: windows one call may take before pausing (≤ 0: no limit), windows taken so far, the
#: next index of t_eval to fill, the status (mbm.status).
PROGRESS = _group(("max_windows", _I), ("call_windows", _I), ("n_windows", _I), ("j", _I),
                  ("status", _I))

#: Long-horizon regimes (mbm.regimes): regimes ≠ 0 lets the run switch to a regime's
#: closed form (adaptive controller, forwards only); regime is the one reached
#: (REGIME_*) and t_regime when (nan before).
SWITCH = _group(("regimes", _I), ("regime", _I), ("t_regime", _F))

#: Running cycle (R1-R3) and libration (C3): the return map so far (crossings of
#: θ = θ_s + 2πm, regimes.section_offset, in one direction: count, sign, last time, θ',
#: return time, change of θ', largest |θ'| since) and, once switched, the stored period
#: (anchor crossing θ, θ', period, time, winding sign; returns since the map converged,
#: 0: not yet; the anchor's winding count; the period's low part in double-double, a
#: libration's, 0 for the running cycle).
CYCLE = _group(("sec_n", _I), ("sec_sign", _F), ("sec_t", _F), ("sec_v", _F), ("sec_T", _F),
               ("sec_dv", _F), ("sec_vmax", _F), ("cyc_theta", _F), ("cyc_v", _F), ("cyc_T", _F),
               ("cyc_t", _F), ("cyc_sign", _F), ("cyc_k", _I), ("cyc_wind", _F), ("cyc_Tlo", _F))

#: Phase-locked to the drive (S1-S7): the stroboscopic samples (the first sample's time
#: origin t_s, the next sample's index n; the last sample as winding count, φ and θ',
#: carried to the exact time; the turns p of the last deviations and how many in a row
#: share it, up to 3; the three deviations before the last, θ and θ' parts), once
#: switched the anchor (its time and the drive's phase there; its state in str_k,
#: str_phi, str_v, its p in str_p); the traces fitted at the last two samples and the
#: last clean fit's spectral radius (nan: failed or none; S4); the run's window count
#: at the last sample (S6); the orbit's period in drive periods q (1 for S1-S6); the
#: last STROBE_RING samples, sample n at words 4(n mod STROBE_RING) on (winding count,
#: φ, θ' carried to the exact time, the window count there); per q (index q) the traces
#: at the last two samples, the last clean fit's spectral radius, and per class n mod q
#: the last finite tail bound B at q·STROBE_MAX_PERIODS + (n mod q) (inf: none; S7);
#: the lock watch (S8): the first sample's winding and φ, the current block's sum of
#: θ − θ_first and its count, the level (blocks of LOCK_BLOCK·2^level samples), the
#: number of block means kept and the means.
STROBE = _group(
    ("str_t0", _F), ("str_n", _I), ("str_k", _F), ("str_phi", _F), ("str_v", _F), ("str_p", _F),
    ("str_m", _I), ("str_d1t", _F), ("str_d1v", _F), ("str_d2t", _F), ("str_d2v", _F), ("str_d3t", _F),
    ("str_d3v", _F), ("str_ta", _F), ("str_psi", _F), ("str_tau1", _F), ("str_tau2", _F), ("str_rho", _F),
    ("str_nw", _I), ("str_q", _F), ("str_ring", _F, (4 * STROBE_RING,)), ("str_qtau1", _F, (_STROBE_Q,)),
    ("str_qtau2", _F, (_STROBE_Q,)), ("str_qrho", _F, (_STROBE_Q,)),
    ("str_qb", _F, (_STROBE_Q * STROBE_MAX_PERIODS,)), ("lk_k0", _F), ("lk_phi0", _F), ("lk_acc", _F),
    ("lk_cnt", _I), ("lk_lvl", _I), ("lk_nb", _I), ("lk_means", _F, (LOCK_SLOTS,)))

#: The damped regimes' constants (RS_DAMPED): the locked test's (L1, L4 and L7's quick
#: term: mbm.regimes.locked._lock_setup) and the return map's section θ_s with θ'' + βθ'
#: on it (R1), formed for the model dmp_beta, dmp_gamma, dmp_omega (nan: none yet) and
#: formed again by the loop where the model's words differ from those (a template whose
#: model is set later, a swept parameter), so a stale set is never used.
DAMPED = _group(("dmp_beta", _F), ("dmp_gamma", _F), ("dmp_omega", _F), ("dmp_d", _F), ("dmp_wl2", _F),
                ("dmp_g0", _F), ("dmp_g1", _F), ("dmp_sd", _F), ("dmp_q2", _F), ("dmp_sec_off", _F),
                ("dmp_sec_acc", _F))

#: The run record, in named groups: ``r.model.beta``, ``r.state.t``, ``r.cycle.cyc_T``
#: (numba and numpy alike).  One row per scene; :func:`mbm.core.loop.run` reads every group
#: and writes the state, winding, progress and regimes' groups back.
RUN = np.dtype(
    [("model", MODEL), ("state", STATE), ("winding", WINDING), ("control", CONTROL),
     ("progress", PROGRESS), ("switch", SWITCH), ("cycle", CYCLE), ("strobe", STROBE),
     ("damped", DAMPED)],
    align=True,
)

#: The group of each field (field names are unique across groups).
GROUP = {name: group for group in RUN.names for name in RUN.fields[group][0].names}

#: Word index of each field of a RUN record (every field is 8 bytes, aligned), for
#: setting and reading fields through float64/int64 views of a record: a field access
#: through the record costs ~0.3 µs, a copy of a structured array ~3.5 µs, a view ~0.1.
WORD = {name: (RUN.fields[g][1] + RUN.fields[g][0].fields[name][1]) // 8 for name, g in GROUP.items()}

#: The same words under flat field names, for Python (``flat(p)["beta"]``).
FLAT = np.dtype({
    "names": list(GROUP),
    "formats": [RUN.fields[g][0].fields[name][0] for name, g in GROUP.items()],
    "offsets": [8 * WORD[name] for name in GROUP],
    "itemsize": RUN.itemsize,
})


assert len(GROUP) == sum(len(RUN.fields[g][0].names) for g in RUN.names)  # unique names
assert all(RUN.fields[g][0].fields[name][1] % 8 == 0 and RUN.fields[g][1] % 8 == 0
           for name, g in GROUP.items())
assert RUN.itemsize == sum(FLAT.fields[name][0].itemsize for name in FLAT.names)


def flat(p):
    """A view of RUN records ``p`` (an array or one record) with flat field names."""
    return p.view(FLAT)


@numba.njit(cache=True)  # called from Python (new_run)
def init_run(p, i, model, state, control, max_windows, call_windows, regimes):
    """Set row ``i`` of RUN array ``p`` to a fresh run: the one initialiser of a record.

    ``model`` is (β, γ, ω, A, Ω, φ), ``state`` (t0, θ0, θ'0, t_bound), ``control``
    (kind, karg, controller, h_abs, max_step, max_dtheta, rtol, atol, error_order), as
    the groups :data:`MODEL`, :data:`STATE`, :data:`CONTROL`; progress, winding and the
    regimes' groups start empty (``n_windows = j = status = 0``, φ = θ0, ``regime``
    none, ``t_regime`` nan, no damped constants formed; regime switching on unless
    ``regimes = 0``).
    """
    r = p[i]
    m = r.model
    m.beta, m.gamma, m.omega, m.drive_amp, m.drive_freq, m.drive_phase = model
    s = r.state
    s.t, s.theta, s.v, s.t_bound = state
    r.winding.phi, r.winding.wind = s.theta, 0.0
    c = r.control
    c.kind, c.karg, c.controller, c.h_abs, c.max_step, c.max_dtheta, c.rtol, c.atol, c.error_order = control
    g = r.progress
    g.max_windows, g.call_windows, g.n_windows, g.j, g.status = max_windows, call_windows, 0, 0, 0
    w = r.switch
    w.regimes, w.regime, w.t_regime = regimes, REGIME_NONE, math.nan
    y = r.cycle
    y.sec_n, y.sec_sign, y.sec_t, y.sec_v, y.sec_T, y.sec_dv, y.sec_vmax = 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    y.cyc_theta, y.cyc_v, y.cyc_T, y.cyc_t, y.cyc_sign = 0.0, 0.0, math.nan, 0.0, 0.0
    y.cyc_k, y.cyc_wind, y.cyc_Tlo = 0, 0.0, 0.0
    b = r.strobe
    b.str_t0, b.str_n, b.str_k, b.str_phi, b.str_v, b.str_p, b.str_m = 0.0, 0, 0.0, 0.0, 0.0, 0.0, 0
    b.str_d1t, b.str_d1v, b.str_d2t, b.str_d2v, b.str_d3t, b.str_d3v = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    b.str_ta, b.str_psi = 0.0, 0.0
    b.str_tau1, b.str_tau2, b.str_rho, b.str_nw, b.str_q = math.nan, math.nan, math.nan, 0, 1.0
    for q in range(b.str_ring.size):
        b.str_ring[q] = 0.0
    for q in range(b.str_qtau1.size):
        b.str_qtau1[q] = math.nan
        b.str_qtau2[q] = math.nan
        b.str_qrho[q] = math.nan
    for q in range(b.str_qb.size):
        b.str_qb[q] = math.inf
    b.lk_k0, b.lk_phi0, b.lk_acc, b.lk_cnt, b.lk_lvl, b.lk_nb = 0.0, 0.0, 0.0, 0, 0, 0
    for q in range(b.lk_means.size):
        b.lk_means[q] = 0.0
    a = r.damped
    a.dmp_beta, a.dmp_gamma, a.dmp_omega = math.nan, math.nan, math.nan
    a.dmp_d, a.dmp_wl2, a.dmp_g0, a.dmp_g1, a.dmp_sd, a.dmp_q2 = 0.0, 1.0, 0.0, 0.0, 0.0, 0.0
    a.dmp_sec_off, a.dmp_sec_acc = 0.0, 0.0


_WS_T, _WS_THETA, _WS_V, _WS_TBOUND, _WS_H = (WORD[k] for k in ("t", "theta", "v", "t_bound", "h_abs"))


@kernel
def start_record(buf, fresh, t0, theta0, v0, t1, h):
    """The run record of the loop's entries (:func:`mbm.core.loop._runner`): the last row
    of ``buf`` (rows of a RUN record's float64 words) viewed as a RUN array of one.
    With ``fresh``, row 0 (a template record) is copied into it first and the span
    (t0, t1), the state and the first window's h_abs set (a resumed run is left as it
    stands)."""
    words = buf[buf.shape[0] - 1]
    if fresh:
        # An element loop: a slice assignment compiles numpy's broadcast-error
        # machinery and its message formatting (seconds of a first call).
        tpl = buf[0]
        for i in range(words.size):
            words[i] = tpl[i]
        words[_WS_T] = t0
        words[_WS_THETA] = theta0
        words[_WS_V] = v0
        words[_WS_TBOUND] = t1
        words[_WS_H] = h
    return words.view(RUN)


def words_of(p):
    """A RUN array of one record as the (1, words) float64 buffer the loop's entries
    take (a view: the entries write the run back into ``p``)."""
    if p.size != 1:
        raise ValueError(f"words_of takes a RUN array of one record, got {p.size}")
    return p.view(np.float64).reshape(1, RUN.itemsize // 8)


@numba.njit(cache=True)  # also called from Python
def init_runs(p, model, y0, plan, h_abs, shared):
    """:func:`init_run` for every row of ``p`` (a batch): ``model`` rows β, γ, ω, A, Ω, φ
    of shape (6, N), ``y0`` (N, 2), ``plan`` rows kind, karg, controller, error_order
    (4, N), ``h_abs`` (N,); ``shared`` = (t0, t_bound, max_step, rtol, atol, max_windows),
    the span, tolerances and budget of every row (a plain tuple: a named one costs
    ~9 µs of the dispatcher's typing per call from Python); no θ-step limit, no call
    budget, regime switching on."""
    t0, t_bound, max_step, rtol, atol, max_windows = shared
    for i in range(p.size):
        init_run(p, i, (model[0, i], model[1, i], model[2, i], model[3, i], model[4, i], model[5, i]),
                 (t0, y0[i, 0], y0[i, 1], t_bound),
                 (plan[0, i], plan[1, i], plan[2, i], h_abs[i], max_step, math.inf, rtol, atol, plan[3, i]),
                 max_windows, 0, 1)


class RunModel(NamedTuple):
    """The model group of a record (:data:`MODEL`): θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ)."""

    beta: float
    gamma: float
    omega: float
    drive_amp: float = 0.0
    drive_freq: float = 0.0
    drive_phase: float = 0.0


class RunState(NamedTuple):
    """The state group of a record (:data:`STATE`): the start (t, θ, θ') and the span's end."""

    t: float
    theta: float
    v: float
    t_bound: float


class RunControl(NamedTuple):
    """The control group of a record (:data:`CONTROL`): the approximant and its controller,
    the window limits and the tolerances, in the group's order."""

    kind: int
    karg: int
    controller: int
    h_abs: float
    max_step: float
    max_dtheta: float
    rtol: float
    atol: float
    error_order: int


#: What the adaptive controller needs besides a window's own start (coefficients, t, φ, θ',
#: the winding's offset): the direction of time, the span's end, the longest window,
#: scipy's rtol and atol, the estimate's order (the exponent −1/(error_order + 1)) and
#: log(rtol)-ish ``log_eps`` of the a-priori window (mbm.core.window.window_log_eps).
WindowControl = collections.namedtuple(
    "WindowControl", ("direction", "t_bound", "max_step", "rtol", "atol", "error_order", "log_eps"))


@numba.njit(**INLINE)
def window_control(direction, t_bound, max_step, rtol, atol, error_order, log_eps):
    """A :data:`WindowControl` with its fields' types fixed (float64, the order int64), so
    that every caller's compiles to the one type the controllers take."""
    return WindowControl(float(direction), float(t_bound), float(max_step), float(rtol), float(atol),
                         np.int64(error_order), float(log_eps))


def new_run(model, state, control, max_windows, call_windows=0, regimes=1):
    """A run record array of one row, at the start of its run (:func:`init_run`).

    Parameters
    ----------
    model : RunModel
        β, γ, ω and the drive (a driven run, ``drive_amp`` ≠ 0, may reach the
        phase-locked regime only).
    state : RunState
        The start (t, θ, θ') and the span's end ``t_bound``.
    control : RunControl
        The approximant, its controller, the window limits and the tolerances.
    max_windows, call_windows : int
        Windows the whole run may take; windows one call may take (0: no limit).
    regimes : int
        1: regime switching on; 0: off.
    """
    p = np.empty(1, dtype=RUN)
    c = control
    init_run(p, 0, tuple(float(x) for x in model), tuple(float(x) for x in state),
             (int(c.kind), int(c.karg), int(c.controller), float(c.h_abs), float(c.max_step), float(c.max_dtheta),
              float(c.rtol), float(c.atol), int(c.error_order)),
             int(max_windows), int(call_windows), int(regimes))
    return p
