"""Sign changes of a polynomial on [0, 1]: Bernstein isolation and refinement to round-off.

A Taylor window's formula is a polynomial in the time from its anchor, so a crossing
of a level inside a window is a root of a known polynomial.  Its roots on the window
are isolated from the formula itself, as heyoka isolates its Taylor polynomials'
roots (Descartes' rule of signs on the Bernstein form): the number of sign changes of
the Bernstein coefficients on an interval bounds the number of roots there from above
(with the same parity), so an interval with none holds no root and one with a single
sign change holds exactly one.  Intervals with more are halved (de Casteljau) until
each holds at most one sign change or is below the spacing of the doubles; a pair of
roots closer than that, or a tangency, changes no sign and is no crossing.

The verdict on each interval is the polynomial's own value at its ends (Horner, as the
dense output evaluates it), so a crossing is reported where the dense output changes
sign, and refined there by regula falsi (Illinois) with bisection as its guard.

Kernels (``numba.njit``, cached): :func:`bernstein_into`, :func:`sign_changes`,
:func:`isolate`, :func:`horner`, :func:`refine`, :func:`crossings` (the three together).
"""

import numpy as np

from ..compile.jit import kernel

__all__ = ["bernstein_into", "sign_changes", "isolate", "horner", "refine", "crossings", "MAX_DEPTH"]

# Halvings of [0, 1] before an interval with several sign changes is given up as a
# tangency or an unresolvable pair: 2^-52 of a window is below the spacing of the
# doubles near its end.
MAX_DEPTH = 52
# Refinement steps: Illinois converges superlinearly, and every second step that does
# not halve the bracket is a bisection, so 200 steps reach any double.
REFINE_STEPS = 200


@kernel
def bernstein_into(alpha, n, out):
    """The Bernstein coefficients on [0, 1] of p(x) = Σ_{k≤n} alpha[k] x^k, into ``out[:n + 1]``.

    b_j = Σ_{k≤j} C(j, k) / C(n, k) · alpha[k] (the change of basis; its weights lie in
    [0, 1], so the coefficients carry the rounding of a sum of n + 1 terms).
    """
    for j in range(n + 1):
        # w = C(j, k) / C(n, k), from w = 1 at k = 0 by the ratio of consecutive terms.
        w = 1.0
        s = alpha[0]
        for k in range(1, j + 1):
            w *= (j - k + 1) / (n - k + 1)
            s += w * alpha[k]
        out[j] = s


@kernel
def sign_changes(b, n):
    """Sign changes of ``b[:n + 1]`` (zeros skipped)."""
    count = 0
    last = 0.0
    for j in range(n + 1):
        if b[j] != 0.0:
            if last != 0.0 and (b[j] > 0.0) != (last > 0.0):
                count += 1
            last = b[j]
    return count


@kernel
def horner(alpha, n, x):
    """p(x) = Σ_{k≤n} alpha[k] x^k (Horner, the constant term added last)."""
    p = alpha[n]
    for k in range(n - 1, 0, -1):
        p = p * x + alpha[k]
    return alpha[0] + x * p if n > 0 else alpha[0]


@kernel
def _split(b, n, left, right):
    # de Casteljau at 1/2: b on [lo, hi] into its halves' coefficients.
    for j in range(n + 1):
        right[j] = b[j]
    for r in range(1, n + 1):
        left[r - 1] = right[0]
        for j in range(n + 1 - r):
            right[j] = 0.5 * (right[j] + right[j + 1])
    left[n] = right[0]


