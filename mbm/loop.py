"""THE compiled window loop of the moving boundary method, and its two controllers.

Every path runs a scene through :func:`_run`: :class:`mbm.MBM` (a step of one or
more windows, their formulas stored for the dense output), :func:`mbm.solve`
(outputs at ``t_eval`` or the window ends) and :func:`mbm.solve_batch` (groups of
scenes under ``prange``).  So the paths take the same windows and give the same
answers bit for bit.  A batch group (:func:`_run_lanes`) is a scheduler over the same
window: LANES scenes advance one ordinary Taylor window per round in lockstep, _run's
tests, controller and output steps per lane, the anchors and the first tries' window
ends computed for all lanes at once by lane-wise copies of the one-scene kernels (the
same operations per lane, so the same bits); every other window (a regime's, a
failure's, the run's end) is _run's own, the lane handing its scene over as a paused
run.

A window, as (3.29)–(3.31) of the second paper: the approximant is anchored at the
state reached (:func:`anchor`), and the state at the window end is the formula's
value there.  The approximant's *step* (:func:`step`) returns that value and its
local error estimate; a *controller* decides: :func:`fixed_window` (τ, cut at the
span's end) or :func:`adaptive_window` (scipy's acceptance test on the approximant's
estimate; the window tried is the kind's a-priori window from its anchored coefficients
where it has one, :func:`prior_window`, else scipy's RK step factor,
Hairer–Nørsett–Wanner II.4).  A rejected window re-evaluates the same anchored formula
at a shorter length.

The scalars of a run live in one record of dtype :data:`RUN` (a numpy structured
array of length 1, or one row per scene in a batch): model, state, controller
options, budget and progress.  :func:`run` reads it, advances, and writes the state
reached back, so a caller may resume a run where it stopped.

Compiled dispatch: numba cannot cache a kernel that takes another kernel as an
argument, so the approximants the loop runs are chosen by an integer kind
(:data:`COMPILED_KINDS`, from the approximant's declared ``compiled_kind``) in
:func:`anchor`, :func:`evaluate` and :func:`estimate`.  The loop has one compiled
entry per (kind, regime set) of :data:`RUN_TABLE` (:data:`RUNNERS`, made by
:func:`_runner` with both constants of the closure, so numba prunes the other kinds'
and regimes' branches): a scene compiles only the approximant kernels and the
regimes it can reach (:func:`regime_set`: an undriven damped scene the locked regime
and the return map's watch, never the drive's stroboscopic watch nor the libration;
the stored period's windows only once a run has switched to them, the loop pausing
at the switch so that its caller resumes it through the new set's entry,
:func:`run`, :func:`_run_chain`).  The controllers and the watches are compiled once
per kind and called (:func:`first_window_for`, :func:`adaptive_window_for`,
:func:`_cycle_watch_for`), not inlined: numba's inlining copies the callee's IR at
every call site, which was most of a first call's compile.  Adding a compiled
approximant means: one entry in :data:`COMPILED_KINDS`, one branch in each of
:func:`anchor`, :func:`evaluate`, :func:`estimate`, its rows in :data:`RUN_TABLE`
(and :func:`_dispatch`) and the evaluators of :mod:`mbm.dense`.
"""

import math

import numba
import numpy as np

from .approximants.belendez2007 import belendez_anchor_kernel, belendez_eval_kernel
from .approximants.salas2022 import salas_torque_anchor, salas_torque_eval
from .approximants.splitting import split_anchor, split_error_kernel, split_eval_kernel
from .approximants.taylor import (
    drive_phase_sincos,
    taylor_coefficients_into,
    taylor_driven_coefficients_into,
    taylor_error_kernel,
    taylor_eval_kernel,
    taylor_eval_range,
    taylor_window_log,
    taylor_workspace,
)
from .approximants.taylor_simd import HEADER as SIMD_HEADER
from .approximants.taylor_simd import LANES, SIMD_ORDER, horner24_lanes, taylor24_lanes
from .regimes import (
    CROSSING_ITERATIONS,
    CYCLE_AVERAGE_PERIODS,
    CYCLE_MAX_WINDOWS,
    CYCLE_TAG,
    CYCLE_WIDTH,
    LOCKED_TAG,
    LIBRATION_MIN_PERIODS,
    LOCKED_WIDTH,
    LOCKED2_WIDTH,
    REGIME_LIBRATION,
    REGIME_LOCKED,
    REGIME_NONE,
    REGIME_PHASE_LOCKED,
    REGIME_RUNNING,
    STROBE_CODE,
    STROBE_DISTINCT,
    STROBE_MAX_PERIODS,
    STROBE_RING,
    STROBE_TAG,
    STROBE_WIDTH,
    SWITCH_SAFETY,
    cycle_coef,
    cycle_switch,
    locked2_quick,
    locked_choice,
    locked_coef,
    locked_constants,
    locked_eval,
    locked_quick_reject,
    libration_period,
    section_offset,
    strobe_coef,
    strobe_period,
    strobe_phase,
    strobe_split,
    strobe_switch,
    strobe_time,
)
from .special.dd import two_prod, two_sum

__all__ = [
    "RUN",
    "COMPILED_KINDS",
    "CONTROLLER_FIXED",
    "CONTROLLER_ADAPTIVE",
    "STATUS_OK",
    "STATUS_TOO_SMALL",
    "STATUS_ANCHOR",
    "STATUS_NONFINITE",
    "STATUS_MAX_WINDOWS",
    "STATUS_INTERRUPTED",
    "STATUS_PAUSED",
    "STATUS_MESSAGES",
    "kind_of",
    "WORD",
    "plan_windows",
    "new_run",
    "anchor",
    "anchor_driven",
    "evaluate",
    "estimate",
    "step",
    "prior_window",
    "fixed_window",
    "adaptive_window_for",
    "first_window_for",
    "run",
    "run_taylor",
    "run_exact",
    "run_salas_torque",
    "run_split",
    "RUNNERS",
    "RUN_TABLE",
    "CHAINS",
    "RS_PLAIN",
    "RS_DAMPED",
    "RS_CONSERVATIVE",
    "RS_DRIVEN",
    "RS_CYCLE",
    "RS_STROBE",
    "regime_set",
    "set_of",
    "runner_for",
    "run_batch",
    "evaluate_windows",
    "WRAPPING_KINDS",
    "TWO_PI_A",
    "TWO_PI_B",
    "theta_of",
    "wrap",
]

# Kinds of the compiled dispatch: ``compiled_kind`` name -> (id, the approximant's
# eval kernel).  The kernel is checked against the approximant's own, so a subclass
# that overrides its formula never runs the parent's compiled kernels.
KIND_TAYLOR = 0
KIND_EXACT = 1
KIND_SALAS_TORQUE = 2
KIND_SPLIT = 3
COMPILED_KINDS = {
    "taylor": (KIND_TAYLOR, taylor_eval_kernel),
    "exact": (KIND_EXACT, belendez_eval_kernel),
    "salas-torque": (KIND_SALAS_TORQUE, salas_torque_eval),
    "split": (KIND_SPLIT, split_eval_kernel),
}

CONTROLLER_FIXED = 0
CONTROLLER_ADAPTIVE = 1

#: Kinds whose runs hold θ as a winding count and φ (see TWO_PI_A): the true
#: equation's approximants, periodic in θ.  The exact flow takes one window, and the
#: papers' ℘ formula models sin θ by a cubic in θ (not periodic): they keep θ.
WRAPPING_KINDS = (KIND_TAYLOR, KIND_SPLIT)

# Adaptive controller, as scipy's RK controller (Hairer–Nørsett–Wanner II.4): a
# safety factor below 1 keeps most windows accepted, the growth cap keeps one lucky
# estimate from jumping past the region the estimate describes (scipy caps at 10; 5
# because an estimate near the series' radius is least reliable), and the shrink
# floor keeps a bad estimate from collapsing the window.
SAFETY = 0.9
MAX_FACTOR = 5.0
MIN_FACTOR = 0.2
# First-window search: start from a quarter of the small-oscillation period and
# correct it by the estimate's own h^(p+1) scaling this many times (the anchor is
# computed once; each correction costs one evaluation and one estimate).
FIRST_WINDOW_PERIODS = 0.25
FIRST_WINDOW_ITERS = 4
# Taylor windows are chosen a priori from the anchored coefficients
# (:func:`prior_window`, heyoka's radius rule per component) with the neglected terms
# at 1/TAYLOR_WINDOW_MARGIN of the tolerance per window.  Why so far below it: along a
# conservative (β = 0) orbit the local errors lean to one sign and add up over the
# 10³–10⁴ windows of a run, and the energy error they leave turns into a phase error
# growing with t; at a margin of ~1 the global error reached 1e5× tol on issue 16's
# random scenes.  Measured on 3 × 1006 of them (docs/oracle.md): 1e3 leaves up to 84×
# tol, 1e4 up to 47× (and 7× at 1e-4) for 10 % more windows; 1e5 drives some 1e-8 runs
# to the round-off floor, where the 1e-12 run (more windows, more rounding) is then
# the less accurate one.
TAYLOR_WINDOW_MARGIN = 1e4
# ... but not below TAYLOR_WINDOW_FLOOR·(atol/rtol + |y|), about one ulp of |y|:
# truncation under round-off buys nothing, and more windows round more (the floor
# binds for rtol < TAYLOR_WINDOW_MARGIN · 2.2e-16 ≈ 2.2e-12).
TAYLOR_WINDOW_FLOOR = 2.220446049250313e-16
# A window shorter than this many ulps of t cannot advance t: fail instead of looping.
MIN_WINDOW_ULPS = 10.0
# A section crossing's Newton stops once its next correction, (θ''/2θ')·d² after a
# step d, is below this many ulps of s (quadratic convergence: the step after the
# last one made would be below it; 1 would ask for the last bit).
CROSSING_NEWTON_SAFETY = 2.0
_EPS = 2.220446049250313e-16
# Winding: a run of a kind whose formula depends on θ through sin θ and cos θ only
# (:data:`WRAPPING_KINDS`) holds its angle as θ = 2πk + φ, k an integer count and φ
# in (−π, π] once reduced, so that a window adds its increment to φ, rounded at
# ulp(π), not to θ, rounded at ulp(|θ|): on a rotation wound to |θ| = 10⁶ that
# rounding (1e-10 per window) would add up over the run, here it is 4e-16 and the
# outputs round θ once each.  2π = TWO_PI_A + TWO_PI_B (Cody–Waite): A has 32
# significant bits, so m·A is exact for |m| < 2²¹ and φ − m·A is exact (Sterbenz);
# B carries the next 53 bits (2π − fl(2π) = 2.4492935982947064e-16).
TWO_PI_A = math.ldexp(round(math.ldexp(2.0 * math.pi, 29)), -29)
TWO_PI_B = (2.0 * math.pi - TWO_PI_A) + 2.4492935982947064e-16

# The small per-window pieces are inlined into their callers, where the kind is a
# constant (numba prunes the other kinds' branches before compiling); large ones are
# compiled once per kind and called (first_window_for, ...).
_INLINE = dict(cache=True, inline="always")

# The statuses (code, name, message): mbm.status's one table, as every path reports them.
from .status import (  # noqa: E402
    STATUS_ANCHOR,
    STATUS_INTERRUPTED,
    STATUS_MAX_WINDOWS,
    STATUS_MESSAGES,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_PAUSED,
    STATUS_TOO_SMALL,
)


