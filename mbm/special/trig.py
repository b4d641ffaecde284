r"""Trigonometric approximants sin_m, cos_m of the Jacobi functions sn(t|m), cn(t|m).

First paper (Salas 2021), (3.12)–(3.14), and second paper (Salas, Martínez, Ocampo
2022), (2.25)–(2.26):

.. math::

    A(m) = \sqrt{m^2 - 144 m + 144}                       \qquad (3.13),\ \kappa \text{ of } (2.26)

    w(t) = \sqrt{\tfrac{A - m + 2}{14}}\; t                \qquad (2.26)

    \cos_m(t) = \frac{\sqrt{A - m + 2}\,\cos w}{\sqrt{14 + (A - m - 12)\cos^2 w}}   \qquad (3.14),\ (2.25)

    \sin_m(t) = \frac{\sqrt{14}\,\sin w}{\sqrt{14 + (A - m - 12)\cos^2 w}}          \qquad (3.12)\ \text{reconstructed}

Reconstruction of (3.12).  As extracted, (3.12) reads
sin(√(1 + (A−m−12)/14)·t) / √(1 + (A−m−12)/14 · cos²(√((A−m−12)/14)·t)): the
numerator's argument is w (1 + (A−m−12)/14 = (A−m+2)/14), but the cos² argument in
the denominator has lost the "1 +" under its root.  With w in both places the
denominator is √(14 + (A−m−12)cos²w)/√14, the *same* as in (3.14)/(2.25), and then

    sin_m² + cos_m² = [14 sin²w + (A−m+2) cos²w] / [14 + (A−m−12) cos²w] = 1

exactly, the identity sn² + cn² = 1; with the printed argument it fails (and sin_m
would not vanish where cos_m has its maxima).  At m = 0, A = 12 and the pair is
(sin t, cos t) = (sn(t|0), cn(t|0)).

Derivatives.  With L = A − m + 2 and D = 14 + (A − m − 12)cos²w, differentiating
the formulas gives

    d sin_m/dt =  cos_m · dn_m,   d cos_m/dt = −sin_m · dn_m,   dn_m := L / D,

mirroring sn' = cn dn, cn' = −sn dn; dn_m(t) approximates dn(t|m) (it is 1 at
m = 0).  :func:`sin_m_dm_kernel` gives ∂sin_m/∂m at fixed t (needed when m varies
with t, as in Johannessen's approximant (3.9)).

Domain.  A is real for m ≤ 72 − √5040 ≈ 1.00703 and L > 0 there; the papers use
−1 ≤ m < 1 ((3.13)) and −1 ≤ m ≤ 0.55 ((2.25), whose Table 1 lists the errors).
The kernels accept m ≤ 1 (:data:`M_MAX`) and return nan beyond; the numpy-level
functions raise ``ValueError``.  The period of sin_m is 2π√(14/L), not 4K(m), so the
phase error against sn grows linearly in t (use one period, as the papers do).
"""

import math

import numba
import numpy as np

from ..compile.jit import NJIT_OPTIONS, kernel

__all__ = [
    "M_MAX",
    "sin_m",
    "cos_m",
    "dn_m",
    "trig_m_kernel",
    "sin_m_kernel",
    "cos_m_kernel",
    "sin_m_dm_kernel",
]

# Largest parameter accepted: sn, cn are approximated for m < 1 (3.13) and the
# formula itself stays real up to 72 − √5040 ≈ 1.00703; m = 1 is kept as a closed end.
M_MAX = 1.0


@kernel(error_model="numpy")
def _setup(m):
    """A (3.13), L = A − m + 2, N = A − m − 12 and the frequency ν = √(L/14) of (2.26)."""
    A = math.sqrt(m * m - 144.0 * m + 144.0)
    L = A - m + 2.0
    N = A - m - 12.0
    return A, L, N, math.sqrt(L / 14.0)


@numba.njit(**NJIT_OPTIONS)
def trig_m_kernel(t, m):
    """sin_m(t), cos_m(t), dn_m(t) of (3.12)–(3.14); nan when m > M_MAX or m is nan.

    ``d sin_m/dt = cos_m·dn_m`` and ``d cos_m/dt = −sin_m·dn_m`` exactly.
    """
    if not (m <= M_MAX):
        return math.nan, math.nan, math.nan
    A, L, N, nu = _setup(m)
    w = nu * t
    sw = math.sin(w)
    cw = math.cos(w)
    D = 14.0 + N * cw * cw
    rD = 1.0 / math.sqrt(D)
    return math.sqrt(14.0) * sw * rD, math.sqrt(L) * cw * rD, L / D


