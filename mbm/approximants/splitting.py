r"""Splitting approximants: compositions of the exact pendulum flow and the exact drift flow.

The vector field of θ'' + βθ' + ω² sin θ = γ, y = (θ, v), is split as X = A + B,

    A = v ∂_θ − ω² sin θ ∂_v          (the undamped, untorqued pendulum),
    B = (γ − β v) ∂_v                 (torque and damping, no restoring force).

Both flows are known in closed form:

* e^{tA}: the exact elliptic flow of θ'' + ω² sin θ = 0 from any state
  (libration sn/cn/dn, rotation am, the separatrix, rest):
  :func:`mbm.special.pendulum_flow.pendulum_flow_kernel`.
* e^{tB}: θ(t) = θ₀, v(t) = v₀ e^{−βt} + γ φ₁(t) with φ₁(t) = (1 − e^{−βt})/β,
  summed as the power series t Σ (−βt)^k/(k+1)! for |βt| ≤ B_SERIES_MAX (so
  β → 0 gives φ₁ = t without cancellation) and by expm1 beyond.

(The position is advanced by A alone: B carries no θ' = v term, else the
kinematics would be counted twice.  The flow of the full θ'' = γ − βθ' pairs with
the kick −ω² sin θ ∂_v, whose flow is trivial and gives the ordinary
Störmer–Verlet family; it is not what the elliptic flow buys.)

A symmetric composition

    Φ(t) = e^{b₀tB} e^{a₁tA} e^{b₁tB} ⋯ e^{a_s tA} e^{b_s tB},   Σa = Σb = 1,

is, for every t, an analytic formula in t (a composition of closed forms), it is
the identity at t = 0 (the anchor is reproduced exactly), and by the BCH formula it
agrees with the exact flow e^{t(A+B)} to O(t^{p+1}) when the coefficients
satisfy the order conditions of order p.  Re-anchored over windows of length τ
it converges to the *true* solution with global error O(τ^p), whatever the sizes
of β, γ: nothing is assumed small.  The expensive flow (elliptic) is put at the
a-positions, so the cost of a window is s elliptic flows plus s + 1 cheap B flows.

Registered methods (``a`` = elliptic flows per window):

``"split2"``  Strang, B(t/2) A(t) B(t/2); order 2, a = 1.
``"split4"``  Yoshida / Suzuki / Forest–Ruth triple jump of Strang
              (Yoshida 1990, Phys. Lett. A 150, 262); order 4, a = 3.
``"split4bm"`` Blanes & Moan (2002, J. Comput. Appl. Math. 142, 313), the
              6-stage order-4 "S6" partitioned method with small error
              constants, elliptic flow at its 6 b-positions; order 4, a = 6.
``"split6"``  Kahan & Li (1997, Math. Comp. 66, 1089) s9odr6a symmetric
              composition of Strang; order 6, a = 9.
``"split8"``  Kahan & Li s17odr8a; order 8, a = 17.

Laskar & Robutel's SBAB_n (Celest. Mech. 80, 39, 2001) is measured in
``docs/convergent.md`` but not registered: its error O(ε τ^{2n} + ε² τ²) is of
order 2 here, where the B part (β, γ) is not small against ω², and its corrector
needs the flow of [B, [A, B]] = β(γ − βv) ∂_θ + β²ω² sin θ ∂_v, which is not
known in closed form (for the Hamiltonian kicks it was designed for, the double
bracket depends on θ alone and is a kick).

Error estimate
--------------
Compositions have no cheap embedded partner (the intermediate states depend on t,
so no flow is shared between methods of different order).  :func:`split_error_kernel`
compares Φ(h) with the true state at h computed by degree-24 Taylor polynomials
(:mod:`mbm.approximants.taylor`'s vector kernel, the one a default Taylor run has
compiled already) in substeps of at most a quarter of the series' radius (one
substep unless h is large or the rotation fast); their error, ~(1/4)^25, is far
below Φ's O(h^{p+1}), so the estimate is the local error itself
(``tests/approximants/test_convergent.py`` measures the ratio: 1.00).  It costs one more
composition and a Taylor anchor or a few (the solver could reuse the composition it
evaluates anyway, but the interface does not pass it in).
"""

import math

import numba
import numpy as np

from ..special.dd import reduce_2pi
from ..compile.jit import NJIT_OPTIONS, kernel
from ..special.pendulum_flow import pendulum_flow_kernel
from .base import Approximant, register
from .taylor import taylor24_coefficients_into, taylor_eval_kernel, taylor_radius_kernel
from .taylor_series import SIMD_ORDER, taylor_workspace

