r"""Anchored Taylor series of the true pendulum: a convergent approximant of degree N, order N − 1.

Each window's formula is the degree-N Taylor polynomial of the exact solution of
θ'' + βθ' + ω² sin θ = γ at the anchor (θ₀, θ̇₀):

    θ(t) ≈ Σ_{k=0}^{N} a_k t^k,      θ'(t) ≈ Σ_{k=1}^{N} k a_k t^{k−1}.

It is an analytic formula in t, it reproduces the anchor exactly (a₀ = θ₀,
a₁ = θ̇₀), and the polynomial *is* the dense output.  Unlike the second paper's
℘ formula (``salas-torque``), which solves a cubic model of sin θ, it
approximates the true equation, so a moving-boundary run converges to the true
solution.  Nothing restricts β, γ, ω or the state: damping, any torque
(|γ| > ω², running states included), libration and rotation, any |θ|.

Order: N − 1, not N
-------------------
Over a window of length τ the degree-N polynomial of θ is off by O(τ^{N+1}), but
the velocity is its derivative, a polynomial of degree N − 1, off by the dropped
term (N+1) a_{N+1} τ^N: a local error O(τ^N).  The next window is anchored at both,
so the velocity's error enters θ; summed over the T/τ windows of a run, the global
error in θ and θ' is O(τ^{N−1}).  Measured (heyoka in long double as reference): from
one anchor of the second paper's Example 1 the local errors of taylor8 scale as
τ^9.1 in θ and τ^8.2 in θ'; the global error fits 6.97-7.09 there, 6.7-7.2 on the six
scenes of docs/convergent.md, 6.96 ± 0.03 on the running scene (``mbm study --scene
running``); the fits for N ≥ 12 scatter by ±2 around N − 1 (3-8 points lie between
their pre-asymptotic range and round-off).

Coefficients (automatic differentiation)
----------------------------------------
Write s(t) = sin θ(t) = Σ s_k t^k and c(t) = cos θ(t) = Σ c_k t^k.  From
s' = c θ' and c' = −s θ', matching powers of t (with b_j = j a_j the
coefficients of θ' shifted by one):

    s₀ = sin a₀,  c₀ = cos a₀,
    k s_k =  Σ_{j=1}^{k} b_j c_{k−j},      k c_k = −Σ_{j=1}^{k} b_j s_{k−j},   k ≥ 1,

and from θ'' = γ − βθ' − ω² sin θ at power t^k:

    (k+1)(k+2) a_{k+2} = γ δ_{k0} − β (k+1) a_{k+1} − ω² s_k,   k ≥ 0.

Each order costs 2k multiply-adds for (s_k, c_k), so the N coefficients cost
about N² operations; there is one sin and one cos per window.  At the default
degree 24 the recurrence runs as vector code (:mod:`mbm.approximants.taylor_simd`:
the same sums, paired in four-lane multiplies and reordered so that each order waits
on the one before through one multiply and one add).

AC drive
--------
With the torque γ + A sin(Ωt + φ) (``mbm.Pendulum(..., drive_amplitude=A,
drive_frequency=Ω, drive_phase=φ)``) the anchor needs the window's start time t₀ as
well: in the window's own time s = t − t₀ the drive is the entire series

    A sin(Ω(t₀ + s) + φ) = Σ d_k s^k,   d_k = A Ω^k / k! · sin(ψ + kπ/2),   ψ = Ωt₀ + φ,

(sin(ψ + kπ/2) cycles through sin ψ, cos ψ, −sin ψ, −cos ψ), and it enters the
recurrence at every order:

    (k+1)(k+2) a_{k+2} = γ δ_{k0} + d_k − β (k+1) a_{k+1} − ω² s_k,   k ≥ 0

(:func:`taylor_driven_coefficients`; O(N) more per window, and one more sin and
cos).  ψ is formed with the rounding error of Ω·t₀ carried (an exact product), so the
drive's phase is good to a few ulps of φ + 1 at any t₀, not to eps·Ωt₀.  The series
adds no singularity (it is entire), so the radius, the a-priori window and the error
estimate below apply unchanged; the undriven kernel is untouched (A = 0 runs it, bit
for bit as before).

Radius and window length
------------------------
The series converges for |t| < R, the distance from the anchor to the nearest
complex singularity of θ(t).  R is a few 1/ω for slow motion (π/(2ω) on the
separatrix, where θ = 4 arctan e^{ωt} − π has branch points at ωt = ±iπ/2) and
shrinks like (2/v) ln(2v/ω) for a fast rotation with speed v (θ = 2 am(vt/2 | 4ω²/v²),
whose nearest singularity lies at u = iK′ ≈ i ln(2v/ω)): the running pendulum of
γ = 1.2, β = 0.1 turns at v ≈ 12, R ≈ 0.53 (the root test below reads 0.56-0.59
along that run, 1.7-8 on the other five scenes of docs/convergent.md).  The window τ
must stay well inside R.  Under rtol/atol the window is chosen a priori from the
anchored coefficients (:func:`taylor_window_kernel`, heyoka's rule per component:
a radius estimate from the orders N − 2 … N in units of each component's tolerance
scale, times eps^(1/(N−1))), so that the neglected terms are a set fraction eps of
the tolerance (the controller's margin, ``mbm.core.window.TAYLOR_WINDOW_MARGIN``), and the
estimate below only checks it; :func:`radius_estimate` (the root test
|a_k|^{−1/k} on the two extra coefficients, exposed as ``params['radius']``) tells a
caller with a fixed τ where the formula stops being usable.

Why a priori, and so far below the tolerance (docs/oracle.md): with the window grown
until the two-term estimate met the tolerance, the estimate was honest for most
windows (median 1.25× the true local error) but those windows sat at 0.2–0.6 of R,
where it underestimated the θ' error by up to 7×; and on a conservative orbit
(β = 0) the local errors lean to one sign (the energy changes of one run summed to
31 % of their absolute sum), so the energy drifted by 400× tol over a run and the
phase error grew with it: up to 1e5× tol at every tolerance on issue 16's random
scenes.

Error estimate
--------------
Two further coefficients a_{N+1}, a_{N+2} are computed (O(N) each) but not used
in the formula; the local error of the window [0, h] is estimated by the first
two neglected terms,

    err_θ ≈ |a_{N+1}| h^{N+1} + |a_{N+2}| h^{N+2},
    err_v ≈ (N+1)|a_{N+1}| h^N + (N+2)|a_{N+2}| h^{N+1}.

Two terms, not one, because one coefficient can vanish by symmetry (an
undamped, untorqued libration through θ = 0 has an odd θ(t): every even
coefficient is 0).  For h well inside R the tail is geometric with ratio h/R and
the two-term sum is within a factor 1/(1 − h/R) of it.  Measured on six scenes
(docs/convergent.md): never below 0.83 of the true local error, median 1.0-2.3,
and up to ~190 above it for windows close to R, where the true tail's terms
cancel; an overestimate by F shortens the controller's next window by only
F^{1/(N+1)}.  Along issue 16's β = 0 example (docs/oracle.md) it fell to 1/7 of
the true θ' error in windows at 0.4 R; under the a-priori window (about
(rtol/10⁴)^(1/(N−1)) of the radius) it rejected none of 7·10⁵ windows.  Signed partial tails underestimated by up to 20×, so absolute
values are used.  The estimate scales as h^{N+1}, as the solver's step factor
(1/err)^{1/(order+1)} assumes.
"""

