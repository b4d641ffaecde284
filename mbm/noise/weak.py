r"""The splitting's weak order, measured with coupled noise across a step sweep.

A run at step h = 2^L h0 (level L) drives its O steps with the exact OU increments
of one Brownian path shared by all levels: the path's noise is given on intervals of
length δ = h0/2 by deviates η_m, and an O step over [a, b] (a union of such
intervals) adds Σ_m e^{−β(b − t_{m+1})} sqrt(T (1 − e^{−2βδ})) η_m, the exact OU
integral ∫_a^b e^{−β(b−s)} sqrt(2βT) dW(s) composed interval by interval.  Every level
is then the splitting O(h/2) D(h) O(h/2) with the right law, and the levels' outcomes
differ by their discretisation only (common random numbers), so that the weak error
of a coarse level against the next finer one, E f(X_L) − E f(X_{L−1}) = C h_{L−1}^q
(2^q − 1), is measured with a standard error that falls with h.
"""

import math

import numpy as np
from numba import njit, prange

from .flow import P_BETA, P_TEMP, TAYLOR_ORDER, hamiltonian_flow, make_params, substeps
from .kernels import PARALLEL_OPTIONS
from .rng import normal_pair, resolve_seed, scene_key

__all__ = ["coupled_levels_kernel", "weak_order"]


@njit(**PARALLEL_OPTIONS)
def coupled_levels_kernel(p, seed, n, start, h0, levels, fine_steps, plans):
    """cos θ(τ) of ``n`` coupled paths at levels 0 .. levels − 1: an (n, levels) array.

    τ = fine_steps · h0; ``fine_steps`` must be a multiple of 2^(levels − 1);
    ``plans`` (levels, 2): each level's (substeps, degree) of D.
    """
    out = np.empty((n, levels))
    beta = p[P_BETA]
    m_tot = 2 * fine_steps
    delta = 0.5 * h0
    sd = math.sqrt(p[P_TEMP] * -math.expm1(-2.0 * beta * delta))
    decay = math.exp(-beta * delta)
    for i in prange(n):
        b = np.empty(TAYLOR_ORDER + 1)
        sn = np.empty(TAYLOR_ORDER + 1)
        cn = np.empty(TAYLOR_ORDER + 1)
        eta = np.empty(m_tot)
        key = scene_key(seed, i)
        for m in range(0, m_tot, 2):
            eta[m], eta[m + 1] = normal_pair(key, m >> 1)
        for lev in range(levels):
            half = 1 << lev  # intervals in h/2
            h = h0 * half
            plan = (plans[lev, 0], plans[lev, 1])
            theta, v = start[0], start[1]
            m = 0
            t = 0.0
            while True:
                # O over the next `span` intervals (h/2 at the start, then h), exactly
                span = half if m == 0 else 2 * half
                span = min(span, m_tot - m)
                for j in range(span):
                    v = decay * v + sd * eta[m + j]
                m += span
                if t >= fine_steps * h0 - 0.5 * h0:
                    break
                theta, v = hamiltonian_flow(theta, v, t, h, plan, p, (b, sn, cn))
                t += h
            out[i, lev] = math.cos(theta)
    return out


def weak_order(beta=3.0, gamma=0.3, temperature=0.2, *, omega=1.0, start=(2.0, 0.0),
               tau=2.0, h0=0.025, levels=6, n=100000, seed=12345):
    """The splitting's weak order on E cos θ(τ), fitted over a step sweep.

    The scene θ'' + βθ' + ω² sin θ = γ + ξ from ``start``; the defaults (strong
    friction, a short τ) make the O/D commutator's error stand 6–100 standard errors
    above the noise at h = 0.05–0.8 with n = 10^5 (benchmarks/noise.py).

    Returns
    -------
    dict
        ``h`` (levels − 1,) the coarser step of each adjacent pair, ``diff`` E cos θ at
        h minus at h/2, ``stderr`` its standard error, ``order`` the least-squares slope
        of log|diff| against log h, ``n``.
    """
    fine_steps = int(round(tau / h0))
    unit = 1 << (levels - 1)
    fine_steps = unit * max(1, int(round(fine_steps / unit)))
    p = make_params(beta, omega, gamma, 0.0, 0.0, 0.0, 0.0, temperature)
    plans = np.array([substeps(h0 * (1 << lev), omega, abs(gamma), 0.0) for lev in range(levels)],
                     dtype=np.int64)
    f = coupled_levels_kernel(p, np.uint64(resolve_seed(seed)), n, np.asarray(start, float), h0,
                              levels, fine_steps, plans)
    d = f[:, 1:] - f[:, :-1]
    diff = d.mean(axis=0)
    se = d.std(axis=0, ddof=1) / math.sqrt(n)
    h = h0 * 2.0 ** np.arange(1, levels)
    order = float(np.polyfit(np.log(h), np.log(np.abs(diff)), 1)[0])
    return {"h": h, "diff": diff, "stderr": se, "order": order, "n": n}
