r"""The Langevin runs at compiled speed: many scenes in parallel (``numba.prange``, no GIL).

One step of length h is the symmetric splitting O(h/2) D(h) O(h/2) of
:mod:`mbm.noise.flow`.  Two half O steps in a row are one exact O(h) (the OU flow is a
semigroup), so a run is O(h/2), then [D(h), O(h)] repeated: one normal deviate a step.
θ between D and O is θ of the symmetric scheme at the step's end (O leaves θ alone);
θ' there is the scheme's θ' before its last O(h/2), which, like every intermediate
state, has the Boltzmann law when the scene has one (each piece preserves it).

Scene ``i`` draws its deviates from the counter-based stream (seed, i)
(:mod:`mbm.noise.rng`): results do not depend on the thread count.
"""

import collections
import math

import numpy as np
from numba import njit, prange

from ..compile.jit import INLINE, NJIT_OPTIONS
from .flow import P_BETA, P_GAMMA0, P_OMEGA2, P_RATE, P_TEMP, TAYLOR_ORDER, hamiltonian_flow
from .rng import normal_pair, scene_key, uniform_pair

__all__ = ["START_COUNTER", "thermal_start_kernel", "escape_kernel", "switching_kernel", "retrapping_kernel", "moments_kernel", "path_kernel",
           "batch_path_kernel"]

# numba's options of the parallel run kernels: the package's, with prange threads.
PARALLEL_OPTIONS = dict(NJIT_OPTIONS, parallel=True, nogil=True)
# The first counter of a scene's thermal start draws: 2^40, past any step's counter (a
# run has at most 10^9 < 2^30 steps), so the start and the steps never share numbers.
START_COUNTER = 2**40

#: The random stream of one scene's path (:func:`path_kernel`): the run's seed and the
#: scene's index (a plain tuple of the two serves as well).
PathStream = collections.namedtuple("PathStream", ("seed", "scene"))

#: The steps a path call runs (:func:`path_kernel`): from step k0 to step k1 of size h
#: (a plain tuple of the three serves as well).
PathSteps = collections.namedtuple("PathSteps", ("k0", "k1", "h"))


@njit(**INLINE)
def _next(key, k, spare):
    # The k-th deviate of a stream read in order: (deviate, spare for k + 1). An even k
    # draws a pair and keeps its second half; an odd k returns the spare.
    if (k & 1) == 0:
        return normal_pair(key, k >> 1)
    return spare, spare


@njit(**INLINE)
def _ou(p, h):
    # (decay, spread) of the exact OU step over h, and of the half step h/2.
    beta = p[P_BETA]
    temp = p[P_TEMP]
    c = math.exp(-beta * h)
    c2 = math.exp(-0.5 * beta * h)
    return c, math.sqrt(temp * -math.expm1(-2.0 * beta * h)), c2, math.sqrt(temp * -math.expm1(-beta * h))


@njit(**PARALLEL_OPTIONS)
def thermal_start_kernel(p, stream, n, lo, u_min):
    """Per scene, a start [θ, θ'] from the Boltzmann law e^{−E/T} with θ in (lo, lo + 2π).

    ``stream`` = (seed, first scene) as :func:`escape_kernel`; the draws use the
    counters from :data:`START_COUNTER` on.  θ' = sqrt(T) z (z the first deviate of
    pair START_COUNTER); θ by rejection: uniform on (lo, lo + 2π) (u1 of pair
    START_COUNTER + j, j = 1, 2, ...), accepted when u2 < e^{−(U(θ) − u_min)/T},
    U(θ) = −ω² cos θ − γ0 θ (u_min ≤ min U on the interval).  Returns (n, 2).
    """
    out = np.empty((n, 2))
    w2 = p[P_OMEGA2]
    g = p[P_GAMMA0]
    temp = p[P_TEMP]
    for i in prange(n):
        key = scene_key(stream[0], stream[1] + i)
        out[i, 1] = math.sqrt(temp) * normal_pair(key, START_COUNTER)[0]
        j = START_COUNTER + 1
        while True:
            u1, u2 = uniform_pair(key, j)
            theta = lo + 2.0 * math.pi * u1
            if u2 < math.exp(-(-w2 * math.cos(theta) - g * theta - u_min) / temp):
                out[i, 0] = theta
                break
            j += 1
    return out