import math

import numpy as np

from ..compile.jit import kernel
from .base import Approximant, register
from .taylor_series import (  # noqa: F401  callers and tests import these from here
    HEADER, N_EXTRA, MAX_ORDER, _INV_K, _INV_K12, STATUS_OK, STATUS_BAD_STATE,
    STATUS_BAD_ORDER, _header, _header_into, _finite5, _start, _sin_order,
    taylor_workspace, taylor_coefficients_into, series_loop, taylor_coefficients,
    drive_phase_sincos, taylor_driven_coefficients_into, driven_series_loop,
    taylor_driven_coefficients, taylor24_coefficients_into, taylor24_driven_coefficients_into,
)


__all__ = [
    "taylor_coefficients",
    "taylor_coefficients_into",
    "taylor_driven_coefficients",
    "taylor_driven_coefficients_into",
    "taylor24_coefficients_into",
    "taylor24_driven_coefficients_into",
    "drive_phase_sincos",
    "taylor_workspace",
    "taylor_eval_kernel",
    "taylor_eval_array_kernel",
    "taylor_eval_range",
    "taylor_error_kernel",
    "taylor_window_kernel",
    "taylor_window_log",
    "radius_estimate",
    "taylor_radius_kernel",
    "TAYLOR_ORDERS",
    "TAYLOR_DEFAULT_ORDER",
    "Taylor",
]

