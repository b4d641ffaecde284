"""solve_batch in lockstep lanes (mbm.core.lanes._lanes) and its across-scene kernels.

The lanes' anchor (taylor24_lanes) and window-end Horner (horner24_lanes) apply the
one-scene kernels' operations lane-wise, so they must give those kernels' bits; and a
scene run in a lane, handed to the one-scene loop at a regime switch, a failure, its
window limit or the interrupt flag, must give the record and outputs of that loop alone.
"""

import math

import numpy as np
import pytest

import mbm
from mbm.core import lanes, loop, record, window
from mbm.core.controller import CONTROLLER_ADAPTIVE, CONTROLLER_FIXED
from mbm.status import STATUS_MAX_WINDOWS, STATUS_OK
from mbm.approximants.taylor import HEADER, taylor_eval_kernel
from mbm.approximants.taylor_simd import LANES, SIMD_ORDER, horner24_lanes, taylor24_lanes, taylor24_series

NT = SIMD_ORDER + 3


def _lane_inputs(rng):
    b = rng.uniform(0.0, 2.0, LANES)
    g = rng.uniform(-2.0, 2.0, LANES)
    w = rng.uniform(0.2, 3.0, LANES)
    th = rng.uniform(-20.0, 20.0, LANES)
    v = rng.uniform(-6.0, 6.0, LANES)
    ins = np.ascontiguousarray([b, g, w * w, [math.sin(x) for x in th], [math.cos(x) for x in th], th, v])
    return b, g, w, th, v, ins


@pytest.mark.parametrize("seed", range(4))
def test_lane_anchor_is_the_one_scene_kernel_bit_for_bit(seed):
    rng = np.random.default_rng(seed)
    for _ in range(25):
        b, g, w, th, v, ins = _lane_inputs(rng)
        coefs = np.zeros((LANES, HEADER + NT))
        soa = np.zeros((NT, LANES))
        taylor24_lanes(ins, coefs, soa)
        np.testing.assert_array_equal(soa.T, coefs[:, HEADER:])
        for i in range(LANES):
            ref = np.zeros(HEADER + NT)
            taylor24_series(b[i], g[i], w[i], th[i], v[i], ref)
            np.testing.assert_array_equal(coefs[i, HEADER:], ref[HEADER:])


def test_lane_horner_is_taylor_eval_kernel_bit_for_bit():
    rng = np.random.default_rng(7)
    for _ in range(25):
        b, g, w, th, v, ins = _lane_inputs(rng)
        coefs = np.zeros((LANES, HEADER + NT))
        soa = np.zeros((NT, LANES))
        taylor24_lanes(ins, coefs, soa)
        coefs[:, 1] = SIMD_ORDER
        s = rng.uniform(-0.5, 0.5, LANES)
        s[0] = 0.0
        out = np.zeros((2, LANES))
        horner24_lanes(soa, s, out)
        for i in range(LANES):
            th_i, v_i = taylor_eval_kernel(coefs[i], s[i])
            assert out[0, i] == th_i and out[1, i] == v_i
        assert out[0, 0] == th[0]  # the anchor exactly at s = 0


def test_lane_kernels_check_their_shapes():
    with pytest.raises(ValueError, match="taylor24_lanes"):
        taylor24_lanes(np.zeros((7, LANES)), np.zeros((LANES, HEADER + NT)), np.zeros((NT, LANES - 1)))
    with pytest.raises(ValueError, match="horner24_lanes"):
        horner24_lanes(np.zeros((NT, LANES)), np.zeros(LANES - 1), np.zeros((2, LANES)))