@njit(**PARALLEL_OPTIONS)
def escape_kernel(p, stream, n, starts, h, plan, max_steps, bounds):
    """First times θ leaves (bounds[0], bounds[1]), scene i from ``starts[i]`` at t = 0.

    ``stream`` = (seed, first scene): scene i draws the stream of scene first + i.

    Returns
    -------
    ndarray (n,)
        Per scene, the end time of the first step whose θ is outside the open
        interval; inf when none within ``max_steps`` steps.
    """
    out = np.empty(n)
    lo, hi = bounds[0], bounds[1]
    c, s, c2, s2 = _ou(p, h)
    for i in prange(n):
        b = np.empty(TAYLOR_ORDER + 1)
        sn = np.empty(TAYLOR_ORDER + 1)
        cn = np.empty(TAYLOR_ORDER + 1)
        key = scene_key(stream[0], stream[1] + i)
        theta = starts[i, 0]
        z, spare = _next(key, 0, 0.0)
        v = c2 * starts[i, 1] + s2 * z
        t_hit = np.inf
        for k in range(max_steps):
            theta, v = hamiltonian_flow(theta, v, k * h, h, plan, p, (b, sn, cn))
            if theta >= hi or theta <= lo:
                t_hit = (k + 1) * h
                break
            z, spare = _next(key, k + 1, spare)
            v = c * v + s * z
        out[i] = t_hit
    return out


@njit(**PARALLEL_OPTIONS)
def switching_kernel(p, stream, n, theta0, h, plan, max_steps, theta_done):
    """Under the bias γ0 + r t, the time each scene crossed the barrier before θ ≥ theta_done.

    ``stream`` = (seed, first scene): scene i draws the stream of scene first + i.

    Each scene starts at θ = ``theta0`` with θ' = 0 (after the first half O step: a
    deviate's worth of velocity).

    The barrier of the well at θ ∈ (−π/2, π/2]: θ is past its top when π/2 < θ < π and
    sin θ < γ(t)/ω² (the top is π − arcsin(γ/ω²)); the time recorded is the end of the
    last step that went from not past to past before θ reached ``theta_done``.  θ ≤ −π
    (a backward slip) is wrapped by 2π.  Returns (n,) times, inf for scenes that did not
    switch within ``max_steps``.
    """
    out = np.empty(n)
    c, s, c2, s2 = _ou(p, h)
    w2 = p[P_OMEGA2]
    for i in prange(n):
        b = np.empty(TAYLOR_ORDER + 1)
        sn = np.empty(TAYLOR_ORDER + 1)
        cn = np.empty(TAYLOR_ORDER + 1)
        key = scene_key(stream[0], stream[1] + i)
        theta = 0.0
        z, spare = _next(key, 0, 0.0)
        v = s2 * z
        t_cross = np.inf
        past = False
        out[i] = np.inf
        for k in range(max_steps):
            t = (k + 1) * h
            theta, v = hamiltonian_flow(theta, v, k * h, h, plan, p, (b, sn, cn))
            if theta <= -math.pi:
                theta += 2.0 * math.pi
            now = theta > 0.5 * math.pi and (theta >= math.pi or
                                              w2 * math.sin(theta) < p[P_GAMMA0] + p[P_RATE] * t)
            if now and not past:
                t_cross = t
            past = now
            if theta >= theta_done:
                out[i] = t_cross
                break
            z, spare = _next(key, k + 1, spare)
            v = c * v + s * z
    return out


@njit(**PARALLEL_OPTIONS)
def retrapping_kernel(p, stream, n, v0, h, plan, max_steps, wait):
    """Under the bias γ0 + r t (r < 0), the time each scene last passed a new barrier top.

    ``stream`` = (seed, first scene): scene i draws the stream of scene first + i.

    Each scene starts at θ = 0 with θ' = ``v0`` (before the first half O step).  A
    barrier top passed is a new odd multiple of π reached by θ (past every top
    π − arcsin(γ/ω²) + 2πk for γ ≥ 0): the time recorded is the end of the step that
    passed the last one, read once ``wait`` has elapsed without a new one (0 if none
    was passed).  Returns (n,) times, inf for scenes still slipping at ``max_steps``.
    """
    out = np.empty(n)
    c, s, c2, s2 = _ou(p, h)
    for i in prange(n):
        b = np.empty(TAYLOR_ORDER + 1)
        sn = np.empty(TAYLOR_ORDER + 1)
        cn = np.empty(TAYLOR_ORDER + 1)
        key = scene_key(stream[0], stream[1] + i)
        theta = 0.0
        z, spare = _next(key, 0, 0.0)
        v = c2 * v0 + s2 * z
        top = math.pi
        t_last = 0.0
        out[i] = np.inf
        for k in range(max_steps):
            t = (k + 1) * h
            theta, v = hamiltonian_flow(theta, v, k * h, h, plan, p, (b, sn, cn))
            if theta >= top:
                t_last = t
                top = (2.0 * math.floor((theta - math.pi) / (2.0 * math.pi)) + 3.0) * math.pi
            elif t - t_last >= wait:
                out[i] = t_last
                break
            z, spare = _next(key, k + 1, spare)
            v = c * v + s * z
    return out


