"""A window's outputs: the times of t_eval in its span written to the call's rows.

One emitter per window formula, each in one call over the window's block of times:
an ordinary Taylor window (:func:`emit_taylor`, shared by the loop and the lanes), an
exact-flow window (:func:`emit_exact`, through the kinds' table) and a locked window
(:func:`emit_locked`).  The loop (:mod:`mbm.core.loop`) calls them after each window.
"""

import collections

import numba

from ..approximants.taylor import taylor_eval_range
from ..compile.jit import INLINE, kernel
from ..regimes.locked import locked_eval_range
from .kind_ops import OP_EVAL_RANGE, OPS_PER_KIND, call_eval_range
from .window import KIND_EXACT, _put

__all__ = ["Outputs", "Span", "emit_taylor", "emit_exact", "emit_locked"]

#: Where a call's outputs go: the times ``t_eval`` and the rows θ, θ' and (``wrapped``:
#: θ wrapped to (−π, π]) the winding count ``w`` (``w`` is ``theta`` when not wrapped).
Outputs = collections.namedtuple("Outputs", ("t_eval", "theta", "v", "w", "wrapped"))

#: A window's outputs' span (t, t_new] in the direction of time (±1), and its winding
#: count k (θ = 2πk + φ).
Span = collections.namedtuple("Span", ("t", "t_new", "direction", "k"))


@numba.njit(**INLINE)
def _block_end(t_eval, j, t_new, direction):
    # The first output index past (t, t_new] from j (t_eval sorted in the direction).
    while j < t_eval.size and (direction * (t_eval[j] - t_new) <= 0.0):
        j += 1
    return j


@numba.njit(**INLINE)
def _wind(out_theta, out_w, wrapped, j, j2, k):
    # θ = 2πk + φ of rows j..j2 (or φ wrapped and k apart), where k or wrapping apply.
    if k != 0.0 or wrapped:
        for i in range(j, j2):
            _put(out_theta, out_w, wrapped, i, k, out_theta[i])


@numba.njit(**INLINE)
def emit_taylor(coef, span, t_eval, j, out_theta, out_v, out_w, wrapped):
    """The outputs of an ordinary Taylor window in (t, t_new] (``span``: a :data:`Span`)
    in one call, four times at once (the same Horner steps per time as evaluate, so the
    same bits; an output at t_new is the evaluation that produced the state).  Returns
    the next output index.  Shared by the loop and the lanes.  The rows one by one:
    taken from an Outputs record at each window they cost a few % of the common damped
    run (reference counts)."""
    t, t_new, direction, k = span
    j2 = _block_end(t_eval, j, t_new, direction)
    if j2 > j:
        # (Not called for an empty range: the call alone, its arrays passed and
        # reference-counted, cost ~25 ns of a ~400 ns window.)
        taylor_eval_range(coef, t, t_eval, j, j2, out_theta, out_v)
        _wind(out_theta, out_w, wrapped, j, j2, k)
    return j2


@kernel
def emit_exact(coef, span, j, th, v, outs):
    """The outputs of an exact-flow window (undriven, kind "exact") in (t, t_new] in one
    call (:func:`mbm.approximants.belendez2007.belendez_eval_range`, :func:`evaluate`'s
    bits: from a table of the flow where the block is large); an output at t_new is the
    end state θ, θ' (``th``, ``v``) itself.  Returns the next output index."""
    t, t_new, direction, k = span
    t_eval, out_theta, out_v, out_w, wrapped = outs
    j2 = j
    while j2 < t_eval.size and (direction * (t_eval[j2] - t_new) < 0.0):
        j2 += 1
    if j2 > j:  # (through the kinds' table: the other kinds' entries compile none of it)
        call_eval_range(KIND_EXACT * OPS_PER_KIND + OP_EVAL_RANGE, (coef, t, t_eval, j, j2, out_theta, out_v))
    while j2 < t_eval.size and t_eval[j2] == t_new:
        out_theta[j2], out_v[j2] = th, v
        j2 += 1
    _wind(out_theta, out_w, wrapped, j, j2, k)
    return j2


@numba.njit(**INLINE)
def emit_locked(coef, span, t_eval, j, out_theta, out_v, out_w, wrapped):
    """The outputs of a locked window (L2, L6) in (t, t_new] (``span``: a :data:`Span`) in
    one call: its constants formed once (:func:`mbm.regimes.locked.locked_eval_range`,
    the same bits as :func:`mbm.regimes.locked.locked_eval` per time; an output at t_new
    is the evaluation that gave the end state).  Returns the next output index."""
    t, t_new, direction, k = span
    j2 = _block_end(t_eval, j, t_new, direction)
    if j2 > j:
        locked_eval_range(coef, t, t_eval, j, j2, out_theta, out_v)
        _wind(out_theta, out_w, wrapped, j, j2, k)
    return j2
