"""Numba kernels of the Jacobi elliptic functions and integrals (:mod:`mbm.special.jacobi`).

Scalar float64 kernels, meant to be called from other numba code: K(m) and F(φ|m),
sn, cn, dn by the descending Landen transformation, and their double-double
building blocks.  The method is described in :mod:`mbm.special.jacobi`, which holds
the numpy-level wrappers and re-exports these kernels.
"""

import math

import numba
import numpy as np
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from .dd import (
    EPS,
    PI_HI,
    PI_LO,
    PIO2_HI,
    PIO2_LO,
    PIO4,
    TWO_PI_HI,
    TWO_PI_LO,
    dd_add,
    dd_add_pos,
    dd_div,
    dd_gt,
    dd_mul,
    dd_mul_safe,
    dd_sqrt,
    two_prod,
)
from ..compile.jit import kernel


# ---------------------------------------------------------------------------
# Tuning constants
# ---------------------------------------------------------------------------


# End of the Landen chain: the base case keeps O(m), so the O(m**2) remainder is < 1e-18.
LANDEN_M_STOP = 1e-9

# Below this mc the first-order expansion about m = 1 is exact to (k'/4)**2 < 1e-17.
MC_HYPERBOLIC = 1e-16

# Landen levels kept on the stack: 7 are needed at worst (mc just above MC_HYPERBOLIC).
LANDEN_SLOTS = 12
_LANDEN_BUF = 2 * LANDEN_SLOTS

# Double-double AGM stop: A(1 - x^2/4) then finishes to < 1e-32 and saves an iteration.
AGM_DD_RTOL = 1e-8

# Double AGM stop: that K only chooses the fast path, a few digits suffice.
AGM_D_RTOL = 1e-8

# AGM safety cap: mc = 1e-308 or 1e308 needs fewer than 25 iterations.
AGM_MAX_ITER = 64

# |u| <= this * K needs no reduction: Landen on [0, K/2] keeps cn, dn relatively accurate.
FAST_PATH_FRACTION = 0.5

# Carlson R_F start, (3 eps)**(-1/8) (Boost): the 7th-order series remainder is then < eps.
RF_Q_FACTOR = (3.0 * 2.220446049250313e-16) ** (-1.0 / 8.0)

# Carlson duplication safety cap: argument ratios of 1e-300 need about 30.
RF_MAX_ITER = 100

# m > 1: 1 - m sin^2(phi) rounding a few ulps below 0 at the domain edge is clamped to 0.
EDGE_CLAMP_ULPS = 8.0

# Allowed |m + mc - 1| in ulps of max(1, |m|, |mc|): 1 - m rounds, clever callers differ a bit more.
MC_CONSISTENCY_ULPS = 8.0

# Exact (double-double) reduction up to 2**52 periods; beyond, doubles are coarser than a period.
REDUCE_MAX_PERIODS = 2.0**52


# ---------------------------------------------------------------------------
# Stack scratch space
# ---------------------------------------------------------------------------


@intrinsic
def _stack_f64(typingctx, n):
    """Pointer to ``n`` (a literal int) float64 slots on the caller's stack.

    A fixed-size ``alloca`` in the entry block: no heap allocation, no
    reference counting; the memory lives until the calling function returns.
    """
    if not isinstance(n, types.IntegerLiteral):
        return None
    size = n.literal_value
    sig = types.CPointer(types.float64)(n)

    def codegen(context, builder, signature, args):
        return cgutils.alloca_once(builder, context.get_value_type(types.float64), size=size)

    return sig, codegen


# ---------------------------------------------------------------------------
# Complete integral K
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def ellipk_kc_dd_kernel(kch, kcl):
    """K(m) in double-double from the complementary modulus k' = sqrt(1 - m).

    K = pi / (2 AGM(1, k')) (A&S 17.6.1) with the AGM in double-double; it stops
    at a relative gap AGM_DD_RTOL and finishes with AGM(A + d/2, A - d/2) =
    A (1 - x^2/4 - ...), x = d/(2A), so the result carries ~1e-32 relative
    error.  This is the package's one double-double K: the argument
    reductions of :func:`ellipj_kernel`, :func:`ellipf_kernel`,
    :mod:`mbm.special.weierstrass` and :mod:`mbm.special.pendulum_flow` use it.

    Parameters
    ----------
    kch, kcl : float
        k' = kch + kcl >= 0 as a double-double (k' > 1 for m < 0).

    Returns
    -------
    hi, lo : float
        K = hi + lo; ``(inf, 0)`` for k' == 0.
    """
    if kch == 0.0:
        return math.inf, 0.0
    ah = 1.0
    al = 0.0
    bh = kch
    bl = kcl
    for _ in range(AGM_MAX_ITER):
        if abs(ah - bh) <= AGM_DD_RTOL * ah:
            break
        sh, sl = dd_add_pos(ah, al, bh, bl)
        ph, pl = dd_mul(ah, al, bh, bl)
        bh, bl = dd_sqrt(ph, pl)
        ah = 0.5 * sh
        al = 0.5 * sl
    d = (ah - bh) + (al - bl)  # ah - bh is exact (Sterbenz)
    Ah, Al = dd_add_pos(ah, al, bh, bl)
    Ah *= 0.5
    Al *= 0.5
    x = d / (2.0 * Ah)
    x2 = x * x
    # AGM(A + d/2, A - d/2) = A pi / (2 K(x)) = A (1 - x^2/4 - 5 x^4/64 - ...)
    Mh, Ml = dd_add(Ah, Al, -0.25 * Ah * x2, 0.0)
    return dd_div(PIO2_HI, PIO2_LO, Mh, Ml)


