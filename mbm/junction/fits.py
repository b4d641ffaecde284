"""From a measurement to the model's parameters: β from the retrapping current.

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

import math

from ..events.compiled import angle_event, velocity_event
from ..frontends.solve import solve
from ..model import Pendulum
from ..validate import check_positive, check_real, check_rule

__all__ = ["retrapping_current", "beta_from_retrapping"]

# Offset of the manifold's start from the saddle along its unstable eigenvector: the
# linear eigenvector's error is O(offset²) ≈ 1e-16, far below the tolerance, while the
# run still leaves the saddle in log(1/offset)/λ ≈ 20/λ time units.
MANIFOLD_OFFSET = 1e-8
# The runs' tolerances: the miss is located to ~1e-12 in γ (measured: the root moves by
# < 1e-11 between rtol 1e-10 and 1e-12).
MANIFOLD_RTOL = 1e-12
MANIFOLD_ATOL = 1e-14
# Longest run: a manifold that neither passes the next saddle nor turns back within it
# creeps onto an overdamped node (trapped).
MANIFOLD_SPAN = 1e5
# Largest γ/ω² probed: at γ → ω² the saddle merges with the node (λ → 0); a γ_r above
# this is reported as ω² (no hysteresis), an error below 1e-6 (the manifold then
# takes ~5000 time units through the bottleneck; 10 times closer, ~3 times longer).
GAMMA_TOP = 1.0 - 1e-6
# β (at ω = 1) above which the undriven junction has no hysteresis (γ_r = 1): β* ≈ 1.19
# (measured); 2 brackets every γ_r < 1 from above.
BETA_TOP = 2.0
# Brent's absolute tolerance on the root (γ or β).
ROOT_XTOL = 1e-14


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
    beta = check_positive("beta", beta)
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
