"""Bad input: every entry point refuses it with a ValueError/TypeError naming the argument.

Entry points: ``solve_ivp(method=mbm.MBM)``, ``mbm.solve``, ``mbm.Pendulum``,
``mbm.reference``, ``approximant.anchor`` (and ``mbm.solve_batch``, ``mbm.pendulum_flow``,
``mbm.period`` where they take the same argument).  Each test checks the exception
type *and* that the message names the offending argument and what is allowed, so a
message that degrades to numpy's or numba's internals fails the test.
"""

import math
import re
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm

NAN = float("nan")
INF = float("inf")
MODEL = mbm.Pendulum(beta=0.1, gamma=0.3)

NON_FINITE_Y0 = [[NAN, 0.0], [0.0, NAN], [INF, 0.0], [0.0, -INF]]
BAD_SHAPE_Y0 = [[0.0], [0.0, 0.0, 0.0], [[0.0, 0.0], [0.0, 0.0]], []]
NON_FINITE_SPANS = [(0.0, NAN), (NAN, 1.0), (0.0, INF), (-INF, 0.0)]


def _ivp(y0=(0.1, 0.0), t_span=(0.0, 1.0), **kw):
    kw.setdefault("rtol", 1e-8)
    kw.setdefault("atol", 1e-10)
    return solve_ivp(MODEL, t_span, y0, method=mbm.MBM, **kw)


# ---------------------------------------------------------------------------
# y0 not finite
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("y0", NON_FINITE_Y0)
def test_non_finite_y0_solve_ivp(y0):
    # scipy's OdeSolver checks first; its message names y0 and "finite".
    with pytest.raises(ValueError, match=r"(?i)y0.*finite"):
        _ivp(y0=y0)


@pytest.mark.parametrize("y0", NON_FINITE_Y0)
def test_non_finite_y0_solve(y0):
    with pytest.raises(ValueError, match=r"y0 must be finite"):
        mbm.solve(MODEL, (0.0, 1.0), y0)


@pytest.mark.parametrize("y0", NON_FINITE_Y0)
def test_non_finite_y0_reference(y0):
    with pytest.raises(ValueError, match=r"y0 must be finite"):
        mbm.reference(MODEL, (0.0, 1.0), y0)


@pytest.mark.parametrize("y0", NON_FINITE_Y0)
def test_non_finite_y0_batch_flow_period(y0):
    with pytest.raises(ValueError, match=r"y0 must be finite"):
        mbm.solve_batch(0.1, 0.3, 1.0, np.array([y0]), (0.0, 1.0), np.array([1.0]))
    with pytest.raises(ValueError, match=r"y0 must be finite"):
        mbm.pendulum_flow(mbm.Pendulum(), y0, 1.0)
    with pytest.raises(ValueError, match=r"y0 must be finite"):
        mbm.period(mbm.Pendulum(), y0)


@pytest.mark.parametrize("name", ["taylor", "split4", "belendez", "salas-damped", "salas-torque", "johannessen"])
@pytest.mark.parametrize("state", [(NAN, 0.0), (0.0, NAN), (INF, 0.0), (0.0, -INF)])
def test_non_finite_anchor(name, state):
    model = mbm.Pendulum() if name == "belendez" else mbm.Pendulum(beta=0.1)
    with pytest.raises(ValueError, match=r"anchor state must be finite"):
        mbm.get_approximant(name).anchor(model, *state)


# ---------------------------------------------------------------------------
# y0 of the wrong shape
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("y0", BAD_SHAPE_Y0)
def test_bad_shape_y0_solve_ivp(y0):
    # (2, 2) is refused by scipy ("`y0` must be 1-dimensional"), the others by MBM.
    with pytest.raises(ValueError, match=r"y0"):
        _ivp(y0=y0)


@pytest.mark.parametrize("y0", BAD_SHAPE_Y0)
def test_bad_shape_y0_solve(y0):
    with pytest.raises(ValueError, match=r"y0 must have shape \(2,\)"):
        mbm.solve(MODEL, (0.0, 1.0), y0)


