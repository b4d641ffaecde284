"""The RUNNING cycle: a damped rotation settling on its limit cycle, one stored period re-taken.

RUNNING cycle (β > 0; a rotation settling on the limit cycle θ(t + T_c) = θ(t) ± 2π).
After each window the loop (the entry of :func:`mbm.core.loop._runner`) looks for the
section crossings (R1, :func:`section_offset`) and tests the switch on them (:func:`cycle_switch`, R2);
after the switch the rest is one stored period re-taken from the anchor crossing (R3):
the window :func:`cycle_coef`, evaluated by :mod:`mbm.regimes.cycle_windows` (``_cycle_phase``,
``_period_windows_for``).  A libration (:mod:`mbm.regimes.libration`, C3) is stored in the
same layout, winding sign 0.

The derivation, items R1–R4 (the comments below cite them), is in the
documentation's theory page, ``docs/theory/regimes.md``.
"""

import collections
import math

import numpy as np

from ..compile.jit import kernel
from .common import REGIME_LIBRATION, REGIME_LOCKED, REGIME_RUNNING, SWITCH_SAFETY

# A running-cycle window's coefficient vector (R3): [CYCLE_TAG, θ_c, v_c, T_c, t_off,
# β, γ, ω, rtol, atol, winding sign, kind argument, error order, k_c, T_lo]; t_off is
# the time from the cycle's anchor crossing to the window's start, the anchor is at
# θ = 2πk_c + θ_c (the loop's winding count, mbm.core.window "Winding"), and T_c + T_lo is
# the period in double-double (T_lo = 0 for the running cycle; C3 for a libration).
CYCLE_TAG = 102.0
CYCLE_WIDTH = 15
# (R2): a return map whose contraction measured over two periods is above this is not
# (yet) converging geometrically: no switch.
CYCLE_MAX_MULTIPLIER = 0.9
# (R2): once the map has converged, the period is averaged over this many more
# returns: the crossing times carry the run's global error, which a single
# difference would repeat in every later period; averaged, the stored period's
# drift is the run's own mean drift per period.
CYCLE_AVERAGE_PERIODS = 32
# (R1): safeguarded Newton steps for a section crossing inside a window (quadratic
# convergence from the bracket's secant start: a handful suffice; bisection backs it up).
CROSSING_ITERATIONS = 60
# (R3): most windows one evaluation of the stored period may take (a period takes
# ~10-100 at the tolerances in use); past it the evaluation is NaN (a failure).
CYCLE_MAX_WINDOWS = 100000

# The cycle window's coefficient layout (CYCLE_WIDTH): the index of each entry of
# :func:`cycle_coef`'s vector (R3; a libration's too, C3).
CYC_TAG = 0  # CYCLE_TAG (an approximant window's anchor status, 0.0, there)
CYC_THETA = 1  # θ_c: the anchor's angle, reduced (θ = 2πk_c + θ_c)
CYC_V = 2  # v_c: θ' at the anchor
CYC_PERIOD = 3  # T_c: the period (its high part where CYC_PERIOD_LO ≠ 0)
CYC_T_OFF = 4  # t_off: time from the anchor to the window's start
CYC_BETA = 5  # β of the model the stored period is re-taken with
CYC_GAMMA = 6  # γ of that model
CYC_OMEGA = 7  # ω of that model
CYC_RTOL = 8  # rtol the stored period is re-taken with
CYC_ATOL = 9  # atol the stored period is re-taken with
CYC_SIGN = 10  # winding sign: θ advances by 2π·sign per period (0: a libration, C3)
CYC_KARG = 11  # the approximant's kind argument
CYC_ERROR_ORDER = 12  # the approximant's error order
CYC_WIND = 13  # k_c: the anchor's winding count (mbm.core.window "Winding")
CYC_PERIOD_LO = 14  # T_lo: T_c + T_lo is the period in double-double (0 for the running cycle; C3)

#: The return map's last changes between successive crossings (R2): of θ' (``dv``), the
#: one before (``dv_prev``), of the return time (``dT``).
MapStep = collections.namedtuple("MapStep", ("dv", "dv_prev", "dT"))

#: A cycle's anchor (R3, C3): the crossing of θ = 2π·``wind`` + ``theta`` with speed ``v``,
#: the period ``period`` (+ ``period_lo`` in double-double: 0 for the running cycle) and
#: the winding ``sign`` (θ advances by 2π·sign per period; 0: a libration).
CycleAnchor = collections.namedtuple("CycleAnchor", ("theta", "v", "period", "period_lo", "sign", "wind"))

#: What a stored period is re-taken with (R3): the model β, γ, ω, the tolerances and the
#: approximant's kind argument and error order.
Retake = collections.namedtuple("Retake", ("beta", "gamma", "omega", "rtol", "atol", "karg", "error_order"))

#: An ordinary window the return map watches: [``t``, ``t_new``] from φ = ``y0`` to
#: (``th``, ``v``), ``k`` the winding count and ``off`` = 2πk.
CycleSpan = collections.namedtuple("CycleSpan", ("t", "t_new", "y0", "th", "v", "k", "off"))

