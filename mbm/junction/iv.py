r"""Josephson-junction tools: the I–V curve of the RCSJ model, with hysteresis.

In reduced units the resistively and capacitively shunted junction is the damped,
torqued pendulum θ'' + βθ' + ω² sin θ = γ: θ is the phase difference, θ' the voltage
(in units of ω_p Φ₀/2π with time in units of 1/ω_p and ω = 1), γ = I/I_c the bias
current and β = 1/√β_c the damping (β_c the Stewart–McCumber parameter).  The dc
voltage is the mean velocity ⟨θ'⟩.

:func:`iv_curve` visits the bias points in the order given, each starting from the
state where the previous one ended (so an up-and-down sweep shows the hysteresis),
and classifies the motion it settles to:

* **locked** (zero voltage): at rest at a stable equilibrium θ* = arcsin(γ/ω²) + 2πk,
  ⟨θ'⟩ = 0;
* **running**: on the running limit cycle θ(t + T_c) = θ(t) ± 2π, and ⟨θ'⟩ = ±2π/T_c
  exactly, T_c the time between two successive passages through θ ≡ θ_s (mod 2π),
  located on the windows' own formulas (the dense output of :class:`mbm.MBM`) after
  the cycle has converged (two successive periods agreeing to :data:`PERIOD_RTOL`).

Between two visited points of different regimes the transition current is located by
bisection, each probe started from the settled state of the point before the
transition (an adiabatic sweep), to ``current_tol``: going from locked to running is
the switching current (ω² for any β: where the equilibrium disappears), from running
to locked the retrapping current (≈ 4β/π·ω² for small β, Melnikov's energy balance).

AC drive and Shapiro steps: with ``drive_amplitude=A, drive_frequency=Ω`` the bias is
γ + A sin(Ωt + φ) (a microwave current), integrated by the Taylor kind with the drive's
series (:class:`mbm.Pendulum`).  A driven run has no running cycle of its own to time
(the equation is not autonomous).  Where a run reaches the phase-locked regime
(:mod:`mbm.regimes` S1–S7: it has converged to a periodic orbit of the stroboscopic
map, θ(t + qT_d) = θ(t) + 2πp, T_d = 2π/Ω, q ≤ STROBE_MAX_PERIODS drive periods),
⟨θ'⟩ = (p/q)Ω exactly.  Elsewhere ⟨θ'⟩ is measured over
whole drive periods on the stroboscopic samples θ_k = θ(kT_d): after a
settling time of :data:`DRIVE_SETTLE_DECAYS` decay times (a whole number of drive
periods), blocks of M = :data:`DRIVE_AVERAGE_PERIODS` drive periods are measured, each
by the weighted Birkhoff average of the increments,

    ⟨θ'⟩ ≈ Σ_k w_k (θ_{k+1} − θ_k) / T_d,   w_k ∝ exp(−1/(x_k(1 − x_k))),  x_k = (k + ½)/M,
    Σ_k w_k = 1

(Das & Yorke 2018, "Super convergence of ergodic averages for quasiperiodic orbits"),
until two successive blocks agree to :data:`DRIVE_VELOCITY_TOL` (else the weighted
average over all :data:`DRIVE_MAX_BLOCKS` blocks measured is reported).  On a Shapiro
step the motion is locked to the drive, θ(t + qT_d) = θ(t) + 2πp for a periodic orbit
of the stroboscopic map: the increments repeat with period q and the average is
(p/q)·Ω to the run's round-off once the transient has decayed (the smooth weights also
damp what is left of it at the block's start).  Between the steps (quasi-periodic
motion) the weighted average converges faster than any power of 1/M, where the plain
mean (θ_M − θ_0)/(M·T_d) converges like 1/M (measured at β = 2, Ω = A = 1, γ = 2.45,
blocks of 240 periods: successive blocks agree to 1e-8 weighted, 2e-3 plain), but
a slowly attracting motion between steps may not have settled within the blocks
(β = 2, Ω = A = 1, γ = 1.9: 1e-6 off a 4000-period reference; 6e-11 at γ = 2.45); on
chaotic motion neither average converges, and the value is an average over the blocks
measured: such a point is not settled (``IVCurve.converged`` False, and
:func:`iv_curve` warns, naming its γ).  A driven point is "phase-locked" on a Shapiro step p/q, the
zero-voltage step p = 0 included (where a run reached the phase-locked regime, or a
converged block's increments repeat with period q, :data:`DRIVE_REPEAT_TOL`; ``period``
q·2π/Ω), as :func:`mbm.solve` labels it; else "locked" when its phase gains less than π
over the last block (a zero-voltage point whose orbit was not identified), else
"running".  The zero-voltage step (p = 0) is on the locked side of the switching and
retrapping currents, every other step on the running side.

Differential resistance (``iv_curve(..., differential=True)``): on a running cycle
⟨θ'⟩ = ±2π/T_c, so d⟨θ'⟩/dγ = ∓2π/T_c² · dT_c/dγ, and dT_c/dγ is the period's
sensitivity.  From the point's settled state y* (on the cycle) one run of one period
with the sensitivities to θ₀, v₀ and γ (:func:`mbm.solve`, ``sensitivities``) gives the
monodromy matrix Φ = ∂y(T_c)/∂y*, s = ∂y(T_c)/∂γ and f = y'(T_c); the cycle's return to
the section θ = θ*, y(T_c(γ); (θ*, v*(γ)), γ) = (θ* ± 2π, v*(γ)), differentiated in γ,

    f₀ T_c' + Φ₀₁ v*' = −s₀,   f₁ T_c' + (Φ₁₁ − 1) v*' = −s₁,

a 2×2 system, regular on a running cycle (f₀ = θ' ≠ 0 and the cycle's other Floquet
multiplier is e^{−βT_c} < 1).  A locked point's voltage is 0 over a neighbourhood of its
γ on its branch, so d⟨θ'⟩/dγ = 0 there, and so on a Shapiro step (the locked orbit
persists, ⟨θ'⟩ = (p/q)Ω); a driven point off the steps has no cycle to time: NaN.

What is not modelled: thermal noise (no premature switching), non-sinusoidal
current–phase relations, arrays of junctions, a capacitance that depends on the
voltage.
"""