@pytest.mark.parametrize("y0", BAD_SHAPE_Y0)
def test_bad_shape_y0_reference(y0):
    with pytest.raises(ValueError, match=r"y0 must have shape \(2,\)"):
        mbm.reference(MODEL, (0.0, 1.0), y0)


def test_bad_shape_y0_batch():
    with pytest.raises(ValueError, match=r"y0 must have shape"):
        mbm.solve_batch([0.1, 0.2], 0.0, 1.0, np.zeros((3, 2)), (0.0, 1.0), np.array([1.0]))


@pytest.mark.parametrize("y0", [["a", 0.0], ["0.1", "0"], [0.1, 1j], [True, False], ["0.1", 0.0]])
def test_non_numeric_y0(y0):
    # A string, a complex or booleans is not a state: a TypeError naming y0 on every path.
    with pytest.raises(TypeError, match=r"y0 must be array_like of 2 real numbers"):
        mbm.reference(MODEL, (0.0, 1.0), y0)
    with pytest.raises(TypeError, match=r"y0 must be array_like of 2 real numbers"):
        mbm.solve(MODEL, (0.0, 1.0), y0)
    with pytest.raises(TypeError, match=r"y0 must be array_like of 2 real numbers"):
        mbm.Integrator(MODEL).solve((0.0, 1.0), y0)
    with pytest.raises(TypeError, match=r"y0 must be a real number or an array of real numbers"):
        mbm.solve_batch(0.1, 0.3, 1.0, y0, (0.0, 1.0), [1.0])


# ---------------------------------------------------------------------------
# t_span not finite
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("t_span", NON_FINITE_SPANS)
def test_non_finite_t_span_solve_ivp(t_span):
    with pytest.raises(ValueError, match=r"t0 and t_bound must be finite"):
        _ivp(t_span=t_span)


@pytest.mark.parametrize("t_span", NON_FINITE_SPANS)
def test_non_finite_t_span_solve(t_span):
    with pytest.raises(ValueError, match=r"t_span must be finite"):
        mbm.solve(MODEL, t_span, [0.1, 0.0])


@pytest.mark.parametrize("t_span", NON_FINITE_SPANS)
def test_non_finite_t_span_reference(t_span):
    with pytest.raises(ValueError, match=r"t_span must be finite"):
        mbm.reference(MODEL, t_span, [0.1, 0.0])


@pytest.mark.parametrize("t_eval", [[0.5, NAN], [0.5, INF]])
def test_non_finite_t_eval(t_eval):
    with pytest.raises(ValueError, match=r"t_eval must be finite"):
        mbm.solve(MODEL, (0.0, 1.0), [0.1, 0.0], t_eval=t_eval)
    with pytest.raises(ValueError, match=r"t_eval must be finite"):
        mbm.reference(MODEL, (0.0, 1.0), [0.1, 0.0], t_eval=t_eval)


def test_empty_t_span_reference():
    with pytest.raises(ValueError, match=r"t_span must have t0 != t_bound"):
        mbm.reference(MODEL, (1.0, 1.0), [0.1, 0.0])


# ---------------------------------------------------------------------------
# β < 0, ω ≤ 0, non-finite or non-numeric parameters
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kw, exc, pattern",
    [
        (dict(beta=-1.0), ValueError, r"beta must be >= 0"),
        (dict(beta=-1e-300), ValueError, r"beta must be >= 0"),
        (dict(omega=0.0), ValueError, r"omega must be > 0"),
        (dict(omega=-0.0), ValueError, r"omega must be > 0"),
        (dict(omega=-2.0), ValueError, r"omega must be > 0"),
        (dict(beta=NAN), ValueError, r"beta must be finite"),
        (dict(gamma=INF), ValueError, r"gamma must be finite"),
        (dict(omega=INF), ValueError, r"omega must be finite"),
        (dict(omega="x"), TypeError, r"omega must be a real number"),
        (dict(beta=None), TypeError, r"beta must be a real number"),
        (dict(gamma=[1.0, 2.0]), TypeError, r"gamma must be a real number"),
    ],
)
def test_pendulum_parameters(kw, exc, pattern):
    with pytest.raises(exc, match=pattern):
        mbm.Pendulum(**kw)


