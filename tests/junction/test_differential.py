"""iv_curve(..., differential=True): the differential resistance d⟨θ'⟩/dγ.

On a running cycle it comes from the period's sensitivity (one period of mbm.solve
with ∂/∂(θ₀, v₀, γ)); it is checked against two independent ways: central differences
of iv_curve's own ⟨θ'⟩ in γ, and the phase drift of ∂θ/∂γ along a long mbm.solve run
on the cycle (its regime "running", the stored period's sensitivity).  0 where locked
and on a Shapiro step, NaN at a driven point off the steps; ohms by mbm.Junction.
"""

import math

import numpy as np
import pytest

import mbm
from mbm.junction import iv as junction

# Relative agreement asked (the 1e-6); measured ≤ 6e-8 against the central
# differences below and ≤ 1e-7 against the phase drift.
SLOPE_RTOL = 1e-6


def _point(beta, gamma):
    # One running point (started fast enough to run on the hysteretic branch) and its
    # settled state on the cycle.
    c = junction.iv_curve(beta, [gamma], theta_dot0=math.copysign(2.0 + abs(gamma) / beta, gamma),
                          differential=True)
    assert c.regime[0] == "running"
    y = junction.mean_velocity(mbm.Pendulum(beta, gamma), c.start_state[0])[3]
    return c, y


def _central(beta, gamma, y, h=1e-3):
    # d⟨θ'⟩/dγ by the fourth-order central difference of mean_velocity from y.
    v = [junction.mean_velocity(mbm.Pendulum(beta, gamma + k * h), y)[1] for k in (-2, -1, 1, 2)]
    return (v[0] - 8.0 * v[1] + 8.0 * v[2] - v[3]) / (12.0 * h)


# β in 0.05–1; γ above ω² (1.05–2) and on the hysteretic branch below it; one negative.
@pytest.mark.parametrize("beta,gamma", [(0.05, 1.3), (0.05, 0.5266), (0.1, 2.0), (0.2, 1.05), (0.2, 0.635),
                                        (0.5, 0.8335), (1.0, 1.6), (0.2, -1.3)])
def test_slope_against_central_differences(beta, gamma):
    c, y = _point(beta, gamma)
    ref = _central(beta, gamma, y)
    assert c.dvoltage_dgamma[0] == pytest.approx(ref, rel=SLOPE_RTOL)
    assert c.dvoltage_dgamma[0] > 0.0  # ⟨θ'⟩ is odd in γ: its slope even, positive


@pytest.mark.parametrize("beta,gamma", [(0.05, 0.0732), (0.2, 0.2899), (1.0, 0.98), (0.2, 1.6)])
def test_slope_against_phase_drift(beta, gamma):
    # On the cycle θ(t) = Θ(⟨θ'⟩t + ψ) with Θ(s + 2π) = Θ(s) + 2π, so ∂θ/∂γ = periodic +
    # t·(d⟨θ'⟩/dγ)·θ'(t)/⟨θ'⟩: K periods apart, after the sensitivity's transient has
    # decayed (e^{−βt}, the cycle's other multiplier), Δ(∂θ/∂γ)/(K T_c)·⟨θ'⟩/θ'(t₁).
    # Near the retrapping current (the first three) central differences lose accuracy
    # (⟨θ'⟩ ~ 1/log), this does not.
    c, y = _point(beta, gamma)
    period, v, k = c.period[0], c.mean_velocity[0], 10
    t = np.array([30.0 / beta, 30.0 / beta + k * period])
    r = mbm.solve(mbm.Pendulum(beta, gamma), (0.0, t[-1]), y, t_eval=t, rtol=1e-10, atol=1e-10,
                  sensitivities=("gamma",))
    s = r.sensitivities[0, 0]
    drift = (s[1] - s[0]) / (k * period) * v / r.y[1, 0]
    assert c.dvoltage_dgamma[0] == pytest.approx(drift, rel=SLOPE_RTOL)