import math
import warnings

import numpy as np

from ..validate import (check_drive, check_positive, check_real, check_real_array, check_rule, check_rule_array,
                        check_state, keywords_named)
from .progress import progress_bar
from ..model import Pendulum
from ..regimes import REGIME_NAMES, REGIME_PHASE_LOCKED, STROBE_MAX_PERIODS
from .iv_result import DRIVE_VELOCITY_TOL, IVCurve, IVCurveSI

__all__ = ["iv_curve", "IVCurve", "IVCurveSI", "mean_velocity", "driven_mean_velocity", "integrate_mbm", "LOCKED",
           "RUNNING"]

LOCKED = "locked"
RUNNING = "running"
# The regime name of mbm.regimes's phase-locked runs (a result's ``regime``).
PHASE_LOCKED = REGIME_NAMES[REGIME_PHASE_LOCKED]

# Settling before a point is classified, in units of the slowest decay time 1/λ of the
# locked state's linearization (λ = β/2 underdamped, β/2 − √(β²/4 − ω_l²) overdamped):
# e^{−30} ≈ 1e-13 of the transient is left, below the tolerances used here.
SETTLE_DECAYS = 30.0
# ... but never less than this many small-oscillation periods 2π/ω, nor more than this
# time in units of 1/ω (near the switching current λ → 0: the point then continues in
# measured chunks, see MAX_CHUNKS; a chunk grows up to it for slow cycles: 5e-5 past
# the saddle-node of β = 2 the period is ~900).
SETTLE_MIN_PERIODS = 4.0
SETTLE_MAX_TIME = 2.0e4
# A state within this distance of a stable equilibrium (|θ − θ*| + |θ'|/ω_l, relative
# to ω-units) after settling is locked: the linearization's energy only decays there.
LOCK_DISTANCE = 1e-6
# Without a revolution over a whole chunk, a state this close to an equilibrium and
# closing in is locked (the saddle-node γ = ω² is approached algebraically, ~1/t).
LOCK_NEAR = 0.05
# Two successive cycle periods agreeing to this relative difference: the cycle has
# converged (a decaying transient changes the period by far more per revolution: 1e-3
# at 1e-4 below the retrapping current).  The runs' own noise in a period is 1e-12 on
# ordinary cycles and up to 4e-9 within 1e-4 of the retrapping current (β = 0.2),
# where the cycle passes the saddle so closely that a passage time amplifies the error.
PERIOD_RTOL = 1e-8
# Chunks of settling a point may take before it is reported undecided (a state that
# neither locks nor converges to a cycle: near a bifurcation or with β tiny).
MAX_CHUNKS = 40
# MBM's tolerances for the runs (the mean velocity is good to ~1e-12 at these).
RUN_RTOL = 1e-11
RUN_ATOL = 1e-11
# Passage times are located to this relative accuracy on the windows' formulas.
PASSAGE_XTOL = 1e-14
# AC drive (module docstring): settling before the mean is measured, in decay times
# 1/λ with λ = min(β/2, ω²/β) (the underdamped transient decays like e^{−βt/2}, the
# overdamped phase relaxes at ~ω²/β), rounded up to whole drive periods and at least
# DRIVE_SETTLE_MIN_PERIODS of them; e^{−30} ≈ 1e-13 of a transient of that rate is left
# (slower near a step's edge, where the locked orbit is born and λ → 0).
DRIVE_SETTLE_DECAYS = 30.0
DRIVE_SETTLE_MIN_PERIODS = 4
# Drive periods per measurement block (the weighted average's M).  At 120 the blocks'
# averages agreed to 3e-12 on the n = 1 step of β = 2, Ω = A = 1 and to 3e-6 between
# steps (γ = 2.45); the plain mean of a block was off by 2e-6 and 2e-3 there.
DRIVE_AVERAGE_PERIODS = 120
# iv_curve warns where |γ| passes this many times ω² (+ the drive's A): an I–V curve's
# features lie within a few ω² (switching at ω², steps a few A wide), and 10× is where a
# current typed in µA or mA for a junction of I_c ~ 1 µA or 1 mA lands.
IMPLAUSIBLE_BIAS = 10.0
# Blocks measured before the weighted average over all of them is reported unconverged
# (between steps: quasi-periodic or chaotic motion).
DRIVE_MAX_BLOCKS = 4
# A converged block whose stroboscopic increments repeat with period q ≤
# STROBE_MAX_PERIODS to this (radians) over its second half is on a Shapiro step p/q,
# as the phase-locked regime would have found (a quasi-periodic motion's increments
# never repeat; a locked orbit's do to the run's round-off once the transient decayed).
DRIVE_REPEAT_TOL = 1e-7




