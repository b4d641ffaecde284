"""The winding representation θ = 2πk + φ of the Taylor and splitting runs (mbm.core.loop).

References: the exact undamped flow (mbm's own, checked against heyoka in long
double in test_oracle) for wound rotations; mpmath for the constants and the
reduction.
"""

import math

import mpmath
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm.core import window


def test_two_pi_split_is_2pi_and_a_has_32_bits():
    mpmath.mp.prec = 200
    total = mpmath.mpf(window.TWO_PI_A) + mpmath.mpf(window.TWO_PI_B)
    # B is one double of size ~2e-9 (its ulp ~4e-25): 2π to that, so k·(A + B) misses
    # 2πk by < 1e-18 for every |k| < 2²¹, far below ulp(π).
    assert abs(total - 2 * mpmath.pi) < 1e-24
    m, e = math.frexp(window.TWO_PI_A)
    assert math.ldexp(m, 32) == int(math.ldexp(m, 32))  # at most 32 significant bits
    assert abs(window.TWO_PI_B) < 2.0**-28


@pytest.mark.parametrize("seed", range(3))
def test_wrap_is_an_exact_idempotent_reduction(seed):
    rng = np.random.default_rng(seed)
    mpmath.mp.prec = 200
    two_pi = 2 * mpmath.pi
    for _ in range(2000):
        phi = rng.choice([-1.0, 1.0]) * 10 ** rng.uniform(-3, 7)
        k = float(rng.integers(-10**5, 10**5))
        k2, phi2 = window.wrap(k, phi)
        assert -math.pi <= phi2 <= math.pi and k2 == int(k2)  # fl(π) < π: inside (−π, π]
        assert window.wrap(k2, phi2) == (k2, phi2)
        # 2πk' + φ' = 2πk + φ up to the rounding of φ' (and of the m·B product).
        exact = two_pi * k + mpmath.mpf(phi)
        assert abs(two_pi * k2 + mpmath.mpf(phi2) - exact) <= 4e-16 * max(1.0, abs(phi) * 1e-7)
    assert window.wrap(0.0, math.pi) == (0.0, math.pi)
    assert window.wrap(0.0, -math.pi) == (0.0, -math.pi)
    assert window.wrap(0.0, 3 * math.pi)[0] == 1.0 and window.wrap(0.0, -3 * math.pi)[0] == -1.0
    assert window.theta_of(0.0, -1.5) == -1.5


@pytest.mark.parametrize("v0, T", [(2.5, 1e4), (20.0, 2e3)])
def test_wound_rotation_keeps_its_tolerance(v0, T):
    # Issue 16: a rotation wound to |θ| ~ 10⁴ at rtol 1e-12.  Held as θ, each window's
    # sum rounded at ulp(|θ|) and the run drifted to 8× its tolerance scale (v0 = 2.5);
    # held as 2πk + φ it stays well inside.  Reference: the exact flow.
    m = mbm.Pendulum(0.0, 0.0, 1.0)
    te = np.linspace(0.0, T, 11)
    ex = mbm.solve(m, (0.0, T), [0.3, v0], t_eval=te, rtol=1e-13, atol=1e-13)
    assert ex.approximant == "belendez"
    r = mbm.solve(m, (0.0, T), [0.3, v0], t_eval=te, rtol=1e-12, atol=1e-12, approximant="taylor")
    scale = 1e-12 * (1.0 + np.abs(ex.y[0]).max())
    assert np.abs(ex.y[0]).max() > 1e4
    assert np.abs(r.y[0] - ex.y[0]).max() <= 0.1 * scale