def test_negative_beta_callable_solve_ivp():
    # A plain callable of the pendulum form with β = −0.5: probing identifies it and refuses.
    def fun(t, y):
        return [y[1], 0.5 * y[1] - math.sin(y[0])]

    with pytest.raises(ValueError, match=r"beta = .*-0\.5.*beta must be >= 0"):
        solve_ivp(fun, (0.0, 1.0), [0.1, 0.0], method=mbm.MBM)


@pytest.mark.parametrize("w2", [0.0, -1.0])
def test_non_positive_omega_callable_solve_ivp(w2):
    def fun(t, y):
        return [y[1], -w2 * math.sin(y[0])]

    with pytest.raises(ValueError, match=r"omega\*\*2 must be > 0"):
        solve_ivp(fun, (0.0, 1.0), [0.1, 0.0], method=mbm.MBM)


def test_negative_beta_solve_batch():
    with pytest.raises(ValueError, match=r"beta must be >= 0"):
        mbm.solve_batch([-1.0], [0.0], [1.0], np.array([[0.1, 0.0]]), (0.0, 1.0), np.array([1.0]))


def test_non_positive_omega_solve_batch():
    with pytest.raises(ValueError, match=r"omega must be > 0"):
        mbm.solve_batch([0.1], [0.0], [0.0], np.array([[0.1, 0.0]]), (0.0, 1.0), np.array([1.0]))


@pytest.mark.parametrize("model", [None, (0.1, 0.3, 1.0), "pendulum"])
def test_model_not_a_pendulum(model):
    with pytest.raises(TypeError, match=r"model must be an? mbm\.Pendulum"):
        mbm.solve(model, (0.0, 1.0), [0.1, 0.0])
    with pytest.raises(TypeError, match=r"model must be an? mbm\.Pendulum"):
        mbm.reference(model, (0.0, 1.0), [0.1, 0.0])
    if model is None:
        return  # solve_ivp's model=None means "identify the model by probing fun"
    with pytest.raises(TypeError, match=r"model must be an? mbm\.Pendulum"):
        solve_ivp(MODEL, (0.0, 1.0), [0.1, 0.0], method=mbm.MBM, model=model)


@pytest.mark.parametrize("model", [None, (0.1, 0.3, 1.0)])
def test_model_not_a_pendulum_anchor(model):
    with pytest.raises(TypeError, match=r"model"):
        mbm.get_approximant("taylor").anchor(model, 0.1, 0.0)


# ---------------------------------------------------------------------------
# τ ≤ 0 (and other window options)
# ---------------------------------------------------------------------------


# One wording per check on every entry point: "> 0" for a value not positive,
# "finite" for nan and inf.
BAD_TAU = [(0.0, r"tau must be > 0, got 0\.0"), (-1.0, r"tau must be > 0, got -1\.0"),
           (-1e-300, r"tau must be > 0, got -1e-300"), (NAN, r"tau must be finite, got nan"),
           (INF, r"tau must be finite, got inf")]


@pytest.mark.parametrize("tau, pattern", BAD_TAU)
def test_bad_tau_solve_ivp(tau, pattern):
    with pytest.raises(ValueError, match=pattern):
        _ivp(tau=tau, approximant="taylor")


@pytest.mark.parametrize("tau, pattern", BAD_TAU)
def test_bad_tau_solve(tau, pattern):
    with pytest.raises(ValueError, match=pattern):
        mbm.solve(MODEL, (0.0, 1.0), [0.1, 0.0], tau=tau)


@pytest.mark.parametrize("tau", [0.0, -1.0])
def test_bad_tau_solve_batch(tau):
    with pytest.raises(ValueError, match=r"tau must be > 0"):
        mbm.solve_batch([0.1], [0.0], [1.0], np.array([[0.1, 0.0]]), (0.0, 1.0), np.array([1.0]), tau=tau)


