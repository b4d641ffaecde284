"""benchmarks.tangent_parts: its table has a row per scene and output count, every time positive."""

from benchmarks import tangent_parts


def test_table_rows(capsys):
    tangent_parts.main(["--calls", "1"])
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| P")]
    assert [r.split("|")[1].strip() for r in rows] == ["P1"] * 3 + ["P5"] * 3
    for r in rows:
        cells = [c.strip() for c in r.strip("|").split("|")]
        assert int(cells[2]) > 0 and all(float(x) > 0.0 for x in cells[3:])
