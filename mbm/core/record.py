"""The run record: the scalars of one run of the compiled window loop, one dtype.

A record of dtype :data:`RUN` (a numpy structured array of length 1, or one row per
scene in a batch) holds a run's model, state, controller options, budget, progress,
winding and each regime's state.  The loop (:mod:`mbm.core.loop`) reads it, advances,
and writes the state reached back, so a caller may resume a run where it stopped.
:func:`new_run` is the one initialiser of a fresh record.
"""

import math
import numpy as np

from ..regimes.common import REGIME_NONE
from ..regimes.strobe import STROBE_MAX_PERIODS, STROBE_RING

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
