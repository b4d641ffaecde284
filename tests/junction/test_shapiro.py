"""mbm.shapiro_steps: Shapiro-step edges against an independent DOP853 bisection.

The reference (tests/data/shapiro_edges_reference.json, written by
tests/data/shapiro_edges_reference.py, which says how) bisects the edges of the steps
n = 1, 2 at β = 1, A = 0.5, Ω = 0.6 with scipy's DOP853 at rtol 1e-10, probes of 16000
drive periods, to 1e-5, and states its own error.
"""

import fractions
import json
import math
from pathlib import Path

import numpy as np
import pytest

import mbm
from mbm.junction import shapiro

REFERENCE = Path(__file__).parents[1] / "data" / "shapiro_edges_reference.json"
SCENE = dict(amplitude=0.5, frequency=0.6)
TOL = 1e-4


def _reference():
    return json.loads(REFERENCE.read_text())


@pytest.fixture(scope="module")
def steps():
    return mbm.shapiro_steps(1.0, (0.0, 1.6), current_tol=TOL, **SCENE)


def test_edges_against_dop853(steps):
    ref = _reference()
    assert (ref["beta"], ref["amplitude"], ref["frequency"]) == (1.0, 0.5, 0.6)
    assert len(ref["edges"]) == 4
    for e in ref["edges"]:
        s = steps.step(e["n"])
        assert s is not None, e
        edge, bracket = (s.lower, s.lower_bracket) if e["side"] == "lower" else (s.upper, s.upper_bracket)
        # the reference's own error is far below the tolerance asked of mbm
        assert e["error"] < 0.1 * TOL, e
        assert abs(edge - e["edge"]) <= TOL, (e, edge)
        # the edge lies in the bracket bisection found (to the reference's own error)
        assert bracket[0] - e["error"] <= e["edge"] <= bracket[1] + e["error"], (e, bracket)


def test_step_table(steps):
    assert [(s.p, s.q) for s in steps.steps] == [(0, 1), (1, 1), (2, 1)]
    for s in steps.steps:
        assert s.voltage == pytest.approx(s.p * 0.6, abs=1e-15)
        assert s.width == pytest.approx(s.upper - s.lower, abs=1e-15) and s.width > 0
        for lo, hi in (s.lower_bracket, s.upper_bracket):
            assert 0 < hi - lo <= TOL
        assert s.lower_bracket[0] <= s.lower <= s.lower_bracket[1]
        assert s.upper_bracket[0] <= s.upper <= s.upper_bracket[1]
    # the grid's points inside a step are on it: ⟨θ'⟩ = nΩ to round-off
    for s in steps.steps:
        inside = (steps.gamma > s.lower_bracket[1]) & (steps.gamma < s.upper_bracket[0])
        assert inside.sum() >= 3
        assert np.max(np.abs(steps.mean_velocity[inside] - s.voltage)) <= 1e-9
    text = steps.table()
    assert len(text.splitlines()) == 1 + len(steps.steps) and "1.19683" in text


def test_zero_step_is_symmetric(steps):
    # γ → −γ, θ → −θ, t → t + π/Ω maps the equation onto itself: the zero step is
    # [−γ₀, γ₀] (its lower edge followed below gamma_range's start).
    s = steps.step(0)
    assert s.lower < 0.0 < s.upper
    assert abs(s.lower + s.upper) <= TOL


def test_edges_bracket_the_step(steps):
    # Each bracket's ends are what the probe said: on the step at its inner end, off it
    # at its outer end (probed from the settled state of a point well inside).
    s = steps.step(2)
    at = lambda g: mbm.Pendulum(1.0, g, 1.0, 0.5, 0.6)  # noqa: E731
    y = mbm.solve(at(1.39), (0.0, 2000 * 2 * math.pi / 0.6), [0.0, 0.0], t_eval=[2000 * 2 * math.pi / 0.6],
                  rtol=shapiro.RUN_RTOL, atol=shapiro.RUN_ATOL).y[:, -1]
    y[0] = math.remainder(y[0], 2 * math.pi)
    assert shapiro._probe(at(s.upper_bracket[0]), y, 2, 1)[0]
    assert not shapiro._probe(at(s.upper_bracket[1] + 10 * TOL), y, 2, 1)[0]


