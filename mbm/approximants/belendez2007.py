"""Third paper: A. Beléndez, C. Pascual, D. I. Méndez, T. Beléndez, C. Neipp,
"Exact solution for the nonlinear pendulum" (2007).

The paper solves θ'' + ω₀² sin θ = 0 (its Eq. (1)) from a turning point
θ(0) = θ₀, θ'(0) = 0 (Eq. (3)):

* (23)  τ(z) = K(k) − F(arcsin z; k), τ = ω₀ t, z = sin(θ/2)/sin(θ₀/2);
* (26)  T = 4 K(k)/ω₀;
* (31)  θ(t) = 2 arcsin{ sin(θ₀/2) sn[K(k) − ω₀ t; k] };
* (32)  θ(t) = θ₀ cos(ω t), with the exact angular frequency
* (33)  ω(θ₀) = π ω₀ / (2 K(sin²(θ₀/2))).

NOTE ON NOTATION.  The paper's ``k`` (its Eq. (10)) is the *parameter*
sin²(θ₀/2) of K(k), F(φ; k) and sn(u; k), i.e. what this module calls
``m``.  Here ``k = √m`` is the modulus.  (As extracted, Eq. (32) repeats
Eq. (31); the text around it and Figs. 1–6 make clear that (32) is the
harmonic θ₀ cos(ω t) with the frequency (33).)

What this module adds to the paper:

``"belendez"``
    The exact flow of θ'' + ω² sin θ = 0 from *any* state, for any real t
    (:func:`mbm.special.pendulum_flow.pendulum_flow_kernel`: libration m < 1,
    rotation m > 1 with the winding counted so θ is continuous and unbounded,
    the separatrix m = 1 and rest; (31) is the turning-point case of the
    libration branch), as an approximant (it is exact, so a moving boundary run with it
    is limited by round-off only).
``"harmonic"``
    The harmonic approximation (32)–(33), anchored at any libration state:
    θ = c + A cos(ω(θ₀) t + φ) with the exact frequency (33) of the anchor's
    energy, c = 2πj the centre of the swing, and A, φ fitted so that the anchor
    (θ₀, θ̇₀) is reproduced exactly (the approximant interface requires it).
    At a turning point this is (32) itself (A = |θ₀ − c|, φ ∈ {0, π}).  The
    amplitude from the energy, A_E = 2 arcsin k, is exposed as ``A_energy``; it
    is *not* used as A, because A_E cos(φ) = θ₀ and −A_E ω sin(φ) = θ̇₀ cannot
    both hold away from a turning point.

The flow's numerics (double-double reduction, K and phase; horizon-free), the
period (26) with its rotation counterpart (:func:`period`) and
:func:`pendulum_flow` live in :mod:`mbm.special.pendulum_flow` (re-exported
here); this module holds the paper's formulas as approximants.
"""

import math

import numba
import numpy as np

from ..special.dd import PI_HI
from ..compile.jit import NJIT_OPTIONS, kernel

# The flow, and the names re-exported from here for existing importers.
from ..special.pendulum_flow import (  # noqa: F401
    FLOW_PARAM_NAMES,
    N_FLOW,
    FlowSetup,
    REGIME_LIBRATION,
    REGIME_REST,
    REGIME_ROTATION,
    REGIME_SEPARATRIX,
    STATUS_BAD_OMEGA,
    STATUS_BAD_STATE,
    STATUS_OK,
    THETA_REDUCE_MAX,
    flow_eval_kernel,
    flow_setup_kernel,
    pendulum_flow,
    pendulum_flow_kernel,
    period,
    period_kernel,
)
from ..special.pendulum_flow_table import flow_table_eval_range, flow_table_point_kernel
from .base import Approximant, ApproximantDomainError, register

