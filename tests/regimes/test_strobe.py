"""The phase-locked regime of driven runs (mbm.regimes, S1–S6): switch, bound, horizon, paths.

A driven damped run on a Shapiro step converges to a periodic orbit of the
stroboscopic map (θ(t + T_d) = θ(t) + 2πp, T_d = 2π/Ω); once the deviations of the
samples θ(t_s + nT_d) have converged for the rest of the horizon the run is the stored
drive period re-taken from its anchor.  The independent reference is heyoka in long
double with the drive in its own expression system (tests/data/oracle_heyoka.py).
"""

import math
from fractions import Fraction

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm.core import controller, loop, record
from mbm import regimes

import oracle_heyoka  # noqa: E402  tests/data, on pytest's pythonpath

# The n = 1 Shapiro step of β = 0.2, ω = 1, A = 2, Ω = 1 (γ from 0.02 to 0.47 is on it;
# examples/shapiro_steps.py draws steps): its stroboscopic map has a complex pair of
# multipliers, |μ| = e^{−βπ} = 0.53.  (β, γ, ω, A, Ω, φ).
STEP = (0.2, 0.2, 1.0, 2.0, 1.0, 0.0)
Y0 = (0.0, 0.0)
# Near the step's edge: a real multiplier μ₁ = 0.943 (γ = 0.47) and 0.994 (γ = 0.48),
# both above STROBE_MAX_MULTIPLIER; γ = 0.44 has μ₁ = 0.77, below it.
EDGE_SLOW = ((0.2, 0.47, 1.0, 2.0, 1.0, 0.0), (0.2, 0.48, 1.0, 2.0, 1.0, 0.0))
# Motions that are not locked to the drive with one period: chaotic (a 1e-10 change of
# θ₀ grows to O(1) by t = 400 at 1e-12), a 3/4 step reached after a chaotic transient
# (q = 4, S7, at some tolerances), the half step ⟨θ'⟩ = Ω/2 (q = 2, S7:
# tests/regimes/test_subharmonic.py) and a quasi-periodic motion of β = 2 (⟨θ'⟩ = 0.606Ω).
NOT_PERIOD_ONE = ((0.2, 0.2, 1.0, 1.0, 1.0, 0.0), (0.5, 0.6, 1.0, 1.0, 1.0, 0.0),
                  (0.2, 0.3, 1.0, 1.0, 1.0, 0.0), (2.0, 1.5, 1.0, 1.0, 1.0, 0.0))
TOLS = (1e-8, 1e-10, 1e-12)
# Long-double oracle horizon (its own error stays at 1e-16 on the stable orbit).
T_REF = 2.0e4
# The on-run's scaled errors after the switch may exceed the off-run's by at most the
# switch's share SWITCH_SAFETY (S5) and the re-run's own windows (measured: 0.006 to
# 0.02 of the scale in all).
from driven_run import LD, TWO_PI_LD, needs_oracle  # noqa: E402  tests/data
from driven_run import model as _model  # noqa: E402
from driven_run import run as _run  # noqa: E402
from driven_run import assert_switch_within_tolerance  # noqa: E402


@pytest.fixture(scope="module")
def step_reference():
    t = np.unique(np.concatenate([np.linspace(0.0, 1000.0, 4001), np.linspace(1000.0, T_REF, 2001)]))
    ref = oracle_heyoka.reference(*STEP[:3], Y0, t, drive=STEP[3:])
    return t, ref


# ---------------------------------------------------------------------------
# The switch against the oracle, both sides of it
# ---------------------------------------------------------------------------


@needs_oracle
@pytest.mark.parametrize("tol", TOLS)
def test_step_switches_and_agrees_with_heyoka(step_reference, tol):
    t, ref = step_reference
    on, r_on = _run(STEP, Y0, T_REF, t, tol)
    off, r_off = _run(STEP, Y0, T_REF, t, tol, regimes_on=0)
    assert r_on["regime"] == regimes.REGIME_PHASE_LOCKED and r_on["str_p"] == 1.0
    assert r_off["regime"] == regimes.REGIME_NONE and math.isnan(r_off["t_regime"])
    ts = r_on["t_regime"]
    assert 100.0 < ts < 1000.0
    # Bit for bit before the switch; tolerance proportionality on both sides; after it
    # within the unswitched run's error plus the switch's share.
    assert_switch_within_tolerance(on, off, ref, t, ts, tol, STEP[2])