#: The run record.  One row per scene; :func:`run` reads every field and writes the
#: state fields back.
RUN = np.dtype(
    [
        # model θ'' + βθ' + ω² sin θ = γ
        ("beta", np.float64),
        ("gamma", np.float64),
        ("omega", np.float64),
        # state: the run's position on entry, the state reached on return
        ("t", np.float64),
        ("theta", np.float64),
        ("v", np.float64),
        ("t_bound", np.float64),
        # approximant: COMPILED_KINDS id and its integer argument
        ("kind", np.int64),
        ("karg", np.int64),
        # controller: CONTROLLER_FIXED or CONTROLLER_ADAPTIVE; h_abs is the next window
        # length (τ when fixed; the adaptive proposal, ≤ 0 to search it from the
        # estimate); error_order sets the adaptive exponent −1/(error_order + 1)
        ("controller", np.int64),
        ("h_abs", np.float64),
        ("max_step", np.float64),
        # longest angle a window may sweep: a window starting at speed θ' is at most
        # max_dtheta/|θ'| long (inf: no limit; set when solve_ivp looks for events)
        ("max_dtheta", np.float64),
        ("rtol", np.float64),
        ("atol", np.float64),
        ("error_order", np.int64),
        # budget and progress
        ("max_windows", np.int64),  # windows the whole run may take (STATUS_MAX_WINDOWS past it)
        ("call_windows", np.int64),  # windows one call may take before pausing (≤ 0: no limit)
        ("n_windows", np.int64),  # windows taken so far
        ("j", np.int64),  # next index of t_eval to fill
        ("status", np.int64),
        # long-horizon regimes (mbm.regimes): regimes ≠ 0 lets the run switch to a
        # regime's closed form (adaptive controller, forwards only); regime is the one
        # reached (REGIME_NONE, REGIME_LOCKED) and t_regime when (nan before)
        ("regimes", np.int64),
        ("regime", np.int64),
        ("t_regime", np.float64),
        # running cycle (mbm.regimes, R1-R3): the return map so far (crossings of
        # θ = θ_s + 2πm, regimes.section_offset, in one direction: count, sign, last
        # time, θ', return time, change of θ', largest |θ'| since) and, once switched,
        # the cycle (anchor crossing θ, θ', period, time, winding sign)
        ("sec_n", np.int64),
        ("sec_sign", np.float64),
        ("sec_t", np.float64),
        ("sec_v", np.float64),
        ("sec_T", np.float64),
        ("sec_dv", np.float64),
        ("sec_vmax", np.float64),
        ("cyc_theta", np.float64),
        ("cyc_v", np.float64),
        ("cyc_T", np.float64),
        ("cyc_t", np.float64),
        ("cyc_sign", np.float64),
        ("cyc_k", np.int64),  # returns since the map converged (0: not yet)
        ("cyc_wind", np.float64),  # winding count of the cycle's anchor
        # winding (TWO_PI_A): θ = 2π·wind + phi, the state a resumed run continues
        # from (theta above is its value, rounded); a fresh run (n_windows = 0) starts
        # from theta
        ("phi", np.float64),
        ("wind", np.float64),
        # AC drive A sin(Ωt + φ) added to γ (A = 0: none, the autonomous equation; a
        # driven run anchors by anchor_driven at each window's start time, and of the
        # regimes takes only the phase-locked one below: the others assume an
        # autonomous equation)
        ("drive_amp", np.float64),
        ("drive_freq", np.float64),
        ("drive_phase", np.float64),
        # low part of the stored period (cyc_T + cyc_Tlo in double-double: a
        # libration's, mbm.regimes C3; 0 for the running cycle)
        ("cyc_Tlo", np.float64),
        # phase-locked to the drive (mbm.regimes, S1-S6): the stroboscopic samples (the
        # first sample's time origin t_s, the next sample's index n; the last sample as
        # winding count, φ and θ', carried to the exact time; the turns p of the last
        # deviations and how many in a row share it, up to 3; the three deviations
        # before the last, θ and θ' parts) and, once switched, the anchor: its time and
        # the drive's phase there (its state in str_k, str_phi, str_v, its p in str_p)
        ("str_t0", np.float64),
        ("str_n", np.int64),
        ("str_k", np.float64),
        ("str_phi", np.float64),
        ("str_v", np.float64),
        ("str_p", np.float64),
        ("str_m", np.int64),
        ("str_d1t", np.float64),
        ("str_d1v", np.float64),
        ("str_d2t", np.float64),
        ("str_d2v", np.float64),
        ("str_d3t", np.float64),
        ("str_d3v", np.float64),
        ("str_ta", np.float64),
        ("str_psi", np.float64),
        # the traces fitted at the last two samples and the last clean fit's spectral
        # radius (nan: failed or none; S4)
        ("str_tau1", np.float64),
        ("str_tau2", np.float64),
        ("str_rho", np.float64),
        # the run's window count at the last sample (a period's windows: S6)
        ("str_nw", np.int64),
        # subharmonic orbits (mbm.regimes S7): the switched orbit's period in drive
        # periods q (1 for S1-S6); the last STROBE_RING samples, sample n at words
        # 4(n mod STROBE_RING) on (winding count, φ, θ' carried to the exact time, the
        # run's window count there); per q (index q): the traces fitted at the last two
        # samples, the last clean fit's spectral radius, and per class n mod q the last
        # finite tail bound B, at q·STROBE_MAX_PERIODS + (n mod q) (inf: none)
        ("str_q", np.float64),
        ("str_ring", np.float64, (4 * STROBE_RING,)),
        ("str_qtau1", np.float64, (STROBE_MAX_PERIODS + 1,)),
        ("str_qtau2", np.float64, (STROBE_MAX_PERIODS + 1,)),
        ("str_qrho", np.float64, (STROBE_MAX_PERIODS + 1,)),
        ("str_qb", np.float64, ((STROBE_MAX_PERIODS + 1) * STROBE_MAX_PERIODS,)),
    ],
    align=True,
)


#: Word index of each field of a RUN record (every field is 8 bytes, aligned), for
#: setting and reading fields through float64/int64 views of a record: a field access
#: through the record costs ~0.3 µs, a copy of a structured array ~3.5 µs, a view ~0.1.
WORD = {name: RUN.fields[name][1] // 8 for name in RUN.names}
assert RUN.itemsize == sum(RUN.fields[name][0].itemsize for name in RUN.names)
assert all(RUN.fields[name][1] % 8 == 0 for name in RUN.names)


def kind_of(approximant):
    """``(kind id, kind argument)`` of an approximant the compiled loop runs, or None.

    None when the approximant declares no ``compiled_kind``, or when its eval kernel
    is not the one the kind dispatches to (a subclass with its own formula).
    """
    entry = COMPILED_KINDS.get(approximant.compiled_kind)
    if entry is None or approximant.eval_kernel is not entry[1]:
        return None
    return entry[0], int(approximant.kind_arg)


def plan_windows(approximant, tau, max_step, span):
    """The controller for an approximant: ``(controller, h_abs, error_order)`` or None.

    A given ``tau`` means fixed windows of that length; an exact flow has no
    truncation error, so one fixed window as long as ``max_step`` allows (the whole
    ``span`` when it is infinite); an approximant with an error estimate and a
    compiled kind runs under the adaptive controller (h_abs = −1: the first window is
    searched from the estimate).  None: the approximant needs a τ from the caller.
    """
    if tau is not None:
        return CONTROLLER_FIXED, float(tau), 0
    if approximant.exact:
        return CONTROLLER_FIXED, (max_step if math.isfinite(max_step) else (span or 1.0)), 0
    if approximant.error_kernel is not None and kind_of(approximant) is not None:
        return CONTROLLER_ADAPTIVE, -1.0, int(approximant.error_order)
    return None


def new_run(beta, gamma, omega, t0, theta0, v0, t_bound, kind, karg, controller, h_abs,
            max_step, rtol, atol, error_order, max_windows, call_windows=0, max_dtheta=math.inf,
            regimes=1, drive_amplitude=0.0, drive_frequency=0.0, drive_phase=0.0):
    """A run record array of one row, at the start of its run (n_windows = j = status = 0;
    regime switching on unless ``regimes=0``; a driven run, ``drive_amplitude`` ≠ 0, may
    reach the phase-locked regime only)."""
    return np.array(
        [(beta, gamma, omega, t0, theta0, v0, t_bound, kind, karg, controller, h_abs,
          max_step, max_dtheta, rtol, atol, error_order, max_windows, call_windows, 0, 0, 0,
          regimes, REGIME_NONE, math.nan, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
          math.nan, 0.0, 0.0, 0, 0.0, theta0, 0.0, drive_amplitude, drive_frequency, drive_phase, 0.0,
          0.0, 0, 0.0, 0.0, 0.0, 0.0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, math.nan, math.nan, math.nan, 0,
          1.0, np.zeros(4 * STROBE_RING), np.full(STROBE_MAX_PERIODS + 1, math.nan),
          np.full(STROBE_MAX_PERIODS + 1, math.nan), np.full(STROBE_MAX_PERIODS + 1, math.nan),
          np.full((STROBE_MAX_PERIODS + 1) * STROBE_MAX_PERIODS, math.inf))],
        dtype=RUN,
    )


# ---------------------------------------------------------------------------
# The approximant's step (compiled dispatch)
# ---------------------------------------------------------------------------


@numba.njit(**_INLINE)
def anchor(kind, karg, beta, gamma, omega, theta0, v0, ws_coef, ws_scratch):
    """Coefficient vector of approximant ``kind`` anchored at (θ₀, θ̇₀); coef[0] = status.

    Kind "taylor" writes it into the run's workspace ``ws_coef``, ``ws_scratch``
    (:func:`mbm.approximants.taylor.taylor_workspace`; no allocation per window), so
    the vector lives until the next anchor; the other kinds return a new array.
    """
    if kind == KIND_TAYLOR:
        return taylor_coefficients_into(beta, gamma, omega, theta0, v0, karg, ws_coef, ws_scratch)
    elif kind == KIND_EXACT:
        return belendez_anchor_kernel(beta, gamma, omega, theta0, v0)
    elif kind == KIND_SPLIT:
        return split_anchor(karg, beta, gamma, omega, theta0, v0)
    elif kind == KIND_SALAS_TORQUE:
        return salas_torque_anchor(beta, gamma, omega, theta0, v0)
    # An unknown kind cannot be anchored: a status, never a formula of another kind.
    bad = np.full(1, np.nan)
    bad[0] = -1.0
    return bad


@numba.njit(**_INLINE)
def anchor_driven(kind, karg, beta, gamma, omega, amp, freq, phase, t0, theta0, v0, ws_coef, ws_scratch):
    """:func:`anchor` of the driven equation (torque γ + A sin(Ωt + φ)), the window
    starting at time ``t0``, into the workspace as :func:`anchor`; only kind "taylor"
    integrates a drive (the others: a bad status, never the autonomous formula)."""
    if kind == KIND_TAYLOR:
        return taylor_driven_coefficients_into(beta, gamma, omega, amp, freq, phase, t0, theta0, v0, karg,
                                               ws_coef, ws_scratch)
    bad = np.full(1, np.nan)
    bad[0] = -1.0
    return bad


@numba.njit(**_INLINE)
def evaluate(kind, coef, t):
    """(θ, θ') of an anchored approximant at time ``t`` from its anchor."""
    if kind == KIND_TAYLOR:
        return taylor_eval_kernel(coef, t)
    elif kind == KIND_EXACT:
        return belendez_eval_kernel(coef, t)
    elif kind == KIND_SPLIT:
        return split_eval_kernel(coef, t)
    elif kind == KIND_SALAS_TORQUE:
        return salas_torque_eval(coef, t)
    return math.nan, math.nan


@numba.njit(**_INLINE)
def estimate(kind, coef, h):
    """Local error estimate (err_θ, err_θ') of the window [0, h].

    0 for the exact flow and for kinds without an estimate (those run under the
    fixed controller only).
    """
    if kind == KIND_TAYLOR:
        return taylor_error_kernel(coef, h)
    elif kind == KIND_SPLIT:
        return split_error_kernel(coef, h)
    return 0.0, 0.0


@numba.njit(**_INLINE)
def prior_window(kind, coef, y0, y1, rtol, atol, log_eps):
    """A-priori window length of an anchored approximant, or inf where it has none.

    Kind "taylor": :func:`mbm.approximants.taylor.taylor_window_kernel` with the
    neglected terms at 1/:data:`TAYLOR_WINDOW_MARGIN` of scipy's scale atol + rtol·|y|
    per component (and not below :data:`TAYLOR_WINDOW_FLOOR`·(atol/rtol + |y|)), its
    logarithm ``log_eps`` from :func:`window_log_eps`.  Other kinds: inf (their
    windows come from the estimate's h^(p+1) scaling alone).
    """
    if kind == KIND_TAYLOR:
        return taylor_window_log(coef, y0, y1, rtol, atol, log_eps)
    return math.inf


@numba.njit(**_INLINE)
def window_log_eps(rtol):
    """ln of :func:`prior_window`'s per-window target eps (a constant of the run, formed
    once per loop call: a log per window was ~10 ns of it)."""
    return math.log(max(rtol / TAYLOR_WINDOW_MARGIN, TAYLOR_WINDOW_FLOOR))


@numba.njit(**_INLINE)
def step(kind, coef, h, with_error):
    """The approximant's step over [0, h]: ``(theta, v, err_theta, err_v)``.

    The estimate is computed only ``with_error`` (the fixed controller does not read
    it, and a splitting's estimate costs as much as the step).
    """
    theta, v = evaluate(kind, coef, h)
    if with_error:
        et, ev = estimate(kind, coef, h)
        return theta, v, et, ev
    return theta, v, 0.0, 0.0


# ---------------------------------------------------------------------------
# Controllers
# ---------------------------------------------------------------------------


@numba.njit(**_INLINE)
def _window_end(t, direction, t_bound, h_abs):
    t_new = t + direction * h_abs
    if direction * (t_new - t_bound) > 0.0:
        t_new = t_bound
    return t_new


@numba.njit(**_INLINE)
def _error_norm(et, ev, y0, y1, theta, v, rtol, atol):
    # scipy's RMS norm of the estimate scaled by atol + rtol·max(|y_start|, |y_end|).
    st = atol + rtol * max(abs(y0), abs(theta))
    sv = atol + rtol * max(abs(y1), abs(v))
    return math.sqrt(0.5 * ((et / st) ** 2 + (ev / sv) ** 2))


@numba.njit(**_INLINE)
def fixed_window(kind, coef, t, direction, t_bound, tau):
    """Fixed controller: one window of length τ (cut at t_bound).

    Returns ``(status, t_new, theta, v)``; a non-finite state fails the window.
    """
    t_new = _window_end(t, direction, t_bound, tau)
    theta, v, _, _ = step(kind, coef, t_new - t, False)
    if not (math.isfinite(theta) and math.isfinite(v)):
        return STATUS_NONFINITE, t_new, theta, v
    return STATUS_OK, t_new, theta, v


def first_window_for(kind):
    """:func:`first_window` compiled for kind ``kind`` (a constant of the closure: numba prunes
    the other kinds' kernels), called rather than inlined: inlining copies the
    callee's IR at each site, which was most of a first call's compile."""

    @numba.njit(cache=True)
    def first_window(coef, t, y0, y1, off, direction, t_bound, omega, max_step, rtol, atol,
                     error_order, log_eps):
        """Initial adaptive window length: the a-priori window (:func:`prior_window`) where
        the kind has one, else searched from the anchored formula's own error estimate.
        ``off`` (2π × the winding count) is added to θ where it sets the tolerance's scale."""
        prior = prior_window(kind, coef, off + y0, y1, rtol, atol, log_eps)
        if prior < math.inf:
            return min(prior, max_step)
        h_abs = min(FIRST_WINDOW_PERIODS * 2.0 * math.pi / omega, max_step)
        inv = -1.0 / (error_order + 1.0)
        for _ in range(FIRST_WINDOW_ITERS):
            h = _window_end(t, direction, t_bound, h_abs) - t
            theta, v, et, ev = step(kind, coef, h, True)
            err = _error_norm(et, ev, off + y0, y1, off + theta, v, rtol, atol)
            if not (math.isfinite(err) and math.isfinite(theta) and math.isfinite(v)):
                h_abs *= MIN_FACTOR
                continue
            fac = MAX_FACTOR if err == 0.0 else SAFETY * err**inv
            h_abs = min(h_abs * min(MAX_FACTOR, max(MIN_FACTOR, fac)), max_step)
        return h_abs

    return first_window


@numba.njit(**_INLINE)
def _accepted_factor(err, theta, v, prior, inv, rejected):
    """:func:`adaptive_window`'s test of a try: the factor of the next proposal when the
    try is accepted (scaled estimate ≤ 1, finite), else 0."""
    if math.isfinite(err) and err <= 1.0 and math.isfinite(theta) and math.isfinite(v):
        if prior < math.inf:
            fac = MAX_FACTOR
        else:
            fac = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err**inv)
        if rejected:
            fac = min(1.0, fac)
        return fac
    return 0.0


