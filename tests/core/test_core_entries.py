"""The loop's entries per (kind, regime set): the table, the dispatch, and what a first call compiles."""

import itertools
import json
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

import mbm
from mbm.frontends import dense
from mbm.frontends import solve as fast
from mbm.core import chains, loop, record, window
from mbm.core.controller import CONTROLLER_ADAPTIVE, CONTROLLER_FIXED
from mbm.status import STATUS_ANCHOR, STATUS_OK, STATUS_PAUSED
from mbm.regimes import (
    REGIME_LIBRATION,
    REGIME_LOCKED,
    REGIME_NONE,
    REGIME_PHASE_LOCKED,
    REGIME_RUNNING,
)

ROOT = Path(__file__).resolve().parents[2]
KINDS = (window.KIND_TAYLOR, window.KIND_EXACT, window.KIND_SALAS_TORQUE, window.KIND_SPLIT)
REGIMES = (REGIME_NONE, REGIME_LOCKED, REGIME_RUNNING, REGIME_LIBRATION, REGIME_PHASE_LOCKED)


def test_every_record_has_an_entry_and_a_dense_evaluator():
    # regime_set over every combination of the fields it reads lands in the table
    for kind, ctl, regimes, beta, amp, regime in itertools.product(
            KINDS, (CONTROLLER_FIXED, CONTROLLER_ADAPTIVE), (0, 1), (-0.1, 0.0, 0.1), (0.0, 0.5),
            REGIMES):
        if regime == REGIME_PHASE_LOCKED and kind != window.KIND_TAYLOR:
            continue  # only Taylor integrates a drive, so only it can phase-lock
        rset = loop.regime_set.py_func(kind, ctl, regimes, beta, amp, regime)
        assert (kind, rset) in loop.RUN_TABLE
        assert (kind, rset) in loop.RUNNERS
        assert (kind, dense.dense_set(regime)) in dense.DENSE_TABLE or kind in (window.KIND_EXACT,
                                                                             window.KIND_SALAS_TORQUE)
    assert set(loop.RUNNERS) == set(loop.RUN_TABLE)


def test_regime_sets_of_the_scene_classes():
    rs = loop.regime_set.py_func
    T, A = window.KIND_TAYLOR, CONTROLLER_ADAPTIVE
    assert rs(T, A, 1, 0.1, 0.0, REGIME_NONE) == loop.RS_DAMPED
    assert rs(T, A, 1, 0.1, 0.0, REGIME_LOCKED) == loop.RS_DAMPED  # the locked window is the set's own
    assert rs(T, A, 1, 0.1, 0.0, REGIME_RUNNING) == loop.RS_CYCLE
    assert rs(T, A, 1, 0.0, 0.0, REGIME_NONE) == loop.RS_CONSERVATIVE
    assert rs(T, A, 1, 0.0, 0.0, REGIME_LIBRATION) == loop.RS_CYCLE
    assert rs(T, A, 1, 0.1, 0.5, REGIME_NONE) == loop.RS_DRIVEN
    assert rs(T, A, 1, 0.1, 0.5, REGIME_PHASE_LOCKED) == loop.RS_STROBE
    assert rs(T, A, 0, 0.1, 0.0, REGIME_NONE) == loop.RS_PLAIN  # regimes off
    assert rs(T, CONTROLLER_FIXED, 1, 0.1, 0.0, REGIME_NONE) == loop.RS_FIXED  # fixed windows
    assert rs(window.KIND_SPLIT, CONTROLLER_FIXED, 0, -0.1, 0.0, REGIME_NONE) == loop.RS_FIXED
    assert rs(T, CONTROLLER_FIXED, 1, 0.1, 0.5, REGIME_NONE) == loop.RS_DRIVEN  # a drive's own anchor
    assert rs(T, A, 1, -0.1, 0.0, REGIME_NONE) == loop.RS_PLAIN  # β < 0: no regime applies
    assert rs(window.KIND_SALAS_TORQUE, CONTROLLER_FIXED, 1, 0.1, 0.0, REGIME_NONE) == loop.RS_FIXED  # no estimate: fixed windows