__all__ = [
    "drift_flow_kernel",
    "compose_kernel",
    "split_eval_kernel",
    "split_eval_array_kernel",
    "split_error_kernel",
    "SPLIT_METHODS",
    "Splitting",
]

# |βt| below which φ₁ is summed as a power series: there the closed form
# loses up to log10(1/|βt|) digits to cancellation; at 1 the series needs
# B_SERIES_TERMS terms for 1e-17 relative accuracy.
B_SERIES_MAX = 1.0
# Terms of the φ₁ series: the first omitted, 1/20!, is 4e-19 at |βt| = 1.
B_SERIES_TERMS = 19
# 1/k! for the drift-flow series.
_INV_FACT = np.array([1.0 / math.factorial(k) for k in range(B_SERIES_TERMS + 2)])
# The error estimate's reference solution: Taylor substeps of this degree (the vector
# kernel's, which the default Taylor runs have compiled already), each at most this
# fraction of its radius estimate, err ≈ (1/4)^25 ≈ 9e-16 relative: below every
# splitting's local error at any window worth taking.
SPLIT_ERROR_TAYLOR_DEGREE = SIMD_ORDER
SPLIT_ERROR_RADIUS_FRACTION = 0.25
# Substep cap (a window 64 radii long is no window for a splitting either):
# beyond it the estimate is inf, i.e. "shrink the window".
SPLIT_ERROR_MAX_SUBSTEPS = 64

# Coefficients of the registered compositions (see the module docstring).
_CBRT2 = 2.0 ** (1.0 / 3.0)
_YX1 = 1.0 / (2.0 - _CBRT2)  # triple jump outer weight
_YX0 = -_CBRT2 / (2.0 - _CBRT2)  # triple jump inner (negative) weight

# Blanes & Moan S6 (order 4): their a_i (7) go to the cheap B flow, their b_i (6)
# to the elliptic flow.
_BM_A = (0.0792036964311957, 0.353172906049774, -0.0420650803577195)
_BM_B = (0.209515106613362, -0.143851773179818)

# Kahan & Li s9odr6a and s17odr8a: weights of Strang steps (first half; palindromic).
_KL6 = (
    0.39216144400731413927925056,
    0.33259913678935943859974864,
    -0.70624617255763935980996482,
    0.08221359629355080023149045,
    0.79854399093482996339895035,
)
_KL8 = (
    0.13020248308889008087881763,
    0.56116298177510838456196441,
    -0.38947496264484728640807860,
    0.15884190655515560089621075,
    -0.39590389413323757733623154,
    0.18453964097831570709183254,
    0.25837438768632204729397911,
    0.29501172360931029887096624,
    -0.60550853383003451169892108,
)


def _palindrome(half, odd):
    """Full weight list from its first half (the middle entry included when ``odd``)."""
    half = list(half)
    return half + half[-2::-1] if odd else half + half[::-1]


def _strang_composition(weights):
    """(a, b) of the composition of Strang steps B(w/2) A(w) B(w/2) with weights w."""
    a = list(weights)
    b = [0.5 * weights[0]]
    for i in range(len(weights) - 1):
        b.append(0.5 * (weights[i] + weights[i + 1]))
    b.append(0.5 * weights[-1])
    return a, b


def _bm_s6():
    a1, a2, a3 = _BM_A
    a4 = 1.0 - 2.0 * (a1 + a2 + a3)
    b1, b2 = _BM_B
    b3 = 0.5 - (b1 + b2)
    return [b1, b2, b3, b3, b2, b1], [a1, a2, a3, a4, a3, a2, a1]


def _sbab(n):
    # Laskar & Robutel (2001) SBAB_n: B(d1) A(c2) B(d2) ... in their notation.
    if n == 2:
        return [0.5, 0.5], [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0]
    if n == 3:
        c2 = 0.5 - math.sqrt(5.0) / 10.0
        c3 = math.sqrt(5.0) / 5.0
        return [c2, c3, c2], [1.0 / 12.0, 5.0 / 12.0, 5.0 / 12.0, 1.0 / 12.0]
    raise ValueError(n)