@njit(**PARALLEL_OPTIONS)
def moments_kernel(p, seed, n, start, h, plan, burn_steps, steps):
    """Per scene, time averages of θ'², cos θ and θ over ``steps`` steps after ``burn_steps``.

    Returns (n, 3): columns ⟨θ'²⟩, ⟨cos θ⟩, ⟨θ⟩ of each scene (its states between D
    and O, module docstring).
    """
    out = np.zeros((n, 3))
    c, s, c2, s2 = _ou(p, h)
    for i in prange(n):
        b = np.empty(TAYLOR_ORDER + 1)
        sn = np.empty(TAYLOR_ORDER + 1)
        cn = np.empty(TAYLOR_ORDER + 1)
        key = scene_key(seed, i)
        theta = start[0]
        z, spare = _next(key, 0, 0.0)
        v = c2 * start[1] + s2 * z
        a0 = 0.0
        a1 = 0.0
        a2 = 0.0
        for k in range(burn_steps + steps):
            theta, v = hamiltonian_flow(theta, v, k * h, h, plan, p, (b, sn, cn))
            if k >= burn_steps:
                a0 += v * v
                a1 += math.cos(theta)
                a2 += theta
            z, spare = _next(key, k + 1, spare)
            v = c * v + s * z
        out[i, 0] = a0 / steps
        out[i, 1] = a1 / steps
        out[i, 2] = a2 / steps
    return out


@njit(**PARALLEL_OPTIONS)
def batch_path_kernel(params, seed, states, steps, plans, marks, out):
    """:func:`path_kernel` for scenes i = 0 .. N − 1 (params (N, 8), states (N, 2),
    plans (N, 2), out (N, len(marks), 2)) on the streams (seed, i), each over the
    :data:`PathSteps` ``steps``."""
    for i in prange(params.shape[0]):
        path_kernel(params[i], (seed, i), states[i], steps, (plans[i, 0], plans[i, 1]), marks, out[i])


@njit(**NJIT_OPTIONS)
def path_kernel(p, stream, state, steps, plan, marks, out):
    """Advance one scene's ``state`` [θ, θ'] in place from step ``k0`` to step ``k1``
    (``steps``, the :data:`PathSteps` (k0, k1, h)).

    ``out[j]`` receives the state after marks[j] steps (sorted, in [k0, k1]; the
    start k0 included).  Step k draws pair k of the :data:`PathStream` ``stream``
    (seed, scene) and runs D
    from time k h: the state after step k does not depend on where the runs between
    k0 and k1 were cut.  Each state is the symmetric scheme's after whole steps, each
    half O with a deviate of its own (these numbers differ from the run kernels',
    which fuse the half steps).
    """
    seed, scene = stream
    k0, k1, h = steps
    m = marks.shape[0]
    c2, s2 = _ou(p, h)[2:]
    b = np.empty(TAYLOR_ORDER + 1)
    sn = np.empty(TAYLOR_ORDER + 1)
    cn = np.empty(TAYLOR_ORDER + 1)
    key = scene_key(seed, scene)
    theta, v = state[0], state[1]
    j = 0
    k = k0
    while True:
        while j < m and marks[j] == k:
            out[j, 0], out[j, 1] = theta, v
            j += 1
        if k >= k1:
            break
        z0, z1 = normal_pair(key, k)
        v = c2 * v + s2 * z0
        theta, v = hamiltonian_flow(theta, v, k * h, h, plan, p, (b, sn, cn))
        v = c2 * v + s2 * z1
        k += 1
    state[0], state[1] = theta, v
