"""PHASE-LOCKED to the drive: a driven run on a periodic orbit of the stroboscopic map.

PHASE-LOCKED to the drive (β > 0, A ≠ 0, Ω > 0; a driven run settling on a periodic
orbit of the stroboscopic map, θ(t + T_d) = θ(t) + 2πp, T_d = 2π/Ω: a Shapiro step;
S7 for θ(t + qT_d) = θ(t) + 2πp, the fractional steps).
The loop (the entry of :func:`mbm.core.loop._runner`) samples the run at the stroboscopic times
(:func:`strobe_period`, :func:`strobe_time`, S1) and tests the switch on the deviations
(:func:`strobe_switch`, S3–S5, S7); after the switch the rest is one stored period
re-taken from the anchor sample (S6): the window :func:`strobe_coef`, evaluated by
:mod:`mbm.regimes.strobe_windows` (``_strobe_windows_taylor``, ``_strobe_range_taylor``;
:func:`strobe_split`, :func:`strobe_phase`).

The derivation, items S1–S7 (the comments below cite them), is in the
documentation's theory page, ``docs/theory/regimes.md``.
"""

import collections
import math

import numba

import numpy as np

from ..special.dd import TWO_PI_HI, TWO_PI_LO, dd_add, dd_div_d, dd_mul_d, reduce_2pi, two_prod, two_sum
from ..compile.jit import INLINE, kernel

# A phase-locked window's coefficient vector (S6): [STROBE_TAG, φ_a, θ'_a, k_a, t_a, q, p,
# ψ_a, β, γ, ω, A, Ω, rtol, atol, karg + STROBE_CODE·error_order]: the anchor at
# θ = 2πk_a + φ_a, θ'_a at time t_a, the period qT_d (q ≥ 1, S7), p turns per period, ψ_a
# the drive's phase at t_a reduced to [−π, π].  16 wide: the narrowest Taylor vector
# (taylor8: 5 + 11) holds it, so every path can store it.
STROBE_TAG = 103.0
STROBE_WIDTH = 16
# (S6): karg and error_order share one entry (both below it; exact in a double).
STROBE_CODE = 1024
# (S5): a stroboscopic map whose spectral radius (from the fitted trace and the exact
# determinant) is above this converges too slowly to trust the fits: no switch.  The
# switch comes at |Δ| ≈ SWITCH_SAFETY·tol·(1 − ρ)², and the computed map's own noise
# (the controller's window choices) is 1e-4 to 1e-3 of tol (measured on the n = 1 step
# of β = 0.2, A = 2, Ω = 1 at 1e-4 to 1e-8): at ρ = 0.8 the deviations are still
# 4 to 40 times the noise, at 0.9 they were as small as it (a run with ρ = 0.994 then
# fitted 0.89 and switched at 1e-6).
STROBE_MAX_MULTIPLIER = 0.8
# (S4): the least-squares residual of x₂ + D·x₀ = τx₁ over the four equations, relative
# to |x₁|, above which the deviations are not (yet) the linear map's: no switch.
# Measured on the n = 1 step of β = 0.2, A = 2, Ω = 1: 1e-7 to 1e-3 while the
# deviations are 1e3 times the computed map's noise or more, 1e-2 to 1 at its floor.
STROBE_FIT_RESIDUAL = 0.05
# (S4): the noise's share of τ taken as this many residuals (relative to |x₁|) times
# 1 + |τ|, the coefficients of x₀-free noise in x₂ − τx₁: the residual of 4 equations
# with 1 unknown sees 3 of the noise's 4 degrees of freedom, so it can read low.
STROBE_NOISE_WIDEN = 2.0
# (S4): a fit with a residual below this (relative to |x₁|) is clean: the deviations are
# far above the computed map's noise, and its ρ stands until the next clean fit.  At
# the noise floor the noise itself can fit three agreeing traces (measured: τ = −0.92,
# a complex pair, on a run whose multipliers are 0.83 and 0.34), so ρ is never taken
# below the last clean fit's.  Clean fits read 1e-7 to 1e-4 on the step above.
STROBE_CLEAN_RESIDUAL = 1e-3
# (S4): the traces of three successive fits must agree to this (absolute; clean fits
# agree to 1e-4 on that step, fits of round-off noise scatter by 0.1 to 1).
STROBE_TRACE_AGREE = 0.01
# (S7): the longest orbit looked for, in drive periods (q ≤ this): the stored period
# after a switch holds q periods of windows and the test needs 4q + 1 samples, and
# 4 covers the widest fractional steps (p/2, p/3, p/4) and two period doublings.
STROBE_MAX_PERIODS = 4
# (S7): the samples kept for the maps P^q (the four q-deviations span 4q + 1 samples).
STROBE_RING = 4 * STROBE_MAX_PERIODS
# (S7): for each proper divisor d of q the samples d drive periods apart must differ by
# more than this many switch scales: both are within one scale of their classes'
# limits, so those differ by 98 scales, ten tolerances: the orbit's period is not d.
STROBE_DISTINCT = 100.0
# (S8): the lock watch's first block of samples: 24 is a multiple of every orbit period
# 1, 2, 3, 4, 6, 8, 12, whose swing a block's mean of θ then removes.
LOCK_BLOCK = 24
# (S8): block means kept; when all are filled, neighbours merge (the blocks double), so
# the history spans the whole run in a fixed number of words.
LOCK_SLOTS = 32
# (S8): drive periods the lock must hold over (the later half of the history) before a
# run that never switched is called locked: a saddle-node's laminar phases next to a
# step are shorter than this a few 1e-6 in γ off its edge (mbm.junction.shapiro).
LOCK_MIN_PERIODS = 384
# (S8): the largest q of a step p/q the watch names (a mean velocity p/q·Ω).
LOCK_MAX_Q = 12
# (S8): the block means' largest distance (rad) from the line of slope 2πp/q: a slip
# moves them by 2π for good, a locked orbit's means stay within its swing's remainder.
LOCK_BAND = 0.5 * math.pi
# (S8): the longest orbit looked for in the ring of samples (drive periods), and the
# agreement (in switch scales) of samples that far apart for the orbit to be periodic.
LOCK_RING_PERIODS = STROBE_RING // 2
LOCK_PERIODIC = 1e3

