"""Outputs of the phase-locked regime from the stored drive period (S6): the same bits
as the period re-run from its anchor at each time (``_strobe_eval_taylor``).

The stored period (``_strobe_windows_taylor``) is taken once; its lookup
(``_strobe_lookup_taylor``) and its block of sorted times (``_strobe_range_taylor``)
are checked against the re-run on sorted, backward, unsorted and repeated times, at
period boundaries, at the anchor and at t ~ 1e6, and the loop's, the dense output's
and the stored windows' values against it on a real run.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm import regimes, status
from mbm.core import controller, loop, record, stored
from mbm.core.window import KIND_TAYLOR, theta_of, wrap
from mbm.regimes.stored_block import STORED_BLOCK
from mbm.regimes.strobe_windows import (
    _strobe_eval_taylor,
    _strobe_lookup_taylor,
    _strobe_range_taylor,
    _strobe_windows_taylor,
)

# The n = 1 Shapiro step (tests/regimes/test_strobe.py, STEP) and the half step
# (tests/regimes/test_subharmonic.py): (β, γ, ω, A, Ω, φ).
STEP = (0.2, 0.2, 1.0, 2.0, 1.0, 0.0)
Y0 = (0.0, 0.0)
TOL = 1e-10


def _phase_locked_coef(params, T, tol):
    """The run's phase-locked window (its coefficient row) and the switch time, from
    the loop by hand with a window store."""
    beta, gamma, omega, amp, freq, phase = params
    ap, kind, karg = mbm.frontends.solve.compiled(mbm.get_approximant("taylor"))
    p = record.new_run(record.RunModel(beta, gamma, omega, amp, freq, phase), record.RunState(0.0, Y0[0], Y0[1], T),
                       record.RunControl(kind, karg, controller.CONTROLLER_ADAPTIVE, -1.0, np.inf, np.inf, tol, tol,
                                         int(ap.error_order)), 10**8)
    cap = 20000
    win_t, win_y, win_coef = np.empty(cap + 1), np.empty((cap + 1, 2)), np.zeros((cap, regimes.STROBE_WIDTH))
    n = loop.run(p, np.empty(0), np.empty((2, 0)), win_t, win_y, win_coef, np.zeros(1, np.int64))
    rec = record.flat(p)[0]
    assert rec["status"] == status.STATUS_OK and n < cap
    rows = np.flatnonzero(win_coef[:n, 0] == regimes.STROBE_TAG)
    assert rows.size > 0
    return win_coef[rows[0]].copy(), win_t[rows[0]]


@pytest.fixture(scope="module")
def step_coef():
    return _phase_locked_coef(STEP, 2000.0, TOL)


def _reference(c, t):
    """θ (2πk + φ), θ' and (k, φ) wrapped, by the re-run from the anchor at each time."""
    th, v, w, ph = (np.empty(t.size) for _ in range(4))
    for j, tj in enumerate(t):
        a, b, k = _strobe_eval_taylor(c, tj)
        th[j], v[j] = theta_of(k, a), b
        w[j], ph[j] = wrap(k, a)
    return th, v, w, ph


def _times(c, t_a):
    """Sorted times after the anchor, with the anchor, period boundaries (t_a + nP,
    each rounding of it and its neighbours), repeats and a horizon of 1e6."""
    p_hi, p_lo = regimes.strobe_period(c[regimes.STR_FREQ], c[regimes.STR_Q])
    bounds = []
    for n in (0, 1, 2, 3, 17, 10**3, 10**5):
        tn, _ = regimes.strobe_time(t_a, float(n), p_hi, p_lo)
        bounds += [np.nextafter(tn, -np.inf), tn, np.nextafter(tn, np.inf)]
    dense = np.linspace(t_a, t_a + 3 * p_hi, 2 * STORED_BLOCK + 37)
    late = np.linspace(1.0e6 - 10.0, 1.0e6, 301)
    t = np.sort(np.concatenate([dense, bounds, late, [t_a, t_a, dense[5], dense[5]]]))
    return t[t >= t_a]


def _range(c, per, t, wrapped):
    out = np.full((3, t.size), np.nan)
    outs = loop.Outputs(t, out[0], out[1], out[2] if wrapped else out[0], wrapped)
    _strobe_range_taylor(c, per, outs, 0, t.size)
    return out


