"""``mbm.bhl_rate``: the Büttiker–Harris–Landauer rate at weak damping, against escape_times."""

import math

import numpy as np
import pytest

import mbm
from mbm.noise import barrier_action, well


def test_barrier_action_limits():
    assert barrier_action(0.0) == 16.0 and barrier_action(0.0, omega=2.0) == 32.0
    assert abs(barrier_action(1e-9) - 16.0) < 1e-6
    # the cubic well near abs(γ) = ω²: S = 7.2 ΔU / ω_a
    for g in (0.99, -0.999):
        w = well(g)
        assert abs(barrier_action(g) / (7.2 * w["barrier"] / w["omega_well"]) - 1) < 1e-5
    # scaling: S(γω², ω) = ω S(γ, 1)
    assert abs(barrier_action(0.5 * 4.0, omega=2.0) - 2.0 * barrier_action(0.5)) < 1e-9


def test_bhl_limits_are_energy_diffusion_and_transition_state():
    w = well(0.5)
    tst = w["omega_well"] / (2 * math.pi) * math.exp(-w["barrier"] / 0.1)
    assert abs(mbm.bhl_rate(1e3, 0.5, 0.1) / tst - 1) < 1e-3  # a_t = 1 − O(1/Δ), Δ = 5e4
    beta = 1e-9  # a_t = Δ (1 − O(sqrt Δ)), Δ = βS/T = 5e-8
    ed = tst * beta * barrier_action(0.5) / 0.1
    assert abs(mbm.bhl_rate(beta, 0.5, 0.1) / ed - 1) < 1e-3


@pytest.mark.parametrize("beta,gamma", [(0.02, 0.5), (0.05, 0.6)])
def test_weak_damping_escape_is_bhl_not_kramers(beta, gamma):
    # ΔU/T = 5.5, βS/T = 0.9–1.8 (energy diffusion limits the rate).  400 escapes give the
    # rate to 5 % (one standard error); a factor 1.3 allows for the O(T/ΔU)
    # finite-barrier corrections of both formulas (measured ratios 1.04 and 1.07).
    # Kramers' moderate-damping rate is 1.6–2.7 times too high here (measured rate /
    # Kramers 0.37 and 0.61): below 0.75, over 5 standard errors off.
    temperature = well(gamma)["barrier"] / 5.5
    e = mbm.escape_times(beta, gamma, temperature, 400, seed=1)
    assert np.isfinite(e.times).all()
    ratio = e.rate / mbm.bhl_rate(beta, gamma, temperature)
    assert 1 / 1.3 < ratio < 1.3, ratio
    assert e.rate / mbm.kramers_rate(beta, gamma, temperature) < 0.75


@pytest.mark.parametrize("args,kw,err,words", [
    ((0.0, 0.5, 0.1), {}, ValueError, "beta must be > 0"),
    ((0.1, 1.0, 0.1), {}, ValueError, "gamma must satisfy"),
    ((0.1, 0.5, -0.1), {}, ValueError, "temperature must be > 0"),
    ((0.1, 0.5, 0.1), {"omega": 0.0}, ValueError, "omega must be"),
    ((0.1, "a", 0.1), {}, TypeError, "gamma"),
])
def test_bhl_rate_refuses(args, kw, err, words):
    with pytest.raises(err, match=words):
        mbm.bhl_rate(*args, **kw)
