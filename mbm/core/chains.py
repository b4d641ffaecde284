"""The compiled whole runs: a run through the loop's entries of its regime sets in turn.

The loop (:mod:`mbm.core.loop`) has one entry per regime set (RUNNERS per kind and set); a run pauses at a
switch to another set, and Python resumes it through the new set's entry
(:func:`mbm.core.loop.run`).  Compiled callers (the batch's rows and lanes, the batch
events, :func:`mbm.solve_njit`) do the same in compiled code: :func:`_run_sets` calls
the entry of the record's set through :func:`_dispatch_flagged`, whose flags (constants
of the caller) say which kinds, degrees and sets it may meet, so that only those
entries are compiled into it.
"""

import numba
import numpy as np

from ..approximants.taylor_simd import SIMD_ORDER
from ..compile.jit import INLINE, kernel
from ..status import STATUS_ANCHOR, STATUS_PAUSED
from .loop import (
    RS_CONSERVATIVE,
    RS_CYCLE,
    RS_DAMPED,
    RS_DRIVEN,
    RS_FIXED,
    RS_PLAIN,
    RS_STROBE,
    RUN_TABLE,
    RUNNERS,
    SIMD_RUNNERS,
    regime_set,
)
from .window import KIND_EXACT, KIND_SALAS_TORQUE, KIND_SPLIT, KIND_TAYLOR


# numba calls a compiled function through a global: the table's entries as globals of
# this module for _dispatch_flagged.
(_R_T0, _R_T1, _R_T2, _R_T3, _R_T4, _R_T5, _R_T6, _R_S0, _R_S1, _R_S2, _R_S3, _R_S4, _R_S6,
 _R_E6, _R_E3, _R_Q6, _R_Q3) = (RUNNERS[key] for key in RUN_TABLE)
(_R_V0, _R_V1, _R_V2, _R_V3, _R_V4, _R_V5, _R_V6) = (
    SIMD_RUNNERS[s] for s in (RS_PLAIN, RS_DAMPED, RS_CONSERVATIVE, RS_DRIVEN, RS_CYCLE, RS_STROBE, RS_FIXED))


@numba.njit(**INLINE)
def _record_set(kind, r):
    return regime_set(kind, r.control.controller, r.switch.regimes, r.model.beta, r.model.drive_amp, r.switch.regime)


