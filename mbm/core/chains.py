"""The compiled whole runs: a run through the loop's entries of its regime sets in turn.

The loop (:mod:`mbm.core.loop`) has one entry per regime set (RUNNERS per kind and set); a run pauses at a
switch to another set, and Python resumes it through the new set's entry
(:func:`mbm.core.loop.run`).  Compiled callers (the batch's rows and lanes, the batch
events, :func:`mbm.solve_njit`) do the same in compiled code: :func:`_run_sets` calls
the entry of the record's set through :func:`_dispatch_flagged`, whose flags (bits of
one int, a constant of the caller: :func:`flag_bits`) say which kinds, degrees and sets
it may meet, so that only those entries are compiled into it.
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

#: The start (t0, θ0, θ'0, t1, h) an entry takes fresh, unused where it resumes a run.
_NO_START = (0.0, 0.0, 0.0, 0.0, 0.0)

# The flags of :func:`_dispatch_flagged`, bits of one int (:func:`flag_bits`): the kinds
# (kind "taylor": its general entries, its default degree's) and the regime sets
# (F_SET << set_flag(rset)), each a global that numba reads as a constant.
F_TAYLOR = 1
F_TAYLOR_SIMD = 2
F_EXACT = 4
F_SALAS_TORQUE = 8
F_SPLIT = 16
F_SET = 32
F_PLAIN = F_SET << RS_PLAIN
F_DAMPED = F_SET << RS_DAMPED
F_CONSERVATIVE = F_SET << RS_CONSERVATIVE
F_DRIVEN = F_SET << RS_DRIVEN
F_CYCLE = F_SET << RS_CYCLE
F_STROBE = F_SET << RS_STROBE


@numba.njit(**INLINE)
def _record_set(kind, r):
    return regime_set(kind, r.control.controller, r.switch.regimes, r.model.beta, r.model.drive_amp, r.switch.regime)


@numba.njit(**INLINE)
def _taylor_flagged(simd, rset, flags, buf, resume, arrays):
    """The Taylor entry of ``rset`` where its flag is set (:func:`_dispatch_flagged`): the
    default degree's (``simd``) or the general one; −1 where the set is not flagged."""
    if rset == RS_PLAIN:
        if flags & F_PLAIN:
            if simd:
                return _R_V0(buf, resume, _NO_START, arrays)
            return _R_T0(buf, resume, _NO_START, arrays)
    elif rset == RS_DAMPED:
        if flags & F_DAMPED:
            if simd:
                return _R_V1(buf, resume, _NO_START, arrays)
            return _R_T1(buf, resume, _NO_START, arrays)
    elif rset == RS_CONSERVATIVE:
        if flags & F_CONSERVATIVE:
            if simd:
                return _R_V2(buf, resume, _NO_START, arrays)
            return _R_T2(buf, resume, _NO_START, arrays)
    elif rset == RS_DRIVEN:
        if flags & F_DRIVEN:
            if simd:
                return _R_V3(buf, resume, _NO_START, arrays)
            return _R_T3(buf, resume, _NO_START, arrays)
    elif rset == RS_CYCLE:
        if flags & F_CYCLE:
            if simd:
                return _R_V4(buf, resume, _NO_START, arrays)
            return _R_T4(buf, resume, _NO_START, arrays)
    elif rset == RS_STROBE:
        if flags & F_STROBE:
            if simd:
                return _R_V5(buf, resume, _NO_START, arrays)
            return _R_T5(buf, resume, _NO_START, arrays)
    elif rset == RS_FIXED:
        if flags & F_PLAIN:
            if simd:
                return _R_V6(buf, resume, _NO_START, arrays)
            return _R_T6(buf, resume, _NO_START, arrays)
    return -1


@numba.njit(**INLINE)
def _dispatch_flagged(kind, rset, flags, p, arrays):
    """The entry of (``kind``, ``rset``) called where that kind and set are flagged in
    ``flags`` (:func:`flag_bits`: F_TAYLOR for the general Taylor entries, F_TAYLOR_SIMD
    for the default degree's, F_EXACT, F_SALAS_TORQUE, F_SPLIT, and a bit per regime set,
    RS_FIXED under F_PLAIN with RS_PLAIN; a constant where the caller is compiled); any
    other pair is STATUS_ANCHOR.  ``arrays``: the entries' (t_eval, out, win_t, win_y,
    win_coef, cancel), passed along.

    One call site, its flags constants: numba prunes the unflagged calls after inlining
    it, so only the flagged entries are typed and compiled.  (The flags are one int,
    each test one ``&`` of two constants: numba prunes a branch on constants, not on a
    tuple's field.  A site per set, each with the kind's branches, made the inlined body
    ~6x larger, and numba's inlining copies a body's whole variable scope once per
    block: quadratic in its size.)
    """
    w = p.view(np.float64)  # the record's words, as the entries take them (a resumed run)
    buf = w.reshape((1, w.size))
    # fresh typed, not a literal (a literal False would compile each entry again).
    resume = np.bool_(False)
    if kind == KIND_TAYLOR:
        # The default degree's entries (SIMD_RUNNERS) and the general ones, by the
        # record's degree where both are flagged (F_TAYLOR_SIMD alone compiles no general
        # entry, F_TAYLOR alone no default one).
        n = -1
        if flags & F_TAYLOR_SIMD:
            if not flags & F_TAYLOR or p[0].control.karg == SIMD_ORDER:
                n = _taylor_flagged(True, rset, flags, buf, resume, arrays)
        if flags & F_TAYLOR:
            if n < 0 and (not flags & F_TAYLOR_SIMD or p[0].control.karg != SIMD_ORDER):
                n = _taylor_flagged(False, rset, flags, buf, resume, arrays)
        if n >= 0:
            return n
    if kind == KIND_SPLIT:
        if flags & F_SPLIT:
            if rset == RS_PLAIN:
                if flags & F_PLAIN:
                    return _R_S0(buf, resume, _NO_START, arrays)
            elif rset == RS_DAMPED:
                if flags & F_DAMPED:
                    return _R_S1(buf, resume, _NO_START, arrays)
            elif rset == RS_CONSERVATIVE:
                if flags & F_CONSERVATIVE:
                    return _R_S2(buf, resume, _NO_START, arrays)
            elif rset == RS_DRIVEN:
                if flags & F_DRIVEN:
                    return _R_S3(buf, resume, _NO_START, arrays)
            elif rset == RS_CYCLE:
                if flags & F_CYCLE:
                    return _R_S4(buf, resume, _NO_START, arrays)
            elif rset == RS_FIXED:
                if flags & F_PLAIN:
                    return _R_S6(buf, resume, _NO_START, arrays)
    elif kind == KIND_EXACT:
        if flags & F_EXACT:
            if rset == RS_FIXED:
                if flags & F_PLAIN:
                    return _R_E6(buf, resume, _NO_START, arrays)
            elif rset == RS_DRIVEN:
                if flags & F_DRIVEN:
                    return _R_E3(buf, resume, _NO_START, arrays)
    elif kind == KIND_SALAS_TORQUE:
        if flags & F_SALAS_TORQUE:
            if rset == RS_FIXED:
                if flags & F_PLAIN:
                    return _R_Q6(buf, resume, _NO_START, arrays)
            elif rset == RS_DRIVEN:
                if flags & F_DRIVEN:
                    return _R_Q3(buf, resume, _NO_START, arrays)
    p[0].progress.status = STATUS_ANCHOR
    return 0


