"""Jacobi elliptic functions sn, cn, dn, am and the elliptic integrals K(m), F(φ|m).

Two layers:

* numba kernels (``ellipj_kernel``, ``ellipk_kernel``, ``ellipf_kernel``) taking
  scalar float64 arguments, meant to be called from other numba code;
* numpy-level wrappers (``sn``, ``cn``, ``dn``, ``am``, ``ellipj``, ``ellipk``,
  ``ellipf``) that broadcast, validate and never return a silent NaN.

Every function of the parameter takes both ``m`` and ``mc = 1 - m``.  The
kernels treat ``mc`` as authoritative wherever ``1 - m`` is needed (it decides
the branch and feeds K and the complementary modulus), so a caller who knows
``mc = 1e-15`` exactly gets the function at that parameter, not at
``m = fl(1 - 1e-15)``.

Method
------
* Argument reduction ``u - n*4K`` in double-double arithmetic with K from an
  arithmetic-geometric mean carried out in double-double (Dekker/Knuth
  error-free transformations; numba emits no fma, so products are split).
* Further folding to ``[0, K/2]`` with the half- and quarter-period shifts
  (``sn(K - t) = cd t``, ``cn(K - t) = k' sd t``, ``dn(K - t) = k' nd t``), so
  that cn and dn are relatively accurate near their zeros/minima.
* On ``[0, K/2]`` the descending Landen transformation (DLMF §22.7(i)) with
  subtraction-free formulas for the moduli (``k1 = m/(1 + k')^2``,
  ``1 - k1^2 = 4k'/(1 + k')^2``) and for the way back up (sn, cn from
  positive terms, dn from ``dn^2 = cn^2 + mc sn^2``), projecting (sn, cn)
  back onto ``sn^2 + cn^2 = 1`` at every level because the upward map
  doubles that error per level.  For ``mc <= 1e-16`` the first-order
  expansion about m = 1 (DLMF §22.10(ii)) replaces the chain.  sn, cn and dn
  keep relative accuracy (~1e-14 worst, at m -> 1) down to ``mc = 1e-308``.
* ``m < 0`` and ``m > 1`` through the imaginary- and reciprocal-modulus
  transformations (DLMF §22.17), with the scaled argument and the
  transformed complementary modulus in double-double so that large arguments
  stay accurate.
* F(φ|m) through Carlson's R_F with ``1 - m sin^2 = cos^2 + mc sin^2`` and
  quasi-periodicity ``F(φ + jπ) = F(φ) + 2jK`` (reduction in double-double).

Double-double building blocks for other kernels: :func:`ellipk_dd_kernel` (K
from 1 - m), :func:`ellipk_kc_dd_kernel` (K from k'), :func:`ellipj_kc_dd_kernel`
(sn, cn, dn at a double-double argument) and :func:`carlson_rf_kernel`.
"""

import numpy as np

from ._arrays import finite_f64, flat, nan_guard, unflat
from .dd import EPS
from .jacobi_kernels import (  # noqa: F401  callers and tests import these from here
    LANDEN_M_STOP, MC_HYPERBOLIC, LANDEN_SLOTS, _LANDEN_BUF, AGM_DD_RTOL,
    AGM_D_RTOL, AGM_MAX_ITER, FAST_PATH_FRACTION, RF_Q_FACTOR, RF_MAX_ITER,
    EDGE_CLAMP_ULPS, MC_CONSISTENCY_ULPS, REDUCE_MAX_PERIODS, _stack_f64,
    ellipk_kc_dd_kernel, ellipk_dd_kernel, _ellipk_rough, ellipk_kernel, _landen,
    ellipj_kc_dd_kernel, _ellipj_dd, ellipj_kernel, carlson_rf_kernel,
    ellipf_kernel,
)
from ..compile.jit import kernel

__all__ = [
    "ellipj_kernel",
    "ellipj_kc_dd_kernel",
    "ellipk_kernel",
    "ellipk_dd_kernel",
    "ellipk_kc_dd_kernel",
    "carlson_rf_kernel",
    "ellipf_kernel",
    "sn",
    "cn",
    "dn",
    "am",
    "ellipj",
    "ellipk",
    "ellipf",
]


# ---------------------------------------------------------------------------
# Array loops (one compiled signature each: 1-D contiguous float64)
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def _ellipj_loop(u, m, mc, out_sn, out_cn, out_dn, out_am):
    for i in range(u.shape[0]):
        s, c, d, a = ellipj_kernel(u[i], m[i], mc[i])
        out_sn[i] = s
        out_cn[i] = c
        out_dn[i] = d
        out_am[i] = a


@kernel(error_model="numpy")
def _ellipk_loop(m, mc, out):
    for i in range(m.shape[0]):
        out[i] = ellipk_kernel(m[i], mc[i])


@kernel(error_model="numpy")
def _ellipf_loop(phi, m, mc, out):
    for i in range(phi.shape[0]):
        out[i] = ellipf_kernel(phi[i], m[i], mc[i])


# ---------------------------------------------------------------------------
# numpy-level wrappers
# ---------------------------------------------------------------------------


