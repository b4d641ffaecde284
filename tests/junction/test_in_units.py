"""IVCurve.in_units and ShapiroSteps.in_units: the results in amperes, volts and ohms.

Checked against the Junction's own conversions (γ I_c, (Φ₀ω_p/2π)⟨θ'⟩, its differential
resistance and drive frequency), a curve at ω = 2 against the same junction at ω = 1 (the
time ωt maps one onto the other), and each step's voltage against n h f / 2e from
scipy.constants' h and e, f = Ω ω_p / 2π.
"""

import dataclasses
import math

import numpy as np
import pytest
from scipy import constants

import mbm

JUNCTION = mbm.Junction(I_c=10e-6, R=10.0, C=1e-12)  # β = 0.574, ω_p / 2π = 27.7 GHz
# the same I_c and C with R for β = 1: the Shapiro scene of tests/junction/test_shapiro.py
JUNCTION_B1 = mbm.Junction(I_c=10e-6, R=1.0 / (JUNCTION.omega_p * 1e-12), C=1e-12)


@pytest.fixture(scope="module")
def curve():
    # a hysteretic down sweep from the running branch, with the slope
    return mbm.iv_curve(JUNCTION.beta, JUNCTION.gamma(np.linspace(14e-6, 0.0, 8)), theta_dot0=3.0,
                        differential=True)


@pytest.fixture(scope="module")
def steps():
    return mbm.shapiro_steps(1.0, (0.0, 0.9), amplitude=0.5, frequency=0.6, current_tol=1e-3, points=12)


def test_iv_curve_against_the_junctions_scales(curve):
    j, si = JUNCTION, curve.in_units(JUNCTION)
    assert isinstance(si, mbm.IVCurveSI) and si.junction is j
    np.testing.assert_allclose(si.current, j.current(curve.gamma), rtol=1e-15)
    np.testing.assert_allclose(si.voltage, j.voltage(curve.mean_velocity), rtol=1e-15)
    np.testing.assert_allclose(si.differential_resistance, j.differential_resistance(curve.dvoltage_dgamma),
                               rtol=1e-15)
    assert math.isfinite(curve.retrapping_current)
    assert si.retrapping_current == pytest.approx(j.current(curve.retrapping_current), rel=1e-15)
    assert si.retrapping_bracket == pytest.approx(tuple(j.current(curve.retrapping_bracket)), rel=1e-15)
    assert math.isnan(si.switching_current) and all(map(math.isnan, si.switching_bracket))  # swept down only
    assert (si.drive_current, si.drive_frequency_hz) == (0.0, 0.0)
    # the numbers of the guide: 138 µV at 14 µA, I_r = 6.71 µA
    assert (si.current[0], si.voltage[0]) == (pytest.approx(14e-6), pytest.approx(138e-6, rel=5e-3))
    assert si.retrapping_current == pytest.approx(6.71e-6, rel=1e-3)
    # without the slope: no differential resistance
    assert dataclasses.replace(curve, dvoltage_dgamma=None).in_units(j).differential_resistance is None


def test_iv_curve_at_another_omega_is_the_same_junction(curve):
    # θ'' + βθ' + ω² sin θ = γ at ω = 2, β = 2β_j, γ = 4γ_j is the junction's model in time 2t
    j, w = JUNCTION, 2.0
    scaled = mbm.iv_curve(w * j.beta, w**2 * curve.gamma, omega=w, theta_dot0=w * 3.0, differential=True)
    a, b = curve.in_units(j), scaled.in_units(j)
    np.testing.assert_allclose(b.current, a.current, rtol=1e-15)
    np.testing.assert_allclose(b.voltage, a.voltage, rtol=1e-9, atol=1e-9 * j.voltage_scale)
    np.testing.assert_allclose(b.differential_resistance, a.differential_resistance, rtol=1e-6)
    assert b.retrapping_current == pytest.approx(a.retrapping_current, abs=1e-4 * j.I_c)  # current_tol
    # the drive's amplitude A/ω² and frequency Ω/ω
    driven = dataclasses.replace(scaled, drive_amplitude=w**2 * 0.3, drive_frequency=w * 0.7).in_units(j)
    assert driven.drive_current == pytest.approx(0.3 * j.I_c, rel=1e-15)
    assert driven.drive_frequency_hz == pytest.approx(j.frequency(0.7), rel=1e-15)


