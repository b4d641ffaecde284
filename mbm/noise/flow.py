r"""The two exact pieces of the Langevin step: the Hamiltonian flow D and the Ornstein–Uhlenbeck step O.

The scene θ'' + βθ' + ω² sin θ = γ0 + r t + A sin(Ωt + φ) + ξ(t), ⟨ξ(t)ξ(t')⟩ =
2βT δ(t − t'), is split into

* D: θ'' = −ω² sin θ + γ0 + r t + A sin(Ωt + φ), the conservative-plus-forcing flow,
  integrated by a Taylor series in time of degree 6–:data:`TAYLOR_ORDER` over substeps
  of at most :data:`SUBSTEP_MAX` / ω_eff (truncation ≲ 1e-11 per substep, far below
  the splitting's error);
* O: v' = −βv + ξ, the Ornstein–Uhlenbeck process on v = θ', advanced exactly:
  v ← e^{−βτ} v + sqrt(T (1 − e^{−2βτ})) N(0, 1).

The scheme (:mod:`mbm.noise.kernels`) is the symmetric splitting O(h/2) D(h) O(h/2).
The Taylor recurrence: with θ(t0 + s) = Σ b_k (s/hs)^k (coefficients scaled by the
substep hs), sin θ = Σ S_k (s/hs)^k and cos θ = Σ C_k (s/hs)^k obey
k S_k = Σ_{j=1..k} j b_j C_{k−j}, k C_k = −Σ_{j=1..k} j b_j S_{k−j}, and
(k+1)(k+2) b_{k+2} = hs² (g_k − ω² S_k) with g_k the forcing's scaled coefficients.
"""

import math

import numpy as np
from numba import njit

from ..compile.jit import INLINE

__all__ = ["P_BETA", "P_OMEGA2", "P_GAMMA0", "P_RATE", "P_AMP", "P_FREQ", "P_PHASE",
           "P_TEMP", "N_PARAMS", "TAYLOR_ORDER", "TAYLOR_ORDER_MIN", "SUBSTEP_MAX", "TRUNCATION", "make_params", "substeps",
           "hamiltonian_flow", "ou_coefficients"]

# Layout of a scene's parameter vector (float64).
P_BETA, P_OMEGA2, P_GAMMA0, P_RATE, P_AMP, P_FREQ, P_PHASE, P_TEMP = range(8)
N_PARAMS = 8

# The highest degree of D's Taylor series (sizes the scratch arrays and the tables).
TAYLOR_ORDER = 12
# The lowest degree used (short steps): below it the per-step cost barely falls.
TAYLOR_ORDER_MIN = 6
# The longest substep of D in units of 1/ω_eff (ω_eff = max(ω, sqrt|forcing|, Ω)).
SUBSTEP_MAX = 0.25
# The degree is the lowest with (ω_eff hs)^(N+1) ≤ TRUNCATION: at SUBSTEP_MAX that is
# the full degree 12; errors measured ≤ 1e-7 per step (typically 1e-10) against a 1e-13
# DOP853 reference for |θ'| ≤ 2 (tests/noise/test_noise_integrator.py), far below the
# splitting's error.
TRUNCATION = 1e-10
# 1/k and 1/((k+1)(k+2)): the recurrence multiplies instead of dividing.
_INV_K = np.array([0.0] + [1.0 / k for k in range(1, TAYLOR_ORDER + 1)])
_INV_K12 = np.array([1.0 / ((k + 1.0) * (k + 2.0)) for k in range(TAYLOR_ORDER + 1)])


def make_params(beta, omega, gamma0, rate, amp, freq, phase, temperature):
    """A scene's parameter vector in the layout above (no checks: the callers validate)."""
    p = np.empty(N_PARAMS)
    p[P_BETA], p[P_OMEGA2], p[P_GAMMA0], p[P_RATE] = beta, omega * omega, gamma0, rate
    p[P_AMP], p[P_FREQ], p[P_PHASE], p[P_TEMP] = amp, freq, phase, temperature
    return p


def substeps(h, omega, force_max, freq):
    """How D covers a step ``h``: (substeps, Taylor degree).

    ``force_max`` bounds |γ(t)| + |A| over the run; ω_eff = max(ω, sqrt(force_max), Ω);
    substeps = ceil(ω_eff h / SUBSTEP_MAX), degree the lowest N ≥ TAYLOR_ORDER_MIN with
    (ω_eff hs)^(N+1) ≤ TRUNCATION (at most TAYLOR_ORDER).
    """
    w_eff = max(omega, math.sqrt(abs(force_max)), freq)
    nsub = max(1, int(math.ceil(w_eff * h / SUBSTEP_MAX - 1e-12)))
    x = w_eff * h / nsub
    order = TAYLOR_ORDER_MIN
    while order < TAYLOR_ORDER and x ** (order + 1) > TRUNCATION:
        order += 1
    return nsub, order


@njit(**INLINE)
def _substep(theta, v, t, hs, n, p, scratch):
    # One Taylor substep of D (degree n) over hs from (theta, v) at t: the new (theta, v).
    b, sn, cn = scratch
    w2 = p[P_OMEGA2]
    amp = p[P_AMP]
    hs2 = hs * hs
    b[0] = theta
    b[1] = v * hs
    sn[0] = math.sin(theta)
    cn[0] = math.cos(theta)
    g0 = p[P_GAMMA0] + p[P_RATE] * t
    g1 = p[P_RATE] * hs
    su = 0.0
    cu = 0.0
    if amp != 0.0:
        psi = p[P_FREQ] * t + p[P_PHASE]
        su = amp * math.sin(psi)
        cu = amp * math.cos(psi)
        g0 += su
        g1 += cu * p[P_FREQ] * hs
    b[2] = hs2 * (g0 - w2 * sn[0]) * 0.5
    b[3] = 0.0
    wk = p[P_FREQ] * hs  # (Ω hs)^k / k! built up as k grows
    for k in range(1, n - 1):
        s = 0.0
        c = 0.0
        for j in range(1, k + 1):
            jb = j * b[j]
            s += jb * cn[k - j]
            c -= jb * sn[k - j]
        sn[k] = s * _INV_K[k]
        cn[k] = c * _INV_K[k]
        g = g1 if k == 1 else 0.0
        if amp != 0.0 and k >= 2:
            wk = wk * p[P_FREQ] * hs * _INV_K[k]
            m = k % 4  # d^k/ds^k sin(psi) = sin(psi + k π/2)
            g = wk * (su if m == 0 else (cu if m == 1 else (-su if m == 2 else -cu)))
        b[k + 2] = hs2 * (g - w2 * sn[k]) * _INV_K12[k]
    th = b[n]
    dv = n * b[n]
    for k in range(n - 1, 0, -1):
        th += b[k]
        dv += k * b[k]
    return th + b[0], dv / hs


@njit(**INLINE)
def hamiltonian_flow(theta, v, t, h, plan, p, scratch):
    """D over ``h`` from (θ, v) at time ``t``: the new (θ, v).

    ``plan`` = (substeps, degree) of :func:`substeps`; ``scratch``: three arrays
    (b, sn, cn) of TAYLOR_ORDER + 1 floats.
    """
    nsub, order = plan
    hs = h / nsub
    for i in range(nsub):
        theta, v = _substep(theta, v, t + i * hs, hs, order, p, scratch)
    return theta, v


def ou_coefficients(beta, temperature, tau):
    """The exact OU step over ``tau``: (e^{−βτ}, sqrt(T (1 − e^{−2βτ})))."""
    return math.exp(-beta * tau), math.sqrt(temperature * -math.expm1(-2.0 * beta * tau))