def test_fractional_step():
    # The 3/2 step at β = 1, A = 0.5, Ω = 0.6 comes in two pieces (≈ 1.198-1.204 and
    # ≈ 1.231-1.263), with motion off the steps between them (⟨θ'⟩ = 0.86 at γ = 1.22).
    with pytest.warns(RuntimeWarning, match=r"step\(s\) 2 not found on the up sweep \(try sweep='both'\)"):
        s = mbm.shapiro_steps(1.0, (1.18, 1.26), orders=[fractions.Fraction(3, 2), 1, 2], points=5, **SCENE)
    halves = [x for x in s.steps if (x.p, x.q) == (3, 2)]
    assert len(halves) == 2 and s.step(3, 2) is halves[0]
    assert all(h.voltage == pytest.approx(0.9, abs=1e-15) for h in halves)
    assert halves[0].lower < 1.2 < halves[0].upper < 1.22 < halves[1].lower < 1.24 < 1.26 < halves[1].upper
    assert abs(s.mean_velocity[2] - 0.9) > 0.01  # γ = 1.22: between the pieces
    # orders given: only those steps are looked for
    assert {(x.p, x.q) for x in s.steps} == {(3, 2), (1, 1)}
    # the n = 1 step reaches below the range and was followed `points` grid steps (0.1)
    # past its start without an end: no lower edge
    one = s.step(1)
    assert math.isnan(one.lower) and math.isnan(one.width) and math.isnan(one.lower_bracket[0])
    assert one.lower_bracket[1] == pytest.approx(1.18 - 5 * 0.02, abs=1e-12)
    # ... and its upper edge, bisected from another grid, is DOP853's
    ref = next(e for e in _reference()["edges"] if (e["n"], e["side"]) == (1, "upper"))
    assert abs(one.upper - ref["edge"]) <= TOL


