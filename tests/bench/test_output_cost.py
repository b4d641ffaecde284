"""benchmarks.output_cost: each scene reaches its regime, and the page is a quotable
block (the timings themselves are the benchmark's, not a test's)."""

import pytest

from benchmarks import output_cost
from benchmarks.report import extract_blocks


def test_rows_reach_their_regimes_and_the_page_quotes_them():
    rows = output_cost.output_costs(n=101, batches=1)
    assert [r["name"] for r in rows] == [s[0] for s in output_cost.SCENES]
    for r, (_, want, _, _) in zip(rows, output_cost.SCENES):
        assert r["regime"] == ("None" if want == "none" else want)
        assert r["outputs"] > 0.0 and r["ends"] > 0.0 and r["windows"] >= 1
    page = output_cost.format_output_costs(rows, 101, 1)
    body = extract_blocks(page)[output_cost.BLOCK_NAME]
    assert body.count("\n") == 2 + len(rows) and "| phase-locked |" in body


def test_a_scene_off_its_regime_is_refused(monkeypatch):
    scenes = (("locked", "running", (0.5, 0.2, 1.0, 0.0, 0.0, 0.0), (1.0, 0.0)),)
    monkeypatch.setattr(output_cost, "SCENES", scenes)
    with pytest.raises(RuntimeError, match="expected 'running'"):
        output_cost.output_costs(n=11, batches=1)
