r"""Retrapping of the running junction under a falling bias: :func:`retrapping_currents`.

The model of :mod:`mbm.noise.api`, θ'' + βθ' + ω² sin θ = γ(t) + ξ(t), with the bias
ramped down, γ(t) = γ0 − r t, from the running (voltage) state until the phase is
caught in a well.  Deterministically (T → 0, r → 0) that happens at the retrapping
current of :func:`mbm.iv_curve`, ≈ 4βω/π for β ≪ ω (Stewart–McCumber; Melnikov's
energy balance: the energy ∮βθ' dθ ≈ 8βω lost over a slip equals the work 2πγ).
"""

import dataclasses
import math

import numpy as np

from ..validate import check_rule
from .api import (DT_DEFAULT, GAMMA_END, MAX_STEPS, SwitchingHistogram, _chunked, _moments, _steps, _threads,
                  ramp_args)
from .flow import make_params, substeps
from .kernels import retrapping_kernel
from .rng import resolve_seed

__all__ = ["RetrappingHistogram", "retrapping_currents"]

# The default start γ0 = min(ω², RETRAP_START · 4βω/π): twice the small-β retrapping
# current, well on the running side (the exact retrapping current is below 4βω/π and
# below ω²), without the fast and costly early ramp from ω² at small β.
RETRAP_START = 2.0
# A scene is retrapped once no new barrier top has been passed for RETRAP_WAIT times
# max(1/ω, β/ω²): ten small-oscillation periods (or, overdamped, ten relaxation times
# β/ω² of the well), past the slowest running cycle near retrapping (its period grows
# only like ln(1/δE) as its energy δE above the barrier shrinks).
RETRAP_WAIT = 20.0 * math.pi
# Thermal velocity spread bounded for the Taylor plan: |θ'| beyond 8 sqrt(T) above the
# running orbit has probability ~e^-32.
SPEED_SIGMAS = 8.0


@dataclasses.dataclass(frozen=True)
class RetrappingHistogram(SwitchingHistogram):
    """Retrapping biases under a falling ramp γ = γ0 − r t (:func:`retrapping_currents`).

    A frozen dataclass (a :class:`SwitchingHistogram`) built by
    :func:`retrapping_currents`: each parameter is an attribute.

    Parameters
    ----------
    currents : ndarray (n,)
        Each scene's retrapping bias γ_r (I_r/I_c = γ_r/ω²); nan for a scene still
        slipping at γ = 0.
    mean, width : float
        Mean and standard deviation (ddof = 1) of the finite currents.
    skewness : float
        m3 / m2^{3/2} (positive: a tail towards higher currents).
    kurtosis : float
        m4 / m2², not the excess.
    seed : int
        The run's seed (reproduces it).
    dt, ramp_rate : float
        The step and the rate r > 0 of the fall.
    """


def retrapping_currents(beta, temperature, ramp_rate, n, *, omega=1.0, seed=None, dt=DT_DEFAULT,
                        gamma_start=None, threads=None):
    r"""Retrapping biases of ``n`` thermal junctions under the falling ramp γ(t) = γ0 − r t.

    Each scene starts running, θ = 0 with θ' = γ0/β (the running state's mean
    velocity for β ≪ ω; it settles within ~1/β), and runs θ'' + βθ' + ω² sin θ =
    γ0 − r t + ξ(t).  Its retrapping bias is γ at the end of the step where θ passed
    its last new barrier top (a new odd multiple of π, past every top
    π − arcsin(γ/ω²) + 2πk for γ ≥ 0), read once θ has passed none for
    :data:`RETRAP_WAIT` · max(1/ω, β/ω²) (ten small-oscillation periods, or well
    relaxation times when overdamped): the phase has stopped advancing and sits in a
    well.  A scene still slipping when γ reaches 0 (plus that wait) is reported as nan.

    The running state's velocity relaxes at the rate β, so it lags the ramp: the
    phase retraps near γ_r − r/β (γ_r of :func:`mbm.retrapping_current`); choose
    r ≪ β γ_r (at r ≳ β γ_r scenes reach γ = 0 still slipping: nan).  Retrapping is
    sharp in the hysteretic regime β < 1.19 ω; overdamped, the phase crawls through
    the ghost of the saddle-node near γ = ω² and the wait decides.

    Parameters
    ----------
    beta : float
        Damping, > 0.
    temperature : float
        T > 0 (as :func:`mbm.escape_times`).
    ramp_rate : float
        r > 0, the bias's fall per unit time.
    n : int
        Number of scenes, ≥ 1.
    omega, seed, dt : optional
        As :func:`mbm.escape_times`.
    gamma_start : float, optional
        γ0 in (0, 1.5 ω²], on the running side of retrapping; default
        min(ω², 2 · 4βω/π) (:data:`RETRAP_START`).
    threads : int, optional
        As :func:`mbm.escape_times`.

    Returns
    -------
    RetrappingHistogram
        ``kurtosis`` is m4/m2² (not the excess).
    """
    beta, temperature, ramp_rate, omega, n, dt = ramp_args(beta, temperature, ramp_rate, omega, n, dt)
    w2 = omega * omega
    if gamma_start is None:
        g0 = min(w2, RETRAP_START * 4.0 * beta * omega / math.pi)
    else:
        g0 = check_rule("gamma_start", gamma_start, (">0", "> 0"))
        if g0 > GAMMA_END * w2:
            raise ValueError(f"gamma_start must be in (0, {GAMMA_END} * omega**2] = (0, {GAMMA_END * w2!r}], "
                             f"got {g0!r}")
    seed = resolve_seed(seed)
    wait = RETRAP_WAIT * max(1.0 / omega, beta / w2)
    slowest = g0 / (MAX_STEPS * dt - wait)
    if ramp_rate < slowest:
        raise ValueError(f"ramp_rate must be >= {slowest!r} with dt = {dt!r} (the ramp down to 0 "
                         f"in at most {MAX_STEPS} steps), got {ramp_rate!r}")
    steps = _steps(g0 / ramp_rate + wait, dt, "gamma_start / ramp_rate")
    v0 = g0 / beta
    # θ' bounds the rate of sin θ(t): the plan's substeps are sized for it as for a frequency
    speed = math.sqrt(v0 * v0 + 4.0 * w2) + SPEED_SIGMAS * math.sqrt(temperature)
    p = make_params(beta, omega, g0, -ramp_rate, 0.0, 0.0, 0.0, temperature)
    with _threads(threads):
        plan = substeps(dt, omega, g0, speed)
        t = _chunked(lambda stream, m: retrapping_kernel(p, stream, m, v0, dt, plan, steps, wait), seed, n)
    currents = np.where(np.isfinite(t), g0 - ramp_rate * t, np.nan)
    return RetrappingHistogram(currents, *_moments(currents), seed, dt, ramp_rate)
