"""Tests of the work-precision benchmark harness (mbm/bench.py).

The numba peers must be correct before their timings mean anything: RK4 must
converge at order 4 and the DOP853 error must fall with rtol (and agree with
scipy's DOP853, which follows the same Hairer-Nørsett-Wanner control, step for
step).  The harness must produce the tables, and the selection of the cheapest
point at a target must follow its rule on data whose answer is known.
"""

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mbm import bench

SCENE = bench.SCENES["P2"]  # Example 1: damped, torqued libration, t <= 80


@pytest.fixture(scope="module")
def ref_p2():
    # The CVODE path is enough here (errors of 1e-10 and up are measured) and
    # avoids the fixed-point reference's cost; the fixed-point one is tested below.
    from mbm import reference

    r = reference(SCENE.model, SCENE.t_span, SCENE.y0, t_eval=SCENE.t_eval, rtol=1e-13, atol=1e-13)
    assert r.success
    return r.y[0]


def _fit_order(hs, errs):
    slope, _ = np.polyfit(np.log(hs), np.log(errs), 1)
    return slope


def test_rk4_converges_at_order_4(ref_p2):
    ks = [4, 8, 16, 32]  # steps per output interval 0.4: h = 0.1 ... 0.0125
    errs, hs = [], []
    for k in ks:
        out = bench.rk4_run(SCENE.beta, SCENE.gamma, SCENE.omega ** 2, SCENE.theta0, SCENE.v0,
                            SCENE.dt_out, bench.N_OUTPUT, k)
        errs.append(np.max(np.abs(out[0] - ref_p2)))
        hs.append(SCENE.dt_out / k)
    # all errors well above the reference's ~1e-11 and round-off, so the fit sees RK4
    assert min(errs) > 1e-10
    assert 3.8 < _fit_order(hs, errs) < 4.2


def test_rk4_lands_on_output_times():
    # Sample j must be the state at t = j·dt_out: the same step h = 0.05 sampled
    # every 8 steps (dt_out 0.4) and every 16 steps (dt_out 0.8) must agree on the
    # common times.
    a = bench.rk4_run(0.1, 0.3, 1.0, 0.5, 0.0, 0.4, 11, 8)
    b = bench.rk4_run(0.1, 0.3, 1.0, 0.5, 0.0, 0.8, 6, 16)
    np.testing.assert_allclose(a[:, ::2], b, rtol=0, atol=1e-13)


def test_dop853_error_falls_with_rtol(ref_p2):
    errs = []
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10):
        out = bench.dop853_run(SCENE.beta, SCENE.gamma, SCENE.omega ** 2, SCENE.theta0, SCENE.v0,
                               SCENE.t_eval, rtol, rtol, 10**6)
        errs.append(np.max(np.abs(out[0] - ref_p2)))
    assert all(b < a / 10 for a, b in zip(errs, errs[1:])), errs
    # the error tracks the tolerance: within a factor 100 of rtol at every point
    assert all(e < 100 * r for e, r in zip(errs, (1e-4, 1e-6, 1e-8, 1e-10))), errs


def test_dop853_matches_scipy_step_for_step():
    # Same coefficients, same controller, same initial step: the two must agree to
    # round-off (a wrong coefficient or dense-output row shows up as ~rtol).
    rtol = 1e-7
    out = bench.dop853_run(SCENE.beta, SCENE.gamma, 1.0, SCENE.theta0, SCENE.v0, SCENE.t_eval,
                           rtol, rtol, 10**6)
    fun, _ = bench._python_rhs(SCENE)
    sp = solve_ivp(fun, SCENE.t_span, SCENE.y0, method="DOP853", rtol=rtol, atol=rtol,
                   t_eval=SCENE.t_eval)
    assert np.max(np.abs(out - sp.y)) < 1e-12


def test_dop853_step_budget_leaves_nan():
    out = bench.dop853_run(0.1, 0.3, 1.0, 0.5, 0.0, np.linspace(0.0, 80.0, 5), 1e-10, 1e-10, 3)
    assert np.isfinite(out[:, 0]).all() and np.isnan(out[:, -1]).all()


