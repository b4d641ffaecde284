"""``mbm.retrapping_currents``: the running junction caught in a well under a falling bias."""

import math

import numpy as np
import pytest

import mbm
from mbm.noise import api


def test_vanishing_temperature_is_the_deterministic_retrapping_current():
    # T = 1e-6: the noise's shift is far below the tolerance (measured +1e-4 at T = 1e-4).
    # The running state's mean velocity γ/β lags the ramp by its relaxation time 1/β:
    # the phase retraps when γ + r/β reaches γ_r.  Measured within 3e-4 of γ_r after
    # that shift (the recorded γ is the last slip's, a cycle before the turn).
    beta, rate = 0.1, 1e-4
    h = mbm.retrapping_currents(beta, 1e-6, rate, 64, seed=3)
    assert not np.isnan(h.currents).any() and h.ramp_rate == rate and h.seed == 3
    g_r = mbm.retrapping_current(beta)
    assert abs(h.mean + rate / beta - g_r) < 1e-3, (h.mean, g_r)
    assert abs(g_r - 4 * beta / math.pi) < 0.01 * g_r  # Stewart–McCumber, β ≪ 1


def test_noise_and_slower_ramps_retrap_earlier():
    # thermal kicks catch the phase in a well above γ_r (activation out of the running
    # state), the more so the hotter and the slower the ramp.  Each step between the
    # means is over 6 standard errors (measured: widths ~0.003–0.007 on 200 scenes,
    # se ~ 3e-4–5e-4; steps 0.004–0.012).
    beta = 0.1
    cold = mbm.retrapping_currents(beta, 1e-3, 1e-4, 200, seed=1)
    hot = mbm.retrapping_currents(beta, 1e-2, 1e-4, 200, seed=1)
    slow = mbm.retrapping_currents(beta, 1e-2, 3e-5, 200, seed=1)
    se = [h.width / math.sqrt(200) for h in (cold, hot, slow)]
    assert hot.mean - cold.mean > 6 * math.hypot(se[0], se[1]), (cold.mean, hot.mean)
    assert slow.mean - hot.mean > 6 * math.hypot(se[1], se[2]), (hot.mean, slow.mean)
    assert cold.mean > mbm.retrapping_current(beta) - 1e-4 / beta - 1e-3
    # positive skew: the law has a tail towards higher currents (measured 0.16–0.42)
    assert hot.skewness > 0 and 2 < hot.kurtosis < 5


def test_seeds_reproduce_and_chunks_do_not_change_the_bits(monkeypatch):
    a = mbm.retrapping_currents(0.2, 0.01, 1e-3, 40, seed=7)
    b = mbm.retrapping_currents(0.2, 0.01, 1e-3, 40, seed=7, threads=1)
    assert np.array_equal(a.currents, b.currents)
    monkeypatch.setattr(api, "CHUNK_SCENES", 16)
    c = mbm.retrapping_currents(0.2, 0.01, 1e-3, 40, seed=7)
    assert np.array_equal(a.currents, c.currents)
    assert not np.array_equal(a.currents, mbm.retrapping_currents(0.2, 0.01, 1e-3, 40, seed=8).currents)
    assert isinstance(a, mbm.SwitchingHistogram) and isinstance(a, mbm.RetrappingHistogram)


@pytest.mark.parametrize("args,kw,err,words", [
    ((0.1, 0.01, 0.0, 10), {}, ValueError, "ramp_rate must be > 0"),
    ((0.1, 0.0, 1e-3, 10), {}, ValueError, "temperature must be > 0"),
    ((0.0, 0.01, 1e-3, 10), {}, ValueError, "beta must be > 0"),
    ((0.1, 0.01, 1e-3, 0), {}, ValueError, "n must be"),
    ((0.1, 0.01, 1e-3, 10), {"gamma_start": 0.0}, ValueError, "gamma_start must be > 0"),
    ((0.1, 0.01, 1e-3, 10), {"gamma_start": 2.0}, ValueError, r"gamma_start must be in \(0, 1.5"),
    ((0.1, 0.01, 1e-12, 10), {}, ValueError, "ramp_rate must be >="),
    ((0.1, 0.01, 1e-3, 10), {"dt": 2.0}, ValueError, "dt must be in"),
    ((0.1, 0.01, 1e-3, 10), {"seed": 1.5}, TypeError, "seed must be None or an integer"),
    ((0.1, 0.01, 1e-3, 10), {"threads": 0}, ValueError, "threads must be in"),
])
def test_retrapping_currents_refuses(args, kw, err, words):
    with pytest.raises(err, match=words):
        mbm.retrapping_currents(*args, **kw)