# Degrees N registered as "taylor<N>".  8 already beats every splitting and RK4
# per microsecond at 1e-10 (docs/convergent.md); past 30 the window is pinned by
# the radius of convergence, so more degree buys little length for its N² cost.
TAYLOR_ORDERS = (8, 12, 16, 20, 24, 30)

# Degree behind the plain name "taylor".  At 1e-10 on the six scenes of
# docs/convergent.md, degrees 16-30 cost the same within ±25 % in a numba loop;
# 24 needs 30-50 % fewer windows than 16 (what solve_ivp's ~6 µs per-step Python
# overhead charges for) at 0.6 µs per window, 30 fewer still at 0.8 µs.
TAYLOR_DEFAULT_ORDER = 24


# A-priori window (:func:`taylor_window_kernel`): heyoka's safety factor
# exp(−WINDOW_SAFETY_EXP/(p−1)) on the radius rule (Biscani & Izzo 2021, §4, after
# Jorba & Zou 2005, §3.2), kept as published; the margin of the per-window error below
# the tolerance is the controller's (mbm.core.window.TAYLOR_WINDOW_MARGIN).
WINDOW_SAFETY_EXP = 0.7

# The kernels below are compiled without fastmath, as the recurrence is
# (taylor_series explains why: the same bits on every compile and cache path).


@kernel
def taylor_eval_kernel(coef, t):
    """θ(t), θ'(t) of the anchored Taylor polynomial (Horner; the anchor exactly at t = 0).

    Parameters
    ----------
    coef : ndarray
        From a ``taylor*`` anchor kernel.
    t : float
        Time from the anchor.

    Returns
    -------
    theta, theta_dot : float
    """
    n = int(coef[1])
    a = coef[HEADER:]
    p = a[n]
    q = n * a[n]
    for k in range(n - 1, 1, -1):
        p = p * t + a[k]
        q = q * t + k * a[k]
    p = p * t + a[1]
    q = q * t + a[1]
    # a₀ added last so that t == 0 returns θ₀ bit for bit.
    return a[0] + t * p, q


