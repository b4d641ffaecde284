r"""The Taylor recurrence of the pendulum (:mod:`mbm.approximants.taylor`).

The coefficient layout, the workspace and the kernels that generate the anchored
Taylor coefficients a_0 .. a_{N+2} of θ'' + βθ' + ω² sin θ = γ, plain and with the
periodic drive.  The series' evaluation, error estimate, window choice and the
registered ``taylor<N>`` approximants are in :mod:`mbm.approximants.taylor`, whose
docstring describes the recurrence.
"""

import collections
import math

import numpy as np
from numba import njit

from ..special.dd import two_prod, two_sum
from ..compile.jit import INLINE, kernel
from .taylor_simd import SIMD_ORDER, DriveSeries, taylor24_driven_series, taylor24_series


# Layout of coef (all float64):
#   [0] status, [1] N, [2] beta, [3] gamma, [4] omega,
#   [5 + k] = a_k for k = 0 .. N + 2 (a_{N+1}, a_{N+2} only feed the error estimate).
HEADER = 5
# Extra coefficients past a_N that feed the error estimate.
N_EXTRA = 2
# Highest degree the kernels accept (sizes the reciprocal tables below).
MAX_ORDER = 60
# 1/k and 1/((k+1)(k+2)): the recurrence multiplies by these instead of dividing
# (with the root test moved out of the kernel, 15-20 % of a degree-16 anchor).
_INV_K = np.array([0.0] + [1.0 / k for k in range(1, MAX_ORDER + N_EXTRA + 1)])
_INV_K12 = np.array([1.0 / ((k + 1.0) * (k + 2.0)) for k in range(MAX_ORDER + N_EXTRA + 1)])

#: The driven equation θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ): its β, γ, ω and the
#: drive's A, Ω ≥ 0, φ (a plain tuple of the six, in this order, serves as well).
DrivenModel = collections.namedtuple("DrivenModel", ("beta", "gamma", "omega", "amp", "freq", "phase"))

STATUS_OK = 0
STATUS_BAD_STATE = 1  # non-finite anchor or parameters
STATUS_BAD_ORDER = 2  # degree outside 1 .. MAX_ORDER


# No fastmath licences (reassociation, fused multiply-add): with them LLVM decides
# vectorization and contraction per inlining context, so a kernel compiled afresh and
# the same kernel loaded from numba's cache gave results differing in the last bits
# (4.5e-12 on a sweep: a chunked sweep on Dask workers then differed from the
# in-process one).  Strict IEEE arithmetic gives the same bits on every path, process
# and cache state; it cost 0-14 % of mbm.solve's time on P2, P4, P5 (measured when
# dropped; the recurrence vectorized 10-25 % better with reassociation).


@njit(**INLINE)
def _header(coef, scratch, n_order, beta, gamma, omega):
    # The header of the layout at module top, in the caller's buffer: (True, the vector's
    # view), or (False, coef[:HEADER] with STATUS_BAD_ORDER) for a degree outside
    # 1 .. MAX_ORDER or buffers too small for it.
    nt = n_order + N_EXTRA
    if (n_order < 1 or n_order > MAX_ORDER or coef.size < HEADER + nt + 1
            or scratch.size < 3 * (nt + 1)):
        bad = coef[:HEADER]
        bad[:] = np.nan
        bad[0] = STATUS_BAD_ORDER
        return False, bad
    coef = coef[: HEADER + nt + 1]
    _header_into(coef, n_order, beta, gamma, omega)
    return True, coef


@njit(**INLINE)
def _prepared(coef, scratch, n_order, beta, gamma, omega, finite):
    # (True, the vector's view with its header: _header), or (False, the status vector to
    # return): a degree or buffer _header refuses, or a non-finite input (``finite``
    # False: STATUS_BAD_STATE, NaN elsewhere).
    ok, coef = _header(coef, scratch, n_order, beta, gamma, omega)
    if ok and not finite:
        coef[:] = np.nan
        coef[0] = STATUS_BAD_STATE
        return False, coef
    return ok, coef


@njit(**INLINE)
def _header_into(coef, n_order, beta, gamma, omega):
    # The header of the layout at module top (status OK).
    coef[0] = STATUS_OK
    coef[1] = n_order
    coef[2] = beta
    coef[3] = gamma
    coef[4] = omega