@numba.njit(**NJIT_OPTIONS)
def sin_m_kernel(t, m):
    """sin_m(t) ≈ sn(t|m), (3.12) reconstructed (see module docstring)."""
    return trig_m_kernel(t, m)[0]


@numba.njit(**NJIT_OPTIONS)
def cos_m_kernel(t, m):
    """cos_m(t) ≈ cn(t|m), (3.14) = (2.25)–(2.26)."""
    return trig_m_kernel(t, m)[1]


@numba.njit(**NJIT_OPTIONS)
def sin_m_dm_kernel(t, m):
    """∂sin_m(t)/∂m at fixed t; nan when m > M_MAX (or at m = 72 − √5040, A = 0)."""
    if not (m <= M_MAX):
        return math.nan
    A, L, N, nu = _setup(m)
    dA = (m - 72.0) / A  # d/dm √(m² − 144m + 144)
    dL = dA - 1.0  # = dN/dm
    dnu = dL / (28.0 * nu)  # d/dm √(L/14)
    w = nu * t
    sw = math.sin(w)
    cw = math.cos(w)
    D = 14.0 + N * cw * cw
    dw = dnu * t
    dD = dL * cw * cw - 2.0 * N * cw * sw * dw
    # sin_m = √14 sin w D^(−1/2)
    return math.sqrt(14.0) * (cw * dw / math.sqrt(D) - 0.5 * sw * dD / (D * math.sqrt(D)))


@kernel(error_model="numpy")
def _trig_array(t, m, which, out):
    for i in range(t.size):
        out[i] = trig_m_kernel(t[i], m[i])[which]


def _apply(t, m, which):
    t_arr, m_arr = np.broadcast_arrays(np.asarray(t, dtype=float), np.asarray(m, dtype=float))
    if np.any(np.isnan(m_arr)) or np.any(m_arr > M_MAX):
        raise ValueError(f"m must be a real number <= {M_MAX} (the approximants need m <= 1), got {m!r}")
    tt = np.ascontiguousarray(t_arr, dtype=float).reshape(-1)
    mm = np.ascontiguousarray(m_arr, dtype=float).reshape(-1)
    out = np.empty_like(tt)
    _trig_array(tt, mm, which, out)
    out = out.reshape(t_arr.shape)
    return out[()] if out.ndim == 0 else out


def sin_m(t, m):
    """Trigonometric approximant of the Jacobi sn, (3.12)–(3.13) of the first paper.

    Parameters
    ----------
    t : array_like
        Argument.
    m : array_like
        Parameter, ``m <= 1`` (the paper uses −1 ≤ m < 1); broadcast against ``t``.

    Returns
    -------
    ndarray or float
        √14 sin w / √(14 + (A − m − 12) cos² w), w = √((A − m + 2)/14) t,
        A = √(m² − 144m + 144).

    Raises
    ------
    ValueError
        If some ``m > 1`` or is nan.

    Examples
    --------
    >>> from mbm.special.trig import sin_m
    >>> import numpy as np
    >>> bool(np.isclose(sin_m(1.0, 0.0), np.sin(1.0), rtol=1e-15))  # m = 0: sin
    True
    >>> round(float(sin_m(1.0, 0.5)), 6)  # sn(1 | 0.5) = 0.803002
    0.800101
    """
    return _apply(t, m, 0)


def cos_m(t, m):
    """Trigonometric approximant of the Jacobi cn, (3.14) of the first paper = (2.25)–(2.26) of the second.

    Parameters
    ----------
    t : array_like
        Argument.
    m : array_like
        Parameter, ``m <= 1`` (the second paper tabulates −1 ≤ m ≤ 0.55).

    Returns
    -------
    ndarray or float
        √(A − m + 2) cos w / √(14 + (A − m − 12) cos² w).

    Raises
    ------
    ValueError
        If some ``m > 1`` or is nan.
    """
    return _apply(t, m, 1)


def dn_m(t, m):
    """The factor dn_m = (A − m + 2)/(14 + (A − m − 12) cos² w) with sin_m' = cos_m dn_m.

    Parameters
    ----------
    t, m : array_like
        As for :func:`sin_m`.

    Returns
    -------
    ndarray or float
        dn_m(t), an approximant of dn(t|m) implied by (3.12)–(3.14).

    Raises
    ------
    ValueError
        If some ``m > 1`` or is nan.
    """
    return _apply(t, m, 2)
