"""From a measurement to the model's parameters: β from the retrapping current, and a
least-squares fit of β, I_c and R to a measured I–V curve (:func:`fit_iv`).

The undriven junction  θ'' + β θ' + ω² sin θ = γ  is bistable for γ_r(β) < γ < ω²
when β is small: the running cycle is born at γ_r in a homoclinic bifurcation, where
the unstable manifold of the saddle θ_s = π − arcsin(γ/ω²) reaches the next saddle
θ_s + 2π.  Scaling time by ω, γ_r(β, ω) = ω² g_r(β/ω), g_r the ω = 1 curve: g_r ≈ 4β/π
for small β (Melnikov), g_r = 1 (no hysteresis) above β* ≈ 1.192 (β_c ≈ 0.70; measured:
beta_from_retrapping(1 − 1e-6) = 1.19204).

The manifold is followed by :func:`mbm.solve` (Taylor, rtol 1e-12) from the saddle,
offset along its unstable eigenvector, until it passes the next saddle or turns back;
the root of the continuous miss :func:`_miss` (the velocity at the next saddle, or the
angle short of it) is found by Brent's method in γ (:func:`retrapping_current`) or,
at a given γ, in β (:func:`beta_from_retrapping`): one root-finding either way.
"""

import dataclasses
import math

import numpy as np

from ..events.compiled import angle_event, velocity_event
from ..frontends.solve import solve
from ..model import Pendulum
from ..validate import check_positive, check_real, check_real_array, check_rule
from .iv import mean_velocity
from .units import FLUX_QUANTUM, Junction

__all__ = ["retrapping_current", "beta_from_retrapping", "fit_iv", "IVFit"]

# Offset of the manifold's start from the saddle along its unstable eigenvector: the
# linear eigenvector's error is O(offset²) ≈ 1e-16, far below the tolerance, while the
# run still leaves the saddle in log(1/offset)/λ ≈ 20/λ time units.
MANIFOLD_OFFSET = 1e-8
# The runs' tolerances (measured at β = 0.5: γ_r moves by 6e-16 between rtol 1e-10 and
# 1e-12, and by less with the offset 1e-6 in place of 1e-8).
MANIFOLD_RTOL = 1e-12
MANIFOLD_ATOL = 1e-14
# Longest run: a manifold that neither passes the next saddle nor turns back within it
# creeps onto an overdamped node (trapped).
MANIFOLD_SPAN = 1e5
# Largest γ/ω² probed: at γ → ω² the saddle merges with the node (λ → 0); a γ_r above
# this is reported as ω² (no hysteresis), an error below 1e-6 (there the manifold
# takes ~4500 time units through the bottleneck at β = 0.5, measured; at 1 − 1e-8 it
# does not pass within 1e4).
GAMMA_TOP = 1.0 - 1e-6
# β* ≈ 1.192 (at ω = 1) is where hysteresis ends (γ_r = 1 above it, measured): 2
# brackets the β of every γ_r < 1 from above.
BETA_TOP = 2.0
# Brent's absolute tolerance on the root (γ or β).
ROOT_XTOL = 1e-14
# fit_iv: points with abs(V) at most this fraction of the largest abs(V) count as zero-voltage
# (locked, no information on the running branch's shape) and are left out by default.
ZERO_VOLTAGE_FRACTION = 0.02
# fit_iv's finite-difference step (scipy's diff_step: 1e-6 · max(1, |x|) on log β,
# log I_c, log R): V moves by ~1e-6 of itself, 1000 times ⟨θ'⟩'s settling error
# (~1e-9, tests/test_junction.py).
FIT_DIFF_STEP = 1e-6
# fit_iv without sigma: residuals in units of this fraction of the largest voltage.
RESIDUAL_UNIT = 1e-3
# fit_iv's default start puts the lowest running point this far above the start's
# retrapping current: a point at the bifurcation itself (locked or running as the
# parameters move by a step) would make the Jacobian meaningless.
START_ABOVE_RETRAPPING = 1.2