@njit(**INLINE)
def _finite5(beta, gamma, omega, theta0, v0):
    return (math.isfinite(theta0) and math.isfinite(v0) and math.isfinite(beta)
            and math.isfinite(gamma) and math.isfinite(omega))


@njit(**INLINE)
def _start(a, scratch, nt, theta0, v0):
    # The recurrence's start, shared by the undriven and the driven kernels: a₀, a₁,
    # and the scratch views (b_j = j a_j backwards, br[nt − j] = b_j; s_m, c_m forwards;
    # see taylor_coefficients_into), with s₀ = sin θ₀, c₀ = cos θ₀.  Returns (br, sn, cn, s₀).
    br = scratch[: nt + 1]
    sn = scratch[nt + 1 : 2 * nt + 2]
    cn = scratch[2 * nt + 2 :]
    a[0] = theta0
    a[1] = v0
    br[nt] = 0.0
    br[nt - 1] = v0
    s0 = math.sin(theta0)
    sn[0] = s0
    cn[0] = math.cos(theta0)
    return br, sn, cn, s0


@njit(**INLINE)
def _sin_order(k, off, br, sn, cn):
    # Order k of s = sin θ and c = cos θ from s' = cθ', c' = −sθ' (the module's
    # "Coefficients"): k s_k = Σ_{m<k} T_m with T_m = b_{k−m} c_m (and likewise c_k);
    # writes s_k, c_k and returns s_k.  The order of the sum: the middle terms
    # T_1 … T_{k−2} in four accumulators (T_m into accumulator (m − 1) mod 4), those
    # added left to right, then T_0 (b_k, the newest b), then T_{k−1} (c_{k−1}, from
    # the order before): independent chains, and the newest inputs enter last, so an
    # order's sum waits little on the one before.  (Degree SIMD_ORDER takes the
    # vector kernel of mbm.approximants.taylor_simd, the same sums in another order.)
    if k == 1:
        ss = br[off] * cn[0]
        cc = br[off] * sn[0]
    elif k == 2:
        ss = br[off] * cn[0] + br[off + 1] * cn[1]
        cc = br[off] * sn[0] + br[off + 1] * sn[1]
    else:
        last = k - 2  # the middle terms are m = 1 .. last
        s0 = br[off + 1] * cn[1]
        c0 = br[off + 1] * sn[1]
        s1 = s2 = s3 = c1 = c2 = c3 = 0.0
        if last >= 2:
            s1 = br[off + 2] * cn[2]
            c1 = br[off + 2] * sn[2]
        if last >= 3:
            s2 = br[off + 3] * cn[3]
            c2 = br[off + 3] * sn[3]
        if last >= 4:
            s3 = br[off + 4] * cn[4]
            c3 = br[off + 4] * sn[4]
        m = 5
        while m + 3 <= last:
            b0 = br[off + m]
            b1 = br[off + m + 1]
            b2 = br[off + m + 2]
            b3 = br[off + m + 3]
            s0 += b0 * cn[m]
            s1 += b1 * cn[m + 1]
            s2 += b2 * cn[m + 2]
            s3 += b3 * cn[m + 3]
            c0 += b0 * sn[m]
            c1 += b1 * sn[m + 1]
            c2 += b2 * sn[m + 2]
            c3 += b3 * sn[m + 3]
            m += 4
        if m <= last:
            s0 += br[off + m] * cn[m]
            c0 += br[off + m] * sn[m]
            m += 1
        if m <= last:
            s1 += br[off + m] * cn[m]
            c1 += br[off + m] * sn[m]
            m += 1
        if m <= last:
            s2 += br[off + m] * cn[m]
            c2 += br[off + m] * sn[m]
        ss = s0
        cc = c0
        if last >= 2:
            ss += s1
            cc += c1
        if last >= 3:
            ss += s2
            cc += c2
        if last >= 4:
            ss += s3
            cc += c3
        ss = (ss + br[off] * cn[0]) + br[off + k - 1] * cn[k - 1]
        cc = (cc + br[off] * sn[0]) + br[off + k - 1] * sn[k - 1]
    sk = ss * _INV_K[k]
    sn[k] = sk
    cn[k] = -cc * _INV_K[k]
    return sk


