"""Tests of mbm.reference: three independent integrators agree, match mpmath, conserve energy."""

import math

import mpmath
import numpy as np
import pytest

from mbm import scenes
from mbm.model import Pendulum
from mbm.frontends.reference import REFERENCE_SOLVERS, reference

SOLVERS = REFERENCE_SOLVERS


def _scene(name, t_end, bound):
    """(model, y0, T, bound) of the catalogue scene ``name`` over 0 ≤ t ≤ T."""
    sc = scenes.get(name).until(t_end)
    return (sc.model, list(sc.y0), sc.t_end, bound)


# (model, y0, T, bound): pairwise agreement bound on max_t |Δy_i| / max(1, max_t |y_i|)
# at rtol = atol = 1e-12.  Local errors of 1e-12 accumulate over the ~1e3–1e4 steps
# of a run, and are amplified by the flow; the bounds are that accumulation with a
# margin of about 3 over the measured worst pair (in brackets).
SCENES = {
    # second paper's Example 1: damped libration around the torqued equilibrium [2.7e-10]
    "damped-torqued": _scene("ex1", 80.0, 1e-9),
    # undamped libration with θ'(0)=1.999, m = 0.999: the quarter period K(m) ≈ ½ ln(16/(1−m))
    # has dK/dm ≈ 1/(2(1−m)) = 500, so a 1e-12 slip in energy moves the phase by ~1e-9 per
    # period; over 2 periods the solvers legitimately differ by ~1e-7 [measured 3.0e-7 over
    # 0 ≤ t ≤ 40 between CVODE and IDA; against a DOP853 run at rtol 2.3e-14 CVODE errs 2.5e-7]
    "near-separatrix": _scene("separatrix", 40.0, 1e-6),
    # running state: θ grows to ~830, relative agreement [measured 1.2e-10 in θ, 8e-10 in θ']
    "running": _scene("running", 80.0, 3e-9),
}


@pytest.fixture(scope="module")
def scene_solutions():
    out = {}
    for key, (model, y0, T, _) in SCENES.items():
        t_eval = np.linspace(0.0, T, 401)
        out[key] = {
            s: reference(model, (0.0, T), y0, t_eval=t_eval, solver=s) for s in SOLVERS
        }
    return out


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_three_solvers_agree(scene, scene_solutions):
    sols = scene_solutions[scene]
    bound = SCENES[scene][3]
    for s in SOLVERS:
        assert sols[s].success, sols[s].message
        assert sols[s].y.shape == (2, 401)
        np.testing.assert_array_equal(sols[s].t, sols["cvode"].t)
    for a, b in (("cvode", "ida"), ("cvode", "dop853"), ("ida", "dop853")):
        for i in range(2):
            scale = max(1.0, np.abs(sols[a].y[i]).max())
            err = np.abs(sols[a].y[i] - sols[b].y[i]).max() / scale
            assert err <= bound, f"{a} vs {b}, component {i}: {err:.3g} > {bound:.0e}"


@pytest.mark.parametrize("solver", SOLVERS)
def test_tolerance_is_honoured(solver):
    # Tightening the tolerance 100x must shrink the error against a much tighter run
    # by at least 10x (measured: CVODE 450x, IDA 77x, DOP853 85x): the solver is in
    # its asymptotic regime at 1e-12, not stuck at a floor.
    model, y0, T = Pendulum(beta=0.1, gamma=0.3), [math.pi / 6, 0.0], 80.0
    t_eval = np.linspace(0.0, T, 201)
    tight = reference(model, (0.0, T), y0, t_eval=t_eval, solver="dop853", rtol=2.3e-14, atol=1e-16)
    e10 = np.abs(reference(model, (0.0, T), y0, t_eval, 1e-10, 1e-10, solver).y - tight.y).max()
    e12 = np.abs(reference(model, (0.0, T), y0, t_eval, 1e-12, 1e-12, solver).y - tight.y).max()
    assert e12 < 1e-9
    assert e10 / e12 > 10.0, (e10, e12)


def _mpmath_solution(beta, gamma, omega, y0, times, dps=30):
    """High-precision Taylor solution (mpmath.odefun) at ``times``, as floats."""
    with mpmath.workdps(dps):
        b, g, w2 = mpmath.mpf(beta), mpmath.mpf(gamma), mpmath.mpf(omega) ** 2
        sol = mpmath.odefun(
            lambda t, y: [y[1], g - b * y[1] - w2 * mpmath.sin(y[0])],
            0,
            [mpmath.mpf(y0[0]), mpmath.mpf(y0[1])],
            tol=mpmath.mpf(10) ** (-(dps - 5)),
        )
        vals = [sol(mpmath.mpf(t)) for t in times]
        return np.array([[float(v[0]) for v in vals], [float(v[1]) for v in vals]])


