"""Tests of mbm.special: Jacobi elliptic functions, K, F and Weierstrass ℘.

References are mpmath values stored in tests/data/special_refs.json
(regenerate with ``python tests/data/special_refs.py``).  The accuracy
target is 1e-13 relative; the maxima measured when this file was written are
quoted next to each assertion.
"""

import json
import math
import os
import pathlib

import mpmath as mp
import numba
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import mbm.special as S
from mbm.special import (
    ellipf_kernel,
    ellipj_kernel,
    ellipk_dd_kernel,
    ellipk_kernel,
    wp_eval_kernel,
    wp_half_period_kernel,
    wp_inverse_kernel,
    wp_kernel,
    wp_lattice_kernel,
    wp_roots_kernel,
)
from mbm.special.dd import DD_TINY, PI_HI, TWO_PI_HI, TWO_PI_LO, dd_sincos, dd_sqrt, reduce_2pi
from mbm.special.jacobi import ellipk_kc_dd_kernel

EPS = np.finfo(float).eps
TOL = 1e-13  # the accuracy target
REFS = json.loads((pathlib.Path(__file__).parents[1] / "data" / "special_refs.json").read_text())
# Property tests: 150 examples each by default (CI budget); raise with
# MBM_HYPOTHESIS_EXAMPLES=5000 for a deeper search.
FAST = settings(
    max_examples=int(os.environ.get("MBM_HYPOTHESIS_EXAMPLES", "150")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)


def rel_err(got, ref, floor=0.0):
    got = np.asarray(got, dtype=float)
    ref = np.asarray(ref, dtype=float)
    return np.abs(got - ref) / np.maximum(np.abs(ref) + floor, 1e-300)


# ---------------------------------------------------------------------------
# Jacobi functions against mpmath
# ---------------------------------------------------------------------------

_J = REFS["ellipj"]
_J_REGION = np.array(_J["region"])

# Measured maxima of the relative error over sn, cn, dn, am (worst function in
# brackets): near1 (mc = 1e-1 ... 1e-15) 7.8e-15 (cn, dn), near1_large_u
# 1.1e-14 (cn, dn), near1_extreme (mc = 1e-20, 1e-50, 1e-300) 8.1e-15 and
# 1.0e-14 at large u, regular 1.9e-15 / 8.3e-16, negative (m in [-5, 0))
# 7.7e-16 / 6.8e-16, above1 (m > 1) 2.3e-15 / 1.9e-15.  "large_u" means |u|
# in [100 K, 1.02e4 K].  The grid also holds u = fl(K), fl(2K), fl(4K),
# within an ulp of a zero of cn or sn, and the error there is still measured
# relative to the (tiny) reference value.


@pytest.mark.parametrize("region", sorted(set(_J["region"])))
def test_ellipj_matches_mpmath(region):
    sel = _J_REGION == region
    u = np.array(_J["u"])[sel]
    m = np.array(_J["m"])[sel]
    mc = np.array(_J["mc"])[sel]
    got = S.ellipj(u, m, mc)
    for name, g in zip(("sn", "cn", "dn", "am"), got):
        ref = np.array(_J[name])[sel]
        err = rel_err(g, ref)
        i = int(np.argmax(err))
        assert err[i] <= TOL, f"{name} {region}: rel err {err[i]:.2e} at u={u[i]!r}, mc={mc[i]!r}"


def test_ellipj_grid_covers_the_required_ranges():
    mc = np.array(_J["mc"])
    m = np.array(_J["m"])
    for k in range(1, 16):
        assert np.any(mc == 10.0**-k)
    assert np.any((m >= -5) & (m < -1)) and np.any(m > 1)
    u = np.abs(np.array(_J["u"]))
    assert u.max() > 1e5  # 1e4 K with K ~ 19 at mc = 1e-15


def test_ellipk_matches_mpmath():
    k = REFS["ellipk"]
    got = S.ellipk(k["m"], k["mc"])
    # Measured: 0 (correctly rounded on the whole grid; double-double AGM).
    assert rel_err(got, k["K"]).max() <= 2 * EPS


def test_ellipf_matches_mpmath():
    f = REFS["ellipf"]
    got = S.ellipf(f["phi"], f["m"], f["mc"])
    # Measured: 5.5e-16 (includes phi = fl(pi/2) at mc = 1e-15, |phi| ~ 3e4,
    # m < 0 and m > 1 up to the edge of the real domain).
    assert rel_err(got, f["F"]).max() <= TOL


# ---------------------------------------------------------------------------
# Jacobi identities
# ---------------------------------------------------------------------------

_PARAMS = [(1.0 - mc, mc) for mc in [10.0**-k for k in range(1, 16)] + [1e-30, 1e-300]]
_PARAMS += [(m, 1.0 - m) for m in (0.0, 0.3, 0.5, 0.8, -0.5, -2.0, -5.0, -1e3, 1.5, 4.0, 1e3)]


@pytest.mark.parametrize("m, mc", _PARAMS)
def test_pythagorean_identities(m, mc):
    K = S.ellipk(0.5) if mc <= 0 else S.ellipk(m, mc)
    u = np.linspace(-7.3, 7.3, 201) * K
    s, c, d, a = S.ellipj(u, m, mc)
    assert np.max(np.abs(s * s + c * c - 1.0)) <= 4 * EPS
    # dn^2 + m sn^2 = 1, the terms are up to max(1, |m| sn^2) in size
    assert np.max(np.abs(d * d + m * s * s - 1.0) / (1.0 + np.abs(m) * s * s)) <= 8 * EPS
    assert np.allclose(np.sin(a), s, rtol=0, atol=4 * EPS * np.maximum(1, np.abs(a)))
    assert np.allclose(np.cos(a), c, rtol=0, atol=4 * EPS * np.maximum(1, np.abs(a)))


@pytest.mark.parametrize("m, mc", [p for p in _PARAMS if p[1] > 0])
def test_f_inverts_am(m, mc):
    """F(am(u|m)|m) = u, within a quarter period and by quasi-periodicity."""
    K = S.ellipk(m, mc)
    u = np.concatenate([np.linspace(-1, 1, 41) * K, np.linspace(1, 40, 37) * K * 1.003])
    s, c, d, a = S.ellipj(u, m, mc)
    back = S.ellipf(a, m, mc)
    # am carries an error of a few ulps of |am|; F amplifies it by dF/dphi = 1/dn.
    bound = TOL * np.abs(u) + 8 * EPS * np.abs(a) / np.abs(d)
    assert np.all(np.abs(back - u) <= bound)


def test_f_inverts_am_above_one():
    for m in (1.5, 4.0, 1e3):
        Kr = S.ellipk(1.0 / m) / math.sqrt(m)  # real quarter period for m > 1
        u = np.linspace(-1, 1, 41) * Kr
        s, c, d, a = S.ellipj(u, m, 1.0 - m)
        back = S.ellipf(a, m, 1.0 - m)
        bound = TOL * np.abs(u) + 8 * EPS * np.abs(a) / np.maximum(np.abs(d), 1e-300)
        assert np.all(np.abs(back - u) <= bound)


def test_m_equal_one_is_hyperbolic():
    u = np.array([-800.0, -20.0, -1.0, 0.0, 1e-8, 0.5, 3.0, 40.0, 800.0])
    s, c, d, a = S.ellipj(u, 1.0, 0.0)
    assert np.array_equal(s, np.tanh(u))
    with np.errstate(over="ignore"):
        assert np.allclose(c, 1 / np.cosh(u), rtol=EPS, atol=0)
        assert np.allclose(a, np.arctan(np.sinh(u)), rtol=2 * EPS, atol=0)
    assert np.array_equal(c, d)
    # ... and the limit mc -> 0 is continuous.
    s2, c2, d2, a2 = S.ellipj(3.0, 1.0, 1e-300)
    assert abs(s2 - math.tanh(3.0)) <= 2 * EPS and abs(c2 / (1 / math.cosh(3.0)) - 1) <= 4 * EPS


def test_periodicity_and_symmetry():
    m, mc = 0.7, 0.3
    K = S.ellipk(m, mc)
    u = np.linspace(0.01, 3.9, 50)
    s, c, d, a = S.ellipj(u, m, mc)
    s4, c4, d4, a4 = S.ellipj(u + 4 * K, m, mc)
    assert np.allclose(s4, s, atol=1e-14) and np.allclose(c4, c, atol=1e-14)
    assert np.allclose(a4 - a, 2 * math.pi, atol=1e-14)
    sm, cm, dm, am_ = S.ellipj(-u, m, mc)
    assert np.array_equal(sm, -s) and np.array_equal(cm, c) and np.array_equal(am_, -a)


# ---------------------------------------------------------------------------
# Weierstrass against mpmath
# ---------------------------------------------------------------------------

_L = REFS["lattice"]
_W = REFS["wp"]


def test_wp_roots_match_mpmath():
    g2 = np.array(_L["g2"])
    g3 = np.array(_L["g3"])
    r1, r2, r3, ds = S.wp_roots(g2, g3)
    assert np.array_equal(ds, _L["dsign"])
    scale = np.maximum(np.abs(_L["e1"]), np.abs(_L["e3"]))
    for got, ref in zip((r1, r2, r3), (_L["e1"], _L["e2"], _L["e3"])):
        # Measured 2.2e-16 relative (e2 = 0 exactly for g3 = 0).
        assert np.all(np.abs(got - np.array(ref)) <= 2 * EPS * np.maximum(np.abs(ref), 1e-300)
                      + 2 * EPS * scale * (np.array(ref) == 0))


def test_wp_roots_conventions():
    e1, e2, e3, ds = wp_roots_kernel(4.0, 1.0)
    assert ds == 1.0 and e1 > e2 > e3 and abs(e1 + e2 + e3) <= 4 * EPS
    a, e2, b, ds = wp_roots_kernel(-2.0, 1.0)
    assert ds == -1.0 and b > 0 and a == -0.5 * e2
    assert abs(4 * e2**3 + 2.0 * e2 - 1.0) <= 8 * EPS
    # e1 = a + ib is a root as well
    z = complex(a, b)
    assert abs(4 * z**3 + 2.0 * z - 1.0) <= 16 * EPS
    assert wp_roots_kernel(3.0, 1.0) == (1.0, -0.5, -0.5, 0.0)
    assert wp_roots_kernel(0.0, 0.0) == (0.0, 0.0, 0.0, 0.0)


def test_wp_half_period_matches_mpmath():
    g2 = np.array(_L["g2"])
    g3 = np.array(_L["g3"])
    om = S.wp_half_period(g2, g3)
    for o, ref in zip(om, _L["omega"]):
        if ref is None:
            assert o == math.inf
        else:
            # Measured: exact to the last bit on the whole set.
            assert abs(o - ref) <= EPS * ref


def _wp_second(p, g2):
    return 6.0 * p * p - 0.5 * g2


def test_wp_matches_mpmath():
    z = np.array(_W["z"])
    g2 = np.array(_W["g2"])
    g3 = np.array(_W["g3"])
    zf = np.abs(np.array(_W["zfrac"]))
    ref_p = np.array(_W["wp"])
    ref_pp = np.array(_W["wpp"])
    p = S.wp(z, g2, g3)
    pp = S.wpp(z, g2, g3)
    r1, r2, r3, ds = S.wp_roots(g2, g3)
    # ℘ = base + (positive term): for Δ < 0 the base e2 may be negative and
    # ℘ crosses zero; there the error is absolute, on the scale of the roots.
    floor_p = np.where(ds < 0, np.abs(r1) + np.abs(r2) + np.abs(r3), 0.0)
    # ℘′ vanishes at z = ω, where ℘ = e_min: absolute floor from an error of
    # a few ulps of ω in the reduced argument times |℘''(ω)|.
    om = S.wp_half_period(g2, g3)
    e_min = np.where(ds < 0, r2, r1)
    with np.errstate(invalid="ignore"):
        floor_pp = np.where(np.isfinite(om), 64 * EPS * om * np.abs(_wp_second(e_min, g2)) / TOL, 0.0)
    # Near-degenerate lattices (0 < |Δ| < 1e-6 g2³) keep the root difference
    # e1 - e2 (or e2 - e3) to double precision only (roots closer than
    # DD_SEP_MIN), so ω is known to ~3e-18 relative instead of ~1e-30; near
    # the poles 2kω the error is amplified by |z| / dist(z, 2kω).
    delta = g2**3 - 27 * g3**2
    near_degenerate = (delta != 0) & (np.abs(delta) < 1e-6 * np.abs(g2) ** 3)
    pole = 2 * np.round(zf / 2)
    dist = np.abs(zf - pole)
    # (℘ ~ dist^-2 and ℘′ ~ dist^-3: relative errors 2 and 3 times the
    # relative error of the pole position 2kω.)
    amp = np.where(near_degenerate & (pole > 0), 3 * 1e-17 * zf / np.maximum(dist, 1e-300), 0.0)
    e_p = rel_err(p, ref_p, floor_p)
    e_pp = rel_err(pp, ref_pp, floor_pp)
    # Measured, outside the near-degenerate near-pole points: 3.8e-15 for ℘
    # (2.7e-13 relative at a zero of ℘ for (g2, g3) = (-2, -1), i.e. 4e-16 of
    # the root scale) and 1.6e-15 for ℘′; 8.9e-16 (℘) and 1.3e-15 (℘′) next to the poles
    # (z = (2 ± 1e-6) ω, (4 + 1e-7) ω) and 3.5e-15 at z ~ 1000 ω.  Near-
    # degenerate lattice (3, -1 + 2^-40): ℘ off by 1.1e-11 at (2 ± 1e-6) ω and
    # 2.2e-10 at (4 + 1e-7) ω (℘′ 3.3e-10), i.e. ω off by ~3e-18 relative.
    assert np.all(e_p <= TOL + amp), (z[np.argmax(e_p - amp)], np.max(e_p - amp))
    assert np.all(e_pp <= TOL + amp), (z[np.argmax(e_pp - amp)], np.max(e_pp - amp))


def test_wp_pole_at_zero():
    for g2, g3 in ((4.0, 1.0), (-2.0, 1.0), (3.0, -1.0), (0.0, 0.0)):
        assert wp_kernel(0.0, g2, g3) == (math.inf, -math.inf)
        assert wp_kernel(-0.0, g2, g3) == (math.inf, math.inf)
        p, pp = wp_kernel(1e-160, g2, g3)
        assert p == math.inf and pp == -math.inf  # overflow, correct sign
        p, pp = wp_kernel(1e-100, g2, g3)
        assert abs(p * 1e-200 - 1) <= 4 * EPS and abs(pp * 1e-300 / -2 - 1) <= 4 * EPS


@pytest.mark.parametrize("g2, g3", [(4.0, 1.0), (-2.0, 1.0), (0.0, -1.0), (3.0, -1.0), (12.0, 8.0),
                                    (1e-3, 2e-5), (37.5, -12.25), (0.0, 0.0), (1e6, 3e8)])
def test_wp_differential_equation(g2, g3):
    om = S.wp_half_period(g2, g3)
    span = om if math.isfinite(om) else 3.0
    z = np.linspace(-7.3, 7.3, 301) * span + 0.0137 * span
    p, pp = S.wp(z, g2, g3), S.wpp(z, g2, g3)
    lhs = pp * pp
    rhs = 4 * p**3 - g2 * p - g3
    scale = pp * pp + 4 * np.abs(p) ** 3 + abs(g2) * np.abs(p) + abs(g3)
    ok = np.isfinite(scale)
    assert np.all(np.abs(lhs - rhs)[ok] <= 16 * EPS * scale[ok])


@pytest.mark.parametrize("g2, g3", [(4.0, 1.0), (4.0, -1.0), (-2.0, 1.0), (-2.0, -1.0), (0.0, 1.0),
                                    (3.0, 1.0), (3.0, -1.0), (1e-3, 2e-5), (37.5, -12.25), (0.0, 0.0)])
def test_wp_inverse_roundtrip(g2, g3):
    om = S.wp_half_period(g2, g3)
    span = om if math.isfinite(om) else 5.0
    z = np.linspace(0.001, 0.95, 60) * span
    p = S.wp(z, g2, g3)
    back = S.wp_inverse(p, g2, g3)
    pp = np.abs(S.wpp(z, g2, g3))
    r1, r2, r3, ds = S.wp_roots(g2, g3)
    base = abs(r2) if ds < 0 else abs(r1)
    # error of w (a few ulps of |℘| + |base|) divided by the slope |℘′|
    bound = TOL * z + 16 * EPS * (np.abs(p) + base) / pp
    assert np.all(np.abs(back - z) <= bound)
    if math.isfinite(om):
        wmin = r2 if ds < 0 else r1
        assert abs(S.wp_inverse(wmin, g2, g3) - om) <= 1e-13 * om
        assert abs(S.wp(om, g2, g3) - wmin) <= 1e-14 * (abs(wmin) + 1)


@pytest.mark.parametrize("g3", [1.0, -1.0])
def test_wp_continuous_across_zero_discriminant(g3):
    """g2 = 3, g3 = ±1 has Δ = 0; nudge g3 to either side (Δ -> 0±)."""
    g2 = 3.0
    z = np.array([0.05, 0.3, 0.9, 1.7, 2.6])
    p0 = S.wp(z, g2, g3)
    pp0 = S.wpp(z, g2, g3)
    # derivative along g3, from a finite difference well away from Δ = 0
    h = 1e-6
    dp = np.abs(S.wp(z, g2, g3 + h) - S.wp(z, g2, g3 - h)) / (2 * h)
    dpp = np.abs(S.wpp(z, g2, g3 + h) - S.wpp(z, g2, g3 - h)) / (2 * h)
    for k in (20, 30, 40, 50):
        for sgn in (1.0, -1.0):
            d = sgn * 2.0**-k
            g3d = g3 + d
            assert np.sign(g2**3 - 27 * g3d**2) != 0
            p = S.wp(z, g2, g3d)
            assert np.all(np.abs(p - p0) <= 2 * dp * abs(d) + 1e-14 * np.abs(p0))
            pp = S.wpp(z, g2, g3d)
            assert np.all(np.abs(pp - pp0) <= 2 * dpp * abs(d) + 1e-14 * np.abs(pp0))
    om0 = S.wp_half_period(g2, g3)
    if g3 > 0:
        for d in (2.0**-40, -(2.0**-40)):
            assert abs(S.wp_half_period(g2, g3 + d) - om0) <= 1e-10 * om0
    else:
        assert om0 == math.inf
        # log-divergent from both sides
        for sgn in (1.0, -1.0):
            om = [S.wp_half_period(g2, g3 + sgn * 2.0**-k) for k in (20, 30, 40, 50)]
            assert om[0] > 4 and np.all(np.diff(om) > 0.5)


# ---------------------------------------------------------------------------
# Public API: broadcasting, scalars, validation
# ---------------------------------------------------------------------------


def test_scalar_in_float_out_and_broadcasting():
    assert type(S.sn(0.3, 0.5)) is float
    assert type(S.ellipk(0.5)) is float
    assert type(S.wp(0.3, 4.0, 1.0)) is float
    out = S.cn(np.zeros((3, 1)) + 0.2, np.array([0.1, 0.5, 0.9]))
    assert out.shape == (3, 3)
    s, c, d, a = S.ellipj([0.1, 0.2], 0.5, 0.5)
    assert s.shape == (2,)
    assert S.am(0.3, 0.5) == S.ellipj(0.3, 0.5)[3]
    assert S.dn(0.3, 0.5) == S.ellipj(0.3, 0.5)[2]
    assert S.wp(np.ones((2, 2)), 4.0, [1.0, -1.0]).shape == (2, 2)
    assert S.wp_half_period([4.0, 3.0], [1.0, -1.0]).shape == (2,)


def test_validation_errors():
    with pytest.raises(ValueError, match="m must be < 1"):
        S.ellipk(1.0)
    with pytest.raises(ValueError, match="m must be < 1"):
        S.ellipk(2.0)
    with pytest.raises(ValueError, match="mc must equal 1 - m"):
        S.sn(0.3, 0.5, 0.4)
    with pytest.raises(ValueError, match="u must be finite"):
        S.sn(np.inf, 0.5)
    with pytest.raises(ValueError, match="m must be finite"):
        S.cn(0.3, np.nan)
    with pytest.raises(ValueError, match="phi outside the real domain"):
        S.ellipf(1.2, 4.0)
    with pytest.raises(ValueError, match="phi outside the real domain"):
        S.ellipf(2.0, 1.0, 0.0)
    with pytest.raises(ValueError, match="z must be finite"):
        S.wp(np.nan, 4.0, 1.0)
    with pytest.raises(ValueError, match="w must be >= min"):
        S.wp_inverse(0.5, 4.0, 1.0)
    with pytest.raises(ValueError, match="w must be >= min"):
        S.wp_inverse(-1.0, 0.0, 0.0)
    # mc given more accurately than 1 - m is accepted, and it is what counts
    # (fl(1 - 1e-15) = 1 - 0.99920e-15; m = 1.0 with mc = 1e-17 is not m = 1)
    assert S.sn(1.0, 1.0 - 1e-15, 1e-15) != S.sn(1.0, 1.0 - 1e-15)
    assert S.cn(30.0, 1.0, 1e-17) != S.cn(30.0, 1.0, 0.0)


def test_huge_arguments_stay_finite():
    """Beyond 2**52 periods no accuracy is possible, but never NaN."""
    u = np.array([1e17, -3e200, 1e300, -1.7e308])
    for m in (0.5, 1.0 - 1e-15, -3.0, -1e300, 7.0, 1e300, 1.0):
        for x in S.ellipj(u, m):
            assert np.all(np.isfinite(x))
    assert np.all(np.isfinite(S.ellipf(u[:3], 0.3)))
    for g2, g3 in ((4.0, 1.0), (-2.0, 1.0), (3.0, -1.0), (3.0, 1.0)):
        assert np.all(np.isfinite(S.wp(u, g2, g3))) and np.all(np.isfinite(S.wpp(u, g2, g3)))


def test_kernels_nan_and_domain_conventions():
    assert math.isnan(ellipk_kernel(2.0, -1.0))
    assert ellipk_kernel(1.0, 0.0) == math.inf
    assert math.isnan(ellipf_kernel(1.2, 4.0, -3.0))
    assert math.isnan(ellipf_kernel(2.0, 1.0, 0.0))
    assert all(math.isnan(x) for x in ellipj_kernel(math.nan, 0.5, 0.5))
    assert math.isnan(wp_inverse_kernel(0.0, 4.0, 1.0))
    assert wp_inverse_kernel(0.5, 3.0, -1.0) == math.inf  # infimum 0.5 reached at infinity
    assert wp_half_period_kernel(0.0, 0.0) == math.inf


def test_kernels_callable_from_user_numba_code():
    @numba.njit
    def use(u, m, mc, g2, g3):
        s, c, d, a = ellipj_kernel(u, m, mc)
        k = ellipk_kernel(m, mc)
        f = ellipf_kernel(a, m, mc)
        p, pp = wp_kernel(u, g2, g3)
        e1, e2, e3, ds = wp_roots_kernel(g2, g3)
        om = wp_half_period_kernel(g2, g3)
        z = wp_inverse_kernel(p, g2, g3)
        return s + c + d + a + k + f + p + pp + e1 + e2 + e3 + ds + om + z

    assert math.isfinite(use(0.4, 0.3, 0.7, 4.0, 1.0))


def test_wp_lattice_split_is_bit_identical():
    for g2, g3 in ((4.0, 1.0), (-2.0, 1.0), (3.0, -1.0), (0.0, 0.0)):
        lat = wp_lattice_kernel(g2, g3)
        for z in (0.0, 1e-3, 0.7, -2.9, 41.0):
            assert wp_eval_kernel(z, lat) == wp_kernel(z, g2, g3)


# ---------------------------------------------------------------------------
# Double-double building blocks: the one K(m), sin/cos, the 2π reduction
# ---------------------------------------------------------------------------


def test_ellipk_dd_kernel():
    with mp.workdps(360):  # 1 − mc must be exact for mc = 1e-300
        # 3e-281 and 1e-275: between dd_sqrt's rescale threshold (DD_TINY = 1e-270) and
        # the 1e-280 the exact flow used to apply itself before it shared this K
        assert DD_TINY == 1e-270
        for mc in (1.0, 0.5, 1e-3, 3.7e-33, 1e-275, 3e-281, 1e-300, 4.0):
            hi, lo = ellipk_dd_kernel(mc, 0.0)
            K = mp.ellipk(1 - mp.mpf(mc))
            assert abs((mp.mpf(hi) + lo) / K - 1) < 1e-30, mc
            # one K: the double kernel is its high part, the k' entry point the same bits
            assert ellipk_kernel(1.0 - mc, mc) == hi
            assert ellipk_kc_dd_kernel(*dd_sqrt(mc, 0.0)) == (hi, lo)
        # the low part of mc counts (the flow passes 1 − m as a double-double)
        hi, lo = ellipk_dd_kernel(1e-20, 3e-37)
        K = mp.ellipk(1 - (mp.mpf(1e-20) + mp.mpf(3e-37)))
        assert abs((mp.mpf(hi) + lo) / K - 1) < 1e-30
    assert ellipk_dd_kernel(0.0, 0.0) == (math.inf, 0.0)
    assert all(math.isnan(x) for x in ellipk_dd_kernel(-1.0, 0.0))
    assert all(math.isnan(x) for x in ellipk_dd_kernel(math.nan, 0.0))


def test_dd_sincos():
    with mp.workdps(50):
        for x in (1e-9, 0.3, 1.0, 1.5707963267948966, -1.2):
            sh, sl, ch, cl = dd_sincos(x, 0.0)
            assert abs(mp.mpf(sh) + sl - mp.sin(mp.mpf(x))) < 1e-31
            assert abs(mp.mpf(ch) + cl - mp.cos(mp.mpf(x))) < 1e-31


def test_reduce_2pi():
    with mp.workdps(60):
        two_pi = 2 * mp.pi
        for x in (0.5, -3.0, 3.2, -7.0, 100.0, 12345.678, -9.87e6, 1e12, -1e15):
            j, hi, lo = reduce_2pi(x)
            assert j == float(j) and abs(hi + lo) <= math.pi
            exact = mp.mpf(x) - j * two_pi
            # ~1e-32 relative to |x| (j·2π's double-double error), far below ulp(hi)
            assert abs(mp.mpf(hi) + lo - exact) <= 1e-31 * max(1.0, abs(x)), x
    assert reduce_2pi(0.25) == (0.0, 0.25, 0.0)
    # fl(π) < π: the rounded quotient says j = 1, the remainder is brought back into
    # [−π, π]: the state stays in its own well
    j, hi, lo = reduce_2pi(PI_HI)
    assert j == 0.0 and hi == PI_HI and abs(lo) < 1e-31
    j, hi, lo = reduce_2pi(TWO_PI_HI)
    assert j == 1.0 and hi == -TWO_PI_LO and lo == 0.0


# ---------------------------------------------------------------------------
# Property tests
# ---------------------------------------------------------------------------

finite_u = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False)