def _param(m, mc):
    """Validated float64 arrays (m, mc); mc defaults to 1 - m."""
    ma = finite_f64("m", m)
    if mc is None:
        return ma, 1.0 - ma
    mca = finite_f64("mc", mc)
    ma, mca = np.broadcast_arrays(ma, mca)
    mismatch = np.abs((ma - 1.0) + mca)
    scale = np.maximum(1.0, np.maximum(np.abs(ma), np.abs(mca)))
    bad = mismatch > MC_CONSISTENCY_ULPS * EPS * scale
    if np.any(bad):
        i = np.flatnonzero(bad.ravel())[0]
        raise ValueError(
            "mc must equal 1 - m to within a few ulps; got "
            f"m={ma.ravel()[i]!r}, mc={mca.ravel()[i]!r}"
        )
    return ma, mca


def ellipj(u, m, mc=None):
    """Jacobi elliptic functions sn, cn, dn and the amplitude am.

    Parameters
    ----------
    u : array_like
        Argument, finite real.
    m : array_like
        Parameter, finite real (any sign; m > 1 and m < 0 by the standard
        modulus transformations).
    mc : array_like, optional
        Complementary parameter 1 - m.  Pass it when it is known more
        accurately than ``1 - m`` (e.g. ``mc = 1e-15``); it must agree with
        ``1 - m`` to a few ulps.

    Returns
    -------
    sn, cn, dn, am : float or ndarray
        Broadcast shape of the inputs; Python floats for scalar input.  am is
        the increasing amplitude for m <= 1 (am(u + 4K) = am(u) + 2 pi) and
        the continuous angle with sin am = sn, cos am = cn for m > 1.

    Raises
    ------
    ValueError
        Non-finite input, or m and mc inconsistent.
    """
    ua = finite_f64("u", u)
    ma, mca = _param(m, mc)
    scalar = ua.ndim == 0 and ma.ndim == 0
    shape, (uf, mf, mcf) = flat(ua, ma, mca)
    outs = [np.empty(uf.shape[0]) for _ in range(4)]
    _ellipj_loop(uf, mf, mcf, *outs)
    nan_guard("ellipj", *outs)
    return tuple(unflat(o, shape, scalar) for o in outs)


def sn(u, m, mc=None):
    """Jacobi sn(u | m); see :func:`ellipj` for parameters and accuracy.

    Returns
    -------
    float or ndarray
    """
    return ellipj(u, m, mc)[0]


def cn(u, m, mc=None):
    """Jacobi cn(u | m); see :func:`ellipj` for parameters and accuracy.

    Returns
    -------
    float or ndarray
    """
    return ellipj(u, m, mc)[1]


def dn(u, m, mc=None):
    """Jacobi dn(u | m); see :func:`ellipj` for parameters and accuracy.

    Returns
    -------
    float or ndarray
    """
    return ellipj(u, m, mc)[2]


def am(u, m, mc=None):
    """Jacobi amplitude am(u | m); see :func:`ellipj`.

    Returns
    -------
    float or ndarray
    """
    return ellipj(u, m, mc)[3]


def ellipk(m, mc=None):
    """Complete elliptic integral of the first kind K(m).

    Parameters
    ----------
    m : array_like
        Parameter, m < 1 (any negative value allowed).
    mc : array_like, optional
        Complementary parameter 1 - m > 0; pass it for m close to 1.

    Returns
    -------
    float or ndarray
        K(m) (double-double AGM, correctly rounded in practice).

    Raises
    ------
    ValueError
        If m >= 1 (mc <= 0): K is infinite at m = 1 and not real beyond.
    """
    ma, mca = _param(m, mc)
    if np.any(mca <= 0.0):
        bad = ma[mca <= 0.0].ravel()[0] if ma.ndim else ma
        raise ValueError(f"m must be < 1 (mc = 1 - m > 0) for ellipk, got m={float(bad)!r}")
    scalar = ma.ndim == 0
    shape, (mf, mcf) = flat(ma, mca)
    out = np.empty(mf.shape[0])
    _ellipk_loop(mf, mcf, out)
    nan_guard("ellipk", out)
    return unflat(out, shape, scalar)


def ellipf(phi, m, mc=None):
    """Incomplete elliptic integral of the first kind F(phi | m).

    Parameters
    ----------
    phi : array_like
        Amplitude.  Any finite real for m < 1 (quasi-periodic:
        F(phi + j pi) = F(phi) + 2 j K); |phi| < pi/2 for m = 1; for m > 1,
        |phi| <= arcsin(1/sqrt(m)) (where F is real).
    m : array_like
        Parameter, finite real.
    mc : array_like, optional
        Complementary parameter 1 - m.

    Returns
    -------
    float or ndarray

    Raises
    ------
    ValueError
        Non-finite input, inconsistent m/mc, or phi outside the real domain
        described above.
    """
    pa = finite_f64("phi", phi)
    ma, mca = _param(m, mc)
    scalar = pa.ndim == 0 and ma.ndim == 0
    shape, (pf, mf, mcf) = flat(pa, ma, mca)
    out = np.empty(pf.shape[0])
    _ellipf_loop(pf, mf, mcf, out)
    bad = np.isnan(out)
    if bad.any():
        i = np.flatnonzero(bad)[0]
        raise ValueError(
            "phi outside the real domain of F(phi|m): need |phi| < pi/2 for m = 1 and "
            "|phi| <= arcsin(1/sqrt(m)) for m > 1; "
            f"got phi={pf[i]!r}, m={mf[i]!r}"
        )
    return unflat(out, shape, scalar)