@kernel
def taylor_workspace(n_order):
    """``(coef, scratch)`` buffers for :func:`taylor_coefficients_into` at degree ``n_order``.

    One pair per run serves every window (no heap allocation per window); ``n_order`` is
    clamped to 1 .. MAX_ORDER (a bad degree still gets its status from the kernel).
    """
    n = min(max(n_order, 1), MAX_ORDER) + N_EXTRA
    return np.empty(HEADER + n + 1), np.empty(3 * (n + 1))


@kernel
def taylor_coefficients_into(beta, gamma, omega, theta0, v0, n_order, coef, scratch):
    """:func:`taylor_coefficients` written into caller-owned buffers (no allocation).

    Parameters
    ----------
    beta, gamma, omega, theta0, v0, n_order
        As :func:`taylor_coefficients`.
    coef, scratch : ndarray
        From :func:`taylor_workspace` (sizes ≥ HEADER + N + 3 and 3(N + 3)); ``coef`` is
        overwritten, so a caller keeps what it needs of one window's vector (a copy)
        before anchoring the next.

    Returns
    -------
    ndarray
        A view of ``coef``: the layout documented at module top (length HEADER + N + 3),
        or ``coef[:HEADER]`` with status STATUS_BAD_ORDER for a degree outside
        1 .. MAX_ORDER or buffers too small for it.
    """
    if (n_order == SIMD_ORDER and coef.size == HEADER + SIMD_ORDER + N_EXTRA + 1
            and _finite5(beta, gamma, omega, theta0, v0)):
        # The run's own workspace at the vector kernel's degree, stored in place, here as
        # in taylor24_coefficients_into: a stored period re-anchors its windows per
        # output, so a call more per anchor costs ~5 % of a phase-locked run.
        _header_into(coef, n_order, beta, gamma, omega)
        taylor24_series(beta, gamma, omega, theta0, v0, coef)
        return coef
    if n_order == SIMD_ORDER:
        # The same recurrence in vector instructions (mbm.approximants.taylor_simd).
        return taylor24_coefficients_into(beta, gamma, omega, theta0, v0, n_order, coef, scratch)
    ok, coef = _prepared(coef, scratch, n_order, beta, gamma, omega, _finite5(beta, gamma, omega, theta0, v0))
    if not ok:
        return coef
    series_loop(beta, gamma, omega, theta0, v0, n_order, coef[HEADER:], scratch)
    return coef


@kernel
def taylor24_coefficients_into(beta, gamma, omega, theta0, v0, n_order, coef, scratch):
    """:func:`taylor_coefficients_into` at degree SIMD_ORDER alone (the vector kernel),
    which compiles no loop form: the loop's entries for the default degree call it.
    Another ``n_order`` returns ``coef[:HEADER]`` with status STATUS_BAD_ORDER."""
    if n_order != SIMD_ORDER:
        coef[:HEADER] = np.nan
        coef[0] = STATUS_BAD_ORDER
        return coef[:HEADER]
    if coef.size == HEADER + SIMD_ORDER + N_EXTRA + 1 and _finite5(beta, gamma, omega, theta0, v0):
        # The run's own workspace at the vector kernel's degree: header and
        # coefficients stored in place, no view made.
        _header_into(coef, n_order, beta, gamma, omega)
        taylor24_series(beta, gamma, omega, theta0, v0, coef)
        return coef
    ok, coef = _prepared(coef, scratch, n_order, beta, gamma, omega, _finite5(beta, gamma, omega, theta0, v0))
    if not ok:
        return coef
    taylor24_series(beta, gamma, omega, theta0, v0, coef)
    return coef


