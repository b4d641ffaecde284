"""Validation and reshaping for the numpy-level wrappers of :mod:`mbm.special`.

Private to the package: :mod:`mbm.special.jacobi` and :mod:`mbm.special.weierstrass`
use it; nothing outside :mod:`mbm.special` should.
"""

import numpy as np

__all__ = ["finite_f64", "flat", "unflat", "nan_guard"]


def finite_f64(name, x):
    """``x`` as a float64 array, or TypeError / ValueError naming the argument."""
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be real (float64-convertible), got {x!r}") from None
    if not np.all(np.isfinite(a)):
        bad = a[~np.isfinite(a)].ravel()[0] if a.ndim else a
        raise ValueError(f"{name} must be finite, got {float(bad)!r}")
    return a


def flat(*arrays):
    """Broadcast, then contiguous 1-D float64 copies plus the common shape."""
    b = np.broadcast_arrays(*arrays)
    shape = b[0].shape
    return shape, [np.ascontiguousarray(x, dtype=np.float64).reshape(-1) for x in b]


def unflat(a, shape, scalar):
    """Undo :func:`flat` on a result: a Python float for scalar input, else ``shape``."""
    if scalar:
        return float(a[0])
    return a.reshape(shape)


def nan_guard(name, *outs):
    """FloatingPointError if a kernel returned NaN from finite input (a bug, never silent)."""
    for o in outs:
        if np.isnan(o).any():
            raise FloatingPointError(f"{name}: internal error, NaN produced from finite input")