@kernel
def isolate(alpha, n, out_lo, out_hi):
    """Intervals of [0, 1] that may hold a sign change of p (``alpha`` its power
    coefficients, degree ``n``), left to right; returns how many (at most
    ``out_lo.size``; -1 when there were more).

    Every interval left out has Bernstein coefficients of one sign, agreeing with the
    sign of p at its ends (so p changes no sign across it); an interval kept holds one
    Bernstein sign change, or is :data:`MAX_DEPTH` halvings deep.
    """
    work = np.empty((MAX_DEPTH + 2, n + 1))
    right = np.empty(n + 1)
    lo_s = np.empty(MAX_DEPTH + 2)
    depth_s = np.empty(MAX_DEPTH + 2, np.int64)
    bernstein_into(alpha, n, work[0])
    lo_s[0], depth_s[0] = 0.0, 0
    sp, count = 1, 0
    while sp > 0:
        sp -= 1
        b = work[sp]
        lo, depth = lo_s[sp], depth_s[sp]
        width = 0.5 ** depth
        v = sign_changes(b, n)
        if v == 0:
            # One sign: no root, unless rounding hides one at an end (then kept).
            sgn = b[0] if b[0] != 0.0 else b[n]
            pa, pb = horner(alpha, n, lo), horner(alpha, n, lo + width)
            if sgn != 0.0 and pa * sgn > 0.0 and pb * sgn > 0.0:
                continue
        if v <= 1 or depth >= MAX_DEPTH:
            if count == out_lo.size:
                return -1
            out_lo[count], out_hi[count] = lo, lo + width
            count += 1
            continue
        # Halve: the right half below, the left on top (popped first: left to right).
        _split(b, n, work[sp + 1], right)
        for j in range(n + 1):
            work[sp, j] = right[j]
        lo_s[sp], depth_s[sp] = lo + 0.5 * width, depth + 1
        lo_s[sp + 1], depth_s[sp + 1] = lo, depth + 1  # work[sp + 1]: the left half
        sp += 2
    return count


@kernel
def refine(alpha, n, lo, hi, glo, ghi, xtol):
    """The crossing of p in (lo, hi] where p(lo) = ``glo`` ≠ 0 and ``ghi`` = p(hi) is 0
    or of the other sign: the first double x of the final bracket (lo, x] with p(x)
    of ``ghi``'s sign or zero, the bracket narrowed to ``xtol`` or to adjacent doubles.
    """
    if ghi == 0.0:
        return hi
    side = 0
    for _ in range(REFINE_STEPS):
        if hi - lo <= xtol:
            break
        x = hi - ghi * (hi - lo) / (ghi - glo)  # regula falsi
        mid = 0.5 * (lo + hi)
        if not (lo < x < hi) or side == 2 or side == -2:
            x = mid
            side = 0
        if not (lo < x < hi):
            break
        gx = horner(alpha, n, x)
        if gx == 0.0:
            return x
        if (gx > 0.0) == (glo > 0.0):
            lo, glo = x, gx
            if side < 0:
                side -= 1
                ghi *= 0.5  # Illinois: the stale end's value halved
            else:
                side = -1
        else:
            hi, ghi = x, gx
            if side > 0:
                side += 1
                glo *= 0.5
            else:
                side = 1
    return hi


@kernel
def crossings(alpha, n, xtol, out_x, out_dir):
    """The sign changes of p (power coefficients ``alpha``, degree ``n``) in (0, 1], left to
    right: their points (:func:`refine`, to ``xtol``) into ``out_x`` and their directions
    (+1: p from negative to positive) into ``out_dir``; returns how many (-1: more than
    ``out_x.size``).

    A sign change at 0 is not one of (0, 1] (the previous window's end); a zero of p
    at an interval's end where p keeps its sign on both sides (a tangency met exactly
    in doubles) is no crossing; a zero exactly at 1 is reported (what follows is the
    next window's).
    """
    cap = out_x.size
    lo_i = np.empty(cap + 1)
    hi_i = np.empty(cap + 1)
    m = isolate(alpha, n, lo_i, hi_i)
    if m < 0:
        return -1
    count = 0
    for i in range(m):
        lo, hi = lo_i[i], hi_i[i]
        glo, ghi = horner(alpha, n, lo), horner(alpha, n, hi)
        if glo == 0.0:
            continue  # a zero at lo: the interval before it (or the window before) has it
        if ghi == 0.0 and hi < 1.0:
            after = horner(alpha, n, min(1.0, hi + (hi - lo)))
            if after == 0.0 or (after > 0.0) == (glo > 0.0):
                continue  # touches zero and turns back: a tangency
        elif ghi != 0.0 and (ghi > 0.0) == (glo > 0.0):
            continue
        if count == cap:
            return -1
        out_x[count] = refine(alpha, n, lo, hi, glo, ghi, xtol)
        out_dir[count] = 1.0 if glo < 0.0 else -1.0
        count += 1
    return count