# The phase-locked window's coefficient layout (STROBE_WIDTH): the index of each entry
# of :func:`strobe_coef`'s vector (S6).
STR_TAG = 0  # STROBE_TAG (an approximant window's anchor status, 0.0, there)
STR_PHI = 1  # φ_a: the anchor's angle, reduced (θ = 2πk_a + φ_a)
STR_V = 2  # θ'_a: θ' at the anchor
STR_WIND = 3  # k_a: the anchor's winding count
STR_T = 4  # t_a: the anchor's time (a stroboscopic sample's)
STR_Q = 5  # q: drive periods per period of the orbit (S7)
STR_P = 6  # p: turns per period
STR_PSI = 7  # ψ_a: the drive's phase at t_a, reduced to [−π, π] (S6)
STR_BETA = 8  # β of the model the stored period is re-taken with
STR_GAMMA = 9  # γ of that model
STR_OMEGA = 10  # ω of that model
STR_AMP = 11  # A: the drive's amplitude
STR_FREQ = 12  # Ω: the drive's frequency
STR_RTOL = 13  # rtol the stored period is re-taken with
STR_ATOL = 14  # atol the stored period is re-taken with
STR_KARG_ORDER = 15  # karg + STROBE_CODE·error_order (the approximant's kind argument and error order)

#: The last four stroboscopic deviations Δ, oldest first (S3, S4): ``d3``, ``d2``, ``d1``
#: and the newest ``c``, each a (θ part, θ' part) pair.
StrobeDevs = collections.namedtuple("StrobeDevs", ("d3", "d2", "d1", "c"))

#: The switch rule's fits so far (S4): the traces fitted at the two samples before
#: (``tau1``, ``tau2``; nan: failed or not made) and the last clean fit's spectral
#: radius ``rho_clean`` (nan: none yet).
StrobeFits = collections.namedtuple("StrobeFits", ("tau1", "tau2", "rho_clean"))

#: A phase-locked window's anchor (S6, S7): θ = 2π``k`` + ``phi``, θ' = ``v`` at time
#: ``t`` (a stroboscopic sample's), ``q`` drive periods and ``p`` turns per period, the
#: drive's phase ``psi`` there (:func:`strobe_phase`).
StrobeAnchor = collections.namedtuple("StrobeAnchor", ("phi", "v", "k", "t", "q", "p", "psi"))