def test_wrapped_output_on_every_path():
    model = mbm.Pendulum(0.1, 1.2)
    te = np.linspace(0.0, 3000.0, 301)
    kw = dict(rtol=1e-10, atol=1e-10)
    a = mbm.solve(model, (0.0, 3000.0), [0.0, 0.0], t_eval=te, **kw)
    b = mbm.solve(model, (0.0, 3000.0), [0.0, 0.0], t_eval=te, wrap=True, **kw)
    assert a.winding is None and b.winding.dtype == np.int64
    assert a.regime == b.regime == "running"
    assert np.all((-np.pi <= b.y[0]) & (b.y[0] <= np.pi)) and b.winding[-1] > 5000
    theta = 2 * np.pi * b.winding + b.y[0]
    assert np.all(np.abs(theta - a.y[0]) <= 4 * np.spacing(np.abs(a.y[0])) + 1e-15)
    np.testing.assert_array_equal(a.y[1], b.y[1])
    ig = mbm.Integrator(model, **kw)
    c = ig.solve((0.0, 3000.0), [0.0, 0.0], te, wrap=True)
    np.testing.assert_array_equal(c.y, b.y)
    np.testing.assert_array_equal(c.winding, b.winding)
    d = mbm.solve_batch([0.1, 0.2], [1.2, 0.1], 1.0, [[0.0, 0.0], [0.5, 0.0]], (0.0, 3000.0), te,
                        wrap=True, **kw)
    np.testing.assert_array_equal(d.y[0], b.y)
    np.testing.assert_array_equal(d.winding[0], b.winding)
    # A libration inside (−π, π]: the wrapped output is θ itself, winding 0.
    e = mbm.solve(mbm.Pendulum(0.2, 0.1), (0.0, 50.0), [0.5, 0.0], t_eval=te / 60, **kw)
    f = mbm.solve(mbm.Pendulum(0.2, 0.1), (0.0, 50.0), [0.5, 0.0], t_eval=te / 60, wrap=True, **kw)
    np.testing.assert_array_equal(e.y, f.y)
    assert not f.winding.any()


def test_wrapped_angle_keeps_its_precision_far_out():
    # On the running cycle at t ~ 1e6 (|θ| ~ 1.2e7, where θ itself is rounded to 1.9e-9),
    # the wrapped angle one period later repeats to the phase's own quantum: the times
    # are doubles, so t − t_anchor − nT (the cycle's phase) is rounded at ulp(1e6) =
    # 1.2e-10, which moves φ by up to |θ'|·ulp(t) (1.4e-9); nothing else may differ.
    # (Before, this compared with 1e-12 and passed only where the three phases happened
    # to round alike.)
    model = mbm.Pendulum(0.1, 1.2)
    r = mbm.solve(model, (0.0, 2e6), [0.0, 0.0], t_eval=[0.0, 1.0], rtol=1e-12, atol=1e-12)
    T = r.period
    t = np.array([1e6, 1e6 + T, 1e6 + 2 * T])
    w = mbm.solve(model, (0.0, 2e6), [0.0, 0.0], t_eval=t, rtol=1e-12, atol=1e-12, wrap=True)
    assert w.regime == "running"
    assert np.diff(w.winding).tolist() == [1, 1]
    quantum = np.abs(w.y[1]).max() * np.spacing(t.max())
    assert np.abs(np.diff(w.y[0])).max() <= quantum + 1e-12
    # θ' moves by |θ''|·ulp(t) at most, |θ''| ≤ |γ| + β|θ'| + ω².
    accel = 1.2 + 0.1 * np.abs(w.y[1]).max() + 1.0
    assert np.abs(np.diff(w.y[1])).max() <= accel * np.spacing(t.max()) + 1e-12


def test_wrap_needs_t_eval_and_a_bool():
    model = mbm.Pendulum(0.1, 0.3)
    with pytest.raises(ValueError, match="t_eval"):
        mbm.solve(model, (0.0, 1.0), [0.0, 0.0], wrap=True)
    with pytest.raises(ValueError, match="wrap"):
        mbm.solve(model, (0.0, 1.0), [0.0, 0.0], t_eval=[1.0], wrap="yes")
    with pytest.raises(ValueError, match="wrap"):
        mbm.solve_batch(0.1, 0.3, 1.0, [0.0, 0.0], (0.0, 1.0), [1.0], wrap=1)


def test_dense_output_repeats_each_step_end_on_a_wound_run():
    # scipy's contract on a run that winds (the state reduced to (−π, π] between
    # windows): sol(t_old) == y_old and sol(t) == y at every step, and solve_ivp's
    # outputs equal mbm.solve's bit for bit.
    model = mbm.Pendulum(0.05, 1.1)
    solver = mbm.MBM(model, 0.0, np.array([3.0, 4.0]), 300.0, rtol=1e-9, atol=1e-9)
    steps = 0
    while solver.status == "running":
        y_old = solver.y.copy()
        solver.step()
        sol = solver.dense_output()
        np.testing.assert_array_equal(sol(solver.t_old), y_old)
        np.testing.assert_array_equal(sol(solver.t), solver.y)
        steps += 1
    assert solver.status == "finished" and abs(solver.y[0]) > 100 and steps > 100
    te = np.linspace(0.0, 300.0, 401)
    a = solve_ivp(model, (0.0, 300.0), [3.0, 4.0], method=mbm.MBM, t_eval=te, rtol=1e-9, atol=1e-9)
    b = mbm.solve(model, (0.0, 300.0), [3.0, 4.0], t_eval=te, rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(a.y, b.y)
