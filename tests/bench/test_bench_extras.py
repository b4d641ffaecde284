"""Tests of benchmarks/extras.py (undamped t = 1e6, the I–V ensemble, fixed costs), on short runs."""

import math

import numpy as np
import pytest

import mbm
from benchmarks import extras as bx
from benchmarks import harness
from benchmarks.__main__ import main
from benchmarks.registry import RTOL_SWEEP
from benchmarks.report import extract_blocks


def test_undamped_scene_is_the_catalogues():
    sc = mbm.scenes.get("undamped-long")
    assert bx.UNDAMPED is sc
    assert (sc.beta, sc.gamma, sc.omega, sc.theta0, sc.v0, sc.t_end) == (0.0, 0.0, 1.0, 1.0, 0.0, 1e6)


def test_exact_undamped_matches_exact_flow():
    # mpmath's cd formula and the package's exact flow are independent implementations.
    theta0 = bx.UNDAMPED.theta0
    for t in (0.0, 1.3, 50.0, 1234.5):
        th = mbm.pendulum_flow(mbm.Pendulum(), [theta0, 0.0], t)[0]
        assert abs(bx.exact_undamped(theta0, t) - th) <= 1e-13


def test_undamped_quick_rows_and_mbm_most_accurate():
    res = bx.undamped_long_horizon(repeats=1, quick=True)
    names = [r["solver"] for r in res["rows"]]
    assert names[:2] == ["MBM auto, solve_ivp", "MBM auto, mbm.solve"]
    assert "scipy DOP853" in names and names.count("numba DOP853") == len(bx.NUMBA_DOP853_RTOLS)
    assert names.count("heyoka (prepared)") == len(bx.HEYOKA_LONG_TOLS)
    assert sorted(res["builds"]) == sorted(bx.HEYOKA_LONG_TOLS)
    mbm_err = max(r["error"] for r in res["rows"][:2])
    assert mbm_err <= 1e-12
    # MBM's error is below every peer's: the report's ratios are lower bounds at equal error
    assert all(r["error"] >= mbm_err for r in res["rows"][2:])
    assert all(r["seconds"] > 0 for r in res["rows"])


def test_ensemble_quick_picks_knobs_meeting_targets(monkeypatch):
    monkeypatch.setattr(bx, "IV_TARGETS", (1e-3,))
    res = bx.ensemble_iv(n=12, quick=True)
    rows = res["rows"]
    names = {r["solver"] for r in rows}
    batch = next(n for n in names if n.startswith("heyoka batch"))
    assert names == {"mbm.solve_batch", "numba DOP853, looped", "numba RK4, looped",
                     "heyoka scalar, looped", batch}
    for r in rows:
        if r["seconds"] is not None:
            assert r["error"] <= r["target"] and r["per_core"] > 0 and math.isfinite(r["seconds"])
    # heyoka's integrators were built before the timed runs, one per tolerance tried
    assert set(res["builds"]) == {"heyoka scalar, looped", batch}
    assert all(v > 0 for b in res["builds"].values() for v in b.values())
    # scalar and batch heyoka give the same subset errors (same steps per lane)
    sc, bt = res["sweeps"]["heyoka scalar, looped"], res["sweeps"][batch]
    assert [k for k, _ in sc] == [k for k, _ in bt]
    assert all(abs(a - b) <= 1e-9 + 1e-6 * a for (_, a), (_, b) in zip(sc, bt))
    text = bx.format_report(bx.undamped_long_horizon(repeats=1, quick=True), res, {"cpu": "x"}, "cmd")
    assert "## Ensemble" in text and "| 0.001 | mbm.solve_batch |" in text and "cmd" in text
    assert f"| 0.001 | {batch} |" in text and "heyoka integrator builds" in text
    blocks = extract_blocks(text)
    assert {"extras-undamped", "extras-ensemble"} <= set(blocks)


def test_subset_reference_samples_the_right_times():
    sol = mbm.solve(mbm.Pendulum(beta=bx.BETA_IV, gamma=0.3), (0.0, 10.0), [0.0, 0.0],
                    rtol=1e-12, atol=1e-12, t_eval=[0.0, 5.0, 10.0])
    for method in ("fixed-point", "heyoka-ld"):
        ref = bx._subset_reference(np.array([0.3]), 10.0, method)
        np.testing.assert_allclose(ref[0], sol.y[0], atol=1e-10)
    a = bx._subset_reference(np.array([0.3, 1.5]), 10.0, "fixed-point")
    b = bx._subset_reference(np.array([0.3, 1.5]), 10.0, "heyoka-ld")
    assert np.max(np.abs(a - b)) < 1e-15  # two independent references


def test_parallel_baseline_reports_speedup():
    res = bx.parallel_baseline(n=8, work=1000)
    assert res["threads"] >= 1 and res["speedup"] > 0