@pytest.mark.parametrize(
    "beta, gamma, omega, y0",
    [
        (0.1, 0.3, 1.0, [math.pi / 6, 0.0]),
        (0.0, 0.0, 1.3, [0.0, 3.0]),  # rotation (θ'(0) > 2ω), θ reaches 17 by t = 8; ω ≠ 1
    ],
)
def test_cvode_matches_mpmath_taylor(beta, gamma, omega, y0):
    times = [0.5, 1.0, 2.5, 5.0, 8.0]
    exact = _mpmath_solution(beta, gamma, omega, y0, times)
    sol = reference(Pendulum(beta, gamma, omega), (0.0, 8.0), y0, t_eval=times)
    assert sol.success
    # 1e-12 local tolerance, a few hundred steps: global error ~1e-11 relative to the
    # size of the component (measured 1.8e-11 libration, 1.2e-11 rotation)
    for i in range(2):
        scale = max(1.0, np.abs(exact[i]).max())
        np.testing.assert_allclose(sol.y[i], exact[i], rtol=0, atol=1e-10 * scale)


@pytest.mark.parametrize("solver", SOLVERS)
def test_energy_conserved_when_undamped_and_unforced(solver):
    model = Pendulum(omega=1.7)
    tol, T = 1e-12, 200.0
    for y0 in ([2.0, 0.0], [0.0, 3.5]):  # libration and rotation
        sol = reference(model, (0.0, T), y0, solver=solver, rtol=tol, atol=tol)
        assert sol.success
        e0 = model.energy(y0)
        rel_drift = np.abs(model.energy(sol.y) - e0).max() / e0
        # A drift of a few tolerances per unit time, relative to E: measured
        # (rel_drift / (tol T)) = 0.5 / 5 (CVODE), 8 / 11 (IDA), 0.06 / 0.1 (DOP853)
        # for libration / rotation.
        assert rel_drift <= 30.0 * tol * T, rel_drift


@pytest.mark.parametrize("solver", SOLVERS)
def test_backward_integration_returns_to_start(solver):
    model, y0 = Pendulum(beta=0.1, gamma=0.3), np.array([0.5, 0.2])
    fwd = reference(model, (0.0, 30.0), y0, solver=solver)
    back = reference(model, (30.0, 0.0), fwd.y[:, -1], t_eval=[30.0, 15.0, 0.0], solver=solver)
    assert back.success
    np.testing.assert_array_equal(back.t, [30.0, 15.0, 0.0])
    # the damped flow run backward amplifies errors by e^{βT/2} ≈ 4.5
    np.testing.assert_allclose(back.y[:, -1], y0, rtol=0, atol=5e-9)
    mid = reference(model, (0.0, 15.0), y0, t_eval=[15.0], solver=solver)
    np.testing.assert_allclose(back.y[:, 1], mid.y[:, 0], rtol=0, atol=5e-9)


@pytest.mark.parametrize("solver", SOLVERS)
def test_output_grid(solver):
    model, y0 = Pendulum(beta=0.2), [0.3, 0.0]
    steps = reference(model, (0.0, 10.0), y0, solver=solver)
    assert steps.t[0] == 0.0 and steps.t[-1] == 10.0
    assert np.all(np.diff(steps.t) > 0) and steps.y.shape == (2, len(steps.t))
    np.testing.assert_array_equal(steps.y[:, 0], y0)
    assert steps.nfev > 0 and steps.solver == solver
    only_end = reference(model, (0.0, 10.0), y0, t_eval=[10.0], solver=solver)
    assert only_end.t.tolist() == [10.0] and only_end.y.shape == (2, 1)
    np.testing.assert_allclose(only_end.y[:, 0], steps.y[:, -1], atol=1e-10)
    ends = reference(model, (0.0, 10.0), y0, t_eval=[0.0, 10.0], solver=solver)
    assert ends.t.tolist() == [0.0, 10.0]
    np.testing.assert_allclose(ends.y[:, 1], steps.y[:, -1], atol=1e-10)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(solver="rk45"), "solver must be one of"),
        (dict(y0=[0.1, 0.2, 0.3]), "y0 must have shape"),
        (dict(y0=[np.nan, 0.0]), "y0 must be finite"),
        (dict(t_span=(0.0, np.inf)), "t_span must be finite"),
        (dict(t_span=(1.0, 1.0)), "t0 != t_bound"),
        (dict(t_span=(0.0,)), "t_span must be a pair"),
        (dict(rtol=0.0), "rtol must be > 0"),
        (dict(atol=-1e-9), "atol must be > 0"),
        (dict(t_eval=[0.0, 11.0]), "t_eval must lie within"),
        (dict(t_eval=[5.0, 1.0]), "strictly monotonic"),
        (dict(t_eval=[]), "at least one"),
    ],
)
def test_bad_input_raises(kwargs, match):
    args = dict(model=Pendulum(), t_span=(0.0, 10.0), y0=[0.1, 0.0])
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        reference(**args)


def test_rtol_below_floor_warns_and_clamps():
    # One rtol policy for every entry point (scipy's): below 100 eps, warn and raise it.
    args = dict(model=Pendulum(0.1, 0.3), t_span=(0.0, 10.0), y0=[0.1, 0.0], t_eval=[5.0, 10.0])
    with pytest.warns(UserWarning, match="below 100 machine epsilons"):
        low = reference(rtol=1e-17, **args)
    floor = reference(rtol=100 * np.finfo(float).eps, **args)
    np.testing.assert_array_equal(low.y, floor.y)


def test_model_type_checked():
    with pytest.raises(TypeError, match="Pendulum"):
        reference(lambda t, y: y, (0.0, 1.0), [0.0, 0.0])