@kernel
def taylor_eval_range(coef, t0, times, lo, hi, out_theta, out_v):
    """:func:`taylor_eval_kernel` at ``times[lo:hi] − t0``, written to ``out_*[lo:hi]``.

    The same operations in the same order per time as :func:`taylor_eval_kernel` (so
    the same bits), four times at once: their eight Horner chains are independent,
    so they overlap instead of each waiting on its own latency (measured per output
    at N = 24 on 201 outputs: 11 ns in one window, 15 ns spread over 11 windows, where
    one call per time takes ~30 ns).  Left-over times go one call each.
    """
    n = int(coef[1])
    a = coef[HEADER:]
    an = a[n]
    bn = n * a[n]
    a0 = a[0]
    a1 = a[1]
    i = lo
    while i + 4 <= hi:
        s0 = times[i] - t0
        s1 = times[i + 1] - t0
        s2 = times[i + 2] - t0
        s3 = times[i + 3] - t0
        p0 = p1 = p2 = p3 = an
        q0 = q1 = q2 = q3 = bn
        for k in range(n - 1, 1, -1):
            ak = a[k]
            bk = k * a[k]
            p0 = p0 * s0 + ak
            p1 = p1 * s1 + ak
            p2 = p2 * s2 + ak
            p3 = p3 * s3 + ak
            q0 = q0 * s0 + bk
            q1 = q1 * s1 + bk
            q2 = q2 * s2 + bk
            q3 = q3 * s3 + bk
        # As taylor_eval_kernel's last steps: a₁, then a₀ added last.
        out_theta[i] = a0 + s0 * (p0 * s0 + a1)
        out_theta[i + 1] = a0 + s1 * (p1 * s1 + a1)
        out_theta[i + 2] = a0 + s2 * (p2 * s2 + a1)
        out_theta[i + 3] = a0 + s3 * (p3 * s3 + a1)
        out_v[i] = q0 * s0 + a1
        out_v[i + 1] = q1 * s1 + a1
        out_v[i + 2] = q2 * s2 + a1
        out_v[i + 3] = q3 * s3 + a1
        i += 4
    while i < hi:
        x, y = taylor_eval_kernel(coef, times[i] - t0)
        out_theta[i] = x
        out_v[i] = y
        i += 1


@kernel
def taylor_eval_array_kernel(coef, t, out_theta, out_v):
    """:func:`taylor_eval_kernel` over a float64 array ``t``."""
    for i in range(t.shape[0]):
        a, b = taylor_eval_kernel(coef, t[i])
        out_theta[i] = a
        out_v[i] = b


@kernel
def taylor_radius_kernel(coef):
    """Root-test radius estimate min(|a_{N+1}|^{−1/(N+1)}, |a_{N+2}|^{−1/(N+2)}); inf if both are 0."""
    n = int(coef[1])
    r = math.inf
    for k in range(n + 1, n + 3):
        ak = abs(coef[HEADER + k])
        if ak > 0.0:
            r = min(r, ak ** (-1.0 / k))
    return r


@kernel
def taylor_error_kernel(coef, h):
    """Estimated local error of the window [0, h]: the first two neglected terms.

    Parameters
    ----------
    coef : ndarray
        From a ``taylor*`` anchor kernel.
    h : float
        Window length.

    Returns
    -------
    err_theta, err_v : float
        Non-negative estimates of |θ_N(h) − θ(h)| and |θ'_N(h) − θ'(h)|.
    """
    n = int(coef[1])
    a = coef[HEADER:]
    ah = abs(h)
    hn = ah ** n
    e1 = abs(a[n + 1]) * hn
    e2 = abs(a[n + 2]) * hn * ah
    return (e1 + e2) * ah, (n + 1.0) * e1 + (n + 2.0) * e2


