"""The exact flow read from a table of Taylor expansions (mbm.special.pendulum_flow_table).

Against the flow kernel (mbm.special.pendulum_flow.flow_eval_kernel) over libration and
rotation scenes from m = 1e-12 to m = 1e4 (next to the separatrix on both sides), for
|t| <= 100 and |t| up to 1e6: within a few ulps of the motion's scale; against the
60-digit mpmath references of tests/approximants/test_belendez2007.py at that file's own
tolerances; the anchor bit for bit at t = 0; the per-time kernel the table's bits; and through
mbm.solve's outputs.
"""

import math

import numba
import numpy as np
import pytest

import mbm
from mbm.special.pendulum_flow import flow_eval_kernel, flow_setup_kernel
from mbm.special.pendulum_flow_table import (
    FLOW_TABLE_OUTPUTS_PER_ANCHOR,
    flow_table_eval_kernel,
    flow_table_eval_range,
    flow_table_half,
    flow_table_kernel,
    flow_table_point_kernel,
)

import belendez2007_mpmath as refmod  # noqa: E402  tests/data, on pytest's pythonpath

# Table against flow kernel, in ulps of the motion's scale: θ in ulps of max(|θ|, max |θ|
# over |t| <= 100), θ' in ulps of max |θ'| (measured 6 and 10 over 1563 scenes).
THETA_ULPS = 8
V_ULPS = 16
# The mpmath tolerances of tests/approximants/test_belendez2007.py (not loosened).
GOAL_ATOL = 1e-12
LONG_ATOL = 1e-9


@numba.njit(cache=True)
def _both(th0, v0, om, ts, out):
    f = flow_setup_kernel(th0, v0, om)
    half = flow_table_half(f)
    table = flow_table_kernel(f, half)
    for i in range(ts.size):
        out[0, i], out[1, i] = flow_eval_kernel(f, ts[i])
        out[2, i], out[3, i] = flow_table_eval_kernel(f, table, ts[i])
        if flow_table_point_kernel(f, ts[i]) != (out[2, i], out[3, i]):
            return -1
    return half


def _run(th0, v0, om, ts):
    out = np.empty((4, ts.size))
    half = _both(th0, v0, om, ts, out)
    return half, out


def _scenes():
    for om in (1.0, 2.7):
        for m in (1e-12, 1e-8, 1e-4, 0.23, 0.9, 1 - 1e-4, 1 - 1e-10, 1 - 4e-15,
                  1 + 1e-14, 1 + 1e-10, 1 + 1e-4, 1.5, 10.0, 1e4):
            if m < 1:
                yield om, 2 * math.asin(math.sqrt(m)), 0.0  # turning point
            yield om, 0.0, 2 * om * math.sqrt(m)  # bottom
            s2 = min(0.9 * m, 1.0)  # off both, winding θ₀ ≈ 4π, negative rate
            yield om, 4 * math.pi - 2 * math.asin(math.sqrt(s2)), -2 * om * math.sqrt(m - s2)


_N = 2001
_TS = np.concatenate([np.linspace(-100.0, 100.0, _N), np.random.default_rng(5).uniform(-1e6, 1e6, _N)])


@pytest.mark.parametrize("om, th0, v0", list(_scenes()))
def test_table_within_ulps_of_flow_kernel(om, th0, v0):
    half, (th_f, v_f, th_t, v_t) = _run(th0, v0, om, _TS)
    assert half > 0  # (−1: the per-time kernel differed from the table)
    th_scale = np.maximum(np.abs(th_f), np.abs(th_f[:_N]).max())
    assert np.all(np.abs(th_t - th_f) <= THETA_ULPS * np.spacing(th_scale)), np.max(
        np.abs(th_t - th_f) / np.spacing(th_scale))
    v_scale = np.abs(v_f).max()
    assert np.all(np.abs(v_t - v_f) <= V_ULPS * np.spacing(v_scale)), np.max(np.abs(v_t - v_f) / np.spacing(v_scale))


@pytest.mark.parametrize("om, th0, v0", [(1.0, 1.0, 0.0), (2.7, 0.0, 2 * 2.7 * 1.2), (1.0, math.pi, 0.0),
                                         (1.0, 1e3 * math.pi, -1e-3), (1.0, 0.0, 2.0 - 1e-12)])
def test_anchor_bit_for_bit_at_zero(om, th0, v0):
    _, out = _run(th0, v0, om, np.array([0.0, -0.0]))
    assert np.all(out[2] == th0) and np.all(out[3] == v0)