@pytest.mark.parametrize("tau", ["x", object()])
def test_non_numeric_tau_solve_ivp(tau):
    with pytest.raises(TypeError, match=r"tau must be a real number"):
        _ivp(tau=tau, approximant="taylor")


@pytest.mark.parametrize("opt", ["rtol", "atol", "max_step", "first_step"])
@pytest.mark.parametrize("value", [0.0, -1.0, NAN])
def test_bad_tolerances_solve_ivp(opt, value):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(ValueError, match=rf"{opt} must be {'finite' if math.isnan(value) else '> 0'}, got"):
            _ivp(**{opt: value})


@pytest.mark.parametrize("opt", ["rtol", "atol"])
@pytest.mark.parametrize("value", [0.0, -1.0, NAN, INF])
def test_bad_tolerances_solve_and_reference(opt, value):
    with pytest.raises(ValueError, match=rf"{opt} must be"):
        mbm.solve(MODEL, (0.0, 1.0), [0.1, 0.0], **{opt: value})
    with pytest.raises(ValueError, match=rf"{opt} must be"):
        mbm.reference(MODEL, (0.0, 1.0), [0.1, 0.0], **{opt: value})


def test_reference_unknown_solver():
    with pytest.raises(ValueError, match=r"solver must be one of \('cvode', 'ida', 'dop853'\)"):
        mbm.reference(MODEL, (0.0, 1.0), [0.1, 0.0], solver="rk45")


# ---------------------------------------------------------------------------
# unknown approximant name
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["nope", "Taylor", "", None, 3])
def test_unknown_approximant(name):
    # The message lists every allowed name.
    pattern = r"approximant must be one of \[.*'taylor'.*\], got "
    with pytest.raises(ValueError, match=pattern):
        mbm.get_approximant(name)
    with pytest.raises(ValueError, match=pattern):
        mbm.solve(MODEL, (0.0, 1.0), [0.1, 0.0], approximant=name)
    with pytest.raises(ValueError, match=pattern):
        _ivp(approximant=name)


def test_solve_refuses_approximant_without_kernel():
    with pytest.raises(ValueError, match=r"approximant 'salas-damped' has no compiled kernel"):
        mbm.solve(mbm.Pendulum(beta=0.1), (0.0, 1.0), [0.1, 0.0], approximant="salas-damped", tau=0.1)


def test_solve_refuses_no_estimate_without_tau():
    with pytest.raises(ValueError, match=r"approximant 'salas-torque' has no error estimate: pass tau"):
        mbm.solve(MODEL, (0.0, 1.0), [0.1, 0.0], approximant="salas-torque")


# ---------------------------------------------------------------------------
# an approximant that cannot take the scene
# ---------------------------------------------------------------------------

# (name, model, state, what the message must say)
OUT_OF_SCENE = [
    ("belendez", mbm.Pendulum(beta=0.1), (0.1, 0.0), r"needs beta = 0 and gamma = 0"),
    ("harmonic", mbm.Pendulum(gamma=0.1), (0.1, 0.0), r"needs beta = 0 and gamma = 0"),
    ("salas-damped", mbm.Pendulum(beta=0.1, gamma=0.3), (0.1, 0.0), r"needs gamma == 0"),
    ("johannessen", mbm.Pendulum(beta=2.0), (0.1, 0.0), r"needs beta/2 < omega"),
    ("salas-damped-linear", mbm.Pendulum(beta=5.0, omega=2.0), (0.1, 0.0), r"needs beta/2 < omega"),
    ("salas-torque", mbm.Pendulum(gamma=0.99), (0.1, 0.0), r"needs \|gamma\|/omega\*\*2 <= 0\.981307"),
    ("salas-torque-trig", mbm.Pendulum(gamma=-4.0, omega=2.0), (0.1, 0.0), r"needs \|gamma\|/omega\*\*2"),
]


@pytest.mark.parametrize("name, model, state, pattern", OUT_OF_SCENE)
def test_scene_outside_domain_anchor(name, model, state, pattern):
    with pytest.raises(mbm.ApproximantDomainError, match=rf"approximant '{name}' .*{pattern}"):
        mbm.get_approximant(name).anchor(model, *state)


