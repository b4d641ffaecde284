"""benchmarks/shapiro_point.py: issue 52's bias point, one line per tolerance with both front ends."""

import re


def test_prints_both_front_ends_per_tolerance(capsys):
    from benchmarks import shapiro_point

    shapiro_point.main(["--repeats", "1"])
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == len(shapiro_point.TOLS)
    for line, (rtol, _) in zip(lines, shapiro_point.TOLS):
        m = re.fullmatch(r"rtol (\S+): mbm.solve ([\d.]+) ms  solve_ivp ([\d.]+) ms", line)
        assert m and float(m.group(1)) == rtol
        assert 0.0 < float(m.group(2)) < 1e4 and 0.0 < float(m.group(3)) < 1e4
