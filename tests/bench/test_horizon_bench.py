"""Tests of benchmarks/horizon_bench.py's comparison with heyoka, on a short horizon."""

import numpy as np

from benchmarks import horizon_bench as hb


def test_heyoka_rows_are_matched_and_rendered():
    key = "conservative trapped (β 0, γ 0.4, θ₀ 0.9)"
    rows = hb.run_heyoka(repeats=1, cases={"libration": (key, (200.0,))})
    (row,) = rows
    assert row["regime"] == "libration" and row["T"] == 200.0
    # The matched tolerance is the loosest of the ladder with an error at most mbm's.
    assert row["heyoka_tol"] in hb.HEYOKA_TOLS
    assert row["heyoka_error"] <= max(row["mbm_error"], hb.MATCH_FLOOR) and row["mbm_error"] <= 1e-9
    looser = [t for t in hb.HEYOKA_TOLS if t > row["heyoka_tol"]]
    assert row["heyoka_best"][1] == row["heyoka_tol"] or not looser
    assert row["mbm_time"] > 0 and row["heyoka_time"] > 0
    text = hb.render([], rows)
    assert "## Against heyoka at matched error" in text
    line = [ln for ln in text.splitlines() if ln.startswith("| libration |")][0]
    ratio = float(line.rstrip(" |").split("|")[-1])
    assert abs(ratio - row["heyoka_time"] / row["mbm_time"]) <= 0.051  # printed to 0.1


def test_unmatched_heyoka_is_said_so():
    rows = [{"case": "x", "T": 1e6, "regime": None, "mbm_error": 1e-20, "mbm_time": 1e-3,
             "heyoka_tol": None, "heyoka_best": (3e-12, 1e-15), "heyoka_error": 3e-12, "heyoka_time": 2e-3}]
    text = hb.render([], rows)
    assert "| none matched: best 1e-15 | 3.0e-12 | 2.000 | ≥ 2.0 |" in text


def test_driven_rows_are_matched():
    case = {"step": (0.2, 0.2, 1.0, 2.0, 1.0, 0.0, 0.0, (100.0,))}
    (row,) = hb.run_driven(repeats=1, cases=case)
    assert row["mbm_error"] <= 1e-9 and row["heyoka_time"] > 0 and row["mbm_time"] > 0
    if row["heyoka_tol"] is not None:
        assert row["heyoka_error"] <= max(row["mbm_error"], hb.MATCH_FLOOR)
    assert "| step | 100 |" in hb.render([], [row])
