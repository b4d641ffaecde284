"""The README's first command: ``python -m mbm demo``."""

import io
import subprocess
import sys

import pytest

from mbm.cli.main import demo, main


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


# ---------------------------------------------------------------- mbm solve / study / bench

import csv  # noqa: E402
import math  # noqa: E402

import numpy as np  # noqa: E402

import mbm  # noqa: E402
from mbm.cli.main import parse_angle  # noqa: E402
from mbm.junction.progress import Progress, progress  # noqa: E402

SOLVE_ARGS = ["solve", "--beta", "0.1", "--gamma", "0.3", "--theta0", "30deg", "--t-end", "20",
              "--n-out", "41", "--rtol", "1e-10", "--atol", "1e-10"]


def _read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array(rows[1:], dtype=float)


def test_solve_writes_csv_with_columns(tmp_path):
    out = tmp_path / "run.csv"
    assert main(SOLVE_ARGS + ["--out", str(out)]) == 0
    header, data = _read_csv(out)
    assert header == ["t", "theta", "theta_dot"]
    assert data.shape == (41, 3)
    assert data[0, 1] == pytest.approx(math.radians(30)) and data[-1, 0] == 20.0
    ref = mbm.reference(mbm.Pendulum(beta=0.1, gamma=0.3), (0.0, 20.0), [math.radians(30), 0.0],
                        t_eval=data[:, 0])
    assert np.max(np.abs(data[:, 1:].T - ref.y)) < 1e-8


def test_solve_writes_npz_and_degrees_flag_matches_suffix(tmp_path):
    a, b = tmp_path / "a.npz", tmp_path / "b.npz"
    main(SOLVE_ARGS + ["--out", str(a)])
    args = [x if x != "30deg" else "30" for x in SOLVE_ARGS] + ["--degrees", "--out", str(b)]
    main(args)
    za, zb = np.load(a), np.load(b)
    assert {"t", "theta", "theta_dot", "beta", "gamma", "omega"} <= set(za.files)
    assert za["theta"].shape == (41,)
    np.testing.assert_array_equal(za["theta"], zb["theta"])


def test_solve_csv_on_stdout_and_non_compiled_approximant(capsys):
    main(["solve", "--beta", "0.4", "--v0", "0.25", "--t-end", "5", "--n-out", "6",
          "--approximant", "johannessen", "--tau", "0.5"])
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0] == "t,theta,theta_dot" and len(lines) == 7


def test_solve_plot(tmp_path):
    png = tmp_path / "p.png"
    main(SOLVE_ARGS + ["--out", str(tmp_path / "x.csv"), "--plot", str(png)])
    assert png.exists() and png.stat().st_size > 5000


@pytest.mark.parametrize("args, name", [
    (["solve", "--theta0", "abc"], "--theta0"),
    (["solve", "--omega", "0"], "--omega"),
    (["solve", "--t-end", "-1"], "--t-end"),
    (["solve", "--n-out", "1"], "--n-out"),
    (["solve", "--approximant", "nope"], "--approximant"),
    (["solve", "--out", "x.txt"], "--out"),
    (["solve", "--beta", "nan"], "--beta"),
    (["study", "--taus", "0.5,-1"], "--taus"),
    (["study", "--scene", "mars"], "--scene"),
    (["study", "--taus", "0.5", "--rtols", "1e-6"], "--rtols"),
])
def test_bad_arguments_name_the_argument(args, name, capsys):
    with pytest.raises(SystemExit) as exc:
        main(args)
    assert exc.value.code == 2
    assert name in capsys.readouterr().err


def test_solve_error_from_solver_is_reported(capsys):
    # The paper's approximant has no error estimate: the solver asks for tau.
    with pytest.raises(SystemExit):
        main(["solve", "--approximant", "johannessen", "--t-end", "1"])
    assert "tau" in capsys.readouterr().err