# name -> (order, a weights (elliptic flows), b weights (drift flows)); each is a
# registered approximant (docs/convergent.md measures them all).
SPLIT_METHODS = {
    "split2": (2,) + _strang_composition([1.0]),
    "split4": (4,) + _strang_composition([_YX1, _YX0, _YX1]),
    "split4bm": (4,) + _bm_s6(),
    "split6": (6,) + _strang_composition(_palindrome(_KL6, True)),
    "split8": (8,) + _strang_composition(_palindrome(_KL8, True)),
    "sbab2": (2,) + _sbab(2),
    "sbab3": (2,) + _sbab(3),
}
_METHOD_IDS = {name: i for i, name in enumerate(SPLIT_METHODS)}
_MAX_STAGES = max(len(m[1]) for m in SPLIT_METHODS.values())
# Weight tables indexed by method id (rows padded with zeros; _N_STAGES gives s).
_A_TABLE = np.zeros((len(SPLIT_METHODS), _MAX_STAGES))
_B_TABLE = np.zeros((len(SPLIT_METHODS), _MAX_STAGES + 1))
_N_STAGES = np.zeros(len(SPLIT_METHODS), dtype=np.int64)
for _name, (_p, _a, _b) in SPLIT_METHODS.items():
    _i = _METHOD_IDS[_name]
    _N_STAGES[_i] = len(_a)
    _A_TABLE[_i, : len(_a)] = _a
    _B_TABLE[_i, : len(_b)] = _b

# Longest substep of one composition: β·h ≤ this (the backward damping of negative
# weights amplifies by at most e^{|w| β h}).  Every window of the convergence study
# is within it, so there the approximant is a single composition.
SPLIT_MAX_SUBSTEP_BETA = 2.0

# coef layout: [status, method id, beta, gamma, omega, theta0, v0]
N_COEF = 7
STATUS_OK = 0
STATUS_BAD_STATE = 1  # non-finite anchor or parameters


@kernel(error_model="numpy")
def drift_flow_kernel(theta0, v0, beta, gamma, t):
    """Exact flow of the B part, θ' = 0, v' = γ − βv: the state at time t.

    Parameters
    ----------
    theta0, v0 : float
        State at 0.
    beta, gamma : float
        Damping (≥ 0, 0 allowed) and torque.
    t : float
        Time (any sign).

    Returns
    -------
    theta, theta_dot : float
        ``theta0`` and ``v0 e^{−βt} + γ φ₁(t)``; exactly the input at t = 0.
    """
    x = -beta * t
    if abs(x) <= B_SERIES_MAX:
        # φ₁ = t Σ x^k/(k+1)! by Horner; e^{−βt} = 1 + x Σ x^k/(k+1)!.
        p1 = 0.0
        for k in range(B_SERIES_TERMS - 1, -1, -1):
            p1 = p1 * x + _INV_FACT[k + 1]
        phi1 = t * p1
        decay = 1.0 + x * p1  # no cancellation for |βt| ≤ 1
    else:
        em1 = math.expm1(x)
        phi1 = -em1 / beta
        decay = 1.0 + em1
    # v₀ e^{−βt} + γ φ₁ rather than v₀ + (γ − βv₀) φ₁: no cancellation when βt is large.
    return theta0, v0 * decay + gamma * phi1


@kernel(error_model="numpy")
def compose_kernel(theta0, v0, model, t, a_w, b_w, n_stages):
    """The composition e^{b₀tB} e^{a₁tA} ⋯ e^{a_s tA} e^{b_s tB} applied to (θ₀, θ̇₀).

    Parameters
    ----------
    theta0, v0 : float
        Anchor state.
    model : tuple
        (β, γ, ω).
    t : float
        Time from the anchor (the step of the composition).
    a_w, b_w : ndarray
        Weights of the elliptic (length ≥ s) and drift (length ≥ s + 1) flows.
    n_stages : int
        s, the number of elliptic flows.

    Returns
    -------
    theta, theta_dot : float
    """
    beta, gamma, omega = model
    if t == 0.0:
        return theta0, v0
    # Work with θ₀ − 2πj, |θ₀ − 2πj| ≤ π, and add the increment to θ₀ once at the
    # end: a running pendulum reaches |θ| ~ 1e3, where every one of the 2s + 1
    # intermediate roundings would cost ulp(θ) ~ 1e-13 and accumulate over windows.
    th = reduce_2pi(theta0)[1]
    start = th
    v = v0
    if beta == 0.0 and gamma == 0.0:
        # B is zero: the composition is e^{a₁tA} ⋯ e^{a_s tA} = e^{tA} (Σa = 1), the
        # exact flow; one call instead of s avoids s − 1 calls' round-off.
        th, v = pendulum_flow_kernel(th, v, omega, t)
        return theta0 + (th - start), v
    for i in range(n_stages):
        if b_w[i] != 0.0:
            th, v = drift_flow_kernel(th, v, beta, gamma, b_w[i] * t)
        th, v = pendulum_flow_kernel(th, v, omega, a_w[i] * t)
    if b_w[n_stages] != 0.0:
        th, v = drift_flow_kernel(th, v, beta, gamma, b_w[n_stages] * t)
    return theta0 + (th - start), v


