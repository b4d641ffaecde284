r"""The tangent pass on the windows of the regimes that stop integrating.

A regime's window is long: the locked closed form to t_bound, or a stored period repeated.
The general reference (:func:`mbm.tangent.transport._reference_window`) would integrate
all of it.  Here:

* **locked** (L1–L7): the reference runs only until the state has settled so close to the
  equilibrium θ* that the nonlinearity is below the reference's own tolerance
  (ω²·|x|² ≤ ε, x the deviation); from there the flow, its tangent map and the parameter
  columns are the linear ones, δ' = J δ + b with J = [[0, 1], [−ω_l², −β]] and
  ω_l² = ω² cos θ*, in closed form: e^{Js} and J⁻¹(e^{Js} − I) b.
* **a stored period** T (a running cycle or a libration, R3; a phase-locked orbit, S6):
  the reference runs one period from the window's start, storing its sub-windows' series
  and the cumulative map at each; later periods are the same map (Floquet):
  e_{k+1} = M e_k + d_T, S_{k+1} = M S_k + P_T, with M = Φ(T) and d_T the period's local
  error, and inside a period Φ(s) and P(s) are looked up.  (∂/∂Ω's forcing A t cos(Ωt + φ)
  is not periodic: a phase-locked window with that column takes the general reference.)
"""

import math

import numpy as np
from numba import njit

from ..compile.jit import INLINE
from .reference import reference_step
from .series import tangent_series, value_rate

#: Sub-windows one stored period may take; past it the window takes the general reference.
PERIOD_SUBWINDOWS = 4096

_TWO_PI = 2.0 * math.pi


@njit(cache=True)
def expm2(wl2, beta, s):
    """e^{Js} of J = [[0, 1], [−wl2, −β]], as (E00, E01, E10, E11)."""
    mu = 0.5 * beta
    disc = mu * mu - wl2
    if disc < 0.0:
        w = math.sqrt(-disc)
        c, sw = math.cos(w * s), math.sin(w * s) / w
    elif disc > 0.0:
        w = math.sqrt(disc)
        c, sw = math.cosh(w * s), math.sinh(w * s) / w
    else:
        c, sw = 1.0, s
    f = math.exp(-mu * s)
    # e^{Js} = e^{−μs} [c I + sw (J + μ I)]
    return f * (c + mu * sw), f * sw, -f * wl2 * sw, f * (c - mu * sw)


@njit(cache=True)
def linear_forcing(code, sc, theta_star):
    """The constant b of parameter column ``code`` at the equilibrium (θ' = 0 there)."""
    if code == 3:  # γ
        return 1.0
    if code == 4:  # ω
        return -2.0 * sc[2] * math.sin(theta_star)
    return 0.0


@njit(cache=True)
def linear_columns(E, wl2, beta, b):
    """J⁻¹(e^{Js} − I)(0, b): a parameter column of the linear flow from zero."""
    # J⁻¹ = (1/ω_l²) [[−β, −1], [ω_l², 0]]
    u0 = E[1] * b
    u1 = (E[3] - 1.0) * b
    return (-beta * u0 - u1) / wl2, u0


@njit(cache=True)
def period_store(n_cols, nt):
    """Arrays for one stored period: sub-window starts, θ's and the columns' series, and the
    cumulative e-map (2, 2) and parameter columns (2, n_cols) at each start."""
    k = PERIOD_SUBWINDOWS
    return (np.empty(k + 1), np.empty((k, nt + 1)), np.empty((k, n_cols, nt + 1)), np.empty((k, 2, 2)),
            np.empty((k, 2, n_cols)))


