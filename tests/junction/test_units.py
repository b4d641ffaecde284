"""mbm.Junction (SI units ↔ the reduced RCSJ model) and β from the retrapping current.

The units are checked against the dimensional RCSJ equations integrated by scipy (an
independent path: SI time, volts and amperes), the retrapping current against the
bisected transitions of :func:`mbm.iv_curve`.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm

PHI0 = 2.067833848e-15  # Wb, h/2e (CODATA 2018, exact in the SI)


def test_junction_parameters_by_hand():
    j = mbm.Junction(I_c=10e-6, R=10.0, C=1e-12, T=4.2)
    beta_c = 2 * math.pi * 10e-6 * 100.0 * 1e-12 / PHI0
    omega_p = math.sqrt(2 * math.pi * 10e-6 / (PHI0 * 1e-12))
    assert j.beta_c == pytest.approx(beta_c, rel=1e-9)
    assert j.beta == pytest.approx(1 / (omega_p * 10.0 * 1e-12), rel=1e-9)  # β = 1/(ω_p R C)
    assert j.omega_p == pytest.approx(omega_p, rel=1e-9)
    assert j.time_scale == pytest.approx(1 / omega_p, rel=1e-9)
    assert j.voltage_scale == pytest.approx(j.beta * 10e-6 * 10.0, rel=1e-9)  # Φ₀ω_p/2π = β I_c R
    assert j.E_J == pytest.approx(PHI0 * 10e-6 / (2 * math.pi), rel=1e-9)
    assert j.temperature_reduced == pytest.approx(1.380649e-23 * 4.2 / j.E_J, rel=1e-9)
    assert mbm.Junction(1e-6, 1.0, 1e-12).temperature_reduced is None
    # 1 GHz ↔ 2.0678 µV on the first step
    assert j.shapiro_voltage(1, 1e9) == pytest.approx(2.067833848e-6, rel=1e-9)
    assert j.gamma(12e-6) == pytest.approx(1.2) and j.current(1.2) == pytest.approx(12e-6)
    np.testing.assert_allclose(j.theta_dot(j.voltage([0.5, 2.0])), [0.5, 2.0], rtol=1e-15)
    assert j.frequency(j.Omega(20e9)) == pytest.approx(20e9, rel=1e-15)
    # the n-th step ⟨θ'⟩ = nΩ is the voltage n Φ₀ f
    assert j.voltage(3 * j.Omega(20e9)) == pytest.approx(j.shapiro_voltage(3, 20e9), rel=1e-14)
    m = j.model(12e-6, drive_current=3e-6, drive_frequency_hz=20e9, drive_phase=0.25)
    assert (m.beta, m.gamma, m.omega, m.drive_amplitude, m.drive_phase) == (j.beta, pytest.approx(1.2), 1.0,
                                                                            pytest.approx(0.3), 0.25)
    assert m.drive_frequency == j.Omega(20e9)


@pytest.mark.parametrize("kw,match", [
    (dict(I_c=np.float64(-1e-6)), r"I_c must be finite and > 0 \(in A\), got -1e-06$"),
    (dict(R=0.0), r"R must be finite and > 0 \(in ohm\), got 0.0$"),
    (dict(C=np.inf), r"C must be finite and > 0 \(in F\), got inf$"),
    (dict(T=-1.0), r"T must be finite and >= 0 \(in K\), got -1.0$"),
    (dict(T=np.float64("nan")), r"T must be finite and >= 0 \(in K\), got nan$"),
])
def test_junction_refuses_bad_parameters(kw, match):
    with pytest.raises(ValueError, match=match):
        mbm.Junction(**{"I_c": 1e-6, "R": 1.0, "C": 1e-12, **kw})


def test_junction_refuses_what_is_not_a_number():
    with pytest.raises(TypeError, match="I_c"):
        mbm.Junction(I_c="1e-6", R=1.0, C=1e-12)


def test_reduced_run_is_the_dimensional_rcsj():
    """V(t) of C dV/dt + V/R + I_c sin φ = I + I_ac sin(2πft + φ₀), V = (Φ₀/2π) dφ/dt,
    integrated in SI by DOP853, against mbm's reduced run mapped back through Junction."""
    I_c, R, C = 10e-6, 10.0, 1e-12
    I, I_ac, f, phase = 12e-6, 3e-6, 20e9, 0.25
    j = mbm.Junction(I_c=I_c, R=R, C=C)

    def rhs(t, y):
        phi, v = y
        return [2 * math.pi * v / PHI0, (I + I_ac * math.sin(2 * math.pi * f * t + phase) - v / R
                                         - I_c * math.sin(phi)) / C]

    t_reduced = np.linspace(0.0, 100.0, 401)
    t_si = t_reduced * j.time_scale
    ref = solve_ivp(rhs, (0.0, t_si[-1]), [0.0, 0.0], method="DOP853", t_eval=t_si, rtol=1e-12,
                    atol=[1e-12, 1e-18])
    run = mbm.solve(j.model(I, drive_current=I_ac, drive_frequency_hz=f, drive_phase=phase),
                    (0.0, 100.0), [0.0, 0.0], t_eval=t_reduced, rtol=1e-12, atol=1e-12)
    v_scale = I_c * R  # ~1e-4 V; the run reaches ~2 I_c R
    # measured: 1.4e-12 V (1.4e-8 I_c R) and 6e-8 rad (θ reaches ~200 rad), the two
    # integrators' global errors at rtol 1e-12
    assert np.max(np.abs(j.voltage(run.y[1]) - ref.y[1])) <= 1e-7 * v_scale
    np.testing.assert_allclose(run.y[0], ref.y[0], rtol=0, atol=1e-6)
    assert np.max(np.abs(ref.y[1])) > 0.5 * v_scale  # not a vacuous comparison: it runs