@kernel(error_model="numpy")
def split_eval_kernel(coef, t):
    """θ(t), θ'(t) of an anchored splitting approximant: the composition with step t,
    applied n times with step t/n when β·|t| exceeds :data:`SPLIT_MAX_SUBSTEP_BETA`."""
    if t == 0.0:
        return coef[5], coef[6]
    m = int(coef[1])
    beta, omega = coef[2], coef[4]
    # Negative substep weights run the damping backwards: e^{β|w|t} overflows on long
    # windows (β = 8, t = 10 gave NaN).  Longer windows are split into equal substeps.
    n = 1
    if beta * abs(t) > SPLIT_MAX_SUBSTEP_BETA:
        n = int(math.ceil(beta * abs(t) / SPLIT_MAX_SUBSTEP_BETA))
    th, v = coef[5], coef[6]
    h = t / n
    for _ in range(n):
        th, v = compose_kernel(th, v, (beta, coef[3], omega), h, _A_TABLE[m], _B_TABLE[m], _N_STAGES[m])
    return th, v


@kernel(error_model="numpy")
def split_eval_array_kernel(coef, t, out_theta, out_v):
    """:func:`split_eval_kernel` over a float64 array ``t``."""
    for i in range(t.shape[0]):
        a, b = split_eval_kernel(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


@kernel(error_model="numpy")
def split_error_kernel(coef, h):
    """Estimated local error of the window [0, h]: distance to the anchor's Taylor polynomial.

    Parameters
    ----------
    coef : ndarray
        From a ``split*`` anchor kernel.
    h : float
        Window length.

    Returns
    -------
    err_theta, err_v : float
        |Φ(h) − T(h)| componentwise, T the degree-SPLIT_ERROR_TAYLOR_DEGREE Taylor
        polynomial of the true solution at the anchor.  Zero when β = γ = 0 (the
        composition is then the exact flow).  Beyond about half the Taylor
        polynomial's radius of convergence the estimate is T's own error and far
        exceeds Φ's: conservative, it shrinks the window.
    """
    if coef[2] == 0.0 and coef[3] == 0.0:
        # β = γ = 0: the composition is the exact elliptic flow (see compose_kernel).
        return 0.0, 0.0
    if h == 0.0:
        return 0.0, 0.0
    th, v = split_eval_kernel(coef, h)
    beta, gamma, omega = coef[2], coef[3], coef[4]
    # The true state at h: Taylor substeps no longer than SPLIT_ERROR_RADIUS_FRACTION
    # of each anchor's radius estimate (one substep for the usual windows).
    tth, tv = coef[5], coef[6]
    done = 0.0
    sgn = 1.0 if h > 0.0 else -1.0
    ws_coef, ws_scratch = taylor_workspace(SPLIT_ERROR_TAYLOR_DEGREE)
    for _ in range(SPLIT_ERROR_MAX_SUBSTEPS):
        # int64: a literal degree would compile the vector kernel a second time.
        tc = taylor24_coefficients_into(beta, gamma, omega, tth, tv, np.int64(SPLIT_ERROR_TAYLOR_DEGREE), ws_coef,
                                        ws_scratch)
        step = min(abs(h) - done, SPLIT_ERROR_RADIUS_FRACTION * taylor_radius_kernel(tc))
        tth, tv = taylor_eval_kernel(tc, sgn * step)
        done += step
        if done >= abs(h):
            return abs(th - tth), abs(v - tv)
    return math.inf, math.inf


@kernel(error_model="numpy")
def split_anchor(method_id, beta, gamma, omega, theta0, v0):
    coef = np.empty(N_COEF)
    coef[0] = STATUS_OK
    coef[1] = method_id
    coef[2] = beta
    coef[3] = gamma
    coef[4] = omega
    coef[5] = theta0
    coef[6] = v0
    if not (math.isfinite(theta0) and math.isfinite(v0) and math.isfinite(beta)
            and math.isfinite(gamma) and math.isfinite(omega) and omega > 0.0):
        coef[0] = STATUS_BAD_STATE
    return coef


# One anchor kernel per method: the kernel signature has no room for the method id.
@kernel(error_model="numpy")
def split2_anchor_kernel(beta, gamma, omega, theta0, v0):
    return split_anchor(0, beta, gamma, omega, theta0, v0)


@numba.njit(**NJIT_OPTIONS)  # also called from Python
def split4_anchor_kernel(beta, gamma, omega, theta0, v0):
    return split_anchor(1, beta, gamma, omega, theta0, v0)


@kernel(error_model="numpy")
def split4bm_anchor_kernel(beta, gamma, omega, theta0, v0):
    return split_anchor(2, beta, gamma, omega, theta0, v0)


@kernel(error_model="numpy")
def split6_anchor_kernel(beta, gamma, omega, theta0, v0):
    return split_anchor(3, beta, gamma, omega, theta0, v0)


@kernel(error_model="numpy")
def split8_anchor_kernel(beta, gamma, omega, theta0, v0):
    return split_anchor(4, beta, gamma, omega, theta0, v0)


@kernel(error_model="numpy")
def sbab2_anchor_kernel(beta, gamma, omega, theta0, v0):
    return split_anchor(5, beta, gamma, omega, theta0, v0)


@kernel(error_model="numpy")
def sbab3_anchor_kernel(beta, gamma, omega, theta0, v0):
    return split_anchor(6, beta, gamma, omega, theta0, v0)


_ANCHOR_KERNELS = {
    "split2": split2_anchor_kernel,
    "split4": split4_anchor_kernel,
    "split4bm": split4bm_anchor_kernel,
    "split6": split6_anchor_kernel,
    "split8": split8_anchor_kernel,
    "sbab2": sbab2_anchor_kernel,
    "sbab3": sbab3_anchor_kernel,
}
assert all(_METHOD_IDS[k] == i for i, k in enumerate(_ANCHOR_KERNELS))


class Splitting(Approximant):
    """Symmetric composition of the exact pendulum flow and the exact drift flow.

    See the module docstring for the methods.  Any β ≥ 0, γ, ω > 0 and any
    anchor state (libration, rotation, separatrix; any |θ|).

    Attributes
    ----------
    error_order : int
        Order p: the estimate of :func:`split_error_kernel` scales as h^(p+1).
    measured_order : int
        Convergence order p: global error O(τ^p) for a fixed window τ (a composition of
        exact flows advances θ and θ' together, each with local error O(τ^{p+1}); the
        fits of docs/convergent.md land within 0.2 of p).
    n_elliptic : int
        Elliptic flows per evaluation (the dominant cost).
    kind_arg : int
        The method's row in the composition tables (kind ``"split"``).
    """

    n_elliptic = None
    compiled_kind = "split"
    anchors = "any"
    status_messages = {STATUS_BAD_STATE: "the anchor state and parameters must be finite"}
    eval_kernel = staticmethod(split_eval_kernel)
    eval_array_kernel = staticmethod(split_eval_array_kernel)
    error_kernel = staticmethod(split_error_kernel)

    def param_names(self):
        return ("method", "beta", "gamma", "omega", "theta0", "v0")


_CITATIONS = {
    "split2": "Strang splitting of the exact elliptic flow and the exact damping/torque flow",
    "split4": "Yoshida (1990) triple jump of Strang; exact elliptic and drift flows",
    "split4bm": "Blanes & Moan (2002) S6 order-4 composition; exact elliptic and drift flows",
    "split6": "Kahan & Li (1997) s9odr6a composition of Strang; exact elliptic and drift flows",
    "split8": "Kahan & Li (1997) s17odr8a composition of Strang; exact elliptic and drift flows",
    "sbab2": "Laskar & Robutel (2001) SBAB2; exact elliptic and drift flows",
    "sbab3": "Laskar & Robutel (2001) SBAB3; exact elliptic and drift flows",
}


def _make(name):
    order, a, _b = SPLIT_METHODS[name]
    cls = type(
        "Split" + name[5:].upper() if name.startswith("split") else name.upper(),
        (Splitting,),
        {
            "name": name,
            "error_order": order,
            "measured_order": order,
            "kind_arg": _METHOD_IDS[name],
            "n_elliptic": len(a),
            "citation": _CITATIONS[name],
            "anchor_kernel": staticmethod(_ANCHOR_KERNELS[name]),
            "__doc__": f"{_CITATIONS[name]}: order {order}, {len(a)} elliptic flows per window.",
        },
    )
    return register(cls)


for _nm in _CITATIONS:
    _c = _make(_nm)
    globals()[_c.__name__] = _c
del _nm, _c
