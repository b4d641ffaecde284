"""mpmath references for the exact pendulum flow, mbm.special.pendulum_flow, and the
approximants of mbm.approximants.belendez2007 (the third paper, Beléndez et al. 2007).

Everything is computed from the *exact* binary values of the float inputs at
high precision (``DPS`` digits), independently of the numba code: the libration
uses ``mpmath.ellipfun`` (theta-function based) and ``mpmath.ellipf``/``ellipk``,
the rotation the same with parameter 1/m, the separatrix the closed form.  The
elliptic formulas are cross-checked against a Taylor integration of the ODE
(``mpmath.odefun``) by :func:`crosscheck_odefun` when this file is run.

Run ``python tests/data/belendez2007_mpmath.py`` to regenerate
``belendez2007_reference.npz`` (a few seconds).
"""

import os
import sys

import mpmath as mp
import numpy as np

# Working precision: m can be 1 − 1e-33 (θ₀ = float π) and u up to ~1e7, so 60
# digits leave > 25 digits after the cancellations in mc and in the reduction.
DPS = 60

HERE = os.path.dirname(os.path.abspath(__file__))
REFERENCE_FILE = os.path.join(HERE, "belendez2007_reference.npz")


def _setup(theta0, v0, omega):
    th0, v, w = mp.mpf(theta0), mp.mpf(v0), mp.mpf(omega)
    j = mp.nint(th0 / (2 * mp.pi))
    th = th0 - 2 * mp.pi * j
    h = th / 2
    sh, ch = mp.sin(h), mp.cos(h)
    ws = v / (2 * w)
    m = sh**2 + ws**2
    mc = ch**2 - ws**2
    return th0, v, w, j, th, h, sh, ch, ws, m, mc


def flow_mp(theta0, v0, omega, t, dps=DPS):
    """Exact state (θ(t), θ'(t)) of θ'' + ω² sin θ = 0 from (θ₀, θ̇₀), as mpf."""
    with mp.workdps(dps):
        th0, v, w, j, th, h, sh, ch, ws, m, mc = _setup(theta0, v0, omega)
        t = mp.mpf(t)
        if mc > 0:
            k = mp.sqrt(m)
            if k == 0:
                return th0, mp.mpf(0)
            u0 = mp.ellipf(mp.atan2(sh, ws), m)
            K = mp.ellipk(m)
            u = w * t + u0
            n = mp.nint(u / (2 * K))
            r = u - 2 * K * n
            sn = mp.ellipfun("sn", r, m=m)
            cn = mp.ellipfun("cn", r, m=m)
            dn = mp.ellipfun("dn", r, m=m)
            if n % 2:
                sn, cn = -sn, -cn
            theta = 2 * mp.atan2(k * sn, dn) + 2 * mp.pi * j
            return theta, 2 * k * w * cn
        if mc < 0:
            k = mp.sqrt(m)
            p = 1 / m
            s = mp.sign(v)
            u0 = mp.ellipf(h, p)
            K = mp.ellipk(p)
            u = s * k * w * t + u0
            n = mp.nint(u / (2 * K))
            r = u - 2 * K * n
            sn = mp.ellipfun("sn", r, m=p)
            cn = mp.ellipfun("cn", r, m=p)
            dn = mp.ellipfun("dn", r, m=p)
            theta = 2 * (mp.atan2(sn, cn) + n * mp.pi) + 2 * mp.pi * j
            return theta, 2 * s * w * k * dn
        if v == 0:
            return th0, mp.mpf(0)
        s = mp.sign(v)
        u = w * t + mp.asinh(s * sh / ch)
        return 2 * s * mp.atan(mp.sinh(u)) + 2 * mp.pi * j, 2 * s * w / mp.cosh(u)