@kernel
def series_loop(beta, gamma, omega, theta0, v0, n_order, a, scratch):
    """The recurrence's loop form: a₀ … a_{N+2} into ``a`` (``scratch`` as
    :func:`taylor_workspace`'s); degree SIMD_ORDER takes the vector kernel of
    :mod:`mbm.approximants.taylor_simd` instead (the same recurrence, rounded apart)."""
    nt = n_order + N_EXTRA
    w2 = omega * omega
    # Scratch (the caller's buffer): s_m, c_m in natural order and b_j = j a_j (the θ'
    # coefficients) stored backwards, br[nt − j] = b_j, so that both convolution sums
    # Σ_{j=1}^{k} b_j c_{k−j} = Σ_{m=0}^{k−1} c_m br[nt − k + m] run forward from m = 0
    # through all three arrays: 23 % less time per anchor at N = 24 (27 % at 30, 13 %
    # at 16) than with s, c stored backwards and b forward (the same sums; the kernel
    # table of docs/oracle.md).
    br, sn, cn, s0 = _start(a, scratch, nt, theta0, v0)
    a[2] = 0.5 * (gamma - beta * v0 - w2 * s0)
    br[nt - 2] = 2.0 * a[2]
    for k in range(1, nt - 1):
        off = nt - k
        sk = _sin_order(k, off, br, sn, cn)
        a[k + 2] = (-beta * br[off - 1] - w2 * sk) * _INV_K12[k]
        br[off - 2] = (k + 2.0) * a[k + 2]


@kernel
def taylor_coefficients(beta, gamma, omega, theta0, v0, n_order):
    """Taylor coefficients of θ(t) at an anchor, with the two error-estimate extras.

    Parameters
    ----------
    beta, gamma, omega : float
        Model parameters (β ≥ 0, any γ, ω > 0; not checked here).
    theta0, v0 : float
        Anchor state.
    n_order : int
        Degree N of the approximant's polynomial, 1 ≤ N ≤ MAX_ORDER.

    Returns
    -------
    coef : ndarray
        The layout documented at module top: ``coef[5 + k] = a_k``, k = 0 .. N + 2
        (a new array; :func:`taylor_coefficients_into` fills a reused one).
    """
    if n_order < 1 or n_order > MAX_ORDER:
        bad = np.full(HEADER, np.nan)
        bad[0] = STATUS_BAD_ORDER
        return bad
    coef, scratch = taylor_workspace(n_order)
    return taylor_coefficients_into(beta, gamma, omega, theta0, v0, n_order, coef, scratch)


@kernel
def drive_phase_sincos(freq, phase, t0):
    """sin ψ, cos ψ of the drive's phase ψ = Ω t₀ + φ at a window start t₀.

    Ω·t₀ + φ is formed exactly as a double plus a small remainder (Dekker's product and
    Knuth's sum), and the remainder enters to first order, sin(s + ℓ) = sin s + ℓ cos s
    (ℓ² ≤ (eps·Ωt₀)² is below round-off for Ωt₀ < 1e8): the phase error is a few ulps
    of ψ's reduction by the library sin, not eps·Ωt₀.
    """
    p, e = two_prod(freq, t0)
    hi, e2 = two_sum(p, phase)
    lo = e + e2
    sh = math.sin(hi)
    ch = math.cos(hi)
    return sh + lo * ch, ch - lo * sh


@kernel
def taylor_driven_coefficients_into(model, t0, theta0, v0, n_order, coef, scratch):
    """:func:`taylor_coefficients_into` of the driven equation θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ).

    The window starts at time ``t0``; the drive's series d_k (module docstring, "AC
    drive") enters the recurrence at every order.  Same layout, buffers and statuses
    as :func:`taylor_coefficients_into` (coef[3] holds γ, the drive is not stored:
    the polynomial is all the evaluation needs).

    Parameters
    ----------
    model : DrivenModel or tuple
        (β, γ, ω, A, Ω ≥ 0, φ): the model's parameters and the drive's.
    t0 : float
        The window's start time (the anchor's time).
    theta0, v0, n_order, coef, scratch
        As :func:`taylor_coefficients_into`.

    Returns
    -------
    ndarray
        A view of ``coef`` (the layout at module top).
    """
    beta, gamma, omega, amp, freq, phase = model
    if (n_order == SIMD_ORDER and coef.size == HEADER + SIMD_ORDER + N_EXTRA + 1
            and _driven_finite(model, t0, theta0, v0)):
        # In place, as taylor_coefficients_into (and for the same reason).
        _header_into(coef, n_order, beta, gamma, omega)
        u, w = drive_phase_sincos(freq, phase, t0)
        taylor24_driven_series((beta, gamma, omega), DriveSeries(amp, freq, u, w), theta0, v0, coef)
        return coef
    if n_order == SIMD_ORDER:
        # The same recurrence in vector instructions (mbm.approximants.taylor_simd).
        return taylor24_driven_coefficients_into(model, t0, theta0, v0, n_order, coef, scratch)
    ok, coef = _prepared(coef, scratch, n_order, beta, gamma, omega, _driven_finite(model, t0, theta0, v0))
    if not ok:
        return coef
    u, w = drive_phase_sincos(freq, phase, t0)
    driven_series_loop((beta, gamma, omega), DriveSeries(amp, freq, u, w), theta0, v0, n_order, coef[HEADER:],
                       scratch)
    return coef


