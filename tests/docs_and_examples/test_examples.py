"""The figure examples of ``examples/``: each runs, writes its PNG, and plots right values.

Every example exposes ``main(out, ...)`` returning the plotted data; the values are
spot-checked against :func:`mbm.reference` (CVODE), independent of how the example
computed them.
"""

import importlib
import math
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

import mbm
import mbm.scenes


@pytest.fixture(scope="module", autouse=True)
def _agg_backend():
    import matplotlib

    matplotlib.use("Agg")  # the tests write files only


def _load(name):
    # examples/ is on pytest's pythonpath (pyproject.toml), as it is on a script's own path.
    return importlib.import_module(name)


def _ref(model, y0, t, **kw):
    return mbm.reference(model, (0.0, float(t[-1])), y0, t_eval=t, **kw).y


def test_salas2021_figure1(tmp_path):
    ex = _load("fig_salas2021")
    d, png = ex.main(tmp_path, n_points=81)
    assert png.exists() and png.stat().st_size > 10_000
    ref = _ref(mbm.Pendulum(beta=0.4), [0.0, 0.25], d["t"])[0]
    assert np.max(np.abs(d["runge_kutta"] - ref)) < 1e-8
    # Johannessen's sn formula and the elementary solution are close, not exact:
    # their model errors on this scene (measured: 9.3e-5, 2.8e-4, 1.4e-3).
    assert np.max(np.abs(d["johannessen"] - ref)) < 2e-4
    assert np.max(np.abs(d["salas-damped"] - ref)) < 5e-4
    assert 5e-4 < np.max(np.abs(d["salas-damped-linear"] - ref)) < 3e-3


def test_salas2022_figures(tmp_path):
    ex = _load("fig_salas2022")
    d, pngs = ex.main(tmp_path, n_points=161, js=(0, 5))
    assert [p.name for p in pngs] == [f"salas2022_fig{k}.png" for k in (1, 2, 3, 4)]
    assert all(p.exists() for p in pngs)
    t = d["t"]
    m1 = mbm.Pendulum(beta=0.1, gamma=0.3)
    ref1 = _ref(m1, [math.radians(30), 0.0], t)
    assert np.max(np.abs(d["ex1"]["numerical"] - ref1)) < 1e-7
    assert d["ex1"]["d"] == pytest.approx(0.304337, abs=1e-6)
    # The paper's E = 0.00162852 for the single approximant (4.33).
    assert np.max(np.abs(d["ex1"]["approximant"][0] - ref1[0])) == pytest.approx(1.63e-3, rel=0.03)
    m2 = mbm.Pendulum(beta=0.1, gamma=0.6)
    ref2 = _ref(m2, [math.radians(90), 0.0], t)[0]
    e2 = d["ex2"]
    assert np.max(np.abs(e2["approximant"][0] - ref2)) > 0.3  # "clearly not good"
    # Re-anchoring improves it: Θ_5 is better than Θ_0, and the event-point solution
    # is within the cubic model's error (~5e-2) everywhere.
    err_j = {j: np.max(np.abs(th - ref2)) for j, th in e2["successive"].items()}
    assert err_j[5] < 0.5 * err_j[0]
    assert np.max(np.abs(e2["event_solution"] - ref2)) < 0.06
    # The marked event points lie on the solution: θ = d or θ' = 0 there.
    te, kinds = e2["event_t"], e2["event_kind"]
    y_at = mbm.reference(m2, (0.0, 80.0), [math.radians(90), 0.0], t_eval=te).y
    from mbm.events.points import KIND_CROSSING, KIND_TURNING

    assert np.all(np.abs(y_at[0, kinds == KIND_CROSSING] - e2["d"]) < 1e-7)
    assert np.all(np.abs(y_at[1, kinds == KIND_TURNING]) < 1e-7)
    assert te.size > 20