def test_stored_period_is_the_re_run_bit_for_bit(step_coef):
    c, t_a = step_coef
    per = _strobe_windows_taylor(c)
    assert 4 <= per[3] < 1000 and per[0][per[3]] >= regimes.strobe_period(1.0, 1.0)[0]
    t = _times(c, t_a)
    th, v, w, ph = _reference(c, t)
    # Sorted (the walk), in blocks of STORED_BLOCK, θ whole and wrapped.
    out = _range(c, per, t, False)
    np.testing.assert_array_equal(out[0], th)
    np.testing.assert_array_equal(out[1], v)
    out = _range(c, per, t, True)
    np.testing.assert_array_equal(out[0], ph)
    np.testing.assert_array_equal(out[2], w)
    np.testing.assert_array_equal(out[1], v)
    # Backward and shuffled (bisection wherever the walk cannot go on).
    for order in (t[::-1], np.random.default_rng(3).permutation(t)):
        out = _range(c, per, order, False)
        ref = _reference(c, order)
        np.testing.assert_array_equal(out[0], ref[0])
        np.testing.assert_array_equal(out[1], ref[1])
    # One time at a time.
    for tj in t[::7]:
        assert _strobe_lookup_taylor(c, *per, tj) == _strobe_eval_taylor(c, tj)


def test_a_failed_period_is_nan_where_the_re_run_is(step_coef):
    # A tolerance the controller cannot meet in CYCLE_MAX_WINDOWS windows: the re-run
    # stops short of the period, and so does the store (NaN past its last window).
    c, t_a = step_coef
    c = c.copy()
    c[regimes.STR_RTOL] = c[regimes.STR_ATOL] = 1e-300
    per = _strobe_windows_taylor(c)
    t = np.linspace(t_a, t_a + 6.0, 97)
    ref = _reference(c, t)
    out = _range(c, per, t, False)
    np.testing.assert_array_equal(out[0], ref[0])
    np.testing.assert_array_equal(out[1], ref[1])
    assert np.isnan(out[0]).any()


def test_every_output_path_is_the_re_run(step_coef):
    # The loop (mbm.solve), the dense output and the stored-window evaluator: sorted
    # times through the switch (the switch time itself an output) to T.
    c, t_a = step_coef
    m = mbm.Pendulum(*STEP)
    T = 2000.0
    fast0 = mbm.solve(m, (0.0, T), Y0, rtol=TOL, atol=TOL)
    assert fast0.regime == "phase-locked"
    t = np.unique(np.concatenate([np.linspace(0.0, T, 4001), [fast0.t_regime, t_a]]))
    fast = mbm.solve(m, (0.0, T), Y0, rtol=TOL, atol=TOL, t_eval=t)
    after = t > fast.t_regime
    th, v, _, _ = _reference(c, t[after])
    np.testing.assert_array_equal(fast.y[0, after], th)
    np.testing.assert_array_equal(fast.y[1, after], v)
    ivp = solve_ivp(m, (0.0, T), Y0, method=mbm.MBM, dense_output=True, rtol=TOL, atol=TOL)
    np.testing.assert_array_equal(ivp.sol(t), fast.y)
    one = np.array([ivp.sol(tj) for tj in t[after][::50]]).T
    np.testing.assert_array_equal(one, fast.y[:, after][:, ::50])
    # The stored-window evaluator on one phase-locked window.
    out_th, out_v = np.empty(t[after].size), np.empty(t[after].size)
    starts, start_theta = np.array([t_a, T]), np.array([theta_of(c[regimes.STR_WIND], c[regimes.STR_PHI])])
    stored.evaluate_windows(KIND_TAYLOR, starts, start_theta, c[None, :], 1, 1.0, t[after], out_theta=out_th,
                            out_v=out_v)
    np.testing.assert_array_equal(out_th, th)
    np.testing.assert_array_equal(out_v, v)


def test_split_from_a_remembered_multiple_is_the_split():
    # strobe_split_from tries the previous time's n·P first (no division where it fits)
    # and forms a new one where n changes: (n, s) bit for bit strobe_split's (which
    # remembers none), over sorted, unsorted and period-boundary times (either side).
    from mbm.regimes.strobe import NO_MULTIPLE, strobe_period, strobe_split, strobe_split_from

    split = strobe_split.py_func if hasattr(strobe_split, "py_func") else strobe_split
    p_hi, p_lo = strobe_period(0.913, 2.0)
    t_a = 251.37
    rng = np.random.default_rng(7)
    k = np.arange(-3, 400, dtype=float)
    times = np.concatenate((np.linspace(t_a, t_a + 3000.0, 4001), t_a + k * p_hi, t_a + k * (p_hi + p_lo),
                            np.nextafter(t_a + k * p_hi, np.inf),
                            np.nextafter(t_a + k * p_hi, -np.inf), np.nextafter(t_a + k * (p_hi + p_lo), -np.inf),
                            rng.uniform(t_a, t_a + 1e5, 2000)))
    for order in (times, rng.permutation(times)):
        known = NO_MULTIPLE
        for t in order:
            n, s, known = strobe_split_from(t, t_a, (p_hi, p_lo), known)
            n0, s0 = split(t, t_a, p_hi, p_lo)
            assert (n, s) == (n0, s0), t
            assert known[0] == n
