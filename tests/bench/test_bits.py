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


def test_ulps_counts_units_in_the_last_place():
    a = np.array([1.0, -1.0, 0.0, -0.0, np.nan, 1.0, 2.0])
    b = np.array([np.nextafter(1.0, 2.0), np.nextafter(-1.0, -2.0), np.nextafter(0.0, -1.0), 0.0, np.nan, np.nan, 2.0])
    assert bits.ulps(a, b).tolist() == [1.0, 1.0, 1.0, 0.0, 0.0, np.inf, 0.0]
    # Across zero: from the least positive to the least negative double is 2 ulps.
    assert bits.ulps(np.array([5e-324]), np.array([-5e-324]))[0] == 2.0


def _snap(y, t_regime=float("nan"), t=None):
    t = np.arange(y.shape[1], dtype=float) if t is None else t
    return {"run": {"t": t, "y": y, "n_windows": 3, "regime": "locked", "t_regime": t_regime, "status": 0,
                    "approximant": "taylor"}}


def test_compare_splits_the_ulps_at_the_switch():
    y = np.array([[0.5, 1.5, 2.5, 3.5], [0.1, 0.2, 0.3, 0.4]])
    assert bits.compare(_snap(y), _snap(y.copy())) == []
    moved = y.copy()
    moved[0, 3] = np.nextafter(moved[0, 3], 9.0)
    moved[0, 3] = np.nextafter(moved[0, 3], 9.0)
    moved[1, 2] = np.nextafter(moved[1, 2], 9.0)
    (row,) = bits.compare(_snap(y, t_regime=2.0), _snap(moved, t_regime=2.0))
    assert row["before"] == (0.0, 0.0) and row["after"] == (2.0, 1.0) and row["moved"] == []
    # Backward: the outputs at or after the switch are those at or below it.
    tb = -np.arange(4.0)
    (row,) = bits.compare(_snap(y, -1.5, tb), _snap(moved, -1.5, tb))
    assert row["before"] == (0.0, 0.0) and row["after"] == (2.0, 1.0)
    # No switch: every output counts as before it; a moved scalar is named.
    other = _snap(moved)
    other["run"]["n_windows"] = 4
    (row,) = bits.compare(_snap(y), other)
    assert row["before"] == (2.0, 1.0) and row["moved"] == ["n_windows"]
    assert "1 of 1 runs differ" in bits.format_compare([row], 1)[0]


def test_save_and_against_round_trip(tmp_path, capsys):
    f = tmp_path / "bits.pkl"
    bits.main(["--random", "0", "--save", str(f)])
    assert "runs saved" in capsys.readouterr().out
    bits.main(["--random", "0", "--against", str(f)])
    assert "the same to the bit" in capsys.readouterr().out