def test_belendez2007_figures(tmp_path):
    ex = _load("fig_belendez2007")
    assert ex.AMPLITUDES_PI == (0.1, 0.25, 0.5, 0.75, 0.9, 0.99)  # the paper's captions
    d, pngs = ex.main(tmp_path, n_points=121, amplitudes_pi=(0.25, 0.9))
    assert len(pngs) == 2 and all(p.exists() for p in pngs)
    t = d["t"]
    for a, (exact, harmonic, per) in d["curves"].items():
        y0 = [a * math.pi, 0.0]
        ref = _ref(mbm.Pendulum(), y0, t)[0]
        assert np.max(np.abs(exact - ref)) < 1e-8
        # Same period: the harmonic curve returns to θ₀ at t = period.
        h = mbm.get_approximant("harmonic").anchor(mbm.Pendulum(), *y0)(np.array([per]))[0]
        assert h[0] == pytest.approx(a * math.pi, abs=1e-9)
    # Small amplitude: close; near the top: far (the paper's point).
    ex_s, h_s, _ = d["curves"][0.25]
    ex_l, h_l, _ = d["curves"][0.9]
    assert np.max(np.abs(ex_s - h_s)) < 0.01 < 0.3 < np.max(np.abs(ex_l - h_l))


def test_step_size_study(tmp_path):
    ex = _load("step_size_study")
    study, png = ex.main(tmp_path, taus=(0.5, 0.25, 0.125), approximants=("split4", "salas-torque"))
    assert png.exists()
    assert study["orders"]["split4"] == pytest.approx(4.0, abs=0.3)
    assert abs(study["orders"]["salas-torque"]) < 0.5  # the cubic's model error: no convergence
    # The reference states its error; the fit never uses a point at its floor.
    assert 0.0 < study["ref_error"] < 1e-10
    assert study["fits"]["split4"].n >= 2 and not any(r["floor"] and r["fitted"] for r in study["rows"])
    # Spot-check one row against an independent reference on a different grid.
    row = next(r for r in study["rows"] if r["approximant"] == "split4" and r["value"] == 0.25)
    model = mbm.Pendulum(beta=0.1, gamma=0.3)
    t = study["t"]
    ref = _ref(model, [math.radians(30), 0.0], t, solver="ida")[0]
    sol = mbm.solve(model, (0.0, 80.0), [math.radians(30), 0.0], tau=0.25, approximant="split4", t_eval=t)
    assert row["error"] == pytest.approx(np.max(np.abs(sol.y[0] - ref)), rel=1e-3)


def test_convergence_orders(tmp_path):
    ex = _load("convergence_orders")
    data, png = ex.main(tmp_path, methods=("rk4", "split4", "taylor8"))
    assert png.exists()
    fits = {m: c["fit"] for m, c in data["curves"].items()}
    # Classical orders, and the order docs/convergent.md measures for taylor8 (6.7-7.2 on
    # six scenes: one below the degree, the global error of a local O(tau^9) window).
    assert fits["rk4"].order == pytest.approx(4.0, abs=0.1)
    assert fits["split4"].order == pytest.approx(4.0, abs=0.1)
    assert 6.7 <= fits["taylor8"].order <= 7.3
    assert all(f.n >= 3 and f.stderr < 0.1 for f in fits.values())
    # The reference states its error; no fitted point lies at its floor.
    assert 0.0 < data["ref_error"] < 1e-15
    assert not any((f.used & f.floor).any() for f in fits.values())
    # Spot-check one point against an independent reference (CVODE at 1e-12, ~1e-11 off).
    c = data["curves"]["rk4"]
    i = c["tau"].index(0.5)
    model = mbm.Pendulum(beta=0.1, gamma=0.3)
    t = np.arange(81.0)
    ref = _ref(model, [math.radians(30), 0.0], t)
    ex_rk4 = ex.run_method("rk4", "ex1", Fraction(1, 2))
    err = max(np.max(np.abs(ex_rk4[:, 0] - ref[0])), np.max(np.abs(ex_rk4[:, 1] - ref[1])))
    assert c["error"][i] == pytest.approx(err, rel=1e-3)