def test_fixed_point_reference_is_exact_on_undamped_scene():
    # β = γ = 0: compare the fixed-point Taylor integrator with the exact elliptic flow.
    pytest.importorskip("mpmath")
    import mbm

    sc = bench.Scene("T", 0.0, 0.0, 1.0, 0.3, 1.2, 4.0, "test")
    fp = bench.fixed_point_reference(sc)
    exact = mbm.pendulum_flow(sc.model, sc.y0, sc.t_eval)[0]
    assert np.max(np.abs(fp - exact)) < 1e-14


def _pts(*rows):
    return [{"knob": k, "error": e, "time": t, "status": s} for k, e, t, s in rows]


def test_cheapest_at_target_rule():
    pts = _pts(
        (1e-2, 5e-3, 1.0, "ok"),     # misses 1e-3
        (1e-3, 8e-4, 3.0, "ok"),     # reaches 1e-3, not the cheapest that does
        (1e-4, 9e-4, 2.0, "ok"),     # non-monotone sweep: cheaper and still <= 1e-3
        (1e-5, 1e-6, 4.0, "ok"),     # exactly at 1e-6: counts (at or below)
        (1e-6, 1e-9, None, "over budget"),  # not timed: never selected
        (1e-7, 1e-12, 0.5, "failed"),       # failed: never selected
    )
    assert bench.cheapest_at_target(pts, 1e-3)["knob"] == 1e-4
    assert bench.cheapest_at_target(pts, 1e-6)["knob"] == 1e-5
    assert bench.cheapest_at_target(pts, 1e-7) is None
    assert bench.cheapest_at_target([], 1e-3) is None


def test_cells_distinguish_budget_from_not_reached():
    pts = _pts((1e-2, 5e-3, 1e-3, "ok"), (1e-3, 2e-4, 2e-3, "ok"))
    assert bench._cell(pts, 1e-3, ref_time=1e-3) == "2.00 (2×)"
    assert bench._cell(pts, 1e-6, ref_time=None) == "—"
    assert bench._cell(pts + _pts((1e-4, 1e-5, None, "over budget")), 1e-6, None) == "> budget"


def test_run_sweep_stops_on_budget_and_records_failures():
    calls = []

    def run(scene, knob):
        calls.append(knob)
        if knob == 2:
            raise RuntimeError("boom")
        if knob == 4:
            import time

            time.sleep(0.05)
        return np.full(3, 1.0 / knob)

    s = bench.Solver("fake", "peer", False, "rtol", run, (1, 2, 3, 4, 5), (1,), "")
    pts = bench.run_sweep(s, SCENE, np.zeros(3), repeats=2, max_seconds=0.02)
    assert [p["status"] for p in pts] == ["ok", "failed", "ok", "over budget"]
    assert 5 not in calls  # stopped after the over-budget point
    assert pts[1]["message"].startswith("RuntimeError: boom")
    assert pts[0]["error"] == 1.0 and len(pts[0]["times"]) == 2 and pts[0]["time"] is not None
    assert pts[3]["time"] is None


def test_quick_harness_produces_tables(tmp_path):
    out = tmp_path / "bench.md"
    js = tmp_path / "bench.json"
    rc = bench.main(["--scenes", "P1", "--quick", "--out", str(out), "--json", str(js),
                     "--cache", str(tmp_path / "cache")])
    assert rc == 0
    text = out.read_text()
    for target in ("1e-03", "1e-06", "1e-09"):
        assert f"## Target error {target}" in text
    assert "| solver | P1 |" in text
    # one row per registered solver in each table, with a time in the MBM rows
    solvers, _ = bench.solver_registry()
    for s in solvers:
        assert f"| {s.name} |" in text
    # P1 at 1e-3: the fixed-τ Taylor MBM reaches it at its first window (1e-14 at τ = 1),
    # and the best MBM row carries the ratio 1
    table = text.split("## Target error 1e-03")[1].split("## Target error 1e-06")[0]
    row = next(line for line in table.splitlines() if line.startswith("| MBM taylor (τ) |"))
    assert float(row.split("|")[2].split("(")[0]) > 0
    assert "(1×)" in table
    assert "## Machine" in text and "scipy" in text and "scikit-sundae" in text
    assert "## First-call overhead" in text
    import json

    data = json.loads(js.read_text())
    assert data["settings"]["quick"] is True and data["scenes"] == ["P1"]
    # the reference was cached
    assert list((tmp_path / "cache").glob("ref_P1_*.npz"))
    # the saved points render the same tables again without running anything
    out2 = tmp_path / "again.md"
    assert bench.main(["--from-json", str(js), "--out", str(out2)]) == 0
    tables = lambda t: t.split("## Target error", 1)[1].split("## First-call")[0]  # noqa: E731
    assert tables(out2.read_text()) == tables(text)


