r"""An independent reference: the stochastic Heun scheme at a fine step.

For θ' = v, v' = F(θ, v, t) + sqrt(2βT) ξ(t), F = −βv − ω² sin θ + γ0 + r t (no drive),
one step of length dt with one deviate z ~ N(0, 1):

    θ* = θ + v dt,  v* = v + F(θ, v, t) dt + σ z     (σ = sqrt(2βT dt))
    θ ← θ + (v + v*) dt / 2,  v ← v + (F(θ, v, t) + F(θ*, v*, t + dt)) dt / 2 + σ z.

It shares nothing with :mod:`mbm.noise.kernels`: not the splitting, not the Taylor
flow, not the generator (numba's Mersenne Twister, reseeded with seed + scene at each
scene's start, so that a scene's numbers do not depend on the thread that runs it).
Used by the tests and ``benchmarks/noise.py`` to check the splitting integrator.
"""

import math

import numpy as np
from numba import njit, prange

from ..compile.jit import INLINE
from .flow import P_BETA, P_GAMMA0, P_OMEGA2, P_RATE, P_TEMP
from .kernels import PARALLEL_OPTIONS

__all__ = ["heun_escape_kernel", "heun_moments_kernel"]


@njit(**INLINE)
def _force(p, theta, v, t):
    return -p[P_BETA] * v - p[P_OMEGA2] * math.sin(theta) + p[P_GAMMA0] + p[P_RATE] * t


@njit(**INLINE)
def _heun(p, theta, v, t, dt, kick):
    # One stochastic Heun step; kick = sqrt(2βT dt) z.
    f0 = _force(p, theta, v, t)
    th1 = theta + v * dt
    v1 = v + f0 * dt + kick
    f1 = _force(p, th1, v1, t + dt)
    return theta + 0.5 * (v + v1) * dt, v + 0.5 * (f0 + f1) * dt + kick


@njit(**PARALLEL_OPTIONS)
def heun_escape_kernel(p, seed, n, start, dt, max_steps, bounds):
    """First times θ leaves (bounds[0], bounds[1]) (as :func:`~mbm.noise.kernels.escape_kernel`)."""
    out = np.empty(n)
    sig = math.sqrt(2.0 * p[P_BETA] * p[P_TEMP] * dt)
    lo, hi = bounds[0], bounds[1]
    for i in prange(n):
        np.random.seed((seed + i) % 4294967296)
        theta, v = start[0], start[1]
        t_hit = np.inf
        for k in range(max_steps):
            theta, v = _heun(p, theta, v, k * dt, dt, sig * np.random.standard_normal())
            if theta >= hi or theta <= lo:
                t_hit = (k + 1) * dt
                break
        out[i] = t_hit
    return out


@njit(**PARALLEL_OPTIONS)
def heun_moments_kernel(p, seed, n, start, dt, burn_steps, steps):
    """Per scene, time averages of θ'², cos θ and θ (as :func:`~mbm.noise.kernels.moments_kernel`)."""
    out = np.zeros((n, 3))
    sig = math.sqrt(2.0 * p[P_BETA] * p[P_TEMP] * dt)
    for i in prange(n):
        np.random.seed((seed + i) % 4294967296)
        theta, v = start[0], start[1]
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        for k in range(burn_steps + steps):
            theta, v = _heun(p, theta, v, k * dt, dt, sig * np.random.standard_normal())
            if k >= burn_steps:
                a0 += v * v
                a1 += math.cos(theta)
                a2 += theta
        out[i, 0] = a0 / steps
        out[i, 1] = a1 / steps
        out[i, 2] = a2 / steps
    return out