def adaptive_window_for(kind):
    """:func:`adaptive_window` compiled for kind ``kind`` (a constant of the closure: numba prunes
    the other kinds' kernels), called rather than inlined: inlining copies the
    callee's IR at each site, which was most of a first call's compile."""

    @numba.njit(cache=True)
    def adaptive_window(coef, t, y0, y1, off, direction, t_bound, h_abs, max_step, rtol, atol,
                        error_order, log_eps):
        """Adaptive controller: one accepted window under rtol/atol.

        The window tried is ``h_abs`` (the previous proposal, or ``first_step``), no longer
        than ``max_step`` nor than the kind's a-priori window (:func:`prior_window`).  It
        is accepted when the scaled estimate is ≤ 1 (scipy's test), else shortened by the
        estimate's h^(p+1) scaling and retried.  Returns ``(status, t_new, theta, v,
        h_next)``.  The proposal h_next: with an a-priori window, MAX_FACTOR × this window
        (the next anchor's own prior decides; the cap only lets a ``first_step`` grow);
        without, scipy's factor from the estimate.  After a rejection, no longer than the
        window accepted.  ``off`` (2π × the winding count) is added to θ where it sets the
        tolerance's scale (scipy's atol + rtol·|y| of the whole angle).
        """
        min_h = MIN_WINDOW_ULPS * _EPS * max(abs(t), 1e-300)
        prior = prior_window(kind, coef, off + y0, y1, rtol, atol, log_eps)
        h_abs = min(h_abs, max_step, prior)
        rejected = False
        inv = -1.0 / (error_order + 1.0)
        while True:
            if h_abs < min_h:
                return STATUS_TOO_SMALL, t, y0, y1, h_abs
            t_new = _window_end(t, direction, t_bound, h_abs)
            theta, v, et, ev = step(kind, coef, t_new - t, True)
            err = _error_norm(et, ev, off + y0, y1, off + theta, v, rtol, atol)
            fac = _accepted_factor(err, theta, v, prior, inv, rejected)
            if fac > 0.0:
                return STATUS_OK, t_new, theta, v, h_abs * fac
            if math.isfinite(err):
                h_abs *= max(MIN_FACTOR, SAFETY * err**inv)
            else:
                h_abs *= MIN_FACTOR
            rejected = True

    return adaptive_window


_first_window_taylor = first_window_for(KIND_TAYLOR)
_first_window_split = first_window_for(KIND_SPLIT)
_adaptive_window_taylor = adaptive_window_for(KIND_TAYLOR)
_adaptive_window_split = adaptive_window_for(KIND_SPLIT)


@numba.njit(**_INLINE)
def _first(kind, coef, t, y0, y1, off, direction, t_bound, omega, max_step, rtol, atol, error_order, log_eps):
    """:func:`first_window` of kind ``kind`` through its compiled entry; h = −1 (no
    window) for a kind without an error estimate."""
    if kind == KIND_TAYLOR:
        return _first_window_taylor(coef, t, y0, y1, off, direction, t_bound, omega, max_step, rtol, atol,
                                    error_order, log_eps)
    if kind == KIND_SPLIT:
        return _first_window_split(coef, t, y0, y1, off, direction, t_bound, omega, max_step, rtol, atol,
                                   error_order, log_eps)
    return -1.0


@numba.njit(**_INLINE)
def _adaptive(kind, coef, t, y0, y1, off, direction, t_bound, h_abs, max_step, rtol, atol, error_order,
              log_eps):
    """:func:`adaptive_window` of kind ``kind`` through its compiled entry; a kind
    without an error estimate cannot run adaptive windows (STATUS_TOO_SMALL)."""
    if kind == KIND_TAYLOR:
        return _adaptive_window_taylor(coef, t, y0, y1, off, direction, t_bound, h_abs, max_step, rtol,
                                       atol, error_order, log_eps)
    if kind == KIND_SPLIT:
        return _adaptive_window_split(coef, t, y0, y1, off, direction, t_bound, h_abs, max_step, rtol,
                                      atol, error_order, log_eps)
    return STATUS_TOO_SMALL, t, y0, y1, h_abs


# ---------------------------------------------------------------------------
# Winding (TWO_PI_A)
# ---------------------------------------------------------------------------


@numba.njit(**_INLINE)
def theta_of(k, phi):
    """θ = 2πk + φ, rounded once (φ itself when k = 0)."""
    if k == 0.0:
        return phi
    return k * TWO_PI_A + (phi + k * TWO_PI_B)


@numba.njit(**_INLINE)
def wrap(k, phi):
    """``(k', φ')`` with φ' in (−π, π] and 2πk' + φ' = 2πk + φ (to the rounding of φ').

    In doubles φ' lies in [−fl(π), fl(π)]: both ends are inside (−π, π], as fl(π) < π
    (and they are different angles).  Idempotent: such a φ is returned as it is.
    """
    if -math.pi <= phi <= math.pi:
        return k, phi
    m = -math.floor((math.pi - phi) / (2.0 * math.pi))
    phi = (phi - m * TWO_PI_A) - m * TWO_PI_B
    # The quotient's rounding can leave φ' just outside the interval: one more turn.
    if phi > math.pi:
        phi = (phi - TWO_PI_A) - TWO_PI_B
        m += 1.0
    elif phi < -math.pi:
        phi = (phi + TWO_PI_A) + TWO_PI_B
        m -= 1.0
    return k + m, phi


@numba.njit(**_INLINE)
def _reduce_phi(k, phi):
    """(k, φ) before a window: φ reduced to (−π, π] where that leaves θ's value unchanged
    to the bit (so a window's start repeats the state the last one ended at; else next
    time)."""
    if not (-math.pi <= phi <= math.pi):
        k2, phi2 = wrap(k, phi)
        if theta_of(k2, phi2) == theta_of(k, phi):
            return k2, phi2
    return k, phi


@numba.njit(**_INLINE)
def _put(out_theta, out_w, wrapped, i, k, phi):
    # An output angle: θ = 2πk + φ, or (φ wrapped to (−π, π], its winding count).
    if wrapped:
        kk, ph = wrap(k, phi)
        out_theta[i] = ph
        out_w[i] = kk
    else:
        out_theta[i] = theta_of(k, phi)


# ---------------------------------------------------------------------------
# Running cycle (mbm.regimes, R1-R3)
# ---------------------------------------------------------------------------

_TWO_PI = 2.0 * math.pi
# Windows a stored period's arrays hold at first (doubled as needed): a period takes
# ~10-100 windows at the tolerances in use.
PERIOD_STORE_START = 64


@numba.njit(**_INLINE)
def _crossing(kind, coef, h, f0, f1, level, acc0, beta, w2):
    """Where the window's θ(s) crosses ``level`` in (0, h] (f0, f1: θ − level at 0, h).

    Safeguarded Newton (θ' from the formula) inside the sign bracket (R1).  ``acc0``
    is γ − ω² sin(level) and ``w2`` ω², so that θ'' = acc0 − βθ' on the level (the
    equation of motion).  Newton's next correction after a step d is about
    (θ''/2θ')·d²; once that is below CROSSING_NEWTON_SAFETY ulps of s, the step's end
    is the root, and θ' there is carried from the last evaluation by d·θ''.  That
    carry is off by at most ~1.5(ω²|θ'| + β|θ''|)·d² (θ'' varies with θ − level = −θ'd
    and with t), which must be below CROSSING_NEWTON_SAFETY ulps of θ' too.  Then the
    usual last two evaluations (one to see the step vanish, one for θ' at the root)
    are not made: two evaluations per crossing instead of four on a running scene.
    Returns ``(s, θ'(s))``.
    """
    lo, hi, flo = 0.0, h, f0
    s = h * f0 / (f0 - f1) if f0 != f1 else h
    v = 0.0
    for _ in range(CROSSING_ITERATIONS):
        a, v = evaluate(kind, coef, s)
        fa = a - level
        if fa == 0.0:
            break
        if (fa > 0.0) == (flo > 0.0):
            lo, flo = s, fa
        else:
            hi = s
        s_new = s - fa / v if v != 0.0 else 0.5 * (lo + hi)
        if not (lo < s_new < hi):
            s_new = 0.5 * (lo + hi)
        else:
            d = s_new - s
            d2 = d * d
            acc = acc0 - beta * v
            tol_v = CROSSING_NEWTON_SAFETY * _EPS * abs(v)
            if (abs(acc) * d2 <= 2.0 * tol_v * abs(s_new)
                    and 1.5 * (w2 * abs(v) + beta * abs(acc)) * d2 <= tol_v):
                return s_new, v + d * acc
        if abs(s_new - s) <= 4.0 * _EPS * max(abs(s), 1e-300):
            s = s_new
            a, v = evaluate(kind, coef, s)
            break
        s = s_new
    return s, v


@numba.njit(**_INLINE)
def _cycle_phase(c, t):
    """``(n, s)``: τ = t + t_off = nT + s, 0 ≤ s ≤ T, for a cycle window ``c`` (R3, C3).

    With a double-double period (c[14] ≠ 0, a libration) n·T is formed exactly, so
    the period's rounding to a double does not accumulate over n periods.
    """
    period, lo = c[3], c[14]
    tau = t + c[4]
    n = float(math.floor(tau / period))
    if lo == 0.0:
        s = tau - n * period
    else:
        ph, pl = two_prod(n, period)
        sh, se = two_sum(tau, -ph)
        s = sh + ((se - pl) - n * lo)
    return n, min(max(s, 0.0), period)


