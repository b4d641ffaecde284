"""benchmarks.warm_calls: the medians it prints and its refusal of a bad --repeats."""

import pytest

from benchmarks import warm_calls


def test_median_seconds_calls_once_more_than_repeats():
    calls = []
    got = warm_calls.median_seconds(lambda: calls.append(1), 5)
    assert len(calls) == 6 and got >= 0.0


def test_rows_state_their_tolerance_or_window():
    labels = list(warm_calls.cases())
    assert len(labels) == 8 + len(warm_calls.LOCKED_TEST_SCENES)
    # an adaptive row its tolerance, a fixed-window row its τ, the exact flow neither
    assert all("1e-" in label or "τ" in label or "exact" in label for label in labels)


def test_bad_repeats_refused():
    with pytest.raises(SystemExit):
        warm_calls.main(["--repeats", "0"])
