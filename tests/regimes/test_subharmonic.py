"""Subharmonic orbits of driven runs (mbm.regimes S7): fractional and period-q Shapiro steps.

A driven damped run on a fractional step converges to an orbit θ(t + qT_d) = θ(t) + 2πp,
q > 1, a fixed point of the q-th power of the stroboscopic map; once the samples of
every class n mod q have converged for the rest of the horizon (S3–S5 on P^q) and the
orbit's period is no divisor of q, the run is one stored period of q drive periods
re-taken from its anchor: ``period`` q·2π/Ω, ``mean_velocity`` (p/q)Ω.  The independent
reference is heyoka in long double (tests/data/oracle_heyoka.py).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm.core import window
from mbm import regimes
from mbm.approximants.taylor import drive_phase_sincos

import oracle_heyoka  # noqa: E402  tests/data, on pytest's pythonpath

# (β, γ, ω, A, Ω, φ), q, p.  The half step of β = 0.2, A = 1, Ω = 1 (⟨θ'⟩ = Ω/2; the
# multipliers of P² a complex pair, |μ| = e^{−2πβ} = 0.28), the half step of an
# overdamped junction (β = 2: P² has μ = 0.51 and 4e-7), a 16/3 step (β = 0.2, A = 1.5,
# Ω = 0.7), a period-4 orbit at ⟨θ'⟩ = Ω/2 (β = 0.5, A = 1.5, Ω = 1: p = 2, q = 4) and
# the 2/3 step of β = 0.3, A = 1, Ω = 1 (its transient's error is 8 tolerances, the
# ordinary run's: not a scene for the oracle).  Found by a scan of γ with heyoka
# (stroboscopic samples after 400 drive periods, period q ≤ 6 to 1e-6).
HALF = ((0.2, 0.3, 1.0, 1.0, 1.0, 0.0), 2, 1)
HALF_OVERDAMPED = ((2.0, 1.35, 1.0, 1.0, 1.0, 0.0), 2, 1)
SIXTEEN_THIRDS = ((0.2, 0.76, 1.0, 1.5, 0.7, 0.0), 3, 16)
PERIOD_FOUR = ((0.5, 0.28, 1.0, 1.5, 1.0, 0.0), 4, 2)
TWO_THIRDS = ((0.3, 0.2, 1.0, 1.0, 1.0, 0.0), 3, 2)
Y0 = (0.0, 0.0)
TOLS = (1e-8, 1e-10, 1e-12)
# (scene, tolerance) against the oracle.  The overdamped half step does not switch at
# 1e-12: its deviations reach round-off (1e-15) before B passes in both classes (S7).
ORACLE_CASES = ([(HALF, tol) for tol in TOLS] + [(HALF_OVERDAMPED, tol) for tol in (1e-8, 1e-10)]
                + [(SIXTEEN_THIRDS, tol) for tol in TOLS] + [(PERIOD_FOUR, tol) for tol in TOLS])
T_REF = 2.0e4
from driven_run import LD, TWO_PI_LD, needs_oracle  # noqa: E402  tests/data
from driven_run import model as _model  # noqa: E402
from driven_run import run as _run  # noqa: E402
from driven_run import assert_switch_within_tolerance  # noqa: E402


_REFS = {}


def _reference(params):
    t = np.unique(np.concatenate([np.linspace(0.0, 3000.0, 6001), np.linspace(3000.0, T_REF, 2001)]))
    if params not in _REFS:
        _REFS[params] = oracle_heyoka.reference(*params[:3], Y0, t, drive=params[3:])
    return t, _REFS[params]


# ---------------------------------------------------------------------------
# The switch against the oracle, both sides of it
# ---------------------------------------------------------------------------


@needs_oracle
@pytest.mark.parametrize("step,tol", ORACLE_CASES, ids=[f"{s[2]}/{s[1]}-b{s[0][0]}-{tol}" for s, tol in ORACLE_CASES])
def test_fractional_step_switches_and_agrees_with_heyoka(step, tol):
    params, q, p = step
    t, ref = _reference(params)
    on, r_on = _run(params, Y0, T_REF, t, tol)
    off, r_off = _run(params, Y0, T_REF, t, tol, regimes_on=0)
    assert r_on["regime"] == regimes.REGIME_PHASE_LOCKED and (r_on["str_q"], r_on["str_p"]) == (q, p)
    assert r_off["regime"] == regimes.REGIME_NONE
    ts = r_on["t_regime"]
    assert 100.0 < ts < 3000.0
    # Bit for bit before the switch; tolerance proportionality on both sides; after it
    # within the unswitched run's error plus the switch's share.
    assert_switch_within_tolerance(on, off, ref, t, ts, tol, params[2])


@pytest.mark.parametrize("step", (HALF, PERIOD_FOUR), ids=("1/2", "2/4"))
@pytest.mark.parametrize("tol", (1e-8, 1e-11))
def test_every_later_sample_within_the_bound(step, tol):
    # (S7): at every stroboscopic sample after the switch, of every class n mod q, the
    # extension differs from the continued ordinary run by at most the switch scale
    # (B_c ≤ scale for every class) plus the two runs' own noise per q periods
    # (measured: up to 1e-2 of the tolerance on the ordinary run at q = 4).
    params, q, _ = step
    freq = params[4]
    n = np.arange(0, 2001)
    t = (n.astype(LD) * TWO_PI_LD / LD(freq)).astype(float)
    on, r = _run(params, Y0, t[-1], t, tol)
    off, _ = _run(params, Y0, t[-1], t, tol, regimes_on=0)
    assert r["str_q"] == q
    later = t > r["t_regime"]
    assert later.sum() > 1500
    omega = params[2]
    d_theta = ((on[2] - off[2]) * 2 * np.pi + (on[0] - off[0]))[later]
    d_v = (on[1] - off[1])[later]
    dist = np.sqrt((omega * d_theta) ** 2 + d_v**2)
    scale = regimes.SWITCH_SAFETY * min(tol + tol * abs(r["str_v"]),
                                        omega * (tol + tol * abs(2 * np.pi * r["str_k"] + r["str_phi"])))
    assert np.max(dist) <= scale + 1e-2 * tol, (np.max(dist), scale)


# ---------------------------------------------------------------------------
# Long horizons
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("step", (HALF, SIXTEEN_THIRDS), ids=("1/2", "16/3"))
def test_long_horizon_costs_the_transient_only(step):
    params, q, p = step
    m = _model(params)
    counts = {}
    for T in (1e3, 1e4, 1e6):
        r = mbm.solve(m, (0.0, T), Y0, rtol=1e-10, atol=1e-10, t_eval=np.linspace(0.0, T, 11))
        assert r.success and r.regime == "phase-locked" and r.mean_velocity == p * params[4] / q
        counts[T] = r.n_windows
    plain = {T: _run(params, Y0, T, np.array([T]), 1e-10, regimes_on=0)[1]["n_windows"] for T in (1e3, 1e4)}
    # The same windows up to the switch, then one: T = 1e6 costs what T = 1e3 does.
    assert counts[1e6] == counts[1e4] == counts[1e3] < plain[1e3]
    assert plain[1e4] > 8 * plain[1e3]


@needs_oracle
def test_value_at_a_late_time_is_q_periods_of_windows():
    # (S6, S7): the exact orbit has period qT_d, so its state at t ~ 1e6 is its state at
    # t − n·qT_d (converged long before): heyoka's there, np turns added.
    params, q, p = HALF
    t, ref = _reference(params)
    period = q * TWO_PI_LD / LD(params[4])
    t_late = np.array([1.0e6 - 1.0, 1.0e6, 1.0e6 + 0.1, 1.0e6 + 7.0])
    n = np.floor((t_late.astype(LD) - LD(T_REF)) / period)
    back = t_late.astype(LD) - n * period
    order = np.argsort(back)
    grid = np.concatenate(([LD(T_REF)], back[order]))
    ref_back = np.empty((2, t_late.size), dtype=LD)
    ref_back[:, order] = oracle_heyoka.reference(*params[:3], [ref[0, -1], ref[1, -1]], grid,
                                                 drive=params[3:])[:, 1:]
    r = mbm.solve(_model(params), (0.0, 1.1e6), Y0, rtol=1e-10, atol=1e-10, t_eval=t_late, wrap=True)
    assert r.regime == "phase-locked" and r.period == q * 2 * np.pi / params[4]
    theta = r.winding.astype(LD) * TWO_PI_LD + r.y[0].astype(LD)
    e_theta = np.abs((theta - (ref_back[0] + n * p * TWO_PI_LD)).astype(float))
    e_v = np.abs((r.y[1] - ref_back[1]).astype(float))
    assert np.all(e_theta <= 1e-10) and np.all(e_v <= 1e-10 * (1 + np.abs(r.y[1]))), (e_theta, e_v)


# ---------------------------------------------------------------------------
# Every path, the same bits and the same summary
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("step", (HALF, SIXTEEN_THIRDS), ids=("1/2", "16/3"))
def test_every_path_gives_the_same_bits(step):
    params, q, p = step
    m = _model(params)
    T, tol = 3000.0, 1e-10
    t = np.linspace(0.0, T, 301)
    kw = dict(rtol=tol, atol=tol)
    fast = mbm.solve(m, (0.0, T), Y0, t_eval=t, **kw)
    assert fast.success and fast.regime == "phase-locked" and 0.0 < fast.t_regime < 1500.0
    assert fast.mean_velocity == p * params[4] / q and fast.period == q * 2.0 * np.pi / params[4]
    ivp = solve_ivp(m, (0.0, T), Y0, method=mbm.MBM, t_eval=t, windows_per_step=None, dense_output=True, **kw)
    assert ivp.success
    np.testing.assert_array_equal(ivp.y, fast.y)
    np.testing.assert_array_equal(ivp.sol(t), fast.y)
    one = solve_ivp(m, (0.0, T), Y0, method=mbm.MBM, dense_output=True, **kw)
    ends = mbm.solve(m, (0.0, T), Y0, **kw)
    np.testing.assert_array_equal(one.t, ends.t)
    np.testing.assert_array_equal(one.y, ends.y)
    np.testing.assert_array_equal(one.sol(t), fast.y)
    assert (ends.regime, ends.t_regime, ends.period, ends.mean_velocity) == (
        fast.regime, fast.t_regime, fast.period, fast.mean_velocity)
    ig = mbm.Integrator(m, **kw)
    res = ig.solve((0.0, T), Y0, t_eval=t)
    np.testing.assert_array_equal(res.y, fast.y)
    assert (res.regime, res.t_regime, res.period, res.mean_velocity) == (
        fast.regime, fast.t_regime, fast.period, fast.mean_velocity)
    out = np.empty((2, t.size))
    status, nw = mbm.solve_njit(*m.params, 0.0, Y0[0], Y0[1], T, t, out, tol, tol, 10**7, *m.drive)
    assert status == 0 and nw == fast.n_windows
    np.testing.assert_array_equal(out, fast.y)
    # A batch: this scene, the n = 1 step (q = 1) and a chaotic one.
    beta, gamma, omega, amp, freq, _ = params
    batch = mbm.solve_batch(beta, [gamma, 0.2, 0.2], omega, Y0, (0.0, T), t,
                            drive_amplitude=[amp, 2.0, 1.0], drive_frequency=[freq, 1.0, 1.0], **kw)
    assert batch.success.all()
    np.testing.assert_array_equal(batch.y[0], fast.y)
    assert list(batch.regime[:2]) == ["phase-locked", "phase-locked"]
    assert batch.t_regime[0] == fast.t_regime and batch.n_windows[0] == fast.n_windows
    assert batch.mean_velocity[0] == fast.mean_velocity and batch.period[0] == fast.period
    if beta == 0.2:
        assert batch.mean_velocity[1] == 1.0 and batch.period[1] == 2.0 * np.pi
        assert batch.regime[2] is None and math.isnan(batch.mean_velocity[2])
    # wrapped: θ = 2π·winding + φ
    wr = mbm.solve(m, (0.0, T), Y0, t_eval=t, wrap=True, **kw)
    np.testing.assert_allclose(2 * np.pi * wr.winding + wr.y[0], fast.y[0], rtol=0, atol=1e-11)
    np.testing.assert_array_equal(wr.y[1], fast.y[1])


def test_solver_reports_the_regime():
    params, q, p = HALF
    solver = mbm.MBM(_model(params), 0.0, np.array(Y0), 2000.0, rtol=1e-10, atol=1e-10, windows_per_step=None)
    while solver.status == "running":
        solver.step()
    assert solver.regime == "phase-locked" and solver.mean_velocity == 0.5
    assert solver.period == 4 * np.pi and 0.0 < solver.t_regime < 2000.0


def test_resumed_run_gives_the_same_bits():
    # The sample ring, the fits and the class bounds live in the run record: a run
    # paused every 7 windows and resumed takes the same windows and switches alike.
    params = PERIOD_FOUR[0]
    t = np.linspace(0.0, 2000.0, 401)
    whole, r1 = _run(params, Y0, 2000.0, t, 1e-10)
    chunked, r2 = _run(params, Y0, 2000.0, t, 1e-10, call_windows=7)
    assert r1["str_q"] == 4
    np.testing.assert_array_equal(whole, chunked)
    assert r1["t_regime"] == r2["t_regime"] and r1["n_windows"] == r2["n_windows"]


def test_the_mirror_is_a_mirror():
    # γ, A → −γ, −A maps θ → −θ exactly: the same switch, p → −p.
    params, q, p = HALF
    t = np.linspace(0.0, 2000.0, 201)
    a = mbm.solve(_model(params), (0.0, 2000.0), Y0, rtol=1e-10, atol=1e-10, t_eval=t)
    mirror = (params[0], -params[1], params[2], -params[3], params[4], params[5])
    b = mbm.solve(_model(mirror), (0.0, 2000.0), Y0, rtol=1e-10, atol=1e-10, t_eval=t)
    assert b.regime == a.regime == "phase-locked" and b.t_regime == a.t_regime
    assert b.mean_velocity == -a.mean_velocity == -0.5 and b.period == a.period
    np.testing.assert_array_equal(b.y, -a.y)


def test_iv_curve_is_exact_on_fractional_steps():
    # ⟨θ'⟩ = (p/q)Ω exactly where a run reaches the regime (mbm.junction.iv).  (Not on every
    # step: a block run that starts on the orbit, its settling run having ended just
    # before its switch, sees no clean fit (S4) and reports the Birkhoff average, as at
    # q = 1.)
    for (params, q, p) in (HALF_OVERDAMPED, PERIOD_FOUR, TWO_THIRDS, ((0.5, 0.16, 1.0, 1.0, 0.7, 0.0), 2, 1)):
        beta, gamma, omega, amp, freq, _ = params
        c = mbm.iv_curve(beta, [gamma], omega=omega, drive_amplitude=amp, drive_frequency=freq)
        # labelled as mbm.solve labels it, with the locked orbit's period q·2π/Ω
        assert c.mean_velocity[0] == p * freq / q and c.regime[0] == "phase-locked"
        assert c.period[0] == q * 2 * np.pi / freq


# ---------------------------------------------------------------------------
# The smallest q; q = 1 and the unlocked scenes unchanged
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("params,q", [
    # q = 1 orbits of the n = 1 step whose multiplier μ₁ = −0.83, −0.86 is above
    # STROBE_MAX_MULTIPLIER, while P² has μ₁² = 0.70, 0.74 below it: P²'s fit passes,
    # the classes' limits coincide, and S7 must not call the orbit q = 2.
    ((0.2, 0.45, 1.0, 2.0, 1.0, 0.0), 1),
    ((0.2, 0.455, 1.0, 2.0, 1.0, 0.0), 1),
    # A q = 2 orbit (the half step of β = 0.2, A = 1, Ω = 0.7 ... p = 9) with ρ(P²) = 0.82,
    # above the limit, and ρ(P⁴) = 0.67 below it: never q = 4.
    ((0.2, 0.64, 1.0, 1.0, 0.7, 0.0), 2),
])
def test_an_orbit_is_never_reported_with_a_multiple_of_its_period(params, q):
    t = np.array([0.0, T_REF])
    for tol in (1e-6, 1e-8, 1e-10, 1e-12):
        _, r = _run(params, Y0, T_REF, t, tol)
        assert r["regime"] == regimes.REGIME_NONE or r["str_q"] == q, (tol, r["str_q"])


def _first_s5_switch(params, tol, n_samples):
    """The first sample at which S5 (q = 1) passes, by the rule replayed in Python on
    the ordinary run's samples (the same bits: before the switch the two runs agree)."""
    beta, gamma, omega, amp, freq, phase = params
    p_hi, p_lo = regimes.strobe_period(freq, 1.0)
    tn, rn = np.empty(n_samples), np.empty(n_samples)
    for i in range(n_samples):
        tn[i], rn[i] = regimes.strobe_time(0.0, float(i + 1), p_hi, p_lo)
    out, _ = _run(params, Y0, tn[-1], tn, tol, regimes_on=0)
    det = math.exp(-beta * p_hi)
    prev = None
    devs, p_dev, tau1, tau2, rho = [], None, math.nan, math.nan, math.nan
    for i in range(n_samples):
        k, a, b = out[2, i], out[0, i], out[1, i]
        acc = (gamma + amp * drive_phase_sincos(freq, phase, tn[i])[0]) - beta * b - omega * omega * math.sin(a)
        ac, bc = a + b * rn[i], b + acc * rn[i]
        if prev is not None:
            dphi = ac - prev[1]
            m = math.floor(dphi / (2 * math.pi) + 0.5)
            turns = (k - prev[0]) + m
            dth = (dphi - m * window.TWO_PI_A) - m * window.TWO_PI_B
            dv = bc - prev[2]
            tau = math.nan
            if len(devs) >= 3 and turns == p_dev:
                scale = regimes.SWITCH_SAFETY * min(tol + tol * abs(b),
                                                    omega * (tol + tol * abs(2 * math.pi * k + a)))
                ok, tau, rho, _, _ = regimes.strobe_switch(
                    (tuple(devs[-3][0:2]), tuple(devs[-2][0:2]), tuple(devs[-1][0:2]), (dth, dv)), det, omega, scale,
                    (tau1, tau2, rho))
                if ok:
                    return tn[i]
            if devs and turns == p_dev:
                devs.append((dth, dv))
            else:
                p_dev, devs, rho = turns, [(dth, dv)], math.nan
            tau2, tau1 = tau1, tau
        prev = (k, ac, bc)
    return None