@pytest.mark.parametrize("name, model, state, pattern", OUT_OF_SCENE)
def test_scene_outside_domain_solve_ivp(name, model, state, pattern):
    with pytest.raises(mbm.ApproximantDomainError, match=pattern):
        solve_ivp(model, (0.0, 1.0), state, method=mbm.MBM, approximant=name, tau=0.1)


@pytest.mark.parametrize("name", ["belendez", "salas-torque"])
def test_scene_outside_domain_solve(name):
    model = mbm.Pendulum(beta=0.1, gamma=0.99)
    with pytest.raises(mbm.ApproximantDomainError, match=rf"approximant '{name}'"):
        mbm.solve(model, (0.0, 1.0), [0.1, 0.0], approximant=name, tau=0.1)


# Anchor states (not scenes) outside the domain: anchor raises; solve_ivp ends with
# status −1 and the same reason (solve_ivp's convention for a step that cannot be taken),
# never a NaN in the output.
OUT_OF_STATE = [
    ("salas-damped", mbm.Pendulum(beta=0.1), (0.0, 3.0), r"at or above the separatrix energy"),
    ("johannessen", mbm.Pendulum(beta=0.1), (math.pi, 0.0), r"at or above the separatrix energy"),
    ("harmonic", mbm.Pendulum(), (0.0, 2.5), r"needs an oscillation"),
    ("salas-torque", mbm.Pendulum(gamma=0.1), (3.0, 0.0), r"not on a bounded orbit"),
]


@pytest.mark.parametrize("name, model, state, pattern", OUT_OF_STATE)
def test_state_outside_domain(name, model, state, pattern):
    with pytest.raises(mbm.ApproximantDomainError, match=rf"approximant '{name}' cannot be anchored at .*{pattern}"):
        mbm.get_approximant(name).anchor(model, *state)
    sol = solve_ivp(model, (0.0, 1.0), state, method=mbm.MBM, approximant=name, tau=0.1)
    assert sol.status == -1
    assert f"approximant {name!r} cannot be anchored" in sol.message
    assert re.search(pattern, sol.message)
    assert np.all(np.isfinite(sol.y))


def test_state_outside_domain_solve():
    # The compiled path reports the same failure as a status, with the states it reached finite.
    res = mbm.solve(mbm.Pendulum(gamma=0.1), (0.0, 1.0), [3.0, 0.0], approximant="salas-torque", tau=0.1,
                    t_eval=[0.5, 1.0])
    assert not res.success
    assert "cannot be anchored" in res.message



# ---------------------------------------------------------------------------
# one input policy: real numbers only, one wording per check on every entry point
# ---------------------------------------------------------------------------

NOT_REAL = ["0.1", b"1", True, np.bool_(False), 1 + 0j, np.complex128(0.5), None, [0.1]]


@pytest.mark.parametrize("value", NOT_REAL)
@pytest.mark.parametrize("name", ["beta", "gamma", "omega", "drive_amplitude", "drive_frequency", "drive_phase"])
def test_pendulum_refuses_what_is_not_a_real_number(name, value):
    with pytest.raises(TypeError, match=rf"^{name} must be a real number, got "):
        mbm.Pendulum(**{name: value})


@pytest.mark.parametrize("value", [np.float32(0.25), np.float64(0.25), np.int64(2), 2, np.array(0.25)])
def test_pendulum_takes_numpy_real_scalars(value):
    assert mbm.Pendulum(beta=value).beta == float(value)


@pytest.mark.parametrize("value", ["0.1", True, 1j])
def test_options_refuse_what_is_not_a_real_number(value):
    for opt in ("rtol", "atol", "tau", "max_step"):
        with pytest.raises(TypeError, match=rf"^{opt} must be a real number, got "):
            mbm.solve(MODEL, (0.0, 1.0), [0.1, 0.0], **{opt: value})
    with pytest.raises(TypeError, match=r"t_span must be a pair of real numbers"):
        mbm.solve(MODEL, (0.0, value), [0.1, 0.0])
    with pytest.raises(TypeError, match=r"t_eval must be a real number or an array of real numbers"):
        mbm.solve(MODEL, (0.0, 1.0), [0.1, 0.0], t_eval=[value])