def test_convergence_orders_reference():
    """The example's own fixed-point reference (it runs downloaded, without the repository's
    data) is the one of tests/data/convergent_reference.npz (written by
    tests/data/convergent_fixed_point.py, mpmath's sine) to far below its stated ~1e-25."""
    ex = _load("convergence_orders")
    ref = ex.reference(*mbm.scenes.get("ex1").params()[:5], 80)
    with np.load(Path(__file__).resolve().parents[1] / "data" / "convergent_reference.npz") as f:
        data = f["ex1"]
    assert ref.shape == data.shape == (81, 4)
    d_theta = (ref[:, 0] - data[:, 0]) + (ref[:, 1] - data[:, 1])
    d_v = (ref[:, 2] - data[:, 2]) + (ref[:, 3] - data[:, 3])
    assert max(np.max(np.abs(d_theta)), np.max(np.abs(d_v))) < 1e-28


def test_josephson_iv(tmp_path):
    ex = _load("josephson_iv")
    curve, png = ex.main(tmp_path, points=21)
    assert png.exists() and curve.beta == 0.1
    # Switching at the critical current ω² = 1; retrapping near Melnikov's 4β/π = 0.1273
    # (tests/junction/test_junction.py checks both against independent references).
    assert abs(curve.switching_current - 1.0) <= curve.current_tol
    assert curve.retrapping_current == pytest.approx(4 * curve.beta / math.pi, rel=0.05)
    up, down = curve.branches()
    # Hysteresis: at γ = 0.5 locked going up, running coming down; ohmic far above.
    i_up = up[np.isclose(curve.gamma[up], 0.5)][0]
    i_dn = down[np.isclose(curve.gamma[down], 0.5)][0]
    assert curve.mean_velocity[i_up] == 0.0 and curve.mean_velocity[i_dn] > 4.0
    assert curve.mean_velocity[up[-1]] == pytest.approx(2.0 / curve.beta, rel=0.01)



def test_shapiro_steps(tmp_path):
    ex = _load("shapiro_steps")
    d, png = ex.main(tmp_path, n_gamma=41, n_amp=4)
    assert png.exists() and png.stat().st_size > 10_000
    # The first lobe (A/Ω ≤ 4 at β = 2): the zero step shrinks from its undriven 2ω² as
    # the drive grows, the n = 1 step opens; the zero step is symmetric about γ = 0 (the
    # equation is, under γ → −γ, θ → −θ, t → t + π/Ω), its lower edge followed below 0.
    assert d["amplitudes"][0] == 0.0 and list(d["widths"][:, 0]) == [2.0, 0.0, 0.0]
    assert np.all(np.diff(d["widths"][0]) < 0.0) and np.all(d["widths"][1, 1:] > 0.0)
    for a, s in d["steps"].items():
        zero = s.step(0)
        assert abs(zero.lower + zero.upper) <= s.current_tol == ex.CURRENT_TOL
    # A plateau point of the A = 1 curve against CVODE: from the point's start state, the
    # phase gains 2π per drive period once settled (⟨θ'⟩ = Ω).
    c = d["iv"][1.0]
    i = int(np.flatnonzero(np.abs(c.mean_velocity - ex.FREQ) <= ex.ON_STEP)[0])
    model = mbm.Pendulum(ex.BETA, c.gamma[i], 1.0, 1.0, ex.FREQ)
    period = 2 * math.pi / ex.FREQ
    t = np.array([200.0, 300.0]) * period
    ref = _ref(model, c.start_state[i], np.r_[0.0, t])[0]
    assert (ref[2] - ref[1]) / (100 * period) == pytest.approx(ex.FREQ, abs=1e-8)
    # and an off-step point of the same curve: CVODE's weighted average of the
    # stroboscopic increments over drive periods 200-300 (mbm.junction.iv's weights; the
    # two agreed to 1.1e-6 at γ = 2.6, the first such point, when measured)
    j = int(np.flatnonzero(np.abs(c.mean_velocity / ex.FREQ - 1.5) < 0.3)[0])
    model = mbm.Pendulum(ex.BETA, c.gamma[j], 1.0, 1.0, ex.FREQ)
    ts = (200.0 + np.arange(101)) * period
    ref = _ref(model, c.start_state[j], np.r_[0.0, ts])[0, 1:]
    x = (np.arange(100) + 0.5) / 100
    w = np.exp(-1.0 / (x * (1.0 - x)))
    mean = np.dot(w / w.sum(), np.diff(ref)) / period
    assert abs(mean - ex.FREQ) > 0.1 and mean == pytest.approx(c.mean_velocity[j], abs=1e-5)