@numba.njit(**_INLINE)
def _period_windows(kind, c):
    """The windows of a cycle window's stored period, re-taken from its anchor (R3).

    The same approximant and controller as the run, span [0, T]: a function of the
    anchor only, so every path and the dense output evaluate the same windows.

    Returns
    -------
    starts : ndarray, shape (n + 1,)
        Window starts from the anchor (starts[n] = T).
    ends : ndarray, shape (n + 1, 2)
        The state at each start (row 0 the anchor; row i + 1 the end of window i).
    coefs : ndarray, shape (n, width)
        The windows' coefficient vectors.
    n : int
        Windows in the period; −1 where the run failed or took more than
        CYCLE_MAX_WINDOWS.
    """
    theta_c, v_c, period = c[1], c[2], c[3]
    beta, gamma, omega, rtol, atol = c[5], c[6], c[7], c[8], c[9]
    karg = int(c[11])
    error_order = int(c[12])
    log_eps = window_log_eps(rtol)
    off = c[13] * _TWO_PI
    cap = PERIOD_STORE_START
    starts = np.empty(cap + 1)
    ends = np.empty((cap + 1, 2))
    # Allocated at the first window, when its width is known (one anchor call site:
    # each inlined anchor is the whole recurrence, compiled again).
    coefs = np.empty((0, 0))
    ws_coef, ws_scratch = taylor_workspace(karg)
    starts[0], ends[0, 0], ends[0, 1] = 0.0, theta_c, v_c
    tt, a0, a1, h = 0.0, theta_c, v_c, -1.0
    for n in range(CYCLE_MAX_WINDOWS):
        coef = anchor(kind, karg, beta, gamma, omega, a0, a1, ws_coef, ws_scratch)
        if coef[0] != 0.0:
            break
        if n == 0:
            coefs = np.empty((cap, coef.size))
        if h <= 0.0:
            h = _first(kind, coef, tt, a0, a1, off, 1.0, period, omega, math.inf, rtol, atol,
                             error_order, log_eps)
        st, t_new, th, v, h_next = _adaptive(kind, coef, tt, a0, a1, off, 1.0, period, h, math.inf,
                                                   rtol, atol, error_order, log_eps)
        if st != STATUS_OK:
            break
        # Element loops, not slice assignments: those compile numpy's broadcast-error
        # machinery (a few seconds of a cold start) for shapes that always agree here.
        if n == cap:
            cap *= 2
            starts2 = np.empty(cap + 1)
            ends2 = np.empty((cap + 1, 2))
            coefs2 = np.empty((cap, coef.size))
            for q in range(n + 1):
                starts2[q] = starts[q]
                ends2[q, 0], ends2[q, 1] = ends[q, 0], ends[q, 1]
            for q in range(n):
                for w in range(coef.size):
                    coefs2[q, w] = coefs[q, w]
            starts, ends, coefs = starts2, ends2, coefs2
        for w in range(coef.size):
            coefs[n, w] = coef[w]
        starts[n + 1], ends[n + 1, 0], ends[n + 1, 1] = t_new, th, v
        if t_new >= period:
            return starts, ends, coefs, n + 1
        tt, a0, a1, h = t_new, th, v, h_next
    return starts, ends, coefs, -1


@numba.njit(**_INLINE)
def _period_lookup(kind, c, starts, ends, coefs, n, t):
    """A cycle window ``c`` at ``t`` from its stored period (:func:`_period_windows`).

    Returns ``(φ, θ', k)``: θ = 2πk + φ (:func:`theta_of`), k the anchor's winding
    count plus the periods passed times the winding sign (0 for a libration).  The
    value is the first window ending at or after s (its end state where it ends at
    s), as a run to s would give it.
    """
    if n < 1:
        return math.nan, math.nan, 0.0
    k_n, s = _cycle_phase(c, t)
    lo, hi = 0, n - 1
    while lo < hi:
        mid = (lo + hi) // 2
        if starts[mid + 1] >= s:
            hi = mid
        else:
            lo = mid + 1
    if starts[lo + 1] == s:
        th, v = ends[lo + 1, 0], ends[lo + 1, 1]
    else:
        th, v = evaluate(kind, coefs[lo], s - starts[lo])
    return th, v, c[13] + c[10] * k_n


# The stored period re-runs a period of windows (a whole controller and step): compiled
# once per kind that can reach a cycle (the adaptive ones) and called, not inlined at
# each call site (inlined, it tripled the loop's compile).
@numba.njit(cache=True)
def _period_windows_taylor(c):
    return _period_windows(KIND_TAYLOR, c)


@numba.njit(cache=True)
def _period_windows_split(c):
    return _period_windows(KIND_SPLIT, c)


@numba.njit(**_INLINE)
def _period_store(kind, c):
    """:func:`_period_windows` of kind ``kind`` through its compiled entry."""
    if kind == KIND_SPLIT:
        return _period_windows_split(c)
    return _period_windows_taylor(c)


# The lookup likewise: one compiled copy serves the loop and both dense outputs.
@numba.njit(cache=True)
def _period_lookup_taylor(c, starts, ends, coefs, n, t):
    return _period_lookup(KIND_TAYLOR, c, starts, ends, coefs, n, t)


@numba.njit(cache=True)
def _period_lookup_split(c, starts, ends, coefs, n, t):
    return _period_lookup(KIND_SPLIT, c, starts, ends, coefs, n, t)


@numba.njit(**_INLINE)
def _period_value(kind, c, starts, ends, coefs, n, t):
    """:func:`_period_lookup` of kind ``kind`` through its compiled entry."""
    if kind == KIND_SPLIT:
        return _period_lookup_split(c, starts, ends, coefs, n, t)
    return _period_lookup_taylor(c, starts, ends, coefs, n, t)


# ---------------------------------------------------------------------------
# Phase-locked to the drive (mbm.regimes, S1-S7)
# ---------------------------------------------------------------------------


@numba.njit(**_INLINE)
def _strobe_eval(kind, c, t):
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
        coef = anchor_driven(kind, karg, beta, gamma, omega, amp, freq, psi, tt, a0, a1, ws_coef, ws_scratch)
        if coef[0] != 0.0:
            break
        if h <= 0.0:
            h = _first(kind, coef, tt, a0, a1, off, 1.0, p_hi, omega, math.inf, rtol, atol,
                             error_order, log_eps)
        st, t_new, th, v, h_next = _adaptive(kind, coef, tt, a0, a1, off, 1.0, p_hi, h, math.inf,
                                                   rtol, atol, error_order, log_eps)
        if st != STATUS_OK:
            break
        if t_new >= s:
            if t_new != s:
                th, v = evaluate(kind, coef, s - tt)
            return th, v, k_a + kk + turns * n
        tt, a0, a1, h = t_new, th, v, h_next
    return math.nan, math.nan, 0.0


# As the cycle's: compiled once (the drive is Taylor's only) and called, not inlined.
@numba.njit(cache=True)
def _strobe_eval_taylor(c, t):
    return _strobe_eval(KIND_TAYLOR, c, t)


@numba.njit(**_INLINE)
def _strobe_value(kind, c, t):
    """:func:`_strobe_eval` of kind ``kind`` through its compiled entry (Taylor only)."""
    if kind == KIND_TAYLOR:
        return _strobe_eval_taylor(c, t)
    return math.nan, math.nan, 0.0


@numba.njit(**_INLINE)
def _strobe_samples(kind, p, coef, t, t_new, k, off, sp_hi, sp_lo, sp_det, n_total):
    """The stroboscopic samples of the window [t, t_new] (formula ``coef``, winding count
    ``k``, ``off`` = 2πk) and the switch rule at each (mbm.regimes, S1-S7): the run
    record ``p[0]`` keeps the samples' state and, on a switch, the anchor.  ``sp_hi``,
    ``sp_lo``: T_d (regimes.strobe_period); ``sp_det``: e^{−βT_d}; ``n_total``: the
    run's windows before this one.  Returns the next sample's time (after t_new)."""
    r = p[0]
    beta, gamma, omega = r.beta, r.gamma, r.omega
    amp, freq, phase = r.drive_amp, r.drive_freq, r.drive_phase
    rtol, atol = r.rtol, r.atol
    while True:
        tn, rn = strobe_time(r.str_t0, float(r.str_n), sp_hi, sp_lo)
        if not (tn <= t_new):
            return tn
        a, b = evaluate(kind, coef, tn - t)
        # (S1): carried to the exact time t_s + nT_d, to first order.
        su, _ = drive_phase_sincos(freq, phase, tn)
        acc = (gamma + amp * su) - beta * b - omega * omega * math.sin(a)
        ac, bc = a + b * rn, b + acc * rn
        if r.str_n >= 2:
            # (S1): the deviation over the last drive period, p turns.
            dphi = ac - r.str_phi
            m = np.floor(dphi / _TWO_PI + 0.5)
            turns = (k - r.str_k) + m
            dth = (dphi - m * TWO_PI_A) - m * TWO_PI_B
            dv = bc - r.str_v
            tau = math.nan
            if r.str_m >= 3 and turns == r.str_p:
                # (S5): the switch rule; the anchor is this sample at t_n itself.
                scale = SWITCH_SAFETY * min(atol + rtol * abs(b), omega * (atol + rtol * abs(off + a)))
                ok, tau, r.str_rho, _, _ = strobe_switch(
                    r.str_d3t, r.str_d3v, r.str_d2t, r.str_d2v, r.str_d1t, r.str_d1v, dth, dv, sp_det,
                    omega, scale, r.str_tau1, r.str_tau2, r.str_rho)
                # (S6): a period the stored re-run can take (it stops at CYCLE_MAX_WINDOWS).
                if ok and n_total + 1 - r.str_nw <= CYCLE_MAX_WINDOWS // 2:
                    r.regime = REGIME_PHASE_LOCKED
                    r.t_regime = t_new
                    r.str_ta, r.str_psi = tn, strobe_phase(freq, phase, tn)
                    r.str_k, r.str_phi, r.str_v = k, a, b
                    r.str_n += 1
                    return math.inf
            if r.str_m > 0 and turns == r.str_p:
                r.str_d3t, r.str_d3v = r.str_d2t, r.str_d2v
                r.str_d2t, r.str_d2v = r.str_d1t, r.str_d1v
                r.str_m = min(r.str_m + 1, 3)
            else:
                r.str_p, r.str_m, r.str_rho = turns, 1, math.nan
            r.str_d1t, r.str_d1v = dth, dv
            r.str_tau2, r.str_tau1 = r.str_tau1, tau
        # (S7): the maps P^q, q = 2 .. STROBE_MAX_PERIODS (q = 1 first, above).
        scale = SWITCH_SAFETY * min(atol + rtol * abs(b), omega * (atol + rtol * abs(off + a)))
        qs, ps = _strobe_subharmonic(p, k, ac, bc, scale, sp_hi, n_total)
        if qs > 0:
            r.regime = REGIME_PHASE_LOCKED
            r.t_regime = t_new
            r.str_ta, r.str_psi = tn, strobe_phase(freq, phase, tn)
            r.str_k, r.str_phi, r.str_v = k, a, b
            r.str_p, r.str_q = ps, float(qs)
            r.str_n += 1
            return math.inf
        slot = 4 * (r.str_n % STROBE_RING)
        r.str_ring[slot] = k
        r.str_ring[slot + 1] = ac
        r.str_ring[slot + 2] = bc
        r.str_ring[slot + 3] = float(n_total + 1)
        r.str_k, r.str_phi, r.str_v = k, ac, bc
        r.str_n += 1
        r.str_nw = n_total + 1


# _strobe_dev and _strobe_subharmonic are called, not inlined: they are kind-free, run once
# per drive period of a driven run, and inlined at their call sites they added ~10 s to
# run_taylor's compile from an empty cache (49 -> 39 s, measured).
@numba.njit(cache=True)
def _strobe_dev(r, n, i, d, k, phi, v):
    """``(turns, Δθ, Δθ')`` of z_i − z_{i−d} (S1's arithmetic; S7): samples before the
    current one, index ``n`` (state ``k``, ``phi``, ``v``), from the record's ring."""
    ring = r.str_ring
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