def _settle_time(beta, gamma, omega):
    # The slowest decay time of the locked linearization (or the cycle's 1/β).
    s = gamma / omega**2
    wl2 = omega**2 * math.sqrt(max(1.0 - s * s, 0.0))
    disc = 0.25 * beta * beta - wl2
    rate = 0.5 * beta - math.sqrt(disc) if disc > 0.0 else 0.5 * beta
    t = SETTLE_DECAYS / max(rate, 1e-300)
    return min(max(t, SETTLE_MIN_PERIODS * 2.0 * math.pi / omega), SETTLE_MAX_TIME / omega)


def _lock_distance(model, y):
    # Distance to the nearest stable equilibrium, or inf when there is none.
    d = model.equilibrium
    if d is None:
        return math.inf
    k = round((y[0] - d) / (2.0 * math.pi))
    wl = model.omega * math.sqrt(max(math.cos(d), 1e-300))
    return abs(y[0] - d - 2.0 * math.pi * k) + abs(y[1]) / wl


def _fast_angle(model):
    # The bottom of the tilted potential, arcsin(γ/ω²) (±π/2 past the critical
    # current): where the running cycle moves fastest.
    s = model.gamma / model.omega**2
    return math.asin(max(-1.0, min(1.0, s)))


def integrate_mbm(model, y, span):
    """The runs behind :func:`iv_curve`: ``solve_ivp(method=mbm.MBM)`` over (0, span)
    from ``y`` with dense output (the windows' formulas), all windows in one step.

    Parameters
    ----------
    model : Pendulum
        The junction at one bias point.
    y : array_like, shape (2,)
        The initial state at t = 0.
    span : float
        The end time.

    Returns
    -------
    scipy.integrate OdeResult
        solve_ivp's result; it also carries ``regime``, ``mean_velocity`` and ``period``, the
        solver's (the long-horizon regime the run reached, :mod:`mbm.regimes`).

    Raises
    ------
    RuntimeError
        If the run fails (its message names γ).
    """
    from scipy.integrate import solve_ivp

    from ..frontends.ivp import MBM

    solvers = []

    class _Recorded(MBM):
        # The solver itself, for the regime it reached (solve_ivp returns no method).
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            solvers.append(self)

    sol = solve_ivp(model, (0.0, span), y, method=_Recorded, rtol=RUN_RTOL, atol=RUN_ATOL,
                    windows_per_step=None, dense_output=True, model=model)
    if not sol.success:
        raise RuntimeError(f"gamma={model.gamma!r}: {sol.message}")
    # The long-horizon regime reached (mbm.regimes), as mbm.MBM records it.
    sol.regime, sol.mean_velocity = solvers[0].regime, solvers[0].mean_velocity
    sol.period = solvers[0].period
    return sol


def _running_slope(model, y, period):
    # d⟨θ'⟩/dγ on the running cycle through y (period T_c) from the period's
    # sensitivity (module docstring): one period with ∂/∂(θ₀, v₀, γ), then the 2×2 system.
    from ..frontends.solve import solve

    r = solve(model, (0.0, period), y, t_eval=[period], rtol=RUN_RTOL, atol=RUN_ATOL,
              sensitivities=("theta0", "v0", "gamma"))
    if not r.success:
        raise RuntimeError(f"gamma={model.gamma!r}: {r.message}")
    p = r.sensitivities[:, :, -1]  # p[j, i] = ∂y_i(T_c)/∂(θ₀, v₀, γ)_j
    v, accel = model(r.t[-1], r.y[:, -1])  # f = y'(T_c)
    a = np.array([[v, p[1, 0]], [accel, p[1, 1] - 1.0]])
    dperiod = np.linalg.solve(a, -p[2])[0]
    return -math.copysign(2.0 * math.pi, v) * dperiod / (period * period)