def test_an_entry_called_for_another_set_pauses_and_run_resumes_through_the_right_one():
    # a record in the running cycle handed to the damped entry: no window of the wrong
    # kind is taken (it pauses at once), and loop.run takes the cycle entry
    model, y0, span = mbm.Pendulum(0.1, 1.2), [0.0, 0.0], (0.0, 600.0)
    te = np.linspace(*span, 7)
    want = mbm.solve(model, span, y0, rtol=1e-8, atol=1e-8, t_eval=te)
    assert want.regime == "running"
    ig = mbm.Integrator(model, rtol=1e-8, atol=1e-8)
    p = np.array(ig._words.copy().view(record.RUN))
    f = record.flat(p)
    f[0]["t"], f[0]["theta"], f[0]["v"], f[0]["t_bound"] = span[0], y0[0], y0[1], span[1]
    f[0]["call_windows"] = 0
    out = np.empty((2, te.size))
    args = (te, out, np.empty(0), np.empty((0, 2)), np.empty((0, 0)), np.zeros(1, np.int64))
    n = loop.run(p, *args)
    assert f[0]["status"] == STATUS_OK and f[0]["regime"] == REGIME_RUNNING
    np.testing.assert_array_equal(out, want.y)
    assert n == want.n_windows
    # now rewound to just after the switch: the damped entry refuses to go on
    damped = loop.RUNNERS[(window.KIND_TAYLOR, loop.RS_DAMPED)]
    p2 = p.copy()
    f2 = record.flat(p2)
    f2[0]["status"] = STATUS_OK
    f2[0]["t_bound"] = span[1] + 10.0
    no_start, arrays = (0.0, 0.0, 0.0, 0.0, 0.0), (np.empty(0), np.empty((2, 0)), *args[2:])
    assert damped(record.words_of(p2), False, no_start, arrays) == 0
    assert f2[0]["status"] == STATUS_PAUSED and f2[0]["t"] == f[0]["t"]


def test_an_unknown_kind_is_a_status():
    p = mbm.Integrator(mbm.Pendulum(0.1, 0.3))._words.copy().view(record.RUN)
    f = record.flat(p)
    f[0]["kind"] = 99
    assert loop.run(p, np.empty(0), np.empty((2, 0)), np.empty(0), np.empty((0, 2)), np.empty((0, 0)),
                    np.zeros(1, np.int64)) == 0
    assert f[0]["status"] == STATUS_ANCHOR


_COMPILED = textwrap.dedent("""
    import json, math, sys
    import numpy as np
    from numba.core import event
    names = set()
    class L(event.Listener):
        def on_start(self, ev):
            f = ev.data["dispatcher"].py_func
            names.add(f.__module__ + "." + f.__qualname__)
        def on_end(self, ev):
            pass
    event.register("numba:compile", L())
    import mbm
    from scipy.integrate import solve_ivp
    m = mbm.Pendulum(beta=0.1, gamma=0.3)
    t = np.linspace(0.0, 80.0, 201)
    if sys.argv[1] == "solve":
        mbm.solve(m, (0.0, 80.0), [math.radians(30), 0.0], rtol=1e-9, atol=1e-9, t_eval=t)
    elif sys.argv[1] == "fixed":
        mbm.solve(m, (0.0, 80.0), [math.radians(30), 0.0], tau=0.5, t_eval=t)
    elif sys.argv[1] == "split":
        solve_ivp(m, (0.0, 80.0), [math.radians(30), 0.0], method=mbm.MBM, approximant="split4", rtol=1e-9,
                  atol=1e-9, t_eval=t)
    elif sys.argv[1] == "split_after":
        solve_ivp(m, (0.0, 80.0), [math.radians(30), 0.0], method=mbm.MBM, rtol=1e-9, atol=1e-9, t_eval=t,
                  dense_output=True)
        names.clear()
        sol = solve_ivp(m, (0.0, 80.0), [math.radians(30), 0.0], method=mbm.MBM, approximant="split4",
                        rtol=1e-9, atol=1e-9, t_eval=t, dense_output=True)
        sol.sol(np.linspace(10.0, 70.0, 7))
    elif sys.argv[1] == "running":
        res = mbm.solve(mbm.Pendulum(beta=0.1, gamma=1.2), (0.0, 400.0), [0.0, 0.0], rtol=1e-9, atol=1e-9,
                        t_eval=np.linspace(0.0, 400.0, 201))
        assert res.regime == "running", res.regime
        sol = solve_ivp(mbm.Pendulum(beta=0.1, gamma=1.2), (0.0, 400.0), [0.0, 0.0], method=mbm.MBM, rtol=1e-9,
                        atol=1e-9, t_eval=np.linspace(0.0, 400.0, 201), dense_output=True)
        sol.sol(np.linspace(300.0, 400.0, 7))
    else:
        solve_ivp(m, (0.0, 80.0), [math.radians(30), 0.0], method=mbm.MBM, approximant="salas-torque",
                  tau=0.25, t_eval=t, dense_output=True)
    print(json.dumps(sorted(names)))
""")

