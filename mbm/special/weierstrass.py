"""Weierstrass ℘ on the real axis for real invariants g2, g3.

Two layers, as in :mod:`mbm.special.jacobi`: scalar numba kernels
(``wp_roots_kernel``, ``wp_kernel``, ``wp_half_period_kernel``,
``wp_inverse_kernel``) and numpy-level wrappers (``wp_roots``, ``wp``, ``wpp``,
``wp_half_period``, ``wp_inverse``).

Conventions
-----------
Δ = g2³ − 27 g3² (computed in double-double, so its sign is exact up to a
relative 1e-32).  The roots of 4x³ − g2 x − g3 are e1, e2, e3:

* Δ ≥ 0 (g2 > 0): three real roots e1 ≥ e2 ≥ e3 (with multiplicity at Δ = 0).
  ℘(z) = e1 + (e1 − e3) cn²/sn²(√(e1 − e3) z | m), m = (e2 − e3)/(e1 − e3),
  which is e3 + (e1 − e3)/sn² written so that both terms are ≥ 0.
* Δ < 0: one real root e2 and e1 = a + i b, e3 = a − i b with b > 0,
  a = −e2/2.  With H = |e1 − e2| = sqrt(3 e2² − g2/4) and
  m = 1/2 − 3 e2/(4H) (A&S §18.9, rewritten by the half-argument formulas)
  ℘(z) = e2 + H cn²/(sn² dn²)(√H z | m).
* g2 = g3 = 0: ℘(z) = 1/z², no real period (half-period = inf).

Δ = 0 is the m = 0 (g3 > 0, trigonometric) or m = 1 (g3 < 0, hyperbolic,
half-period = inf) end of the Δ > 0 formula; the Δ < 0 formula tends to the
same functions, so ℘ is continuous across Δ = 0 from both sides.

Accuracy
--------
The roots are computed in a scaled copy of the cubic (g2/t², g3/t³ with t a
power of 4, exact).  Δ ≥ 0: trigonometric method with the angle from
atan2(sqrt(Δ), ·) (Δ in double-double, so the formulas stay accurate next to
a double root) and the root differences from sine formulas, free of
cancellation.  Δ < 0: Cardano with the cancellation-free choice of cube root
and one Newton step.  Then one Newton step with the cubic evaluated in
double-double on every root that is not part of a close pair.  The lattice
data that fix the period (the scale √(e1 − e3) or √H and the complementary
parameter mc) are carried in double-double, so the argument reduction of z
is accurate far from the origin and next to the poles z = 2kω, where sn is
evaluated with relative accuracy.  Exception: when two roots are closer than
DD_SEP_MIN (relative to the root scale; |Δ| ≲ 1e-6 g2³) their difference,
and with it ω, is known to ~eps/(2K) only (~3e-18 measured), which shows
next to the far poles (2.2e-10 at z = (4 + 1e-7) ω, g2 = 3, g3 = −1 + 2⁻⁴⁰).
"""

import collections
import math

import numba
import numpy as np

from ._arrays import finite_f64, flat, unflat
from .dd import (
    EPS,
    dd_add,
    dd_div,
    dd_mul,
    dd_mul_d,
    dd_mul_safe,
    dd_sqrt,
    fast_two_sum,
    two_prod,
)
from .jacobi import (
    carlson_rf_kernel,
    ellipf_kernel,
    ellipj_kc_dd_kernel,
    ellipk_kc_dd_kernel,
)
from ..compile.jit import NJIT_OPTIONS, kernel

__all__ = [
    "wp_roots_kernel",
    "wp_kernel",
    "wp_lattice_kernel",
    "Lattice",
    "wp_eval_kernel",
    "wp_half_period_kernel",
    "wp_inverse_kernel",
    "wp_roots",
    "wp",
    "wpp",
    "wp_half_period",
    "wp_inverse",
]

# ---------------------------------------------------------------------------
# Tuning constants
# ---------------------------------------------------------------------------

