"""numba compilation options shared by the package's kernels.

``@numba.njit(**NJIT_OPTIONS)`` decorates every kernel of :mod:`mbm.special` and of
the paper and splitting modules of :mod:`mbm.approximants`.
"""

__all__ = ["NJIT_OPTIONS"]

# cache: compiled kernels persist in __pycache__, so only the first run compiles.
# error_model="numpy": a float division by zero gives ±inf/nan instead of raising
# ZeroDivisionError inside a compiled loop; kernels report failure by status code or
# NaN, never by an exception (the cn form (2.17) needs R = 0 → Abar = inf, the special
# functions their poles; no kernel result changes for a non-zero divisor).
NJIT_OPTIONS = {"cache": True, "error_model": "numpy"}
