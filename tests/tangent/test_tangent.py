"""error_estimate= and sensitivities= (mbm.tangent): the same run, the paths equal,
sensitivities against heyoka's variational equations and central differences, the
estimate against heyoka in long double, the warning, the options' checks."""

import warnings

import numpy as np
import pytest

import mbm

# heyoka (the test extra: pip install -e ".[test]") is the long-double reference and the
# var_ode_sys peer these tests compare with; without it there is nothing to compare to.
hy = pytest.importorskip("heyoka", reason="heyoka, the long-double reference, is not installed (pip install heyoka)")

ALL = mbm.SENSITIVITY_NAMES
DRIVEN = mbm.Pendulum(0.3, 0.4, drive_amplitude=0.6, drive_frequency=0.8, drive_phase=0.3)
DAMPED = mbm.Pendulum(0.1, 0.3)


def _system():
    x, v = hy.make_vars("x", "v")
    b, g, w, a, f, p = (hy.par[i] for i in range(6))
    return [(x, v), (v, -b * v - w * w * hy.sin(x) + g + a * hy.sin(f * hy.time + p))]


def _pars(model):
    return list(model.params) + list(model.drive)


def _truth(model, y0, te):
    # heyoka in long double at tol 1e-19: (θ, θ') at te, shape (2, n).
    ld = np.longdouble
    ta = hy.taylor_adaptive(_system(), np.array(y0, ld), pars=np.array(_pars(model), ld), tol=ld(1e-19),
                            fp_type=ld, compact_mode=True, time=ld(te[0]))
    return np.asarray(ta.propagate_grid(np.asarray(te, ld))[-1], np.float64).T


def _quiet(*args, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mbm.AccuracyWarning)
        return mbm.solve(*args, **kw)


@pytest.mark.parametrize("model", [DAMPED, DRIVEN, mbm.Pendulum(0.07, 0.9)])
def test_same_run_with_the_options(model):
    te = np.linspace(0.0, 120.0, 101)
    plain = mbm.solve(model, (0.0, 120.0), [0.5, 0.0], t_eval=te, rtol=1e-8, atol=1e-8)
    r = _quiet(model, (0.0, 120.0), [0.5, 0.0], t_eval=te, rtol=1e-8, atol=1e-8, error_estimate=True,
               sensitivities=ALL)
    assert np.array_equal(plain.y, r.y) and plain.n_windows == r.n_windows and plain.regime == r.regime
    assert r.error_estimate.shape == r.y.shape
    assert r.sensitivities.shape == (len(ALL), 2, te.size) and r.sensitivity_names == ALL
    assert "error_estimate" not in plain and "sensitivities" not in plain


def test_integrator_and_solve_agree_bit_for_bit():
    te = np.linspace(0.0, 60.0, 51)
    ig = mbm.Integrator(DRIVEN, rtol=1e-9, atol=1e-9)
    a = ig.solve((0.0, 60.0), [0.2, 0.1], t_eval=te, error_estimate=True, sensitivities=("beta", "drive_phase"))
    b = mbm.solve(DRIVEN, (0.0, 60.0), [0.2, 0.1], t_eval=te, rtol=1e-9, atol=1e-9, error_estimate=True,
                  sensitivities=("beta", "drive_phase"))
    assert np.array_equal(a.error_estimate, b.error_estimate)
    assert np.array_equal(a.sensitivities, b.sensitivities)


def test_sensitivities_match_heyoka_variational_equations():
    # heyoka's var_ode_sys (order 1, state and parameters) at tol 1e-15; mbm at rtol 1e-10:
    # within 1e-6 of the sensitivities' scale.
    te = np.linspace(0.0, 60.0, 61)
    y0 = [0.4, -0.2]
    vs = hy.var_ode_sys(_system(), hy.var_args.vars | hy.var_args.params, order=1)
    ta = hy.taylor_adaptive(vs, y0, pars=_pars(DRIVEN), tol=1e-15, compact_mode=True)
    ref = ta.propagate_grid(te)[-1]
    r = mbm.solve(DRIVEN, (0.0, 60.0), y0, t_eval=te, rtol=1e-10, atol=1e-10, sensitivities=ALL)
    # heyoka's columns 2..9 are ∂x/∂(x0, v0, β, γ, ω, A, Ω, φ), 10..17 the same of v.
    mine = np.concatenate([r.sensitivities[:, 0, :].T, r.sensitivities[:, 1, :].T], axis=1)
    scale = np.abs(ref[:, 2:]).max()
    assert np.abs(mine - ref[:, 2:]).max() < 1e-6 * scale