@pytest.mark.parametrize("value", ["0.1", [True], [1j], ["0.1", 0.2]])
def test_solve_batch_refuses_what_is_not_real_numbers(value):
    for name in ("beta", "gamma", "omega"):
        args = dict(beta=0.1, gamma=0.3, omega=1.0)
        args[name] = value
        with pytest.raises(TypeError, match=rf"^{name} must be a real number or an array of real numbers"):
            mbm.solve_batch(args["beta"], args["gamma"], args["omega"], [0.1, 0.0], (0.0, 1.0), [1.0])


# The same check, worded once: (arguments of Pendulum, the message), and each array entry
# point names the scene.
ONE_WORDING = [
    ("omega", -1.0, "omega must be > 0, got -1.0"),
    ("omega", 0.0, "omega must be > 0, got 0.0"),
    ("beta", -0.5, "beta must be >= 0 (damping), got -0.5"),
    ("gamma", INF, "gamma must be finite, got inf"),
    ("drive_frequency", -1.0, "drive_frequency must be >= 0 (an angular frequency Omega), got -1.0"),
]


@pytest.mark.parametrize("name, value, message", ONE_WORDING)
def test_one_wording_per_check(name, value, message):
    with pytest.raises(ValueError) as e:
        mbm.Pendulum(**{name: value})
    assert str(e.value) == message
    args = dict(beta=0.1, gamma=0.3, omega=1.0)
    if name in args:
        args[name] = [0.2, value]
        with pytest.raises(ValueError) as e:
            mbm.solve_batch(args["beta"], args["gamma"], args["omega"], [0.1, 0.0], (0.0, 1.0), [1.0])
        prefix, got = message.split(", got ")
        assert str(e.value) == f"{prefix}, got {name}[1] = {got}"


def test_a_drive_needs_a_positive_frequency():
    message = "drive_frequency must be > 0 with a drive (drive_amplitude != 0), got 0.0"
    with pytest.raises(ValueError) as e:
        mbm.Pendulum(beta=0.5, drive_amplitude=1.0, drive_frequency=0.0)
    assert str(e.value) == message
    with pytest.raises(ValueError) as e:
        mbm.iv_curve(0.5, [0.1], drive_amplitude=1.0, drive_frequency=0.0)
    assert str(e.value) == message
    with pytest.raises(ValueError) as e:
        mbm.solve_batch(0.5, 0.1, 1.0, [0.0, 0.0], (0.0, 1.0), [1.0], drive_amplitude=[0.0, 1.0],
                        drive_frequency=0.0)
    assert str(e.value) == "drive_frequency must be > 0 with a drive (drive_amplitude != 0), got drive_frequency[1] = 0.0"
    # no drive: the frequency is free (A = 0 is the autonomous equation)
    assert not mbm.Pendulum(beta=0.5, drive_amplitude=0.0, drive_frequency=0.0).driven


@pytest.mark.parametrize("kw, exc, message", [
    (dict(beta="0.1"), TypeError, "beta must be a real number, got '0.1'"),
    (dict(omega=-1.0), ValueError, "omega must be > 0, got -1.0"),
    (dict(gamma=["0.1"]), TypeError, "gamma must be a real number or an array of real numbers, got ['0.1']"),
    (dict(gamma=[0.1, math.nan]), ValueError, "gamma must be finite, got gamma[1] = nan"),
    (dict(beta=0.0), ValueError, "beta must be > 0 (damping: an I–V curve needs a damped junction), got 0.0"),
])
def test_iv_curve_same_wording(kw, exc, message):
    args = dict(beta=0.5, gamma=[0.1])
    args.update(kw)
    with pytest.raises(exc) as e:
        mbm.iv_curve(args.pop("beta"), args.pop("gamma"), **args)
    assert str(e.value) == message