@numba.njit(cache=True)
def _strobe_subharmonic(p, k, phi, v, scale, sp_hi, n_total):
    """The switch rule of the maps P^q, q = 2 .. STROBE_MAX_PERIODS, at the current
    sample (index ``str_n``, state ``k``, ``phi``, ``v`` carried to the exact time;
    mbm.regimes S7), smallest q first: ``(q, p)`` of the orbit to switch to, or (0, 0).
    ``scale``: S5's at this sample; ``sp_hi``: T_d; ``n_total``: the run's windows
    before this window.  Updates the fits' state of every q tested."""
    r = p[0]
    beta, omega = r.beta, r.omega
    n = r.str_n
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
            ok, tau, r.str_qrho[q], _, bound = strobe_switch(
                d3t, d3v, d2t, d2v, d1t, d1v, ct, cv, det, omega, scale, r.str_qtau1[q], r.str_qtau2[q],
                r.str_qrho[q])
            # (S6): q periods the stored re-run can take.
            nw = r.str_ring[4 * ((n - q) % STROBE_RING) + 3]
            ok = ok and n_total + 1 - nw <= CYCLE_MAX_WINDOWS // 2
            base = q * STROBE_MAX_PERIODS
            for d in range(1, q):
                # (S7): every other class within the scale of its limit, and the classes
                # d periods apart with distinct limits, for every d | q, d < q.
                b_d = r.str_qb[base + (n - d) % q]
                ok = ok and b_d <= scale
                if ok and q % d == 0:
                    _, sdt, sdv = _strobe_dev(r, n, n, d, k, phi, v)
                    sep = math.sqrt((omega * sdt) ** 2 + sdv * sdv)
                    ok = sep - bound - b_d > STROBE_DISTINCT * scale
        else:
            r.str_qrho[q] = math.nan
            # Not (yet) the linear map's deviations: this class's last bound is void.
            r.str_qb[q * STROBE_MAX_PERIODS + n % q] = math.inf
        r.str_qtau2[q] = r.str_qtau1[q]
        r.str_qtau1[q] = tau
        if bound < math.inf:
            # (S7): a tail bound covers every later sample of its class, so a class's
            # last finite one stands until its next.
            r.str_qb[q * STROBE_MAX_PERIODS + n % q] = bound
        if ok:
            return q, p0
    return 0, 0.0


# ---------------------------------------------------------------------------
# The loop
# ---------------------------------------------------------------------------


@numba.njit(cache=True)
def _lock_setup(beta, gamma, omega, can_lock, can_lock2):
    """The locked test's constants of a run (L5; |sin d| and the second-order quick
    test's q₂ where ``can_lock2``): ``(d, ω_l², G₀, G₁, |sin d|, q₂, can_lock2)``, the
    second-order form off where its quick test rules it out."""
    d, wl2, g0, g1, sd, q2 = 0.0, 1.0, 0.0, 0.0, 0.0, 0.0
    if can_lock:
        d, wl2, g0, g1 = locked_constants(beta, gamma, omega)
        sd = abs(math.sin(d))
        if can_lock2:
            q2 = locked2_quick(beta, gamma, omega, d, wl2, g0)
            can_lock2 = q2 > 0.0
    return d, wl2, g0, g1, sd, q2, can_lock2


def _cycle_watch_for(kind):
    """:func:`cycle_watch` compiled for kind ``kind`` (a constant of the closure: numba prunes
    the other kinds' kernels), called rather than inlined: inlining copies the
    callee's IR at each site, which was most of a first call's compile."""

    @numba.njit(cache=True)
    def cycle_watch(r, coef, t, t_new, y0, th, v, k, off, sec_off, sec_acc, beta, gamma, omega, t_bound,
                     rtol, atol):
        """After an ordinary window [t, t_new] from φ = ``y0`` to (``th``, ``v``): the return
        map's bookkeeping in the run record ``r`` (a crossing of θ_s + 2πm, its period and
        speed; the switch to the running cycle, ``r.regime``, once converged)."""
        # The return map (mbm.regimes, R1, R2): a crossing of a saddle level
        # θ = θ_s + 2πm in this window.
        m0 = math.floor((y0 - sec_off) / _TWO_PI)
        m1 = math.floor((th - sec_off) / _TWO_PI)
        r.sec_vmax = max(r.sec_vmax, abs(v))
        if abs(m1 - m0) == 1.0:
            sgn = 1.0 if m1 > m0 else -1.0
            level = sec_off + _TWO_PI * max(m0, m1)
            sx, vx = _crossing(kind, coef, t_new - t, y0 - level, th - level, level, sec_acc, beta,
                               omega * omega)
            tx = t + sx
            if r.sec_n > 0 and r.sec_sign == sgn:
                period = tx - r.sec_t
                dv = vx - r.sec_v
                if r.cyc_k > 0:
                    # Converged: the period averaged over CYCLE_AVERAGE_PERIODS returns (R2).
                    r.cyc_k += 1
                    if r.cyc_k > CYCLE_AVERAGE_PERIODS:
                        r.regime = REGIME_RUNNING
                        r.t_regime = t_new
                        r.cyc_T = (tx - r.cyc_t) / CYCLE_AVERAGE_PERIODS
                        r.cyc_theta, r.cyc_v, r.cyc_t, r.cyc_sign = level, vx, tx, sgn
                        r.cyc_wind = k
                elif r.sec_n >= 2 and cycle_switch(
                        dv, r.sec_dv, period - r.sec_T, vx, off + level, r.sec_vmax,
                        abs(gamma) + beta * r.sec_vmax + omega * omega, (t_bound - t_new) / period, rtol,
                        atol):
                    r.cyc_k, r.cyc_t = 1, tx
                r.sec_dv, r.sec_T = dv, period
                r.sec_n += 1
            else:
                r.sec_n, r.sec_sign, r.cyc_k = 1, sgn, 0
            r.sec_t, r.sec_v, r.sec_vmax = tx, vx, max(abs(vx), abs(v))
        elif m1 != m0:
            r.sec_n, r.cyc_k = 0, 0

    return cycle_watch


@numba.njit(cache=True)
def _libration_test(r, t, y0, y1, k, off, gamma, omega, t_bound, rtol, atol):
    """The libration test of a fresh conservative run (mbm.regimes, C1-C4): switches the
    record ``r`` to REGIME_LIBRATION where the stored period's phase error over the rest
    of the span is within the tolerance (C4)."""
    lb_hi, lb_lo, lb_dt, lb_vmax, lb_span = libration_period(gamma, omega, y0, y1)
    if lb_hi == lb_hi:
        n_rest = (t_bound - t) / lb_hi
        drift = (n_rest + 1.0) * lb_dt
        theta_min = max(0.0, abs(off + y0) - lb_span)
        if (n_rest >= LIBRATION_MIN_PERIODS
                and drift * lb_vmax <= SWITCH_SAFETY * (atol + rtol * theta_min)
                and drift * (omega * omega + abs(gamma)) <= SWITCH_SAFETY * atol):
            r.regime = REGIME_LIBRATION
            r.t_regime = t
            r.cyc_theta, r.cyc_v, r.cyc_t, r.cyc_sign, r.cyc_wind = y0, y1, t, 0.0, k
            r.cyc_T, r.cyc_Tlo = lb_hi, lb_lo


@numba.njit(cache=True)
def _strobe_setup(r, t, freq, beta, n_total):
    """The stroboscopic watch's constants of a driven run (S1-S7): ``(T_d hi, T_d lo,
    e^{−βT_d}, the next sample's time)``; a fresh run sets the samples' origin."""
    sp_hi, sp_lo = strobe_period(freq, 1.0)
    sp_det = math.exp(-beta * sp_hi)  # (S2): det DP, exactly e^{−βT_d}
    if n_total == 0:
        r.str_t0, r.str_n, r.str_m = t, 1, 0
        r.str_tau1, r.str_tau2, r.str_rho = math.nan, math.nan, math.nan
        # (S7): the maps P^q, q > 1.
        r.str_q = 1.0
        for q in range(STROBE_MAX_PERIODS + 1):
            r.str_qtau1[q], r.str_qtau2[q], r.str_qrho[q] = math.nan, math.nan, math.nan
        for q in range((STROBE_MAX_PERIODS + 1) * STROBE_MAX_PERIODS):
            r.str_qb[q] = math.inf
    sp_next = math.inf
    if r.regime == REGIME_NONE:
        sp_next = strobe_time(r.str_t0, float(r.str_n), sp_hi, sp_lo)[0]
    return sp_hi, sp_lo, sp_det, sp_next


@numba.njit(**_INLINE)
def _value_at(kind, rset, is_locked, coef, per_starts, per_ends, per_coefs, per_n, t, tj, k):
    """(φ, θ', winding count) of the window ``coef`` that started at ``t``, at time ``tj``:
    the formula of the window's source (the regime's, or the approximant's)."""
    if rset == RS_CYCLE:
        return _period_value(kind, coef, per_starts, per_ends, per_coefs, per_n, tj - t)
    if rset == RS_STROBE:
        return _strobe_value(kind, coef, tj)
    if rset == RS_DAMPED:
        if is_locked:
            a, b = locked_eval(coef, tj - t)
            return a, b, k
    a, b = evaluate(kind, coef, tj - t)
    return a, b, k


@numba.njit(cache=True)
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


# The watches, compiled once per kind that can take them and called (as the
# controllers).
_cycle_watch_taylor = _cycle_watch_for(KIND_TAYLOR)
_cycle_watch_split = _cycle_watch_for(KIND_SPLIT)


@numba.njit(**_INLINE)
def _watch_cycle(kind, r, coef, t, t_new, y0, th, v, k, off, sec_off, sec_acc, beta, gamma, omega, t_bound,
                 rtol, atol):
    """:func:`_cycle_watch` of kind ``kind`` through its compiled entry (the adaptive
    kinds; no other kind reaches the watch)."""
    if kind == KIND_TAYLOR:
        _cycle_watch_taylor(r, coef, t, t_new, y0, th, v, k, off, sec_off, sec_acc, beta, gamma, omega,
                            t_bound, rtol, atol)
    elif kind == KIND_SPLIT:
        _cycle_watch_split(r, coef, t, t_new, y0, th, v, k, off, sec_off, sec_acc, beta, gamma, omega,
                           t_bound, rtol, atol)


@numba.njit(cache=True)
def _strobe_samples_taylor(p, coef, t, t_new, k, off, sp_hi, sp_lo, sp_det, n_total):
    return _strobe_samples(KIND_TAYLOR, p, coef, t, t_new, k, off, sp_hi, sp_lo, sp_det, n_total)


@numba.njit(**_INLINE)
def _watch_strobe(kind, p, coef, t, t_new, k, off, sp_hi, sp_lo, sp_det, n_total):
    """:func:`_strobe_samples` through its compiled entry (Taylor only: the only kind
    that integrates a drive; no sample otherwise)."""
    if kind == KIND_TAYLOR:
        return _strobe_samples_taylor(p, coef, t, t_new, k, off, sp_hi, sp_lo, sp_det, n_total)
    return math.inf


