"""Tests of the work-precision benchmark (the root package ``benchmarks``).

The peers must be correct before their timings mean anything: RK4 must converge at
order 4, the DOP853 error must fall with rtol (and agree with scipy's DOP853, which
follows the same Hairer-Nørsett-Wanner control, step for step), heyoka's error must
fall with its tolerance, and its prepared integrator must give the same answer
however often it is reused.  The references must agree with each other.  The harness
must produce the tables, and the selection of the cheapest point at a target must
follow its rule on data whose answer is known.
"""

import dataclasses
import io
import json
import math
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from benchmarks import harness, peers, references, registry, report
from benchmarks.__main__ import main
from benchmarks.scenes import N_OUTPUT, SCENES, BenchScene

SCENE = SCENES["P2"]  # Example 1: damped, torqued libration, t <= 80


@pytest.fixture(scope="module")
def ref_p2():
    # The CVODE path is enough here (errors of 1e-10 and up are measured) and
    # avoids the fixed-point reference's cost; the fixed-point one is tested below.
    r = mbm.reference(SCENE.model, SCENE.t_span, SCENE.y0, t_eval=SCENE.t_eval, rtol=1e-13,
                      atol=1e-13)
    assert r.success
    return r.y[0]


def _fit_order(hs, errs):
    slope, _ = np.polyfit(np.log(hs), np.log(errs), 1)
    return slope


# --------------------------------------------------------------------------- numba peers


def test_rk4_converges_at_order_4(ref_p2):
    ks = [4, 8, 16, 32]  # steps per output interval 0.4: h = 0.1 ... 0.0125
    errs, hs = [], []
    for k in ks:
        out = peers.rk4_run(SCENE.beta, SCENE.gamma, SCENE.omega ** 2, SCENE.theta0, SCENE.v0,
                            SCENE.dt_out, N_OUTPUT, k)
        errs.append(np.max(np.abs(out[0] - ref_p2)))
        hs.append(SCENE.dt_out / k)
    # all errors well above the reference's ~1e-11 and round-off, so the fit sees RK4
    assert min(errs) > 1e-10
    assert 3.8 < _fit_order(hs, errs) < 4.2


def test_rk4_lands_on_output_times():
    # Sample j must be the state at t = j·dt_out: the same step h = 0.05 sampled
    # every 8 steps (dt_out 0.4) and every 16 steps (dt_out 0.8) must agree on the
    # common times.
    a = peers.rk4_run(0.1, 0.3, 1.0, 0.5, 0.0, 0.4, 11, 8)
    b = peers.rk4_run(0.1, 0.3, 1.0, 0.5, 0.0, 0.8, 6, 16)
    np.testing.assert_allclose(a[:, ::2], b, rtol=0, atol=1e-13)


def test_dop853_error_falls_with_rtol(ref_p2):
    errs = []
    for rtol in (1e-4, 1e-6, 1e-8, 1e-10):
        out = peers.dop853_run(SCENE.beta, SCENE.gamma, SCENE.omega ** 2, SCENE.theta0, SCENE.v0,
                               SCENE.t_eval, rtol, rtol, 10**6)
        errs.append(np.max(np.abs(out[0] - ref_p2)))
    assert all(b < a / 10 for a, b in zip(errs, errs[1:])), errs
    # the error tracks the tolerance: within a factor 100 of rtol at every point
    assert all(e < 100 * r for e, r in zip(errs, (1e-4, 1e-6, 1e-8, 1e-10))), errs


def test_dop853_matches_scipy_step_for_step():
    # Same coefficients, same controller, same initial step: the two must agree to
    # round-off (a wrong coefficient or dense-output row shows up as ~rtol).
    rtol = 1e-7
    out = peers.dop853_run(SCENE.beta, SCENE.gamma, 1.0, SCENE.theta0, SCENE.v0, SCENE.t_eval,
                           rtol, rtol, 10**6)
    fun, _ = peers.python_rhs(SCENE)
    sp = solve_ivp(fun, SCENE.t_span, SCENE.y0, method="DOP853", rtol=rtol, atol=rtol,
                   t_eval=SCENE.t_eval)
    assert np.max(np.abs(out - sp.y)) < 1e-12


