"""Order fits that cannot be read off a reference's error (mbm.cli.orderfit, mbm study)."""

import math

import numpy as np
import pytest

from mbm.cli import study as cli_study
from mbm.cli import orderfit

H = 0.5 ** np.arange(8)  # 1 .. 1/128


def _sweep(p=4.0, c=1e-2, floor=0.0):
    """Errors C h^p plus a constant floor (a reference off by ``floor``)."""
    return c * H ** p + floor


def test_floor_points_are_marked_and_not_fitted():
    err = _sweep(p=4.0, floor=1e-9)  # C h^4 reaches the floor near h = 1/32
    fit = orderfit.fit_order(H, err, ref_error=1e-9)
    assert np.array_equal(fit.floor, err <= 10 * 1e-9)
    assert fit.floor.sum() >= 2 and not np.any(fit.used & fit.floor)
    assert fit.order == pytest.approx(4.0, abs=0.05)
    # Fitted blindly, the floor points drag the slope to 3.5.
    x, y = np.log(H), np.log(err)
    assert np.polyfit(x, y, 1)[0] < 3.6


def test_a_point_just_above_the_floor_factor_is_kept():
    err = np.array([1e-4, 1.01e-8])
    assert not orderfit.at_floor(err, 1e-9).any()
    assert orderfit.at_floor(err, 1.02e-9).tolist() == [False, True]
    assert not orderfit.at_floor([math.nan], 1.0).any()  # a failed point is not at the floor


def test_pre_asymptotic_points_are_dropped():
    # Large h: the error grows much faster than h^7 (a Taylor series near its radius).
    err = 1e-3 * H ** 7
    err[:2] *= (20.0, 4.0)
    fit = orderfit.fit_order(H, err)
    assert not fit.used[:2].any() and fit.used[2:].all()
    assert fit.order == pytest.approx(7.0, abs=1e-9)
    assert fit.h_range == (H[-1], H[2])
    assert fit.slope_range == pytest.approx((7.0, 7.0))
    assert "local slopes 7.00 to 7.00" in fit.describe()


def test_asymptotic_range_is_the_longest_agreeing_run():
    h = H[:6]
    s = np.array([9.0, 6.0, 4.1, 4.0, 3.9])  # local slopes, from the large-h end
    err = np.exp(np.concatenate(([0.0], -np.cumsum(s * np.log(2.0)))))
    idx = orderfit.asymptotic_range(h, err)
    assert sorted(idx) == [2, 3, 4, 5]
    # Two runs of three points: the one at the smaller h wins.
    s = np.array([8.0, 8.0, 2.0, 2.0])
    err = np.exp(np.concatenate(([0.0], -np.cumsum(s * np.log(2.0)))))
    assert sorted(orderfit.asymptotic_range(H[:5], err)) == [2, 3, 4]
    s = np.array([2.0, 2.0, 2.0, 8.0, 8.0, 8.0])
    err = np.exp(np.concatenate(([0.0], -np.cumsum(s * np.log(2.0)))))
    assert sorted(orderfit.asymptotic_range(H[:7], err)) == [3, 4, 5, 6]


def test_a_plateau_is_not_a_range_under_min_slope():
    # Slopes 7, 7 then a round-off plateau (slopes ~0) of four points.
    s = np.array([7.0, 7.0, 0.1, -0.1, 0.05])
    err = np.exp(np.concatenate(([0.0], -np.cumsum(s * np.log(2.0))))) * 1e-3
    assert sorted(orderfit.asymptotic_range(H[:6], err)) == [2, 3, 4, 5]  # the plateau wins
    assert sorted(orderfit.asymptotic_range(H[:6], err, min_slope=1.0)) == [0, 1, 2]
    fit = orderfit.fit_order(H[:6], err, min_slope=1.0)
    assert fit.order == pytest.approx(7.0) and fit.n == 3
    assert math.isnan(orderfit.fit_order(H[3:6], err[3:6], min_slope=1.0).order)


def test_slope_tolerance():
    assert orderfit.slope_tolerance(2.0) == orderfit.SLOPE_TOL_ABS
    assert orderfit.slope_tolerance(-24.0) == pytest.approx(orderfit.SLOPE_TOL_REL * 24.0)


def test_uncertainty_is_the_slopes_standard_error():
    rng = np.random.default_rng(3)
    noise = np.exp(rng.normal(0.0, 0.02, H.size))
    err = 1e-2 * H ** 4 * noise
    fit = orderfit.fit_order(H, err)
    assert fit.n == H.size
    x, y = np.log(H), np.log(err)
    (p, _), cov = np.polyfit(x, y, 1, cov="unscaled")
    resid = y - np.polyval(np.polyfit(x, y, 1), x)
    se = math.sqrt(cov[0, 0] * np.dot(resid, resid) / (H.size - 2))
    assert fit.order == pytest.approx(p, rel=1e-12)
    assert fit.stderr == pytest.approx(se, rel=1e-9) and 0.0 < fit.stderr < 0.03
    assert abs(fit.order - 4.0) < 3 * fit.stderr
    # Exact power law: no scatter; two points: no uncertainty at all.
    assert orderfit.fit_order(H, 1e-2 * H ** 4).stderr < 1e-12
    two = orderfit.fit_order(H[:2], 1e-2 * H[:2] ** 4)
    assert two.n == 2 and math.isnan(two.stderr) and "2 points only (no uncertainty)" in two.describe()
    none = orderfit.fit_order(H[:1], [1e-3])
    assert math.isnan(none.order) and "n/a" in none.describe()


