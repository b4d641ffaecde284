"""benchmarks.bits: its hash covers every run's outputs to the bit, and repeats."""

import numpy as np
import pytest

from benchmarks import bits


def _result(y):
    return {"y": y, "n_windows": 3, "regime": "none", "t_regime": float("nan"), "status": 0}


def test_one_ulp_of_one_output_changes_the_bytes():
    y = np.array([[0.1, 0.2], [0.3, 0.4]])
    y2 = y.copy()
    y2[1, 0] = np.nextafter(y2[1, 0], 1.0)
    assert bits.result_bytes(_result(y)) == bits.result_bytes(_result(y.copy()))
    assert bits.result_bytes(_result(y)) != bits.result_bytes(_result(y2))
    other = _result(y)
    other["n_windows"] = 4
    assert bits.result_bytes(other) != bits.result_bytes(_result(y))


def test_the_runs_and_their_hash_repeat():
    labels = [label for label, _ in bits.runs(2)]
    assert len(labels) == 6 * len(bits.TOLERANCES) * 2 + 2 and len(set(labels)) == len(labels)
    assert bits.digest(1) == bits.digest(1)


def test_bad_random_refused():
    with pytest.raises(SystemExit):
        bits.main(["--random", "-1"])