# Roots closer than this use the sine-formula differences: the double-double Newton
# step would leave ~eps^2/sep^4 relative error (5e-20 here), and worse below.
DD_SEP_MIN = 1e-3

# Larger Newton corrections only happen next to a double root, where Newton is unreliable.
NEWTON_MAX_STEP = 1e-10

# wp_inverse: w this many ulps below the minimum of ℘ is forward rounding noise, clamped.
INVERSE_CLAMP_ULPS = 16.0

_SQRT3 = 1.7320508075688772
_SQRT27 = 5.196152422706632
_SQRT1728 = 41.569219381653056
_PI_3 = 1.0471975511965979
_LOG4 = 1.3862943611198906



# ---------------------------------------------------------------------------
# Roots and lattice data
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def _delta_dd(g2, g3):
    """Δ = g2³ − 27 g3² in double-double."""
    sh, sl = two_prod(g2, g2)
    ch, cl = dd_mul_d(sh, sl, g2)
    th, tl = two_prod(g3, g3)
    th, tl = dd_mul_d(th, tl, 27.0)
    return dd_add(ch, cl, -th, -tl)


@kernel(error_model="numpy")
def _newton(x, g2, g3):
    """One guarded Newton step on 4x³ − g2 x − g3 (double)."""
    fp = 12.0 * x * x - g2
    if fp == 0.0:
        return x
    dx = ((4.0 * x * x - g2) * x - g3) / fp
    if abs(dx) <= NEWTON_MAX_STEP * max(1.0, abs(x)):
        return x - dx
    return x


@kernel(error_model="numpy")
def _newton_dd(x, g2, g3):
    """x + correction as a double-double: Newton with the cubic in double-double."""
    fp = 12.0 * x * x - g2
    if fp == 0.0:
        return x, 0.0
    x2h, x2l = two_prod(x, x)
    x3h, x3l = dd_mul_d(x2h, x2l, x)
    bh, bl = two_prod(g2, x)
    fh, fl = dd_add(4.0 * x3h, 4.0 * x3l, -bh, -bl)
    fh, fl = dd_add(fh, fl, -g3, 0.0)
    dx = fh / fp
    if abs(dx) <= NEWTON_MAX_STEP * max(1.0, abs(x)):
        return fast_two_sum(x, -dx)
    return x, 0.0


#: wp_lattice_kernel's result: the lattice data of ℘(·; g2, g3), fields as documented there.
Lattice = collections.namedtuple(
    "Lattice", ("kind", "r1", "r2", "r3", "dsign", "base", "lam2", "lamh", "laml", "m", "mc", "kch", "kcl"))