@pytest.mark.parametrize("direction", [1.0, -1.0])
def test_sensitivities_match_central_differences(direction):
    t1 = 25.0 if direction > 0 else -8.0  # backwards the damping amplifies
    te = np.linspace(0.0, t1, 21)
    y0 = np.array([0.3, 0.2])
    base = dict(beta=0.5, gamma=0.3, omega=1.1, drive_amplitude=0.5, drive_frequency=0.9, drive_phase=0.4)
    kw = dict(t_eval=te, rtol=1e-12, atol=1e-12)
    r = mbm.solve(mbm.Pendulum(**base), (0.0, t1), y0, sensitivities=ALL, **kw)
    h = 1e-5
    for i, name in enumerate(ALL):
        ends = []
        for sign in (1.0, -1.0):
            p, y = dict(base), y0.copy()
            if name == "theta0":
                y[0] += sign * h
            elif name == "v0":
                y[1] += sign * h
            else:
                p[name] += sign * h
            ends.append(mbm.solve(mbm.Pendulum(**p), (0.0, t1), y, **kw).y)
        fd = (ends[0] - ends[1]) / (2 * h)
        assert np.abs(r.sensitivities[i] - fd).max() < 1e-6 * max(1.0, np.abs(fd).max()), name


@pytest.mark.parametrize("model, y0, t1, tol", [
    (DAMPED, [0.5, 0.0], 100.0, 1e-6),
    (mbm.Pendulum(0.07, 0.9), [0.0, 0.0], 150.0, 1e-9),
    (DRIVEN, [0.0, 0.0], 300.0, 1e-9),
    (mbm.Pendulum(0.05, 0.3), [1.0, 0.0], 2000.0, 1e-6),
])
def test_estimate_tracks_the_true_error(model, y0, t1, tol):
    # Effectivity max|estimate| / max|true error| of θ near 1 (truth: heyoka long double).
    te = np.linspace(0.0, t1, 201)
    r = _quiet(model, (0.0, t1), y0, t_eval=te, rtol=tol, atol=tol, error_estimate=True)
    true = r.y - _truth(model, y0, te)
    eff = np.abs(r.error_estimate[0]).max() / np.abs(true[0]).max()
    assert 0.5 < eff < 2.0
    # pointwise too: the estimate follows the error's sign and size where it is large
    big = np.abs(true[0]) > 0.5 * np.abs(true[0]).max()
    assert np.all(np.sign(r.error_estimate[0, big]) == np.sign(true[0, big]))