def test_dop853_step_budget_leaves_nan():
    out = peers.dop853_run(0.1, 0.3, 1.0, 0.5, 0.0, np.linspace(0.0, 80.0, 5), 1e-10, 1e-10, 3)
    assert np.isfinite(out[:, 0]).all() and np.isnan(out[:, -1]).all()


# --------------------------------------------------------------------------- heyoka


def test_heyoka_error_falls_with_tol(ref_p2):
    hy = peers.HeyokaPeer()
    errs = [np.max(np.abs(hy.run(SCENE, tol) - ref_p2)) for tol in (1e-4, 1e-6, 1e-8)]
    assert all(b < a / 10 for a, b in zip(errs, errs[1:])), errs
    # measured 7.8e-6, 9.6e-8, 8.4e-11: below the tolerance at every point
    assert all(e < tol for e, tol in zip(errs, (1e-4, 1e-6, 1e-8))), errs


def test_heyoka_integrator_is_built_once_and_reused():
    # One integrator per tolerance serves every scene: a run resets time, state and
    # parameters, so reuse (any order, any scene) gives exactly a fresh run's answer.
    hy = peers.HeyokaPeer()
    p1, p2 = SCENES["P1"], SCENES["P2"]
    a = hy.run(p2, 1e-9)
    ta = hy.integrator(1e-9)
    b = hy.run(p1, 1e-9)
    c = hy.run(p2, 1e-9)
    assert hy.integrator(1e-9) is ta and list(hy.build_seconds) == [1e-9]
    assert hy.build_seconds[1e-9] > 0
    np.testing.assert_array_equal(a, c)
    np.testing.assert_array_equal(b, peers.HeyokaPeer().run(p1, 1e-9))
    assert a.shape == (N_OUTPUT,) and np.isfinite(a).all()


def test_heyoka_batch_matches_scalar():
    batch = peers.HeyokaBatch()
    gammas = np.linspace(0.0, 2.0, batch.batch_size + 3)  # a padded last group
    t_eval = np.array([0.0, 25.0, 50.0])
    got = batch.theta(0.1, gammas, 1.0, [0.0, 0.0], t_eval, 1e-10)
    scalar = peers.HeyokaPeer()
    want = np.array([scalar.propagate(BenchScene.from_params("iv", 0.1, g, 1.0, 0.0, 0.0, 50.0),
                                      1e-10, t_eval)[:, 0] for g in gammas])
    assert got.shape == (gammas.size, 3)
    # per-lane steps as the scalar integrator's: the same answer to round-off
    assert np.max(np.abs(got - want)) < 1e-10


def test_heyoka_entry_prepares_apart_from_timing():
    solvers, _, missing = registry.solver_registry()
    hy = next(s for s in solvers if s.name == "heyoka")
    assert "heyoka" not in missing and hy.compiled and hy.knob == "tol" and hy.prepare
    pts = harness.run_sweep(hy, SCENES["P1"], np.zeros(N_OUTPUT), repeats=2, quick=True)
    assert len(pts) == 3 and all(p["status"] == "ok" for p in pts)
    # the build is recorded with the point, the timed runs are warm runs of the prepared integrator
    assert all("prepare" in p for p in pts) and all(p["time"] is not None for p in pts)


def test_registry_without_heyoka_says_so(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "heyoka", None)  # import heyoka -> ImportError
    solvers, notes, missing = registry.solver_registry()
    assert "heyoka" not in [s.name for s in solvers]
    assert "heyoka" in missing and any("heyoka is not installed" in n for n in notes)
    res = harness.run_benchmark(scenes=["P1"], quick=True, solver_filter=["numba RK4", "heyoka"],
                                cache_dir=tmp_path, show_progress=False)
    assert res["missing"] == {"heyoka": missing["heyoka"]}
    text = report.format_report(res)
    assert "| heyoka | n/a |" in text and "heyoka is not installed" in text


# --------------------------------------------------------------------------- references


def test_fixed_point_reference_is_exact_on_undamped_scene():
    # β = γ = 0: compare the fixed-point Taylor integrator with the exact elliptic flow.
    sc = BenchScene.from_params("T", 0.0, 0.0, 1.0, 0.3, 1.2, 4.0, "test")
    fp = references.fixed_point_reference(sc)
    exact = mbm.pendulum_flow(sc.model, sc.y0, sc.t_eval)[0]
    assert np.max(np.abs(fp - exact)) < 1e-14


