"""benchmarks.driven_clients: each client form runs with method=mbm.MBM, probed in a
bounded number of calls, within 10× its tolerance of DOP853 at 1e-13 (the timings are
the benchmark's, not a test's)."""

from benchmarks import driven_clients


def test_rows_are_within_ten_tolerances():
    rows = driven_clients.rows(spans=(30.0,), repeats=1)
    assert [r["client"] for r in rows[::2]] == ["bound", "closure", "args", "gross"]
    for r in rows:
        assert 0 < r["probes"] <= 400, r
        assert r["mbm_err"] <= 10 * r["rtol"], r
        assert r["mbm_s"] > 0.0 and r["rk45_s"] > 0.0