def test_cli_rejects_unknown_scene():
    with pytest.raises(SystemExit):
        bench.main(["--scenes", "P9", "--quick"])


def test_scenes_match_the_issue():
    p = bench.SCENES
    assert (p["P1"].beta, p["P1"].gamma, p["P1"].theta0, p["P1"].v0, p["P1"].t_end) == (0.4, 0.0, 0.0, 0.25, 20)
    assert math.isclose(p["P2"].theta0, math.radians(30)) and p["P2"].t_end == 80
    assert math.isclose(p["P3"].theta0, math.pi / 2) and p["P3"].gamma == 0.6
    assert (p["P4"].beta, p["P4"].gamma, p["P4"].theta0, p["P4"].t_end) == (0.01, 0.3, 1.0, 1e4)
    assert (p["P5"].gamma, p["P5"].t_end) == (1.2, 1000)
    assert (p["P6"].beta, p["P6"].gamma, p["P6"].v0, p["P6"].t_end) == (0.0, 0.0, 1.999, 200)


def test_scene_inputs_are_built_once():
    # Timed calls get ready inputs: the same objects each time.
    sc = dataclasses.replace(bench.SCENES["P1"])
    assert sc.t_eval is sc.t_eval and sc.y0 is sc.y0 and sc.model is sc.model
    assert np.array_equal(sc.t_eval, np.linspace(0.0, 20.0, bench.N_OUTPUT))
    assert dataclasses.astuple(sc) == dataclasses.astuple(bench.SCENES["P1"])


def test_runners_leave_scene_inputs_unchanged():
    # The shared inputs stay valid only if no solver writes into them.
    sc = dataclasses.replace(bench.SCENES["P1"])
    t_eval, y0 = sc.t_eval.copy(), sc.y0.copy()
    solvers, _ = bench.solver_registry()
    for solver in solvers:
        theta = solver.run(sc, solver.quick_sweep[0])
        assert np.asarray(theta).shape == (bench.N_OUTPUT,), solver.name
        assert np.array_equal(sc.t_eval, t_eval) and np.array_equal(sc.y0, y0), solver.name


def test_reference_without_mpmath_falls_back_to_cvode_and_flags(monkeypatch):
    import sys

    monkeypatch.setitem(sys.modules, "mpmath", None)  # import mpmath -> ImportError
    ref = bench.scene_reference(bench.SCENES["P1"], cache_dir=False)
    assert ref["method"].startswith("CVODE") and ref["check_method"].startswith("numba DOP853")
    # the CVODE reference's own error (~1e-12 on P1) is measured by its check
    assert 0 < ref["uncertainty"] == ref["check"] < 1e-10
    # a reference no better than 1e-9 makes the 1e-9 column flagged, the others not
    result = {"scenes": ["P1"], "solvers": {"x": {"family": "mbm"}},
              "points": {"P1": {"x": _pts((1.0, 1e-10, 1e-3, "ok"))}},
              "references": {"P1": {"uncertainty": 1e-9}}}
    assert bench._target_table(result, 1e-9, ["x"], "mbm")[1]
    assert not bench._target_table(result, 1e-6, ["x"], "mbm")[1]


def test_run_benchmark_draws_progress_over_scene_solver_pairs(tmp_path):
    import io

    buf = io.StringIO()
    res = bench.run_benchmark(scenes=["P1"], quick=True, solver_filter=["numba RK4", "scipy RK45"],
                              cache_dir=tmp_path, show_progress=buf)
    assert sorted(res["points"]["P1"]) == ["numba RK4", "scipy RK45"]
    text = buf.getvalue()
    assert "bench [" in text and text.rstrip().split("\r")[-1].count("2/2") == 1
    assert text.endswith("\n")