def test_fixed_point_step_matches_the_tests_copy():
    # tests/data carries its own copy of the fixed-point step (test data does not
    # import the benchmark): the two must give the same integers.
    from convergent_fixed_point import _constants, _step

    from fractions import Fraction

    h = Fraction(1, 16)
    cst = _constants(0.1, 1.2, 1.0, h)
    X = V = 1 << 127
    for degree in (12, 28):
        assert references._fp_step(X, V, cst, degree) == _step(X, V, h, cst, degree)


def test_heyoka_long_double_reference_matches_fixed_point():
    assert references.heyoka_ld_available()
    sc = BenchScene(SCENE.scene.until(8.0))
    fp = references.fixed_point_reference(sc)
    ld = references.heyoka_ld_reference(sc)
    assert np.max(np.abs(ld - fp)) < 1e-15


def test_reference_methods_and_cache(tmp_path):
    sc = SCENES["P1"]
    fp = references.scene_reference(sc, cache_dir=tmp_path)
    ld = references.scene_reference(sc, cache_dir=tmp_path, method="heyoka-ld")
    assert fp["method"].startswith("Taylor degree 28") and ld["method"].startswith("heyoka")
    assert ld["uncertainty"] == 0.0 and ld["check"] < 1e-10
    assert np.max(np.abs(fp["theta"] - ld["theta"])) < 1e-15
    assert len(list(tmp_path.glob("ref_P1_*.npz"))) == 2  # one file per method
    with pytest.raises(ValueError, match="unknown reference method"):
        references.scene_reference(sc, cache_dir=False, method="nope")


def test_reference_without_mpmath_uses_heyoka_long_double(monkeypatch):
    monkeypatch.setitem(sys.modules, "mpmath", None)  # import mpmath -> ImportError
    ref = references.scene_reference(SCENES["P1"], cache_dir=False)
    assert ref["method"].startswith("heyoka long double") and ref["uncertainty"] == 0.0


def test_reference_without_mpmath_falls_back_to_cvode_and_flags(monkeypatch):
    monkeypatch.setitem(sys.modules, "mpmath", None)  # import mpmath -> ImportError
    monkeypatch.setitem(sys.modules, "heyoka", None)
    ref = references.scene_reference(SCENES["P1"], cache_dir=False)
    assert ref["method"].startswith("CVODE") and ref["check_method"].startswith("numba DOP853")
    # the CVODE reference's own error (~1e-12 on P1) is measured by its check
    assert 0 < ref["uncertainty"] == ref["check"] < 1e-10
    # a reference no better than 1e-9 makes the 1e-9 column flagged, the others not
    result = {"scenes": ["P1"], "solvers": {"x": {"family": "mbm"}},
              "points": {"P1": {"x": _pts((1.0, 1e-10, 1e-3, "ok"))}},
              "references": {"P1": {"uncertainty": 1e-9}}}
    assert report._target_table(result, 1e-9, ["x"], "mbm")[1]
    assert not report._target_table(result, 1e-6, ["x"], "mbm")[1]


# --------------------------------------------------------------------------- harness and report


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
    assert harness.cheapest_at_target(pts, 1e-3)["knob"] == 1e-4
    assert harness.cheapest_at_target(pts, 1e-6)["knob"] == 1e-5
    assert harness.cheapest_at_target(pts, 1e-7) is None
    assert harness.cheapest_at_target([], 1e-3) is None


def test_cells_distinguish_budget_from_not_reached():
    pts = _pts((1e-2, 5e-3, 1e-3, "ok"), (1e-3, 2e-4, 2e-3, "ok"))
    assert report._cell(pts, 1e-3, ref_time=1e-3) == "2.00 (2×)"
    assert report._cell(pts, 1e-6, ref_time=None) == "—"
    assert report._cell(pts + _pts((1e-4, 1e-5, None, "over budget")), 1e-6, None) == "> budget"


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

    s = registry.Solver("fake", "peer", False, "rtol", run, (1, 2, 3, 4, 5), (1,), "")
    pts = harness.run_sweep(s, SCENE, np.zeros(3), repeats=2, max_seconds=0.02)
    assert [p["status"] for p in pts] == ["ok", "failed", "ok", "over budget"]
    assert 5 not in calls  # stopped after the over-budget point
    assert pts[1]["message"].startswith("RuntimeError: boom")
    assert pts[0]["error"] == 1.0 and len(pts[0]["times"]) == 2 and pts[0]["time"] is not None
    assert pts[3]["time"] is None