__all__ = [
    "belendez_anchor_kernel",
    "belendez_eval_kernel",
    "belendez_eval_array_kernel",
    "belendez_eval_range",
    "harmonic_anchor_kernel",
    "harmonic_eval_kernel",
    "harmonic_eval_array_kernel",
    "BelendezExact",
    "BelendezHarmonic",
    # re-exported from mbm.special.pendulum_flow
    "pendulum_flow_kernel",
    "flow_setup_kernel",
    "flow_eval_kernel",
    "period_kernel",
    "period",
    "pendulum_flow",
    "REGIME_LIBRATION",
    "REGIME_ROTATION",
    "REGIME_SEPARATRIX",
    "REGIME_REST",
]

# Status codes (coef[0]): the flow's own (STATUS_OK 0, STATUS_BAD_OMEGA 2,
# STATUS_BAD_STATE 3, from mbm.special.pendulum_flow) and these two.
STATUS_NOT_CONSERVATIVE = 1  # β ≠ 0 or γ ≠ 0
STATUS_NOT_LIBRATION = 4  # harmonic (32)-(33) needs an oscillation

# Length of the "harmonic" coef[1:].
N_HARM = 11

_NAN = float("nan")


# ---------------------------------------------------------------------------
# Approximant "belendez": the exact flow
# ---------------------------------------------------------------------------


# Names of coef[1:] of the "belendez-harmonic" approximant (harmonic_anchor_kernel).
HARMONIC_PARAM_NAMES = ("omega", "theta0", "v0", "omega_h", "A", "phase", "A_energy", "period",
                        "theta_red", "theta_red_lo", "m")


@numba.njit(**NJIT_OPTIONS)  # also called from Python
def belendez_anchor_kernel(beta, gamma, omega, theta0, v0):
    """Anchor the exact flow: ``coef = [status, *flow_setup_kernel(...)[:-1]]``.

    Layout of coef[1:] (``BelendezExact.param_names()``): regime, omega, theta0, v0,
    k, m, mc, K, period, u0, sign, par, parc, K_lo, k_lo, theta_red, theta_red_lo,
    rate, rate_lo, vscale (see :func:`flow_setup_kernel`).  Status
    STATUS_NOT_CONSERVATIVE unless β = γ = 0.
    """
    coef = np.empty(N_FLOW)
    if beta != 0.0 or gamma != 0.0:
        coef[:] = _NAN
        coef[0] = STATUS_NOT_CONSERVATIVE
        return coef
    res = flow_setup_kernel(theta0, v0, omega)
    coef[0] = res[N_FLOW - 1]
    for i in range(N_FLOW - 1):
        coef[1 + i] = res[i]
    return coef


@kernel(error_model="numpy")
def _flow_of(coef):
    """The :data:`FlowSetup` held by ``coef`` (:func:`belendez_anchor_kernel`)."""
    return FlowSetup(coef[1], coef[2], coef[3], coef[4], coef[5], coef[6], coef[7], coef[8], coef[9], coef[10],
                     coef[11], coef[12], coef[13], coef[14], coef[15], coef[16], coef[17], coef[18], coef[19],
                     coef[20], coef[0])


@kernel(error_model="numpy")
def belendez_eval_kernel(coef, t):
    """(θ, θ') at time t after the anchor; exactly the anchor at t == 0.0.

    The values of the flow's table (:func:`mbm.special.pendulum_flow_table.flow_table_point_kernel`,
    within a few ulps of :func:`flow_eval_kernel`), so that a window's outputs are the
    same bits whether a block of them is read from a table or each is evaluated alone.
    """
    return flow_table_point_kernel(_flow_of(coef), t)


@kernel(error_model="numpy")
def belendez_eval_range(coef, t, t_eval, j, j2, out_theta, out_v):
    """(θ, θ') at the sorted times ``t_eval[j:j2]`` of the window anchored at time ``t``
    into ``out_theta``, ``out_v``, in one call: :func:`belendez_eval_kernel`'s values bit
    for bit, a block with many times per anchor read from the flow's table
    (:func:`mbm.special.pendulum_flow_table.flow_table_eval_range`)."""
    flow_table_eval_range(_flow_of(coef), t, t_eval, j, j2, out_theta, out_v)