@pytest.mark.parametrize("beta", [0.05, 0.5, 1.0, 1.5])
def test_retrapping_current_within_iv_curves_bracket(beta):
    g_r = mbm.retrapping_current(beta)
    if beta < 1.19:
        assert g_r < 1.0 and g_r < 4 * beta / math.pi  # Melnikov's first order bounds it above
    else:
        assert g_r == 1.0  # no hysteresis
    # a down sweep from a running state across γ_r, bisected to 1e-5
    c = mbm.iv_curve(beta, [min(g_r + 0.013, 1.1), g_r - 0.007], current_tol=1e-5, theta_dot0=3.0)
    lo, hi = c.retrapping_bracket
    assert hi - lo <= 1e-5
    assert lo - 1e-4 <= g_r <= hi + 1e-4


def test_retrapping_current_values():
    # the check: 0.59738 at β = 0.5 (DOP853 between 0.5973 and 0.5975)
    assert mbm.retrapping_current(0.5) == pytest.approx(0.5973832003, abs=1e-9)
    # ω scaling: γ_r(β, ω) = ω² γ_r(β/ω, 1)
    assert mbm.retrapping_current(1.0, omega=2.0) == pytest.approx(4 * mbm.retrapping_current(0.5), rel=1e-12)


@pytest.mark.parametrize("beta", [0.05, 0.3, 1.0, 1.18])
def test_beta_from_retrapping_inverts_it(beta):
    assert abs(mbm.beta_from_retrapping(mbm.retrapping_current(beta)) - beta) <= 1e-8
    assert mbm.beta_from_retrapping(mbm.retrapping_current(beta, omega=2.0) / 4.0, omega=2.0) \
        == pytest.approx(beta, abs=1e-8)


@pytest.mark.parametrize("ratio", [0.0, 1.0, -0.5, 1.5, float("nan")])
def test_beta_from_retrapping_refuses_ratio_outside_0_1(ratio):
    with pytest.raises(ValueError, match="ratio"):
        mbm.beta_from_retrapping(ratio)


def test_fit_iv_recovers_a_noisy_curve():
    """A synthetic running branch (10 µA, 10 Ω, 1 pF: β = 0.574) with 0.3 µV of noise,
    fitted from β0 = 0.4 and the default I_c0, R0: the truth within 3σ."""
    from mbm.junction.fits import running_branch_voltage

    j = mbm.Junction(I_c=10e-6, R=10.0, C=1e-12)
    current = np.linspace(25e-6, 7e-6, 30)
    clean = running_branch_voltage(current, j.beta, j.I_c, j.R)
    assert clean[-1] > 0.0 and np.all(np.diff(clean) < 0)  # all running, down to 0.7 I_c
    voltage = clean + np.random.default_rng(3).normal(0.0, 0.3e-6, current.size)
    # two zero-voltage points of the sweep below retrapping: left out by default
    f = mbm.fit_iv(np.r_[current, 5e-6, 3e-6], np.r_[voltage, 1e-8, -1e-8], beta0=0.4)
    assert f.success and f.fitted.sum() == 30 and not f.fitted[-2:].any()
    for value, err, truth in ((f.beta, f.beta_err, j.beta), (f.I_c, f.I_c_err, j.I_c), (f.R, f.R_err, j.R),
                              (f.beta_c, f.beta_c_err, j.beta_c)):
        assert 0.0 < err < 0.25 * truth and abs(value - truth) <= 3 * err, (value, err, truth)
    assert 0.2e-6 < f.sigma < 0.4e-6  # the noise, estimated from the residuals
    assert f.junction.C == pytest.approx(1e-12, rel=6 * f.beta_err / f.beta)
    assert f.beta_c == pytest.approx(1 / f.beta**2) and f.covariance.shape == (3, 3)


@pytest.mark.parametrize("args,kw,match", [
    (([1e-5, 2e-5], [1e-5]), {}, "same length"),
    (([1e-5, 2e-5], [1e-5, 2e-5]), {}, "at least 4"),
    (([1e-5, np.nan, 3e-5, 4e-5], [1e-5, 2e-5, 3e-5, 4e-5]), {}, r"current must be finite, got current\[1\] = nan"),
    (([1e-5, 2e-5, 3e-5, 4e-5], [1e-5, 2e-5, 3e-5, 4e-5]), dict(beta0=-1.0), "beta0"),
])
def test_fit_iv_refuses_bad_input(args, kw, match):
    with pytest.raises(ValueError, match=match):
        mbm.fit_iv(*args, **kw)
