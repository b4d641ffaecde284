"""Long-horizon regimes: once a run reaches its attractor, the closed form of the rest.

A run whose motion has settled on its attractor ends with one last "window" to
``t_bound`` whose formula is the rest of the motion, so it costs its transient only.
One module per regime; their derivations (items L1–L7, R1–R4, C1–C4, S1–S8, which
the code's comments cite) are in the documentation's theory page,
``docs/theory/regimes.md``:

- :mod:`mbm.regimes.locked` (L1–L7): LOCKED (β > 0, |γ| < ω²), a run settling on a
  stable equilibrium: the linearized closed form, first or second order, with rigorous
  bounds on the neglected nonlinearity over any horizon.
- :mod:`mbm.regimes.cycle` (R1–R4): RUNNING (β > 0), a rotation settling on its limit
  cycle θ(t + T_c) = θ(t) ± 2π: one stored period re-taken from an anchor crossing.
- :mod:`mbm.regimes.libration` (C1–C4): LIBRATION (β = 0, |γ| < ω²), a conservative
  motion trapped in a well: its period by quadrature in double-double, stored as a cycle.
- :mod:`mbm.regimes.strobe` (S1–S7): PHASE-LOCKED (β > 0, A ≠ 0, Ω > 0), a periodic
  orbit of the stroboscopic map (a Shapiro step, integer or fractional): one stored
  period of q drive periods.
- :mod:`mbm.regimes.common`: the REGIME_* codes, REGIME_NAMES and SWITCH_SAFETY.
- :mod:`mbm.regimes.summary` (S8): a finished run's regime, period and mean velocity
  for every front end, and the lock watch's reading of a driven run that never switched.

How a regime plugs into the window loop (the entry of :func:`mbm.core.loop._runner`):

switch rule
    Tested between windows; it passes only where every output after the switch stays
    within SWITCH_SAFETY of the tolerance scale, whatever the horizon.  Locked:
    :func:`locked_far` (cheapest, every window), :func:`locked_quick_reject` (cheap),
    then :func:`locked_choice`
    (L5, L7).  Running: :func:`cycle_switch` on the section crossings (R1, R2).
    Libration: C4 at the run's first window, from :func:`libration_period`.
    Phase-locked: :func:`strobe_switch` on the stroboscopic samples (S3–S5, S7).  The
    run record's ``regime`` is then one of the REGIME_* codes (REGIME_NAMES[regime]
    is the result's name for it).
window
    The rest of the run is one more window in the run's window store: a coefficient
    vector whose entry 0 is a tag (an approximant's window holds its anchor status,
    0.0, there): LOCKED_TAG (:func:`locked_coef`, entries LCK_*), CYCLE_TAG
    (:func:`cycle_coef`, entries CYC_*; a libration's too, C3), STROBE_TAG
    (:func:`strobe_coef`, entries STR_*).
evaluation
    A locked window is its closed form, :func:`locked_eval`.  A cycle, libration or
    phase-locked window is its stored period re-taken from the anchor by the same
    approximant and controller (``_period_windows_for`` of
    :mod:`mbm.regimes.cycle_windows`, ``_strobe_windows_taylor`` of :mod:`mbm.regimes.strobe_windows`;
    R3, C3, S6), so every path and the dense output (mbm.frontends.dense) give the same bits.
    A result's ``regime``, ``period`` and ``mean_velocity`` are
    :func:`mbm.regimes.summary.run_summary`'s (:func:`cycle_summary`,
    :func:`strobe_summary`, the lock watch).

Every name of the former single module ``mbm/regimes.py`` is re-exported here, so
``from mbm.regimes import X`` and ``mbm.regimes.X`` work as before.
"""

