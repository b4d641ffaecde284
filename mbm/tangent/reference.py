"""The reference series' step: a Taylor series of degree REF_DEGREE from a window's
start, far tighter than the run it measures (:mod:`mbm.tangent.transport`)."""

import math

import numpy as np
from numba import njit

#: Degree of the reference series: the default run's 24 plus 8, so that on the run's own
#: windows the reference's tail is (h/ρ)⁸ below the run's.
REF_DEGREE = 32
#: The reference's error per sub-window as a fraction of the run's local tolerance: the
#: estimate's own error stays three digits below what it estimates.
REF_SHARPNESS = 1e-3
#: The reference's tolerance is never below this many ulps of the state (round-off).
REF_ULPS = 4.0
_EPS = np.finfo(np.float64).eps


@njit(cache=True)
def reference_step(ws, rtol, atol):
    """The reference series' step at its anchor (``ws``: :func:`mbm.tangent.series.workspace`)."""
    # The Taylor step of the reference series at the anchor: Jorba & Zou's rule on the
    # last two coefficients of θ and of every column (the columns converge on the same
    # disc, but near an equilibrium θ's coefficients are tiny while Φ's are not), for an
    # error of REF_SHARPNESS of the local tolerance.
    a, d = ws[0], ws[5]
    eps = reference_eps(a[0], a[1], rtol, atol)
    nt = a.size - 1
    h = math.inf
    for k in (nt - 1, nt):
        c = abs(a[k])
        for i in range(d.shape[0]):
            c = max(c, abs(d[i, k]))
        if c > 0.0:
            h = min(h, (eps / c) ** (1.0 / k))
    return h


@njit(cache=True)
def reference_eps(theta, v, rtol, atol):
    """The reference's error per sub-window at the state (θ, θ')."""
    # θ's scale counts at most half a turn: rtol·|θ| of a far-wound angle is the run's
    # loose criterion, and a reference that loose would drift over a long window.
    scale = max(min(abs(theta), math.pi), abs(v))
    return max(REF_SHARPNESS * (atol + rtol * scale), REF_ULPS * _EPS * max(scale, 1.0))
