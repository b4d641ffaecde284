"""``escape_times(..., start="thermal")``: Boltzmann starts in the well, from the scene's own stream."""

import math

import numpy as np
import pytest

import mbm
from mbm.noise import api
from mbm.noise.flow import make_params


def _starts(gamma, temperature, n, seed, omega=1.0):
    p = make_params(1.0, omega, gamma, 0.0, 0.0, 0.0, 0.0, temperature)
    return api._thermal_starts(p, (np.uint64(seed), np.int64(0)), n, gamma, omega)


def _boltzmann_means(gamma, temperature, omega=1.0):
    # ⟨θ⟩ and ⟨cos θ⟩ of e^{−U/T} on the well (−π − θ0, π − θ0), by quadrature
    th0 = math.asin(gamma / omega**2)
    th = np.linspace(-math.pi - th0, math.pi - th0, 200001)
    w = np.exp(-(-omega**2 * np.cos(th) - gamma * th) / temperature)
    z = np.trapezoid(w, th)
    return np.trapezoid(th * w, th) / z, np.trapezoid(np.cos(th) * w, th) / z


@pytest.mark.parametrize("gamma,temperature,omega", [(0.5, 0.1, 1.0), (-0.3, 0.4, 1.3)])
def test_thermal_starts_have_the_boltzmann_law(gamma, temperature, omega):
    # 20,000 independent draws: each mean within 4 standard errors of the law's
    n = 20000
    s = _starts(gamma, temperature, n, 11, omega)
    th, v = s[:, 0], s[:, 1]
    th0 = math.asin(gamma / omega**2)
    assert np.all((th > -math.pi - th0) & (th < math.pi - th0))
    se_v2 = (v**2).std(ddof=1) / math.sqrt(n)
    assert abs((v**2).mean() - temperature) < 4 * se_v2
    m_th, m_cos = _boltzmann_means(gamma, temperature, omega)
    assert abs(th.mean() - m_th) < 4 * th.std(ddof=1) / math.sqrt(n)
    assert abs(np.cos(th).mean() - m_cos) < 4 * np.cos(th).std(ddof=1) / math.sqrt(n)


def test_thermal_start_is_reproducible_and_the_default_is_the_bottom(monkeypatch):
    kw = dict(seed=4, t_max=2000.0)
    bottom = mbm.escape_times(1.0, 0.7, 0.1, 64, **kw)
    assert np.array_equal(bottom.times, mbm.escape_times(1.0, 0.7, 0.1, 64, start="bottom", **kw).times)
    hot = mbm.escape_times(1.0, 0.7, 0.1, 64, start="thermal", **kw)
    assert not np.array_equal(hot.times, bottom.times)
    assert np.array_equal(hot.times, mbm.escape_times(1.0, 0.7, 0.1, 64, start="thermal", threads=1, **kw).times)
    monkeypatch.setattr(api, "CHUNK_SCENES", 10)
    assert np.array_equal(hot.times, mbm.escape_times(1.0, 0.7, 0.1, 64, start="thermal", **kw).times)
    # the starts do not depend on the chunks either
    assert np.array_equal(_starts(0.7, 0.1, 30, 4)[20:], _thermal_tail())


def _thermal_tail():
    p = make_params(1.0, 1.0, 0.7, 0.0, 0.0, 0.0, 0.0, 0.1)
    return api._thermal_starts(p, (np.uint64(4), np.int64(20)), 10, 0.7, 1.0)


@pytest.mark.parametrize("start", ["Thermal", "", None, 1])
def test_bad_start_is_refused(start):
    with pytest.raises(ValueError, match="start must be 'bottom' or 'thermal'"):
        mbm.escape_times(1.0, 0.7, 0.1, 4, start=start)
