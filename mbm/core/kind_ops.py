"""The compiled pieces of the kinds other than "taylor", called through a table of addresses.

numba links the code of every compiled function a kernel calls into that kernel and
optimises and emits it again there: a loop entry, a controller or a crossing that called
a splitting's evaluation directly re-compiled the elliptic flow, the Jacobi functions
and double-double arithmetic in each of them.  The kinds exact, salas-torque and split
are instead called through the intrinsics of this module (:func:`call_anchor`,
:func:`call_eval`, ...): an indirect call through slot ``(kind, op)`` of one
process-wide table of addresses (:data:`OPS`).  A slot is filled on its first call, from
compiled code: the op is compiled then (or loaded from numba's cache) by
:func:`_load_slot`, a callback into Python.  So the loop's entries are shared by every
kind (:mod:`mbm.core.loop`) and compile none of those kinds' code, a run compiles only
its own kind's, and a kernel that calls one stays cached (the table's address is
resolved by name when the cached code is loaded).

Each op has one signature (:data:`SIGNATURES`): the formulas (anchor, evaluation,
estimate; thin kernels over the kind's own, the same calls, so the same bits) and the
pieces compiled once per kind (the adaptive controller's first and later windows, the
return map's crossing, and the stored period's windows, look-up and refinement).
"""

import ctypes
import sys

import llvmlite.binding as ll
import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

import importlib

import numba

from ..approximants.belendez2007 import belendez_anchor_kernel
from ..approximants.salas2022 import salas_torque_anchor
from ..approximants.splitting import split_anchor
from ..compile.jit import kernel
from ..regimes.cycle import CycleSpan, CycleWatch
from .record import RUN, WindowControl

__all__ = ["OPS", "SIGNATURES", "call_adaptive", "call_anchor", "call_crossing", "call_error", "call_eval",
           "call_eval_range", "call_first", "call_period_store", "call_period_value", "call_refine", "slot_of"]

# The ops of a kind, each a column of the table.
OP_ANCHOR, OP_EVAL, OP_ERROR, OP_FIRST, OP_ADAPTIVE, OP_CROSSING = 0, 1, 2, 3, 4, 5
OP_PERIOD_STORE, OP_PERIOD_VALUE, OP_REFINE = 6, 7, 8
OP_EVAL_RANGE = 9
# Columns per kind (room for further ops without moving the slots).
OPS_PER_KIND = 16
# Rows: the kind ids of mbm.core.window (0 "taylor" .. 3 "split") and room for more.
TABLE_KINDS = 8

_F8, _I8 = types.float64, types.int64
_COEF = types.Array(_F8, 1, "C")
_PAIR = types.UniTuple(_F8, 2)
_ROW = types.Array(_F8, 1, "A")
_RECORD = numba.from_dtype(RUN)
# The controllers' arguments (mbm.core.controller.first_window_for, adaptive_window_for):
# the window's start (coef, t, φ, θ', the winding's offset), ω or h_abs, the run's
# WindowControl (as mbm.core.record.window_control types it).
_CONTROL = types.NamedTuple((_F8, _F8, _F8, _F8, _F8, _I8, _F8), WindowControl)
_CONTROL_ARGS = (_COEF,) + (_F8,) * 5 + (_CONTROL,)
#: Each op's signature: an anchor (karg, β, γ, ω, θ₀, θ̇₀) -> coefficients (coef[0] the
#: status), an evaluation (coef, t) -> (θ, θ'), an estimate (coef, h) -> (err_θ, err_θ');
#: the controllers', the crossing's, the stored period's as their kernels'; a window's
#: outputs (coef, t, t_eval, j, j2, out_θ, out_θ') -> None.
SIGNATURES = {
    OP_ANCHOR: _COEF(_I8, _F8, _F8, _F8, _F8, _F8),
    OP_EVAL: _PAIR(_COEF, _F8),
    OP_ERROR: _PAIR(_COEF, _F8),
    OP_FIRST: _F8(*_CONTROL_ARGS),
    OP_ADAPTIVE: types.Tuple((_I8, _F8, _F8, _F8, _F8))(*_CONTROL_ARGS),
    OP_CROSSING: types.none(_RECORD, _COEF, types.BaseTuple.from_types((_F8,) * 7, CycleSpan),
                            types.BaseTuple.from_types((_F8,) * 8, CycleWatch), _I8, _I8),
    OP_PERIOD_STORE: types.Tuple((_COEF, types.Array(_F8, 2, "C"), types.Array(_F8, 2, "C"), _I8))(_COEF),
    OP_PERIOD_VALUE: types.UniTuple(_F8, 3)(_COEF, _COEF, types.Array(_F8, 2, "C"), types.Array(_F8, 2, "C"),
                                            _I8, _F8),
    OP_REFINE: types.none(_RECORD),
    OP_EVAL_RANGE: types.none(_COEF, _F8, _ROW, _I8, _I8, _ROW, _ROW),
}