def test_locked_points_and_the_curve_unchanged():
    # An up-and-down sweep: 0 exactly where locked, finite and positive where running;
    # everything else bit for bit as without the option (which leaves None).
    g = np.r_[np.linspace(0.0, 1.5, 7), np.linspace(1.5, 0.0, 7)]
    plain = junction.iv_curve(0.2, g)
    c = junction.iv_curve(0.2, g, differential=True)
    assert plain.dvoltage_dgamma is None
    locked = c.regime == "locked"
    assert locked.any() and (~locked).any()
    assert np.all(c.dvoltage_dgamma[locked] == 0.0)
    assert np.all(np.isfinite(c.dvoltage_dgamma[~locked])) and np.all(c.dvoltage_dgamma[~locked] > 0.0)
    for name in ("mean_velocity", "period", "start_state", "regime"):
        np.testing.assert_array_equal(getattr(c, name), getattr(plain, name))
    assert (c.switching_bracket, c.retrapping_bracket) == (plain.switching_bracket, plain.retrapping_bracket)


def test_csv_column(tmp_path):
    c = junction.iv_curve(0.5, [0.5, 1.5], differential=True)
    c.to_csv(tmp_path / "d.csv")
    rows = (tmp_path / "d.csv").read_text().splitlines()
    assert rows[1] == "gamma,mean_velocity,regime,period,converged,dvoltage_dgamma"
    assert float(rows[2].split(",")[-1]) == 0.0 and float(rows[3].split(",")[-1]) == c.dvoltage_dgamma[1]
    junction.iv_curve(0.5, [0.5, 1.5]).to_csv(tmp_path / "p.csv")
    assert (tmp_path / "p.csv").read_text().splitlines()[1] == "gamma,mean_velocity,regime,period,converged"


def test_driven_points():
    # β = 2, A = Ω = 1: γ = 2.1 on the n = 1 Shapiro step (phase-locked: 0), γ = 2.45
    # between the steps (quasi-periodic, no cycle of its own to time: NaN).
    with pytest.warns(RuntimeWarning, match="did not settle"):
        c = junction.iv_curve(2.0, [2.1, 2.45], drive_amplitude=1.0, drive_frequency=1.0, differential=True)
    assert list(c.regime) == ["phase-locked", "running"]
    assert c.dvoltage_dgamma[0] == 0.0 and math.isnan(c.dvoltage_dgamma[1])


def test_ohms():
    # dV/dI = (Φ₀ω_p/2π)/I_c · d⟨θ'⟩/dγ = β R · d⟨θ'⟩/dγ, against central differences in SI
    # units of the voltages iv_curve gives, and → R on the ohmic branch (⟨θ'⟩ → γ/β).
    j = mbm.Junction(I_c=10e-6, R=10.0, C=1e-12)
    current, dI = 14e-6, 1e-9
    c = junction.iv_curve(j.beta, j.gamma([current - 2 * dI, current - dI, current, current + dI, current + 2 * dI]),
                          theta_dot0=3.0, differential=True)
    v = j.voltage(c.mean_velocity)
    ref = (v[0] - 8.0 * v[1] + 8.0 * v[3] - v[4]) / (12.0 * dI)
    assert j.differential_resistance(c.dvoltage_dgamma[2]) == pytest.approx(ref, rel=1e-6)
    assert j.differential_resistance(2.0) == pytest.approx(2.0 * j.beta * j.R, rel=1e-14)
    far = junction.iv_curve(j.beta, [9.0], theta_dot0=15.0, differential=True)
    assert j.differential_resistance(far.dvoltage_dgamma)[0] == pytest.approx(j.R, rel=1e-3)
    assert np.isnan(j.differential_resistance([np.nan, 1.0])[0])


def test_bad_input():
    with pytest.raises(TypeError, match="differential must be True or False"):
        junction.iv_curve(0.2, [1.5], differential="yes")
    with pytest.raises(TypeError, match="dvoltage_dgamma"):
        mbm.Junction(I_c=10e-6, R=10.0, C=1e-12).differential_resistance("1")