def _scenes(n, seed):
    # Every regime the lanes meet or hand over: locked, running (bistable band
    # included), damped untorqued, torqued from far away, and a few that are never
    # lane scenes (β = 0, librations and rotations).
    rng = np.random.default_rng(seed)
    b = rng.uniform(0.0, 1.0, n)
    b[: n // 10] = 0.0
    g = rng.uniform(-2.0, 2.0, n)
    w = rng.uniform(0.5, 2.0, n)
    y0 = np.c_[rng.uniform(-3.0, 3.0, n), rng.uniform(-3.0, 3.0, n)]
    return b, g, w, y0


def _assert_batch_is_each_solve(b, g, w, y0, span, te, **kw):
    r = mbm.solve_batch(b, g, w, y0, span, te, **kw)
    for i in range(b.size):
        s = mbm.solve(mbm.Pendulum(b[i], g[i], w[i]), span, y0[i], t_eval=te, **kw)
        # A failed scene: solve returns the outputs reached, solve_batch NaN after them.
        m = s.y.shape[1]
        np.testing.assert_array_equal(r.y[i][:, :m], s.y)
        assert np.all(np.isnan(r.y[i][:, m:]))
        assert r.n_windows[i] == s.n_windows and r.status[i] == s.status and r.regime[i] == s.regime
        np.testing.assert_array_equal(r.t_regime[i], s.t_regime)
        if kw.get("wrap"):
            np.testing.assert_array_equal(r.winding[i][:m], s.winding)
    return r


@pytest.mark.parametrize("tol,wrap", [(1e-6, False), (1e-10, True)])
def test_lane_batch_is_each_scene_alone(tol, wrap):
    # More scenes than one lane group (lanes.LANE_GROUP), so groups refill their lanes.
    b, g, w, y0 = _scenes(300, 11)
    te = np.linspace(0.0, 150.0, 16)
    r = _assert_batch_is_each_solve(b, g, w, y0, (0.0, 150.0), te, rtol=tol, atol=tol, wrap=wrap)
    assert {"locked", "running"} <= set(r.regime)


def test_lane_batch_backwards_and_window_limit():
    b, g, w, y0 = _scenes(40, 12)
    te = np.linspace(0.0, -30.0, 7)
    # Backwards a damped motion gains energy exponentially: most of these scenes reach
    # the window limit, which is set so that each does so in ~1e5 windows (the default
    # 1e7 made this test ~100 s) and their statuses and outputs are compared too.
    r = _assert_batch_is_each_solve(b, g, w, y0, (0.0, -30.0), te, rtol=1e-8, atol=1e-8, max_windows=10**5)
    assert np.any(r.status == STATUS_MAX_WINDOWS) and np.any(r.status == STATUS_OK)
    # A window limit reached inside the lanes: the status and the outputs up to it.
    te = np.linspace(0.0, 50.0, 6)
    r = _assert_batch_is_each_solve(b, g, w, y0, (0.0, 50.0), te, rtol=1e-8, atol=1e-8, max_windows=30)
    assert np.any(r.status == STATUS_MAX_WINDOWS)


def test_lane_eligibility():
    p = np.zeros(4, dtype=record.RUN)
    f = record.flat(p)
    f["kind"], f["karg"], f["controller"] = window.KIND_TAYLOR, SIMD_ORDER, CONTROLLER_ADAPTIVE
    f["beta"], f["max_dtheta"], f["regimes"] = 0.1, np.inf, 1
    f["karg"][1] = 12  # another degree: the one-scene loop
    f["drive_amp"][2] = 0.5  # driven: the one-scene loop
    f["regimes"][3] = 0  # regime switching off (RS_PLAIN): the one-scene loop

    import numba

    @numba.njit
    def eligible(p):
        return [lanes.lane_eligible(p[i]) for i in range(p.size)]

    assert eligible(p) == [True, False, False, False] == list(lanes.eligible_rows(p))


def test_batch_compiles_only_the_kinds_and_sets_its_scenes_reach():
    # an undriven damped auto batch: Taylor in RS_DAMPED (and RS_CYCLE it may reach) by
    # the lanes, the exact flow for β = γ = 0 in RS_PLAIN by the loop; nothing driven,
    # conservative or split is compiled for it
    b = mbm.solve_batch([0.1, 0.0], [0.3, 0.0], 1.0, [0.5, 0.0], (0.0, 5.0), [5.0])
    assert list(b.status) == [0, 0]
    p = np.zeros(2, dtype=record.RUN)
    f = record.flat(p)
    f["kind"] = [window.KIND_TAYLOR, window.KIND_EXACT]
    f["karg"] = [SIMD_ORDER, 0]
    f["controller"] = [CONTROLLER_ADAPTIVE, CONTROLLER_FIXED]
    f["beta"], f["regimes"], f["max_dtheta"] = [0.1, 0.0], 1, np.inf
    taylor, exact, salas, split = 2, 1, 0, 0  # taylor 2: the default degree's entries alone
    plain, damped, conservative, driven, cycle, strobe = 1, 1, 0, 0, 1, 0
    assert lanes.batch_flags(p) == (taylor, exact, salas, split, plain, damped, conservative, driven, cycle, strobe)
    q = np.concatenate([p[:1], p[:1]])
    record.flat(q)["karg"][1] = 16
    assert lanes.batch_flags(q[1:])[0] == 1 and lanes.batch_flags(q)[0] == 3  # general entries, both
    assert list(lanes.eligible_rows(p)) == [True, False]
    # the loop's entry for the exact row: that kind and set only
    assert lanes.batch_flags(p[1:]) == (0, 1, 0, 0, 1, 0, 0, 0, 0, 0) and lanes.batch_flags(p[1:]) in lanes.ROWS_ENTRIES
    f["drive_amp"][0] = 0.5  # driven: its strobe set too, the damped one no longer
    assert lanes.batch_flags(p)[4:] == (1, 0, 0, 1, 0, 1)



def test_a_batch_of_default_and_other_degrees_runs_each_through_its_own_entries():
    # the default degree beside taylor16, outside the lanes (regimes off): flags 3, each
    # record through the entries of its degree, its answers those of loop.run alone
    def record_of(name):
        ig = mbm.Integrator(mbm.Pendulum(0.1, 0.3), approximant=name, rtol=1e-8, atol=1e-8)
        r = np.array(ig._words.copy().view(record.RUN))
        f = record.flat(r)
        f["t"], f["theta"], f["v"], f["t_bound"] = 0.0, 0.5, 0.0, 20.0
        f["call_windows"], f["regimes"] = 0, 0
        return r

    p = np.concatenate([record_of("taylor"), record_of("taylor16")])
    assert lanes.batch_flags(p)[0] == 3 and not lanes.eligible_rows(p).any()
    te = np.linspace(0.0, 20.0, 11)
    none = (np.empty(0), np.empty((0, 2)), np.empty((0, 0)), np.zeros(1, np.int64))
    want = []
    for i in range(2):
        out = np.empty((2, te.size))
        q = p[i:i + 1].copy()
        loop.run(q, te, out, *none)
        assert record.flat(q)["status"][0] == STATUS_OK
        want.append(out)
    out = np.empty((2, 2, te.size))
    lanes.run_batch(p, te, out, np.arange(2), np.zeros(1, np.int64))
    assert list(record.flat(p)["status"]) == [STATUS_OK] * 2
    np.testing.assert_array_equal(out[0], want[0])
    np.testing.assert_array_equal(out[1], want[1])