@needs_oracle
@pytest.mark.parametrize("tol", TOLS)
def test_every_later_sample_within_the_bound(tol):
    # (S5): at the stroboscopic samples after the switch the extension differs from the
    # continued ordinary run by at most B ≤ the switch scale (plus the two runs' own
    # noise per period: 1e-3 of the tolerance, measured on the ordinary run).
    n = np.arange(0, 3001)
    t = (n.astype(LD) * TWO_PI_LD).astype(float)
    on, r = _run(STEP, Y0, t[-1], t, tol)
    off, _ = _run(STEP, Y0, t[-1], t, tol, regimes_on=0)
    later = t > r["t_regime"]
    assert later.sum() > 2900
    omega = STEP[2]
    d_theta = ((on[2] - off[2]) * 2 * np.pi + (on[0] - off[0]))[later]
    d_v = (on[1] - off[1])[later]
    dist = np.sqrt((omega * d_theta) ** 2 + d_v**2)
    # The switch's scale at the anchor (S5: atol + rtol·|θ'| and ω(atol + rtol·|θ|)).
    scale = regimes.SWITCH_SAFETY * min(tol + tol * abs(r["str_v"]),
                                        omega * (tol + tol * abs(2 * np.pi * r["str_k"] + r["str_phi"])))
    assert np.max(dist) <= scale + 1e-3 * tol, (np.max(dist), scale)


# ---------------------------------------------------------------------------
# The bound (S3) on exact linear sequences, and the runs that must wait
# ---------------------------------------------------------------------------


def _linear_deviations(mu1, mu2, skew, n, complex_pair=False):
    # Δ_k = M^k Δ_0 for M with multipliers μ₁, μ₂ (complex: μ₁ ± iμ₂ as re, im) in a
    # skewed basis (condition number ~ skew).
    v = np.array([[1.0, 1.0], [0.0, 1.0 / skew]])
    if complex_pair:
        core = np.array([[mu1, -mu2], [mu2, mu1]])
    else:
        core = np.array([[mu1, 1.0 if mu1 == mu2 else 0.0], [0.0, mu2]])  # equal: a Jordan block
    m = v @ core @ np.linalg.inv(v)
    x = np.empty((n, 2))
    x[0] = (0.3, -0.7)
    for k in range(1, n):
        x[k] = m @ x[k - 1]
    return x, float(np.linalg.det(m))


def _first_switch(x, det, scale):
    tau1 = tau2 = rho_clean = math.nan
    for n in range(3, len(x)):
        devs = tuple((float(x[i, 0]), float(x[i, 1])) for i in range(n - 3, n + 1))
        ok, tau, rho_clean, rho, bound = regimes.strobe_switch(devs, det, 1.0, scale, (tau1, tau2, rho_clean))
        tau2, tau1 = tau1, tau
        if ok:
            return n, rho, bound
    return None, None, None


@pytest.mark.parametrize("mu1,mu2,skew,cplx", [
    (0.4, 0.35, 30.0, True),  # complex pair, |μ| = 0.53, a skewed basis
    (-0.5, 0.1, 10.0, True),
    (0.7, 0.2, 5.0, False),  # real pair
    (-0.75, -0.3, 50.0, False),  # det > 0 (Liouville): real multipliers share a sign
    (0.55, 0.55, 20.0, False),  # equal: defective (a Jordan block)
])
def test_bound_holds_on_linear_sequences(mu1, mu2, skew, cplx):
    x, det = _linear_deviations(mu1, mu2, skew, 400, cplx)
    norms = np.hypot(x[:, 0], x[:, 1])
    scale = 1e-9 * norms[0]
    n, rho, bound = _first_switch(x, det, scale)
    assert n is not None
    # Every later deviation summed (the deviation still to come) is within B ≤ scale.
    assert np.sum(norms[n + 1:]) <= bound <= scale
    assert rho >= max(abs(complex(mu1, mu2)) if cplx else max(abs(mu1), abs(mu2)), math.sqrt(det)) - 1e-12
    if cplx:
        # Why no single ratio bounds the tail: successive ratios oscillate, some above √D.
        ratios = norms[1:60] / norms[:59]
        assert ratios.max() > 1.05 * math.sqrt(det)