def _runner(kind, rset):
    """The loop's compiled entry for kind ``kind`` and regime set ``rset`` (:func:`regime_set`).

    Both are constants of the closure, so numba prunes the other kinds' and sets'
    branches before it compiles (a first run compiles the kernels and regimes its scene
    class uses), and caches each closure apart (its constants are in the cache's key).
    The entry advances the run ``p[0]`` (a :data:`RUN` record) window by window; its
    own docstring says how.
    """

    @numba.njit(cache=True)
    def run_entry(p, t_eval, out, win_t, win_y, win_coef, cancel):
        """Advance the run ``p[0]`` (a :data:`RUN` record) window by window (kind ``kind``,
        regime set ``rset``: :func:`regime_set`).

        Stops at ``t_bound`` (status 0), at a failure (a ``STATUS_*`` code), at
        ``max_windows`` (:data:`STATUS_MAX_WINDOWS`), or paused
        (:data:`STATUS_PAUSED`) after ``call_windows`` windows, when the window store
        is full or when the record's regime set is no longer ``rset`` (a regime switch:
        the run resumes through the entry of its new set), or :data:`STATUS_INTERRUPTED`
        once ``cancel[0]`` is set (by another thread: how a batch running without the
        GIL honours Ctrl-C).  The state reached, the next window length, the window
        count and the next output index are written back to ``p[0]``, so a paused run
        resumes where it stopped.

        Long horizons (:mod:`mbm.regimes`), each compiled only into the entries of its
        set: with ``regimes`` set, before each window the state is tested for the locked
        regime (RS_DAMPED); once the bound on the neglected nonlinearity over the rest of
        the horizon is within the tolerance (L5 there), the window (to ``t_bound``, or
        ``max_step`` long) is the linearized closed form (or, where only its bound passes,
        the second-order one, L6-L7: where the window store has room for it), stored with
        coefficient layout ``regimes.LOCKED_TAG``, and ``regime``, ``t_regime`` record the
        switch.  After each window the return map of θ ≡ θ_s (mod 2π) is watched (R1, R2
        there); once it has converged for the rest of the horizon, the windows are the
        stored period shifted (RS_CYCLE: ``regimes.CYCLE_TAG``, R3), the period's windows
        re-taken once from the cycle's anchor (at the first such window of the call) and
        every output looked up in them.  A conservative run (β = 0, RS_CONSERVATIVE)
        trapped in a well is tested before its first window (C1-C4 there): with its period
        known to double-double precision, the whole run is one such window, with winding
        sign 0.

        AC drive (``drive_amp`` ≠ 0, RS_DRIVEN): each window is anchored at its start time
        by :func:`anchor_driven` (the drive's series enters the coefficients).  The locked
        and running regimes assume an autonomous equation and are not tested; instead the
        stroboscopic samples at t_s + nT_d, T_d = 2π/Ω, are watched (S1–S7 there), and once
        their deviations have converged for good the windows are the stored drive period
        from the anchor sample (RS_STROBE: ``regimes.STROBE_TAG``, S6), ``regime``
        phase-locked.

        Parameters
        ----------
        p : ndarray of RUN, shape (1,)
            The run record.
        t_eval : ndarray, shape (m,)
            Output times, monotone in the direction of integration, within the span.
        out : ndarray, shape (2, m) or (3, m)
            θ, θ' at ``t_eval``, filled from index ``p[0].j`` on: an output in
            (t, t_new] comes from that window's formula (the window end repeats the
            evaluation that produced the state).  With three rows, row 0 is θ wrapped to
            (−π, π] and row 2 its winding count (θ = 2π·row 2 + row 0).
        win_t : ndarray, shape (cap + 1,) or (0,)
            Window store (empty: none).  ``win_t[i]`` is the start of the call's window
            i, ``win_t[n]`` the end of its last.
        win_y : ndarray, shape (cap + 1, 2) or (0, 2)
            The states at ``win_t``.
        win_coef : ndarray, shape (cap, width) or (0, width)
            The windows' coefficient vectors (cut or zero-padded to ``width``; width 0
            stores none).
        cancel : ndarray of int64, shape (1,)
            Checked before each window; non-zero stops the run.

        Returns
        -------
        n : int
            Windows this call took.
        """
        r = p[0]
        karg = r.karg
        beta, gamma, omega = r.beta, r.gamma, r.omega
        amp, freq, phase = r.drive_amp, r.drive_freq, r.drive_phase
        t, y0, y1, t_bound = r.t, r.theta, r.v, r.t_bound
        h_abs, max_step, rtol, atol = r.h_abs, r.max_step, r.rtol, r.atol
        adaptive = r.controller == CONTROLLER_ADAPTIVE
        error_order = r.error_order
        log_eps = window_log_eps(rtol)
        direction = 1.0 if t_bound >= t else -1.0
        budget = r.call_windows
        store = win_t.size > 0
        cap = win_t.size - 1
        width = win_coef.shape[1]
        ne = t_eval.size
        out_theta = out[0]
        out_v = out[1]
        # Three output rows: θ wrapped to (−π, π] and its winding count in the third.
        wrapped = out.shape[0] == 3
        out_w = out[2] if wrapped else out[0]
        j = r.j
        n = 0
        n_total = r.n_windows
        status = STATUS_OK
        # The angle as θ = 2πk + φ (TWO_PI_A): y0 holds φ, k the winding count; a fresh
        # run starts from θ as given (k = 0), a resumed one where it stopped.
        wraps = kind == KIND_TAYLOR or kind == KIND_SPLIT  # WRAPPING_KINDS
        k = 0.0
        if n_total > 0:
            k, y0 = r.wind, r.phi
        if store:
            win_t[0] = t
            win_y[0, 0] = theta_of(k, y0)
            win_y[0, 1] = y1
        # Each regime's switch rule where it may apply: windows from rtol/atol, forwards,
        # room for its formula in the window store (its set's own conditions in
        # regime_set); every test depends on the record only, so a resumed run repeats it.
        may = r.regimes != 0 and adaptive and direction > 0.0
        # Locked regime (L5) where |γ| < ω², the second-order form (L6, L7) where its
        # coefficients fit the window store; the running cycle's return map (R1-R3).
        can_lock = can_lock2 = can_cycle = False
        lk_d, lk_wl2, lk_g0, lk_g1, lk_sd, lk_q2 = 0.0, 1.0, 0.0, 0.0, 0.0, 0.0
        lk_ts, lk_order = 0.0, 0
        sec_off = sec_acc = 0.0
        if rset == RS_DAMPED:
            can_lock = may and abs(gamma) < omega * omega and (width == 0 or width >= LOCKED_WIDTH)
            lk_d, lk_wl2, lk_g0, lk_g1, lk_sd, lk_q2, can_lock2 = _lock_setup(
                beta, gamma, omega, can_lock, can_lock and (width == 0 or width >= LOCKED2_WIDTH))
            can_cycle = may and (width == 0 or width >= CYCLE_WIDTH)
            sec_off = section_offset(gamma, omega) if can_cycle else 0.0
            # θ'' = sec_acc − βθ' on a section level (sin θ there is sin θ_s): _crossing.
            sec_acc = gamma - omega * omega * math.sin(sec_off)
        # Libration (C1-C4): a conservative run trapped in a well is periodic from its
        # start; tested once, before a fresh run's first window.
        can_librate = False
        if rset == RS_CONSERVATIVE:
            can_librate = (may and wraps and abs(gamma) < omega * omega and n_total == 0
                           and r.regime == REGIME_NONE and (width == 0 or width >= CYCLE_WIDTH))
        # Phase-locked to the drive (S1-S7): stroboscopic samples at t_s + nT_d watched
        # after each window (Taylor, β > 0; not with max_dtheta, the short windows of
        # solve_ivp's event search, each of which would re-take a period).
        sp_hi, sp_lo, sp_det, sp_next = 0.0, 0.0, 0.0, math.inf  # sp_next: the next sample's time
        if rset == RS_DRIVEN:
            if (may and beta > 0.0 and freq > 0.0 and kind == KIND_TAYLOR and r.max_dtheta == math.inf
                    and (width == 0 or width >= STROBE_WIDTH)):
                sp_hi, sp_lo, sp_det, sp_next = _strobe_setup(r, t, freq, beta, n_total)
        # One coefficient workspace for the call's windows (anchor).
        ws_coef, ws_scratch = taylor_workspace(karg)
        # The stored period of a cycle window (R3), built at the first one this call meets.
        per_n = -2
        per_starts = np.empty(0)
        per_ends = np.empty((0, 2))
        per_coefs = np.empty((0, 0))
        while direction * (t_bound - t) > 0.0:
            if n_total >= r.max_windows:
                status = STATUS_MAX_WINDOWS
                break
            if ((budget > 0 and n >= budget) or (store and n >= cap)
                    or regime_set(kind, r.controller, r.regimes, beta, amp, r.regime) != rset):
                status = STATUS_PAUSED
                break
            if cancel[0] != 0:
                status = STATUS_INTERRUPTED
                break
            max_step = r.max_step
            if r.max_dtheta < math.inf and y1 != 0.0:
                max_step = min(max_step, r.max_dtheta / abs(y1))
            if wraps:
                k, y0 = _reduce_phi(k, y0)
            # θ's scale for the tolerances (scipy's rtol·|θ| of the whole angle).
            off = k * _TWO_PI
            if rset == RS_CONSERVATIVE:
                if can_librate:
                    can_librate = False
                    _libration_test(r, t, y0, y1, k, off, gamma, omega, t_bound, rtol, atol)
                    if r.regime != REGIME_NONE:
                        # The rest of the run is the stored period: RS_CYCLE's entry.
                        status = STATUS_PAUSED
                        break
            is_locked = False
            ordinary = True
            k_new = k
            st, h_next = STATUS_OK, h_abs
            if rset == RS_CYCLE:
                # The rest of the run is the stored period, shifted (mbm.regimes, R3).
                ordinary = False
                coef = cycle_coef(r.cyc_theta, r.cyc_v, r.cyc_T, t - r.cyc_t, beta, gamma, omega, rtol, atol,
                                  r.cyc_sign, karg, error_order, r.cyc_wind, r.cyc_Tlo)
                t_new = _window_end(t, direction, t_bound, max_step)
                if per_n == -2:
                    per_starts, per_ends, per_coefs, per_n = _period_store(kind, coef)
                th, v, k_new = _period_value(kind, coef, per_starts, per_ends, per_coefs, per_n, t_new - t)
            elif rset == RS_STROBE:
                # The rest of the run is the stored period (q drive periods, S7) from the
                # anchor (S6); its formula takes the absolute time.
                ordinary = False
                coef = strobe_coef(r.str_phi, r.str_v, r.str_k, r.str_ta, r.str_q, r.str_p, r.str_psi, beta,
                                   gamma, omega, amp, freq, rtol, atol, karg, error_order)
                t_new = _window_end(t, direction, t_bound, max_step)
                th, v, k_new = _strobe_value(kind, coef, t_new)
            else:
                if rset == RS_DAMPED:
                    if can_lock and (r.regime == REGIME_LOCKED or not locked_quick_reject(
                            off + y0, y1, lk_d, lk_sd, lk_wl2, lk_g0, omega, rtol, atol, lk_q2)):
                        lk_order, lk_ts = locked_choice(beta, gamma, omega, y0, y1, lk_d, lk_wl2, lk_g0, lk_g1,
                                                        rtol, atol, off, can_lock2)
                        is_locked = lk_order > 0
                if is_locked:
                    # The rest of the run is the linearized closed form (mbm.regimes, L2, L5).
                    ordinary = False
                    coef = locked_coef(beta, lk_wl2, lk_ts, y0, y1, gamma, lk_order)
                    t_new = _window_end(t, direction, t_bound, max_step)
                    th, v = locked_eval(coef, t_new - t)
                    if r.regime != REGIME_LOCKED:
                        r.regime = REGIME_LOCKED
                        r.t_regime = t
                else:
                    if rset == RS_DRIVEN:
                        coef = anchor_driven(kind, karg, beta, gamma, omega, amp, freq, phase, t, y0, y1, ws_coef,
                                             ws_scratch)
                    else:
                        coef = anchor(kind, karg, beta, gamma, omega, y0, y1, ws_coef, ws_scratch)
                    if coef[0] != 0.0:
                        status = STATUS_ANCHOR
                        break
                    if adaptive:
                        if h_abs <= 0.0:
                            h_abs = _first(kind, coef, t, y0, y1, off, direction, t_bound, omega, max_step,
                                                 rtol, atol, error_order, log_eps)
                        st, t_new, th, v, h_next = _adaptive(
                            kind, coef, t, y0, y1, off, direction, t_bound, h_abs, max_step, rtol, atol,
                            error_order, log_eps)
                    else:
                        st, t_new, th, v = fixed_window(kind, coef, t, direction, t_bound, min(h_abs, max_step))
            if not ordinary and not (math.isfinite(th) and math.isfinite(v)):
                st = STATUS_NONFINITE
            if st != STATUS_OK:
                status = st
                break
            if kind == KIND_TAYLOR and ordinary:
                # The window's outputs in one call, four times at once (the same Horner
                # steps per time as evaluate, so the same bits; an output at t_new is the
                # evaluation that produced the state).
                j2 = j
                while j2 < ne and (direction * (t_eval[j2] - t_new) <= 0.0):
                    j2 += 1
                if j2 > j:
                    # (Not called for an empty range: the call alone, its arrays passed and
                    # reference-counted, cost ~25 ns of a ~400 ns window.)
                    taylor_eval_range(coef, t, t_eval, j, j2, out_theta, out_v)
                if k != 0.0 or wrapped:
                    for i in range(j, j2):
                        _put(out_theta, out_w, wrapped, i, k, out_theta[i])
                j = j2
            while j < ne and (direction * (t_eval[j] - t_new) <= 0.0):
                if t_eval[j] == t_new:
                    _put(out_theta, out_w, wrapped, j, k_new, th)
                    out_v[j] = v
                else:
                    a, b, kc = _value_at(kind, rset, is_locked, coef, per_starts, per_ends, per_coefs, per_n, t,
                                         t_eval[j], k)
                    _put(out_theta, out_w, wrapped, j, kc, a)
                    out_v[j] = b
                j += 1
            if rset == RS_DAMPED:
                if can_cycle and r.regime == REGIME_NONE:
                    _watch_cycle(kind, r, coef, t, t_new, y0, th, v, k, off, sec_off, sec_acc, beta, gamma, omega,
                                 t_bound, rtol, atol)
            if rset == RS_DRIVEN:
                if sp_next <= t_new and r.regime == REGIME_NONE:
                    # The stroboscopic samples in (t, t_new] (mbm.regimes, S1-S7).
                    sp_next = _watch_strobe(kind, p, coef, t, t_new, k, off, sp_hi, sp_lo, sp_det, n_total)
            if store:
                _store_window(win_t, win_y, win_coef, n, coef, t_new, theta_of(k_new, th), v)
            t, y0, y1, h_abs, k = t_new, th, v, h_next, k_new
            n += 1
            n_total += 1
        # A span of zero length: the outputs are the initial state.
        while j < ne and n_total == 0 and status != STATUS_PAUSED and t_eval[j] == t:
            _put(out_theta, out_w, wrapped, j, k, y0)
            out_v[j] = y1
            j += 1
        r.t, r.theta, r.v, r.h_abs = t, theta_of(k, y0), y1, h_abs
        r.phi, r.wind = y0, k
        r.n_windows = n_total
        r.j = j
        r.status = status
        return n

    return run_entry