def test_plot_without_matplotlib_is_a_clear_error(monkeypatch, capsys, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib -> ImportError
    with pytest.raises(SystemExit):
        main(SOLVE_ARGS + ["--plot", str(tmp_path / "p.png")])
    assert "matplotlib" in capsys.readouterr().err


def test_theta0_parsing():
    assert parse_angle("30deg") == (30.0, True)
    assert parse_angle("30°") == (30.0, True)
    assert parse_angle("0.5") == (0.5, False)


def test_study_prints_table_with_fitted_orders(tmp_path, capsys):
    out_csv, png = tmp_path / "s.csv", tmp_path / "s.png"
    assert main(["study", "--scene", "ex1", "--approximants", "split4,taylor8",
                 "--taus", "0.5,0.25,0.125", "--csv", str(out_csv), "--plot", str(png)]) == 0
    text = capsys.readouterr().out
    assert "windows" in text and "error" in text and "estimate" in text
    orders = {line.split()[1]: float(line.split()[2]) for line in text.splitlines()
              if line.strip().startswith("order ")}
    assert orders["split4"] == pytest.approx(4.0, abs=0.3)
    assert orders["taylor8"] > 6.0
    with open(out_csv, newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 6 and {"approximant", "tau", "error", "error_estimate", "fitted_order"} <= set(rows[0])
    assert png.exists()


def test_study_rtol_sweep_records_failures(capsys):
    # salas-torque has no error estimate: an rtol sweep marks its rows failed.
    main(["study", "--scene", "ex1", "--approximants", "taylor8,salas-torque", "--rtols", "1e-4,1e-6,1e-8"])
    text = capsys.readouterr().out
    assert "rtol" in text and "failed" in text and "order taylor8" in text


def test_bench_says_it_runs_from_a_checkout(capsys):
    # The benchmark left the package (benchmarks/ at the repository root): `mbm bench`
    # runs nothing and says where it went, whatever options follow it.
    for args in (["bench"], ["bench", "--quick", "--scenes", "P1"]):
        assert main(args) == 2
        err = capsys.readouterr().err
        assert "python -m benchmarks" in err and "checkout" in err
    import importlib.util

    assert importlib.util.find_spec("mbm.bench") is None  # no benchmark inside mbm


def test_mbm_does_not_import_the_benchmark():
    # Nothing in the package imports the root `benchmarks` package.
    import pathlib
    import re

    pkg = pathlib.Path(mbm.__file__).resolve().parent
    pattern = re.compile(r"^\s*(from|import)\s+benchmarks\b", re.M)
    assert not [p.name for p in pkg.rglob("*.py") if pattern.search(p.read_text(encoding="utf-8"))]


def test_progress_silent_unless_terminal():
    buf = io.StringIO()  # not a terminal
    assert list(progress(range(3), "x", stream=buf)) == [0, 1, 2]
    assert buf.getvalue() == ""
    buf = io.StringIO()
    with Progress(2, "sweep", stream=buf, enabled=True) as bar:
        bar.update()
        bar.update()
    text = buf.getvalue()
    assert "sweep [" in text and "2/2" in text and text.endswith("\n")


def test_progress_message_goes_above_the_bar():
    buf = io.StringIO()
    bar = Progress(4, "bench", stream=buf, enabled=True)
    bar.update()
    bar.message("P1: reference done")
    text = buf.getvalue()
    # the bar line is cleared, the message gets a line of its own, the bar is redrawn after it
    head, tail = text.rsplit("P1: reference done\n", 1)
    assert head.endswith("\r") and tail.startswith("\rbench [") and "1/4" in tail
    # with the bar off, a message goes plainly to the stream it names
    off, log = Progress(4, "bench", stream=io.StringIO(), enabled=False), io.StringIO()
    off.message("hello", stream=log)
    assert log.getvalue() == "hello\n"


def test_iv_command(tmp_path, capsys):
    from mbm.cli.main import main

    csv, png = tmp_path / "iv.csv", tmp_path / "iv.png"
    assert main(["iv", "--beta", "2", "--points", "6", "--csv", str(csv), "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert "switching current" in out and "retrapping current" in out
    assert png.exists() and csv.read_text().splitlines()[1] == "gamma,mean_velocity,regime,period,converged"


def test_iv_command_differential(tmp_path, capsys):
    from mbm.cli.main import main

    csv = tmp_path / "iv.csv"
    assert main(["iv", "--beta", "2", "--points", "6", "--differential", "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    rows = csv.read_text().splitlines()
    assert rows[1] == "gamma,mean_velocity,regime,period,converged,dvoltage_dgamma"
    top = rows[2 + 5].split(",")  # gamma = 1.5, the top of the sweep
    assert float(top[0]) == 1.5 and f"dgamma at gamma = 1.5: {float(top[-1]):.6g}" in out
    with pytest.raises(SystemExit):
        main(["iv", "--beta", "2", "--drive-amplitude", "1", "--drive-frequency", "1", "--steps", "--differential"])
    assert "--differential is for the I-V sweep" in capsys.readouterr().err


def test_iv_command_with_a_drive(tmp_path, capsys):
    from mbm.cli.main import main

    csv = tmp_path / "iv.csv"
    assert main(["iv", "--beta", "2", "--gamma-max", "2.2", "--points", "3", "--drive-amplitude", "1",
                 "--drive-frequency", "1", "--csv", str(csv)]) == 0
    report = capsys.readouterr().out
    assert "AC drive A = 1, Omega = 1, phi = 0" in report
    rows = csv.read_text().splitlines()
    assert "drive_amplitude=1.0, drive_frequency=1.0" in rows[0]
    # the points that did not settle, as the CSV flags them, named in the report too
    unsettled = [float(r.split(",")[0]) for r in rows[2:] if r.endswith(",False")]
    assert unsettled and (f"not settled: {len(unsettled)} of 6 points (velocity_tol = 1e-09), gamma = ["
                          + ", ".join(f"{g:.6g}" for g in unsettled) + "]") in report
    # γ = 2.2 lies on the n = 1 Shapiro step: ⟨θ'⟩ = Ω
    assert float(rows[4].split(",")[0]) == 2.2 and abs(float(rows[4].split(",")[1]) - 1.0) < 1e-9
    with pytest.raises(SystemExit):
        main(["iv", "--beta", "2", "--drive-amplitude", "1"])  # no drive frequency
    assert "drive_frequency must be > 0" in capsys.readouterr().err


def test_solve_reports_phase_slips_and_mean_velocity(tmp_path, capsys):
    from mbm.cli.main import main

    png = tmp_path / "run.png"
    assert main(["solve", "--beta", "0.1", "--gamma", "1.2", "--t-end", "1000", "--out",
                 str(tmp_path / "run.csv"), "--plot", str(png)]) == 0
    err = capsys.readouterr().err
    r = mbm.solve(mbm.Pendulum(0.1, 1.2), (0.0, 1000.0), [0.0, 0.0], t_eval=[0.0, 1000.0])
    slips = round((r.y[0, -1] - r.y[0, 0]) / (2 * math.pi))
    assert f"phase slips (net 2*pi turns): {slips}" in err
    assert f"mean velocity = {r.mean_velocity:.10g} (limit cycle)" in err and png.exists()
    assert main(["solve", "--beta", "0.1", "--gamma", "0.3", "--t-end", "100", "--out",
                 str(tmp_path / "lock.csv")]) == 0
    assert "phase slips (net 2*pi turns): 0\n" in capsys.readouterr().err


def test_cli_wording_is_the_library_wording(capsys):
    # argparse names the option; the rule is worded as every entry point words it.
    from mbm.cli.main import main

    for argv, words in ((["solve", "--omega", "-1"], "must be > 0, got '-1'"),
                        (["solve", "--beta", "x"], "must be a real number, got 'x'"),
                        (["iv", "--beta", "1", "--drive-amplitude", "nan"], "must be finite, got 'nan'")):
        with pytest.raises(SystemExit):
            main(argv)
        assert words in capsys.readouterr().err


def test_iv_report_flags_an_unsettled_bracket(monkeypatch):
    # The report on stdout says what iv_curve's warnings say (a saved report keeps it): a
    # bracket resting on probes that changed voltage state, and the points not settled.
    from mbm.cli.main import iv_command

    g = np.array([0.0, 1.0, 1.0, 0.0])
    curve = mbm.IVCurve(gamma=g, mean_velocity=np.array([0.0, 1.1, 1.1, 0.0]), regime=np.array(["locked",
                        "running", "running", "locked"]), period=np.full(4, np.nan), start_state=np.zeros((4, 2)),
                        switching_current=0.95, retrapping_current=0.5, beta=2.0, omega=1.0, current_tol=1e-4,
                        drive_amplitude=1.0, drive_frequency=1.0, switching_bracket=(0.94995, 0.95005),
                        retrapping_bracket=(0.49995, 0.50005), converged=np.array([True, False, False, True]),
                        switching_settled=False, retrapping_settled=True)
    monkeypatch.setattr(mbm, "iv_curve", lambda *a, **k: curve)
    out = io.StringIO()
    iv_command(2.0, 1.0, 2, drive_amplitude=1.0, drive_frequency=1.0, out=out)
    lines = out.getvalue().splitlines()
    switching = next(x for x in lines if x.startswith("switching current"))
    retrapping = next(x for x in lines if x.startswith("retrapping current"))
    assert "probes changed voltage state" in switching and "probes changed" not in retrapping
    assert "not settled: 2 of 4 points (velocity_tol = 1e-09), gamma = [1, 1]; converged False in the CSV" in lines


def test_help_is_plain_text(capsys):
    # A terminal shows reStructuredText as typed: the description has no quotes or roles.
    from mbm.cli.main import main
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    assert "Subcommands: demo" in out
    assert "``" not in out and ":func:" not in out