def period_mp(theta0, v0, omega, dps=DPS):
    """(26) T = 4K(m)/ω (libration), 2K(1/m)/(√m ω) (rotation), inf otherwise."""
    with mp.workdps(dps):
        th0, v, w, j, th, h, sh, ch, ws, m, mc = _setup(theta0, v0, omega)
        if mc > 0:
            return 4 * mp.ellipk(m) / w
        if mc < 0:
            return 2 * mp.ellipk(1 / m) / (mp.sqrt(m) * w)
        return mp.inf


def crosscheck_odefun(theta0, v0, omega, ts, dps=30):
    """Max |θ_elliptic − θ_taylor| over ``ts`` (t ≥ 0, short horizons)."""
    with mp.workdps(dps):
        w2 = mp.mpf(omega) ** 2
        f = mp.odefun(lambda t, y: [y[1], -w2 * mp.sin(y[0])], 0, [mp.mpf(theta0), mp.mpf(v0)])
        err = mp.mpf(0)
        for t in ts:
            a = f(mp.mpf(t))
            b = flow_mp(theta0, v0, omega, t, dps=dps + 10)
            err = max(err, abs(a[0] - b[0]), abs(a[1] - b[1]))
        return err


def harmonic_error_mp(amplitude, npts=400, dps=30):
    """max over a period of |θ_exact − θ₀ cos(ω t)|, θ₀ = amplitude (turning point).

    (31) against (32)-(33), ω₀ = 1.  The maximum is located on an ``npts`` grid
    over a quarter period (the error is even about t = 0 and odd about T/4) and
    refined with a golden-section search.
    """
    with mp.workdps(dps):
        a = mp.mpf(amplitude)
        m = mp.sin(a / 2) ** 2
        K = mp.ellipk(m)
        om = mp.pi / (2 * K)

        def err(t):
            exact = 2 * mp.asin(mp.sin(a / 2) * mp.ellipfun("sn", K - t, m=m))  # (31)
            return abs(exact - a * mp.cos(om * t))  # (32)

        ts = [K * i / npts for i in range(npts + 1)]
        vals = [err(t) for t in ts]
        i = max(range(len(vals)), key=lambda q: vals[q])
        lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, npts)]
        g = (mp.sqrt(5) - 1) / 2
        for _ in range(60):
            c, d = hi - g * (hi - lo), lo + g * (hi - lo)
            if err(c) > err(d):
                hi = d
            else:
                lo = c
        return max(vals[i], err((lo + hi) / 2))


# --- reference cases (θ₀, θ̇₀, ω) and their time grids ----------------------------

# The accuracy-target cases: libration at 0.99π, rotation at 2.5ω, near-separatrix
# libration at 2ω(1 − 1e-6), ω ∈ {1, 3}; 0 ≤ t ≤ 100.
GOAL_CASES = [
    (0.99 * np.pi, 0.0, 1.0),
    (0.99 * np.pi, 0.0, 3.0),
    (0.0, 2.5 * 1.0, 1.0),
    (0.0, 2.5 * 3.0, 3.0),
    (0.0, 2.0 * 1.0 * (1.0 - 1e-6), 1.0),
    (0.0, 2.0 * 3.0 * (1.0 - 1e-6), 3.0),
]
# Off-turning-point anchors, large θ₀, negative θ̇₀, near-separatrix rotation.
EXTRA_CASES = [
    (1.234, -0.7, 1.0),
    (-2.9, 0.11, 2.0),
    (1000.0 * np.pi + 3.0, -0.2, 1.0),
    (2e5 * np.pi + 0.4, 0.3, 1.0),
    (-20.0, 3.3, 1.5),
    (0.3, -2.0 * (1.0 + 1e-6), 1.0),
    (np.pi, 0.0, 1.0),
    # Off-turning-point libration next to the separatrix (mc ≈ 1.9e-6), where
    # the phase u0 is computed from the complementary form ±(K − v).
    (3.1, 0.0415, 1.0),
    (-3.1, 0.0415, 1.0),
    # ... and the direct form at mc ≈ 1e-10.
    (2.0, 2.0 * np.cos(1.0) * (1.0 - 1e-10), 1.0),
    # Either side of the switch between the two forms, cos²(θ₀/2) = √mc
    # (cos(θ₀/2) = 0.01, mc = 1e-8 (1 ∓ 1e-2)).
    (2.0 * np.arccos(0.01), 2.0 * np.sqrt(1e-4 - 1e-8 * (1.0 - 1e-2)), 1.0),
    (2.0 * np.arccos(0.01), -2.0 * np.sqrt(1e-4 - 1e-8 * (1.0 + 1e-2)), 1.0),
]
GOAL_T = np.linspace(0.0, 100.0, 201)[1:]
EXTRA_T = np.concatenate([-np.linspace(0.0, 40.0, 41)[1:], np.linspace(0.0, 40.0, 41)[1:]])
# Long horizon (1e6) around which the phase is checked.
LONG_T = np.array([1e6 - 0.5, 1e6 - 0.25, 1e6, 1e6 + 0.125, 1e6 + 0.3])