def test_fit_iv_curve(tmp_path):
    ex = _load("fit_iv_curve")
    fit, png = ex.main(tmp_path)
    assert png.exists() and png.stat().st_size > 10_000
    # the zero-voltage points below retrapping (≈ 6.7 µA) are left out, the rest fitted
    current, voltage = ex.measure()
    assert fit.success and np.array_equal(fit.fitted, current > 6.7e-6)
    # the truth within 3σ (the guide's coverage over 20 noisy curves: all within 3σ)
    for value, err, truth in ((fit.beta, fit.beta_err, ex.TRUE.beta), (fit.beta_c, fit.beta_c_err, ex.TRUE.beta_c),
                              (fit.I_c, fit.I_c_err, ex.TRUE.I_c), (fit.R, fit.R_err, ex.TRUE.R)):
        assert 0.0 < err < 0.25 * truth and abs(value - truth) <= 3 * err, (value, err, truth)


def test_fit_trajectory(tmp_path):
    ex = _load("fit_trajectory")
    fits, png = ex.main(tmp_path, repeats=1)
    assert png.exists() and png.stat().st_size > 10_000
    sens, fd = fits["sensitivities"], fits["2-point"]
    # both fits recover the truth within 3σ, with sensible errors, at one minimum
    for f in (sens, fd):
        assert f["result"].success
        assert np.all(f["err"] > 0.0) and np.all(f["err"] < 0.05 * ex.TRUE), f["err"]
        assert np.all(np.abs(f["value"] - ex.TRUE) <= 3 * f["err"]), (f["value"], f["err"])
        assert f["sigma"] == pytest.approx(ex.NOISE, rel=0.3)
    assert np.allclose(sens["value"], fd["value"], rtol=0, atol=1e-3 * sens["err"].min())
    # the sensitivity Jacobian's fit: no finite differences, fewer runs of the model
    assert sens["n_jacobian"] >= 1 and fd["n_jacobian"] == 0
    assert sens["n_residual"] + sens["n_jacobian"] < fd["n_residual"]
    # its Jacobian is the derivative of the residuals: against central differences of
    # tighter runs at the solution (the example's runs are at 1e-10)
    p, h = sens["value"], 1e-5
    jac = sens["result"].jac
    for k in range(3):
        dp = np.zeros(3)
        dp[k] = h
        up = mbm.solve(mbm.Pendulum(*(p + dp)[:2]), (0.0, 40.0), [(p + dp)[2], 0.0], t_eval=ex.T,
                       rtol=1e-13, atol=1e-13).y[0]
        dn = mbm.solve(mbm.Pendulum(*(p - dp)[:2]), (0.0, 40.0), [(p - dp)[2], 0.0], t_eval=ex.T,
                       rtol=1e-13, atol=1e-13).y[0]
        assert np.max(np.abs((up - dn) / (2 * h) - jac[:, k])) < 1e-6 * np.max(np.abs(jac[:, k]))