def test_csv_and_plot(steps, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    path = tmp_path / "steps.csv"
    steps.to_csv(path)
    rows = path.read_text().splitlines()
    assert rows[0].startswith("# beta=1.0") and rows[1].startswith("p,q,voltage,lower,upper")
    assert len(rows) == 2 + len(steps.steps)
    assert float(rows[3].split(",")[3]) == steps.steps[1].lower
    ax = steps.plot()
    assert len(ax.lines) == 1 + len(steps.steps)


def test_exported():
    assert {"shapiro_steps", "ShapiroSteps", "ShapiroStep"} <= set(mbm.__all__)
    assert mbm.shapiro_steps is shapiro.shapiro_steps


GOOD = dict(beta=1.0, gamma_range=(0.0, 1.0), amplitude=0.5, frequency=0.6)


@pytest.mark.parametrize("kw, err, match", [
    (dict(amplitude=0.0), ValueError, "amplitude must be > 0, got 0.0"),
    (dict(amplitude=-0.5), ValueError, "amplitude must be > 0, got -0.5"),
    (dict(frequency=0.0), ValueError, "frequency must be > 0, got 0.0"),
    (dict(frequency=-1), ValueError, "frequency must be > 0, got -1"),
    (dict(frequency=math.inf), ValueError, "frequency must be finite"),
    (dict(beta=0.0), ValueError, "beta must be > 0"),
    (dict(omega=0.0), ValueError, "omega must be > 0"),
    (dict(current_tol=0.0), ValueError, "current_tol must be > 0, got 0.0"),
    (dict(current_tol=-1e-4), ValueError, "current_tol must be > 0"),
    (dict(gamma_range=(1.0, 0.0)), ValueError, r"gamma_range must be increasing \(lo < hi\)"),
    (dict(gamma_range=(1.0, 1.0)), ValueError, r"gamma_range must be increasing \(lo < hi\)"),
    (dict(gamma_range=(0.0, math.nan)), ValueError, "gamma_range must be finite"),
    (dict(gamma_range=(0.0, 1.0, 2.0)), ValueError, r"gamma_range must be a pair \(lo, hi\)"),
    (dict(gamma_range="0,1"), TypeError, "gamma_range must be a real number or an array of real numbers"),
    (dict(amplitude="0.5"), TypeError, "amplitude must be a real number"),
    (dict(frequency="0.6"), TypeError, "frequency must be a real number"),
    (dict(beta="1"), TypeError, "beta must be a real number"),
    (dict(current_tol="1e-4"), TypeError, "current_tol must be a real number"),
    (dict(points=2), ValueError, "points must be >= 3, got 2"),
    (dict(points=4.0), TypeError, "points must be an integer"),
    (dict(orders="1"), TypeError, "orders must be a sequence"),
    (dict(orders=[1.5]), TypeError, "orders must hold integers"),
    (dict(orders=[(1, 0)]), ValueError, "q must be >= 1"),
    (dict(orders=[]), ValueError, "orders must hold at least one step"),
    (dict(sweep="upward"), ValueError, "sweep must be 'up', 'down' or 'both', got 'upward'"),
])
def test_bad_input(kw, err, match):
    args = {**GOOD, **kw}
    beta, gamma_range = args.pop("beta"), args.pop("gamma_range")
    with pytest.raises(err, match=match):
        mbm.shapiro_steps(beta, gamma_range, **args)


def test_cli_steps(capsys, tmp_path):
    from mbm.cli.main import main

    csv = tmp_path / "steps.csv"
    assert main(["iv", "--beta", "1", "--gamma-max", "1.6", "--points", "21", "--drive-amplitude", "0.5",
                 "--drive-frequency", "0.6", "--steps", "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert "Shapiro steps over gamma in [0, 1.6]" in out
    rows = [r.split() for r in out.splitlines()[2:]]
    assert [r[0] for r in rows] == ["0", "1", "2"]
    assert abs(float(rows[1][2]) - 0.897) < 1e-3 and abs(float(rows[2][3]) - 1.459) < 1e-3
    assert len(csv.read_text().splitlines()) == 2 + 3
    with pytest.raises(SystemExit):
        main(["iv", "--beta", "1", "--steps"])
    assert "--steps needs a drive" in capsys.readouterr().err


def test_sweep_directions():
    # β = 1 (no hysteresis on these steps): the down sweep, from rest at the top of the
    # range, finds the steps the up sweep finds, with the same edges; "both" lists each
    # once, found on both sweeps, with both grids' voltages.
    kw = dict(orders=[1, 2], points=7, current_tol=1e-3, **SCENE)
    up = mbm.shapiro_steps(1.0, (0.7, 1.5), **kw)
    down = mbm.shapiro_steps(1.0, (0.7, 1.5), sweep="down", **kw)
    both = mbm.shapiro_steps(1.0, (0.7, 1.5), sweep="both", **kw)
    assert up.sweep == "up" and up.mean_velocity_down is None
    assert down.sweep == "down" and np.isnan(down.mean_velocity).all()
    assert {s.sweep for s in up.steps} == {"up"} and {s.sweep for s in down.steps} == {"down"}
    assert [(s.p, s.q) for s in up.steps] == [(s.p, s.q) for s in down.steps] == [(1, 1), (2, 1)]
    for a, b in zip(up.steps, down.steps):
        assert abs(a.lower - b.lower) <= 2e-3 and abs(a.upper - b.upper) <= 2e-3
        # each bracket holds one bias on the step and one off it, lo < hi
        assert a.lower_bracket[0] < a.lower_bracket[1] and b.upper_bracket[0] < b.upper_bracket[1]
    assert [(s.p, s.sweep) for s in both.steps] == [(1, "both"), (2, "both")]
    np.testing.assert_array_equal(both.mean_velocity, up.mean_velocity)
    assert both.mean_velocity_down.shape == both.gamma.shape
    # on a step the two grids agree on the voltage
    on = np.abs(both.mean_velocity / 0.6 - np.round(both.mean_velocity / 0.6)) < 1e-6
    np.testing.assert_allclose(both.mean_velocity_down[on], both.mean_velocity[on], atol=1e-6)
