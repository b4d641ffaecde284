"""The locked regime's outputs in blocks (issue 52): locked_eval_range, the loop's and the
dense output's, against the closed form per output (items L2, L6)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm
from mbm import regimes
from mbm.core.window import theta_of
from mbm.regimes import locked

# (β, γ, ω, order): under-damped at orders 1 and 2 (L2, L6), over-damped, critically
# damped (s² = 0 exactly: ω_l² = 1 = β²/4).
FORMS = [(0.5, 0.2, 1.0, 1), (0.5, 0.2, 1.0, 2), (0.1, -0.5, 2.0, 2), (3.0, 0.2, 1.0, 1), (2.0, 0.0, 1.0, 1)]


def _coef(beta, gamma, omega, order):
    d, wl2, _, _ = regimes.locked_constants(beta, gamma, omega)
    return regimes.locked_coef(beta, wl2, d, d + 1e-3, -2e-3, gamma, order)


def _reference(coef, t):
    # L2 (and L6's x₂ at order 2) in Python floats, one output at a time, as the closed
    # form was written before the blocks (sin and cos apart).
    th0, x0, v0, hb, s2, wl2 = coef[1:7]
    b = v0 + hb * x0
    e = c1 = s1 = s = 0.0
    if s2 > 0.0:
        s = math.sqrt(s2)
        e, c1, s1 = math.exp(-hb * t), math.cos(s * t), math.sin(s * t)
        ec, es = e * c1, e * s1 / s
    elif s2 < 0.0:
        mu = math.sqrt(-s2)
        e1 = math.exp(-wl2 / (hb + mu) * t)
        ec = 0.5 * (e1 + math.exp((-hb - mu) * t))
        es = e1 * (-math.expm1(-2.0 * mu * t)) / (2.0 * mu)
    else:
        e = math.exp(-hb * t)
        ec, es = e, e * t
    x = x0 * ec + b * es
    xd = x0 * (-hb * ec - s2 * es) + b * (ec - hb * es)
    if coef.size >= locked.LOCKED2_WIDTH and coef[7] == 2.0 and t != 0.0 and s2 > 0.0:
        qr, qi, m, dr, di = coef[8:13]
        e2, c2, sn2, beta = e * e, c1 * c1 - s1 * s1, 2.0 * s1 * c1, 2.0 * hb
        x = x + (e2 * (qr * c2 - qi * sn2) + m * e2 + e * (dr * c1 - di * s1))
        xd = xd + (e2 * ((-beta * qr - 2.0 * s * qi) * c2 - (-beta * qi + 2.0 * s * qr) * sn2) - beta * m * e2
                   + e * ((-hb * dr - s * di) * c1 - (-hb * di + s * dr) * s1))
    return th0 + (x - x0), xd


def _ulps(a, b):
    return np.max(np.abs(a - b) / np.spacing(np.maximum(np.abs(a), np.abs(b))), initial=0.0)


@pytest.mark.parametrize("form", FORMS)
def test_a_range_is_the_closed_form_per_output(form):
    # Any range of unsorted times (large, negative, the anchor itself), blocks and the
    # short path alike: locked_eval's bits per output, and within an ulp of the formula
    # in Python floats (0 where sin and cos fused into sincos round alike).
    coef = _coef(*form)
    rng = np.random.default_rng(52)
    t0 = 1.5
    times = t0 + np.concatenate([[0.0], rng.uniform(-3.0, 2500.0, 300), rng.uniform(0.0, 1e6, 40)])
    rng.shuffle(times)
    for lo, hi in ((0, times.size), (3, 5), (7, 72), (11, 12)):
        th, v = np.full(times.size, 7.0), np.full(times.size, 7.0)
        regimes.locked_eval_range(coef, t0, times, lo, hi, th, v)
        want = np.array([regimes.locked_eval(coef, x - t0) for x in times[lo:hi]]).reshape(-1, 2)
        np.testing.assert_array_equal(th[lo:hi], want[:, 0])
        np.testing.assert_array_equal(v[lo:hi], want[:, 1])
        assert (th[:lo] == 7.0).all() and (th[hi:] == 7.0).all() and (v[hi:] == 7.0).all()
    ref = np.array([_reference(coef, x - t0) for x in times])
    th, v = np.empty_like(times), np.empty_like(times)
    regimes.locked_eval_range(coef, t0, times, 0, times.size, th, v)
    assert _ulps(th, ref[:, 0]) <= 1 and _ulps(v, ref[:, 1]) <= 1
    # The anchor is its state bit for bit.
    i = int(np.flatnonzero(times == t0)[0])
    assert (th[i], v[i]) == (coef[1], coef[3])


def test_the_shortcuts_give_the_library_zeros():
    # E2_FLOOR: e·e is +0 for every e below it (and not far above); EXP_ZERO: exp is +0
    # there (and below, exp being monotone), not a little above.
    e = np.nextafter(locked.E2_FLOOR, 0.0)
    assert e * e == 0.0 and math.copysign(1.0, e * e) == 1.0
    assert (2.0 * locked.E2_FLOOR) ** 2 > 0.0
    assert math.exp(locked.EXP_ZERO) == 0.0 and math.exp(locked.EXP_ZERO + 2.0) > 0.0


@pytest.mark.parametrize("form", FORMS)
def test_non_finite_times_are_the_closed_form_s(form):
    coef = _coef(*form)
    times = np.array([np.nan, np.inf, -np.inf, 0.0, 1e4, 3e3, -1e3, 1e300])
    th, v = np.empty_like(times), np.empty_like(times)
    regimes.locked_eval_range(coef, 0.0, times, 0, times.size, th, v)
    want = np.array([regimes.locked_eval(coef, x) for x in times])
    np.testing.assert_array_equal(np.stack([th, v], axis=1), want)


@pytest.mark.parametrize("wrap", [False, True])
def test_the_outputs_after_a_switch_are_the_closed_form(wrap):
    # mbm.solve's outputs past the switch (a winding count k ≠ 0: θ* 3 turns up) and the
    # dense output at unsorted times: the closed form from the switch per output, the
    # output at the switch the anchor.
    model, y0, span = mbm.Pendulum(0.5, 0.2, 1.0), (1.0 + 6.0 * math.pi, 0.0), (0.0, 2000.0)
    kw = dict(rtol=1e-9, atol=1e-9)
    sol = solve_ivp(model, span, y0, method=mbm.MBM, dense_output=True, **kw)
    last = sol.sol.interpolants[-1]
    coef, t_s = last.coefs[0, :locked.LOCKED2_WIDTH], last.starts[0]
    assert coef[0] == locked.LOCKED_TAG
    t = np.sort(np.concatenate([np.linspace(0.0, 2000.0, 2001), [t_s]]))
    r = mbm.solve(model, span, y0, t_eval=t, wrap=wrap, **kw)
    assert r.regime == "locked" and r.t_regime == t_s
    after = t >= t_s
    want = np.array([regimes.locked_eval(coef, x - t_s) for x in t[after]])
    k = 3.0  # the window holds φ = θ − 2πk (TWO_PI_A)
    if wrap:
        np.testing.assert_array_equal(r.winding[after], 3)
        np.testing.assert_array_equal(r.y[0, after], want[:, 0])
    else:
        np.testing.assert_array_equal(r.y[0, after], [theta_of(k, a) for a in want[:, 0]])
    np.testing.assert_array_equal(r.y[1, after], want[:, 1])
    assert r.y[1, np.flatnonzero(t == t_s)[0]] == coef[3]
    tq = np.random.default_rng(3).uniform(t_s, 2000.0, 500)
    want = np.array([regimes.locked_eval(coef, x - t_s) for x in tq])
    np.testing.assert_array_equal(last(tq), [[theta_of(k, a) for a in want[:, 0]], want[:, 1]])
