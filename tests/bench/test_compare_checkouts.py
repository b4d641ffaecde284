"""benchmarks.compare_checkouts: its parse of warm_calls' rows, its table, its refusals."""

import pytest

from benchmarks import compare_checkouts as cc


def test_a_warm_calls_row_is_parsed_to_its_median():
    line = f"{'P1 mbm.solve, rtol = atol = 1e-4':46s} {0.0123 * 1e3:10.4f} ms  (min {0.0119 * 1e3:.4f})"
    m = cc._ROW.match(line.strip())
    assert m and m["label"].strip() == "P1 mbm.solve, rtol = atol = 1e-4" and float(m["ms"]) == 12.3


def test_the_table_gives_each_row_and_the_ratio(tmp_path):
    page = cc.table({"row a": (2.0, 1.0), "row b": (1.0, 1.5)}, tmp_path, 3, 21)
    assert "| row a | 2.0000 | 1.0000 | 0.500 |" in page
    assert "| row b | 1.0000 | 1.5000 | 1.500 |" in page


def test_a_base_that_is_not_a_checkout_is_refused(tmp_path, capsys):
    with pytest.raises(SystemExit):
        cc.main([str(tmp_path)])
    assert "base must be the root of a checkout of mbm" in capsys.readouterr().err


def test_rounds_below_one_are_refused(tmp_path, capsys):
    with pytest.raises(SystemExit):
        cc.main([str(tmp_path), "--rounds", "0"])
    assert "--rounds and --repeats must be >= 1" in capsys.readouterr().err


def test_first_call_rows_are_rows_of_benchmarks_first_calls():
    from benchmarks import first_calls as fc

    rows = dict(fc.ROWS, **fc.HELPERLESS_ROWS)
    assert set(cc.FIRST_CALL_ROWS) <= set(rows)


def test_compare_takes_the_median_of_each_side_over_rounds(tmp_path):
    seen = iter([{"r": 3.0}, {"r": 1.0}, {"r": 1.0}, {"r": 2.0}, {"r": 2.0}, {"r": 9.0}])
    rows = cc.compare(tmp_path, 3, 1, "", measure=lambda checkout: next(seen))
    assert rows == {"r": (2.0, 2.0)}