#: The return map's constants of a run (R1, R2): the section's offset θ_s
#: (``sec_off``) and θ'' = ``sec_acc`` − βθ' on it, the model β, γ, ω, the span's end
#: ``t_bound`` and the tolerances.
CycleWatch = collections.namedtuple(
    "CycleWatch", ("sec_off", "sec_acc", "beta", "gamma", "omega", "t_bound", "rtol", "atol"))


@kernel
def section_offset(gamma, omega):
    """θ_s of the running cycle's section θ ≡ θ_s (mod 2π) (item R1): the saddle π − d.

    Parameters
    ----------
    gamma, omega : float
        The model's torque and ω > 0.

    Returns
    -------
    float
        π − arcsin(γ/ω²), with γ/ω² clamped to [−1, 1].
    """
    return math.pi - math.asin(min(1.0, max(-1.0, gamma / (omega * omega))))


@kernel
def cycle_switch(step, v, theta, vmax, amax, n_rest, tols):
    """Whether the return map has converged enough to switch to the cycle (item R2).

    Parameters
    ----------
    step : MapStep
        The last two changes of θ' between successive crossings (``dv``, ``dv_prev``) and
        the last change of the return time (``dT``).
    v, theta : float
        θ', θ at the last crossing.
    vmax : float
        Largest |θ'| seen over the last period.
    amax : float
        A bound on |θ''| (|γ| + β·vmax + ω²).
    n_rest : float
        Periods left to the end of the span.
    tols : Tolerance
        The run's tolerances (:data:`mbm.regimes.common.Tolerance`).

    Returns
    -------
    bool
    """
    dv, dv_prev, dT = step.dv, step.dv_prev, step.dT
    rtol, atol = tols.rtol, tols.atol
    if dv_prev == 0.0:
        return dv == 0.0 and dT == 0.0
    mu = abs(dv) / abs(dv_prev)
    if not (mu <= CYCLE_MAX_MULTIPLIER):
        return False
    tail = 1.0 / (1.0 - mu)
    # (R2): the period's distance to the cycle's, |dT|·tail, repeats every remaining period.
    drift = n_rest * abs(dT) * tail
    scale_v = SWITCH_SAFETY * (atol + rtol * abs(v))
    return (abs(dv) * tail <= scale_v and drift * amax <= scale_v
            and drift * vmax <= SWITCH_SAFETY * (atol + rtol * abs(theta)))


@kernel
def cycle_coef(anchor, t_off, retake):
    """A running-cycle window's coefficient vector (layout: CYCLE_TAG; item R3).

    Parameters
    ----------
    anchor : CycleAnchor
        The cycle's anchor: the crossing of θ = 2π·wind + θ_c with speed v_c, the
        period T_c (``period_lo``: its low part in double-double, 0 for the running
        cycle's averaged period; C3) and the winding sign (+1 or −1: θ advances by
        2π·sign per period).
    t_off : float
        Time from the anchor crossing to the window's start.
    retake : Retake
        The model, the tolerances, the approximant's kind argument and error order the
        stored period is re-taken with.

    Returns
    -------
    ndarray, shape (CYCLE_WIDTH,)
    """
    theta_c, v_c, period, period_lo, sign, wind_c = (anchor.theta, anchor.v, anchor.period, anchor.period_lo,
                                                     anchor.sign, anchor.wind)
    beta, gamma, omega, rtol, atol, karg, error_order = (retake.beta, retake.gamma, retake.omega, retake.rtol,
                                                         retake.atol, retake.karg, retake.error_order)
    c = np.empty(CYCLE_WIDTH)
    c[CYC_TAG] = CYCLE_TAG
    c[CYC_THETA] = theta_c
    c[CYC_V] = v_c
    c[CYC_PERIOD] = period
    c[CYC_T_OFF] = t_off
    c[CYC_BETA] = beta
    c[CYC_GAMMA] = gamma
    c[CYC_OMEGA] = omega
    c[CYC_RTOL] = rtol
    c[CYC_ATOL] = atol
    c[CYC_SIGN] = sign
    c[CYC_KARG] = karg
    c[CYC_ERROR_ORDER] = error_order
    c[CYC_WIND] = wind_c
    c[CYC_PERIOD_LO] = period_lo
    return c


def cycle_summary(regime, period, sign):
    """``(period, mean_velocity)`` of a result: T_c and ⟨θ'⟩ = ±2π/T_c when the run
    switched to the running cycle, (T, 0) when it switched to a libration, (nan, 0) when
    it switched to the locked state, else (nan, nan).

    Parameters
    ----------
    regime : int
        The run record's ``regime``.
    period, sign : float
        Its ``cyc_T`` and ``cyc_sign``.

    Returns
    -------
    (float, float)
    """
    if regime == REGIME_LOCKED:
        return math.nan, 0.0  # at rest at the equilibrium: no net motion
    if regime == REGIME_LIBRATION:
        return float(period), 0.0  # a closed orbit: no net motion
    if regime != REGIME_RUNNING:
        return math.nan, math.nan
    return float(period), float(sign) * 2.0 * math.pi / float(period)