#: What a phase-locked window's stored period is re-taken with (S6): the model β, γ, ω,
#: the drive's A, Ω, the tolerances and the approximant's kind argument and error order.
StrobeRetake = collections.namedtuple(
    "StrobeRetake", ("beta", "gamma", "omega", "amp", "freq", "rtol", "atol", "karg", "error_order"))


@kernel
def strobe_period(freq, q):
    """The period qT_d = 2πq/Ω as a double-double (items S1, S6).

    Parameters
    ----------
    freq : float
        Ω > 0.
    q : float
        Drive periods per period of the orbit (an integer, 1 to STROBE_MAX_PERIODS: S7).

    Returns
    -------
    hi, lo : float
    """
    hi, lo = dd_div_d(TWO_PI_HI, TWO_PI_LO, freq)
    return dd_mul_d(hi, lo, q)


@kernel
def strobe_time(t_s, n, p_hi, p_lo):
    """The stroboscopic time t_s + n·P (item S1): its rounding and the residual.

    Parameters
    ----------
    t_s : float
        The first sample's time (the run's start).
    n : float
        Sample index (an integer).
    p_hi, p_lo : float
        P (:func:`strobe_period`).

    Returns
    -------
    t_n, r_n : float
        t_n = fl(t_s + nP) and r_n = (t_s + nP) − t_n (to double-double accuracy).
    """
    mh, ml = dd_mul_d(p_hi, p_lo, n)
    return dd_add(mh, ml, t_s, 0.0)


@kernel
def strobe_phase(freq, phase, t):
    """The drive's phase Ωt + φ reduced to [−π, π] (item S6).

    Ωt is an exact product and the reduction is :func:`mbm.special.dd.reduce_2pi`'s, so
    the result is good to a few ulps of π for any t (|Ωt| < 1e15).

    Parameters
    ----------
    freq, phase : float
        The drive's Ω and φ.
    t : float
        Time.

    Returns
    -------
    float
    """
    p, e = two_prod(freq, t)
    hi, e2 = two_sum(p, phase)
    _, rh, rl = reduce_2pi(hi)
    return rh + (rl + (e + e2))


@kernel
def strobe_split(t, t_a, p_hi, p_lo):
    """``(n, s)`` with t − t_a = nP + s, 0 ≤ s ≤ fl(P) (item S6).

    t − t_a is formed exactly (Knuth's sum) and nP in double-double, so s carries a few
    ulps of P whatever n (not n·eps·P).

    Parameters
    ----------
    t, t_a : float
        The time and the anchor's time.
    p_hi, p_lo : float
        P (:func:`strobe_period`).

    Returns
    -------
    n, s : float
        n an integer (as a float).
    """
    n, s, _ = strobe_split_from(t, t_a, (p_hi, p_lo), NO_MULTIPLE)
    return n, s


#: A :func:`strobe_split_from` ``known`` that holds no multiple of P yet.
NO_MULTIPLE = (math.nan, 0.0, 0.0)


# Inlined: the range kernels call it once per output time, where a call measured ~2 ns
# of ~21 per output.
@numba.njit(**INLINE)
def strobe_split_from(t, t_a, p, known):
    """:func:`strobe_split` (``p`` = (p_hi, p_lo)) with a multiple of P remembered:
    ``known`` = (n, nP in double-double) of an earlier call (:data:`NO_MULTIPLE`: none)
    is tried first and taken where this time's n is the same, as it is for most of a run
    of sorted times (the same operations on the same values: the same bits, and no
    division).  Returns (n, s, the multiple to pass on)."""
    p_hi, p_lo = p
    th, tl = two_sum(t, -t_a)
    if known[0] == known[0]:
        # The remembered multiple first: where it puts s in [0, P) it is the one n the
        # quotient's test below ends on (one n does), without the division.
        sh, sl = dd_add(th, tl, -known[1], -known[2])
        if (sh > 0.0 or (sh == 0.0 and sl >= 0.0)) and (sh < p_hi or (sh == p_hi and sl < p_lo)):
            return known[0], min(max(sh + sl, 0.0), p_hi), known
    n = np.floor(th / p_hi)
    sh, sl = 0.0, 0.0
    for _ in range(3):
        if n != known[0]:
            mh, ml = dd_mul_d(p_hi, p_lo, n)
            known = (n, mh, ml)
        sh, sl = dd_add(th, tl, -known[1], -known[2])
        # The quotient's rounding can put s just outside [0, P) (compared in
        # double-double: s may round to fl(P) while below P): one period more or less.
        if sh < 0.0 or (sh == 0.0 and sl < 0.0):
            n -= 1.0
        elif sh > p_hi or (sh == p_hi and sl >= p_lo):
            n += 1.0
        else:
            break
    return n, min(max(sh + sl, 0.0), p_hi), known