@kernel(error_model="numpy")
def _lattice_three_real(G2, G3, dh, t, rt):
    """:func:`wp_lattice_kernel` for Δ ≥ 0 (three real roots), at the scaled invariants.

    ``G2, G3`` are g2, g3 scaled by t = 4**k, ``dh`` the high part of their Δ,
    ``rt`` = sqrt(t); returns the :data:`Lattice` of :func:`wp_lattice_kernel`.
    """
    # Trigonometric method: e = 2 r cos(angle), r = sqrt(G2/12),
    # cos(3 alpha) = c = sqrt(27) G3 / G2^1.5, sin(3 alpha) = s = sqrt(Δ)/G2^1.5.
    dsign = 1.0 if dh > 0.0 else 0.0
    g15 = G2 * math.sqrt(G2)
    c = _SQRT27 * G3 / g15
    s = math.sqrt(dh) / g15
    r = math.sqrt(G2 / 12.0)
    alpha = math.atan2(s, c) / 3.0  # in [0, pi/3]
    beta = math.atan2(s, -c) / 3.0  # pi/3 - alpha, without cancellation
    gamma = math.atan2(-c, s) / 3.0  # alpha - pi/6, without cancellation
    # No Newton step in double here: next to a double root it would
    # trade the ~eps accuracy of these formulas (they see the exact Δ)
    # for ~eps/separation.
    if dsign != 0.0:
        e1 = 2.0 * r * math.cos(alpha)
        e2 = 2.0 * r * math.sin(gamma)  # relatively accurate when e2 ~ 0
        e3 = -2.0 * r * math.cos(beta)
        w = 2.0 * _SQRT3 * r
        d13 = w * math.sin(alpha + _PI_3)
        d23 = w * math.sin(alpha)
        d12 = w * math.sin(beta)
    elif G3 > 0.0:
        # Δ = 0 exactly: the double root is -r (the angles are 0 and pi/3).
        e1 = 2.0 * r
        e2 = -r
        e3 = -r
        d13 = 3.0 * r
        d23 = 0.0
        d12 = d13
    else:
        e1 = r
        e2 = r
        e3 = -2.0 * r
        d13 = 3.0 * r
        d23 = d13
        d12 = 0.0
    if d12 >= DD_SEP_MIN and d23 >= DD_SEP_MIN:
        # Well separated: one Newton step with the cubic in double-double
        # gives roots, hence differences, to ~1e-30.
        e1h, e1l = _newton_dd(e1, G2, G3)
        e2h, e2l = _newton_dd(e2, G2, G3)
        e3h, e3l = _newton_dd(e3, G2, G3)
        D13h, D13l = dd_add(e1h, e1l, -e3h, -e3l)
        D12h, D12l = dd_add(e1h, e1l, -e2h, -e2l)
        e1 = e1h
        e2 = e2h
        e3 = e3h
    elif d23 < DD_SEP_MIN:
        # e2 ~ e3: e1 is simple and well separated; e2 + e3 = -e1 gives
        # D13 = 3 e1/2 + d23/2 and D12 = 3 e1/2 - d23/2 (d23 tiny).
        e1h, e1l = _newton_dd(e1, G2, G3)
        fh, fl = dd_mul_d(e1h, e1l, 1.5)
        D13h, D13l = dd_add(fh, fl, 0.5 * d23, 0.0)
        D12h, D12l = dd_add(fh, fl, -0.5 * d23, 0.0)
        e1 = e1h
    else:
        # e1 ~ e2: e3 is simple; D13 = -3 e3/2 + d12/2, D12 = d12 (tiny,
        # it enters K only logarithmically).
        e3h, e3l = _newton_dd(e3, G2, G3)
        fh, fl = dd_mul_d(e3h, e3l, -1.5)
        D13h, D13l = dd_add(fh, fl, 0.5 * d12, 0.0)
        D12h, D12l = d12, 0.0
        e3 = e3h
    mch, mcl = dd_div(D12h, D12l, D13h, D13l)
    m = d23 / d13
    mc = mch
    kch, kcl = dd_sqrt(mch, mcl)
    lh, ll = dd_sqrt(D13h, D13l)
    return Lattice(1.0, e1 * t, e2 * t, e3 * t, dsign, e1 * t, d13 * t,
                   lh * rt, ll * rt, m, mc, kch, kcl)