@kernel(error_model="numpy")
def ellipk_dd_kernel(mc, mc_lo):
    """K(m) in double-double from the complementary parameter mc = 1 - m.

    :func:`ellipk_kc_dd_kernel` at k' = sqrt(mc) (square root in double-double,
    rescaled for a tiny mc), for callers that hold 1 - m itself, possibly as a
    double-double (the exact pendulum flow next to the separatrix).

    Parameters
    ----------
    mc, mc_lo : float
        1 - m = mc + mc_lo (double-double); mc > 1 (m < 0) is allowed.

    Returns
    -------
    hi, lo : float
        K = hi + lo, ~1e-30 relative down to mc = 1e-308.  ``(inf, 0)`` for
        mc == 0 (m = 1); ``(nan, nan)`` for mc < 0 (K not real) or NaN.
    """
    if mc > 0.0:
        kch, kcl = dd_sqrt(mc, mc_lo)
        return ellipk_kc_dd_kernel(kch, kcl)
    if mc == 0.0:
        return math.inf, 0.0
    return math.nan, math.nan


@kernel(error_model="numpy")
def _ellipk_rough(kc):
    """K to ~8 digits in plain double (used only to pick the fast path)."""
    if kc == 0.0:
        return math.inf
    a = 1.0
    b = kc
    for _ in range(AGM_MAX_ITER):
        if abs(a - b) <= AGM_D_RTOL * a:
            break
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return PIO2_HI / (0.5 * (a + b))


@kernel(error_model="numpy")
def ellipk_kernel(m, mc):
    """Complete elliptic integral of the first kind K(m), numba kernel.

    Parameters
    ----------
    m : float
        Parameter (only its consistency with ``mc`` matters; unused here).
    mc : float
        Complementary parameter 1 - m; must be > 0 for a finite real K.

    Returns
    -------
    float
        K(m), correctly rounded in practice (double-double AGM).  ``inf`` for
        ``mc == 0``; ``nan`` for ``mc < 0`` (m > 1, K not real) or NaN input.
    """
    if mc > 0.0:
        kh, kl = ellipk_dd_kernel(mc, 0.0)
        return kh
    if mc == 0.0:
        return math.inf
    return math.nan


