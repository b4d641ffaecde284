"""The formulas of the kinds other than "taylor", called through a table of addresses.

numba links the code of every compiled function a kernel calls into that kernel and
optimises and emits it again there: a loop entry, a controller or a crossing that called
a splitting's evaluation directly re-compiled the elliptic flow, the Jacobi functions
and double-double arithmetic in each of them.  The kinds exact, salas-torque and split
are instead called through :func:`call_anchor`, :func:`call_eval` and
:func:`call_error`: an indirect call through slot ``(kind, op)`` of one process-wide
table of addresses (:data:`OPS`).  A slot is filled on its first call, from compiled
code: the op is compiled then (or loaded from numba's cache) by :func:`_load_slot`, a
callback into Python.  So a kernel of the loop compiles none of those formulas, a run
compiles only the formulas of its own kind, and a kernel that calls one stays cached
(the table's address is resolved by name when the cached code is loaded).

Each op has one signature (:data:`SIGNATURES`); the ops of a kind are thin kernels with
that signature over the kind's own formulas (the same calls, so the same bits).
"""

import ctypes
import sys

import llvmlite.binding as ll
import numpy as np
from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from ..approximants.belendez2007 import belendez_anchor_kernel, belendez_eval_kernel
from ..approximants.salas2022 import salas_torque_anchor, salas_torque_eval
from ..approximants.splitting import split_anchor, split_error_kernel, split_eval_kernel
from ..special.jit import kernel

__all__ = ["OPS", "SIGNATURES", "call_anchor", "call_error", "call_eval", "slot_of"]

# The ops of a kind, each a column of the table.
OP_ANCHOR, OP_EVAL, OP_ERROR = 0, 1, 2
# Columns per kind (room for further ops without moving the slots).
OPS_PER_KIND = 8
# Rows: the kind ids of mbm.core.window (0 "taylor" .. 3 "split") and room for more.
TABLE_KINDS = 8

_F8 = types.float64
_COEF = types.Array(_F8, 1, "C")
_PAIR = types.UniTuple(_F8, 2)
#: Each op's signature: an anchor (karg, β, γ, ω, θ₀, θ̇₀) -> coefficients (coef[0] the
#: status), an evaluation (coef, t) -> (θ, θ'), an estimate (coef, h) -> (err_θ, err_θ').
SIGNATURES = {
    OP_ANCHOR: _COEF(types.int64, _F8, _F8, _F8, _F8, _F8),
    OP_EVAL: _PAIR(_COEF, _F8),
    OP_ERROR: _PAIR(_COEF, _F8),
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
# restated here; tests/test_kind_ops.py checks them against window's).
_EXACT, _SALAS_TORQUE, _SPLIT = 1, 2, 3

#: (kind id, op) -> the compiled function of that slot.
OPS = {
    (_EXACT, OP_ANCHOR): _exact_anchor,
    (_EXACT, OP_EVAL): belendez_eval_kernel,
    (_SALAS_TORQUE, OP_ANCHOR): _salas_torque_anchor,
    (_SALAS_TORQUE, OP_EVAL): salas_torque_eval,
    (_SPLIT, OP_ANCHOR): _split_anchor,
    (_SPLIT, OP_EVAL): split_eval_kernel,
    (_SPLIT, OP_ERROR): split_error_kernel,
}


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
            disp = OPS.get((kind, op))
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