def _passages(sol, theta_s, direction, count):
    """The first ``count`` times where θ passes θ_s + direction·2πk (k = 0, 1, ...) after
    the start, located on the windows' formulas (the dense output)."""
    from scipy.optimize import brentq

    t = sol.t
    th0 = sol.y[0, 0]
    # the first target strictly ahead of the start
    k0 = math.floor(direction * (th0 - theta_s) / (2.0 * math.pi)) + 1
    ahead = direction * (sol.y[0] - theta_s)
    out = []
    for k in range(k0, k0 + count):
        reached = np.flatnonzero(ahead >= 2.0 * math.pi * k)
        if reached.size == 0 or reached[0] == 0:
            break
        i = reached[0]
        target = theta_s + direction * 2.0 * math.pi * k
        out.append(brentq(lambda s: sol.sol(s)[0] - target, t[i - 1], t[i],
                          xtol=PASSAGE_XTOL * max(1.0, t[i]), rtol=4 * np.finfo(float).eps))
    return out


def mean_velocity(model, y0, integrate=integrate_mbm):
    """The motion a state settles to under ``model``: regime, ⟨θ'⟩, period, settled state.

    Parameters
    ----------
    model : Pendulum
        β > 0.
    y0 : array_like, shape (2,)
    integrate : callable, optional
        ``integrate(model, y, span)`` returning a ``solve_ivp`` result with dense
        output over (0, span); default :func:`integrate_mbm` (another integrator may be
        put in to compare, as the junction benchmark does).

    Returns
    -------
    regime : str
        ``"locked"`` or ``"running"``.
    mean_velocity : float
        0 when locked; ±2π/T_c on the running cycle.
    period : float
        T_c (NaN when locked).
    y : ndarray, shape (2,)
        The settled state (θ reduced to (−π, π]).

    Raises
    ------
    RuntimeError
        If the state neither locks nor converges to a cycle within :data:`MAX_CHUNKS`
        settling chunks (undriven).

    Notes
    -----
    A driven model (``model.driven``): ⟨θ'⟩ over whole drive periods, see
    :func:`driven_mean_velocity` (``period`` q·2π/Ω on a Shapiro step p/q, else NaN).
    """
    return _measure(model, y0, integrate)[:4]


def _measure(model, y0, integrate=integrate_mbm, velocity_tol=DRIVE_VELOCITY_TOL):
    # mean_velocity's (regime, ⟨θ'⟩, period, y), whether the point settled and whether
    # its voltage state was steady (_driven_measure; an undriven point that does not
    # settle raises).
    if model.driven:
        return _driven_measure(model, y0, integrate, velocity_tol)
    return _settle(model, y0, integrate) + (True, True)


def _settle(model, y0, integrate):
    # mean_velocity of an undriven model.
    y = np.array(y0, dtype=float)
    span = _settle_time(model.beta, model.gamma, model.omega)
    for _ in range(MAX_CHUNKS):
        sol = integrate(model, y, span)
        y = sol.y[:, -1].copy()
        y[0] = math.remainder(y[0], 2.0 * math.pi)
        before = _lock_distance(model, y)
        if before <= LOCK_DISTANCE:
            return LOCKED, 0.0, math.nan, y
        direction = 1.0 if y[1] > 0.0 else -1.0
        # Passages through θ ≡ arcsin(γ/ω²) where the cycle is fastest: the time of a
        # passage is least sensitive to the state's error there.
        probe = integrate(model, y, span)
        times = _passages(probe, _fast_angle(model), direction, 3)
        if len(times) == 3:
            p1, p2 = times[1] - times[0], times[2] - times[1]
            if abs(p2 - p1) <= PERIOD_RTOL * p2:
                y = probe.y[:, -1].copy()
                y[0] = math.remainder(y[0], 2.0 * math.pi)
                period = 0.5 * (times[2] - times[0])  # two periods: half the noise of one
                return RUNNING, direction * 2.0 * math.pi / period, period, y
        else:
            if not times:
                # No revolution over a whole chunk: still closing in on an equilibrium
                # (slowly at the saddle-node γ = ω², algebraically) is locked.
                end = probe.y[:, -1].copy()
                end[0] = math.remainder(end[0], 2.0 * math.pi)
                if _lock_distance(model, end) < min(before, LOCK_NEAR):
                    return LOCKED, 0.0, math.nan, end
            # Fewer than three passages: a slow cycle (just past the saddle-node, where
            # the period grows like (γ − ω²)^{-1/2}) gets a longer chunk.
            span = min(2.0 * span, SETTLE_MAX_TIME / model.omega)
        y = probe.y[:, -1].copy()
        y[0] = math.remainder(y[0], 2.0 * math.pi)
    raise RuntimeError(
        f"gamma={model.gamma!r}, beta={model.beta!r}: the state neither locks nor converges to a "
        f"running cycle within {MAX_CHUNKS} settling chunks (near a bifurcation?)"
    )