@njit(cache=True)
def period_map(sc, codes, ws, start, span, store):
    """Fill ``store`` over one period span.t1 − span.t0 from ``start`` = (t, θ, θ') by the
    reference; returns the sub-windows taken (−1: too many, or a non-finite state)."""
    starts, pa, pd, cum, pcol = store
    rtol, atol = span.tol
    t0, t1, direction = span.t0, span.t1, span.direction
    ts, x0, x1 = t0, start[1], start[2]
    nc = codes.size
    phi = np.eye(2)
    pc = np.zeros((2, nc))
    i = 0
    while True:
        if i == PERIOD_SUBWINDOWS:
            return -1
        tangent_series(sc, ts, x0, x1, codes, ws)
        hs = reference_step(ws, rtol, atol)
        if not hs > 0.0:
            return -1
        starts[i] = ts - t0
        pa[i] = ws[0]
        pd[i] = ws[5]
        cum[i] = phi
        pcol[i] = pc
        last = hs >= direction * (t1 - ts)
        t_sub = t1 if last else ts + direction * hs
        phi, pc = _compose(ws[5], t_sub - ts, phi, pc, codes)
        x0, x1 = value_rate(ws[0], t_sub - ts)
        ts = t_sub
        i += 1
        if last:
            starts[i] = t1 - t0
            return i


@njit(cache=True)
def _compose(d, s, phi, pc, codes):
    # The cumulative (Φ, P) after a sub-window whose columns' series are d, at s.
    p00, p10 = value_rate(d[0], s)
    p01, p11 = value_rate(d[1], s)
    out = (np.empty((2, 2)), np.empty_like(pc))
    _compose_into((p00, p10, p01, p11), d, s, (phi, pc), codes, out)
    return out


@njit(**INLINE)
def _compose_into(step, d, s, cum, codes, out):
    # out = (Φ, P) after a sub-window whose Φ(s) is ``step`` = (p00, p10, p01, p11) and whose
    # columns' series are d, from the cumulative ``cum`` = (Φ, P) at its start.
    p00, p10, p01, p11 = step
    phi, pc = cum
    new_phi, new_pc = out
    new_phi[0, 0] = p00 * phi[0, 0] + p01 * phi[1, 0]
    new_phi[0, 1] = p00 * phi[0, 1] + p01 * phi[1, 1]
    new_phi[1, 0] = p10 * phi[0, 0] + p11 * phi[1, 0]
    new_phi[1, 1] = p10 * phi[0, 1] + p11 * phi[1, 1]
    for c in range(codes.size):
        x0 = p00 * pc[0, c] + p01 * pc[1, c]
        x1 = p10 * pc[0, c] + p11 * pc[1, c]
        if c >= 2:
            q0, q1 = value_rate(d[c], s)
            x0 += q0
            x1 += q1
        new_pc[0, c] = x0
        new_pc[1, c] = x1


@njit(cache=True)
def period_at(store, n_sub, s, codes, out):
    """(θ̂(s), θ̂'(s)) at phase s of the stored period (0 ≤ s ≤ its length), and its
    (Φ(s), P(s)) into ``out`` = ((2, 2), (2, n_cols)) arrays."""
    starts, pa, pd, cum, pcol = store
    lo, hi = 0, n_sub - 1
    while lo < hi:  # the last sub-window starting at or before s
        mid = (lo + hi + 1) // 2
        if starts[mid] <= s:
            lo = mid
        else:
            hi = mid - 1
    u = s - starts[lo]
    # θ and Φ's two columns by Horner side by side (value_rate's operations each).
    n = pa.shape[1] - 1
    tp, p0, p1 = pa[lo, n], pd[lo, 0, n], pd[lo, 1, n]
    tq, q0, q1 = 0.0, 0.0, 0.0
    for k in range(n - 1, -1, -1):
        tq = tq * u + tp
        tp = tp * u + pa[lo, k]
        q0 = q0 * u + p0
        p0 = p0 * u + pd[lo, 0, k]
        q1 = q1 * u + p1
        p1 = p1 * u + pd[lo, 1, k]
    _compose_into((p0, q0, p1, q1), pd[lo], u, (cum[lo], pcol[lo]), codes, out)
    return tp, tq