def _miss(beta, gamma):
    """How far the saddle's unstable manifold overshoots the next saddle at ω = 1.

    > 0: the velocity θ' with which it passes θ_s + 2π (a running cycle exists);
    ≤ 0: θ − (θ_s + 2π) where it turns back (θ' = 0) or ends (trapped).  Continuous in
    (β, γ), zero at the homoclinic bifurcation γ = γ_r(β).
    """
    theta_s = math.pi - math.asin(gamma)
    # linearization at the saddle: λ² + βλ − √(1 − γ²) = 0, eigenvector (1, λ)
    lam = -0.5 * beta + math.sqrt(0.25 * beta * beta + math.sqrt(1.0 - gamma * gamma))
    events = [angle_event(theta_s, direction=1.0, terminal=True),
              velocity_event(0.0, direction=-1.0, terminal=True)]
    run = solve(Pendulum(beta, gamma, 1.0), (0.0, MANIFOLD_SPAN),
                [theta_s + MANIFOLD_OFFSET, lam * MANIFOLD_OFFSET], rtol=MANIFOLD_RTOL,
                atol=MANIFOLD_ATOL, approximant="taylor", events=events, max_events=1)
    if run.t_events[0].size:
        return float(run.y_events[0][0][1])
    return float(run.y[0, -1]) - (theta_s + 2.0 * math.pi)


def _reduced_gamma_r(beta):
    # g_r(β) at ω = 1: the root in γ of the miss, or 1 where none lies below GAMMA_TOP
    from scipy.optimize import brentq

    if _miss(beta, GAMMA_TOP) <= 0.0:
        return 1.0
    return brentq(lambda g: _miss(beta, g), 0.0, GAMMA_TOP, xtol=ROOT_XTOL)


def retrapping_current(beta, *, omega=1.0):
    """The retrapping current γ_r of the undriven RCSJ junction (homoclinic bifurcation).

    Parameters
    ----------
    beta : float
        Damping β > 0.
    omega : float, optional
        ω > 0 (1 in the junction's reduced units).

    Returns
    -------
    float
        γ_r = ω² g_r(β/ω), the lowest bias at which a running state exists: the
        retrapping current of an I–V sweep coming down, in units of γ (``γ_r/ω²`` is
        I_r/I_c).  ω² (no hysteresis) for β/ω ≥ β* ≈ 1.19.

    Raises
    ------
    ValueError
        For β ≤ 0 or ω ≤ 0, or a non-finite value.

    See Also
    --------
    beta_from_retrapping : its inverse.
    mbm.iv_curve : the retrapping current bisected on a sweep.
    """
    beta = check_positive("beta", beta, why="damping: an I–V curve needs a damped junction")
    omega = check_rule("omega", omega)
    return omega * omega * _reduced_gamma_r(beta / omega)


def beta_from_retrapping(ratio, *, omega=1.0):
    """The damping β at which the retrapping current is ``ratio`` × the critical current.

    Inverts :func:`retrapping_current`: β with γ_r(β)/ω² = ``ratio`` (a measured
    I_r/I_c); β_c = (ω/β)² is the Stewart–McCumber parameter.

    Parameters
    ----------
    ratio : float
        I_r/I_c, strictly between 0 and 1 (at 1 the junction has no hysteresis and β
        is only bounded below, by β* ≈ 1.19 ω).
    omega : float, optional
        ω > 0 (1 in the junction's reduced units).

    Returns
    -------
    float
        β > 0, to about 1e-12 relative.

    Raises
    ------
    ValueError
        For ``ratio`` outside (0, 1), ω ≤ 0, or a non-finite value.
    """
    r = check_real("ratio", ratio)
    if not 0.0 < r < 1.0:
        raise ValueError(f"ratio must be > 0 and < 1 (I_r/I_c of a hysteretic junction), got {float(ratio)!r}")
    omega = check_rule("omega", omega)
    from scipy.optimize import brentq

    # g_r < 4β/π (Melnikov's first order is an upper bound, measured): β_r > πr/4
    lo = 0.5 * math.pi * r / 4.0
    while _miss(lo, r) <= 0.0:
        lo *= 0.5
    return omega * brentq(lambda b: _miss(b, r), lo, BETA_TOP, xtol=ROOT_XTOL)