@numba.njit(**INLINE)
def _run_sets(kind, flags, p, arrays):
    """A run through its regime sets' entries in turn, of the kinds and sets flagged
    (:func:`_dispatch_flagged`): a pause at a regime switch is resumed through the new
    set's entry (every other stop returns); a kind or set not flagged is STATUS_ANCHOR.
    ``kind`` is the record's kind (a constant where the caller knows it); ``arrays`` the
    entries' (t_eval, out, win_t, win_y, win_coef, cancel)."""
    t_eval, out, win_t, win_y, win_coef, cancel = arrays
    r = p[0]
    n = 0
    while True:
        rset = _record_set(kind, r)
        n += _dispatch_flagged(kind, rset, flags, p, (t_eval, out, win_t[n:], win_y[n:], win_coef[n:], cancel))
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


def flag_bits(flags):
    """The ten flags of a batch (:func:`mbm.core.lanes.batch_flags`: the kinds taylor,
    exact, salas-torque, split, the Taylor kind's 1, 2 or 3, then a 0/1 per regime set
    by :func:`set_flag`) as the one int :func:`_dispatch_flagged` takes."""
    k0, k1, k2, k3 = flags[:4]
    bits = (F_TAYLOR if k0 & 1 else 0) | (F_TAYLOR_SIMD if k0 & 2 else 0)
    bits |= (F_EXACT if k1 else 0) | (F_SALAS_TORQUE if k2 else 0) | (F_SPLIT if k3 else 0)
    for s, on in enumerate(flags[4:]):
        if on:
            bits |= F_SET << s
    return bits


#: Every set's flag (a whole run of one kind).
_ALL_SETS = F_PLAIN | F_DAMPED | F_CONSERVATIVE | F_DRIVEN | F_CYCLE | F_STROBE


# One compiled whole run per kind (every set it may reach), for the compiled callers
# (solve_njit, the batch); its flags globals (constants, so numba prunes on them).
_RUN_TAYLOR = F_TAYLOR_SIMD | _ALL_SETS
_RUN_EXACT = F_EXACT | _ALL_SETS
_RUN_SALAS_TORQUE = F_SALAS_TORQUE | _ALL_SETS
_RUN_SPLIT = F_SPLIT | _ALL_SETS


@kernel
def run_taylor(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_sets` through every set of kind ``"taylor"`` at its default degree
    SIMD_ORDER (:data:`SIMD_RUNNERS`; another degree ends STATUS_ANCHOR); returns the
    windows taken."""
    return _run_sets(KIND_TAYLOR, _RUN_TAYLOR, p, (t_eval, out, win_t, win_y, win_coef, cancel))


@kernel
def run_exact(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_sets` through every set of kind ``"exact"``; returns the windows taken."""
    return _run_sets(KIND_EXACT, _RUN_EXACT, p, (t_eval, out, win_t, win_y, win_coef, cancel))


@kernel
def run_salas_torque(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_sets` through every set of kind ``"salas-torque"``; returns the windows taken."""
    return _run_sets(KIND_SALAS_TORQUE, _RUN_SALAS_TORQUE, p, (t_eval, out, win_t, win_y, win_coef, cancel))


@kernel
def run_split(p, t_eval, out, win_t, win_y, win_coef, cancel):
    """:func:`_run_sets` through every set of kind ``"split"``; returns the windows taken."""
    return _run_sets(KIND_SPLIT, _RUN_SPLIT, p, (t_eval, out, win_t, win_y, win_coef, cancel))


#: The whole-run entry of each kind id (compiled callers).
CHAINS = {KIND_TAYLOR: run_taylor, KIND_EXACT: run_exact, KIND_SALAS_TORQUE: run_salas_torque,
          KIND_SPLIT: run_split}