@kernel
def _spectral_radius(tau, det):
    # (S4): max |μ| of μ² − τμ + D = 0.
    disc = tau * tau - 4.0 * det
    return math.sqrt(det) if disc < 0.0 else 0.5 * (abs(tau) + math.sqrt(disc))


@kernel
def strobe_switch(devs, det, omega, scale, fits):
    """Whether the stroboscopic deviations have converged enough to switch (items S3-S5).

    Parameters
    ----------
    devs : StrobeDevs
        The last four deviations Δ, oldest first, each a (θ part, θ' part) pair (a plain
        tuple of pairs from Python).
    det : float
        D = e^{−βP} (S2).
    omega : float
        ω: the θ parts are weighted by it.
    scale : float
        SWITCH_SAFETY · min(atol + rtol·|θ'|, ω(atol + rtol·|θ|)) at the anchor (S5).
    fits : StrobeFits
        The traces fitted at the two samples before (``tau1``, ``tau2``: nan where that
        fit failed or was not made) and the spectral radius of the last clean fit
        (``rho_clean``: residual ≤ STROBE_CLEAN_RESIDUAL; nan: none yet); a plain
        triple from Python.

    Returns
    -------
    ok : bool
        A clean fit seen, the three fits (this one, tau1, tau2) within
        STROBE_FIT_RESIDUAL and within STROBE_TRACE_AGREE of each other,
        ρ ≤ STROBE_MAX_MULTIPLIER and B ≤ scale.
    tau : float
        This sample's fitted trace (nan where the fit failed).
    rho_clean : float
        Updated: this fit's spectral radius if it is clean, else the one given.
    rho, bound : float
        The spectral radius used and B (S3); inf where a fit failed.
    """
    (d3t, d3v), (d2t, d2v), (d1t, d1v), (ct, cv) = devs
    tau1, tau2, rho_clean = fits
    # Scaled to the largest component (the squares below neither underflow nor overflow).
    big = max(max(max(omega * abs(d3t), abs(d3v)), max(omega * abs(d2t), abs(d2v))),
              max(max(omega * abs(d1t), abs(d1v)), max(omega * abs(ct), abs(cv))))
    if big == 0.0:
        # Converged to the bit: every later deviation is 0.
        return True, math.nan, rho_clean, 0.0, 0.0
    if not (big < math.inf):
        return False, math.nan, rho_clean, math.inf, math.inf
    w = omega / big
    u = 1.0 / big
    # (S4): the equations x₂ + D·x₀ = τ·x₁ of the triples (d3, d2, d1) and (d2, d1, c).
    a0, a1, a2, a3 = w * d2t, u * d2v, w * d1t, u * d1v
    b0 = w * (d1t + det * d3t)
    b1 = u * (d1v + det * d3v)
    b2 = w * (ct + det * d2t)
    b3 = u * (cv + det * d2v)
    x1 = big * math.sqrt((w * ct) ** 2 + (u * cv) ** 2)
    x0 = big * math.sqrt(a2 * a2 + a3 * a3)
    s11 = a0 * a0 + a1 * a1 + a2 * a2 + a3 * a3
    if s11 == 0.0:
        # d2 = d1 = 0: converged to the bit if the newest is 0 too.
        return x1 == 0.0, math.nan, rho_clean, 0.0, 0.0
    tau = (a0 * b0 + a1 * b1 + a2 * b2 + a3 * b3) / s11
    res = math.sqrt((b0 - tau * a0) ** 2 + (b1 - tau * a1) ** 2 + (b2 - tau * a2) ** 2
                    + (b3 - tau * a3) ** 2)
    res_rel = res / math.sqrt(s11)
    if not (res_rel <= STROBE_FIT_RESIDUAL):
        return False, math.nan, rho_clean, math.inf, math.inf
    # (S4): ρ of this fit, at |τ| widened by the residual's share of τ (ρ does not
    # decrease as |τ| grows); a clean fit's is remembered, for fits at the noise floor.
    rho = _spectral_radius(abs(tau) + STROBE_NOISE_WIDEN * res_rel * (1.0 + abs(tau)), det)
    if res_rel <= STROBE_CLEAN_RESIDUAL:
        rho_clean = rho
    if math.isnan(tau1) or math.isnan(tau2) or math.isnan(rho_clean):
        return False, tau, rho_clean, math.inf, math.inf
    # (S4): three successive fits agreeing (noise passes one fit now and then, with a
    # wrong τ, but not three that agree), ρ at the largest |τ| of them widened by their
    # spread, and not below the last clean fit's.
    lo = min(tau, min(tau1, tau2))
    hi = max(tau, max(tau1, tau2))
    if not (hi - lo <= STROBE_TRACE_AGREE):
        return False, tau, rho_clean, math.inf, math.inf
    tau_wide = (max(abs(tau), max(abs(tau1), abs(tau2))) + (hi - lo)
                + STROBE_NOISE_WIDEN * res_rel * (1.0 + abs(tau)))
    rho = max(_spectral_radius(tau_wide, det), rho_clean)
    if not (rho <= STROBE_MAX_MULTIPLIER):
        return False, tau, rho_clean, rho, math.inf
    # (S3): the tail of the deviations still to come.
    g = 1.0 / ((1.0 - rho) * (1.0 - rho))
    bound = x1 * (g - 1.0) + det * x0 * g
    return bound <= scale, tau, rho_clean, rho, bound