@dataclasses.dataclass(frozen=True)
class IVFit:
    """The result of :func:`fit_iv`: β, I_c and R with their uncertainties.

    Parameters
    ----------
    beta, I_c, R : float
        The fitted damping β (reduced units, ω = 1), critical current (A) and
        resistance (Ω).
    beta_err, I_c_err, R_err : float
        Their standard errors (one σ) from the Jacobian at the solution.
    beta_c, beta_c_err : float
        β_c = 1/β² and its standard error.
    covariance : ndarray, shape (3, 3)
        The covariance of (β, I_c, R).
    junction : Junction
        The junction of the fitted values (C = β_c Φ₀ / (2π I_c R²)).
    residuals : ndarray
        Model minus measured voltage (V) at the fitted points.
    fitted : ndarray of bool
        Which of the given points were fitted (the running ones).
    sigma : float or ndarray
        The voltage noise the uncertainties assume: the one given, or the residuals'
        root mean square (with 3 degrees of freedom removed).
    success : bool
        Whether :func:`scipy.optimize.least_squares` converged.
    nfev : int
        Model evaluations (each a sweep down the running branch).
    """

    beta: float
    I_c: float
    R: float
    beta_err: float
    I_c_err: float
    R_err: float
    beta_c: float
    beta_c_err: float
    covariance: np.ndarray
    junction: Junction
    residuals: np.ndarray
    fitted: np.ndarray
    sigma: object
    success: bool
    nfev: int


def running_branch_voltage(current, beta, I_c, R):
    """The dc voltage of the running branch at each current, swept down adiabatically.

    V = β I_c R ⟨θ'⟩(γ = I/I_c), the points visited in decreasing abs(I) from a running
    state (sign(I) restored): 0 below the retrapping current.

    Parameters
    ----------
    current : ndarray
        Currents in amperes.
    beta, I_c, R : float
        β (reduced units), I_c (A) and R (Ω).

    Returns
    -------
    ndarray
        Voltages in volts, in the order of ``current``.
    """
    gamma = np.abs(current) / I_c
    order = np.argsort(-gamma, kind="stable")
    v = np.zeros(gamma.size)
    y = np.array([0.0, gamma[order[0]] / beta + 1.0])  # above the running cycle's top speed
    for k in order:
        try:
            _, v[k], _, y = mean_velocity(Pendulum(beta, gamma[k], 1.0), y)
        except RuntimeError:  # on the bifurcation itself: counted locked
            v[k] = 0.0
    return np.sign(current) * beta * I_c * R * v


def _initial_guess(current, voltage, beta0, I_c0, R0):
    # R from the highest bias (V ≈ I R there), I_c with the lowest running current at
    # START_ABOVE_RETRAPPING × the retrapping current of beta0 (I_r = γ_r(β0) I_c)
    top = int(np.argmax(np.abs(current)))
    if R0 is None:
        R0 = voltage[top] / current[top]
    if I_c0 is None:
        I_c0 = float(np.min(np.abs(current))) / (START_ABOVE_RETRAPPING * retrapping_current(beta0))
    return check_positive("I_c0", I_c0), check_positive("R0", R0)