def test_run_sweep_retries_a_warm_up_slowed_by_a_first_call_compile():
    # The first call of a knob pays a compile (as numba's first call of a code path):
    # the warm-up is run again, and the point is timed when that second run is within
    # the budget; a point slow on every call still ends the sweep.
    calls = []

    def run(scene, knob):
        import time

        calls.append(knob)
        if (knob == 2 and calls.count(2) == 1) or knob == 3:
            time.sleep(0.05)
        return np.full(3, 1.0 / knob)

    s = registry.Solver("fake", "peer", False, "rtol", run, (1, 2, 3, 4), (1,), "")
    pts = harness.run_sweep(s, SCENE, np.zeros(3), repeats=2, max_seconds=0.02)
    assert [p["status"] for p in pts] == ["ok", "ok", "over budget"]
    assert "a compile" in pts[1]["message"] and pts[1]["time"] < 0.02
    assert 4 not in calls and calls.count(3) == 2


def test_run_sweep_times_without_the_prepare_step():
    def prepare(knob):
        import time

        time.sleep(0.05)

    s = registry.Solver("fake", "peer", True, "tol", lambda sc, k: np.zeros(3), (1.0,), (1.0,), "",
                        prepare=prepare)
    (p,) = harness.run_sweep(s, SCENE, np.zeros(3), repeats=3, max_seconds=0.02)
    # the slow prepare step neither counts against the budget nor enters the time
    assert p["status"] == "ok" and p["prepare"] >= 0.05 and p["time"] < 0.01


def test_quick_harness_produces_tables(tmp_path):
    out = tmp_path / "bench.md"
    js = tmp_path / "bench.json"
    rc = main(["--scenes", "P1", "--quick", "--out", str(out), "--json", str(js),
               "--cache", str(tmp_path / "cache")])
    assert rc == 0
    text = out.read_text()
    for target in ("1e-03", "1e-06", "1e-09"):
        assert f"## Target error {target}" in text
    assert "| solver | P1 |" in text
    # one row per registered solver in each table, with a time in the MBM rows
    solvers, _, missing = registry.solver_registry()
    for s in solvers:
        assert f"| {s.name} |" in text
    for name in missing:
        assert f"| {name} | n/a |" in text
    # P1 at 1e-3: the fixed-τ Taylor MBM reaches it at its first window (1e-14 at τ = 1),
    # and the best MBM row carries the ratio 1
    table = text.split("## Target error 1e-03")[1].split("## Target error 1e-06")[0]
    row = next(line for line in table.splitlines() if line.startswith("| MBM taylor (τ) |"))
    assert float(row.split("|")[2].split("(")[0]) > 0
    assert "(1×)" in table
    assert "## Machine" in text and "scipy" in text and "scikit-sundae" in text
    assert "## First-call overhead" in text and "| heyoka |" in text
    # the blocks the README quotes are there
    blocks = report.extract_blocks(text)
    assert {"machine", "summary-python-rhs", "summary-compiled", "findings"} <= set(blocks)
    assert "heyoka (prepared integrator)" in blocks["summary-compiled"]
    data = json.loads(js.read_text())
    assert data["settings"]["quick"] is True and data["scenes"] == ["P1"]
    # the reference was cached
    assert list((tmp_path / "cache").glob("ref_P1_*.npz"))
    # the saved points render the same tables again without running anything
    out2 = tmp_path / "again.md"
    assert main(["--from-json", str(js), "--out", str(out2)]) == 0
    tables = lambda t: t.split("## Summary", 1)[1].split("## First-call")[0]  # noqa: E731
    assert tables(out2.read_text()) == tables(text)


def test_cli_rejects_unknown_scene():
    with pytest.raises(SystemExit):
        main(["--scenes", "P9", "--quick"])


