"""The README's first command: ``python -m mbm demo``."""

import io
import subprocess
import sys

import pytest

from mbm.__main__ import demo, main


def test_demo_reports_errors_and_times():
    buf = io.StringIO()
    res = demo(rtol=1e-9, out=buf)
    text = buf.getvalue()
    assert "MBM auto" in text and "DOP853" in text
    err_ivp, t_ivp = res["MBM auto, solve_ivp"]
    err_fast, t_fast = res["MBM auto, mbm.solve"]
    assert err_ivp < 1e-8 and err_fast == err_ivp
    assert 2e-3 < res["MBM salas-torque tau=0.25"][0] < 4e-3
    assert res["single"][0] == pytest.approx(1.63e-3, rel=0.02)
    assert t_ivp > 0 and t_fast > 0


def test_cli_entry_point():
    out = subprocess.run([sys.executable, "-m", "mbm", "demo", "--rtol", "1e-6"], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert "MBM auto, mbm.solve" in out.stdout
    with pytest.raises(SystemExit):
        main(["demo", "--rtol", "-1"])