@kernel
def taylor_window_kernel(coef, theta0, v0, rtol, atol, eps):
    """A-priori window length from the anchored coefficients (heyoka's rule, per component).

    With p = N − 1 (the degree of the θ' polynomial), the state's Taylor coefficients
    x^[k] = (a_k, (k+1) a_{k+1}) of the orders p − 1 and p, each component in units of
    its tolerance scale S_c = atol/rtol + |y_c| (so that rtol·S_c = atol + rtol·|y_c|,
    scipy's scale), give the radius estimate

        ρ = min_{k ∈ {p−1, p}, c} (S_c / |x_c^[k]|)^(1/k),

    and the window is h = ρ · eps^(1/p) · exp(−0.7/(p−1)): the neglected terms are then
    about eps·S_c (eps = rtol/margin is the caller's per-window target).  heyoka takes
    eps = tol, S = max(1, ‖y‖∞) and the degree from eps (p = ⌈−ln eps / 2⌉ + 1, where
    eps^(1/p) ≈ e⁻²); here the degree is the approximant's and eps^(1/p) follows the
    tolerance.  Three orders (a_{N−2}, a_{N−1}, a_N) enter, so one coefficient vanishing
    by symmetry does not fool it (an odd or even θ(t)).

    Parameters
    ----------
    coef : ndarray
        From a ``taylor*`` anchor kernel.
    theta0, v0 : float
        The anchor state (coef's a₀, a₁).
    rtol, atol : float
        Tolerances, rtol > 0.
    eps : float
        Target of the neglected terms per window in units of S_c (0 < eps < 1; the
        tolerance is rtol·S_c, so eps = rtol/margin asks for 1/margin of it).

    Returns
    -------
    float
        The window length; ``inf`` when N < 3 (no rule: the caller falls back to
        its estimate) or when the coefficients vanish (rest at an equilibrium).
    """
    return taylor_window_log(coef, theta0, v0, rtol, atol, math.log(eps))


@kernel
def taylor_window_log(coef, theta0, v0, rtol, atol, log_eps):
    """:func:`taylor_window_kernel` with ln eps given (the loop forms it once per run)."""
    n = int(coef[1])
    if n < 3:
        return math.inf
    a = coef[HEADER:]
    p = n - 1
    r = atol / rtol
    s0 = r + abs(theta0)
    s1 = r + abs(v0)
    n1 = max(abs(a[p - 1]) / s0, p * abs(a[p]) / s1)
    n2 = max(abs(a[p]) / s0, (p + 1.0) * abs(a[p + 1]) / s1)
    # In logarithms: two logs and one exp cost less than two pows and an exp (the
    # a-priori window's share of a window fell from ~40 to ~20 ns at N = 24: the kernel
    # table of docs/oracle.md), and ln eps, a constant of the run, comes from the caller.
    log_rho = math.inf
    if n1 > 0.0:
        log_rho = -math.log(n1) / (p - 1.0)
    if n2 > 0.0:
        log_rho = min(log_rho, -math.log(n2) / p)
    if log_rho == math.inf:
        return math.inf
    return math.exp(log_rho + log_eps / p - WINDOW_SAFETY_EXP / (p - 1.0))


# One anchor kernel per registered degree: the kernel signature has no room for
# N, and numba caches a function of module-level constants, not a closure.  The degree
# is passed as np.int64(N), not a literal: a literal argument compiles taylor_coefficients
# and its callees again for that value instead of sharing the loop's int64 compilation.
@kernel
def taylor8_anchor_kernel(beta, gamma, omega, theta0, v0):
    return taylor_coefficients(beta, gamma, omega, theta0, v0, np.int64(8))


@kernel
def taylor12_anchor_kernel(beta, gamma, omega, theta0, v0):
    return taylor_coefficients(beta, gamma, omega, theta0, v0, np.int64(12))


@kernel
def taylor16_anchor_kernel(beta, gamma, omega, theta0, v0):
    return taylor_coefficients(beta, gamma, omega, theta0, v0, np.int64(16))


@kernel
def taylor20_anchor_kernel(beta, gamma, omega, theta0, v0):
    return taylor_coefficients(beta, gamma, omega, theta0, v0, np.int64(20))


@kernel
def taylor24_anchor_kernel(beta, gamma, omega, theta0, v0):
    return taylor_coefficients(beta, gamma, omega, theta0, v0, np.int64(24))


@kernel
def taylor30_anchor_kernel(beta, gamma, omega, theta0, v0):
    return taylor_coefficients(beta, gamma, omega, theta0, v0, np.int64(30))


_ANCHOR_KERNELS = {
    8: taylor8_anchor_kernel,
    12: taylor12_anchor_kernel,
    16: taylor16_anchor_kernel,
    20: taylor20_anchor_kernel,
    24: taylor24_anchor_kernel,
    30: taylor30_anchor_kernel,
}