def test_scenes_match_the_issue():
    p = SCENES
    assert (p["P1"].beta, p["P1"].gamma, p["P1"].theta0, p["P1"].v0, p["P1"].t_end) == (0.4, 0.0, 0.0, 0.25, 20)
    assert math.isclose(p["P2"].theta0, math.radians(30)) and p["P2"].t_end == 80
    assert math.isclose(p["P3"].theta0, math.pi / 2) and p["P3"].gamma == 0.6
    assert (p["P4"].beta, p["P4"].gamma, p["P4"].theta0, p["P4"].t_end) == (0.01, 0.3, 1.0, 1e4)
    assert (p["P5"].gamma, p["P5"].t_end) == (1.2, 1000)
    assert (p["P6"].beta, p["P6"].gamma, p["P6"].v0, p["P6"].t_end) == (0.0, 0.0, 1.999, 200)
    # the benchmark's scenes are the catalogue's
    assert all(p[n].scene is mbm.scenes.get(n) for n in p)


def test_scene_inputs_are_built_once():
    # Timed calls get ready inputs: the same objects each time.
    sc = dataclasses.replace(SCENES["P1"])
    assert sc.t_eval is sc.t_eval and sc.y0 is sc.y0 and sc.model is sc.model
    assert np.array_equal(sc.t_eval, np.linspace(0.0, 20.0, N_OUTPUT))
    assert dataclasses.astuple(sc) == dataclasses.astuple(SCENES["P1"])


def test_runners_leave_scene_inputs_unchanged():
    # The shared inputs stay valid only if no solver writes into them.
    sc = dataclasses.replace(SCENES["P1"])
    t_eval, y0 = sc.t_eval.copy(), sc.y0.copy()
    solvers, _, _ = registry.solver_registry()
    for solver in solvers:
        theta = solver.run(sc, solver.quick_sweep[0])
        assert np.asarray(theta).shape == (N_OUTPUT,), solver.name
        assert np.array_equal(sc.t_eval, t_eval) and np.array_equal(sc.y0, y0), solver.name


def test_run_benchmark_draws_progress_over_scene_solver_pairs(tmp_path):
    buf = io.StringIO()
    res = harness.run_benchmark(scenes=["P1"], quick=True, solver_filter=["numba RK4", "scipy RK45"],
                                cache_dir=tmp_path, show_progress=buf)
    assert sorted(res["points"]["P1"]) == ["numba RK4", "scipy RK45"]
    text = buf.getvalue()
    assert "bench [" in text and text.rstrip().split("\r")[-1].count("2/2") == 1
    assert text.endswith("\n")


def test_findings_name_winners_and_ratios():
    result = {"scenes": ["P1", "P2"], "settings": {"targets": [1e-6]},
              "solvers": {"peer": {"family": "peer", "compiled": True},
                          "mbm.solve x": {"family": "mbm-compiled", "compiled": True}},
              "points": {"P1": {"peer": _pts((1.0, 1e-7, 2e-3, "ok")),
                                "mbm.solve x": _pts((1.0, 1e-7, 1e-3, "ok"))},
                         "P2": {"peer": _pts((1.0, 1e-7, 1e-3, "ok")),
                                "mbm.solve x": _pts((1.0, 1e-7, 3e-3, "ok"))}}}
    (line,) = report.findings(result)
    assert "faster on P1 2×" in line and "slower on P2 (peer 3× faster)" in line


def test_sync_readme_copies_blocks(tmp_path):
    doc = tmp_path / "docs" / "gen.md"
    doc.parent.mkdir()
    doc.write_text("# x\n\n" + "\n".join(report.block("t", ["| a |", "|---|", "| 1 |"])) + "\n")
    readme = tmp_path / "README.md"
    readme.write_text("intro\n<!-- quote docs/gen.md t -->\nstale\n<!-- /quote -->\nend\n")
    assert main(["readme", "--readme", str(readme), "--check"]) == 1
    assert report.sync_readme(readme) == ["docs/gen.md t"]
    assert readme.read_text() == "intro\n<!-- quote docs/gen.md t -->\n| a |\n|---|\n| 1 |\n<!-- /quote -->\nend\n"
    assert report.sync_readme(readme) == []
    assert main(["readme", "--readme", str(readme), "--check"]) == 0
    readme.write_text("<!-- quote docs/gen.md nope -->\n<!-- /quote -->\n")
    with pytest.raises(KeyError, match="nope"):
        report.sync_readme(readme)
