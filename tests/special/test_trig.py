"""Tests of mbm.special.trig: sin_m, cos_m of (3.12)–(3.14) / (2.25)–(2.26)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import ellipj, ellipk

from mbm.special.trig import (
    M_MAX,
    cos_m,
    dn_m,
    sin_m,
    sin_m_dm_kernel,
    sin_m_kernel,
    trig_m_kernel,
)


def _jacobi(t, m):
    """sn, cn, dn for any m <= 1, via the imaginary-modulus transformation for m < 0."""
    if m >= 0.0:
        return ellipj(t, m)[:3]
    s = math.sqrt(1.0 - m)
    sn, cn, dn, _ = ellipj(t * s, -m / (1.0 - m))  # DLMF 22.17.2 (m < 0)
    return sn / (dn * s), cn / dn, 1.0 / dn


def _quarter_period(m):
    return ellipk(m) if m >= 0.0 else ellipk(-m / (1.0 - m)) / math.sqrt(1.0 - m)


def _max_err(m, which):
    K = _quarter_period(m)
    t = np.linspace(-2.0 * K, 2.0 * K, 20001)  # one period, T = 4K, as in the papers
    sn, cn, dn = _jacobi(t, m)
    return np.abs({"cn": cos_m(t, m) - cn, "sn": sin_m(t, m) - sn}[which]).max()


def test_m_zero_is_sin_cos():
    t = np.linspace(-10.0, 10.0, 101)
    np.testing.assert_allclose(sin_m(t, 0.0), np.sin(t), rtol=0, atol=2e-15)
    np.testing.assert_allclose(cos_m(t, 0.0), np.cos(t), rtol=0, atol=2e-15)
    np.testing.assert_allclose(dn_m(t, 0.0), 1.0, rtol=0, atol=2e-15)


@given(
    t=st.floats(-50.0, 50.0),
    m=st.floats(-1.0, M_MAX),
)
@settings(max_examples=200, deadline=None)
def test_pythagoras(t, m):
    # The reconstruction of (3.12): with w in both places sin_m² + cos_m² = 1 exactly.
    s, c, d = trig_m_kernel(t, m)
    assert abs(s * s + c * c - 1.0) < 4e-15
    assert d > 0.0 and math.isfinite(d)


@pytest.mark.parametrize("m", [-1.0, -0.3, 0.0, 0.2, 0.55, 0.9, 1.0])
def test_derivative_identities(m):
    # d sin_m/dt = cos_m dn_m, d cos_m/dt = −sin_m dn_m (5-point stencil, error ~h⁴ + eps/h)
    h = 1e-3
    for t in (-3.3, 0.0, 0.4, 2.7, 11.0):
        ds = (-sin_m(t + 2 * h, m) + 8 * sin_m(t + h, m) - 8 * sin_m(t - h, m) + sin_m(t - 2 * h, m)) / (12 * h)
        dc = (-cos_m(t + 2 * h, m) + 8 * cos_m(t + h, m) - 8 * cos_m(t - h, m) + cos_m(t - 2 * h, m)) / (12 * h)
        assert abs(ds - cos_m(t, m) * dn_m(t, m)) < 1e-11
        assert abs(dc + sin_m(t, m) * dn_m(t, m)) < 1e-11


@pytest.mark.parametrize("m", [-0.8, -0.1, 0.1, 0.5, 0.95])
def test_dm_derivative(m):
    h = 1e-4
    for t in (0.3, 1.7, 6.0, 25.0):
        fd = (
            -sin_m_kernel(t, m + 2 * h) + 8 * sin_m_kernel(t, m + h)
            - 8 * sin_m_kernel(t, m - h) + sin_m_kernel(t, m - 2 * h)
        ) / (12 * h)
        assert abs(fd - sin_m_dm_kernel(t, m)) < 1e-9 * max(1.0, abs(fd))


# Second paper, Table 1: max over one period |cn − cos_m|.  Our recomputation agrees
# with the printed values to < 0.5 % (grid of 20001 points per period).
CN_TABLE = {
    0.15: 0.00032743, 0.2: 0.000611528, 0.25: 0.00100518, 0.3: 0.00152492,
    0.35: 0.00219766, 0.4: 0.00304477, 0.45: 0.00410158, 0.5: 0.00541633,
    0.55: 0.00704757, -1.0: 0.00673646, -0.9: 0.00574835, -0.8: 0.00478114,
    -0.7: 0.0038748, -0.6: 0.0030145, -0.5: 0.00222486, -0.4: 0.00151738,
    -0.3: 0.000912756, -0.2: 0.000434754, -0.1: 0.000117442,
}


@pytest.mark.parametrize("m", sorted(CN_TABLE))
def test_cos_m_matches_second_paper_table1(m):
    assert _max_err(m, "cn") == pytest.approx(CN_TABLE[m], rel=5e-3)


def test_second_paper_table1_m01_row_is_a_copy():
    # The printed row m = 0.1 repeats the m = −1 value 0.00673646; the error at m = 0.1
    # lies between those at m = −0.1 and m = 0.15, as the trend of the table requires.
    err = _max_err(0.1, "cn")
    assert CN_TABLE[-0.1] < err < CN_TABLE[0.15]
    assert err == pytest.approx(1.39e-4, rel=0.01)


# sin_m against sn over one period (our measurements, not printed anywhere).
SN_ERRORS = {-1.0: 6.39e-3, -0.5: 2.40e-3, 0.1: 1.86e-4, 0.3: 2.26e-3, 0.55: 1.22e-2, 0.9: 0.100}


@pytest.mark.parametrize("m", sorted(SN_ERRORS))
def test_sin_m_approximates_sn(m):
    assert _max_err(m, "sn") == pytest.approx(SN_ERRORS[m], rel=0.01)


def test_numpy_level_broadcasting_and_scalars():
    out = sin_m(np.array([[0.1], [0.2]]), np.array([0.0, 0.5, -0.5]))
    assert out.shape == (2, 3)
    assert isinstance(cos_m(0.3, 0.2), float)


@pytest.mark.parametrize("m", [1.0 + 1e-9, 2.0, np.nan])
def test_bad_parameter_raises(m):
    with pytest.raises(ValueError, match="m must be"):
        sin_m(1.0, m)
    with pytest.raises(ValueError, match="m must be"):
        cos_m([1.0, 2.0], m)
    assert math.isnan(sin_m_kernel(1.0, m))
