"""Double-double arithmetic (Dekker 1971, Knuth TAOCP 4.2.2) and the 2π reduction.

A double-double is an unevaluated sum ``hi + lo`` with ``|lo| <= ulp(hi)/2``: about
32 significant digits from float64 operations.  numba emits no fused multiply-add,
so exact products use Veltkamp's split.  Used by :mod:`mbm.special.jacobi` (argument
reduction, K), :mod:`mbm.special.weierstrass`, :mod:`mbm.special.pendulum_flow` and
the splitting approximants.

Every function is a numba kernel on float64 scalars and returns a tuple
``(hi, lo)``; the arguments ``ah, al`` (``bh, bl``) are the parts of a (b).

The one 2π reduction of the package is :func:`reduce_2pi` (θ − 2πj in
double-double, in [−π, π]); :func:`nearest_2pi_multiple` is its j.
"""

import math

import numpy as np

from ..compile.jit import kernel


__all__ = [
    "EPS",
    "PI_HI",
    "PI_LO",
    "PIO2_HI",
    "PIO2_LO",
    "PIO4",
    "TWO_PI_HI",
    "TWO_PI_LO",
    "two_sum",
    "fast_two_sum",
    "split",
    "two_prod",
    "dd_add",
    "dd_add_pos",
    "dd_mul",
    "dd_mul_safe",
    "dd_mul_d",
    "dd_div",
    "dd_div_d",
    "dd_gt",
    "dd_sqrt",
    "dd_sincos",
    "dd_sincos_any",
    "nearest_2pi_multiple",
    "reduce_2pi",
]

# Veltkamp split point 2**27 + 1: exact products need it, numba emits no fma.
SPLITTER = 134217729.0

# The Veltkamp split overflows above this: huge (already hopeless) products use plain double.
SPLIT_SAFE = 1e290

# Below this a double-double low part would be subnormal: dd_sqrt rescales (mc >= 1e-308 works).
DD_TINY = 1e-270

# Taylor terms of dd_sincos at |y| <= π/16: the first omitted term y^21/21! < 1e-33.
DD_SINCOS_TERMS = 10

# float64 machine epsilon, 2**-52.
EPS = 2.220446049250313e-16

# π, π/2 and 2π as unevaluated double-double sums (hi + lo), π/4 in double: reductions
# by them are carried to ~1e-32 relative.
PI_HI = 3.141592653589793
PI_LO = 1.2246467991473532e-16
PIO2_HI = 1.5707963267948966
PIO2_LO = 6.123233995736766e-17
TWO_PI_HI = 6.283185307179586
TWO_PI_LO = 2.4492935982947064e-16
PIO4 = 0.7853981633974483


# ---------------------------------------------------------------------------
# Error-free transformations
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def two_sum(a, b):
    """s + e == a + b exactly, s = fl(a + b)."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


@kernel(error_model="numpy")
def fast_two_sum(a, b):
    """s + e == a + b exactly, assuming |a| >= |b| or a == 0."""
    s = a + b
    e = b - (s - a)
    return s, e


@kernel(error_model="numpy")
def split(a):
    """Veltkamp's split a = hi + lo, each half with at most 26 significant bits."""
    t = SPLITTER * a
    hi = t - (t - a)
    return hi, a - hi


@kernel(error_model="numpy")
def two_prod(a, b):
    """p + e == a * b exactly, p = fl(a * b) (no fma: Dekker's split)."""
    p = a * b
    ah, al = split(a)
    bh, bl = split(b)
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e


# ---------------------------------------------------------------------------
# Double-double arithmetic
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def dd_add(ah, al, bh, bl):
    """Accurate double-double sum (both parts two-summed)."""
    s, e = two_sum(ah, bh)
    t, f = two_sum(al, bl)
    e += t
    s, e = fast_two_sum(s, e)
    e += f
    return fast_two_sum(s, e)