# ---------------------------------------------------------------------------
# The entries: one per (kind, regime set), generated from RUN_TABLE
# ---------------------------------------------------------------------------

# Regime sets: which regimes an entry of the loop compiles (numba prunes the other
# sets' branches, so a scene class pays only for the regimes it can reach).
RS_PLAIN = 0  # no regime: fixed windows, regimes off, β < 0
RS_DAMPED = 1  # undriven, β > 0: the locked regime (L1-L7) and the return map's watch (R1, R2)
RS_CONSERVATIVE = 2  # undriven, β = 0: the libration test (C1-C4)
RS_DRIVEN = 3  # an AC drive: the driven anchor and the stroboscopic watch (S1-S7)
RS_CYCLE = 4  # in the running cycle or a libration: the stored period's windows (R3)
RS_STROBE = 5  # phase-locked to the drive: the stored drive period's windows (S6, S7)


@numba.njit(cache=True)
def regime_set(kind, controller, regimes, beta, amp, regime):
    """The regime set (``RS_*``) of a run record's fields: the entry that runs it.

    A run's set changes only at a regime switch (to RS_CYCLE or RS_STROBE), where the
    loop pauses so that the caller resumes it through the new set's entry.  The kinds
    without an error estimate run fixed windows and take no regime.
    """
    if kind == KIND_EXACT or kind == KIND_SALAS_TORQUE:
        return RS_DRIVEN if amp != 0.0 else RS_PLAIN
    if regime == REGIME_RUNNING or regime == REGIME_LIBRATION:
        return RS_CYCLE
    if regime == REGIME_PHASE_LOCKED and kind == KIND_TAYLOR:
        return RS_STROBE
    if amp != 0.0:
        return RS_DRIVEN
    if regimes == 0 or controller != CONTROLLER_ADAPTIVE or beta < 0.0:
        return RS_PLAIN
    return RS_DAMPED if beta > 0.0 else RS_CONSERVATIVE


#: Every (kind, regime set) the loop has an entry for: those regime_set can return.
RUN_TABLE = tuple(
    [(KIND_TAYLOR, s) for s in (RS_PLAIN, RS_DAMPED, RS_CONSERVATIVE, RS_DRIVEN, RS_CYCLE, RS_STROBE)]
    + [(KIND_SPLIT, s) for s in (RS_PLAIN, RS_DAMPED, RS_CONSERVATIVE, RS_DRIVEN, RS_CYCLE)]
    + [(kd, s) for kd in (KIND_EXACT, KIND_SALAS_TORQUE) for s in (RS_PLAIN, RS_DRIVEN)]
)


#: The loop's entry for each (kind id, regime set) of RUN_TABLE.
RUNNERS = {key: _runner(*key) for key in RUN_TABLE}
# numba calls a compiled function through a global: the table's entries as globals of
# this module for _dispatch.
(_R_T0, _R_T1, _R_T2, _R_T3, _R_T4, _R_T5, _R_S0, _R_S1, _R_S2, _R_S3, _R_S4,
 _R_E0, _R_E3, _R_Q0, _R_Q3) = (RUNNERS[key] for key in RUN_TABLE)


