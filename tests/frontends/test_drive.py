"""The AC drive γ(t) = γ + A sin(Ωt + φ): the model, every path, the refusals, the oracle.

The driven equation θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ) is integrated by the Taylor
kind, the drive's series entering the coefficient recurrence at each window's start time
(``mbm/approximants/taylor.py``, "AC drive").  The accuracy is checked against heyoka in
long double with the drive in its own expression system (``tests/data/oracle_heyoka.py``)
on random scenes of the box β ∈ [0, 2], |γ| ≤ 1.5, A ∈ [0, 2], Ω ∈ [0.2, 3]
(``oracle_scenes.driven_scenes``), with test_oracle's error measure and round-off
allowance.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm.approximants import ApproximantDomainError

import oracle_heyoka  # noqa: E402  tests/data, on pytest's pythonpath
import oracle_scenes  # noqa: E402

DRIVEN = mbm.Pendulum(0.5, 0.3, 1.0, drive_amplitude=1.2, drive_frequency=0.7, drive_phase=0.3)
Y0 = [0.1, 0.0]

# Random driven scenes: SEED fixes the draw (N_DEFAULT in the default run, N_SLOW more
# under -m slow with another seed).
SEED = 14
N_DEFAULT = 60
SEED_SLOW = 2014
N_SLOW = 1000
TOLS = (1e-4, 1e-8, 1e-12)
# As tests/test_oracle.py: the error within 100× the tolerance, plus the round-off
# allowance 10·eps·κ·√n (n windows, κ the outputs' sensitivity to the initial state).
PROPORTIONALITY_BOUND = 100.0
EPS = np.finfo(float).eps
# A drive makes the equation three-dimensional, and chaos possible: on a chaotic scene
# a local error is amplified by κ ~ e^{λT} (measured up to 7e11 on the 1000 scenes of
# seed 2014), so no tolerance bounds the global error there, for mbm as for any
# integrator.  Proportionality is asserted on the well-conditioned scenes, κ ≤ this
# (972 of those 1000: max error/tol 0.42, 0.52, 1.9 at 1e-4, 1e-8, 1e-12; among the
# other 28, 4e3× at 1e-4 for κ = 1.8e8, 1e6× for κ = 7e11); they must be most of the draw.
KAPPA_WELL_CONDITIONED = 1e4
MIN_WELL_CONDITIONED = 0.8

DEFAULT_SCENES = oracle_scenes.driven_scenes(N_DEFAULT, SEED)
SLOW_SCENES = oracle_scenes.driven_scenes(N_SLOW, SEED_SLOW)

needs_oracle = pytest.mark.skipif(
    not oracle_heyoka.available(),
    reason="the oracle needs heyoka (the test extra) and an 80-bit long double (x86-64)")


# ---------------------------------------------------------------------------
# The model
# ---------------------------------------------------------------------------


def test_pendulum_carries_the_drive():
    m = mbm.Pendulum(0.5, 0.3, 2.0, drive_amplitude=1.2, drive_frequency=0.7, drive_phase=0.3)
    assert m.drive == (1.2, 0.7, 0.3) and m.driven
    assert (m.drive_amplitude, m.drive_frequency, m.drive_phase) == (1.2, 0.7, 0.3)
    assert m.params == (0.5, 0.3, 2.0)
    assert repr(m) == ("Pendulum(beta=0.5, gamma=0.3, omega=2.0, drive_amplitude=1.2, "
                       "drive_frequency=0.7, drive_phase=0.3)")
    assert eval("mbm." + repr(m)) == m and hash(eval("mbm." + repr(m))) == hash(m)
    assert m != mbm.Pendulum(0.5, 0.3, 2.0)
    assert m != mbm.Pendulum(0.5, 0.3, 2.0, drive_amplitude=1.2, drive_frequency=0.7)
    # undriven: as before the drive existed
    u = mbm.Pendulum(0.5, 0.3, 2.0)
    assert repr(u) == "Pendulum(beta=0.5, gamma=0.3, omega=2.0)" and not u.driven
    assert hash(u) == hash((0.5, 0.3, 2.0)) and u.drive == (0.0, 0.0, 0.0)
    # the right-hand side, the SUNDIALS callbacks, the Jacobian
    t, y = 2.5, np.array([0.4, -0.7])
    torque = 0.3 + 1.2 * math.sin(0.7 * t + 0.3)
    expect = [-0.7, torque - 0.5 * -0.7 - 4.0 * math.sin(0.4)]
    np.testing.assert_allclose(m(t, y), expect, rtol=1e-15)
    rhs, jac = m.sundials_callbacks()
    yp = np.empty(2)
    rhs(t, y, yp)
    np.testing.assert_allclose(yp, expect, rtol=1e-15)
    jj = np.empty((2, 2))
    jac(t, y, None, jj)
    np.testing.assert_array_equal(jj, m.jac(t, y))
    np.testing.assert_array_equal(m.jac(t, y), u.jac(t, y))
    assert "not conserved" in mbm.Pendulum.energy.__doc__


@pytest.mark.parametrize(
    "kw,exc,match",
    [
        (dict(drive_amplitude=float("nan")), ValueError, "drive_amplitude must be finite"),
        (dict(drive_amplitude=float("inf")), ValueError, "drive_amplitude must be finite"),
        (dict(drive_frequency=float("inf")), ValueError, "drive_frequency must be finite"),
        (dict(drive_frequency=-0.5), ValueError, r"drive_frequency must be >= 0"),
        (dict(drive_phase=float("nan")), ValueError, "drive_phase must be finite"),
        (dict(drive_phase="zero"), TypeError, "drive_phase must be a real number"),
        (dict(drive_amplitude=[1.0]), TypeError, "drive_amplitude must be a real number"),
    ],
)
def test_bad_drive_rejected(kw, exc, match):
    with pytest.raises(exc, match=match):
        mbm.Pendulum(0.1, 0.2, 1.0, **kw)


@pytest.mark.parametrize(
    "kw,match",
    [
        (dict(drive_amplitude=[1.0, float("nan")]), r"drive_amplitude must be finite, got drive_amplitude\[1\]"),
        (dict(drive_amplitude=1.0, drive_frequency=[0.5, -1.0]), r"drive_frequency must be >= 0"),
        (dict(drive_amplitude=1.0, drive_phase=[0.0, 1.0, 2.0]), "drive_phase must broadcast to one shape"),
    ],
)
def test_bad_drive_rejected_by_batch(kw, match):
    with pytest.raises(ValueError, match=match):
        mbm.solve_batch([0.1, 0.2], 0.3, 1.0, Y0, (0.0, 1.0), [0.0, 1.0], **kw)


def test_zero_amplitude_changes_nothing():
    # A = 0 with a frequency and phase: the undriven run, bit for bit, regimes included.
    plain = mbm.Pendulum(1.0, 0.3)
    idle = mbm.Pendulum(1.0, 0.3, drive_frequency=2.0, drive_phase=1.0)
    t = np.linspace(0.0, 200.0, 101)
    a = mbm.solve(plain, (0.0, 200.0), Y0, rtol=1e-9, atol=1e-9, t_eval=t)
    b = mbm.solve(idle, (0.0, 200.0), Y0, rtol=1e-9, atol=1e-9, t_eval=t)
    np.testing.assert_array_equal(a.y, b.y)
    assert a.regime == b.regime == "locked" and a.n_windows == b.n_windows
    c = solve_ivp(idle, (0.0, 200.0), Y0, method=mbm.MBM, rtol=1e-9, atol=1e-9, t_eval=t)
    np.testing.assert_array_equal(c.y, a.y)
    assert mbm.solve(mbm.Pendulum(0.0, 0.0, drive_frequency=1.0), (0.0, 5.0), Y0).approximant == "belendez"


# ---------------------------------------------------------------------------
# The driven series
# ---------------------------------------------------------------------------


def test_driven_series_matches_the_equation():
    # θ_N'' + βθ_N' + ω² sin θ_N − γ − A sin(Ω(t₀ + s) + φ) vanishes to O(s^(N−1)): at
    # s = 1e-2 (well inside the radius) it is round-off.
    ap = mbm.get_approximant("taylor")
    t0 = 3.7
    a = ap.anchor(DRIVEN, 0.4, -0.6, t0=t0)
    coefs = a.params["coefficients"]
    n = coefs.size - 1
    for s in (1e-3, 1e-2, 3e-2):
        th = sum(coefs[k] * s**k for k in range(n + 1))
        v = sum(k * coefs[k] * s ** (k - 1) for k in range(1, n + 1))
        acc = sum(k * (k - 1) * coefs[k] * s ** (k - 2) for k in range(2, n + 1))
        beta, gamma, omega = DRIVEN.params
        amp, freq, phase = DRIVEN.drive
        res = acc + beta * v + omega**2 * math.sin(th) - gamma - amp * math.sin(freq * (t0 + s) + phase)
        assert abs(res) < 1e-14, (s, res)
    # the anchor time matters (the drive's phase), the anchor state is reproduced
    b = ap.anchor(DRIVEN, 0.4, -0.6, t0=t0 + 1.0)
    assert a(0.0) == b(0.0) == (0.4, -0.6)
    assert abs(a(0.5)[0] - b(0.5)[0]) > 1e-3


def test_drive_phase_is_exact_at_large_t0():
    # The drive's phase Ωt₀ + φ carries Ω·t₀'s rounding: anchored at t₀ = 1e7 the
    # coefficients equal those at t₀ = 0 with φ' = Ωt₀ + φ (mod 2π) computed in 50-digit
    # arithmetic, to round-off; the plain double phase fl(fl(Ω·t₀) + φ) is off by ~1e-10.
    import mpmath

    mpmath.mp.dps = 50
    freq, phase, t0 = 0.7318, 0.3, 1.0e7 + 0.123
    exact = mpmath.fmod(mpmath.mpf(freq) * mpmath.mpf(t0) + mpmath.mpf(phase), 2 * mpmath.pi)
    naive = math.fmod(freq * t0 + phase, 2 * math.pi)
    assert abs(naive - float(exact)) > 1e-11  # the error the exact product avoids
    ap = mbm.get_approximant("taylor")
    at_t0 = ap.anchor(mbm.Pendulum(0.5, 0.3, 1.0, 1.2, freq, phase), 0.4, -0.6, t0=t0).params["coefficients"]
    at_0 = ap.anchor(mbm.Pendulum(0.5, 0.3, 1.0, 1.2, freq, float(exact)), 0.4, -0.6).params["coefficients"]
    np.testing.assert_allclose(at_t0, at_0, rtol=0, atol=4 * EPS)


# ---------------------------------------------------------------------------
# Every path, one answer
# ---------------------------------------------------------------------------

PATH_SCENES = [
    (DRIVEN, Y0, 60.0, 1e-9),
    (DRIVEN, Y0, -12.0, 1e-7),  # backwards (anti-damped: short)
    (mbm.Pendulum(0.0, 0.0, 1.0, 0.8, 1.3, 0.0), [0.5, 0.0], 50.0, 1e-10),  # β = γ = 0, driven
    (mbm.Pendulum(0.1, 1.2, 1.0, 0.5, 2.0, 1.0), [0.0, 0.0], 100.0, 1e-6),  # running, driven
    (mbm.Pendulum(2.0, 1.5, 1.0, 1.0, 1.0, 0.0), [0.0, 0.0], 80.0, 1e-12),  # a Shapiro step
]


@pytest.mark.parametrize("model,y0,T,tol", PATH_SCENES)
def test_paths_agree_bit_for_bit(model, y0, T, tol):
    t = np.linspace(0.0, T, 201)
    kw = dict(rtol=tol, atol=tol)
    fast = mbm.solve(model, (0.0, T), y0, t_eval=t, **kw)
    assert fast.success and fast.approximant == "taylor" and fast.regime is None
    assert "AC drive" in fast.reason
    ivp = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, windows_per_step=None,
                    dense_output=True, **kw)
    assert ivp.success
    np.testing.assert_array_equal(ivp.y, fast.y)
    np.testing.assert_array_equal(ivp.sol(t), fast.y)  # the windows' formulas
    one = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, dense_output=True, **kw)
    ends = mbm.solve(model, (0.0, T), y0, **kw)
    np.testing.assert_array_equal(one.t, ends.t)
    np.testing.assert_array_equal(one.y, ends.y)
    np.testing.assert_array_equal(one.sol(t), fast.y)
    ig = mbm.Integrator(model, **kw)
    np.testing.assert_array_equal(ig.solve((0.0, T), y0, t_eval=t).y, fast.y)
    out = np.empty((2, t.size))
    status, nw = mbm.solve_njit(*model.params, 0.0, y0[0], y0[1], T, t, out, tol, tol, 10**7, *model.drive)
    assert status == 0 and nw == fast.n_windows
    np.testing.assert_array_equal(out, fast.y)
    # a batch mixing this scene with its undriven twin and another drive
    amp, freq, phase = model.drive
    batch = mbm.solve_batch(model.beta, model.gamma, model.omega, y0, (0.0, T), t,
                            drive_amplitude=[amp, 0.0, 0.5 * amp], drive_frequency=freq, drive_phase=phase, **kw)
    assert batch.success.all()
    np.testing.assert_array_equal(batch.y[0], fast.y)
    assert batch.n_windows[0] == fast.n_windows and batch.regime[0] is None
    twin = mbm.solve(mbm.Pendulum(*model.params), (0.0, T), y0, t_eval=t, **kw)
    np.testing.assert_array_equal(batch.y[1], twin.y)
    half = mbm.solve(mbm.Pendulum(*model.params, 0.5 * amp, freq, phase), (0.0, T), y0, t_eval=t, **kw)
    np.testing.assert_array_equal(batch.y[2], half.y)


def test_dense_output_is_the_window_formula():
    # Each step (one window) of the solver: its dense output is the driven formula
    # anchored at the window's start, θ = 2πk + φ with φ the reduced angle the loop
    # anchors at (mbm.core.window "Winding": reduced where θ's value is unchanged).
    from mbm.core import window

    solver = mbm.MBM(DRIVEN, 0.0, np.array(Y0, dtype=float), 30.0, rtol=1e-10, atol=1e-10)
    ap = mbm.get_approximant("taylor")
    steps = 0
    while solver.status == "running":
        rec = mbm.core.record.flat(solver._run)[0]
        k, phi = (float(rec["wind"]), float(rec["phi"])) if rec["n_windows"] else (0.0, solver.y[0])
        k2, phi2 = window.wrap(k, phi)
        if window.theta_of(k2, phi2) == window.theta_of(k, phi):
            k, phi = k2, phi2
        v0, t0 = solver.y[1], solver.t
        solver.step()
        formula = ap.anchor(DRIVEN, phi, v0, t0=t0)
        tm = np.linspace(t0, solver.t, 7)
        th, v = formula(tm - t0)
        want = np.array([[window.theta_of(k, x) for x in np.atleast_1d(th)], v])
        np.testing.assert_array_equal(solver.dense_output()(tm), want)
        assert tuple(solver.dense_output()(solver.t)) == tuple(solver.y)
        steps += 1
    assert steps > 10 and abs(solver.y[0]) > np.pi


def test_driven_scene_takes_only_the_phase_locked_regime():
    # The same scenes lock or reach their cycle undriven.  Weakly driven, the locked one
    # follows the drive on a periodic orbit of the stroboscopic map (p = 0 turns per
    # drive period: mbm.regimes S1-S6, "phase-locked"); the running one is not locked to
    # the drive and is integrated to the end (the locked and running regimes assume an
    # autonomous equation).
    t = np.linspace(0.0, 300.0, 31)
    for beta, gamma, regime, driven_regime in ((1.0, 0.3, "locked", "phase-locked"),
                                               (0.1, 1.2, "running", None)):
        r0 = mbm.solve(mbm.Pendulum(beta, gamma), (0.0, 300.0), Y0, rtol=1e-8, atol=1e-8, t_eval=t)
        r1 = mbm.solve(mbm.Pendulum(beta, gamma, 1.0, 1e-3, 0.9), (0.0, 300.0), Y0, rtol=1e-8, atol=1e-8,
                       t_eval=t)
        assert r0.regime == regime and r1.regime == driven_regime
        if driven_regime is None:
            assert math.isnan(r1.t_regime) and r1.n_windows > r0.n_windows
        else:
            assert r1.mean_velocity == 0.0 and r1.period == 2.0 * math.pi / 0.9 and r1.t_regime < 300.0
        b = mbm.solve_batch(beta, gamma, 1.0, Y0, (0.0, 300.0), t, rtol=1e-8, atol=1e-8,
                            drive_amplitude=[0.0, 1e-3], drive_frequency=0.9)
        assert list(b.regime) == [regime, driven_regime]
        np.testing.assert_array_equal(b.y[1], r1.y)
        ivp = solve_ivp(mbm.Pendulum(beta, gamma, 1.0, 1e-3, 0.9), (0.0, 300.0), Y0, method=mbm.MBM,
                        rtol=1e-8, atol=1e-8, windows_per_step=None, t_eval=t)
        assert ivp.success
        np.testing.assert_array_equal(ivp.y, r1.y)


# ---------------------------------------------------------------------------
# Refusals
# ---------------------------------------------------------------------------

REFUSING = [n for n in mbm.approximant_names() if not mbm.get_approximant(n).drive_capable]


def test_every_non_taylor_approximant_refuses():
    assert set(mbm.approximant_names()) - set(REFUSING) == {n for n in mbm.approximant_names()
                                                             if n.startswith("taylor")}
    assert {"belendez", "salas-torque", "split4", "sbab2", "johannessen"} <= set(REFUSING)


@pytest.mark.parametrize("name", REFUSING)
def test_refusal_names_the_drive_and_taylor(name):
    ap = mbm.get_approximant(name)
    match = rf"approximant '{name}' cannot integrate the AC drive .*approximant='taylor'"
    with pytest.raises(ApproximantDomainError, match=match):
        ap.anchor(DRIVEN, *Y0)
    with pytest.raises(ValueError, match=match):
        solve_ivp(DRIVEN, (0.0, 1.0), Y0, method=mbm.MBM, approximant=name, tau=0.1)
    if ap.compiled_kind is not None:
        with pytest.raises(ValueError, match=match):
            mbm.solve(DRIVEN, (0.0, 1.0), Y0, approximant=name, tau=0.1)
        with pytest.raises(ValueError, match=match):
            mbm.solve_batch(0.5, 0.3, 1.0, Y0, (0.0, 1.0), [0.0, 1.0], approximant=name, tau=0.1,
                            drive_amplitude=[0.0, 1.2], drive_frequency=0.7)


def test_event_anchors_refuse_the_drive():
    with pytest.raises(ValueError, match="anchors='events' cannot take the AC drive"):
        solve_ivp(DRIVEN, (0.0, 1.0), Y0, method=mbm.MBM, anchors="events")


def test_time_dependent_callable_is_identified():
    def forced(t, y):
        return [y[1], 0.3 + 1.2 * math.sin(0.7 * t + 0.3) - 0.5 * y[1] - math.sin(y[0])]

    # the drive identified by probing (tests/frontends/test_probe.py: the client forms)
    model, _ = mbm.identify_model(forced, 0.0, 20.0)
    assert model.drive_frequency == 0.7 and model.drive_phase == pytest.approx(0.3, abs=1e-14)
    assert model.drive_amplitude == pytest.approx(1.2, rel=1e-14) and model.gamma == pytest.approx(0.3, rel=1e-14)
    ref = mbm.reference(DRIVEN, (0.0, 20.0), Y0, t_eval=[20.0])
    for kw in ({}, {"model": DRIVEN}):
        sol = solve_ivp(forced, (0.0, 20.0), Y0, method=mbm.MBM, rtol=1e-10, atol=1e-10, **kw)
        assert abs(sol.y[0, -1] - ref.y[0, -1]) < 1e-9
    # a non-member without time dependence: no drive in the message
    with pytest.raises(ValueError, match="not of the pendulum family") as err:
        solve_ivp(lambda t, y: [y[1], (1 - y[0] ** 2) * y[1] - y[0]], (0.0, 1.0), Y0, method=mbm.MBM)
    assert "depends on t" not in str(err.value)


# ---------------------------------------------------------------------------
# Against the oracle
# ---------------------------------------------------------------------------


@needs_oracle
def test_cvode_reference_takes_the_drive():
    t = np.linspace(0.0, 50.0, 11)
    h = oracle_heyoka.reference(*DRIVEN.params, Y0, t, drive=DRIVEN.drive).astype(float)
    for solver in ("cvode", "ida", "dop853"):
        ref = mbm.reference(DRIVEN, (0.0, 50.0), Y0, t_eval=t, solver=solver)
        assert np.max(np.abs(ref.y - h)) < (1e-9 if solver == "cvode" else 1e-7), solver


def _check_proportional(scenes):
    well = 0
    for scene in scenes:
        if oracle_scenes.oracle_with_floor(scene)[1] > KAPPA_WELL_CONDITIONED:
            continue
        well += 1
        oracle_scenes.assert_proportional(scene, TOLS, PROPORTIONALITY_BOUND)
    assert well >= MIN_WELL_CONDITIONED * len(scenes), (well, len(scenes))


def _check_monotone(scenes):
    for scene in scenes:
        oracle_scenes.assert_monotone(scene)


@needs_oracle
def test_driven_error_proportional_to_tolerance():
    _check_proportional(DEFAULT_SCENES)


@needs_oracle
def test_driven_error_monotone_in_tolerance():
    _check_monotone(DEFAULT_SCENES)


@needs_oracle
def test_driven_scene_draw_is_fixed_and_in_the_box():
    assert oracle_scenes.driven_scenes(N_DEFAULT, SEED) == DEFAULT_SCENES
    for s in DEFAULT_SCENES:
        assert 0.0 <= s.beta <= 2.0 and abs(s.gamma) <= 1.5 and 0.0 <= s.amp <= 2.0 and 0.2 <= s.freq <= 3.0
    assert sum(s.beta == 0.0 for s in DEFAULT_SCENES) == N_DEFAULT // 4


@needs_oracle
@pytest.mark.parametrize("tol", TOLS)
def test_driven_batch_agrees_bit_for_bit(tol):
    scenes = DEFAULT_SCENES
    T = 30.0
    t = np.linspace(0.0, T, oracle_scenes.N_OUTPUT)
    cols = {k: np.array([getattr(s, k) for s in scenes]) for k in ("beta", "gamma", "omega", "amp", "freq",
                                                                  "phase")}
    y0 = np.array([(s.theta0, s.v0) for s in scenes])
    batch = mbm.solve_batch(cols["beta"], cols["gamma"], cols["omega"], y0, (0.0, T), t, rtol=tol, atol=tol,
                            drive_amplitude=cols["amp"], drive_frequency=cols["freq"],
                            drive_phase=cols["phase"])
    assert np.all(batch.success), batch.status
    for i, s in enumerate(scenes):
        one = mbm.solve(oracle_scenes.model(s), (0.0, T), y0[i], rtol=tol, atol=tol, t_eval=t)
        np.testing.assert_array_equal(batch.y[i], one.y, err_msg=repr(s))
        ivp = solve_ivp(oracle_scenes.model(s), (0.0, T), y0[i], method=mbm.MBM, rtol=tol, atol=tol,
                        t_eval=t, windows_per_step=None)
        np.testing.assert_array_equal(ivp.y, one.y, err_msg=repr(s))


@needs_oracle
@pytest.mark.slow
def test_driven_error_proportional_to_tolerance_slow():
    _check_proportional(SLOW_SCENES)


@needs_oracle
@pytest.mark.slow
def test_driven_error_monotone_in_tolerance_slow():
    _check_monotone(SLOW_SCENES)


def test_sweep_takes_the_drive():
    # Drive parameters as sweep dimensions (after the others) or attributes; each scene
    # equals mbm.solve of its driven model, bit for bit; no drive: no drive attributes.
    t = np.linspace(0.0, 40.0, 9)
    ds = mbm.sweep(beta=0.5, gamma=[0.1, 0.3], drive_amplitude=[0.0, 1.2], drive_frequency=0.7,
                   t_span=(0.0, 40.0), t_eval=t, rtol=1e-9, atol=1e-9, theta0=0.1)
    assert ds.theta.dims == ("gamma", "drive_amplitude", "time")
    assert ds.attrs["drive_frequency"] == 0.7 and ds.attrs["drive_phase"] == 0.0
    for g in (0.1, 0.3):
        for a in (0.0, 1.2):
            one = mbm.solve(mbm.Pendulum(0.5, g, 1.0, a, 0.7), (0.0, 40.0), [0.1, 0.0], rtol=1e-9, atol=1e-9,
                            t_eval=t)
            np.testing.assert_array_equal(ds.theta.sel(gamma=g, drive_amplitude=a).values, one.y[0])
    chunked = mbm.sweep(beta=0.5, gamma=[0.1, 0.3], drive_amplitude=[0.0, 1.2], drive_frequency=0.7,
                        t_span=(0.0, 40.0), t_eval=t, rtol=1e-9, atol=1e-9, theta0=0.1, chunks=1)
    np.testing.assert_array_equal(chunked.theta.values, ds.theta.values)
    plain = mbm.sweep(beta=0.5, gamma=[0.1, 0.3], t_span=(0.0, 40.0), t_eval=t)
    assert not any(k.startswith("drive") for k in plain.attrs)
    with pytest.raises(ValueError, match="drive_frequency must be >= 0"):
        mbm.sweep(beta=0.5, gamma=0.1, drive_amplitude=1.0, drive_frequency=[1.0, -1.0], t_span=(0.0, 1.0),
                  t_eval=[1.0])
    with pytest.raises(ValueError, match="cannot integrate the AC drive"):
        mbm.sweep(beta=0.5, gamma=0.1, drive_amplitude=1.0, drive_frequency=1.0, t_span=(0.0, 1.0), t_eval=[1.0],
                  approximant="split4", tau=0.1)