@FAST
@given(u=finite_u, m=st.floats(min_value=-1e4, max_value=1e4, allow_nan=False))
def test_ellipj_property_finite_and_identities(u, m):
    mc = 1.0 - m
    s, c, d, a = ellipj_kernel(u, m, mc)
    assert all(math.isfinite(x) for x in (s, c, d, a))
    assert abs(s * s + c * c - 1.0) <= 8 * EPS
    assert abs(d * d + m * s * s - 1.0) <= 8 * EPS * (1.0 + abs(m) * s * s)
    # am is odd and (for m <= 1) monotone
    assert ellipj_kernel(-u, m, mc)[3] == -a
    if mc > 0 and u < 1e6 - 1:
        assert ellipj_kernel(u + 0.5, m, mc)[3] > a


@FAST
@given(mc=st.floats(min_value=1e-300, max_value=1.0), frac=st.floats(min_value=-1.0, max_value=1.0))
def test_ellipj_property_near_one(mc, frac):
    m = 1.0 - mc
    K = ellipk_kernel(m, mc)
    u = frac * K
    s, c, d, a = ellipj_kernel(u, m, mc)
    assert abs(s * s + c * c - 1.0) <= 8 * EPS
    # dn^2 = cn^2 + mc sn^2 checks the small values relatively
    assert abs(d * d - (c * c + mc * s * s)) <= 8 * EPS * d * d
    back = ellipf_kernel(a, m, mc)
    assert abs(back - u) <= TOL * abs(u) + 8 * EPS * abs(a) / d + 1e-300