@numba.njit(**_INLINE)
def _dispatch(kind, rset, p, t_eval, out, win_t, win_y, win_coef, cancel):
    """The entry of (``kind``, ``rset``) called: with both constants, one call after
    pruning; an unknown pair is a status (STATUS_ANCHOR), never another entry."""
    if kind == KIND_TAYLOR:
        if rset == RS_PLAIN:
            return _R_T0(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_DAMPED:
            return _R_T1(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_CONSERVATIVE:
            return _R_T2(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_DRIVEN:
            return _R_T3(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_CYCLE:
            return _R_T4(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_STROBE:
            return _R_T5(p, t_eval, out, win_t, win_y, win_coef, cancel)
    elif kind == KIND_SPLIT:
        if rset == RS_PLAIN:
            return _R_S0(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_DAMPED:
            return _R_S1(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_CONSERVATIVE:
            return _R_S2(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_DRIVEN:
            return _R_S3(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_CYCLE:
            return _R_S4(p, t_eval, out, win_t, win_y, win_coef, cancel)
    elif kind == KIND_EXACT:
        if rset == RS_PLAIN:
            return _R_E0(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_DRIVEN:
            return _R_E3(p, t_eval, out, win_t, win_y, win_coef, cancel)
    elif kind == KIND_SALAS_TORQUE:
        if rset == RS_PLAIN:
            return _R_Q0(p, t_eval, out, win_t, win_y, win_coef, cancel)
        if rset == RS_DRIVEN:
            return _R_Q3(p, t_eval, out, win_t, win_y, win_coef, cancel)
    p[0].status = STATUS_ANCHOR
    return 0


@numba.njit(**_INLINE)
def _record_set(kind, r):
    return regime_set(kind, r.controller, r.regimes, r.beta, r.drive_amp, r.regime)


@numba.njit(**_INLINE)
def _run_chain(kind, p, t_eval, out, win_t, win_y, win_coef, cancel):
    """A run of kind ``kind`` through its regime sets' entries in turn: a pause at a
    regime switch is resumed through the new set's entry (every other stop returns)."""
    r = p[0]
    n = 0
    while True:
        rset = _record_set(kind, r)
        if rset == RS_PLAIN:
            n += _dispatch(kind, RS_PLAIN, p, t_eval, out, win_t[n:], win_y[n:], win_coef[n:], cancel)
        elif rset == RS_DAMPED:
            n += _dispatch(kind, RS_DAMPED, p, t_eval, out, win_t[n:], win_y[n:], win_coef[n:], cancel)
        elif rset == RS_CONSERVATIVE:
            n += _dispatch(kind, RS_CONSERVATIVE, p, t_eval, out, win_t[n:], win_y[n:], win_coef[n:], cancel)
        elif rset == RS_DRIVEN:
            n += _dispatch(kind, RS_DRIVEN, p, t_eval, out, win_t[n:], win_y[n:], win_coef[n:], cancel)
        elif rset == RS_CYCLE:
            n += _dispatch(kind, RS_CYCLE, p, t_eval, out, win_t[n:], win_y[n:], win_coef[n:], cancel)
        else:
            n += _dispatch(kind, RS_STROBE, p, t_eval, out, win_t[n:], win_y[n:], win_coef[n:], cancel)
        if r.status != STATUS_PAUSED or _record_set(kind, r) == rset:
            return n


# One compiled whole run per kind (every set it may reach), for the compiled callers
# (solve_njit, the batch).
@numba.njit(cache=True)
def run_taylor(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_chain` for kind ``"taylor"``; returns the windows taken."""
    return _run_chain(KIND_TAYLOR, p, t_eval, out, win_t, win_y, win_coef, cancel)


@numba.njit(cache=True)
def run_exact(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_chain` for kind ``"exact"``; returns the windows taken."""
    return _run_chain(KIND_EXACT, p, t_eval, out, win_t, win_y, win_coef, cancel)


@numba.njit(cache=True)
def run_salas_torque(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_chain` for kind ``"salas-torque"``; returns the windows taken."""
    return _run_chain(KIND_SALAS_TORQUE, p, t_eval, out, win_t, win_y, win_coef, cancel)


@numba.njit(cache=True)
def run_split(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_chain` for kind ``"split"``; returns the windows taken."""
    return _run_chain(KIND_SPLIT, p, t_eval, out, win_t, win_y, win_coef, cancel)


#: The whole-run entry of each kind id (compiled callers).
CHAINS = {KIND_TAYLOR: run_taylor, KIND_EXACT: run_exact, KIND_SALAS_TORQUE: run_salas_torque,
          KIND_SPLIT: run_split}

_regime_set = regime_set.py_func


def set_of(r):
    """The regime set of run record ``r`` (a record, or a row of a RUN array), in Python."""
    return _regime_set(int(r["kind"]), int(r["controller"]), int(r["regimes"]), float(r["beta"]),
                       float(r["drive_amp"]), int(r["regime"]))


def runner_for(r):
    """The compiled entry (:data:`RUNNERS`) that runs record ``r`` now."""
    return RUNNERS.get((int(r["kind"]), set_of(r)))


def run(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """Advance the run ``p[0]``: :func:`_run` through the entry of its kind and regime
    set (:data:`RUNNERS`), resumed through the new set's entry after a regime switch,
    so that only the sets a run reaches are compiled.  Returns the windows taken.
    """
    n = 0
    while True:
        rset = set_of(p[0])
        entry = RUNNERS.get((int(p[0]["kind"]), rset))
        if entry is None:
            p[0]["status"] = STATUS_ANCHOR
            return n
        n += entry(p, t_eval, out, win_t[n:], win_y[n:], win_coef[n:], cancel)
        if p[0]["status"] != STATUS_PAUSED or set_of(p[0]) == rset:
            return n


@numba.njit(cache=True)
def _run_any(p, t_eval, out, win_t, win_y, win_coef, cancel):
    # The kind read from the record, for a batch of mixed kinds: calls the entries.
    kind = p[0].kind
    if kind == KIND_TAYLOR:
        return run_taylor(p, t_eval, out, win_t, win_y, win_coef, cancel)
    elif kind == KIND_EXACT:
        return run_exact(p, t_eval, out, win_t, win_y, win_coef, cancel)
    elif kind == KIND_SALAS_TORQUE:
        return run_salas_torque(p, t_eval, out, win_t, win_y, win_coef, cancel)
    elif kind == KIND_SPLIT:
        return run_split(p, t_eval, out, win_t, win_y, win_coef, cancel)
    p[0].status = STATUS_ANCHOR
    return 0


# Scenes per lane group of run_batch: a group keeps its LANES lanes full from its own
# scenes, so only its last few run with idle lanes; large enough that this tail is a
# few per cent, small enough that the groups balance over the threads.
LANE_GROUP = 256
# _run_lanes names its eight coefficient rows in one tuple.
assert LANES == 8

# The lockstep state of one lane (_run_lanes): the scene, the loop's locals of _run that
# change per window, and the constants _run derives once per call.
LANE = np.dtype([
    ("scene", np.int64), ("t", np.float64), ("phi", np.float64), ("v", np.float64),
    ("h_abs", np.float64), ("wind", np.float64), ("j", np.int64), ("n_windows", np.int64),
    ("direction", np.float64), ("log_eps", np.float64), ("lk_d", np.float64), ("lk_wl2", np.float64),
    ("lk_g0", np.float64), ("lk_g1", np.float64), ("lk_sd", np.float64), ("lk_q2", np.float64),
    ("can_lock", np.int64), ("can_lock2", np.int64), ("can_cycle", np.int64), ("sec_off", np.float64),
    ("sec_acc", np.float64), ("ready", np.int64), ("h_try", np.float64), ("prior", np.float64),
    ("first", np.int64), ("t_end", np.float64),
])


@numba.njit(**_INLINE)
def lane_eligible(r):
    """Whether run record ``r`` can take lockstep windows in :func:`_run_lanes`: a fresh
    undriven Taylor run at the vector kernel's degree, adaptive, β > 0, no window budget
    and no θ-step limit (everything else runs as :func:`_run` alone)."""
    return (r.kind == KIND_TAYLOR and r.karg == SIMD_ORDER and r.controller == CONTROLLER_ADAPTIVE
            and r.drive_amp == 0.0 and r.beta > 0.0 and r.call_windows == 0 and r.max_dtheta == math.inf
            and r.n_windows == 0 and r.regime == REGIME_NONE and r.status == STATUS_OK)


@numba.njit(**_INLINE)
def _lane_start(r, i, ln, coefs, lane):
    # _run's set-up for a fresh run (the undriven Taylor branches of its can_* flags).
    ln.scene = i
    ln.t, ln.phi, ln.v, ln.h_abs, ln.wind = r.t, r.theta, r.v, r.h_abs, 0.0
    ln.j, ln.n_windows, ln.ready = r.j, 0, 0
    ln.direction = 1.0 if r.t_bound >= r.t else -1.0
    ln.log_eps = window_log_eps(r.rtol)
    beta, gamma, omega = r.beta, r.gamma, r.omega
    can_lock = r.regimes != 0 and ln.direction > 0.0 and abs(gamma) < omega * omega
    ln.lk_d, ln.lk_wl2, ln.lk_g0, ln.lk_g1, ln.lk_sd, ln.lk_q2, can_lock2 = _lock_setup(
        beta, gamma, omega, can_lock, can_lock)
    ln.can_lock, ln.can_lock2 = can_lock, can_lock2
    can_cycle = r.regimes != 0 and ln.direction > 0.0
    ln.can_cycle = can_cycle
    ln.sec_off = section_offset(gamma, omega) if can_cycle else 0.0
    ln.sec_acc = gamma - omega * omega * math.sin(ln.sec_off)
    # The header of the lane's coefficient row (taylor.py's layout; the kernel writes
    # the coefficients after it).
    coefs[lane, 0] = 0.0
    coefs[lane, 1] = SIMD_ORDER
    coefs[lane, 2] = beta
    coefs[lane, 3] = gamma
    coefs[lane, 4] = omega


@numba.njit(**_INLINE)
def _lane_hand_off(p, ln, t_eval, out, win_t, win_y, win_coef, cancel):
    # The lane's state written back as a paused run's, and the run finished by _run.
    i = ln.scene
    r = p[i]
    r.t, r.theta, r.v, r.h_abs = ln.t, theta_of(ln.wind, ln.phi), ln.v, ln.h_abs
    r.phi, r.wind = ln.phi, ln.wind
    r.n_windows = ln.n_windows
    r.j = ln.j
    ln.scene = -1
    ln.ready = 0
    run_taylor(p[i:i + 1], t_eval, out[i], win_t, win_y, win_coef, cancel)


@numba.njit(cache=True)
def _run_lanes(p, ids, t_eval, out, cancel):
    """Run the scenes ``ids`` of ``p`` (output rows ``out[ids]``), LANES at a time in lockstep.

    Each lockstep round takes one window of every lane: _run's window for an ordinary
    Taylor window (the same tests, controller and output steps, in the same order), with
    the anchors of all lanes in one call of the across-scene kernel
    (:func:`mbm.approximants.taylor_simd.taylor24_lanes`, each lane's coefficients the
    bits of the one-scene kernel).  A lane whose next window is anything else (the
    run's end, a failure, ``max_windows``, the interrupt flag, a locked or cycle
    window) hands its state to :func:`_run` as a paused run's, which finishes the
    scene, and the lane takes the next scene.  So every scene's windows, outputs and
    record are those of :func:`_run` alone.  Scenes that are not
    :func:`lane_eligible` run by :func:`_run_any`.
    """
    win_t = np.empty(0)
    win_y = np.empty((0, 2))
    win_coef = np.empty((0, 0))
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
    ne = t_eval.size
    wrapped = out.shape[1] == 3
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
                    _run_any(p[i:i + 1], t_eval, out[i], win_t, win_y, win_coef, cancel)
            if ln.scene < 0:
                continue
            r = p[ln.scene]
            # _run's tests before a window, in its order.
            t, y0, y1, k = ln.t, ln.phi, ln.v, ln.wind
            if (not (ln.direction * (r.t_bound - t) > 0.0) or ln.n_windows >= r.max_windows
                    or cancel[0] != 0 or not (math.isfinite(y0) and math.isfinite(y1))):
                _lane_hand_off(p, ln, t_eval, out, win_t, win_y, win_coef, cancel)
                continue
            k, y0 = _reduce_phi(k, y0)
            ln.wind, ln.phi = k, y0
            off = k * _TWO_PI
            if ln.can_lock != 0 and not locked_quick_reject(
                    off + y0, y1, ln.lk_d, ln.lk_sd, ln.lk_wl2, ln.lk_g0, r.omega, r.rtol, r.atol, ln.lk_q2):
                lk_order, _ = locked_choice(r.beta, r.gamma, r.omega, y0, y1, ln.lk_d, ln.lk_wl2, ln.lk_g0,
                                            ln.lk_g1, r.rtol, r.atol, off, ln.can_lock2 != 0)
                if lk_order > 0:
                    _lane_hand_off(p, ln, t_eval, out, win_t, win_y, win_coef, cancel)
                    continue
            ins[0, q] = r.beta
            ins[1, q] = r.gamma
            ins[2, q] = r.omega * r.omega
            ins[3, q] = math.sin(y0)
            ins[4, q] = math.cos(y0)
            ins[5, q] = y0
            ins[6, q] = y1
            ln.ready = 1
            live += 1
        if live == 0:
            if nxt >= ids.size:
                break
            continue
        taylor24_lanes(ins, coefs, soa)
        # adaptive_window's first try of every lane: its a-priori window (each lane's),
        # then θ, θ' at the window's end in one lane-wise Horner.
        for q in range(LANES):
            ln = lanes[q]
            hs[q] = 0.0
            if ln.ready == 0:
                continue
            r = p[ln.scene]
            coef = rows[q]
            t, y0, y1 = ln.t, ln.phi, ln.v
            off = ln.wind * _TWO_PI
            if ln.h_abs <= 0.0:
                ln.h_abs = _first_window_taylor(coef, t, y0, y1, off, ln.direction, r.t_bound, r.omega,
                                                r.max_step, r.rtol, r.atol, r.error_order, ln.log_eps)
            min_h = MIN_WINDOW_ULPS * _EPS * max(abs(t), 1e-300)
            ln.prior = prior_window(KIND_TAYLOR, coef, off + y0, y1, r.rtol, r.atol, ln.log_eps)
            ln.h_try = min(ln.h_abs, r.max_step, ln.prior)
            # A window below the floor: adaptive_window's own status (below).
            ln.first = 1 if ln.h_try >= min_h else 0
            if ln.first != 0:
                ln.t_end = _window_end(t, ln.direction, r.t_bound, ln.h_try)
                hs[q] = ln.t_end - t
        horner24_lanes(soa, hs, hv)
        for q in range(LANES):
            ln = lanes[q]
            if ln.ready == 0:
                continue
            ln.ready = 0
            i = ln.scene
            r = p[i]
            coef = rows[q]
            t, y0, y1, k = ln.t, ln.phi, ln.v, ln.wind
            off = k * _TWO_PI
            direction, t_bound, max_step = ln.direction, r.t_bound, r.max_step
            rtol, atol = r.rtol, r.atol
            accepted = False
            if ln.first != 0:
                # adaptive_window's test of its first try, in its words.
                t_new = ln.t_end
                th, v = hv[0, q], hv[1, q]
                et, ev = estimate(KIND_TAYLOR, coef, hs[q])
                err = _error_norm(et, ev, off + y0, y1, off + th, v, rtol, atol)
                fac = _accepted_factor(err, th, v, ln.prior, -1.0 / (r.error_order + 1.0), False)
                if fac > 0.0:
                    h_next = ln.h_try * fac
                    accepted = True
            if not accepted:
                # Rejected (or below the floor): adaptive_window itself, from the start.
                st, t_new, th, v, h_next = _adaptive_window_taylor(
                    coef, t, y0, y1, off, direction, t_bound, ln.h_abs, max_step, rtol, atol,
                    r.error_order, ln.log_eps)
                if st != STATUS_OK:
                    _lane_hand_off(p, ln, t_eval, out, win_t, win_y, win_coef, cancel)
                    continue
            # The window's outputs, as _run's Taylor branch (the views of out made only
            # for a window that has outputs).
            j = ln.j
            j2 = j
            while j2 < ne and (direction * (t_eval[j2] - t_new) <= 0.0):
                j2 += 1
            if j2 > j:
                out_theta = out[i, 0]
                out_v = out[i, 1]
                out_w = out[i, 2] if wrapped else out_theta
                taylor_eval_range(coef, t, t_eval, j, j2, out_theta, out_v)
                if k != 0.0 or wrapped:
                    for jj in range(j, j2):
                        _put(out_theta, out_w, wrapped, jj, k, out_theta[jj])
            ln.j = j2
            if ln.can_cycle != 0 and r.regime == REGIME_NONE:
                _cycle_watch_taylor(r, coef, t, t_new, y0, th, v, k, off, ln.sec_off, ln.sec_acc,
                                    r.beta, r.gamma, r.omega, t_bound, rtol, atol)
            ln.t, ln.phi, ln.v, ln.h_abs = t_new, th, v, h_next
            ln.n_windows += 1
            if r.regime != REGIME_NONE:
                _lane_hand_off(p, ln, t_eval, out, win_t, win_y, win_coef, cancel)
    return 0


@numba.njit(cache=True, parallel=True, nogil=True)
def run_batch(p, t_eval, out, order, cancel):
    """:func:`run` for every row of ``p`` in parallel (``prange``), in the order ``order``.

    ``order`` is cut into groups of LANE_GROUP scenes, run in parallel; each group by
    :func:`_run_lanes` (LANES scenes in lockstep, every scene's result that of
    :func:`run` alone).  ``out`` has shape (N, 2, m), or (N, 3, m) for θ wrapped with
    its winding count.  Runs without the GIL, so a caller may run it in a thread and
    set ``cancel[0]`` to stop every scene at its next window.
    """
    n_groups = (order.size + LANE_GROUP - 1) // LANE_GROUP
    for g in numba.prange(n_groups):
        _run_lanes(p, order[g * LANE_GROUP:min((g + 1) * LANE_GROUP, order.size)], t_eval, out, cancel)


@numba.njit(**_INLINE)
def _evaluate_windows(kind, starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    """Evaluate a run of ``n`` stored windows (``win_t``, ``win_y``, ``win_coef`` of :func:`run`) at ``t``.

    Window i covers [starts[i], starts[i+1]]; a time on an interior boundary takes the
    later window (whose anchor is the earlier window's end value), the run's end the
    last window.  Times outside the run are extrapolated by the nearest window.  A
    window of a wrapping kind is anchored at φ (TWO_PI_A); its winding count is
    recovered from its start's θ, ``start_theta[i]`` (``win_y[i, 0]``), so the value
    is the run's own θ = 2πk + φ to the bit.
    """
    # The stored period of the cycle windows met (R3): built once (they share it).
    per_n = -2
    per_starts = np.empty(0)
    per_ends = np.empty((0, 2))
    per_coefs = np.empty((0, 0))
    for j in range(t.size):
        tj = t[j]
        # The last window whose start is not after tj (bisection: windows_per_step=None
        # stores a whole run).
        lo, hi = 0, n - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if direction * (tj - starts[mid]) >= 0.0:
                lo = mid
            else:
                hi = mid - 1
        i = lo
        s = tj - starts[i]
        if coefs.shape[1] >= STROBE_WIDTH and coefs[i, 0] == STROBE_TAG:
            # A phase-locked window: the stored drive period from its anchor, at the
            # absolute time (S6; at most a period of windows).
            a, b, kc = _strobe_value(kind, coefs[i], tj)
            out_theta[j] = theta_of(kc, a)
            out_v[j] = b
            continue
        if (kind == KIND_TAYLOR or kind == KIND_SPLIT) and coefs.shape[1] >= CYCLE_WIDTH \
                and coefs[i, 0] == CYCLE_TAG:
            # A cycle window: the stored period, shifted.
            if per_n == -2:
                per_starts, per_ends, per_coefs, per_n = _period_store(kind, coefs[i])
            a, b, kc = _period_value(kind, coefs[i], per_starts, per_ends, per_coefs, per_n, s)
            out_theta[j] = theta_of(kc, a)
            out_v[j] = b
            continue
        if coefs.shape[1] >= LOCKED_WIDTH and coefs[i, 0] == LOCKED_TAG:
            # A locked window (mbm.regimes): the closed form, cheap at any t.
            a, b = locked_eval(coefs[i], s)
            phi0 = coefs[i, 1]
        else:
            a, b = evaluate(kind, coefs[i], s)
            phi0 = evaluate(kind, coefs[i], 0.0)[0]
        ki = 0.0
        if kind == KIND_TAYLOR or kind == KIND_SPLIT:  # WRAPPING_KINDS
            ki = float(round((start_theta[i] - phi0) / _TWO_PI))
        out_theta[j] = theta_of(ki, a)
        out_v[j] = b


@numba.njit(cache=True)
def _evaluate_windows_taylor(starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    _evaluate_windows(KIND_TAYLOR, starts, start_theta, coefs, n, direction, t, out_theta, out_v)


@numba.njit(cache=True)
def _evaluate_windows_exact(starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    _evaluate_windows(KIND_EXACT, starts, start_theta, coefs, n, direction, t, out_theta, out_v)


@numba.njit(cache=True)
def _evaluate_windows_salas_torque(starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    _evaluate_windows(KIND_SALAS_TORQUE, starts, start_theta, coefs, n, direction, t, out_theta, out_v)


@numba.njit(cache=True)
def _evaluate_windows_split(starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    _evaluate_windows(KIND_SPLIT, starts, start_theta, coefs, n, direction, t, out_theta, out_v)


_EVALUATORS = {KIND_TAYLOR: _evaluate_windows_taylor, KIND_EXACT: _evaluate_windows_exact,
               KIND_SALAS_TORQUE: _evaluate_windows_salas_torque, KIND_SPLIT: _evaluate_windows_split}


def evaluate_windows(kind, starts, start_theta, coefs, n, direction, t, out_theta, out_v):
    """Evaluate ``n`` stored windows (``win_t``, ``win_y[:, 0]``, ``win_coef`` of :func:`run`)
    of kind ``kind`` at times ``t`` (see :func:`_evaluate_windows`)."""
    _EVALUATORS[kind](starts, start_theta, coefs, n, direction, t, out_theta, out_v)