def _drive_settle_periods(model):
    # Whole drive periods of settling (DRIVE_SETTLE_DECAYS decay times).
    beta, w2 = model.beta, model.omega**2
    rate = min(0.5 * beta, w2 / beta)
    periods = DRIVE_SETTLE_DECAYS / rate * model.drive_frequency / (2.0 * math.pi)
    return max(DRIVE_SETTLE_MIN_PERIODS, math.ceil(periods))


def _birkhoff_weights(m):
    # The weights w_k of the module docstring's weighted average (Σ w_k = 1).
    x = (np.arange(m) + 0.5) / m
    w = np.exp(-1.0 / (x * (1.0 - x)))
    return w / w.sum()


def driven_mean_velocity(model, y0, integrate=integrate_mbm, velocity_tol=DRIVE_VELOCITY_TOL):
    """⟨θ'⟩ of a driven model (β > 0, Ω > 0) over whole drive periods, from ``y0`` at t = 0.

    Settles over whole drive periods (:data:`DRIVE_SETTLE_DECAYS` decay times), then
    measures blocks of :data:`DRIVE_AVERAGE_PERIODS` drive periods T_d = 2π/Ω, each by
    the weighted average of its stroboscopic increments θ((k+1)T_d) − θ(kT_d) (module
    docstring; the samples from the run's dense output), until two successive blocks
    agree to ``velocity_tol`` (at most :data:`DRIVE_MAX_BLOCKS` blocks; then
    the weighted average over all of them).  Every run of ``integrate`` spans whole
    drive periods from t = 0, so the drive's phase at each run's start is φ, as in one
    continued run.  Where a run reports the phase-locked regime (its result's
    ``regime``, :mod:`mbm.regimes` S1–S7), ⟨θ'⟩ is its ``mean_velocity``, (p/q)Ω exactly,
    and no more blocks are measured.

    Parameters
    ----------
    model : Pendulum
        A driven model (β > 0, Ω > 0).
    y0 : array_like, shape (2,)
        The state at t = 0.
    integrate : callable, optional
        ``integrate(model, y, span)`` returning a dense ``solve_ivp`` result over
        (0, span), as in :func:`mean_velocity`; default :func:`integrate_mbm`.
    velocity_tol : float, optional
        Two successive blocks agreeing to this (absolute, in units of ω) have converged
        (default :data:`DRIVE_VELOCITY_TOL`).

    Returns
    -------
    regime : str
        ``"phase-locked"`` on a Shapiro step p/q, p = 0 included (a run reached the
        phase-locked regime, as :func:`mbm.solve` labels it, or a converged block's
        increments repeat); else ``"locked"`` when θ gains less than π over the last
        block, else ``"running"``.
    mean_velocity : float
        ⟨θ'⟩: (p/q)Ω where a run reached the phase-locked regime, else the last block's
        when converged, else over all blocks measured.
    period : float
        The locked orbit's period q·2π/Ω on a Shapiro step; NaN elsewhere (no cycle
        is timed).
    y : ndarray, shape (2,)
        The state at the end, after a whole number of drive periods (θ reduced to
        (−π, π]).

    Notes
    -----
    Whether the average converged (:attr:`IVCurve.converged`) is recorded by
    :func:`iv_curve`.
    """
    return _driven_measure(model, y0, integrate, velocity_tol)[:4]


