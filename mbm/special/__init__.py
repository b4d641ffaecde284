"""Special functions for the pendulum approximants: Jacobi elliptic functions,
elliptic integrals of the first kind, the Weierstrass ℘ function, and the exact
flow of the undamped pendulum built on them.

Numpy-level functions (broadcasting, validated, never a silent NaN):

* Jacobi: :func:`sn`, :func:`cn`, :func:`dn`, :func:`am`, :func:`ellipj`,
  :func:`ellipk`, :func:`ellipf` -- every function of the parameter takes
  ``m`` and, optionally, ``mc = 1 - m`` (pass it when known more accurately,
  e.g. ``mc = 1e-15``).
* Weierstrass: :func:`wp`, :func:`wpp` (℘′), :func:`wp_roots`,
  :func:`wp_half_period`, :func:`wp_inverse`.

Scalar numba kernels for use inside other ``numba.njit`` code (call them
with float64 arguments so that a single signature is compiled):

* ``ellipj_kernel(u, m, mc) -> (sn, cn, dn, am)``
* ``ellipk_kernel(m, mc) -> K``
* ``ellipf_kernel(phi, m, mc) -> F``
* ``wp_roots_kernel(g2, g3) -> (r1, r2, r3, delta_sign)``
* ``wp_kernel(z, g2, g3) -> (wp, wpprime)``; for many z with the same
  invariants, ``wp_eval_kernel(z, wp_lattice_kernel(g2, g3))`` gives the same
  bits without recomputing the roots and the period each time
* ``wp_half_period_kernel(g2, g3) -> omega``
* ``wp_inverse_kernel(w, g2, g3) -> z``
* ``ellipk_dd_kernel(mc, mc_lo) -> (K_hi, K_lo)``: the one double-double K
* ``pendulum_flow_kernel(theta0, v0, omega, t) -> (theta, theta_dot)``: the exact
  flow of θ'' + ω² sin θ = 0 from any state; ``period_kernel(theta0, v0, omega)``

Modules: :mod:`~mbm.special.jacobi`, :mod:`~mbm.special.weierstrass`,
:mod:`~mbm.special.trig`, :mod:`~mbm.special.pendulum_flow` (also the Python-level
``pendulum_flow`` and ``period``, exported as ``mbm.pendulum_flow``, ``mbm.period``),
:mod:`~mbm.special.dd` (double-double arithmetic and the one 2π reduction,
``reduce_2pi``) and :mod:`~mbm.compile.jit` (``NJIT_OPTIONS``, the kernels' numba
options).

See :mod:`mbm.special.jacobi` and :mod:`mbm.special.weierstrass` for the
conventions (in particular the Δ < 0 convention of ``wp_roots_kernel``) and
the accuracy.
"""

from .jacobi import (
    am,
    cn,
    dn,
    ellipf,
    ellipf_kernel,
    ellipj,
    ellipj_kernel,
    ellipk,
    ellipk_dd_kernel,
    ellipk_kernel,
    sn,
)
from .pendulum_flow import pendulum_flow_kernel, period_kernel
from .trig import (
    M_MAX as TRIG_M_MAX,
    cos_m,
    cos_m_kernel,
    dn_m,
    sin_m,
    sin_m_dm_kernel,
    sin_m_kernel,
    trig_m_kernel,
)
from .weierstrass import (
    wp,
    wp_eval_kernel,
    wp_half_period,
    wp_half_period_kernel,
    wp_inverse,
    wp_inverse_kernel,
    wp_kernel,
    wp_lattice_kernel,
    wp_roots,
    wp_roots_kernel,
    wpp,
)

__all__ = [
    # Jacobi, numpy level
    "sn",
    "cn",
    "dn",
    "am",
    "ellipj",
    "ellipk",
    "ellipf",
    # Weierstrass, numpy level
    "wp",
    "wpp",
    "wp_roots",
    "wp_half_period",
    "wp_inverse",
    # trigonometric approximants of sn, cn (first paper (3.12)-(3.14), second (2.25)-(2.26))
    "sin_m",
    "cos_m",
    "dn_m",
    "TRIG_M_MAX",
    # numba kernels
    "ellipj_kernel",
    "ellipk_kernel",
    "ellipk_dd_kernel",
    "ellipf_kernel",
    "wp_roots_kernel",
    "wp_kernel",
    "wp_lattice_kernel",
    "wp_eval_kernel",
    "wp_half_period_kernel",
    "wp_inverse_kernel",
    "trig_m_kernel",
    "sin_m_kernel",
    "cos_m_kernel",
    "sin_m_dm_kernel",
    "pendulum_flow_kernel",
    "period_kernel",
]
