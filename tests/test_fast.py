"""The compiled path: mbm.solve and mbm.solve_batch equal the solve_ivp path."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm

EX1 = mbm.Pendulum(0.1, 0.3)
EX1_Y0 = [math.radians(30.0), 0.0]


@pytest.mark.parametrize(
    "model,y0,T,kw",
    [
        (EX1, EX1_Y0, 80.0, dict(rtol=1e-6, atol=1e-9)),
        (EX1, EX1_Y0, -30.0, dict(rtol=1e-10, atol=1e-10)),
        (mbm.Pendulum(0.1, 1.2), [0.0, 0.0], 100.0, dict(rtol=1e-8, atol=1e-8)),
        (mbm.Pendulum(0.0, 0.0), [0.0, 1.999], 200.0, dict(rtol=1e-6, atol=1e-9)),
        (EX1, EX1_Y0, 20.0, dict(approximant="salas-torque", tau=0.5)),
        (EX1, EX1_Y0, 20.0, dict(approximant="split4", tau=0.5)),
        (EX1, EX1_Y0, 20.0, dict(approximant="taylor12", rtol=1e-7, atol=1e-7)),
    ],
)
def test_solve_equals_solve_ivp_path(model, y0, T, kw):
    t = np.linspace(0.0, T, 201)
    fast = mbm.solve(model, (0.0, T), y0, t_eval=t, **kw)
    ivp = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, t_eval=t, **kw)
    assert fast.success and ivp.success
    np.testing.assert_array_equal(fast.t, t)
    np.testing.assert_allclose(fast.y, ivp.y, rtol=0, atol=1e-12)
    # without t_eval: the window ends, as solve_ivp returns its steps
    ends = mbm.solve(model, (0.0, T), y0, **kw)
    ivp_ends = solve_ivp(model, (0.0, T), y0, method=mbm.MBM, **kw)
    np.testing.assert_array_equal(ends.t, ivp_ends.t)
    np.testing.assert_allclose(ends.y, ivp_ends.y, rtol=0, atol=1e-12)
    assert ends.n_windows == ends.t.size - 1


def test_auto_choice_reported():
    r = mbm.solve(mbm.Pendulum(0.0, 0.0), (0.0, 1e6), [0.3, 1.0], t_eval=[0.0, 1e6])
    assert r.approximant == "belendez" and "exact" in r.reason and r.n_windows == 1
    np.testing.assert_array_equal(r.y[:, 0], [0.3, 1.0])
    r = mbm.solve(EX1, (0.0, 10.0), EX1_Y0)
    assert r.approximant == mbm.choice.CONVERGENT_DEFAULT


def test_failure_is_a_status_not_nan():
    r = mbm.solve(mbm.Pendulum(0.0, 0.2), (0.0, 10.0), [0.0, 2.5], approximant="salas-torque", tau=0.5)
    assert not r.success and r.status != 0 and "domain" in r.message
    assert np.all(np.isfinite(r.y))


@pytest.mark.parametrize(
    "kw,match",
    [
        (dict(t_span=(0.0, float("inf"))), "t_span"),
        (dict(y0=[0.0, float("nan")]), "y0"),
        (dict(y0=[0.0, 1.0, 2.0]), "y0"),
        (dict(rtol=-1.0), "rtol"),
        (dict(tau=0.0), "tau"),
        (dict(t_eval=[0.0, 20.0]), "t_eval"),
        (dict(t_eval=[5.0, 1.0]), "t_eval"),
        (dict(approximant="johannessen", tau=0.1), "compiled"),
        (dict(approximant="nope"), "approximant"),
    ],
)
def test_bad_input(kw, match):
    args = dict(t_span=(0.0, 10.0), y0=EX1_Y0)
    args.update(kw)
    with pytest.raises(ValueError, match=match):
        mbm.solve(mbm.Pendulum(0.0, 0.0) if kw.get("approximant") == "johannessen" else EX1, **args)


def test_batch_equals_single_scenes():
    gammas = np.linspace(0.0, 2.0, 9)
    t = np.linspace(0.0, 200.0, 21)
    b = mbm.solve_batch(0.1, gammas, 1.0, [0.0, 0.0], (0.0, 200.0), t, rtol=1e-8, atol=1e-8)
    assert b.y.shape == (9, 2, 21) and b.success.all()
    for i, g in enumerate(gammas):
        r = mbm.solve(mbm.Pendulum(0.1, g), (0.0, 200.0), [0.0, 0.0], t_eval=t, rtol=1e-8, atol=1e-8)
        np.testing.assert_array_equal(b.y[i], r.y)
        assert b.n_windows[i] == r.n_windows
    # γ = 0 with θ = θ' = 0 stays at rest; β = 0.1 ≠ 0 so the convergent family is used
    assert set(b.approximant) == {mbm.choice.CONVERGENT_DEFAULT}


def test_batch_mixed_scenes_and_status():
    b = mbm.solve_batch([0.0, 0.1], [0.0, 0.3], [1.0, 2.0], [[0.3, 1.0], [0.1, 0.0]], (0.0, 10.0), np.linspace(0.0, 10.0, 5))
    assert list(b.approximant) == ["belendez", mbm.choice.CONVERGENT_DEFAULT]
    assert b.success.all()
    with pytest.raises(ValueError, match="y0"):
        mbm.solve_batch([0.1, 0.2], 0.3, 1.0, [[0.0, 0.0]] * 3, (0.0, 1.0), [1.0])


def test_batch_order_balances_contiguous_blocks():
    # numba splits a prange into contiguous blocks; sweeps list scenes by cost.  Every
    # block of the order must sample the whole batch: here each quarter's mean position
    # is within 2 % of the middle, and the order is a permutation.
    from mbm.fast import _balanced_order

    for n in (1, 2, 7, 1000, 10_000):
        order = _balanced_order(n)
        assert np.array_equal(np.sort(order), np.arange(n))
    order = _balanced_order(10_000)
    for block in np.array_split(order, 4):
        assert abs(block.mean() / 10_000 - 0.5) < 0.02