@pytest.mark.parametrize("mu1,mu2", [(0.85, 0.3), (0.95, 0.3), (0.999, 0.285), (-0.97, 0.2)])
def test_bound_waits_when_a_multiplier_is_near_one(mu1, mu2):
    x, det = _linear_deviations(mu1, mu2, 5.0, 3000, False)
    assert _first_switch(x, det, 1e-9 * np.hypot(*x[0]))[0] is None


def test_bound_sees_a_saddle_from_its_stable_mode():
    # (S4): deviations shrinking like μ₂ⁿ near a saddle orbit (μ₁ = 1.3 > 1), the
    # unstable part 1e-14 of the stable one: D is exact, so τ = μ₂ + D/μ₂ shows μ₁.
    mu1, mu2 = 1.3, 0.4
    m = np.diag([mu1, mu2])
    x = np.empty((60, 2))
    x[0] = (1e-14, 1.0)
    for k in range(1, 60):
        x[k] = m @ x[k - 1]
    assert _first_switch(x, mu1 * mu2, 1e-3)[0] is None


@pytest.mark.parametrize("params", EDGE_SLOW)
def test_runs_near_the_step_edge_wait(params):
    t = np.array([0.0, T_REF])
    for tol in (1e-6,) + TOLS:
        _, r = _run(params, Y0, T_REF, t, tol)
        assert r["regime"] == regimes.REGIME_NONE, tol


@pytest.mark.parametrize("params", NOT_PERIOD_ONE)
def test_motion_not_locked_with_period_one_never_switches_to_period_one(params):
    # (S5): no switch to one drive period; a subharmonic orbit is S7's (q > 1).
    t = np.array([0.0, T_REF])
    for tol in (1e-6, 1e-10):
        _, r = _run(params, Y0, T_REF, t, tol)
        assert r["regime"] == regimes.REGIME_NONE or r["str_q"] > 1, tol


# ---------------------------------------------------------------------------
# Long horizons
# ---------------------------------------------------------------------------


def test_long_horizon_costs_the_transient_only():
    m = _model(STEP)
    counts, plain = {}, {}
    for T in (1e3, 1e4, 1e6):
        r = mbm.solve(m, (0.0, T), Y0, rtol=1e-10, atol=1e-10, t_eval=np.linspace(0.0, T, 11))
        assert r.success and r.regime == "phase-locked"
        counts[T] = r.n_windows
    for T in (1e3, 1e4):
        _, rec = _run(STEP, Y0, T, np.array([T]), 1e-10, regimes_on=0)
        plain[T] = rec["n_windows"]
    # The same windows up to the switch, then one: T = 1e6 costs what T = 1e3 does.
    assert counts[1e6] == counts[1e4] == counts[1e3] < plain[1e3]
    assert plain[1e4] > 8 * plain[1e3]


@needs_oracle
def test_value_at_a_late_time_is_one_period_of_windows(step_reference):
    # (S6): the period is exact (s from t − t_a in double-double), so the extension at
    # t ~ 1e6 is the stored period's value at s = (t − t_a) mod T_d plus p turns per
    # period.  The exact orbit has period T_d = 2π, so its state at t is its state at
    # t − nT_d (converged long before): the reference is heyoka's there, n turns added.
    t, ref = step_reference
    t_late = np.array([1.0e6 - 1.0, 1.0e6, 1.0e6 + 0.1])
    n = np.floor((t_late.astype(LD) - LD(T_REF)) / TWO_PI_LD)
    back = t_late.astype(LD) - n * TWO_PI_LD
    grid = np.concatenate(([LD(T_REF)], back))
    ref_back = oracle_heyoka.reference(*STEP[:3], [ref[0, -1], ref[1, -1]], grid, drive=STEP[3:])[:, 1:]
    r = mbm.solve(_model(STEP), (0.0, 1.1e6), Y0, rtol=1e-10, atol=1e-10, t_eval=t_late, wrap=True)
    assert r.regime == "phase-locked"
    theta = r.winding.astype(LD) * TWO_PI_LD + r.y[0].astype(LD)
    e_theta = np.abs((theta - (ref_back[0] + n * TWO_PI_LD)).astype(float))
    e_v = np.abs((r.y[1] - ref_back[1]).astype(float))
    assert np.all(e_theta <= 1e-10) and np.all(e_v <= 1e-10 * (1 + np.abs(r.y[1]))), (e_theta, e_v)