class Taylor(Approximant):
    """Degree-N Taylor polynomial of the true solution at the anchor (global order N − 1).

    Registered as ``"taylor8"``, ``"taylor12"``, ``"taylor16"``, ``"taylor20"``,
    ``"taylor24"``, ``"taylor30"`` and ``"taylor"`` (= degree
    :data:`TAYLOR_DEFAULT_ORDER`).  Any β ≥ 0, γ, ω > 0 and any anchor state, and
    the AC drive A sin(Ωt + φ) (:meth:`drive_anchor`; module docstring, "AC drive").
    The window must lie inside the series' radius of convergence (``params['radius']``
    estimates it); :meth:`error_kernel` estimates the local error for window control.

    Attributes
    ----------
    error_order : int
        N: the two-term estimate of :func:`taylor_error_kernel` scales as h^(N+1).
    measured_order : int
        Convergence order N − 1: global error O(τ^{N−1}) for a fixed window τ (the
        velocity polynomial has degree N − 1; module docstring, "Order").
    kind_arg : int
        The degree N, the compiled loop's argument of kind ``"taylor"``.
    """

    compiled_kind = "taylor"
    drive_capable = True
    citation = (
        "Taylor series of the exact solution, coefficients by automatic differentiation "
        "(s' = c θ', c' = −s θ'); not from the papers"
    )
    anchors = "any"
    status_messages = {
        STATUS_BAD_STATE: "the anchor state and parameters must be finite",
        STATUS_BAD_ORDER: f"the degree must be 1 .. {MAX_ORDER}",
    }
    eval_kernel = staticmethod(taylor_eval_kernel)
    eval_array_kernel = staticmethod(taylor_eval_array_kernel)
    error_kernel = staticmethod(taylor_error_kernel)

    def param_names(self):
        return ("order", "beta", "gamma", "omega")

    def drive_anchor(self, model, t0, theta0, v0):
        """The coefficient vector of the driven model's series at time ``t0``
        (:func:`taylor_driven_coefficients`)."""
        amp, freq, phase = model.drive
        return taylor_driven_coefficients((model.beta, model.gamma, model.omega, amp, freq, phase),
                                          float(t0), theta0, v0, int(self.kind_arg))

    def params_from_coef(self, coef):
        """``order``, ``beta``, ``gamma``, ``omega``, ``radius`` (see :func:`radius_estimate`)
        and ``coefficients`` (a_0 .. a_N)."""
        d = {k: float(v) for k, v in zip(self.param_names(), coef[1:HEADER])}
        d["order"] = int(coef[1])
        d["radius"] = radius_estimate(coef)
        d["coefficients"] = np.array(coef[HEADER:HEADER + int(coef[1]) + 1])
        return d


def radius_estimate(coef):
    """Root-test estimate of the series' radius of convergence, min_k |a_k|^{−1/k}, k = N+1, N+2.

    Parameters
    ----------
    coef : ndarray
        From a ``taylor*`` anchor kernel.

    Returns
    -------
    float
        ``inf`` when both extra coefficients vanish (e.g. at rest at an equilibrium).
    """
    return float(taylor_radius_kernel(coef))


def _make(n, name):
    cls = type(
        f"Taylor{n}" if name != "taylor" else "TaylorDefault",
        (Taylor,),
        {
            "name": name,
            "error_order": n,
            "measured_order": n - 1,
            "kind_arg": n,
            "anchor_kernel": staticmethod(_ANCHOR_KERNELS[n]),
            "__doc__": f"Degree-{n} anchored Taylor polynomial (global order {n - 1}); see :class:`Taylor`.",
        },
    )
    return register(cls)


for _n in TAYLOR_ORDERS:
    _c = _make(_n, f"taylor{_n}")
    globals()[_c.__name__] = _c
TaylorDefault = _make(TAYLOR_DEFAULT_ORDER, "taylor")
del _n, _c
