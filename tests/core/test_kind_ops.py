"""The kinds' formulas called through the table of addresses (mbm.core.kind_ops)."""

import numba
import numpy as np
import pytest
from mbm.approximants.belendez2007 import belendez_anchor_kernel, belendez_eval_kernel
from mbm.approximants.salas2022 import salas_torque_anchor, salas_torque_eval
from mbm.approximants.splitting import split_anchor, split_error_kernel, split_eval_kernel
from mbm.core import kind_ops, window
from mbm.core.kind_ops import OP_ANCHOR, OP_ERROR, OP_EVAL, OPS_PER_KIND, call_anchor, call_error, call_eval, slot_of

_S = OPS_PER_KIND

_SPLIT4 = 4  # split_anchor's method id of "split4"


def test_kind_ids_are_the_windows():
    assert (kind_ops._EXACT, kind_ops._SALAS_TORQUE, kind_ops._SPLIT) == (
        window.KIND_EXACT, window.KIND_SALAS_TORQUE, window.KIND_SPLIT)
    # the table has a row for every kind and a column for every op
    assert max(window.COMPILED_KINDS[k][0] for k in window.COMPILED_KINDS) < kind_ops.TABLE_KINDS
    assert max(kind_ops.SIGNATURES) < kind_ops.OPS_PER_KIND
    assert kind_ops._TABLE.size == kind_ops.TABLE_KINDS * kind_ops.OPS_PER_KIND


@numba.njit
def _through_table(t):
    a = call_anchor(3 * _S + 0, (4, 0.1, 0.3, 1.0, 0.5, 0.2))
    e = call_anchor(1 * _S + 0, (0, 0.0, 0.0, 1.0, 0.5, 0.2))
    s = call_anchor(2 * _S + 0, (0, 0.1, 0.3, 1.0, 0.5, 0.2))
    return (a, call_eval(3 * _S + 1, (a, t)), call_error(3 * _S + 2, (a, t)), e, call_eval(1 * _S + 1, (e, t)),
            s, call_eval(2 * _S + 1, (s, t)))


@numba.njit
def _direct(t):
    a = split_anchor(4, 0.1, 0.3, 1.0, 0.5, 0.2)
    e = belendez_anchor_kernel(0.0, 0.0, 1.0, 0.5, 0.2)
    s = salas_torque_anchor(0.1, 0.3, 1.0, 0.5, 0.2)
    return (a, split_eval_kernel(a, t), split_error_kernel(a, t), e, belendez_eval_kernel(e, t), s,
            salas_torque_eval(s, t))


def test_a_table_call_gives_the_direct_calls_bits():
    assert slot_of(3, OP_ANCHOR) == 3 * _S + 0 and slot_of(3, OP_EVAL) == 3 * _S + 1
    assert slot_of(3, OP_ERROR) == 3 * _S + 2 and slot_of(1, OP_EVAL) == 1 * _S + 1
    for t in (0.0, 0.7, -1.3, 4.0):
        got, want = _through_table(t), _direct(t)
        for g, w in zip(got, want):
            assert np.array_equal(np.asarray(g), np.asarray(w))
    # the slots are filled with the ops' addresses
    for key in ((3, OP_ANCHOR), (3, OP_EVAL), (3, OP_ERROR), (1, OP_EVAL), (2, OP_ANCHOR)):
        assert kind_ops._TABLE[slot_of(*key)] != 0


@numba.njit
def _no_such_op():
    return call_eval(5 * _S + 1, (np.zeros(3), 1.0))  # kind 5 has no ops


def test_a_slot_without_an_op_raises_rather_than_calls():
    with pytest.raises(RuntimeError, match="could not be loaded"):
        _no_such_op()
    assert kind_ops._TABLE[5 * _S + 1] == 0
    assert kind_ops._load_slot(5 * _S + 1) == 0


def test_a_failed_load_is_reported():
    n = len(kind_ops.LOAD_ERRORS)
    key = (kind_ops._SPLIT, kind_ops.OPS_PER_KIND - 1)
    kind_ops.OPS[key] = ("mbm.approximants.splitting", "split_eval_kernel")  # an op without a signature
    try:
        assert kind_ops._load_slot(slot_of(*key)) == 0
    finally:
        del kind_ops.OPS[key]
    assert len(kind_ops.LOAD_ERRORS) == n + 1 and isinstance(kind_ops.LOAD_ERRORS[-1], KeyError)


_NJIT_FIRST = """
import json, numba, numpy as np, mbm
from mbm.core import kind_ops
slot = kind_ops.slot_of(kind_ops._EXACT, kind_ops.OP_EVAL)
empty = int(kind_ops._TABLE[slot]) == 0

@numba.njit
def user_code(t, out):
    # the exact flow (beta = gamma = 0) from the user's own compiled code, first of all
    return mbm.solve_njit(0.0, 0.0, 1.0, 0.0, 0.5, 0.2, 10.0, t, out, 1e-9, 1e-9, 10**6)

t = np.linspace(0.0, 10.0, 11)
out = np.empty((2, t.size))
status, n = user_code(t, out)
ref = mbm.solve(mbm.Pendulum(0.0, 0.0), (0.0, 10.0), [0.5, 0.2], rtol=1e-9, atol=1e-9, t_eval=t)
print(json.dumps({"empty": empty, "filled": int(kind_ops._TABLE[slot]) != 0, "status": int(status),
                  "same": bool(np.array_equal(out, ref.y))}))
"""


def test_compiled_code_fills_a_slot_at_its_first_call():
    # A fresh process's table is empty; solve_njit called from the user's compiled code
    # (no Python step of mbm before it) fills the exact flow's slots itself and gives
    # mbm.solve's answer.
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    env = dict(os.environ, MBM_COMPILE_HELPER="0")
    env["PYTHONPATH"] = os.pathsep.join([str(root)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    proc = subprocess.run([sys.executable, "-c", _NJIT_FIRST], env=env, cwd=root, capture_output=True, text=True,
                          timeout=900)
    assert proc.returncode == 0, proc.stderr[-2000:]
    got = json.loads(proc.stdout.strip().splitlines()[-1])
    assert got == {"empty": True, "filled": True, "status": 0, "same": True}