# ---------------------------------------------------------------------------
# Every path, the same bits; the opt-out; resumed runs
# ---------------------------------------------------------------------------


def test_every_path_gives_the_same_bits():
    m = _model(STEP)
    T, tol = 3000.0, 1e-10
    t = np.linspace(0.0, T, 301)
    kw = dict(rtol=tol, atol=tol)
    fast = mbm.solve(m, (0.0, T), Y0, t_eval=t, **kw)
    assert fast.success and fast.regime == "phase-locked" and 0.0 < fast.t_regime < 1000.0
    assert fast.mean_velocity == 1.0 * STEP[4] and fast.period == 2.0 * np.pi / STEP[4]
    ivp = solve_ivp(m, (0.0, T), Y0, method=mbm.MBM, t_eval=t, windows_per_step=None, dense_output=True, **kw)
    assert ivp.success
    np.testing.assert_array_equal(ivp.y, fast.y)
    np.testing.assert_array_equal(ivp.sol(t), fast.y)
    one = solve_ivp(m, (0.0, T), Y0, method=mbm.MBM, dense_output=True, **kw)
    ends = mbm.solve(m, (0.0, T), Y0, **kw)
    np.testing.assert_array_equal(one.t, ends.t)
    np.testing.assert_array_equal(one.y, ends.y)
    np.testing.assert_array_equal(one.sol(t), fast.y)
    assert ends.regime == fast.regime and ends.t_regime == fast.t_regime
    ig = mbm.Integrator(m, **kw)
    res = ig.solve((0.0, T), Y0, t_eval=t)
    np.testing.assert_array_equal(res.y, fast.y)
    assert (res.regime, res.t_regime, res.period, res.mean_velocity) == (
        fast.regime, fast.t_regime, fast.period, fast.mean_velocity)
    out = np.empty((2, t.size))
    status, nw = mbm.solve_njit(*m.params, 0.0, Y0[0], Y0[1], T, t, out, tol, tol, 10**7, *m.drive)
    assert status == 0 and nw == fast.n_windows
    np.testing.assert_array_equal(out, fast.y)
    # A batch: this scene, a chaotic one and the undriven twin (which locks).
    batch = mbm.solve_batch(STEP[0], [STEP[1], STEP[1], STEP[1]], 1.0, Y0, (0.0, T), t,
                            drive_amplitude=[STEP[3], 1.0, 0.0], drive_frequency=STEP[4], **kw)
    assert batch.success.all()
    np.testing.assert_array_equal(batch.y[0], fast.y)
    assert list(batch.regime) == ["phase-locked", None, "locked"]
    assert batch.t_regime[0] == fast.t_regime and batch.n_windows[0] == fast.n_windows
    assert batch.mean_velocity[0] == fast.mean_velocity and batch.period[0] == fast.period
    assert math.isnan(batch.mean_velocity[1]) and math.isnan(batch.period[1])
    assert batch.mean_velocity[2] == 0.0 and math.isnan(batch.period[2])
    # wrapped: θ = 2π·winding + φ
    wr = mbm.solve(m, (0.0, T), Y0, t_eval=t, wrap=True, **kw)
    np.testing.assert_allclose(2 * np.pi * wr.winding + wr.y[0], fast.y[0], rtol=0, atol=1e-11)
    np.testing.assert_array_equal(wr.y[1], fast.y[1])


def test_solver_reports_the_regime():
    m = _model(STEP)
    solver = mbm.MBM(m, 0.0, np.array(Y0), 2000.0, rtol=1e-10, atol=1e-10, windows_per_step=None)
    while solver.status == "running":
        solver.step()
    assert solver.regime == "phase-locked" and solver.mean_velocity == 1.0
    assert solver.period == 2 * np.pi and 0.0 < solver.t_regime < 2000.0