@kernel(error_model="numpy")
def belendez_eval_array_kernel(coef, t, out_theta, out_v):
    """:func:`belendez_eval_kernel` over a contiguous float64 array ``t``."""
    for i in range(t.shape[0]):
        a, b = belendez_eval_kernel(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


def _check_conservative(approx_name, model):
    if model.beta != 0.0 or model.gamma != 0.0:
        raise ApproximantDomainError(
            f"approximant {approx_name!r} is the solution of theta'' + omega**2 sin(theta) = 0 "
            f"(Beléndez et al. 2007, Eq. (1)); it needs beta = 0 and gamma = 0, got {model!r}"
        )


@register
class BelendezExact(Approximant):
    """Exact solution of θ'' + ω² sin θ = 0 from any state (Beléndez et al. 2007, (31)).

    Libration, rotation (winding counted), separatrix and rest; see
    :func:`pendulum_flow_kernel`.  ``params`` holds ``k`` (modulus √m), ``m`` (the
    paper's "k", Eq. (10)), ``mc = 1 − m``, ``K`` (of the Jacobi parameter in use),
    ``period`` (Eq. (26) in libration), ``u0`` (Jacobi argument at the anchor),
    ``regime`` (0 libration, 1 rotation, 2 separatrix, 3 rest) and the internals
    of the double-double evaluation.
    """

    name = "belendez"
    # The exact flow: no truncation error, so MBM's default window is the whole span.
    exact = True
    compiled_kind = "exact"
    citation = (
        "Beléndez, Pascual, Méndez, Beléndez, Neipp (2007), Eqs. (23), (26), (31), "
        "generalized to any state: libration, rotation and separatrix"
    )
    anchors = "any"
    status_messages = {
        STATUS_NOT_CONSERVATIVE: "beta and gamma must be 0 (undamped, unforced pendulum)",
        STATUS_BAD_OMEGA: "omega must be finite and > 0",
        STATUS_BAD_STATE: (
            "the state must be finite, |theta0| <= 1e15 and its energy representable"
        ),
    }
    anchor_kernel = staticmethod(belendez_anchor_kernel)
    eval_kernel = staticmethod(belendez_eval_kernel)
    eval_array_kernel = staticmethod(belendez_eval_array_kernel)

    def check_model(self, model):
        _check_conservative(self.name, model)

    def param_names(self):
        return FLOW_PARAM_NAMES


# ---------------------------------------------------------------------------
# Approximant "harmonic": (32)-(33)
# ---------------------------------------------------------------------------


@kernel(error_model="numpy")
def harmonic_anchor_kernel(beta, gamma, omega, theta0, v0):
    """Anchor the harmonic approximation (32)-(33).

    Layout of coef[1:] (``BelendezHarmonic.param_names()``): omega, theta0, v0,
    omega_h (Eq. (33)), A, phase, A_energy, period (Eq. (26)), theta_red,
    theta_red_lo (the anchor relative to the centre 2πj of its swing), m.
    Status STATUS_NOT_LIBRATION for a rotation or the separatrix.
    """
    coef = np.empty(1 + N_HARM)
    coef[:] = _NAN
    if beta != 0.0 or gamma != 0.0:
        coef[0] = STATUS_NOT_CONSERVATIVE
        return coef
    res = flow_setup_kernel(theta0, v0, omega)
    if res[N_FLOW - 1] != 0.0:
        coef[0] = res[N_FLOW - 1]
        return coef
    if res[0] != REGIME_LIBRATION:
        coef[0] = STATUS_NOT_LIBRATION
        return coef
    k = res[4]
    mc = res[6]
    K = res[7] + res[13]
    th = res[15] + res[16]
    # (33): ω(θ₀) = π ω₀ / (2K(m)), the exact angular frequency of the motion.
    om_h = 0.5 * PI_HI * omega / K
    # Harmonic through the anchor with that frequency: θ = c + A cos(ω_h t + φ),
    # c = 2πj the centre of the swing.  At a turning point (θ̇₀ = 0) this is (32):
    # A = |θ₀ − c|, φ ∈ {0, π}.
    x = -v0 / om_h
    A = math.hypot(th, x)
    phase = math.atan2(x, th)
    # Exact amplitude of the true motion, sin(A_E/2) = k, from the energy.
    A_E = 2.0 * math.atan2(k, math.sqrt(mc))
    coef[0] = STATUS_OK
    coef[1] = omega
    coef[2] = theta0
    coef[3] = v0
    coef[4] = om_h
    coef[5] = A
    coef[6] = phase
    coef[7] = A_E
    coef[8] = 2.0 * PI_HI / om_h  # (26): T = 4K/ω₀ = 2π/ω(θ₀)
    coef[9] = res[15]
    coef[10] = res[16]
    coef[11] = res[5]
    return coef


@kernel(error_model="numpy")
def harmonic_eval_kernel(coef, t):
    """(θ, θ') of the harmonic c + A cos(ω_h t + φ); exactly the anchor at t == 0.0."""
    if t == 0.0:
        return coef[2], coef[3]
    om_h = coef[4]
    A = coef[5]
    arg = om_h * t + coef[6]
    th_loc = A * math.cos(arg)
    return coef[2] + ((th_loc - coef[9]) - coef[10]), -A * om_h * math.sin(arg)


@kernel(error_model="numpy")
def harmonic_eval_array_kernel(coef, t, out_theta, out_v):
    """:func:`harmonic_eval_kernel` over a contiguous float64 array ``t``."""
    for i in range(t.shape[0]):
        a, b = harmonic_eval_kernel(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


@register
class BelendezHarmonic(Approximant):
    """Harmonic approximation with the exact frequency (Beléndez et al. 2007, (32)–(33)).

    θ(t) = c + A cos(ω(θ₀) t + φ) with ω(θ₀) = π ω₀ / (2K(m)), Eq. (33), m the
    Jacobi parameter of the anchor's energy, and c = 2πj the centre of the swing.
    A and φ are fitted so the anchor (θ₀, θ̇₀) is reproduced exactly; at a
    turning point (θ̇₀ = 0, the paper's initial conditions (3)) that is
    A = |θ₀ − c|, φ ∈ {0, π}, i.e. exactly Eq. (32).  Away from a turning point
    A differs from the true amplitude ``A_energy`` (2 arcsin k) by the
    anharmonicity of the motion; the paper's formula is the turning-point case.

    Only oscillations (m < 1) are accepted: a rotation or the separatrix has no
    harmonic approximation (ApproximantDomainError).
    """

    name = "harmonic"
    citation = (
        "Beléndez, Pascual, Méndez, Beléndez, Neipp (2007), Eqs. (32)-(33) "
        "(exact frequency from (26)); any libration anchor, (32) itself at turning points"
    )
    anchors = "any"
    status_messages = {
        STATUS_NOT_CONSERVATIVE: "beta and gamma must be 0 (undamped, unforced pendulum)",
        STATUS_BAD_OMEGA: "omega must be finite and > 0",
        STATUS_BAD_STATE: (
            "the state must be finite, |theta0| <= 1e15 and its energy representable"
        ),
        STATUS_NOT_LIBRATION: (
            "the harmonic approximation (32)-(33) needs an oscillation "
            "(energy below the separatrix, m < 1)"
        ),
    }
    anchor_kernel = staticmethod(harmonic_anchor_kernel)
    eval_kernel = staticmethod(harmonic_eval_kernel)
    eval_array_kernel = staticmethod(harmonic_eval_array_kernel)

    def check_model(self, model):
        _check_conservative(self.name, model)

    def param_names(self):
        return HARMONIC_PARAM_NAMES