# Separatrix approach θ̇₀ = 2ω(1 ± 10^-e), e = 1..12, and exactly 2ω, ω = 1.
SEP_EXPONENTS = np.arange(1, 13)
SEP_T = np.array([-3.0, -1.0, 0.5, 1.0, 2.0, 4.0, 6.0])

# The paper's claim: amplitudes (rad) at which the harmonic error is pinned.
HARMONIC_AMPLITUDES = np.array([0.1, 0.25, 0.5, 0.75, 0.9, 0.99]) * np.pi


def _grid(cases, ts):
    th = np.empty((len(cases), len(ts)))
    v = np.empty_like(th)
    for i, (a, b, w) in enumerate(cases):
        for q, t in enumerate(ts):
            x, y = flow_mp(a, b, w, t)
            th[i, q], v[i, q] = float(x), float(y)
    return th, v


def main():
    out = {}
    out["goal_cases"] = np.array(GOAL_CASES)
    out["goal_t"] = GOAL_T
    out["goal_theta"], out["goal_v"] = _grid(GOAL_CASES, GOAL_T)
    out["extra_cases"] = np.array(EXTRA_CASES)
    out["extra_t"] = EXTRA_T
    out["extra_theta"], out["extra_v"] = _grid(EXTRA_CASES, EXTRA_T)
    out["long_t"] = LONG_T
    out["long_theta"], out["long_v"] = _grid(GOAL_CASES, LONG_T)
    sep_cases = [(0.0, 2.0, 1.0)]
    for e in SEP_EXPONENTS:
        sep_cases.append((0.0, 2.0 * (1.0 - 10.0 ** -float(e)), 1.0))
        sep_cases.append((0.0, 2.0 * (1.0 + 10.0 ** -float(e)), 1.0))
    out["sep_cases"] = np.array(sep_cases)
    out["sep_t"] = SEP_T
    out["sep_theta"], out["sep_v"] = _grid(sep_cases, SEP_T)
    out["period_cases"] = np.array(GOAL_CASES + EXTRA_CASES)
    out["period"] = np.array([float(period_mp(*c)) for c in GOAL_CASES + EXTRA_CASES])
    out["harmonic_amplitudes"] = HARMONIC_AMPLITUDES
    out["harmonic_max_error"] = np.array([float(harmonic_error_mp(a)) for a in HARMONIC_AMPLITUDES])
    np.savez(REFERENCE_FILE, **out)
    # Independent check of the elliptic formulas against a Taylor integration.
    for c in GOAL_CASES[:1] + GOAL_CASES[2:3] + GOAL_CASES[4:5] + EXTRA_CASES[:4]:
        e = crosscheck_odefun(*c, ts=[0.5, 1.7, 3.0])
        print(f"odefun cross-check {c}: {mp.nstr(e, 3)}")
        if e > 1e-20:
            sys.exit(f"elliptic reference disagrees with odefun for {c}: {e}")
    print("wrote", REFERENCE_FILE)


if __name__ == "__main__":
    main()