def _table_errors(ref, prefix, cases_key, t_key):
    for i, case in enumerate(ref[cases_key]):
        _, out = _run(case[0], case[1], case[2], np.ascontiguousarray(ref[t_key]))
        yield (tuple(case), np.abs(out[2] - ref[prefix + "_theta"][i]), np.abs(out[3] - ref[prefix + "_v"][i]),
               ref[prefix + "_theta"][i])


@pytest.fixture(scope="module")
def ref():
    with np.load(refmod.REFERENCE_FILE) as data:
        return dict(data)


def test_table_against_mpmath(ref):
    """The goal cases and the other states of test_belendez2007 at its tolerances (t <= 100)."""
    for case, eth, ev, _ in _table_errors(ref, "goal", "goal_cases", "goal_t"):
        assert eth.max() <= GOAL_ATOL and ev.max() <= GOAL_ATOL * max(1.0, case[2]), case
    for case, eth, ev, _ in _table_errors(ref, "extra", "extra_cases", "extra_t"):
        if flow_setup_kernel(*case).regime > 1.0:  # no table on the separatrix / at rest
            continue
        assert eth.max() <= GOAL_ATOL + 4 * np.spacing(abs(case[0]) + 50.0), case
        assert ev.max() <= GOAL_ATOL * max(1.0, case[2]), case


def test_table_long_horizon(ref):
    """t ≈ 1e6: the double-double argument and its reduction are the flow kernel's."""
    for case, eth, ev, th_ref in _table_errors(ref, "long", "goal_cases", "long_t"):
        assert eth.max() <= LONG_ATOL and ev.max() <= LONG_ATOL, case
        assert np.all(eth <= 1e-13 + 2 * np.spacing(np.abs(th_ref))), case
        assert np.all(ev <= 1e-13 * max(1.0, case[2])), case


@numba.njit(cache=True)
def _range(th0, v0, om, t0, ts, j, j2, out):
    flow_table_eval_range(flow_setup_kernel(th0, v0, om), t0, ts, j, j2, out[0], out[1])


@numba.njit(cache=True)
def _points(th0, v0, om, t0, ts, out):
    f = flow_setup_kernel(th0, v0, om)
    for i in range(ts.size):
        out[0, i], out[1, i] = flow_table_point_kernel(f, ts[i] - t0)


@pytest.mark.parametrize("th0, v0, om", [(1.0, 0.3, 1.3), (0.5, -2.9, 1.1), (math.pi, 0.0, 1.0)])
def test_range_is_the_point_kernel(th0, v0, om):
    """A block below FLOW_TABLE_OUTPUTS_PER_ANCHOR outputs per anchor (no table) and one
    above (a table): the per-time kernel's bits, and nothing outside the block written."""
    f = flow_setup_kernel(th0, v0, om)
    for n in (FLOW_TABLE_OUTPUTS_PER_ANCHOR * (flow_table_half(f) + 1) - 1, 20_000):
        ts = np.linspace(-50.0, 1e4, n)
        out = np.full((2, n + 2), np.nan)
        _range(th0, v0, om, 0.25, ts, 0, n, out)
        ref = np.empty((2, n))
        _points(th0, v0, om, 0.25, ts, ref)
        assert np.array_equal(out[:, :n], ref)
        assert np.all(np.isnan(out[:, n:]))


@pytest.mark.parametrize("y0", [(1.0, 0.0), (0.0, 2.5), (-2.0, -2.1)])
def test_solve_outputs(y0):
    """mbm.solve's exact flow (one window) with many outputs: solve_ivp(method=mbm.MBM)'s
    bits, within the bounds of the flow kernel, the anchor at t = 0."""
    from scipy.integrate import solve_ivp

    model = mbm.Pendulum(0.0, 0.0, 1.0)
    t_eval = np.linspace(0.0, 2000.0, 20_001)
    r = mbm.solve(model, (0.0, 2000.0), y0, rtol=1e-9, atol=1e-9, t_eval=t_eval)
    assert r.success and r.n_windows == 1
    s = solve_ivp(model, (0.0, 2000.0), y0, method=mbm.MBM, rtol=1e-9, atol=1e-9, t_eval=t_eval)
    np.testing.assert_array_equal(r.y, s.y)
    flow = mbm.pendulum_flow(model, y0, t_eval)
    assert r.y[0, 0] == y0[0] and r.y[1, 0] == y0[1]
    th_scale = np.maximum(np.abs(flow[0]), np.abs(flow[0]).max())
    assert np.all(np.abs(r.y[0] - flow[0]) <= THETA_ULPS * np.spacing(th_scale))
    assert np.all(np.abs(r.y[1] - flow[1]) <= V_ULPS * np.spacing(np.abs(flow[1]).max()))
