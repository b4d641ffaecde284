"""`mbm.frontends.dense`, the compiled dense output of MBM's steps: the values of
`mbm.core.stored.evaluate_windows` bit for bit, for every kind, regime window and order of
times."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm.frontends import dense
from mbm.core import stored
from mbm.scenes import get as scene


def _bits(a):
    return np.ascontiguousarray(a, dtype=np.float64).view(np.int64)


def _store(model, t_span, y0, **kw):
    """A whole run's windows (windows_per_step=None) and its kind."""
    solver = mbm.MBM(model, t_span[0], y0, t_span[1], model=model, windows_per_step=None, **kw)
    solver.step()
    assert solver.status == "finished"
    starts, start_theta, coefs, n = solver._windows
    return solver, solver._kind[0], starts, start_theta, coefs, n


def _times(starts, n, rng):
    t0, t1 = starts[0], starts[n]
    lo, hi = min(t0, t1), max(t0, t1)
    return [
        np.linspace(t0, t1, 201),  # in order, as solve_ivp's t_eval
        np.sort(rng.uniform(lo, hi, 300)),
        rng.uniform(lo - 1.0, hi + 1.0, 300),  # any order, some outside the run
        starts.copy(),  # every window boundary
        starts[::-1].copy(),  # against the direction
        np.array([math.nan, t0, t1, math.inf, -math.inf, t0, t0]),
        np.empty(0),
    ]


CASES = [
    ("P1", dict(rtol=1e-3, atol=1e-3)),  # ends in a locked window
    ("P1", dict(rtol=1e-10, atol=1e-10)),
    ("P2", dict(approximant="taylor", tau=0.5)),
    ("P3", dict(approximant="split4", tau=0.25)),
    ("P2", dict(approximant="salas-torque", tau=0.3)),
    ("P5", dict(rtol=1e-6, atol=1e-6)),  # wound far (winding counts), then a running cycle
    ("P5", dict(approximant="split4", rtol=1e-6, atol=1e-6)),
    ("P6", dict(rtol=1e-6, atol=1e-6)),  # the exact flow, one window
    ("P6", dict(approximant="belendez", tau=0.7)),
]


@pytest.mark.parametrize("name,kw", CASES)
def test_same_bits_as_loop_evaluate_windows(name, kw):
    sc = scene(name)
    rng = np.random.default_rng(7)
    solver, kind, starts, start_theta, coefs, n = _store(sc.model, sc.t_span, sc.y0_array, **kw)
    contiguous = np.ascontiguousarray(start_theta)
    for t in _times(starts, n, rng):
        th, v = np.empty(t.size), np.empty(t.size)
        stored.evaluate_windows(kind, starts, contiguous, coefs, n, 1.0, t, out_theta=th, out_v=v)
        for theta_starts in (start_theta, contiguous):  # a strided view, as MBM passes, or not
            out = np.empty((2, t.size))
            dense.evaluate_windows_into(kind, starts, theta_starts, coefs, n, 1.0, t, out)
            np.testing.assert_array_equal(_bits(out[0]), _bits(th))
            np.testing.assert_array_equal(_bits(out[1]), _bits(v))
        for j in range(0, t.size, max(1, t.size // 25)):
            y = dense.evaluate_windows_at(kind, starts, start_theta, coefs, n, 1.0, float(t[j]))
            np.testing.assert_array_equal(_bits(y), _bits([th[j], v[j]]))
    if name == "P5" and "approximant" not in kw:
        assert solver.regime == "running"
    if name == "P1" and kw["rtol"] == 1e-3:
        assert solver.regime == "locked"


@pytest.mark.parametrize("kw", [dict(rtol=1e-8, atol=1e-8), dict(approximant="split4", tau=0.2),
                                dict(approximant="taylor8", tau=0.05)])
def test_same_bits_backwards(kw):
    model = mbm.Pendulum(0.1, 0.3)
    solver, kind, starts, start_theta, coefs, n = _store(model, (40.0, 0.0), np.array([2.0, -1.5]), **kw)
    t = np.concatenate((np.linspace(40.0, 0.0, 301), np.random.default_rng(3).uniform(-1.0, 41.0, 200)))
    th, v = np.empty(t.size), np.empty(t.size)
    stored.evaluate_windows(kind, starts, np.ascontiguousarray(start_theta), coefs, n, -1.0, t, out_theta=th, out_v=v)
    out = np.empty((2, t.size))
    dense.evaluate_windows_into(kind, starts, start_theta, coefs, n, -1.0, t, out)
    np.testing.assert_array_equal(_bits(out), _bits(np.vstack((th, v))))


def test_driven_windows_same_bits():
    model = mbm.Pendulum(0.3, 0.2, 1.0, drive_amplitude=0.8, drive_frequency=0.7, drive_phase=0.3)
    solver, kind, starts, start_theta, coefs, n = _store(model, (0.0, 60.0), np.array([0.1, 0.0]),
                                                         rtol=1e-8, atol=1e-8)
    t = np.linspace(0.0, 60.0, 1001)
    th, v = np.empty(t.size), np.empty(t.size)
    stored.evaluate_windows(kind, starts, np.ascontiguousarray(start_theta), coefs, n, 1.0, t, out_theta=th, out_v=v)
    out = np.empty((2, t.size))
    dense.evaluate_windows_into(kind, starts, start_theta, coefs, n, 1.0, t, out)
    np.testing.assert_array_equal(_bits(out), _bits(np.vstack((th, v))))


def test_dense_output_contract_shapes_and_dtypes():
    # sol(scalar) -> shape (2,), sol(array) -> (2, m), sol(list of ints) converted,
    # sol(2-D) refused as by scipy's DenseOutput.
    sc = scene("P2")
    sol = solve_ivp(sc.model, sc.t_span, sc.y0_array, method=mbm.MBM, dense_output=True, rtol=1e-6,
                    atol=1e-6, windows_per_step=None).sol
    assert sol(3.0).shape == (2,) and sol(np.float64(3.0)).dtype == np.float64
    assert sol(np.array([1.0, 2.0])).shape == (2, 2)
    np.testing.assert_array_equal(sol([1, 2, 3]), sol(np.array([1.0, 2.0, 3.0])))
    assert sol.interpolants[0](np.empty(0)).shape == (2, 0)
    np.testing.assert_array_equal(sol(np.linspace(0, 80, 11)[::-2]), sol(np.linspace(0, 80, 11)[::-2].copy()))
    with pytest.raises(ValueError):
        sol.interpolants[0](np.zeros((2, 2)))