def test_shapiro_steps_against_the_junctions_scales(steps):
    j, si = JUNCTION_B1, steps.in_units(JUNCTION_B1)
    assert j.beta == pytest.approx(1.0, rel=1e-12) and isinstance(si, mbm.ShapiroStepsSI)
    assert [(s.p, s.q) for s in si.steps] == [(s.p, s.q) for s in steps.steps] == [(0, 1), (1, 1)]
    np.testing.assert_allclose(si.current, j.current(steps.gamma), rtol=1e-15)
    np.testing.assert_allclose(si.voltage, j.voltage(steps.mean_velocity), rtol=1e-15)
    assert si.voltage_down is None
    assert si.step(1) is si.steps[1] and si.step(0) is si.steps[0] and si.step(1, 2) is None
    assert si.drive_current == pytest.approx(0.5 * j.I_c, rel=1e-15)
    for s, r in zip(si.steps, steps.steps):
        assert isinstance(s, mbm.ShapiroStepSI) and s.sweep == r.sweep
        for name in ("lower", "upper", "width"):
            assert getattr(s, name) == pytest.approx(j.current(getattr(r, name)), rel=1e-15)
        for name in ("lower_bracket", "upper_bracket"):
            assert getattr(s, name) == pytest.approx(tuple(j.current(getattr(r, name))), rel=1e-15)
        assert s.width == pytest.approx(s.upper - s.lower, rel=1e-14) and s.width > 0


def test_shapiro_step_voltage_is_n_h_f_over_2e(steps):
    j, si = JUNCTION_B1, steps.in_units(JUNCTION_B1)
    f = steps.frequency * j.omega_p / (2.0 * math.pi)  # Ω = 0.6 in hertz, f = Ω ω_p / 2π
    assert si.drive_frequency_hz == pytest.approx(f, rel=1e-15) == j.frequency(steps.frequency)
    assert j.Omega(si.drive_frequency_hz) == pytest.approx(steps.frequency, rel=1e-15)
    for s in si.steps:
        n = s.p / s.q
        assert s.voltage == pytest.approx(n * constants.h * f / (2.0 * constants.e), rel=1e-14, abs=0.0)
        assert s.voltage == pytest.approx(j.shapiro_voltage(n, f), rel=1e-14, abs=0.0)
    assert si.steps[1].voltage == pytest.approx(34.42e-6, rel=1e-3)  # 16.6 GHz: 34.4 µV


def test_shapiro_steps_at_another_omega(steps):
    # the same steps at ω = 2 (β 2, γ ×4, A ×4, Ω ×2; ⟨θ'⟩ ×2) convert to the same SI values
    w = 2.0
    scaled = dataclasses.replace(
        steps, beta=w * steps.beta, omega=w, amplitude=w**2 * steps.amplitude, frequency=w * steps.frequency,
        gamma=w**2 * steps.gamma, mean_velocity=w * steps.mean_velocity,
        steps=tuple(dataclasses.replace(s, voltage=w * s.voltage, lower=w**2 * s.lower, upper=w**2 * s.upper,
                                        width=w**2 * s.width, lower_bracket=tuple(w**2 * np.array(s.lower_bracket)),
                                        upper_bracket=tuple(w**2 * np.array(s.upper_bracket)))
                    for s in steps.steps))
    a, b = steps.in_units(JUNCTION_B1), scaled.in_units(JUNCTION_B1)
    assert (b.drive_current, b.drive_frequency_hz) == (pytest.approx(a.drive_current, rel=1e-15),
                                                       pytest.approx(a.drive_frequency_hz, rel=1e-15))
    for s, r in zip(b.steps, a.steps):
        assert (s.voltage, s.lower, s.upper, s.width) == pytest.approx((r.voltage, r.lower, r.upper, r.width),
                                                                       rel=1e-15)


@pytest.mark.parametrize("junction", [None, 1e-6, {"I_c": 1e-6, "R": 1.0, "C": 1e-12},
                                      mbm.Pendulum(beta=1.0, gamma=0.5)])
def test_refuses_what_is_not_a_junction(curve, steps, junction):
    for result in (curve, steps):
        with pytest.raises(TypeError, match=r"^junction must be an mbm\.Junction, got "):
            result.in_units(junction)


def test_refuses_another_junctions_result(curve, steps):
    other = mbm.Junction(I_c=10e-6, R=20.0, C=1e-12)  # β = 0.287
    with pytest.raises(ValueError, match=r"^junction: its beta = 0\.28.* is not the result's beta/omega = 0\.57"):
        curve.in_units(other)
    with pytest.raises(ValueError, match=r"^junction: its beta = 0\.28.* beta/omega = 1\.0 "):
        steps.in_units(other)