def fit_iv(current, voltage, *, beta0=0.5, I_c0=None, R0=None, sigma=None, fitted=None):
    """Fit β, I_c and R of the RCSJ model to a measured I–V curve (least squares).

    The model is the running branch swept down (:func:`running_branch_voltage`):
    V = β I_c R ⟨θ'⟩(I/I_c), fitted by :func:`scipy.optimize.least_squares` in log β,
    log I_c, log R; the standard errors come from the Jacobian at the solution.

    Parameters
    ----------
    current, voltage : array_like
        The measured points, amperes and volts, same length.
    beta0 : float, optional
        Starting β (default 0.5).
    I_c0, R0 : float, optional
        Starting I_c and R (default: R from the highest bias, V/I; I_c from the lowest
        fitted current taken as the retrapping current of ``beta0``).
    sigma : float or array_like, optional
        The voltage noise of each point (V); default None: estimated from the
        residuals.
    fitted : array_like of bool, optional
        Which points to fit; default the running ones, abs(V) above
        :data:`ZERO_VOLTAGE_FRACTION` of the largest (a zero-voltage point says only that
        the junction was locked there).

    Returns
    -------
    IVFit

    Raises
    ------
    ValueError
        For arrays of different lengths, non-finite values, fewer than 4 points to fit,
        a non-positive start or ``sigma``.
    """
    from scipy.optimize import least_squares

    current = _finite_array("current", current)
    voltage = _finite_array("voltage", voltage)
    if current.shape != voltage.shape:
        raise ValueError(f"current and voltage must have the same length, got {current.size} and {voltage.size}")
    use = (np.abs(voltage) > ZERO_VOLTAGE_FRACTION * np.max(np.abs(voltage), initial=0.0)
           if fitted is None else np.asarray(fitted, dtype=bool).reshape(-1))
    if use.shape != current.shape or np.count_nonzero(use) < 4:
        raise ValueError(f"fit_iv needs at least 4 running points to fit, got {int(np.count_nonzero(use))}")
    i, v = current[use], voltage[use]
    beta0 = check_positive("beta0", beta0)
    I_c0, R0 = _initial_guess(i, v, beta0, I_c0, R0)
    # residuals in units of sigma, or (none given) of a thousandth of the largest voltage:
    # of order 1 either way, as least_squares's tolerances (gtol on Jᵀr) expect
    s = RESIDUAL_UNIT * np.max(np.abs(v)) if sigma is None else np.broadcast_to(
        _finite_array("sigma", sigma), v.shape)
    if np.any(np.asarray(s) <= 0.0):
        raise ValueError("sigma must be > 0")

    def residuals(x):
        b, ic, r = np.exp(x)
        return (running_branch_voltage(i, b, ic, r) - v) / s

    res = least_squares(residuals, np.log([beta0, I_c0, R0]), diff_step=FIT_DIFF_STEP, x_scale=1.0)
    p = np.exp(res.x)
    scale = 2.0 * res.cost / max(v.size - 3, 1) if sigma is None else 1.0
    cov_log = scale * np.linalg.pinv(res.jac.T @ res.jac)
    cov = cov_log * np.outer(p, p)
    err = np.sqrt(np.diag(cov))
    beta_c = 1.0 / p[0] ** 2
    return IVFit(beta=float(p[0]), I_c=float(p[1]), R=float(p[2]), beta_err=float(err[0]),
                 I_c_err=float(err[1]), R_err=float(err[2]), beta_c=beta_c,
                 beta_c_err=float(2.0 * beta_c * math.sqrt(cov_log[0, 0])), covariance=cov,
                 junction=Junction(I_c=p[1], R=p[2], C=beta_c * FLUX_QUANTUM / (2.0 * math.pi * p[1] * p[2] ** 2)),
                 residuals=res.fun * s, fitted=use,
                 sigma=float(s * math.sqrt(scale)) if sigma is None else s, success=bool(res.success),
                 nfev=int(res.nfev))


def _finite_array(name, value):
    # a 1-D float array of finite real numbers, or the error naming ``name``
    arr = check_real_array(name, value).reshape(-1)
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise ValueError(f"{name} must be finite, got {name}[{int(bad[0])}] = {float(arr[bad[0]])!r}")
    return arr
