"""Counter-based normal deviates: a scene's noise is a pure function of (seed, scene, counter).

The k-th pair of standard normals of scene ``i`` under seed ``s`` is Box–Muller applied
to two SplitMix64 outputs at positions ``2k + 1`` and ``2k + 2`` of the stream whose
start is ``key(s, i) = mix64(mix64(s ^ SEED_SALT) + i · GOLDEN)``.  SplitMix64 (Steele,
Lea & Flood 2014; the generator that seeds xoshiro) is ``mix64(start + n · GOLDEN)``
for n = 1, 2, ...: random access by position, no state to carry or split, so a run's
numbers do not depend on how scenes are spread over threads or chunks, and the same
seed gives the same bits.  A leaf module (numba and numpy only).
"""

import math
import numbers

import numpy as np
from numba import njit

from ..compile.jit import INLINE

__all__ = ["GOLDEN", "mix64", "scene_key", "normal_pair", "uniform_pair", "resolve_seed"]

# The golden-ratio increment of SplitMix64 (odd, so n · GOLDEN visits all 2^64 values).
GOLDEN = np.uint64(0x9E3779B97F4A7C15)
# The two multipliers of SplitMix64's finaliser (Stafford's "Mix13").
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)
# Xored into the seed before hashing, so that seed 0 does not start at mix64(0) = 0.
SEED_SALT = np.uint64(0x5851F42D4C957F2D)
# 2^-53: a 53-bit integer times this is a double in [0, 1) with every bit random.
_TWO_M53 = 1.0 / 9007199254740992.0
# The largest seed accepted (seeds are unsigned 64-bit integers).
SEED_MAX = 2**64 - 1


@njit(**INLINE)
def mix64(z):
    """SplitMix64's finaliser: a bijection of uint64 with full avalanche."""
    z = (z ^ (z >> np.uint64(30))) * _M1
    z = (z ^ (z >> np.uint64(27))) * _M2
    return z ^ (z >> np.uint64(31))


@njit(**INLINE)
def scene_key(seed, scene):
    """The stream start of scene ``scene`` (int ≥ 0) under ``seed`` (uint64)."""
    return mix64(mix64(seed ^ SEED_SALT) + np.uint64(scene) * GOLDEN)


@njit(**INLINE)
def normal_pair(key, counter):
    """The ``counter``-th pair (counter ≥ 0) of independent N(0, 1) deviates of a stream.

    Box–Muller on u1 ∈ (0, 1] and u2 ∈ [0, 1), each from the top 53 bits of a
    SplitMix64 output; the largest deviate possible is sqrt(2 · 53 ln 2) ≈ 8.57.
    """
    base = key + np.uint64(2 * counter) * GOLDEN
    z1 = mix64(base + GOLDEN)
    z2 = mix64(base + GOLDEN + GOLDEN)
    u1 = (float(z1 >> np.uint64(11)) + 1.0) * _TWO_M53
    u2 = float(z2 >> np.uint64(11)) * _TWO_M53
    r = math.sqrt(-2.0 * math.log(u1))
    a = 2.0 * math.pi * u2
    return r * math.cos(a), r * math.sin(a)


@njit(**INLINE)
def uniform_pair(key, counter):
    """The ``counter``-th pair of independent uniforms on [0, 1) of a stream: the two
    SplitMix64 outputs that :func:`normal_pair` turns into normals at that counter."""
    base = key + np.uint64(2 * counter) * GOLDEN
    u1 = float(mix64(base + GOLDEN) >> np.uint64(11)) * _TWO_M53
    u2 = float(mix64(base + GOLDEN + GOLDEN) >> np.uint64(11)) * _TWO_M53
    return u1, u2


def resolve_seed(seed):
    """``seed`` as an int in [0, 2^64 − 1]; None draws one from the operating system.

    Raises
    ------
    TypeError
        For a seed that is not an integer (bool included).
    ValueError
        For a negative seed or one above 2^64 − 1.
    """
    if seed is None:
        return int(np.random.SeedSequence().entropy) & SEED_MAX
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, numbers.Integral):
        raise TypeError(f"seed must be None or an integer in [0, 2**64 - 1], got {seed!r}")
    seed = int(seed)
    if not 0 <= seed <= SEED_MAX:
        raise ValueError(f"seed must be in [0, 2**64 - 1], got {seed!r}")
    return seed