@FAST
@given(phi=st.floats(min_value=-1e5, max_value=1e5, allow_nan=False),
       m=st.floats(min_value=-1e4, max_value=1.0, exclude_max=True))
def test_ellipf_property_quasi_periodic(phi, m):
    mc = 1.0 - m
    f = ellipf_kernel(phi, m, mc)
    assert math.isfinite(f)
    K = ellipk_kernel(m, mc)
    g = ellipf_kernel(phi + math.pi, m, mc)
    assert abs(g - f - 2 * K) <= 1e-12 * (abs(f) + K) + 4 * EPS * abs(phi) * math.sqrt(max(1.0, -m))


invariant = st.floats(min_value=-1e3, max_value=1e3, allow_nan=False)


@FAST
@given(g2=invariant, g3=invariant, frac=st.floats(min_value=0.02, max_value=1.98))
def test_wp_property_finite_and_ode(g2, g3, frac):
    assume(abs(g2) + abs(g3) > 1e-6)
    om = wp_half_period_kernel(g2, g3)
    span = om if math.isfinite(om) else 1.0 / max(abs(g2), abs(g3)) ** 0.25
    z = frac * span
    p, pp = wp_kernel(z, g2, g3)
    assert math.isfinite(p) and math.isfinite(pp)
    scale = pp * pp + 4 * abs(p) ** 3 + abs(g2 * p) + abs(g3)
    assert abs(pp * pp - (4 * p**3 - g2 * p - g3)) <= 32 * EPS * scale
    # periodicity
    if math.isfinite(om):
        q, qq = wp_kernel(z + 2 * om, g2, g3)
        r1, r2, r3, ds = wp_roots_kernel(g2, g3)
        assert abs(q - p) <= 1e-12 * (abs(p) + abs(r1) + abs(r2) + abs(r3))


@FAST
@given(g2=invariant, g3=invariant, frac=st.floats(min_value=0.01, max_value=0.9))
def test_wp_property_inverse(g2, g3, frac):
    assume(abs(g2) + abs(g3) > 1e-6)
    om = wp_half_period_kernel(g2, g3)
    assume(math.isfinite(om))
    z = frac * om
    p, pp = wp_kernel(z, g2, g3)
    back = wp_inverse_kernel(p, g2, g3)
    r1, r2, r3, ds = wp_roots_kernel(g2, g3)
    base = abs(r2) if ds < 0 else abs(r1)
    assert abs(back - z) <= TOL * z + 16 * EPS * (abs(p) + base) / abs(pp)