def _driven_measure(model, y0, integrate, velocity_tol):
    # driven_mean_velocity's (regime, ⟨θ'⟩, period, y), whether it converged (two blocks'
    # averages agreed to velocity_tol) and whether it was steady (every block measured in
    # the voltage state of the last: no transient or intermittent slips within them).
    period_d = 2.0 * math.pi / model.drive_frequency
    y = np.array(y0, dtype=float)
    sol = integrate(model, y, _drive_settle_periods(model) * period_d)
    y = sol.y[:, -1].copy()
    y[0] = math.remainder(y[0], 2.0 * math.pi)
    if getattr(sol, "regime", None) == PHASE_LOCKED:
        return _phase_locked(sol, y) + (True, True)
    m = DRIVE_AVERAGE_PERIODS
    weights = _birkhoff_weights(m)
    samples = np.arange(m + 1) * period_d
    means, steps = [], []
    for _ in range(DRIVE_MAX_BLOCKS):
        sol = integrate(model, y, m * period_d)
        theta = sol.sol(samples)[0]
        theta[-1] = sol.y[0, -1]  # the run's end, as the next block starts from it
        d = np.diff(theta)
        steps.append(d)
        means.append(float(np.dot(weights, d)) / period_d)
        y = sol.y[:, -1].copy()
        y[0] = math.remainder(y[0], 2.0 * math.pi)
        if getattr(sol, "regime", None) == PHASE_LOCKED:
            return _phase_locked(sol, y) + (True, True)
        if len(means) >= 2 and abs(means[-1] - means[-2]) <= velocity_tol * model.omega:
            v, converged = means[-1], True
            step = _repeating(d)
            if step is not None:
                return PHASE_LOCKED, v, step[1] * period_d, y, True, True
            break
    else:
        d = np.concatenate(steps)
        v, converged = float(np.dot(_birkhoff_weights(d.size), d)) / period_d, False
    # The voltage state of each block: a slip (θ gains π or more) or none; the run's is its last block's.
    slips = [abs(float(np.sum(b))) >= math.pi for b in steps]
    regime = RUNNING if slips[-1] else LOCKED
    return regime, v, math.nan, y, converged, all(x == slips[-1] for x in slips)