@kernel
def _exact_anchor(karg, beta, gamma, omega, theta0, v0):
    return belendez_anchor_kernel(beta, gamma, omega, theta0, v0)


@kernel
def _salas_torque_anchor(karg, beta, gamma, omega, theta0, v0):
    return salas_torque_anchor(beta, gamma, omega, theta0, v0)


@kernel
def _split_anchor(karg, beta, gamma, omega, theta0, v0):
    return split_anchor(karg, beta, gamma, omega, theta0, v0)


# Kind ids as mbm.core.window numbers them (window imports this module, so they are
# restated here; tests/core/test_kind_ops.py checks them against window's).
_EXACT, _SALAS_TORQUE, _SPLIT = 1, 2, 3

#: The kinds with pieces in the table, by id (the compile helper's keys, mbm.compile.warm).
KINDS = {_EXACT: "exact", _SALAS_TORQUE: "salas-torque", _SPLIT: "split"}

_M = "mbm.core.kind_ops"
#: (kind id, op) -> (module, name) of the compiled function of that slot, imported at the
#: slot's first call (the controllers' and regimes' modules import this one).
OPS = {
    (_EXACT, OP_ANCHOR): (_M, "_exact_anchor"),
    (_EXACT, OP_EVAL): ("mbm.approximants.belendez2007", "belendez_eval_kernel"),
    (_EXACT, OP_EVAL_RANGE): ("mbm.approximants.belendez2007", "belendez_eval_range"),
    (_SALAS_TORQUE, OP_ANCHOR): (_M, "_salas_torque_anchor"),
    (_SALAS_TORQUE, OP_EVAL): ("mbm.approximants.salas2022", "salas_torque_eval"),
    (_SPLIT, OP_ANCHOR): (_M, "_split_anchor"),
    (_SPLIT, OP_EVAL): ("mbm.approximants.splitting", "split_eval_kernel"),
    (_SPLIT, OP_ERROR): ("mbm.approximants.splitting", "split_error_kernel"),
    (_SPLIT, OP_FIRST): ("mbm.core.controller", "_first_window_split"),
    (_SPLIT, OP_ADAPTIVE): ("mbm.core.controller", "_adaptive_window_split"),
    (_SPLIT, OP_CROSSING): ("mbm.regimes.cycle_windows", "_cycle_crossing_split"),
    (_SPLIT, OP_PERIOD_STORE): ("mbm.regimes.cycle_windows", "_period_windows_split"),
    (_SPLIT, OP_PERIOD_VALUE): ("mbm.regimes.cycle_windows", "_period_lookup_split"),
    (_SPLIT, OP_REFINE): ("mbm.regimes.cycle_windows", "_refine_period_split"),
}


def op_function(kind, op):
    """The compiled function of slot (``kind``, ``op``), or None where it has none."""
    where = OPS.get((kind, op))
    return None if where is None else getattr(importlib.import_module(where[0]), where[1])


def slot_of(kind, op):
    """The table slot of op ``op`` of kind id ``kind``."""
    return kind * OPS_PER_KIND + op


# The table: one address per slot, 0 until the slot's first call.  Named to the JIT's
# linker (ll.add_symbol), so compiled code finds it by name, cached code included.
_TABLE = np.zeros(TABLE_KINDS * OPS_PER_KIND, dtype=np.int64)
_TABLE_SYMBOL = "mbm_kind_ops_table"
_LOAD_SYMBOL = "mbm_kind_ops_load"
#: The exceptions that failed a slot's load (the compiled caller raises RuntimeError).
LOAD_ERRORS = []


def _address(disp, sig):
    # The native entry of ``disp`` compiled for ``sig`` (numba's calling convention).
    disp.compile(sig)
    cres = disp.overloads[tuple(sig.args)]
    return cres.library.get_pointer_to_function(cres.fndesc.llvm_func_name)


def _load_slot(slot):
    """Fill table slot ``slot`` (compile or load its op) and return its address; 0 where
    the slot has no op or its compile failed (the error kept in LOAD_ERRORS)."""
    try:
        if _TABLE[slot] == 0:
            kind, op = divmod(int(slot), OPS_PER_KIND)
            disp = op_function(kind, op)
            if disp is None:
                return 0
            _TABLE[slot] = _address(disp, SIGNATURES[op])
        return int(_TABLE[slot])
    except BaseException as exc:  # a callback must not raise: the caller reports it
        LOAD_ERRORS.append(exc)
        print(f"mbm: loading a compiled formula failed: {exc!r}", file=sys.stderr)
        return 0