def test_failed_and_huge_errors_are_not_fitted():
    err = 1e-3 * H ** 2
    err[0], err[1] = math.nan, 5.0
    fit = orderfit.fit_order(H, err)
    assert not fit.used[:2].any() and fit.n == H.size - 2
    assert fit.order == pytest.approx(2.0, abs=1e-9)


def test_running_scene_study_fits_off_the_floor():
    # `mbm study --scene running` at a small size: taylor8 over its default sweep, and
    # taylor24 at two windows where it sits on the reference's floor.
    scene = cli_study.SCENES["running"]
    taus = cli_study.SCENE_TAUS["running"]
    study = cli_study.run_study(scene, ["taylor8"], taus=(0.25,) + taus, n_out=51, show_progress=False)
    ref_err = study["ref_error"]
    # heyoka against mbm at its tightest: 5.5e-13 (θ ~ 2400); DOP853 without heyoka: 1.3e-11.
    assert 0.0 < ref_err < (1e-11 if cli_study.heyoka_ld_available() else 1e-10)
    rows = study["rows"]
    assert not any(r["floor"] and r["fitted"] for r in rows)
    fit = study["fits"]["taylor8"]
    assert fit.n >= 5 and math.isfinite(fit.stderr) and fit.stderr < 0.1
    expected = 8 - 1  # the velocity polynomial's degree (mbm.approximants.taylor, "Order")
    assert abs(fit.order - expected) <= 2 * fit.stderr
    table = cli_study.format_table(study)
    assert table.count("   fitted") == fit.n and "its error" in table
    # τ = 1/4 is pre-asymptotic (R ~ 0.53): shown, not fitted, not at the floor.
    assert not rows[0]["fitted"] and not rows[0]["floor"] and rows[0]["value"] == 0.25
    assert "not fitted (outside the asymptotic range)" in table
    hi = cli_study.run_study(scene, ["taylor"], taus=taus[:2], n_out=51, show_progress=False)
    assert all(r["floor"] and not r["fitted"] for r in hi["rows"])
    assert "at the reference's floor" in cli_study.format_table(hi)
    assert math.isnan(hi["orders"]["taylor"])


def test_reference_states_its_error_with_and_without_heyoka(monkeypatch):
    import mbm

    model = mbm.Pendulum(beta=0.1, gamma=1.2)
    t = np.linspace(0.0, 20.0, 21)
    ref = cli_study.study_reference(model, [0.0, 0.0], t)
    cvode = mbm.reference(model, (0.0, 20.0), [0.0, 0.0], t_eval=t, rtol=1e-12, atol=1e-12).y[0]
    assert np.max(np.abs(ref["theta"].astype(float) - cvode)) < 1e-8
    assert 0.0 < ref["error"] < 1e-12 and "mbm taylor" in ref["check_name"]
    monkeypatch.setattr(cli_study, "heyoka_ld_available", lambda: False)
    dop = cli_study.study_reference(model, [0.0, 0.0], t)
    assert "DOP853" in dop["name"] and dop["theta"].dtype == np.float64
    # DOP853 is the less accurate reference: its stated error is the larger.
    assert dop["error"] > ref["error"] and dop["error"] < 1e-10


def test_heyoka_reference_follows_the_drive():
    import mbm

    # heyoka is a test dependency (pyproject's [test] extra).
    model = mbm.Pendulum(beta=0.5, gamma=0.2, drive_amplitude=0.8, drive_frequency=0.7, drive_phase=0.3)
    t = np.linspace(0.0, 30.0, 31)
    ld = cli_study.heyoka_ld_states(model, [0.1, 0.0], t)
    cvode = mbm.reference(model, (0.0, 30.0), [0.1, 0.0], t_eval=t, rtol=1e-12, atol=1e-12).y
    assert ld.shape == (31, 2) and np.max(np.abs(ld.astype(float).T - cvode)) < 1e-9


def test_study_prints_the_runs_error_estimate(tmp_path):
    # Beside the measured error, each run through mbm.solve states its own estimate
    # (max |error_estimate of θ|); a run through solve_ivp (salas-torque-cn: no compiled
    # window) has none, "—" in the table and an empty CSV cell.
    study = cli_study.run_study(cli_study.SCENES["ex1"], ["taylor8", "split4"], rtols=(1e-6, 1e-8),
                                show_progress=False)
    table = cli_study.format_table(study)
    header = next(line for line in table.splitlines() if line.startswith("approximant"))
    assert header.split()[:7] == ["approximant", "rtol", "windows", "mean", "h", "error", "estimate"]
    for r in study["rows"]:
        assert not r["note"] and r["error"] > 10 * study["ref_error"]
        # on ex1 the estimate is the measured error to a few per cent; a factor 10 asked
        assert r["error"] / 10 <= r["estimate"] <= 10 * r["error"], r
        assert f"{r['error']:10.2e} {r['estimate']:10.2e}" in table
    fixed = cli_study.run_study(cli_study.SCENES["ex1"], ["split4", "salas-torque-cn"], taus=(0.5, 0.25),
                                show_progress=False)
    est = {r["approximant"]: r["estimate"] for r in fixed["rows"]}
    assert est["salas-torque-cn"] is None and est["split4"] > 0.0
    assert cli_study.format_table(fixed).count("          — ") == 2
    cli_study.write_csv(fixed, tmp_path / "s.csv")
    import csv

    with open(tmp_path / "s.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["error_estimate"] == "" for r in rows] == [False, False, True, True]