@kernel
def strobe_coef(anchor, retake):
    """A phase-locked window's coefficient vector (layout: STROBE_TAG; item S6).

    Parameters
    ----------
    anchor : StrobeAnchor
        The anchor: θ = 2πk_a + φ_a, θ'_a at its time t_a (a stroboscopic sample's);
        q, p: drive periods per period (1 to STROBE_MAX_PERIODS, S7) and turns per
        period; ψ_a: :func:`strobe_phase` at t_a.
    retake : StrobeRetake
        The model and the drive's A, Ω, the tolerances, the approximant's kind argument
        and error order the stored period is re-taken with.

    Returns
    -------
    ndarray, shape (STROBE_WIDTH,)
    """
    phi_a, v_a, k_a, t_a, q, p, psi_a = anchor.phi, anchor.v, anchor.k, anchor.t, anchor.q, anchor.p, anchor.psi
    beta, gamma, omega, amp, freq = retake.beta, retake.gamma, retake.omega, retake.amp, retake.freq
    rtol, atol, karg, error_order = retake.rtol, retake.atol, retake.karg, retake.error_order
    c = np.empty(STROBE_WIDTH)
    c[STR_TAG] = STROBE_TAG
    c[STR_PHI] = phi_a
    c[STR_V] = v_a
    c[STR_WIND] = k_a
    c[STR_T] = t_a
    c[STR_Q] = q
    c[STR_P] = p
    c[STR_PSI] = psi_a
    c[STR_BETA] = beta
    c[STR_GAMMA] = gamma
    c[STR_OMEGA] = omega
    c[STR_AMP] = amp
    c[STR_FREQ] = freq
    c[STR_RTOL] = rtol
    c[STR_ATOL] = atol
    c[STR_KARG_ORDER] = karg + STROBE_CODE * error_order
    return c


def strobe_summary(p, q, freq):
    """``(period, mean_velocity)`` of a phase-locked run: qT_d and pΩ/q (item S6).

    Parameters
    ----------
    p, q : float
        Turns per period and drive periods per period (the record's ``str_p``, ``str_q``).
    freq : float
        Ω.

    Returns
    -------
    (float, float)
    """
    return float(q) * 2.0 * math.pi / float(freq), float(p) * float(freq) / float(q)