@numba.njit(**INLINE)
def _taylor_flagged(simd, rset, s0, s1, s2, s3, s4, s5, buf, resume, t_eval, out, win_t, win_y, win_coef, cancel):
    """The Taylor entry of ``rset`` where its flag is set (:func:`_dispatch_flagged`): the
    default degree's (``simd``) or the general one; −1 where the set is not flagged."""
    if rset == RS_PLAIN:
        if s0 == 1:
            if simd:
                return _R_V0(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
            return _R_T0(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
    elif rset == RS_DAMPED:
        if s1 == 1:
            if simd:
                return _R_V1(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
            return _R_T1(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
    elif rset == RS_CONSERVATIVE:
        if s2 == 1:
            if simd:
                return _R_V2(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
            return _R_T2(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
    elif rset == RS_DRIVEN:
        if s3 == 1:
            if simd:
                return _R_V3(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
            return _R_T3(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
    elif rset == RS_CYCLE:
        if s4 == 1:
            if simd:
                return _R_V4(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
            return _R_T4(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
    elif rset == RS_STROBE:
        if s5 == 1:
            if simd:
                return _R_V5(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
            return _R_T5(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
    elif rset == RS_FIXED:
        if s0 == 1:
            if simd:
                return _R_V6(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
            return _R_T6(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef, cancel)
    return -1


@numba.njit(**INLINE)
def _dispatch_flagged(kind, rset, k0, k1, k2, k3, s0, s1, s2, s3, s4, s5, p, t_eval, out, win_t, win_y, win_coef,
                      cancel):
    """The entry of (``kind``, ``rset``) called where that kind and set are flagged
    (``k<i>``: taylor, exact, salas-torque, split, ``k0`` 1 for the general Taylor
    entries, 2 for the default degree's, 3 for both; ``s<i>``: RS index, RS_FIXED under
    ``s0`` with RS_PLAIN (:func:`set_flag`); constants where the caller is compiled);
    any other pair is STATUS_ANCHOR.

    One call site, its flags constants: numba prunes the unflagged calls after inlining
    it, so only the flagged entries are typed and compiled.  (A site per set, each with
    the kind's branches, made the inlined body ~6x larger, and numba's inlining copies
    a body's whole variable scope once per block: quadratic in its size.)
    """
    w = p.view(np.float64)  # the record's words, as the entries take them (a resumed run)
    buf = w.reshape((1, w.size))
    # fresh typed, not a literal (a literal False would compile each entry again).
    resume = np.bool_(False)
    if kind == KIND_TAYLOR:
        # k0: 1 the general entries, 2 the default degree's (SIMD_RUNNERS), 3 both, by
        # the record's degree (a constant 2 compiles no general entry, 1 no default one).
        n = -1
        if k0 == 2 or k0 == 3:
            if k0 == 2 or p[0].control.karg == SIMD_ORDER:
                n = _taylor_flagged(True, rset, s0, s1, s2, s3, s4, s5, buf, resume, t_eval, out, win_t, win_y,
                                    win_coef, cancel)
        if k0 == 1 or k0 == 3:
            if n < 0 and (k0 == 1 or p[0].control.karg != SIMD_ORDER):
                n = _taylor_flagged(False, rset, s0, s1, s2, s3, s4, s5, buf, resume, t_eval, out, win_t, win_y,
                                    win_coef, cancel)
        if n >= 0:
            return n
    if kind == KIND_SPLIT:
        if k3 == 1:
            if rset == RS_PLAIN:
                if s0 == 1:
                    return _R_S0(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
            elif rset == RS_DAMPED:
                if s1 == 1:
                    return _R_S1(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
            elif rset == RS_CONSERVATIVE:
                if s2 == 1:
                    return _R_S2(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
            elif rset == RS_DRIVEN:
                if s3 == 1:
                    return _R_S3(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
            elif rset == RS_CYCLE:
                if s4 == 1:
                    return _R_S4(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
            elif rset == RS_FIXED:
                if s0 == 1:
                    return _R_S6(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
    elif kind == KIND_EXACT:
        if k1 == 1:
            if rset == RS_FIXED:
                if s0 == 1:
                    return _R_E6(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
            elif rset == RS_DRIVEN:
                if s3 == 1:
                    return _R_E3(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
    elif kind == KIND_SALAS_TORQUE:
        if k2 == 1:
            if rset == RS_FIXED:
                if s0 == 1:
                    return _R_Q6(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
            elif rset == RS_DRIVEN:
                if s3 == 1:
                    return _R_Q3(buf, resume, 0.0, 0.0, 0.0, 0.0, 0.0, t_eval, out, win_t, win_y, win_coef,
                                 cancel)
    p[0].progress.status = STATUS_ANCHOR
    return 0


@numba.njit(**INLINE)
def _run_sets(kind, k0, k1, k2, k3, s0, s1, s2, s3, s4, s5, p, t_eval, out, win_t, win_y, win_coef, cancel):
    """A run through its regime sets' entries in turn, of the kinds and sets flagged
    (:func:`_dispatch_flagged`): a pause at a regime switch is resumed through the new
    set's entry (every other stop returns); a kind or set not flagged is STATUS_ANCHOR.
    ``kind`` is the record's kind (a constant where the caller knows it)."""
    r = p[0]
    n = 0
    while True:
        rset = _record_set(kind, r)
        n += _dispatch_flagged(kind, rset, k0, k1, k2, k3, s0, s1, s2, s3, s4, s5, p, t_eval, out, win_t[n:],
                               win_y[n:], win_coef[n:], cancel)
        if r.progress.status != STATUS_PAUSED or _record_set(kind, r) == rset:
            return n


#: The sets a run starting in a set may reach (a switch to a stored period).
REACHES = {RS_PLAIN: (), RS_DAMPED: (RS_CYCLE,), RS_CONSERVATIVE: (RS_CYCLE,), RS_DRIVEN: (RS_STROBE,),
           RS_CYCLE: (), RS_STROBE: (), RS_FIXED: ()}


def set_flag(rset):
    """The index of the 0/1 flag that compiles set ``rset`` in a whole-run entry
    (:func:`_dispatch_flagged`): the set's own, RS_PLAIN's for RS_FIXED (the plain sets
    of a kind, with and without the adaptive controller)."""
    return RS_PLAIN if rset == RS_FIXED else rset


# One compiled whole run per kind (every set it may reach), for the compiled callers
# (solve_njit, the batch).
@kernel
def run_taylor(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_sets` through every set of kind ``"taylor"`` at its default degree
    SIMD_ORDER (:data:`SIMD_RUNNERS`; another degree ends STATUS_ANCHOR); returns the
    windows taken."""
    return _run_sets(KIND_TAYLOR, 2, 0, 0, 0, 1, 1, 1, 1, 1, 1, p, t_eval, out, win_t, win_y, win_coef, cancel)


@kernel
def run_exact(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_sets` through every set of kind ``"exact"``; returns the windows taken."""
    return _run_sets(KIND_EXACT, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1, p, t_eval, out, win_t, win_y, win_coef, cancel)


@kernel
def run_salas_torque(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_sets` through every set of kind ``"salas-torque"``; returns the windows taken."""
    return _run_sets(KIND_SALAS_TORQUE, 0, 0, 1, 0, 1, 1, 1, 1, 1, 1, p, t_eval, out, win_t, win_y, win_coef, cancel)


@kernel
def run_split(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_sets` through every set of kind ``"split"``; returns the windows taken."""
    return _run_sets(KIND_SPLIT, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, p, t_eval, out, win_t, win_y, win_coef, cancel)


#: The whole-run entry of each kind id (compiled callers).
CHAINS = {KIND_TAYLOR: run_taylor, KIND_EXACT: run_exact, KIND_SALAS_TORQUE: run_salas_torque,
          KIND_SPLIT: run_split}