@kernel(error_model="numpy")
def _lattice_one_real(G2, G3, dh, dl, t, rt):
    """:func:`wp_lattice_kernel` for Δ < 0 (one real root), at the scaled invariants.

    ``G2, G3`` are g2, g3 scaled by t = 4**k, ``(dh, dl)`` their Δ as a
    double-double, ``rt`` = sqrt(t); returns the :data:`Lattice` of :func:`wp_lattice_kernel`.
    """
    # Δ < 0: Cardano for x³ + p x + q, p = −G2/4, q = −G3/4, with the cube
    # root of the larger-magnitude term (no cancellation) ...
    p = -0.25 * G2
    q = -0.25 * G3
    sqrtD = math.sqrt(-dh) / _SQRT1728  # sqrt(q²/4 + p³/27) = sqrt(−Δ/1728)
    A = math.pow(0.5 * abs(q) + sqrtD, 1.0 / 3.0)
    if q > 0.0:
        A = -A
    B = -p / (3.0 * A)
    if p >= 0.0:
        # ... and, when A and B have opposite signs, A + B from
        # (A³ + B³)/(A² − AB + B²) with −AB = p/3 > 0.
        e2 = -q / (A * A + B * B + p / 3.0)
    else:
        e2 = A + B
    e2 = _newton(e2, G2, G3)
    e2h, e2l = _newton_dd(e2, G2, G3)
    # H² = |e1 − e2|² = 3 e2² − G2/4 = (3 e2/2)² + b² (>= 9 e2²/4: mild cancellation at most).
    sqh, sql = dd_mul(e2h, e2l, e2h, e2l)
    s3h, s3l = dd_mul_d(sqh, sql, 3.0)  # (scaling by 3 is not exact: use the dd product)
    H2h, H2l = dd_add(s3h, s3l, -0.25 * G2, 0.0)
    if G2 <= 0.0:
        # b² = (3 e2² − G2)/4: a sum of non-negative terms.
        b2h, b2l = dd_add(0.25 * s3h, 0.25 * s3l, -0.25 * G2, 0.0)
    else:
        # b² = −Δ / (64 H⁴) (the discriminant is −4 b² H⁴ · 16): exact in
        # relative terms even as b -> 0 (Δ -> 0−), where 3 e2² − G2 cancels.
        h4h, h4l = dd_mul(H2h, H2l, H2h, H2l)
        b2h, b2l = dd_div(-dh, -dl, 64.0 * h4h, 64.0 * h4l)
    Hh, Hl = dd_sqrt(H2h, H2l)
    # m = 1/2 − 3e2/(4H), mc = 1/2 + 3e2/(4H); the one that would cancel is
    # rewritten with (2H − 3e2)(2H + 3e2) = 4 b².
    t3h, t3l = dd_mul_d(e2h, e2l, 3.0)
    if e2h >= 0.0:
        Dh, Dl = dd_add(2.0 * Hh, 2.0 * Hl, t3h, t3l)  # 2H + 3 e2
        xh, xl = dd_mul(Hh, Hl, Dh, Dl)
        m_h, m_l = dd_div(b2h, b2l, xh, xl)
        mch, mcl = dd_div(Dh, Dl, 4.0 * Hh, 4.0 * Hl)
    else:
        Dh, Dl = dd_add(2.0 * Hh, 2.0 * Hl, -t3h, -t3l)  # 2H − 3 e2
        xh, xl = dd_mul(Hh, Hl, Dh, Dl)
        mch, mcl = dd_div(b2h, b2l, xh, xl)
        m_h, m_l = dd_div(Dh, Dl, 4.0 * Hh, 4.0 * Hl)
    kch, kcl = dd_sqrt(mch, mcl)
    lh, ll = dd_sqrt(Hh, Hl)  # the argument scale is sqrt(H)
    b = math.sqrt(b2h)
    return Lattice(-1.0, -0.5 * e2 * t, e2 * t, b * t, -1.0, e2 * t, Hh * t,
                   lh * rt, ll * rt, m_h, mch, kch, kcl)


