"""benchmarks.watch_cost: the watched and the plain entries take the same windows, and
the page is a quotable block (the timings themselves are the benchmark's, not a test's)."""

import math

import numpy as np
import pytest

from benchmarks import watch_cost
from benchmarks.report import extract_blocks
from benchmarks.scenes import SCENES


def test_rows_compare_the_same_windows():
    rows = watch_cost.watch_costs(scene_names=("P1",), tolerances=(1e-6,), repeats=3, block_size=2)
    (row,) = rows
    assert row["scene"] == "P1" and row["tol"] == 1e-6 and row["windows"] > 1
    assert row["cut"] == SCENES["P1"].t_span[1]  # P1 does not switch to a regime by t = 20
    assert row["plain"] > 0.0 and row["watched"] > 0.0
    assert math.isclose(row["share"], (row["watched"] - row["plain"]) / row["plain"])
    page = watch_cost.format_watch_costs(rows, 3, 2)
    body = extract_blocks(page)[watch_cost.BLOCK_NAME]
    assert body.count("\n") == 3 and "| P1 | 1e-06 |" in body


def test_entries_that_take_other_windows_are_refused():
    scene = SCENES["P2"]
    watched, plain, h, cut = watch_cost._buffers(scene, 1e-9)
    other, _, _, _ = watch_cost._buffers(scene, 1e-6)  # other tolerances: other windows
    other[0].view(np.int64)[watch_cost.WORD["regimes"]] = 0
    assert watch_cost._same_windows(scene, watched, plain, h, cut) > 1
    with pytest.raises(RuntimeError, match="different windows"):
        watch_cost._same_windows(scene, watched, other, h, cut)