# ---------------------------------------------------------------------------
# sn, cn, dn on [0, K/2]: descending Landen transformation
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def _landen(z, m, mc):
    """(sn, cn, dn)(z | m) for 0 <= z <= K(m)/2, |m| small or 0 <= m < 1.

    ``mc`` must be the accurate complement of ``m``.  For mc <= MC_HYPERBOLIC
    the first-order expansion about m = 1 is used directly.  Otherwise the
    descending Landen chain runs down to m_N <= LANDEN_M_STOP, the base case
    keeps the first-order term in m_N, and the chain is climbed back
    (DLMF §22.7(i)).  Every upward step uses only sums of non-negative terms,
    so the results keep relative accuracy even where cn and dn are tiny.  The
    chain is kept in a fixed-size stack buffer (no heap allocation).
    """
    if mc <= MC_HYPERBOLIC:
        # DLMF §22.10(ii); the O(mc**2) remainder relative to cn, dn is
        # ~(k'/4)**2 on 0 <= z <= K/2.
        ch = math.cosh(z)
        t = math.tanh(z)
        sech = 1.0 / ch
        sc = t * ch * ch  # sinh z cosh z
        q = 0.25 * mc * (sc - z)
        return t + q * sech * sech, sech - q * t * sech, sech + 0.25 * mc * (sc + z) * t * sech
    # Level i keeps k1 in buf[i] and its parameter mc in buf[LANDEN_SLOTS + i].
    buf = numba.carray(_stack_f64(_LANDEN_BUF), _LANDEN_BUF)
    n = 0
    while m > LANDEN_M_STOP and n < LANDEN_SLOTS:
        kc = math.sqrt(mc)
        opk = 1.0 + kc
        inv = 1.0 / opk
        k1 = m * inv * inv  # (1 - k')/(1 + k') without cancellation
        buf[n] = k1
        buf[LANDEN_SLOTS + n] = mc
        z = z * opk * 0.5  # z / (1 + k1)
        m = k1 * k1
        mc = 4.0 * kc * inv * inv  # 1 - k1**2 without cancellation
        n += 1
    s0 = math.sin(z)
    c0 = math.cos(z)
    # First-order term of the expansion in m (DLMF §22.10(ii)).
    t = 0.25 * m * (z - s0 * c0)
    s = s0 - t * c0
    c = c0 + t * s0
    d = 1.0 - 0.5 * m * s0 * s0
    for i in range(n - 1, -1, -1):
        k1 = buf[i]
        r = 1.0 / (1.0 + k1 * s * s)
        s, c = (1.0 + k1) * s * r, c * d * r
        # The upward map doubles any error that leaves the curve
        # s^2 + c^2 = 1 at every level: project back (one Newton step for
        # 1/sqrt, the residual is a few ulps) and take dn from the
        # subtraction-free identity dn^2 = cn^2 + mc sn^2.
        f = 1.5 - 0.5 * (s * s + c * c)
        s *= f
        c *= f
        d = math.sqrt(c * c + buf[LANDEN_SLOTS + i] * s * s)
    return s, c, d


@kernel(error_model="numpy")
def ellipj_kc_dd_kernel(vh, vl, m, mc, kch, kcl):
    """sn, cn, dn at a double-double argument with the period fixed by k', numba kernel.

    For 0 <= m < 1 (mc > 0), reduced by 4K with K from
    :func:`ellipk_kc_dd_kernel` (the workhorse of :func:`ellipj_kernel`, also
    used by :mod:`mbm.special.weierstrass`, whose lattice fixes k' itself).

    Parameters
    ----------
    vh, vl : float
        Argument v = vh + vl (double-double).
    m, mc : float
        Parameter and its accurate complement.
    kch, kcl : float
        k' = sqrt(mc) in double-double (it fixes the period used for the
        reduction).

    Returns
    -------
    sn, cn, dn, n, am_local : float
        n is the number of whole periods 4K removed, and am_local in [-pi, pi]
        the amplitude of the reduced argument, so that am(v) = am_local + 2 pi n.
    """
    av = abs(vh)
    if av <= PIO4 or av <= FAST_PATH_FRACTION * _ellipk_rough(kch):
        # |v| <= K/2 (K >= pi/2 for m >= 0): no reduction needed.
        s, c, d = _landen(av, m, mc)
        s = math.copysign(s, vh)
        return s, c, d, 0.0, math.atan2(s, c)
    Kh, Kl = ellipk_kc_dd_kernel(kch, kcl)
    K4h = 4.0 * Kh
    K4l = 4.0 * Kl
    n = np.floor(vh / K4h + 0.5)
    if abs(n) < REDUCE_MAX_PERIODS:
        ph, pl = two_prod(n, K4h)
        pl += n * K4l
        rh, rl = dd_add(vh, vl, -ph, -pl)
    else:
        # Beyond 2**52 periods the ulp of v exceeds the period: no accuracy
        # is possible; reduce by the double 4K to return something finite.
        rh = np.fmod(vh, K4h)
        rl = 0.0
        n = (vh - rh) / K4h
    # The quotient was rounded in double: fix a reduced argument that landed
    # just outside [-2K, 2K].
    if dd_gt(rh, rl, 2.0 * Kh, 2.0 * Kl):
        rh, rl = dd_add(rh, rl, -K4h, -K4l)
        n += 1.0
    elif dd_gt(-2.0 * Kh, -2.0 * Kl, rh, rl):
        rh, rl = dd_add(rh, rl, K4h, K4l)
        n -= 1.0
    neg = rh < 0.0 or (rh == 0.0 and math.copysign(1.0, rh) < 0.0)
    if neg:
        rh = -rh
        rl = -rl
    flip = dd_gt(rh, rl, Kh, Kl)
    if flip:
        # sn(2K - r) = sn r, cn(2K - r) = -cn r, dn(2K - r) = dn r.
        rh, rl = dd_add(2.0 * Kh, 2.0 * Kl, -rh, -rl)
        if rh < 0.0:
            rh = 0.0
            rl = 0.0
    if rh > 0.5 * Kh:
        # Quarter-period shift: cn and dn near K computed from sn(t), dn(t).
        th, tl = dd_add(Kh, Kl, -rh, -rl)
        if th < 0.0:
            th = 0.0
        s, c, d = _landen(th, m, mc)
        sn_ = c / d
        cn_ = kch * s / d
        dn_ = kch / d
    else:
        sn_, cn_, dn_ = _landen(rh, m, mc)
    a = math.atan2(sn_, cn_)
    if flip:
        cn_ = -cn_
        a = PI_HI - a
    if neg:
        sn_ = -sn_
        a = -a
    return sn_, cn_, dn_, n, a