def test_resumed_run_gives_the_same_bits():
    # The samples, deviations and fits live in the run record: a run paused every 7
    # windows and resumed takes the same windows and switches at the same sample.
    t = np.linspace(0.0, 2000.0, 401)
    whole, r1 = _run(STEP, Y0, 2000.0, t, 1e-10)
    chunked, r2 = _run(STEP, Y0, 2000.0, t, 1e-10, call_windows=7)
    np.testing.assert_array_equal(whole, chunked)
    assert r1["t_regime"] == r2["t_regime"] and r1["n_windows"] == r2["n_windows"]


def test_regimes_off_is_the_ordinary_run():
    t = np.linspace(0.0, 2000.0, 401)
    on, r_on = _run(STEP, Y0, 2000.0, t, 1e-10)
    off, r_off = _run(STEP, Y0, 2000.0, t, 1e-10, regimes_on=0)
    assert r_off["regime"] == regimes.REGIME_NONE and r_off["n_windows"] > 5 * r_on["n_windows"]
    pre = t <= r_on["t_regime"]
    np.testing.assert_array_equal(on[:, pre], off[:, pre])
    # After the switch: the same motion to far below the tolerance.
    assert np.max(np.abs(on[1] - off[1])) < 1e-11


def test_other_steps_and_the_mirror():
    # p = 2 (β = 0.2, A = 1, Ω = 1, γ = 0.5), p = 0 (a weak drive on a locked state) and
    # the mirror image of STEP (γ, A → −γ, −A: θ → −θ exactly), p = −1.
    for params, p in (((0.2, 0.5, 1.0, 1.0, 1.0, 0.0), 2.0), ((1.0, 0.3, 1.0, 1e-3, 0.9, 0.0), 0.0)):
        r = mbm.solve(_model(params), (0.0, 1e4), Y0, rtol=1e-10, atol=1e-10, t_eval=[1e4])
        assert r.regime == "phase-locked" and r.mean_velocity == p * params[4]
    t = np.linspace(0.0, 2000.0, 201)
    a = mbm.solve(_model(STEP), (0.0, 2000.0), Y0, rtol=1e-10, atol=1e-10, t_eval=t)
    mirror = (STEP[0], -STEP[1], STEP[2], -STEP[3], STEP[4], STEP[5])
    b = mbm.solve(_model(mirror), (0.0, 2000.0), Y0, rtol=1e-10, atol=1e-10, t_eval=t)
    assert b.regime == "phase-locked" and b.mean_velocity == -1.0 and b.t_regime == a.t_regime
    np.testing.assert_array_equal(b.y, -a.y)


# ---------------------------------------------------------------------------
# The kernels: stroboscopic times, the drive's phase, the split (S1, S6)
# ---------------------------------------------------------------------------


def _exact_pi():
    import mpmath

    mpmath.mp.prec = 200
    return Fraction(str(mpmath.pi)[:60])  # ~1e-58


def test_strobe_time_phase_and_split_have_no_drift():
    pi = _exact_pi()
    for freq in (1.0, 0.7, 3.0):
        p_hi, p_lo = regimes.strobe_period(freq, 1.0)
        period = 2 * pi / Fraction(freq)
        assert abs(Fraction(p_hi) + Fraction(p_lo) - period) < Fraction(1, 10**30)
        for t_s, n in ((0.0, 10**6), (12.5, 3 * 10**5), (0.0, 10**7)):
            tn, rn = regimes.strobe_time(t_s, float(n), p_hi, p_lo)
            exact = Fraction(t_s) + n * period
            assert abs(Fraction(tn) + Fraction(rn) - exact) < Fraction(1, 10**20)
            assert abs(Fraction(tn) - exact) <= Fraction(math.ulp(tn)) / 2
            # The drive's phase at the rounded time, reduced, to a few ulps of π.
            psi = regimes.strobe_phase(freq, 0.3, tn)
            want = Fraction(freq) * Fraction(tn) + Fraction(0.3)
            want -= round(want / (2 * pi)) * 2 * pi
            assert abs(Fraction(psi) - want) < Fraction(4e-16)
            # t − t_a = nP + s: s with no n·eps·P drift.
            s0 = 1.25
            t = float(Fraction(t_s) + n * period + Fraction(s0))
            k, s = regimes.strobe_split(t, t_s, p_hi, p_lo)
            assert k == n
            assert abs(Fraction(s) - (Fraction(t) - Fraction(t_s) - n * period)) < Fraction(1e-15)


