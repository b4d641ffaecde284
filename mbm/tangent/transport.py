r"""The tangent pass: error transport and sensitivities along a run's windows.

A run of the moving boundary method takes windows [t_n, t_{n+1}], each anchored at the
state y_n it reached.  Along each window this pass integrates the exact equation from
y_n by a Taylor series of degree :data:`REF_DEGREE` (sub-windows where the window is
longer than that series' step at :data:`REF_SHARPNESS` of the tolerance), together with
its variational columns (:mod:`mbm.tangent.series`).  That gives, per window,

* the signed local error d_n = y_{n+1} − φ(t_{n+1}; y_n) of what the run computed
  (whatever formed y_{n+1}: a Taylor window, a splitting, the locked closed form, a
  stored period: each regime's error enters as its windows' local errors),
* the tangent map Φ_n = ∂φ(t_{n+1}; y_n)/∂y_n and the parameter columns P_n,

and the linearised transport of the error and of the sensitivities S = ∂y/∂(y₀, p):

    e_{n+1} = Φ_n e_n + d_n,        S_{n+1} = Φ_n S_n + P_n,

with the same inside a window at every output time (the output's own difference from
the exact flow in place of d_n).  e estimates y_computed − y_true to first order; it is
only first order where Φ varies across the error's size (near a separatrix, on a
chaotic orbit once e is no longer small: :doc:`/theory/error_estimate`).
"""

import collections
import math

import numpy as np
from numba import njit

from .series import COL_THETA0, COL_V0, tangent_series, value_rate

#: Degree of the reference series: the default run's 24 plus 8, so that on the run's own
#: windows the reference's tail is (h/ρ)⁸ below the run's.
REF_DEGREE = 32
#: The reference's error per sub-window as a fraction of the run's local tolerance: the
#: estimate's own error stays three digits below what it estimates.
REF_SHARPNESS = 1e-3
#: The reference's tolerance is never below this many ulps of the state (round-off).
REF_ULPS = 4.0

_TWO_PI = 2.0 * math.pi
_EPS = np.finfo(np.float64).eps

#: The run a pass follows: the window ends ``t`` (n + 1,) and states ``y`` (n + 1, 2) and
#: the outputs ``t_out`` (m,) and ``y_out`` (2 or 3 rows, m) at which to report.
Track = collections.namedtuple("Track", ("t", "y", "t_out", "y_out"))

#: Where the pass writes: ``err`` (2, m) and ``sens`` (n_sens, 2, m); ``rows`` (n_sens,):
#: each sensitivity's row in the series' columns (0: θ₀'s, 1: θ̇₀'s, ≥ 2: a parameter's).
Report = collections.namedtuple("Report", ("err", "sens", "rows"))


@njit(cache=True)
def _reference_step(ws, rtol, atol):
    # The Taylor step of the reference series at the anchor: Jorba & Zou's rule on the
    # last two coefficients of θ and of every column (the columns converge on the same
    # disc, but near an equilibrium θ's coefficients are tiny while Φ's are not), for an
    # error of REF_SHARPNESS of the local tolerance.
    a, d = ws[0], ws[5]
    # θ's scale counts at most half a turn: rtol·|θ| of a far-wound angle is the run's
    # loose criterion, and a reference that loose would drift over a long window.
    scale = max(min(abs(a[0]), math.pi), abs(a[1]))
    eps = max(REF_SHARPNESS * (atol + rtol * scale), REF_ULPS * _EPS * max(scale, 1.0))
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
def _columns_at(ws, s, rows, e, S, out_e, out_s):
    # Φ(s)·e into out_e, Φ(s)·S + P(s) into out_s, and the reference state ŷ(s).
    a, d = ws[0], ws[5]
    p00, p10 = value_rate(d[0], s)
    p01, p11 = value_rate(d[1], s)
    out_e[0] = p00 * e[0] + p01 * e[1]
    out_e[1] = p10 * e[0] + p11 * e[1]
    for i in range(rows.size):
        x0 = p00 * S[0, i] + p01 * S[1, i]
        x1 = p10 * S[0, i] + p11 * S[1, i]
        if rows[i] >= 2:
            q0, q1 = value_rate(d[rows[i]], s)
            x0 += q0
            x1 += q1
        out_s[0, i] = x0
        out_s[1, i] = x1
    return value_rate(a, s)


@njit(cache=True)
def _wrapped(dtheta):
    # A difference of angles, to the nearest turn (the outputs may be θ wrapped).
    return dtheta - _TWO_PI * round(dtheta / _TWO_PI)


@njit(cache=True)
def transport(sc, codes, track, tol, report, ws):
    """Error transport and sensitivities along a run (module docstring).

    Parameters
    ----------
    sc : tuple of 6 floats
        (β, γ, ω, A, Ω, φ).
    codes : int64 array
        The series' columns: θ₀'s and θ̇₀'s (Φ), then the parameters' (``COL_*``).
    track : Track
    tol : (float, float, float)
        The run's (rtol, atol), and the time until which its windows' local errors are
        measured (± inf: all or none).
    report : Report
        Filled for the outputs reached.
    ws : tuple
        :func:`mbm.tangent.series.workspace` of degree REF_DEGREE and len(codes) columns.

    Returns
    -------
    int
        Sub-windows taken, or −1 where a reference step failed (a non-finite state).
    """
    wt, wy, te, yo = track
    err, sens, rows = report
    rtol, atol, t_measured = tol
    m, ns = te.size, rows.size
    e = np.zeros(2)
    S = np.zeros((2, ns))
    for i in range(ns):
        S[0, i] = 1.0 if rows[i] == COL_THETA0 else 0.0
        S[1, i] = 1.0 if rows[i] == COL_V0 else 0.0
    e2 = np.empty(2)
    S2 = np.empty((2, ns))
    direction = 1.0 if wt[wt.size - 1] >= wt[0] else -1.0
    j = 0
    while j < m and te[j] == wt[0]:
        err[:, j] = 0.0
        sens[:, :, j] = S.T
        j += 1
    n_sub = 0
    for n in range(wt.size - 1):
        tb = wt[n + 1]
        ts, x0, x1 = wt[n], wy[n, 0], wy[n, 1]
        while True:
            tangent_series(sc, ts, x0, x1, codes, ws)
            hs = _reference_step(ws, rtol, atol)
            if not hs > 0.0:
                return -1
            n_sub += 1
            last = hs >= direction * (tb - ts)
            t_sub = tb if last else ts + direction * hs
            while j < m and direction * (te[j] - t_sub) <= 0.0:
                th, v = _columns_at(ws, te[j] - ts, rows, e, S, e2, S2)
                err[0, j] = e2[0]
                err[1, j] = e2[1]
                if direction * (t_measured - wt[n]) > 0.0:
                    err[0, j] += _wrapped(yo[0, j] - th)
                    err[1, j] += yo[1, j] - v
                sens[:, :, j] = S2.T
                j += 1
            x0, x1 = _columns_at(ws, t_sub - ts, rows, e, S, e2, S2)
            e[:] = e2
            S[:, :] = S2
            ts = t_sub
            if last:
                break
        if direction * (t_measured - wt[n]) > 0.0:
            e[0] += _wrapped(wy[n + 1, 0] - x0)
            e[1] += wy[n + 1, 1] - x1
    return n_sub
