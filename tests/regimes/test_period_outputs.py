"""Outputs of the running cycle and the libration from their stored period (R3, C3) in
blocks (``_period_range_taylor``): the same bits as the one-time lookup
(``_period_lookup_taylor``) on sorted, backward, shuffled and repeated times, at period
boundaries, at the window's start and at t ~ 1e6, θ whole and wrapped."""

import numpy as np
import pytest

import mbm
from mbm import regimes, status
from mbm.core import controller, loop, record
from mbm.core.window import KIND_TAYLOR, theta_of, wrap
from mbm.regimes.cycle_windows import _period_lookup_taylor, _period_range_taylor, _period_store
from mbm.regimes.stored_block import STORED_BLOCK

# A running cycle and a libration (tests/regimes/test_regimes.py, test_libration.py):
# ((β, γ, ω), y0).
SCENES = {"running": ((0.1, 1.2, 1.0), (0.0, 0.0)), "libration": ((0.0, 0.4, 1.0), (1.0, 0.0))}
TOL = 1e-10


def _cycle_window(params, y0, T, tol):
    """The run's last window (a stored period's: its coefficients and start), from the
    loop by hand with a window store, resumed across its switch of entries."""
    ap, kind, karg = mbm.frontends.solve.compiled(mbm.get_approximant("taylor"))
    p = record.new_run(record.RunModel(*params), record.RunState(0.0, y0[0], y0[1], T),
                       record.RunControl(kind, karg, controller.CONTROLLER_ADAPTIVE, -1.0, np.inf, np.inf, tol, tol,
                                         int(ap.error_order)), 10**8)
    cap = 20000
    win_t, win_y, win_coef = np.empty(cap + 1), np.empty((cap + 1, 2)), np.zeros((cap, regimes.CYCLE_WIDTH))
    while True:
        n = loop.run(p, np.empty(0), np.empty((2, 0)), win_t, win_y, win_coef, np.zeros(1, np.int64))
        if record.flat(p)[0]["status"] != status.STATUS_PAUSED:
            break
    assert record.flat(p)[0]["status"] == status.STATUS_OK and 0 < n < cap
    assert win_coef[n - 1, 0] == regimes.CYCLE_TAG
    return win_coef[n - 1].copy(), win_t[n - 1]


@pytest.fixture(scope="module", params=sorted(SCENES))
def cycle_window(request):
    params, y0 = SCENES[request.param]
    return _cycle_window(params, y0, 2000.0, TOL)


def _reference(c, per, t, t0):
    th, v, w, ph = (np.empty(t.size) for _ in range(4))
    for j, tj in enumerate(t):
        a, b, k = _period_lookup_taylor(c, *per, tj - t0)
        th[j], v[j] = theta_of(k, a), b
        w[j], ph[j] = wrap(k, a)
    return th, v, w, ph


def _range(c, per, t, t0, wrapped):
    out = np.full((3, t.size), np.nan)
    _period_range_taylor(c, per, loop.Outputs(t, out[0], out[1], out[2] if wrapped else out[0], wrapped),
                         0, t.size, t0)
    return out


def _times(per, t0):
    """Sorted times from the window's start: three periods densely, each stored window's
    start and neighbours in the first and a late period, repeats, and t ~ 1e6."""
    starts, n = per[0], per[3]
    period = starts[n]
    marks = np.concatenate([t0 + starts[:n + 1], t0 + 917 * period + starts[:n + 1]])
    near = np.concatenate([np.nextafter(marks, -np.inf), marks, np.nextafter(marks, np.inf)])
    dense = np.linspace(t0, t0 + 3 * period, 2 * STORED_BLOCK + 37)
    late = np.linspace(1.0e6 - 10.0, 1.0e6, 301)
    t = np.sort(np.concatenate([dense, near, late, [t0, t0, dense[5], dense[5]]]))
    return t[t >= t0]


def test_block_is_the_lookup_bit_for_bit(cycle_window):
    c, t0 = cycle_window
    per = _period_store(KIND_TAYLOR, c)
    assert per[3] >= 2
    t = _times(per, t0)
    th, v, w, ph = _reference(c, per, t, t0)
    out = _range(c, per, t, t0, False)
    np.testing.assert_array_equal(out[0], th)
    np.testing.assert_array_equal(out[1], v)
    out = _range(c, per, t, t0, True)
    np.testing.assert_array_equal(out[0], ph)
    np.testing.assert_array_equal(out[2], w)
    np.testing.assert_array_equal(out[1], v)
    for order in (t[::-1], np.random.default_rng(5).permutation(t)):
        out = _range(c, per, order, t0, False)
        ref = _reference(c, per, order, t0)
        np.testing.assert_array_equal(out[0], ref[0])
        np.testing.assert_array_equal(out[1], ref[1])


def test_a_failed_period_is_nan(cycle_window):
    # n = −1 (a period the re-take could not store): NaN, as the lookup gives.
    c, t0 = cycle_window
    per = _period_store(KIND_TAYLOR, c)
    failed = (per[0], per[1], per[2], -1)
    t = np.linspace(t0, t0 + 10.0, 11)
    out = _range(c, failed, t, t0, False)
    assert np.isnan(out).all()
    np.testing.assert_array_equal(out[0], _reference(c, failed, t, t0)[0])