# Kernels an undriven damped scene can never use (the drive, the libration) or uses
# only after a switch to a stored period (its windows), and the dense output's store.
NOT_FOR_DAMPED = ("_strobe", "taylor_driven_coefficients_into", "libration_period", "_period_windows",
                  "mbm.frontends.dense.")
# Every regime's kernels: a fixed-window kind takes none.
REGIME_KERNELS = NOT_FOR_DAMPED + ("locked_choice", "cycle_crossing", "locked_quick_reject", "_lock_setup",
                                  "_form_damped")


def _compiled_names(which, tmp_path):
    # (no compile helper: a kernel it compiled first would be loaded, not compiled, here)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), MBM_COMPILE_NOTICE="0", MBM_COMPILE_HELPER="0")
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
    proc = subprocess.run([sys.executable, "-c", _COMPILED, which], env=env, cwd=ROOT, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_first_solve_of_a_damped_scene_compiles_only_its_regimes(tmp_path):
    names = _compiled_names("solve", tmp_path)
    assert any("run_entry" in n for n in names) and any("cycle_crossing" in n for n in names)
    assert any("locked_choice" in n for n in names)
    assert [n for n in names if any(k in n for k in NOT_FOR_DAMPED)] == []
    # the default degree's entry anchors with the vector kernel alone (loop.SIMD_RUNNERS)
    assert not any("series_loop" in n for n in names)


def test_first_call_of_a_fixed_window_kind_compiles_no_regime(tmp_path):
    names = _compiled_names("salas", tmp_path)
    assert any("salas_torque_anchor" in n for n in names)
    assert [n for n in names if any(k in n for k in REGIME_KERNELS) and "mbm.frontends.dense." not in n] == []
    assert not any("_period" in n or "_strobe" in n for n in names)


def test_a_splitting_s_estimate_compiles_no_loop_form_of_the_taylor_recurrence(tmp_path):
    # Its reference solution takes the default degree's vector kernel, which a default
    # Taylor run has compiled already (splitting.SPLIT_ERROR_TAYLOR_DEGREE).
    names = _compiled_names("split", tmp_path)
    assert any("split_error_kernel" in n for n in names)
    assert any("taylor24_coefficients_into" in n for n in names)
    assert not any("series_loop" in n or n.endswith(".taylor_coefficients") for n in names)


def test_a_further_kind_compiles_only_its_own_pieces(tmp_path):
    # After a default Taylor solve_ivp, split4's solve_ivp with its dense output takes the
    # same loop entry and dense entry (the kind read at run time, its pieces called
    # through mbm.core.kind_ops' table): it compiles its formulas and its controller's
    # first window (a rejection's retries only when one is rejected), and no entry of the
    # loop or the dense output, and no regime's piece (the crossing: at a crossing only).
    names = _compiled_names("split_after", tmp_path)
    assert any("split_eval_kernel" in n for n in names) and any("first_window" in n for n in names)
    assert any("kind_ops._split_anchor" in n for n in names)
    assert [n for n in names if any(k in n for k in ("run_entry", "mbm.frontends.dense.", "mbm.core.loop", "mbm.regimes."))] == []


# The other kinds' formulas (a Taylor run compiles none of them).
OTHER_KINDS = ("splitting.", "salas2022", "belendez2007", "weierstrass", "pendulum_flow", "jacobi_kernels")


def test_a_taylor_run_that_reaches_the_running_cycle_compiles_no_other_kind(tmp_path):
    # mbm.solve and solve_ivp with its dense output: the stored period's windows re-taken
    # at the default degree by the vector kernel alone, no loop form of the recurrence
    names = _compiled_names("running", tmp_path)
    assert any("refine_period" in n for n in names) and any("period_windows" in n for n in names)
    assert any("mbm.frontends.dense." in n for n in names)
    assert [n for n in names if any(k in n for k in OTHER_KINDS)] == []
    assert not any("series_loop" in n for n in names)


# The adaptive controller's kernels and the locked window.
ADAPTIVE_KERNELS = ("first_window", "adaptive_window", "_accepted_factor", "accept_try", "taylor_error_kernel")
LOCKED_WINDOW = ("locked_coef", "locked_eval")


def test_first_fixed_window_taylor_run_compiles_no_controller_and_no_regime(tmp_path):
    # τ given: the RS_FIXED entry, fixed windows only
    names = _compiled_names("fixed", tmp_path)
    assert any("run_entry" in n for n in names) and any("taylor24_coefficients_into" in n for n in names)
    assert [n for n in names if any(k in n for k in ADAPTIVE_KERNELS + LOCKED_WINDOW + REGIME_KERNELS)] == []
    assert not any("series_loop" in n for n in names)  # the default degree: the vector kernel alone


@pytest.mark.parametrize("regime,want", [(REGIME_NONE, loop.RS_PLAIN), (REGIME_LOCKED, loop.RS_PLAIN),
                                          (REGIME_RUNNING, loop.RS_CYCLE), (REGIME_LIBRATION, loop.RS_CYCLE),
                                          (REGIME_PHASE_LOCKED, loop.RS_STROBE)])
def test_dense_set_of_a_regime(regime, want):
    assert dense.dense_set(regime) == want


def test_a_dense_entry_without_a_stored_period_gives_nan_for_its_window():
    # a cycle window handed to the plain evaluator is NaN, never another formula
    model, y0, span = mbm.Pendulum(0.1, 1.2), [0.0, 0.0], (0.0, 600.0)
    from scipy.integrate import solve_ivp

    sol = solve_ivp(model, span, y0, method=mbm.MBM, rtol=1e-8, atol=1e-8, dense_output=True)
    last = sol.sol.interpolants[-1]
    assert int(last.coefs[0, 0]) == 102  # regimes.CYCLE_TAG
    into, _ = dense.evaluators(window.KIND_TAYLOR, loop.RS_PLAIN)
    out = np.empty((2, 1))
    into(window.KIND_TAYLOR, last.starts, last.start_theta, last.coefs, last.n, last.direction,
         np.array([last.t]), out)
    assert np.isnan(out).all()
    np.testing.assert_array_equal(last(np.array([last.t])).ravel(), sol.y[:, -1])


def test_first_calls_page_is_a_quotable_block():
    from benchmarks import first_calls
    from benchmarks.report import extract_blocks

    page = first_calls.format_table([("a", [2.0, None, 4.0]), ("b", [None])], 3, "test machine")
    body = extract_blocks(page)[first_calls.BLOCK_NAME]
    assert "| a | 3.0 |" in body and "| b | failed |" in body and "test machine" in page


def test_the_default_degree_takes_its_own_entry_and_other_degrees_the_general_one():
    for name, table in (("taylor", loop.SIMD_RUNNERS), ("taylor24", loop.SIMD_RUNNERS), ("taylor16", None)):
        ig = mbm.Integrator(mbm.Pendulum(0.1, 0.3), approximant=name)
        want = table[loop.RS_DAMPED] if table else loop.RUNNERS[(window.KIND_TAYLOR, loop.RS_DAMPED)]
        assert ig._entry is want
    assert loop.entry_for(window.KIND_SPLIT, loop.RS_DAMPED, 24) is loop.RUNNERS[(window.KIND_SPLIT, loop.RS_DAMPED)]
    assert loop.entry_for(window.KIND_EXACT, loop.RS_DAMPED, 0) is None  # no such pair
    assert set(loop.SIMD_RUNNERS) == {s for k, s in loop.RUN_TABLE if k == window.KIND_TAYLOR}


def _entry_outputs(entry, model, y0, span, te, **kw):
    ig = mbm.Integrator(model, rtol=1e-9, atol=1e-9, **kw)
    p = np.array(ig._words.copy().view(record.RUN))
    f = record.flat(p)
    f[0]["t"], f[0]["theta"], f[0]["v"], f[0]["t_bound"] = span[0], y0[0], y0[1], span[1]
    f[0]["call_windows"] = 0
    out = np.empty((2, te.size))
    n = entry(record.words_of(p), False, (0.0, 0.0, 0.0, 0.0, 0.0),
              (te, out, np.empty(0), np.empty((0, 2)), np.empty((0, 0)), np.zeros(1, np.int64)))
    return int(f[0]["status"]), n, out


@pytest.mark.parametrize("rset,model", [(loop.RS_DAMPED, mbm.Pendulum(0.1, 0.3)),
                                        (loop.RS_DRIVEN, mbm.Pendulum(0.1, 0.3, drive_amplitude=0.4,
                                                                      drive_frequency=0.7))])
def test_the_default_degree_entry_gives_the_general_entry_s_answers_bit_for_bit(rset, model):
    span, y0 = (0.0, 40.0), [0.5, 0.0]
    te = np.linspace(*span, 57)
    simd = _entry_outputs(loop.SIMD_RUNNERS[rset], model, y0, span, te)
    general = _entry_outputs(loop.RUNNERS[(window.KIND_TAYLOR, rset)], model, y0, span, te)
    assert simd[0] == STATUS_OK and simd[1] > 5
    assert simd[:2] == general[:2]
    np.testing.assert_array_equal(simd[2], general[2])


def test_the_default_degree_entry_refuses_another_degree_with_a_status():
    # handed a degree-16 record (bypassing entry_for) it anchors nothing: STATUS_ANCHOR
    status, n, _ = _entry_outputs(loop.SIMD_RUNNERS[loop.RS_DAMPED], mbm.Pendulum(0.1, 0.3), [0.5, 0.0],
                                  (0.0, 10.0), np.empty(0), approximant="taylor16")
    assert status == STATUS_ANCHOR and n == 0


def test_solve_njit_runs_the_default_degree_that_run_taylor_compiles():
    # chains.run_taylor compiles the default degree's entries alone (F_TAYLOR_SIMD)
    from mbm.approximants.taylor_simd import SIMD_ORDER

    assert fast._AUTO_TAYLOR == (window.KIND_TAYLOR, SIMD_ORDER)
    t = np.array([5.0])
    out = np.empty((2, 1))
    status, n = mbm.solve_njit(0.1, 0.3, 1.0, 0.0, 0.5, 0.0, 5.0, t, out, 1e-8, 1e-8, 10**6)
    want = mbm.solve(mbm.Pendulum(0.1, 0.3), (0.0, 5.0), [0.5, 0.0], t_eval=t, rtol=1e-8, atol=1e-8)
    assert status == 0 and n == want.n_windows
    np.testing.assert_array_equal(out, want.y)