def _repeating(d):
    # (p, q) when the increments' second half repeats with period q (smallest first).
    tail = d[d.size // 2:]
    for q in range(1, STROBE_MAX_PERIODS + 1):
        if np.max(np.abs(tail[q:] - tail[:-q])) <= DRIVE_REPEAT_TOL:
            return round(float(np.sum(tail[:q])) / (2.0 * math.pi)), q
    return None


def _phase_locked(sol, y):
    # A run that reached the phase-locked regime: ⟨θ'⟩ = (p/q)Ω exactly and the orbit's
    # period q·2π/Ω (the solver's, as mbm.solve reports them and labels it), the
    # zero-voltage step p = 0 included.
    return PHASE_LOCKED, float(sol.mean_velocity), float(getattr(sol, "period", math.nan)), y


def _voltage_state(regime, v, drive_frequency):
    # The side of a transition a regime is on: a Shapiro step p/q ≠ 0 carries a voltage
    # |v| ≥ Ω/q ≥ Ω/STROBE_MAX_PERIODS, the zero-voltage step (p = 0) none.
    if regime == PHASE_LOCKED:
        return LOCKED if abs(v) < 0.5 * drive_frequency / STROBE_MAX_PERIODS else RUNNING
    return regime


@keywords_named
def iv_curve(beta, gamma, *, omega=1.0, current_tol=1e-4, theta0=0.0, theta_dot0=0.0,
             integrate=integrate_mbm, drive_amplitude=0.0, drive_frequency=0.0, drive_phase=0.0,
             velocity_tol=DRIVE_VELOCITY_TOL, progress=False, differential=False):
    """The I–V curve of the RCSJ junction over the bias points ``gamma``, in the order given.

    Parameters
    ----------
    beta : float
        Damping β > 0 (hysteretic for small β, overdamped for large).
    gamma : array_like
        Bias points in the order visited, e.g. an up-and-down sweep
        ``np.r_[np.linspace(0, 1.5, 151), np.linspace(1.5, 0, 151)]``.
    omega : float, optional
        ω > 0 (1 in the junction's reduced units).
    current_tol : float, optional
        Width to which the switching and retrapping currents are bisected.
    theta0, theta_dot0 : float, optional
        The state the first point starts from.
    integrate : callable, optional
        The runs' integrator (see :func:`mean_velocity`); default MBM.
    drive_amplitude, drive_frequency, drive_phase : float, optional
        An AC drive A sin(Ωt + φ) added to every bias point (default A = 0: none; a
        drive needs Ω > 0).  ⟨θ'⟩ is then measured over whole drive periods
        (:func:`driven_mean_velocity`): the Shapiro steps ⟨θ'⟩ = nΩ.
    velocity_tol : float, optional
        With a drive: two successive blocks of a point agreeing to this (absolute, in
        units of ω) have settled (default :data:`DRIVE_VELOCITY_TOL`).
    progress : bool, optional
        A progress bar over the bias points (default False): a widget in a notebook,
        else a line on stderr (``tqdm.auto``), terminal or not.
    differential : bool, optional
        Also compute d⟨θ'⟩/dγ at each point (``IVCurve.dvoltage_dgamma``, module
        docstring): one more :func:`mbm.solve` of one period per running point.

    Returns
    -------
    IVCurve
        ``converged`` says which points settled.

    Warns
    -----
    RuntimeWarning
        When abs(γ) passes IMPLAUSIBLE_BIAS (10) times ω² + A: γ is the reduced bias I/I_c,
        and a current typed in µA or mA lands there (:class:`mbm.Junction` converts).
        Once, when some driven points did not settle to ``velocity_tol``, naming how
        many and their γ (``IVCurve.converged`` False there); once more for each
        bisection with probes whose voltage state changed between their blocks,
        naming the current and the probes' γ (``IVCurve.switching_settled`` or
        ``retrapping_settled`` False).

    Raises
    ------
    ValueError
        For β ≤ 0 (no dissipation: no limit cycle to settle on), an empty or
        non-finite ``gamma``, ω ≤ 0, ``current_tol`` ≤ 0, a non-finite drive, or a
        drive (A ≠ 0) with Ω ≤ 0.
    TypeError
        For an argument that is not a real number (or, ``gamma``, real numbers).
    """
    beta = check_positive("beta", beta, why="damping: an I–V curve needs a damped junction")
    omega = check_rule("omega", omega)
    current_tol = check_positive("current_tol", current_tol)
    velocity_tol = check_positive("velocity_tol", velocity_tol)
    drive = tuple(check_rule(name, value) for name, value in (
        ("drive_amplitude", drive_amplitude), ("drive_frequency", drive_frequency), ("drive_phase", drive_phase)))
    check_drive(drive[0], drive[1])
    g = check_rule_array("gamma", check_real_array("gamma", gamma)).reshape(-1)
    if g.size == 0:
        raise ValueError("gamma must hold at least one bias point")
    _warn_implausible_bias(g, omega, drive[0])
    for name, flag in (("progress", progress), ("differential", differential)):
        if flag is not False and flag is not True:
            raise TypeError(f"{name} must be True or False, got {flag!r}")
    y = check_state("(theta0, theta_dot0)", [check_real("theta0", theta0), check_real("theta_dot0", theta_dot0)])
    regimes, velocities, periods, states, starts, converged = _sweep_points(
        (beta, omega, drive), g, y, integrate, velocity_tol, progress)
    _warn_unsettled(g, converged, velocity_tol)
    switching, retrapping, unsettled = _currents(beta, omega, g, regimes, velocities, states,
                                                 current_tol=current_tol, integrate=integrate, drive=drive,
                                                 velocity_tol=velocity_tol)
    _warn_unsettled_probes(unsettled)
    slope = None
    if differential:
        slope = np.array([_slope(Pendulum(beta, gi, omega, *drive), r, p, y)
                          for gi, r, p, y in zip(g, regimes, periods, states)])
    return IVCurve(gamma=g, mean_velocity=np.array(velocities), regime=np.array(regimes),
                   period=np.array(periods), start_state=np.array(starts),
                   switching_current=_midpoint(switching), retrapping_current=_midpoint(retrapping),
                   beta=beta, omega=omega, current_tol=current_tol, drive_amplitude=drive[0],
                   drive_frequency=drive[1], drive_phase=drive[2], switching_bracket=tuple(map(float, switching)),
                   retrapping_bracket=tuple(map(float, retrapping)), converged=converged,
                   velocity_tol=velocity_tol, switching_settled=not unsettled["switching"],
                   retrapping_settled=not unsettled["retrapping"], dvoltage_dgamma=slope)


def _sweep_points(params, g, y, integrate, velocity_tol, progress):
    # Each bias point settled from the last one's state (params: β, ω, drive), with the
    # progress bar: (regimes, velocities, periods, end states, start states, converged).
    beta, omega, drive = params
    regimes, velocities, periods, states, starts, converged = [], [], [], [], [], []
    bar = progress_bar(g.size, "I-V points", unit="point") if progress else None
    try:
        for gi in g:
            starts.append(y.copy())
            regime, v, period, y, ok, _ = _measure(Pendulum(beta, gi, omega, *drive), y, integrate, velocity_tol)
            regimes.append(regime)
            velocities.append(v)
            periods.append(period)
            states.append(y.copy())
            converged.append(ok)
            if bar is not None:
                bar.update()
    finally:
        if bar is not None:
            bar.close()
    return regimes, velocities, periods, states, starts, np.array(converged, dtype=bool)


def _slope(model, regime, period, y):
    # A point's d⟨θ'⟩/dγ: 0 locked or on a Shapiro step, the period's sensitivity on an
    # undriven running cycle, NaN at a driven point off the steps (module docstring).
    if regime == PHASE_LOCKED or (regime == LOCKED and not model.driven):
        return 0.0
    if model.driven:
        return math.nan
    return _running_slope(model, y, period)


def _currents(beta, omega, g, regimes, velocities, states, *, current_tol, integrate, drive, velocity_tol):
    # The first locked -> running and running -> locked transitions between visited points,
    # bisected: their brackets ((nan, nan) if none) and each bisection's unsettled probes.
    none = (math.nan, math.nan)
    switching = retrapping = none
    unsettled = {"switching": [], "retrapping": []}  # probes whose voltage state changed between blocks
    for i in range(1, g.size):
        a = _voltage_state(regimes[i - 1], velocities[i - 1], drive[1])
        b = _voltage_state(regimes[i], velocities[i], drive[1])
        if a == b:
            continue
        if a == LOCKED and switching is none:
            g_a, g_b, unsettled["switching"] = _bisect(beta, omega, g[i - 1], g[i], states[i - 1], LOCKED,
                                                       current_tol, integrate, drive=drive, velocity_tol=velocity_tol)
            lo, hi = sorted((g_a, g_b))
            # No zero-voltage state beyond |γ| = ω² (IVCurve): the bracket within it.
            w2 = omega * omega
            switching = (max(lo, -w2), min(hi, w2))
        elif a == RUNNING and retrapping is none:
            g_a, g_b, unsettled["retrapping"] = _bisect(beta, omega, g[i - 1], g[i], states[i - 1], RUNNING,
                                                        current_tol, integrate, drive=drive,
                                                        velocity_tol=velocity_tol)
            retrapping = tuple(sorted((g_a, g_b)))
    return switching, retrapping, unsettled


def _warn_implausible_bias(g, omega, amplitude):
    # A reduced bias far above the switching range is most often a current entered in
    # µA or mA: say so (the run goes on; the answer is right for the numbers given).
    top = float(np.max(np.abs(g)))
    w2 = omega * omega
    if top > IMPLAUSIBLE_BIAS * (w2 + abs(amplitude)):
        warnings.warn(f"iv_curve: |gamma| reaches {top:g}, {top / w2:.3g} times the critical current omega**2 = "
                      f"{w2:g}: gamma is the reduced bias I/I_c (a current in µA or mA by mistake? "
                      f"mbm.Junction(I_c=..., R=..., C=...).gamma(I) converts)", RuntimeWarning, stacklevel=3)


def _warn_unsettled(g, converged, velocity_tol):
    # iv_curve's warning for the driven points that did not settle: how many, and where.
    bad = np.flatnonzero(~converged)
    if bad.size:
        where = ", ".join(f"{float(x):.10g}" for x in g[bad])
        warnings.warn(f"iv_curve: {bad.size} of {g.size} driven points did not settle (the averages of "
                      f"successive blocks did not agree to velocity_tol = {velocity_tol:g} within "
                      f"{DRIVE_MAX_BLOCKS} blocks of {DRIVE_AVERAGE_PERIODS} drive periods), gamma = "
                      f"[{where}]; IVCurve.converged is False there", RuntimeWarning, stacklevel=3)


def _warn_unsettled_probes(unsettled):
    # iv_curve's warning for a bracket that rests on probes whose blocks did not settle.
    for name, probes in unsettled.items():
        if probes:
            where = ", ".join(f"{float(x):.10g}" for x in probes)
            warnings.warn(f"iv_curve: {len(probes)} probe(s) of the {name} current's bisection changed voltage "
                          f"state between their blocks of {DRIVE_AVERAGE_PERIODS} drive periods (a transient, or "
                          f"intermittent slips beside the edge), gamma = [{where}]: the bracket rests on each "
                          f"one's last block; IVCurve.{name}_settled is False", RuntimeWarning, stacklevel=3)


def _midpoint(bracket):
    # The reported current: the bracket's midpoint, inside it (nan without a bracket).
    lo, hi = bracket
    return float(min(max(0.5 * (lo + hi), lo), hi))


def _bisect(beta, omega, g_a, g_b, y_a, regime_a, tol, integrate, *, drive=(0.0, 0.0, 0.0),
            velocity_tol=DRIVE_VELOCITY_TOL):
    # [g_a, g_b]: regime_a at g_a (settled state y_a), the other regime at g_b; returns
    # the final (g_a, g_b), |g_b − g_a| ≤ tol, and the γ of the probes whose voltage
    # state was not steady over their blocks (_driven_measure).  A probe
    # that keeps regime_a becomes the new g_a with its settled state: the bias steps
    # shrink as the interval does, an adiabatic sweep in the limit (a finite step from
    # a locked state can kick it over the saddle below the switching current ω²).
    unsettled = []
    while abs(g_b - g_a) > tol:
        mid = 0.5 * (g_a + g_b)
        regime, v, _, y, _, steady = _measure(Pendulum(beta, mid, omega, *drive), y_a, integrate, velocity_tol)
        if not steady:
            unsettled.append(mid)
        if _voltage_state(regime, v, drive[1]) == regime_a:
            g_a, y_a = mid, y
        else:
            g_b = mid
    return g_a, g_b, unsettled