@kernel(error_model="numpy")
def _ellipj_dd(uh, ul, m, mc):
    """(sn, cn, dn, am)(u | m) for u = uh + ul given in double-double."""
    if mc == 0.0:
        # m = 1: sn = tanh, cn = dn = sech, am = gd.
        u = uh + ul
        ch = math.cosh(u)
        return math.tanh(u), 1.0 / ch, 1.0 / ch, math.atan(math.sinh(u))
    if mc < 0.0:
        # m > 1, reciprocal modulus (DLMF §22.17) with mu = 1/m:
        # sn(u|m) = sn(k u|mu)/k, cn(u|m) = dn(k u|mu), dn(u|m) = cn(k u|mu).
        kh, kl = dd_sqrt(m, 0.0)
        vh, vl = dd_mul_safe(uh, ul, kh, kl)
        qh, ql = dd_div(-mc, 0.0, m, 0.0)  # mu_c = (m - 1)/m
        kch, kcl = dd_sqrt(qh, ql)
        s, c, d, n, a = ellipj_kc_dd_kernel(vh, vl, 1.0 / m, qh, kch, kcl)
        sn_ = s / kh
        return sn_, d, c, math.atan2(sn_, d)
    if mc > 1.0:
        # m < 0, imaginary modulus (DLMF §22.17) with mu = -m/mc:
        # sn(u|m) = sd(v|mu)/sqrt(mc), cn = cd(v|mu), dn = nd(v|mu),
        # v = u sqrt(mc).  The period 4K(m) in u is 4K(mu) in v.
        sh, sl = dd_sqrt(mc, 0.0)
        vh, vl = dd_mul_safe(uh, ul, sh, sl)
        kch, kcl = dd_div(1.0, 0.0, sh, sl)  # sqrt(mu_c) = 1/sqrt(mc)
        s, c, d, n, a = ellipj_kc_dd_kernel(vh, vl, -m / mc, 1.0 / mc, kch, kcl)
        sn_ = s / (d * sh)
        cn_ = c / d
        a = math.atan2(sn_, cn_)
        return sn_, cn_, 1.0 / d, n * TWO_PI_HI + (a + n * TWO_PI_LO)
    # 0 <= m < 1 (m may be a few ulps negative when mc rounds to 1).
    kch, kcl = dd_sqrt(mc, 0.0)
    s, c, d, n, a = ellipj_kc_dd_kernel(uh, ul, m, mc, kch, kcl)
    return s, c, d, n * TWO_PI_HI + (a + n * TWO_PI_LO)


@kernel(error_model="numpy")
def ellipj_kernel(u, m, mc):
    """Jacobi elliptic functions and amplitude, numba kernel.

    Parameters
    ----------
    u : float
        Argument, any finite real.
    m : float
        Parameter, any finite real.
    mc : float
        Complementary parameter 1 - m, supplied by the caller; it decides the
        branch (``mc == 0``: m = 1, ``mc < 0``: m > 1, ``mc > 1``: m < 0) and
        is used wherever 1 - m is needed.

    Returns
    -------
    sn, cn, dn, am : float
        Relative accuracy ~1e-15 (1e-14 worst, for m -> 1 where cn and dn
        are tiny), including near the zeros of sn and cn, for ``mc`` down to
        1e-300 and ``|u|`` up to 2**52 periods (double-double reduction);
        beyond that the values are only guaranteed finite.  For
        m <= 1, am is the increasing amplitude (am(u + 4K) = am(u) + 2 pi);
        for m > 1 it is the continuous angle with sin am = sn, cos am = cn,
        which stays in (-pi/2, pi/2) since cn = dn(k u | 1/m) > 0.  At
        m = 1 (mc == 0): tanh, sech, sech, gd.  NaN input gives NaN.
    """
    return _ellipj_dd(u, 0.0, m, mc)


