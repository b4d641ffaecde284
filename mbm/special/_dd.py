"""Double-double arithmetic (Dekker 1971, Knuth TAOCP 4.2.2), shared by the numba kernels.

A double-double is an unevaluated sum ``hi + lo`` with ``|lo| <= ulp(hi)/2``: about
32 significant digits from float64 operations.  numba emits no fused multiply-add,
so exact products use Veltkamp's split.  Used by :mod:`mbm.special.jacobi` (argument
reduction, K), :mod:`mbm.special.weierstrass` and the exact pendulum flow of
:mod:`mbm.approximants.belendez2007`.
"""

import math

import numba

# Veltkamp split point 2**27 + 1: exact products need it, numba emits no fma.
SPLITTER = 134217729.0

# The Veltkamp split overflows above this: huge (already hopeless) products use plain double.
SPLIT_SAFE = 1e290

# Below this a double-double low part would be subnormal: _dd_sqrt rescales (mc >= 1e-308 works).
DD_TINY = 1e-270

_jit = numba.njit(cache=True, error_model="numpy")

# ---------------------------------------------------------------------------
# Double-double arithmetic (Dekker 1971, Knuth TAOCP 4.2.2)
# ---------------------------------------------------------------------------


@_jit
def _two_sum(a, b):
    """s + e == a + b exactly, s = fl(a + b)."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


@_jit
def _fast_two_sum(a, b):
    """s + e == a + b exactly, assuming |a| >= |b| or a == 0."""
    s = a + b
    e = b - (s - a)
    return s, e


@_jit
def _split(a):
    t = SPLITTER * a
    hi = t - (t - a)
    return hi, a - hi


@_jit
def _two_prod(a, b):
    """p + e == a * b exactly, p = fl(a * b) (no fma: Dekker's split)."""
    p = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e


@_jit
def _dd_add(ah, al, bh, bl):
    """Accurate double-double sum (both parts two-summed)."""
    s, e = _two_sum(ah, bh)
    t, f = _two_sum(al, bl)
    e += t
    s, e = _fast_two_sum(s, e)
    e += f
    return _fast_two_sum(s, e)


@_jit
def _dd_add_pos(ah, al, bh, bl):
    """Double-double sum of two numbers of equal sign (no cancellation)."""
    s, e = _two_sum(ah, bh)
    e += al + bl
    return _fast_two_sum(s, e)


@_jit
def _dd_mul(ah, al, bh, bl):
    p, e = _two_prod(ah, bh)
    e += ah * bl + al * bh
    return _fast_two_sum(p, e)


@_jit
def _dd_mul_safe(ah, al, bh, bl):
    """_dd_mul, falling back to a plain product where the split would overflow."""
    p = ah * bh
    if abs(ah) > SPLIT_SAFE or abs(bh) > SPLIT_SAFE or abs(p) > SPLIT_SAFE:
        if abs(p) == math.inf:
            # Hopelessly beyond the exact range anyway: stay finite.
            p = math.copysign(SPLIT_SAFE, p)
        return p, 0.0
    return _dd_mul(ah, al, bh, bl)


@_jit
def _dd_mul_d(ah, al, b):
    p, e = _two_prod(ah, b)
    e += al * b
    return _fast_two_sum(p, e)


@_jit
def _dd_div(ah, al, bh, bl):
    q1 = ah / bh
    ph, pl = _dd_mul_d(bh, bl, q1)
    rh, rl = _dd_add(ah, al, -ph, -pl)
    q2 = rh / bh
    return _fast_two_sum(q1, q2)


@_jit
def _dd_gt(ah, al, bh, bl):
    """a > b for normalized double-doubles."""
    return ah > bh or (ah == bh and al > bl)


@_jit
def _dd_sqrt(ah, al):
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
    p, e = _two_prod(s, s)
    r = (((ah - p) - e) + al) / (2.0 * s)
    h, l = _fast_two_sum(s, r)
    return h * down, l * down


@_jit
def _dd_div_d(ah, al, b):
    """(ah + al) / b for a double b."""
    q1 = ah / b
    p, e = _two_prod(q1, b)
    q2 = (((ah - p) - e) + al) / b
    return _fast_two_sum(q1, q2)