def test_strobe_split_at_period_boundaries():
    p_hi, p_lo = regimes.strobe_period(1.0, 1.0)
    for n in (0, 1, 7, 10**6):
        t = float(n * (Fraction(p_hi) + Fraction(p_lo)))
        k, s = regimes.strobe_split(t, 0.0, p_hi, p_lo)
        assert 0.0 <= s <= p_hi and (k == n or (k == n - 1 and s > p_hi * (1 - 1e-9)) or s < 1e-9)
        assert k * p_hi + s == pytest.approx(t, rel=1e-15, abs=1e-15)


# ---------------------------------------------------------------------------
# iv_curve: exact pΩ on a step
# ---------------------------------------------------------------------------


def test_iv_curve_is_exact_on_the_step():
    beta, _, omega, amp, freq, _ = STEP
    c = mbm.iv_curve(beta, [0.2, 0.3, 0.1], omega=omega, drive_amplitude=amp, drive_frequency=freq)
    # on the step: labelled as mbm.solve labels it, with the locked orbit's period 2π/Ω
    assert list(c.mean_velocity) == [freq, freq, freq] and list(c.regime) == ["phase-locked"] * 3
    np.testing.assert_array_equal(c.period, np.full(3, 2 * np.pi / freq))
    # Off the steps (chaotic), the Birkhoff average: not a multiple of Ω.
    # Its blocks never agree: the point is flagged as not settled, with a warning.
    with pytest.warns(RuntimeWarning, match=r"1 of 1 driven points did not settle.*gamma = \[0\.2\]"):
        off = mbm.iv_curve(beta, [0.2], omega=omega, drive_amplitude=1.0, drive_frequency=freq)
    assert 0.1 < off.mean_velocity[0] < 0.9 and off.regime[0] == "running" and not off.converged[0]
    assert c.converged.all()
    # The zero step p = 0: phase-locked as mbm.solve labels it, ⟨θ'⟩ = 0 exactly, the
    # orbit's period 2π/Ω; on the locked side of the switching current.
    model = mbm.Pendulum(1.0, 0.3, 1.0, 1e-3, 0.9)
    z = mbm.iv_curve(1.0, [0.3], drive_amplitude=1e-3, drive_frequency=0.9)
    r = mbm.solve(model, (0.0, 3000.0), [0.0, 0.0], t_eval=[3000.0])
    assert z.mean_velocity[0] == 0.0 and z.regime[0] == r.regime == "phase-locked"
    assert z.period[0] == pytest.approx(2 * np.pi / 0.9, rel=1e-12) and r.period == pytest.approx(z.period[0])


def test_a_later_start_time_sets_the_samples():
    # (S1): the samples are at t_s + nT_d with t_s the run's start, whatever t_s (the
    # drive's phase there is the run's own): from t0 = 1e5 + 0.3 the run switches and
    # agrees with the ordinary run from the same start.
    t0 = 1.0e5 + 0.3
    t = t0 + np.linspace(0.0, 3000.0, 301)
    m = _model(STEP)
    r = mbm.solve(m, (t0, t[-1]), Y0, rtol=1e-10, atol=1e-10, t_eval=t)
    assert r.regime == "phase-locked" and t0 < r.t_regime < t0 + 1000.0 and r.mean_velocity == 1.0
    b, g, w, amp, freq, phase = STEP
    ap, kind, karg = mbm.frontends.solve.compiled(mbm.get_approximant("taylor"))
    p = record.new_run(record.RunModel(b, g, w, amp, freq, phase), record.RunState(t0, Y0[0], Y0[1], t[-1]),
                       record.RunControl(kind, karg, controller.CONTROLLER_ADAPTIVE, -1.0, np.inf, np.inf, 1e-10,
                                         1e-10, int(ap.error_order)), 10**8, regimes=0)
    out = np.full((2, t.size), np.nan)
    loop.run(p, t, out, np.empty(0), np.empty((0, 2)), np.empty((0, 0)), np.zeros(1, np.int64))
    assert record.flat(p)[0]["regime"] == regimes.REGIME_NONE
    np.testing.assert_allclose(r.y[1], out[1], rtol=0, atol=2e-11)
    assert np.all(np.abs(r.y[0] - out[0]) <= 2e-11 * (1 + np.abs(out[0])))