@pytest.mark.parametrize("params", [(0.2, 0.2, 1.0, 2.0, 1.0, 0.0), (0.2, 0.5, 1.0, 1.0, 1.0, 0.0),
                                    (1.0, 0.3, 1.0, 1e-3, 0.9, 0.0)])
@pytest.mark.parametrize("tol", (1e-6, 1e-10))
def test_period_one_switch_is_unchanged(params, tol):
    # A q = 1 orbit switches where S5 alone would: its anchor is the first sample at
    # which S5 passes, replayed on the ordinary run's samples, with q = 1.
    t = np.array([3000.0])
    _, r = _run(params, Y0, 3000.0, t, tol)
    assert r["regime"] == regimes.REGIME_PHASE_LOCKED and r["str_q"] == 1.0
    assert r["str_ta"] == _first_s5_switch(params, tol, int(r["str_ta"] / (2 * np.pi / params[4])) + 5)


@pytest.mark.parametrize("params", [
    (0.2, 0.2, 1.0, 1.0, 1.0, 0.0),  # chaotic (a 1e-10 change of θ₀ is O(1) by t = 400)
    (2.0, 1.25, 1.0, 1.0, 1.0, 0.0),  # overdamped, between steps: quasi-periodic, ⟨θ'⟩ = 0.424Ω
    (2.0, 1.5, 1.0, 1.0, 1.0, 0.0),  # overdamped, quasi-periodic, ⟨θ'⟩ = 0.606Ω
])
def test_unlocked_runs_are_the_ordinary_run(params):
    # No switch, and the samples and fits leave the run untouched: bit for bit the
    # run with the regimes off, over the whole span.
    t = np.linspace(0.0, T_REF, 2001)
    for tol in (1e-6, 1e-10):
        on, r_on = _run(params, Y0, T_REF, t, tol)
        off, r_off = _run(params, Y0, T_REF, t, tol, regimes_on=0)
        assert r_on["regime"] == regimes.REGIME_NONE, tol
        np.testing.assert_array_equal(on, off)
        assert r_on["n_windows"] == r_off["n_windows"]


def test_orbits_longer_than_the_limit_are_not_detected():
    # Over STROBE_MAX_PERIODS drive periods (the 6/5 step of β = 1, A = 1, Ω = 1, γ = 1.5):
    # the ordinary run continues.
    assert regimes.STROBE_MAX_PERIODS < 5
    _, r = _run((1.0, 1.5, 1.0, 1.0, 1.0, 0.0), Y0, T_REF, np.array([T_REF]), 1e-10)
    assert r["regime"] == regimes.REGIME_NONE


def test_summary_kernel():
    assert regimes.strobe_summary(1.0, 2.0, 1.0) == (4 * math.pi, 0.5)
    assert regimes.strobe_summary(16.0, 3.0, 0.7) == (3 * 2 * math.pi / 0.7, 16 * 0.7 / 3)
    assert regimes.strobe_summary(1.0, 1.0, 1.0) == (2 * math.pi, 1.0)