# ---------------------------------------------------------------------------
# a run far past max_windows is refused before it runs, naming the cause
# ---------------------------------------------------------------------------

HUGE = mbm.Pendulum(beta=0.1, gamma=1e12)


def test_huge_torque_refused_before_running():
    pattern = r"^gamma=1000000000000\.0 .*would take more than .* windows, .* times max_windows=10000000"
    with pytest.raises(ValueError, match=pattern):
        mbm.solve(HUGE, (0.0, 10.0), [0.0, 0.0])
    with pytest.raises(ValueError, match=pattern):
        mbm.Integrator(HUGE).solve((0.0, 10.0), [0.0, 0.0])
    with pytest.raises(ValueError, match=pattern):
        solve_ivp(HUGE, (0.0, 10.0), [0.0, 0.0], method=mbm.MBM)
    with pytest.raises(ValueError, match=r"^scene 1: gamma=1000000000000\.0 "):
        mbm.solve_batch([0.1, 0.1], [0.3, 1e12], 1.0, [0.0, 0.0], (0.0, 10.0), [10.0])
    with pytest.raises(ValueError, match=r"gamma=1000000000000\.0 "):
        mbm.sweep(beta=0.1, gamma=[0.3, 1e12], t_span=(0.0, 10.0), reduce="final_state")


def test_tiny_fixed_window_refused_naming_tau():
    with pytest.raises(ValueError, match=r"^tau=1e-09 over t_span \(0\.0, 1000\.0\) .* would take more than"):
        mbm.solve(mbm.Pendulum(0.1, 3.0), (0.0, 1000.0), [0.0, 0.0], tau=1e-9, approximant="taylor")


@pytest.mark.parametrize("params, span, kw", [
    ((0.1, 1e6), 10.0, {}),          # 2.9e6 windows: runs (a runaway, but within max_windows)
    ((1.0, 1e4), 1000.0, {}),        # 1.3e6 windows
    ((0.0, 1e8), 100.0, {}),         # would stop at max_windows (2500 times over): not predicted, runs
    ((0.1, 0.3), 1e3, dict(tau=1e-9)),  # locked: the regime takes over, not predicted
    ((0.1, 1e12), 10.0, dict(max_windows=10**12)),  # the margin is over max_windows
    ((0.1, 1e12), (10.0, 0.0), {}),  # backward runs are not predicted
    ((0.5, 1e12, 1.0, 1.0, 1.0), 10.0, {}),  # nor driven ones
])
def test_budget_does_not_refuse_what_it_cannot_bound(params, span, kw):
    from mbm.validate import DEFAULT_MAX_WINDOWS, check_window_budget
    m = mbm.Pendulum(*params)
    t0, t1 = (0.0, span) if np.ndim(span) == 0 else span
    check_window_budget(m.beta, m.gamma, m.omega, m.drive_amplitude, t0, t1, 0.0, kw.get("tau"), max_step=math.inf,
                        max_windows=kw.get("max_windows", DEFAULT_MAX_WINDOWS))


def test_budget_allows_an_ordinary_runaway():
    r = mbm.solve(mbm.Pendulum(0.0, 1e4), (0.0, 10.0), [0.0, 0.0], t_eval=[10.0])
    assert r.success and r.n_windows > 10**4


@pytest.mark.parametrize("value", [np.float64(-0.1) * 1.0000000000000003, np.float32(-0.5), -2])
def test_a_refused_number_is_printed_as_a_plain_float(value):
    # numpy scalars in a message read as plain floats, not np.float64(...)
    with pytest.raises(ValueError, match=r"beta must be >= 0 \(damping\), got -") as info:
        mbm.Pendulum(beta=value)
    assert "np." not in str(info.value) and str(info.value).endswith(repr(float(value)))
    with pytest.raises(ValueError, match=r"omega must be > 0, got ") as info:
        mbm.Pendulum(omega=value)
    assert "np." not in str(info.value) and str(info.value).endswith(repr(float(value)))
    with pytest.raises(ValueError, match="must be finite, got nan"):
        mbm.Pendulum(beta=np.float64("nan"))
