"""Tests of benchmarks/unseen_bench.py (random scenes against heyoka), on two small scenes."""

import numpy as np
import pytest

import mbm
from benchmarks import peers
from benchmarks import unseen_bench as ub
from benchmarks.references import heyoka_ld_reference

# heyoka is in the test extra (the benchmark's peer and the long-double reference): no skip.


def test_scenes_are_seeded_and_in_range():
    a, b = ub.draw_scenes(6, 11), ub.draw_scenes(6, 11)
    assert [s.scene for s in a] == [s.scene for s in b]
    assert [s.scene for s in ub.draw_scenes(6, 12)] != [s.scene for s in a]
    for i, s in enumerate(a):
        assert s.name == f"U{i + 1}"
        assert ub.BETA_RANGE[0] <= s.beta <= ub.BETA_RANGE[1]
        assert ub.GAMMA_RANGE[0] <= s.gamma <= ub.GAMMA_RANGE[1]
        assert ub.OMEGA_RANGE[0] <= s.omega <= ub.OMEGA_RANGE[1]
        assert -np.pi <= s.theta0 <= np.pi and ub.V0_RANGE[0] <= s.v0 <= ub.V0_RANGE[1]
        assert s.t_end == ub.HORIZONS[i % len(ub.HORIZONS)]


def test_rows_are_matched_and_rendered():
    scene = ub.draw_scenes(1, 3)[0]
    row = ub.run_scene(scene, peers.HeyokaPeer(), repeats=2, targets=(1e-6,))
    cell = row["targets"]["1e-06"]
    ref = heyoka_ld_reference(scene)
    # The chosen points meet the target, and the next looser tolerance does not.
    assert cell["mbm"]["error"] <= 1e-6 and cell["heyoka"]["error"] <= 1e-6
    i = ub.MBM_RTOLS.index(cell["mbm"]["rtol"])
    if i > 0:
        looser = mbm.Integrator(scene.model, rtol=ub.MBM_RTOLS[i - 1], atol=ub.MBM_RTOLS[i - 1])
        res = looser.solve(scene.t_span, scene.y0, scene.t_eval)
        assert np.max(np.abs(res.y[0] - ref)) > 1e-6
    assert cell["ratio"] == pytest.approx(cell["heyoka"]["seconds"] / cell["mbm"]["seconds"])
    result = {"machine": {"cpu": "x", "logical cores": 2, "python": "3", "numba": "0", "heyoka": "7",
                          "mbm": "0.1"}, "seed": 3, "n_scenes": 1, "repeats": 2, "run": "now", "rows": [row]}
    summ = ub.summary(result)["1e-06"]
    assert summ["compared"] == 1 and summ["median"] == cell["ratio"] == summ["min"]
    text = ub.render(result)
    line = [ln for ln in text.splitlines() if ln.startswith(f"| {scene.name} |")][0]
    assert line.rstrip(" |").split("|")[-1].strip() == f"{cell['ratio']:.2f}"


def test_a_target_nobody_meets_is_a_dash():
    scene = ub.draw_scenes(1, 3)[0]
    row = ub.run_scene(scene, peers.HeyokaPeer(), repeats=1, targets=(1e-30,))
    cell = row["targets"]["1e-30"]
    assert cell["mbm"] is None and cell["heyoka"] is None and cell["ratio"] is None
    result = {"machine": {"cpu": "x", "logical cores": 2, "python": "3", "numba": "0", "heyoka": "7",
                          "mbm": "0.1"}, "seed": 3, "n_scenes": 1, "repeats": 1, "run": "now", "rows": [row]}
    assert "| 1e-30 | — | — | — |" in ub.render(result)
    assert ub.summary(result)["1e-30"]["compared"] == 0


def test_recorded_report_is_the_render_of_its_json():
    """docs/unseen.md is what ``render`` writes from docs/unseen.json (the README and the
    benchmarks page quote its summary block: no figure of it is typed by hand)."""
    import json
    from pathlib import Path

    from benchmarks.report import extract_blocks

    docs = Path(__file__).resolve().parents[2] / "docs"
    text = (docs / "unseen.md").read_text(encoding="utf-8")
    assert ub.render(json.loads((docs / "unseen.json").read_text(encoding="utf-8"))) == text
    assert "summary" in extract_blocks(text)