from .common import (  # noqa: F401
    SWITCH_SAFETY,
    REGIME_NONE,
    REGIME_LOCKED,
    REGIME_RUNNING,
    REGIME_LIBRATION,
    REGIME_PHASE_LOCKED,
    REGIME_NAMES,
)
from .locked import (  # noqa: F401
    AMPLITUDE_MARGIN,
    AMPLITUDE_BISECTIONS,
    AMPLITUDE_NEWTON_STEPS,
    X_MINUS_SIN_SERIES,
    QUICK_FACTOR,
    LOCKED_TAG,
    LOCKED_WIDTH,
    LOCKED2_WIDTH,
    green_integrals,
    locked_constants,
    _rho,
    _x_minus_sin,
    _potential,
    _nearest_k,
    locked_far,
    locked_quick_reject,
    _amplitude_newton,
    locked_bound,
    locked_amplitude,
    locked2_terms,
    locked2_bound,
    locked_choice,
    locked2_quick,
    locked_coef,
    locked_eval,
    locked_eval_array,
    locked_eval_range,
    LCK_TAG,
    LCK_THETA0,
    LCK_X0,
    LCK_V0,
    LCK_HALF_BETA,
    LCK_S2,
    LCK_WL2,
    LCK_ORDER,
    LCK_QR,
    LCK_QI,
    LCK_M,
    LCK_DR,
    LCK_DI,
)
from .cycle import (  # noqa: F401
    CYCLE_TAG,
    CYCLE_WIDTH,
    CYCLE_MAX_MULTIPLIER,
    CYCLE_AVERAGE_PERIODS,
    CROSSING_ITERATIONS,
    CYCLE_MAX_WINDOWS,
    section_offset,
    cycle_switch,
    cycle_coef,
    cycle_summary,
    CYC_TAG,
    CYC_THETA,
    CYC_V,
    CYC_PERIOD,
    CYC_T_OFF,
    CYC_BETA,
    CYC_GAMMA,
    CYC_OMEGA,
    CYC_RTOL,
    CYC_ATOL,
    CYC_SIGN,
    CYC_KARG,
    CYC_ERROR_ORDER,
    CYC_WIND,
    CYC_PERIOD_LO,
)
from .libration import (  # noqa: F401
    LIBRATION_NODES_MIN,
    LIBRATION_NODES_MAX,
    LIBRATION_QUAD_RTOL,
    LIBRATION_DD_FLOOR,
    LIBRATION_DD_NEWTON,
    LIBRATION_NEWTON_STEPS,
    LIBRATION_MIN_AMPLITUDE,
    LIBRATION_BARRIER_MARGIN,
    LIBRATION_MIN_PERIODS,
    DD_X_MINUS_SIN_TERMS,
    _dd_potential,
    _turning_point,
    libration_period,
)
from .strobe import (  # noqa: F401
    STROBE_TAG,
    STROBE_WIDTH,
    STROBE_CODE,
    STROBE_MAX_MULTIPLIER,
    STROBE_FIT_RESIDUAL,
    STROBE_NOISE_WIDEN,
    STROBE_CLEAN_RESIDUAL,
    STROBE_TRACE_AGREE,
    STROBE_MAX_PERIODS,
    STROBE_RING,
    STROBE_DISTINCT,
    strobe_period,
    strobe_time,
    strobe_phase,
    strobe_split,
    strobe_split_from,
    _spectral_radius,
    strobe_switch,
    strobe_coef,
    strobe_summary,
    STR_TAG,
    STR_PHI,
    STR_V,
    STR_WIND,
    STR_T,
    STR_Q,
    STR_P,
    STR_PSI,
    STR_BETA,
    STR_GAMMA,
    STR_OMEGA,
    STR_AMP,
    STR_FREQ,
    STR_RTOL,
    STR_ATOL,
    STR_KARG_ORDER,
)

__all__ = [
    "SWITCH_SAFETY",
    "REGIME_NONE",
    "REGIME_LOCKED",
    "REGIME_NAMES",
    "LOCKED_TAG",
    "LOCKED_WIDTH",
    "locked_constants",
    "section_offset",
    "locked_far",
    "locked_quick_reject",
    "locked_amplitude",
    "locked2_terms",
    "locked2_bound",
    "locked2_quick",
    "locked_choice",
    "LOCKED2_WIDTH",
    "locked_bound",
    "locked_coef",
    "locked_eval",
    "locked_eval_array",
    "locked_eval_range",
    "green_integrals",
    "REGIME_RUNNING",
    "CYCLE_TAG",
    "CYCLE_WIDTH",
    "cycle_coef",
    "cycle_switch",
    "cycle_summary",
    "REGIME_LIBRATION",
    "libration_period",
    "REGIME_PHASE_LOCKED",
    "STROBE_TAG",
    "STROBE_WIDTH",
    "strobe_period",
    "strobe_time",
    "strobe_phase",
    "strobe_split",
    "strobe_split_from",
    "strobe_switch",
    "strobe_coef",
    "strobe_summary",
    "STROBE_MAX_PERIODS",
    "STROBE_RING",
    "LCK_TAG",
    "LCK_THETA0",
    "LCK_X0",
    "LCK_V0",
    "LCK_HALF_BETA",
    "LCK_S2",
    "LCK_WL2",
    "LCK_ORDER",
    "LCK_QR",
    "LCK_QI",
    "LCK_M",
    "LCK_DR",
    "LCK_DI",
    "CYC_TAG",
    "CYC_THETA",
    "CYC_V",
    "CYC_PERIOD",
    "CYC_T_OFF",
    "CYC_BETA",
    "CYC_GAMMA",
    "CYC_OMEGA",
    "CYC_RTOL",
    "CYC_ATOL",
    "CYC_SIGN",
    "CYC_KARG",
    "CYC_ERROR_ORDER",
    "CYC_WIND",
    "CYC_PERIOD_LO",
    "STR_TAG",
    "STR_PHI",
    "STR_V",
    "STR_WIND",
    "STR_T",
    "STR_Q",
    "STR_P",
    "STR_PSI",
    "STR_BETA",
    "STR_GAMMA",
    "STR_OMEGA",
    "STR_AMP",
    "STR_FREQ",
    "STR_RTOL",
    "STR_ATOL",
    "STR_KARG_ORDER",
]