_LOAD = ctypes.CFUNCTYPE(ctypes.c_int64, ctypes.c_int64)(_load_slot)
ll.add_symbol(_TABLE_SYMBOL, _TABLE.ctypes.data)
ll.add_symbol(_LOAD_SYMBOL, ctypes.cast(_LOAD, ctypes.c_void_p).value)


def _table_call(op):
    """An intrinsic ``call(slot, args)``: op ``op``'s function of table slot ``slot``
    called with the tuple ``args`` (cast to the op's signature)."""
    op_sig = SIGNATURES[op]

    @intrinsic
    def call(typingctx, slot, args):
        if not isinstance(slot, types.Integer) or not isinstance(args, types.BaseTuple):
            return None
        if len(args) != len(op_sig.args):
            return None
        sig = op_sig.return_type(slot, args)

        def codegen(context, builder, sig, llargs):
            i64 = ir.IntType(64)
            slot_v = context.cast(builder, llargs[0], sig.args[0], types.int64)
            vals = [context.cast(builder, v, fr, to)
                    for v, fr, to in zip(cgutils.unpack_tuple(builder, llargs[1], len(args)), args, op_sig.args)]
            mod = builder.module
            table = mod.globals.get(_TABLE_SYMBOL)
            if table is None:
                table = ir.GlobalVariable(mod, ir.ArrayType(i64, _TABLE.size), _TABLE_SYMBOL)
                table.linkage = "external"
            load = cgutils.get_or_insert_function(mod, ir.FunctionType(i64, [i64]), _LOAD_SYMBOL)
            ptr = builder.gep(table, [ir.Constant(ir.IntType(32), 0), slot_v])
            addr = builder.load(ptr)
            with builder.if_then(builder.icmp_unsigned("==", addr, i64(0)), likely=False):
                builder.store(builder.call(load, [slot_v]), ptr)
            addr = builder.load(ptr)
            with builder.if_then(builder.icmp_unsigned("==", addr, i64(0)), likely=False):
                context.call_conv.return_user_exc(
                    builder, RuntimeError, ("mbm: a kind's compiled formula could not be loaded "
                                            "(mbm.core.kind_ops.LOAD_ERRORS)",))
            fnty = context.call_conv.get_function_type(op_sig.return_type, op_sig.args)
            fn = builder.inttoptr(addr, fnty.as_pointer())
            status, res = context.call_conv.call_function(builder, fn, op_sig.return_type, op_sig.args, vals)
            with cgutils.if_unlikely(builder, status.is_error):
                context.call_conv.return_status_propagate(builder, status)
            return res

        return sig, codegen

    return call


#: ``call_anchor(slot, (karg, β, γ, ω, θ₀, θ̇₀))`` -> coefficients (a new array).
call_anchor = _table_call(OP_ANCHOR)
#: ``call_eval(slot, (coef, t))`` -> (θ, θ').
call_eval = _table_call(OP_EVAL)
#: ``call_error(slot, (coef, h))`` -> (err_θ, err_θ').
call_error = _table_call(OP_ERROR)
#: The controllers: ``call_first(slot, args)`` -> h, ``call_adaptive(slot, args)`` ->
#: (status, t_new, θ, θ', h_next); args (coef, t, φ, θ', off, ω or h_abs, WindowControl) as
#: mbm.core.controller.first_window's and adaptive_window's.
call_first = _table_call(OP_FIRST)
call_adaptive = _table_call(OP_ADAPTIVE)
#: The return map's step at a crossing (mbm.regimes.cycle_windows._cycle_crossing_for).
call_crossing = _table_call(OP_CROSSING)
#: The stored period: its windows from a cycle window's coefficients, the value at a
#: time, the refinement of the record's period (mbm.regimes.cycle_windows).
call_period_store = _table_call(OP_PERIOD_STORE)
call_period_value = _table_call(OP_PERIOD_VALUE)
call_refine = _table_call(OP_REFINE)
#: A window's outputs t_eval[j:j2] in one call: ``call_eval_range(slot, (coef, t, t_eval, j,
#: j2, out_θ, out_θ'))`` (the exact flow's table, mbm.special.pendulum_flow_table).
call_eval_range = _table_call(OP_EVAL_RANGE)


def _python_call(slot, args):
    # Under NUMBA_DISABLE_JIT the kernels run as Python: the slot's function called directly.
    fn = op_function(*divmod(int(slot), OPS_PER_KIND))
    if fn is None:
        raise RuntimeError("mbm: a kind's compiled formula could not be loaded (mbm.core.kind_ops.LOAD_ERRORS)")
    return fn(*args)


if numba.config.DISABLE_JIT:
    call_anchor = call_eval = call_error = call_first = call_adaptive = call_crossing = _python_call
    call_period_store = call_period_value = call_refine = call_eval_range = _python_call
