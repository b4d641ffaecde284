"""The noise entry points refuse bad arguments, naming them and their range."""

import pytest

import mbm


@pytest.mark.parametrize("args,kw,err,words", [
    ((0.0, 0.5, 0.1, 10), {}, ValueError, "beta must be > 0"),
    ((1.0, 1.0, 0.1, 10), {}, ValueError, r"gamma must satisfy \|gamma\| < omega\*\*2"),
    ((1.0, 0.5, 2.0, 10), {"omega": 0.5}, ValueError, "gamma must satisfy"),
    ((1.0, 0.5, -0.1, 10), {}, ValueError, "temperature must be > 0"),
    ((1.0, 0.5, float("nan"), 10), {}, ValueError, "temperature must be finite"),
    ((1.0, 0.5, 0.1, 0), {}, ValueError, "n must be >= 1"),
    ((1.0, 0.5, 0.1, 2.5), {}, TypeError, "n must be an integer"),
    ((1.0, 0.5, 0.1, 10), {"dt": 2.0}, ValueError, r"dt must be in \(0, 1.0/omega\]"),
    ((1.0, 0.5, 0.1, 10), {"dt": 0.0}, ValueError, "dt must be > 0"),
    ((1.0, 0.5, 0.1, 10), {"t_max": -1.0}, ValueError, "t_max must be > 0"),
    ((1.0, 0.5, 0.1, 10), {"threads": 0}, ValueError, "threads must be in"),
    ((1.0, 0.5, 0.1, 10), {"seed": -3}, ValueError, "seed must be in"),
    (("1", 0.5, 0.1, 10), {}, TypeError, "beta must be"),
    ((1.0, 0.5, 0.1, 10), {"omega": 0.0}, ValueError, "omega must be > 0"),
])
def test_escape_times_refuses(args, kw, err, words):
    with pytest.raises(err, match=words):
        mbm.escape_times(*args, **kw)


@pytest.mark.parametrize("args,kw,err,words", [
    ((1.0, 0.1, 0.0, 10), {}, ValueError, "ramp_rate must be > 0"),
    ((1.0, 0.0, 1e-3, 10), {}, ValueError, "temperature must be > 0"),
    ((-1.0, 0.1, 1e-3, 10), {}, ValueError, "beta must be > 0"),
    ((1.0, 0.1, 1e-3, 10), {"gamma_start": 1.0}, ValueError, "gamma_start must satisfy"),
    ((1.0, 0.1, 1e-3, 10), {"gamma_start": -0.1}, ValueError, "gamma_start must be >= 0"),
    ((1.0, 0.1, 1e-12, 10), {}, ValueError, "ramp_rate must be >="),
    ((1.0, 0.1, 1e-3, 10), {"seed": 1.0}, TypeError, "seed must be None or an integer"),
])
def test_switching_currents_refuses(args, kw, err, words):
    with pytest.raises(err, match=words):
        mbm.switching_currents(*args, **kw)


def test_a_long_horizon_is_refused_before_it_runs():
    with pytest.raises(ValueError, match="t_max / dt must be <="):
        mbm.escape_times(1.0, 0.5, 0.1, 10, t_max=1e12)