# ---------------------------------------------------------------------------
# Incomplete integral F
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def carlson_rf_kernel(x, y, z):
    """Carlson's R_F(x, y, z) for x, y, z >= 0, at most one of them zero.

    Duplication (Carlson 1995) with Boost's 7th-order series; relative
    accuracy a few ulps.  Returns inf when two arguments vanish.
    """
    nz = (x == 0.0) + (y == 0.0) + (z == 0.0)
    if nz >= 2:
        return math.inf
    a0 = (x + y + z) / 3.0
    an = a0
    q = RF_Q_FACTOR * max(abs(a0 - x), max(abs(a0 - y), abs(a0 - z)))
    xn = x
    yn = y
    zn = z
    fn = 1.0
    for _ in range(RF_MAX_ITER):
        rx = math.sqrt(xn)
        ry = math.sqrt(yn)
        rz = math.sqrt(zn)
        lam = rx * ry + rx * rz + ry * rz
        an = 0.25 * (an + lam)
        xn = 0.25 * (xn + lam)
        yn = 0.25 * (yn + lam)
        zn = 0.25 * (zn + lam)
        q *= 0.25
        fn *= 4.0
        if q < abs(an):
            break
    X = (a0 - x) / (an * fn)
    Y = (a0 - y) / (an * fn)
    Z = -X - Y
    E2 = X * Y - Z * Z
    E3 = X * Y * Z
    return (
        1.0
        + E3 * (1.0 / 14.0 + 3.0 * E3 / 104.0)
        + E2 * (-1.0 / 10.0 + E2 / 24.0 - 3.0 * E3 / 44.0 - 5.0 * E2 * E2 / 208.0 + E2 * E3 / 16.0)
    ) / math.sqrt(an)


@kernel(error_model="numpy")
def ellipf_kernel(phi, m, mc):
    """Incomplete elliptic integral of the first kind F(phi | m), numba kernel.

    Parameters
    ----------
    phi : float
        Amplitude, any finite real for m <= 1.
    m, mc : float
        Parameter and its complement 1 - m (``mc`` is used for
        ``1 - m sin^2 phi = cos^2 phi + mc sin^2 phi``).

    Returns
    -------
    float
        F(phi | m) = sin(phi) R_F(cos^2 phi, 1 - m sin^2 phi, 1) on
        |phi| <= pi/2, extended by F(phi + j pi) = F(phi) + 2 j K (reduction
        in double-double).  NaN where F is not real or finite: m = 1 with
        |phi| beyond pi/2, and m > 1 unless |phi| <= pi/2 and
        |sin phi| <= 1/sqrt(m).
    """
    if mc < 0.0:
        # m > 1: real only on |phi| <= arcsin(1/sqrt(m)).
        if not abs(phi) <= PIO2_HI:
            return math.nan
        s = math.sin(phi)
        c = math.cos(phi)
        c2 = c * c
        t = mc * s * s
        y = c2 + t
        if y < 0.0:
            if y >= -EDGE_CLAMP_ULPS * EPS * (c2 - t):
                y = 0.0
            else:
                return math.nan
        return s * carlson_rf_kernel(c2, y, 1.0)
    if not (abs(phi) < math.inf and mc >= 0.0):
        return math.nan
    j = np.floor(phi / PI_HI + 0.5)
    if j == 0.0:
        s = math.sin(phi)
        c = math.cos(phi)
    elif abs(j) >= REDUCE_MAX_PERIODS:
        # No accuracy possible (ulp(phi) > pi); stay finite.
        rh = np.fmod(phi, PI_HI)
        j = (phi - rh) / PI_HI
        s = math.sin(rh)
        c = math.cos(rh)
    else:
        ph, pl = two_prod(j, PI_HI)
        pl += j * PI_LO
        rh, rl = dd_add(phi, 0.0, -ph, -pl)
        sh = math.sin(rh)
        ch = math.cos(rh)
        s = sh + ch * rl
        c = ch - sh * rl
    if c < 0.0:
        # The double quotient put the reduced angle just beyond +-pi/2, where
        # the R_F formula (it sees only cos^2) does not hold: move one more pi.
        j += 1.0 if s > 0.0 else -1.0
        s = -s
        c = -c
    c2 = c * c
    f = s * carlson_rf_kernel(c2, c2 + mc * s * s, 1.0)
    if j == 0.0:
        return f
    if mc == 0.0:
        return math.nan  # F(phi | 1) diverges at |phi| = pi/2
    Kh, Kl = ellipk_dd_kernel(mc, 0.0)
    return 2.0 * j * Kh + (2.0 * j * Kl + f)