@numba.njit(**NJIT_OPTIONS)
def wp_lattice_kernel(g2, g3):
    """Lattice data of ℘(·; g2, g3): everything ℘ needs, from the invariants.

    ``wp_kernel(z, g2, g3)`` spends roughly half of its time deriving the
    roots and the period from (g2, g3); a caller evaluating many z for the
    same invariants can do that once and pass the tuple to ``wp_eval_kernel``.
    Callers that need the roots' normal form itself (the cn form of
    :mod:`mbm.approximants.salas2022`) unpack it.

    Returns
    -------
    Lattice
        A named tuple of 13 floats ``(kind, r1, r2, r3, dsign, base, lam2, lamh, laml,
        m, mc, kch, kcl)``:

        * ``kind``: 1.0 (Δ ≥ 0), -1.0 (Δ < 0) or 0.0 (g2 = g3 = 0); NaNs for
          non-finite invariants;
        * ``r1, r2, r3, dsign``: what ``wp_roots_kernel`` returns;
        * ``base, lam2``: ℘ = base + lam2 * X with X = cn²/sn² (kind 1) or
          cn²/(sn² dn²) (kind −1) at v = lam * z;
        * ``lamh, laml``: lam = sqrt(lam2) as a double-double;
        * ``m, mc``: the parameter of the Jacobi functions and its complement;
        * ``kch, kcl``: k' = sqrt(mc) as a double-double (fixes the period).
    """
    nan = math.nan
    if not (abs(g2) < math.inf and abs(g3) < math.inf):
        return Lattice(nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan, nan)
    if g2 == 0.0 and g3 == 0.0:
        return Lattice(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    # Scale by t = 4**k (exact) so that the normalised roots are of order 1;
    # sqrt(t) = 2**k is exact too.
    size = max(math.sqrt(abs(g2)), math.pow(abs(g3), 1.0 / 3.0))
    k = int(math.floor(math.log(size) / _LOG4 + 0.5))
    t = math.ldexp(1.0, 2 * k)
    rt = math.ldexp(1.0, k)
    G2 = math.ldexp(g2, -4 * k)
    G3 = math.ldexp(g3, -6 * k)
    dh, dl = _delta_dd(G2, G3)
    if dh >= 0.0:
        return _lattice_three_real(G2, G3, dh, t, rt)
    return _lattice_one_real(G2, G3, dh, dl, t, rt)


@numba.njit(**NJIT_OPTIONS)
def wp_roots_kernel(g2, g3):
    """Roots of 4x³ − g2 x − g3, numba kernel.

    Parameters
    ----------
    g2, g3 : float
        Real invariants.

    Returns
    -------
    r1, r2, r3, delta_sign : float
        * Δ = g2³ − 27 g3² > 0: ``(e1, e2, e3, 1.0)``, e1 > e2 > e3 real.
        * Δ = 0 (exactly, in double-double), g2 > 0: ``(e1, e2, e3, 0.0)``
          with a double root (e2 = e3 if g3 > 0, e1 = e2 if g3 < 0).
        * Δ < 0: ``(Re e1, e2, Im e1, -1.0)``: e2 is the real root and
          e1 = Re e1 + i Im e1, e3 = conj(e1), with Im e1 > 0 and
          Re e1 = −e2/2.
        * g2 = g3 = 0: ``(0.0, 0.0, 0.0, 0.0)``.
        Non-finite input gives NaNs.
    """
    lat = wp_lattice_kernel(g2, g3)
    return lat.r1, lat.r2, lat.r3, lat.dsign


@numba.njit(**NJIT_OPTIONS)
def wp_eval_kernel(z, lattice):
    """``wp_kernel`` with the lattice data precomputed by ``wp_lattice_kernel``.

    Returns
    -------
    wp, wpprime : float
        Bit-for-bit what ``wp_kernel(z, g2, g3)`` returns.
    """
    kind, r1, r2, r3, ds, base, lam2, lh, ll, m, mc, kch, kcl = lattice
    if kind == 0.0:
        if z == 0.0:
            return math.inf, -math.copysign(math.inf, z)
        zi = 1.0 / z
        return zi * zi, -2.0 * zi * zi * zi
    if not (kind == kind and abs(z) < math.inf):
        return math.nan, math.nan
    if z == 0.0:
        return math.inf, -math.copysign(math.inf, z)
    vh, vl = dd_mul_safe(lh, ll, z, 0.0)
    if mc == 0.0:
        # Δ = 0 with g3 < 0: m = 1, sn = tanh, cn = dn = sech.
        # First order in the low part keeps sech(v) ~ 2 exp(-v) relatively
        # accurate for large v.
        th = math.tanh(vh)
        cn = (1.0 - th * vl) / math.cosh(vh)
        sn = th + cn * cn * vl
        dn = cn
    else:
        sn, cn, dn, n, a = ellipj_kc_dd_kernel(vh, vl, m, mc, kch, kcl)
    if sn == 0.0:
        return math.inf, -math.copysign(math.inf, sn)
    lam3 = lam2 * lh
    if kind > 0.0:
        q = cn / sn
        wp_ = base + lam2 * q * q
        wpp_ = -2.0 * lam3 * q * (dn / sn) / sn
    else:
        q = cn / (sn * dn)
        wp_ = base + lam2 * q * q
        # d/dv [cn/(sn dn)] = −(dn⁴ + m mc sn⁴)/(sn² dn²): all terms >= 0.
        sd = sn * dn
        d2 = dn * dn
        s2 = sn * sn
        wpp_ = -2.0 * lam3 * q * ((d2 * d2 + m * mc * s2 * s2) / sd) / sd
    return wp_, wpp_


@numba.njit(**NJIT_OPTIONS)
def wp_kernel(z, g2, g3):
    """Weierstrass ℘(z; g2, g3) and ℘′ for real z, numba kernel.

    Parameters
    ----------
    z : float
        Real argument.
    g2, g3 : float
        Real invariants, any sign of Δ.

    Returns
    -------
    wp, wpprime : float
        At a pole (z = 0, or z exactly on 2kω after reduction) ``wp = +inf``
        and ``wpprime = -inf`` for z = +0 (the limit from the right,
        ℘′ ~ −2/z³) and ``+inf`` for z = −0.  Values whose magnitude exceeds
        the float range overflow to inf with the correct sign.  Accuracy
        ~1e-15 relative (absolute, on the scale of the roots, next to a zero
        of ℘; relative to |z ℘″| eps next to the zero of ℘′ at z = ω),
        including next to the poles and for |z| up to ~1e3 ω and beyond.
    """
    return wp_eval_kernel(z, wp_lattice_kernel(g2, g3))


@numba.njit(**NJIT_OPTIONS)
def wp_half_period_kernel(g2, g3):
    """Real half-period ω of ℘(·; g2, g3), numba kernel.

    Returns
    -------
    float
        ω with ℘(z + 2ω) = ℘(z) on the real axis: K(m)/sqrt(e1 − e3) for
        Δ > 0, K(m)/sqrt(H) for Δ < 0; ``inf`` when there is no real period
        (g2 = g3 = 0, or Δ = 0 with g3 < 0).
    """
    kind, r1, r2, r3, ds, base, lam2, lh, ll, m, mc, kch, kcl = wp_lattice_kernel(g2, g3)
    if kind == 0.0:
        return math.inf
    if not kind == kind:
        return math.nan
    Kh, Kl = ellipk_kc_dd_kernel(kch, kcl)
    if Kh == math.inf:
        return math.inf
    oh, ol = dd_div(Kh, Kl, lh, ll)
    return oh


@numba.njit(**NJIT_OPTIONS)
def wp_inverse_kernel(w, g2, g3):
    """The z in (0, ω] with ℘(z) = w, numba kernel.

    Parameters
    ----------
    w : float
        Value of ℘, at least the minimum of ℘ on the real axis: e1 for
        Δ >= 0, e2 for Δ < 0, 0 (not attained) for g2 = g3 = 0.
    g2, g3 : float
        Real invariants.

    Returns
    -------
    float
        z in (0, ω]; ``inf`` when w equals an infimum that is only reached at
        infinity (Δ = 0 with g3 < 0); NaN for w below the minimum.

    Notes
    -----
    Δ >= 0: z = R_F(w − e1, w − e2, w − e3) (DLMF §23.6(iv), the integral
    ∫_w^∞ dt/sqrt(4t³ − g2 t − g3)) with w − e2, w − e3 formed from the
    cancellation-free root differences.  Δ < 0: invert
    ℘ = e2 + H (1 + cn 2v)/(1 − cn 2v) through
    am(2v) = atan2(2 sqrt(X), X − 1), X = (w − e2)/H, and F.
    """
    kind, r1, r2, r3, ds, base, lam2, lh, ll, m, mc, kch, kcl = wp_lattice_kernel(g2, g3)
    if not (abs(w) < math.inf and kind == kind):
        return math.nan
    if kind == 0.0:
        if w > 0.0:
            return 1.0 / math.sqrt(w)
        return math.nan
    x = w - base
    if x < 0.0:
        if x >= -INVERSE_CLAMP_ULPS * EPS * (abs(base) + lam2):
            x = 0.0
        else:
            return math.nan
    if kind > 0.0:
        return carlson_rf_kernel(x, x + mc * lam2, x + lam2)
    X = x / lam2
    phi2 = math.atan2(2.0 * math.sqrt(X), (x - lam2) / lam2)
    return ellipf_kernel(phi2, m, mc) / (2.0 * (lh + ll))


# ---------------------------------------------------------------------------
# Array loops (one compiled signature each: 1-D contiguous float64)
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def _wp_loop(z, g2, g3, out_wp, out_wpp):
    for i in range(z.shape[0]):
        a, b = wp_kernel(z[i], g2[i], g3[i])
        out_wp[i] = a
        out_wpp[i] = b


@kernel(error_model="numpy")
def _wp_roots_loop(g2, g3, o1, o2, o3, o4):
    for i in range(g2.shape[0]):
        a, b, c, d = wp_roots_kernel(g2[i], g3[i])
        o1[i] = a
        o2[i] = b
        o3[i] = c
        o4[i] = d


@kernel(error_model="numpy")
def _wp_half_period_loop(g2, g3, out):
    for i in range(g2.shape[0]):
        out[i] = wp_half_period_kernel(g2[i], g3[i])


@kernel(error_model="numpy")
def _wp_inverse_loop(w, g2, g3, out):
    for i in range(w.shape[0]):
        out[i] = wp_inverse_kernel(w[i], g2[i], g3[i])


# ---------------------------------------------------------------------------
# numpy-level wrappers
# ---------------------------------------------------------------------------


def _wp_eval(z, g2, g3):
    za = finite_f64("z", z)
    g2a = finite_f64("g2", g2)
    g3a = finite_f64("g3", g3)
    scalar = za.ndim == 0 and g2a.ndim == 0 and g3a.ndim == 0
    shape, (zf, g2f, g3f) = flat(za, g2a, g3a)
    o1 = np.empty(zf.shape[0])
    o2 = np.empty(zf.shape[0])
    _wp_loop(zf, g2f, g3f, o1, o2)
    if np.isnan(o1).any() or np.isnan(o2).any():
        raise FloatingPointError("wp: internal error, NaN produced from finite input")
    return o1, o2, shape, scalar


def wp(z, g2, g3):
    """Weierstrass elliptic function ℘(z; g2, g3) on the real axis.

    Parameters
    ----------
    z : array_like
        Real argument.
    g2, g3 : array_like
        Real invariants (any sign of Δ = g2³ − 27 g3²).

    Returns
    -------
    float or ndarray
        ℘(z); ``+inf`` at the poles z = 2kω that are hit exactly (z = 0).

    Raises
    ------
    ValueError
        Non-finite input.
    """
    o1, o2, shape, scalar = _wp_eval(z, g2, g3)
    return unflat(o1, shape, scalar)


def wpp(z, g2, g3):
    """Derivative ℘′(z; g2, g3) on the real axis.

    Parameters
    ----------
    z : array_like
        Real argument.
    g2, g3 : array_like
        Real invariants.

    Returns
    -------
    float or ndarray
        ℘′(z) (℘′ ~ −2/z³ at 0: ``-inf`` at z = +0, ``+inf`` at z = −0).

    Raises
    ------
    ValueError
        Non-finite input.
    """
    o1, o2, shape, scalar = _wp_eval(z, g2, g3)
    return unflat(o2, shape, scalar)


def wp_roots(g2, g3):
    """Roots of 4x³ − g2 x − g3 in the convention of ``wp_roots_kernel``.

    Parameters
    ----------
    g2, g3 : array_like
        Real invariants.

    Returns
    -------
    r1, r2, r3, delta_sign : float or ndarray
        Δ >= 0: (e1, e2, e3, sign Δ) with e1 >= e2 >= e3 real.
        Δ < 0: (Re e1, e2, Im e1, -1.0), e2 the real root, e1 = conj(e3)
        with Im e1 > 0.  g2 = g3 = 0: all zero.

    Raises
    ------
    ValueError
        Non-finite input.
    """
    g2a = finite_f64("g2", g2)
    g3a = finite_f64("g3", g3)
    scalar = g2a.ndim == 0 and g3a.ndim == 0
    shape, (g2f, g3f) = flat(g2a, g3a)
    outs = [np.empty(g2f.shape[0]) for _ in range(4)]
    _wp_roots_loop(g2f, g3f, *outs)
    return tuple(unflat(o, shape, scalar) for o in outs)


def wp_half_period(g2, g3):
    """Real half-period ω of ℘(·; g2, g3) (the real period is 2ω).

    Parameters
    ----------
    g2, g3 : array_like
        Real invariants.

    Returns
    -------
    float or ndarray
        ω; ``inf`` where ℘ has no real period (g2 = g3 = 0, or Δ = 0 with
        g3 < 0).

    Raises
    ------
    ValueError
        Non-finite input.
    """
    g2a = finite_f64("g2", g2)
    g3a = finite_f64("g3", g3)
    scalar = g2a.ndim == 0 and g3a.ndim == 0
    shape, (g2f, g3f) = flat(g2a, g3a)
    out = np.empty(g2f.shape[0])
    _wp_half_period_loop(g2f, g3f, out)
    if np.isnan(out).any():
        raise FloatingPointError("wp_half_period: internal error, NaN produced from finite input")
    return unflat(out, shape, scalar)


def wp_inverse(w, g2, g3):
    """Inverse of ℘ on the first half-period: the z in (0, ω] with ℘(z) = w.

    Parameters
    ----------
    w : array_like
        Value of ℘; must be >= the minimum of ℘ on the real axis (e1 when
        Δ >= 0, e2 when Δ < 0, > 0 when g2 = g3 = 0).
    g2, g3 : array_like
        Real invariants.

    Returns
    -------
    float or ndarray
        z in (0, ω]; ``inf`` for w at an infimum reached only at infinity.

    Raises
    ------
    ValueError
        Non-finite input, or w below the minimum of ℘ on the real axis.
    """
    wa = finite_f64("w", w)
    g2a = finite_f64("g2", g2)
    g3a = finite_f64("g3", g3)
    scalar = wa.ndim == 0 and g2a.ndim == 0 and g3a.ndim == 0
    shape, (wf, g2f, g3f) = flat(wa, g2a, g3a)
    out = np.empty(wf.shape[0])
    _wp_inverse_loop(wf, g2f, g3f, out)
    bad = np.isnan(out)
    if bad.any():
        i = np.flatnonzero(bad)[0]
        r1, r2, r3, ds = (float(x) for x in wp_roots_kernel(g2f[i], g3f[i]))
        lo = r2 if ds < 0 else (0.0 if g2f[i] == 0 and g3f[i] == 0 else r1)
        raise ValueError(
            f"w must be >= min of wp on the real axis ({lo!r} for g2={g2f[i]!r}, "
            f"g3={g3f[i]!r}); got w={wf[i]!r}"
        )
    return unflat(out, shape, scalar)