def test_warns_where_the_estimate_exceeds_the_tolerance():
    te = np.linspace(0.0, 300.0, 201)
    with pytest.warns(mbm.AccuracyWarning, match="times the tolerance"):
        mbm.solve(DRIVEN, (0.0, 300.0), [0.0, 0.0], t_eval=te, rtol=1e-6, atol=1e-6, error_estimate=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error", mbm.AccuracyWarning)
        mbm.solve(DAMPED, (0.0, 80.0), [0.5, 0.0], t_eval=te[:50], rtol=1e-6, atol=1e-6, error_estimate=True)


def test_window_ends_wrap_and_the_start():
    r = mbm.solve(DAMPED, (0.0, 30.0), [0.5, 0.1], rtol=1e-8, atol=1e-8, error_estimate=True,
                  sensitivities=("v0", "theta0", "gamma"))
    assert r.error_estimate.shape == r.y.shape and np.all(r.error_estimate[:, 0] == 0.0)
    assert np.array_equal(r.sensitivities[:, :, 0], [[0.0, 1.0], [1.0, 0.0], [0.0, 0.0]])
    te = np.linspace(0.0, 200.0, 41)
    running = mbm.Pendulum(0.1, 1.2)
    a = mbm.solve(running, (0.0, 200.0), [0.0, 0.0], t_eval=te, error_estimate=True)
    b = mbm.solve(running, (0.0, 200.0), [0.0, 0.0], t_eval=te, error_estimate=True, wrap=True)
    # the same estimate, but for the rounding of the unwound θ (θ reaches ~2300 rad: ulp 4.5e-13)
    assert np.abs(a.error_estimate - b.error_estimate).max() < 8 * np.spacing(np.abs(a.y[0]).max())


def test_exact_flow_estimate_is_zero():
    # β = γ = 0: the exact elliptic flow, exact to round-off (its error is not measured).
    r = mbm.solve(mbm.Pendulum(), (0.0, 50.0), [1.0, 0.0], t_eval=np.linspace(0, 50, 11), error_estimate=True,
                  sensitivities=("theta0",))
    assert np.all(r.error_estimate == 0.0) and np.all(np.isfinite(r.sensitivities))


def test_options_are_checked():
    span, y0 = (0.0, 1.0), [0.1, 0.0]
    with pytest.raises(TypeError, match="error_estimate"):
        mbm.solve(DAMPED, span, y0, error_estimate="yes")
    with pytest.raises(TypeError, match="sensitivities"):
        mbm.solve(DAMPED, span, y0, sensitivities="beta")
    with pytest.raises(ValueError, match="unknown name 'mass'"):
        mbm.solve(DAMPED, span, y0, sensitivities=("mass",))
    with pytest.raises(ValueError, match="repeated"):
        mbm.solve(DAMPED, span, y0, sensitivities=("beta", "beta"))
    with pytest.raises(ValueError, match="events"):
        mbm.solve(DAMPED, span, y0, error_estimate=True, events=mbm.angle_event(0.0))
    with pytest.raises(ValueError, match="temperature"):
        mbm.solve(DAMPED, span, y0, error_estimate=True, temperature=0.1, seed=1, dt=0.01)
    with pytest.raises(TypeError, match="error_estimate"):
        mbm.Integrator(DAMPED).solve(span, y0, error_estimate=1)


@pytest.mark.parametrize("model, y0, t1, regime", [
    (mbm.Pendulum(0.05, 0.3), [1.0, 0.0], 1500.0, "locked"),  # the linear flow once settled
    (mbm.Pendulum(0.1, 1.2), [0.0, 0.0], 600.0, "running"),  # Floquet over the stored period
    (mbm.Pendulum(0.2, 0.0, drive_amplitude=0.5, drive_frequency=1.5), [0.1, 0.0], 600.0, "phase-locked"),
])
def test_regime_windows(model, y0, t1, regime):
    # The windows of a regime that stops integrating: the estimate against the true error,
    # the sensitivities against heyoka's variational equations.
    te = np.linspace(0.0, t1, 201)
    names = ("theta0", "v0", "beta", "gamma", "omega")
    r = _quiet(model, (0.0, t1), y0, t_eval=te, rtol=1e-9, atol=1e-9, error_estimate=True, sensitivities=names)
    assert r.regime == regime
    true = r.y - _truth(model, y0, te)
    eff = np.abs(r.error_estimate[0]).max() / np.abs(true[0]).max()
    assert 0.3 < eff < 3.0
    vs = hy.var_ode_sys(_system(), hy.var_args.vars | hy.var_args.params, order=1)
    ref = hy.taylor_adaptive(vs, y0, pars=_pars(model), tol=1e-15, compact_mode=True).propagate_grid(te)[-1]
    cols = list(range(2, 7)) + list(range(10, 15))
    mine = np.concatenate([r.sensitivities[:, 0, :].T, r.sensitivities[:, 1, :].T], axis=1)
    scale = np.abs(ref[:, cols]).max()
    assert np.abs(mine - ref[:, cols]).max() < 1e-5 * scale


def test_solve_batch_equals_solve():
    gammas = np.array([0.3, 0.9, 1.2])
    te = np.linspace(0.0, 150.0, 51)
    b = mbm.solve_batch(0.1, gammas, 1.0, [0.5, 0.0], (0.0, 150.0), te, rtol=1e-8, atol=1e-8,
                        drive_amplitude=[0.0, 0.3, 0.0], drive_frequency=[0.0, 0.7, 0.0],
                        error_estimate=True, sensitivities=("gamma", "theta0"))
    assert b.error_estimate.shape == (3, 2, 51) and b.sensitivities.shape == (3, 2, 2, 51)
    for i, g in enumerate(gammas):
        model = mbm.Pendulum(0.1, g, drive_amplitude=[0.0, 0.3, 0.0][i], drive_frequency=[0.0, 0.7, 0.0][i])
        r = mbm.solve(model, (0.0, 150.0), [0.5, 0.0], t_eval=te, rtol=1e-8, atol=1e-8, error_estimate=True,
                      sensitivities=("gamma", "theta0"))
        assert np.array_equal(b.y[i], r.y)
        assert np.array_equal(b.error_estimate[i], r.error_estimate)
        assert np.array_equal(b.sensitivities[i], r.sensitivities)
    with pytest.raises(ValueError, match="temperature"):
        mbm.solve_batch(0.1, gammas, 1.0, [0.5, 0.0], (0.0, 1.0), te[:2] / 150, error_estimate=True,
                        temperature=0.1, seed=1, dt=0.01)


def test_solve_ivp_names_the_paths_that_carry_the_estimate():
    from scipy.integrate import solve_ivp

    def fun(t, y):
        return [y[1], -0.1 * y[1] - np.sin(y[0]) + 0.3]

    for name in ("error_estimate", "sensitivities"):
        with pytest.raises(ValueError, match="mbm.solve"):
            solve_ivp(fun, (0.0, 1.0), [0.1, 0.0], method=mbm.MBM, **{name: True})


def test_drive_sensitivities_of_an_undriven_scene():
    # ∂/∂A at A = 0 is the response to sin(Ωt + φ) (the drive's phase is still needed).
    te = np.linspace(0.0, 20.0, 11)
    kw = dict(t_eval=te, rtol=1e-12, atol=1e-12)
    base = dict(beta=0.4, gamma=0.2, drive_frequency=0.9, drive_phase=0.5)
    r = mbm.solve(mbm.Pendulum(**base), (0.0, 20.0), [0.2, 0.0], sensitivities=("drive_amplitude",), **kw)
    h = 1e-5
    up, down = (mbm.solve(mbm.Pendulum(drive_amplitude=s * h, **base), (0.0, 20.0), [0.2, 0.0], **kw).y
                for s in (1.0, -1.0))
    fd = (up - down) / (2 * h)
    assert np.abs(fd).max() > 0.1 and np.abs(r.sensitivities[0] - fd).max() < 1e-6


def test_a_run_of_many_chunks():
    # More windows than one compiled call of the pass takes (CHUNK_WINDOWS: Ctrl-C gets in
    # between calls): the chunks join seamlessly, against heyoka's variational equations.
    from mbm.tangent.transport import CHUNK_WINDOWS

    model = mbm.Pendulum(0.02, 0.0, drive_amplitude=0.2, drive_frequency=0.9)
    te = np.linspace(0.0, 3000.0, 31)
    r = mbm.solve(model, (0.0, 3000.0), [0.1, 0.0], t_eval=te, rtol=1e-10, atol=1e-10,
                  sensitivities=("theta0", "gamma"))
    assert r.n_windows > CHUNK_WINDOWS
    vs = hy.var_ode_sys(_system(), hy.var_args.vars | hy.var_args.params, order=1)
    ref = hy.taylor_adaptive(vs, [0.1, 0.0], pars=_pars(model), tol=1e-15, compact_mode=True).propagate_grid(te)[-1]
    mine = np.stack([r.sensitivities[0, 0], r.sensitivities[1, 0]], axis=1)  # ∂θ/∂θ₀, ∂θ/∂γ
    assert np.abs(mine - ref[:, [2, 5]]).max() < 1e-5 * np.abs(ref[:, [2, 5]]).max()


def test_a_reused_store_gives_a_fresh_integrators_answer():
    # An Integrator keeps the pass's window-coefficient store for its next call: after a
    # long run (the store grown past its first capacity) and a run that switches to its
    # running cycle, a short run's estimate and sensitivities are a fresh Integrator's,
    # bit for bit (no stale window of an earlier run is read).
    from mbm.frontends.solve import TANGENT_CAPACITY

    model = mbm.Pendulum(0.1, 1.2)
    ig = mbm.Integrator(model, rtol=1e-8, atol=1e-8)
    long = ig.solve((0.0, 600.0), [0.0, 0.0], t_eval=np.linspace(0.0, 600.0, 7), error_estimate=True)
    assert long.n_windows > TANGENT_CAPACITY and long.regime == "running"
    for span, y0 in (((0.0, 5.0), [0.5, 0.0]), ((0.0, 300.0), [1.0, 0.2]), ((10.0, 0.0), [0.2, 0.1])):
        te = np.linspace(span[0], span[1], 11)
        mine = ig.solve(span, y0, t_eval=te, error_estimate=True, sensitivities=ALL[:5])
        fresh = mbm.Integrator(model, rtol=1e-8, atol=1e-8).solve(span, y0, t_eval=te, error_estimate=True,
                                                                  sensitivities=ALL[:5])
        np.testing.assert_array_equal(mine.error_estimate, fresh.error_estimate)
        np.testing.assert_array_equal(mine.sensitivities, fresh.sensitivities)


CHAOTIC = mbm.Pendulum(0.5, 0.0, drive_amplitude=1.15, drive_frequency=2 / 3)  # Baker and Gollub's


def test_a_saturated_estimate_comes_from_a_companion_run(monkeypatch):
    # Chaos over T = 600 (heyoka's long double still good to ~1e-6 there): the error at
    # 1e-6 saturates at the attractor's size (tens of rad), where the linear transport
    # keeps growing; past SATURATION the estimate is a tighter companion run's, and its
    # effectivity is near 1 again.  Without the companion it is far above 10.
    import mbm.tangent.api as api

    te = np.linspace(0.0, 600.0, 201)
    true, default = None, api.SATURATION
    for saturation, lo, hi in ((default, 0.3, 3.0), (np.inf, 10.0, np.inf)):
        monkeypatch.setattr(api, "SATURATION", saturation)
        with pytest.warns(mbm.AccuracyWarning) as caught:
            r = mbm.solve(CHAOTIC, (0.0, 600.0), [0.0, 0.0], t_eval=te, rtol=1e-6, atol=1e-6, error_estimate=True)
        if true is None:
            true = r.y[0] - _truth(CHAOTIC, [0.0, 0.0], te)[0]
            assert np.abs(true).max() > 5.0  # saturated
        eff = np.abs(r.error_estimate[0]).max() / np.abs(true).max()
        assert lo < eff < hi, (saturation, eff)
        assert ("companion" in str(caught[0].message)) == (saturation == default)


def test_the_companion_compares_unwrapped_angles():
    te = np.linspace(0.0, 600.0, 101)
    kw = dict(t_eval=te, rtol=1e-6, atol=1e-6, error_estimate=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mbm.AccuracyWarning)
        a = mbm.solve(CHAOTIC, (0.0, 600.0), [0.0, 0.0], **kw)
        b = mbm.solve(CHAOTIC, (0.0, 600.0), [0.0, 0.0], wrap=True, **kw)
    assert np.abs(a.error_estimate[0]).max() > 1.0
    np.testing.assert_allclose(b.error_estimate, a.error_estimate, rtol=0, atol=1e-9)


def test_no_companion_at_the_rtol_floor():
    # The companion must be ten times tighter; at the floor it cannot be: None (the
    # linear estimate stands).
    import mbm.tangent.api as api
    from mbm.validate import RTOL_FLOOR

    ig = mbm.Integrator(CHAOTIC, rtol=RTOL_FLOOR, atol=1e-14)
    r = ig.solve((0.0, 1.0), [0.0, 0.0], t_eval=np.linspace(0.0, 1.0, 5))
    assert api.companion_error(r, ig, (0.0, (0.0, 0.0), 1.0)) is None
    ig = mbm.Integrator(CHAOTIC, rtol=1e-6, atol=1e-6)
    r = ig.solve((0.0, 1.0), [0.0, 0.0], t_eval=np.linspace(0.0, 1.0, 5))
    err = api.companion_error(r, ig, (0.0, (0.0, 0.0), 1.0))
    assert err.shape == (2, 5) and err[:, 0].tolist() == [0.0, 0.0] and 0.0 < np.abs(err).max() < 1e-5