def test_overheads_section():
    ov = bx.overheads(repeats=2)
    # public calls only: no window, one window, a whole run without and with outputs
    names = list(ov["fixed"]) + list(ov["unavailable"])
    assert len(names) == 6 and all(v > 0 for v in ov["fixed"].values())
    assert not any("mbm.frontends.solve" in n or "._" in n for n in names)  # no internals timed
    assert "mbm.solve, one window" in ov["fixed"]
    assert any(k.startswith("mbm.solve, P1 without outputs") for k in ov["fixed"])
    # the split of the fixed cost: differences of those calls
    assert any(k.startswith("each further window") for k in ov["derived"])
    assert any(k.startswith("each output") for k in ov["derived"])
    # kernel costs: one row per degree; the generic recurrence's anchor is O(N^2), so
    # degree 20 costs more than degree 8 (measured ~2x); degree SIMD_ORDER has its own
    # emitted recurrence and is not compared
    ks = ov["kernels"]
    assert [r["degree"] for r in ks] == list(bx.OVERHEAD_DEGREES)
    by = {r["degree"]: r["anchor_ns"] for r in ks}
    assert by[20] > by[8] > 0 and all(r["output_ns"] > 0 for r in ks)
    rows = ov["degrees"]
    assert [(r["scene"], r["degree"]) for r in rows] == [
        (s, d) for s in ("P1", "P2") for d in bx.OVERHEAD_DEGREES]
    # fewer windows at higher degree (longer windows at the same tolerance)
    p2 = [r["windows"] for r in rows if r["scene"] == "P2"]
    assert p2[0] > p2[-1]
    text = bx.format_overheads(ov)
    assert "| P2 | 24 |" in text and "one window" in text and "| 24 |" in text
    assert "derived: each further window" in text
    assert {"overheads-fixed", "overheads-kernels"} <= set(extract_blocks(text))


def test_round_robin_medians_times_each_call_in_turns():
    order = []
    calls = {"a": lambda: order.append("a"), "b": lambda: order.append("b")}
    med = harness.round_robin_medians(calls, 5, block=2)
    # per turn: one untimed call, then up to `block` timed ones; turns alternate a, b
    # until each has 5 timings
    assert order == ["a"] * 3 + ["b"] * 3 + ["a"] * 3 + ["b"] * 3 + ["a"] * 2 + ["b"] * 2
    assert set(med) == {"a", "b"} and all(v >= 0 for v in med.values())


def test_degrees_at_equal_error_section():
    rows = bx.degrees_at_equal_error(scenes=("P1",), targets=(1e-3, 1e-6), repeats=2)
    assert [r["degree"] for r in rows] == list(bx.OVERHEAD_DEGREES)
    for r in rows:
        for target in (1e-3, 1e-6):
            seconds, rtol = r[target]  # every degree reaches both targets on P1
            assert seconds > 0 and rtol in RTOL_SWEEP
        # every point meeting 1e-6 also meets 1e-3, so 1e-3 is never dearer
        assert r[1e-3][0] <= r[1e-6][0]
    ov = {"fixed": {"x": 1e-6}, "degrees": [], "equal_error": rows}
    text = bx.format_overheads(ov)
    assert "At equal error" in text and "| P1 | 8 |" in text


def test_extras_command_line():
    # `python -m benchmarks extras` is benchmarks.extras.main; its parser rejects bad options.
    with pytest.raises(SystemExit):
        main(["extras", "--repeats", "0"])
    with pytest.raises(SystemExit):
        main(["extras", "--reference", "cvode"])


def test_fixed_cost_per_call_section(tmp_path):
    # benchmarks.overheads: Integrator.solve, mbm.solve and their compiled part, per call.
    from benchmarks import overheads as per_call

    fc = per_call.fixed_costs(repeats=3, block=2)
    names = [r[0] for r in fc["rows"]]
    assert "Integrator.solve, zero-length span (no window)" in names
    assert "compiled entry in a compiled loop, span 1e-9" in names
    assert all(m > 0 and lo > 0 and lo <= m for _, m, lo in fc["rows"])
    assert len(fc["derived"]) == 4 and fc["setup"]["approximant"] == "taylor"
    section = per_call.format_fixed_costs(fc)
    assert per_call.BLOCK_NAME in extract_blocks(section)
    # --update rewrites only its block of a file, or appends the section
    doc = tmp_path / "doc.md"
    doc.write_text("# Title\n\nkept\n")
    per_call.update_file(doc, section)
    once = doc.read_text()
    assert once.startswith("# Title\n\nkept\n") and extract_blocks(once)[per_call.BLOCK_NAME]
    other = per_call.format_fixed_costs(dict(fc, rows=[(n, 1e-6, 1e-6) for n in names]))
    per_call.update_file(doc, other)
    twice = doc.read_text()
    assert twice.count(f"block {per_call.BLOCK_NAME} ") == 1 and "| 1.00 | 1.00 |" in twice
    assert extract_blocks(twice)[per_call.BLOCK_NAME] == extract_blocks(other)[per_call.BLOCK_NAME]
    # the section goes into extras' overheads report when measured there
    assert section in bx.format_overheads({"fixed": {}, "degrees": [], "per_call": fc})
    with pytest.raises(SystemExit):
        main(["overheads", "--repeats", "0"])