@kernel(error_model="numpy")
def dd_add_pos(ah, al, bh, bl):
    """Double-double sum of two numbers of equal sign (no cancellation)."""
    s, e = two_sum(ah, bh)
    e += al + bl
    return fast_two_sum(s, e)


@kernel(error_model="numpy")
def dd_mul(ah, al, bh, bl):
    """Double-double product."""
    p, e = two_prod(ah, bh)
    e += ah * bl + al * bh
    return fast_two_sum(p, e)


@kernel(error_model="numpy")
def dd_mul_safe(ah, al, bh, bl):
    """dd_mul, falling back to a plain product where the split would overflow."""
    p = ah * bh
    if abs(ah) > SPLIT_SAFE or abs(bh) > SPLIT_SAFE or abs(p) > SPLIT_SAFE:
        if abs(p) == math.inf:
            # Hopelessly beyond the exact range anyway: stay finite.
            p = math.copysign(SPLIT_SAFE, p)
        return p, 0.0
    return dd_mul(ah, al, bh, bl)


@kernel(error_model="numpy")
def dd_mul_d(ah, al, b):
    """Double-double times a double b."""
    p, e = two_prod(ah, b)
    e += al * b
    return fast_two_sum(p, e)


@kernel(error_model="numpy")
def dd_div(ah, al, bh, bl):
    """Double-double quotient a / b."""
    q1 = ah / bh
    ph, pl = dd_mul_d(bh, bl, q1)
    rh, rl = dd_add(ah, al, -ph, -pl)
    q2 = rh / bh
    return fast_two_sum(q1, q2)


@kernel(error_model="numpy")
def dd_gt(ah, al, bh, bl):
    """a > b for normalized double-doubles."""
    return ah > bh or (ah == bh and al > bl)


@kernel(error_model="numpy")
def dd_sqrt(ah, al):
    """sqrt of a non-negative double-double (one Newton correction)."""
    if ah <= 0.0:
        if ah == 0.0:
            return 0.0, 0.0
        return math.nan, math.nan
    if ah == math.inf:
        return math.inf, 0.0
    down = 1.0
    if ah < DD_TINY:
        # The low parts would be subnormal: work on a 2**600 scaled copy.
        ah *= 2.0**600
        al *= 2.0**600
        down = 2.0**-300
    s = math.sqrt(ah)
    p, e = two_prod(s, s)
    r = (((ah - p) - e) + al) / (2.0 * s)
    h, l = fast_two_sum(s, r)
    return h * down, l * down


@kernel(error_model="numpy")
def dd_div_d(ah, al, b):
    """(ah + al) / b for a double b."""
    q1 = ah / b
    p, e = two_prod(q1, b)
    q2 = (((ah - p) - e) + al) / b
    return fast_two_sum(q1, q2)


@kernel(error_model="numpy")
def dd_sincos(xh, xl):
    """sin x and cos x in double-double for |x| <= π/2 (+ tiny).

    Taylor series at x/8 (|x/8| < 0.2: DD_SINCOS_TERMS = 10 terms reach 1e-33)
    followed by three double-angle steps, cos 2y = (c − s)(c + s) keeping cos
    accurate near π/2.

    Returns
    -------
    sin_hi, sin_lo, cos_hi, cos_lo : float
    """
    yh, yl = xh * 0.125, xl * 0.125
    y2h, y2l = dd_mul(yh, yl, yh, yl)
    sh, sl = yh, yl
    ch, cl = 1.0, 0.0
    th, tl = yh, yl  # sin term y^(2n+1)/(2n+1)!
    uh, ul = 1.0, 0.0  # cos term y^(2n)/(2n)!
    for n in range(1, DD_SINCOS_TERMS + 1):
        th, tl = dd_mul(th, tl, y2h, y2l)
        th, tl = dd_div_d(th, tl, -float((2 * n) * (2 * n + 1)))
        sh, sl = dd_add(sh, sl, th, tl)
        uh, ul = dd_mul(uh, ul, y2h, y2l)
        uh, ul = dd_div_d(uh, ul, -float((2 * n - 1) * (2 * n)))
        ch, cl = dd_add(ch, cl, uh, ul)
    for _ in range(3):
        s2h, s2l = dd_mul(sh, sl, ch, cl)
        dh, dl = dd_add(ch, cl, -sh, -sl)
        ph, pl = dd_add(ch, cl, sh, sl)
        ch, cl = dd_mul(dh, dl, ph, pl)
        sh, sl = 2.0 * s2h, 2.0 * s2l
    return sh, sl, ch, cl


