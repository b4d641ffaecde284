"""Escape times against Kramers and an independent stochastic Heun run; switching
histograms against the Kramers rate integrated over the ramp."""

import math

import numpy as np
import pytest

import mbm
from mbm.noise import flow, heun

N_SE = 4.5
# Kramers' formula has finite-barrier corrections of order T/ΔU (~20 % at ΔU/T = 5):
# the factor a measured mean escape time may stand from it.
KRAMERS_FACTOR = 1.35


@pytest.mark.parametrize("beta,gamma,temperature,n", [(1.0, 0.7, 0.063, 400), (1.0, 0.5, 0.12, 400),
                                                      (3.0, 0.7, 0.063, 250)])
def test_mean_escape_time_is_kramers(beta, gamma, temperature, n):
    r = mbm.escape_times(beta, gamma, temperature, n, seed=11)
    assert np.all(np.isfinite(r.times))
    ratio = r.mean * mbm.kramers_rate(beta, gamma, temperature)
    se = r.stderr / r.mean * ratio
    assert se < 0.08
    assert 1 / KRAMERS_FACTOR - N_SE * se < ratio < KRAMERS_FACTOR + N_SE * se, (ratio, se)
    # the censored-rate estimate agrees with 1/mean when nothing is censored
    assert r.rate == pytest.approx(1 / r.mean, rel=1e-12)


def test_escape_times_agree_with_a_fine_heun_run():
    beta, gamma, temperature, n = 1.0, 0.7, 0.1, 1200
    r = mbm.escape_times(beta, gamma, temperature, n, seed=11, dt=0.1)
    p = flow.make_params(beta, 1.0, gamma, 0.0, 0.0, 0.0, 0.0, temperature)
    th = math.asin(gamma)
    h = heun.heun_escape_kernel(p, 99, n, np.array([th, 0.0]), 0.01, 10**8,
                                np.array([th - 2 * math.pi, th + 2 * math.pi]))
    assert np.all(np.isfinite(h))
    se_h = h.std(ddof=1) / math.sqrt(n)
    assert abs(r.mean - h.mean()) < N_SE * math.hypot(r.stderr, se_h), (r.mean, h.mean())
    # exponential law: the standard deviation of escape times is the mean (within 10 %)
    assert r.times.std() == pytest.approx(r.mean, rel=0.1)


def _kramers_histogram(beta, temperature, ramp, g0, factor=1.0):
    # (mean, width, skewness, kurtosis) of P(γ) = k(γ)/r exp(−∫ k/r dγ), k Kramers'.
    g = np.linspace(g0, 0.99999, 20001)
    k = np.array([mbm.kramers_rate(beta, x, temperature) for x in g]) * factor
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(g))]) / ramp
    w = k * np.exp(-cum)
    w /= np.trapezoid(w, g)
    m = np.trapezoid(w * g, g)
    m2, m3, m4 = (np.trapezoid(w * (g - m)**j, g) for j in (2, 3, 4))
    return m, math.sqrt(m2), m3 / m2**1.5, m4 / m2**2


@pytest.mark.parametrize("beta,temperature,g0", [(1.0, 0.05, 0.6), (0.5, 0.02, 0.75)])
def test_switching_histogram_is_the_integrated_kramers_law(beta, temperature, g0):
    n, ramp = 400, 1e-4
    s = mbm.switching_currents(beta, temperature, ramp, n, seed=3, gamma_start=g0)
    assert not np.any(np.isnan(s.currents)) and s.currents.shape == (n,)
    lo, mid, hi = (_kramers_histogram(beta, temperature, ramp, g0, f)
                   for f in (KRAMERS_FACTOR, 1.0, 1 / KRAMERS_FACTOR))
    se_mean = s.width / math.sqrt(n)
    se_width = s.width * math.sqrt((s.kurtosis - 1) / (4 * n))
    assert lo[0] - N_SE * se_mean < s.mean < hi[0] + N_SE * se_mean, (s.mean, lo[0], hi[0])
    assert (min(lo[1], hi[1]) - N_SE * se_width < s.width < max(lo[1], hi[1]) + N_SE * se_width), \
        (s.width, lo[1], hi[1])
    # a left-skewed, heavier-than-normal histogram (Kramers: skewness ≈ −0.7, kurtosis
    # ≈ 3.6–3.9 here; the Gumbel limit −1.14, 5.4 needs far slower ramps)
    assert abs(s.skewness - mid[2]) < N_SE * math.sqrt(6 / n)
    assert abs(s.kurtosis - mid[3]) < N_SE * math.sqrt(24 / n)
    assert s.skewness < 0 and s.kurtosis > 3
    # the statistics are those of .currents
    d = s.currents - s.currents.mean()
    assert s.kurtosis == pytest.approx((d**4).mean() / (d**2).mean()**2)