@kernel
def taylor24_driven_coefficients_into(model, t0, theta0, v0, n_order, coef, scratch):
    """:func:`taylor_driven_coefficients_into` at degree SIMD_ORDER alone, as
    :func:`taylor24_coefficients_into` is :func:`taylor_coefficients_into`'s."""
    if n_order != SIMD_ORDER:
        coef[:HEADER] = np.nan
        coef[0] = STATUS_BAD_ORDER
        return coef[:HEADER]
    beta, gamma, omega, amp, freq, phase = model
    finite = _driven_finite(model, t0, theta0, v0)
    if coef.size == HEADER + SIMD_ORDER + N_EXTRA + 1 and finite:
        # The workspace in place, as taylor_coefficients_into.
        _header_into(coef, n_order, beta, gamma, omega)
        u, w = drive_phase_sincos(freq, phase, t0)
        taylor24_driven_series((beta, gamma, omega), DriveSeries(amp, freq, u, w), theta0, v0, coef)
        return coef
    ok, coef = _prepared(coef, scratch, n_order, beta, gamma, omega, finite)
    if not ok:
        return coef
    u, w = drive_phase_sincos(freq, phase, t0)
    taylor24_driven_series((beta, gamma, omega), DriveSeries(amp, freq, u, w), theta0, v0, coef)
    return coef


@njit(**INLINE)
def _driven_finite(model, t0, theta0, v0):
    beta, gamma, omega, amp, freq, phase = model
    return (_finite5(beta, gamma, omega, theta0, v0) and math.isfinite(amp) and math.isfinite(freq)
            and math.isfinite(phase) and math.isfinite(t0))


@kernel
def driven_series_loop(model, drive, theta0, v0, n_order, a, scratch):
    """:func:`series_loop` of the driven recurrence: ``model`` (β, γ, ω), ``drive`` the
    :data:`DriveSeries` (f = A, Ω, the phase as u = sin ψ, w = cos ψ:
    :func:`drive_phase_sincos`)."""
    beta, gamma, omega = model
    amp, freq, u, w = drive
    nt = n_order + N_EXTRA
    w2 = omega * omega
    # d_k = f_k · u_k: f_k = A Ω^k / k!, u_k = sin(ψ + kπ/2), w_k = cos(ψ + kπ/2), and
    # (u, w) ← (w, −u) from one order to the next (exact: a swap and a sign).
    f = amp
    # The scratch layout of series_loop (b_j backwards, s_m and c_m forwards).
    br, sn, cn, s0 = _start(a, scratch, nt, theta0, v0)
    a[2] = 0.5 * ((gamma + f * u) - beta * v0 - w2 * s0)
    br[nt - 2] = 2.0 * a[2]
    for k in range(1, nt - 1):
        off = nt - k
        sk = _sin_order(k, off, br, sn, cn)
        f = f * freq * _INV_K[k]
        u, w = w, -u
        a[k + 2] = (f * u - beta * br[off - 1] - w2 * sk) * _INV_K12[k]
        br[off - 2] = (k + 2.0) * a[k + 2]


@kernel
def taylor_driven_coefficients(model, t0, theta0, v0, n_order):
    """:func:`taylor_coefficients` of the driven equation ``model`` (β, γ, ω, A, Ω, φ), the
    window starting at ``t0`` (a new array; see :func:`taylor_driven_coefficients_into`)."""
    if n_order < 1 or n_order > MAX_ORDER:
        bad = np.full(HEADER, np.nan)
        bad[0] = STATUS_BAD_ORDER
        return bad
    coef, scratch = taylor_workspace(n_order)
    return taylor_driven_coefficients_into(model, t0, theta0, v0, n_order, coef, scratch)