@kernel(error_model="numpy")
def dd_sincos_any(xh, xl):
    """sin x and cos x in double-double for a double-double x of moderate size.

    x is reduced by the nearest multiple j of 2π (2π in double-double, the product
    j·TWO_PI_HI exact) and folded by π into [−π/2, π/2] for :func:`dd_sincos`:
    ~1e-32 absolute for |x| up to ~1e6 (j·2π's double-double error grows with j).

    Returns
    -------
    sin_hi, sin_lo, cos_hi, cos_lo : float
    """
    j = np.floor(xh / TWO_PI_HI + 0.5)
    rh, rl = xh, xl
    if j != 0.0:
        p_hi, p_lo = two_prod(j, TWO_PI_HI)
        rh, rl = dd_add(rh, rl, -p_hi, -p_lo)
        rh, rl = dd_add(rh, rl, -j * TWO_PI_LO, 0.0)
    flip = False
    if rh > PIO2_HI:
        rh, rl = dd_add(rh, rl, -PI_HI, -PI_LO)
        flip = True
    elif rh < -PIO2_HI:
        rh, rl = dd_add(rh, rl, PI_HI, PI_LO)
        flip = True
    sh, sl, ch, cl = dd_sincos(rh, rl)
    if flip:
        return -sh, -sl, -ch, -cl
    return sh, sl, ch, cl


# ---------------------------------------------------------------------------
# The 2π reduction
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def nearest_2pi_multiple(x):
    """j = round(x / 2π) as a float: the j of :func:`reduce_2pi` before its boundary fix.

    np.floor, not math.floor: numba's math.floor returns an int64 (it overflows
    for huge x and is undefined for NaN); a float j is exact up to 2**53.
    """
    return np.floor(x / TWO_PI_HI + 0.5)


@kernel(error_model="numpy")
def reduce_2pi(x):
    """x − 2πj in double-double, with j an integer and the result in [−π, π].

    j·2π is formed from 2π = TWO_PI_HI + TWO_PI_LO with an exact product
    (Dekker), so the remainder is x − 2πj to ~1e-32 relative for |x| up to
    ~1e15 (beyond, j·2π's double-double error j·2π·2^-107 exceeds ulp(π)).

    Returns
    -------
    j, hi, lo : float
        ``x == j·2π + (hi + lo)`` to that accuracy, ``-π <= hi + lo <= π``
        (as double-doubles); ``(0.0, x, 0.0)`` where x/2π rounds to 0
        (|x| < π, except within rounding of ±π).
    """
    j = nearest_2pi_multiple(x)
    if j == 0.0:
        hi, lo = x, 0.0
    else:
        p_hi, p_lo = two_prod(j, TWO_PI_HI)
        d, d_err = two_sum(x, -p_hi)
        hi, lo = two_sum(d, (d_err - p_lo) - j * TWO_PI_LO)
    # The rounded quotient can be off by one at the boundary (x = fl(π) gives
    # j = 1 and a remainder just below −π, in the neighbouring well).
    if hi < -PI_HI or (hi == -PI_HI and lo < -PI_LO):
        hi, lo = dd_add(hi, lo, TWO_PI_HI, TWO_PI_LO)
        j -= 1.0
    elif hi > PI_HI or (hi == PI_HI and lo > PI_LO):
        hi, lo = dd_add(hi, lo, -TWO_PI_HI, -TWO_PI_LO)
        j += 1.0
    return j, hi, lo
