"""Regenerate the mpmath reference values for tests/special/test_special.py.

Run from the repository root::

    python tests/data/special_refs.py

It writes ``tests/data/special_refs.json`` (deterministic: fixed grids plus a
seeded ``random.Random``).  Every input is an exact float64 and every
reference is the mpmath value at that exact input, computed with enough
working precision (at least 40 digits, more for m close to 1), then rounded
to float64.

Parameter convention: for m <= 1 the complementary parameter ``mc`` is the
authoritative float64 input and the reference is taken at m = 1 - mc exactly
(the kernels use mc wherever 1 - m matters).  For m > 1 the grid only uses
values with 1 - m exact in float64, so m and mc describe the same number.

mpmath has no Weierstrass function; ℘ is built from the roots (mpmath
polyroots at high precision) as

    ℘(z) = e3 + (e1 - e3) / sn²(sqrt(e1 - e3) z | (e2 - e3)/(e1 - e3)),

in complex arithmetic when the discriminant is negative, and cross-checked
here against the Laurent series at small z and against the differential
equation ℘'² = 4℘³ - g2 ℘ - g3.  The real half-period is the integral
∫_{e_min}^∞ dt / sqrt(4t³ - g2 t - g3) by quadrature.
"""

import json
import math
import os
import random

import mpmath as mp

BASE_DPS = 40
OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "special_refs.json")


def _dps_for(mc):
    """Digits needed so that 1 - mc and the reduction keep ~40 good digits."""
    if mc == 0 or abs(mc) >= 1e-3:
        return BASE_DPS
    return BASE_DPS + int(-math.log10(abs(mc))) + 10


def quarter_period(m, mc):
    """Real quarter period of sn(·|m) (K(m) for m < 1, K(1/m)/sqrt(m) for m > 1)."""
    if mc > 0:
        return mp.ellipk(1 - mp.mpf(mc))
    M = mp.mpf(m)
    return mp.ellipk(1 / M) / mp.sqrt(M)


def ellipj_ref(u, m, mc):
    with mp.workdps(_dps_for(mc) + 10):
        M = 1 - mp.mpf(mc) if mc >= 0 else mp.mpf(m)
        U = mp.mpf(u)
        K = quarter_period(m, mc)
        n = mp.nint(U / (4 * K))
        r = U - 4 * K * n
        s = mp.re(mp.ellipfun("sn", r, m=M))
        c = mp.re(mp.ellipfun("cn", r, m=M))
        d = mp.re(mp.ellipfun("dn", r, m=M))
        a = mp.atan2(s, c)
        if mc >= 0:
            a += 2 * mp.pi * n
        return [float(s), float(c), float(d), float(a)]


def ellipk_ref(mc):
    with mp.workdps(_dps_for(mc)):
        return float(mp.ellipk(1 - mp.mpf(mc)))


def ellipf_ref(phi, m, mc):
    with mp.workdps(_dps_for(mc) + 10):
        M = 1 - mp.mpf(mc) if mc >= 0 else mp.mpf(m)
        return float(mp.re(mp.ellipf(mp.mpf(phi), M)))


# ---------------------------------------------------------------------------
# Weierstrass
# ---------------------------------------------------------------------------


def wp_roots_ref(g2, g3):
    """(e1, e2, e3) as mpc, real ones sorted e1 >= e2 >= e3; for Δ < 0
    e2 is the real root and e1 = conj(e3) has positive imaginary part."""
    G2, G3 = mp.mpf(g2), mp.mpf(g3)
    delta = G2**3 - 27 * G3**2
    if G2 == 0 and G3 == 0:
        return mp.mpf(0), mp.mpf(0), mp.mpf(0), delta
    if delta == 0:
        # Double root: closed form (polyroots converges slowly there).
        c = mp.sqrt(G2 / 12)
        if G3 > 0:
            return 2 * c, -c, -c, delta
        return c, c, -2 * c, delta
    roots = mp.polyroots([4, 0, -G2, -G3], maxsteps=400, extraprec=4 * mp.mp.prec)
    if delta >= 0:
        rr = sorted((mp.re(r) for r in roots), reverse=True)
        return rr[0], rr[1], rr[2], delta
    real = min(roots, key=lambda r: abs(mp.im(r)))
    cplx = [r for r in roots if r is not real]
    e1 = cplx[0] if mp.im(cplx[0]) > 0 else cplx[1]
    e2 = mp.re(real)
    return e1, e2, mp.conj(e1), delta


def wp_mp(z, g2, g3):
    """(℘, ℘') at z from the roots; mpc arithmetic, real parts returned."""
    e1, e2, e3, delta = wp_roots_ref(g2, g3)
    Z = mp.mpf(z)
    if mp.mpf(g2) == 0 and mp.mpf(g3) == 0:
        return 1 / Z**2, -2 / Z**3
    if delta == 0 and e1 == e2:
        # Δ = 0, g3 < 0: hyperbolic degenerate case, m = 1.
        c = e1
        lam = mp.sqrt(3 * c)
        p = c + 3 * c / mp.sinh(lam * Z) ** 2
        pp = -6 * c * lam * mp.cosh(lam * Z) / mp.sinh(lam * Z) ** 3
        return p, pp
    d13 = e1 - e3
    lam = mp.sqrt(d13)
    m = (e2 - e3) / d13
    w = lam * Z
    s = mp.ellipfun("sn", w, m=m)
    c = mp.ellipfun("cn", w, m=m)
    d = mp.ellipfun("dn", w, m=m)
    p = e3 + d13 / s**2
    pp = -2 * lam**3 * c * d / s**3
    return mp.re(p), mp.re(pp)


def wp_laurent(z, g2, g3):
    """Laurent series of ℘ about 0 (DLMF §23.9), first eight terms."""
    Z, G2, G3 = mp.mpf(z), mp.mpf(g2), mp.mpf(g3)
    c = [None, None, G2 / 20, G3 / 28]
    for n in range(4, 10):
        c.append(3 / ((2 * n + 1) * (n - 3)) * sum(c[k] * c[n - k] for k in range(2, n - 1)))
    return 1 / Z**2 + sum(c[k] * Z ** (2 * k - 2) for k in range(2, 10))


def half_period_ref(g2, g3):
    e1, e2, e3, delta = wp_roots_ref(g2, g3)
    emin = e1 if delta >= 0 else e2
    emin = mp.re(emin)
    G2 = mp.mpf(g2)
    c0 = emin**2 - G2 / 4

    def f(s):
        t = emin + s * s
        return 1 / mp.sqrt(t * t + emin * t + c0)

    points = [0, 1, 10, mp.inf]
    if delta < 0 and mp.re(e1) > emin:
        # Near Δ -> 0- the integrand peaks where t = Re e1 (height 1/Im e1).
        points = sorted(set([0, mp.sqrt(mp.re(e1) - emin), 1, 10])) + [mp.inf]
    return mp.quad(f, points)


def build():
    rng = random.Random(20240611)
    mp.mp.dps = BASE_DPS
    data = {"mpmath_version": mp.__version__, "base_dps": BASE_DPS}

    # --- ellipj -----------------------------------------------------------
    params = []
    for k in range(1, 16):
        mc = 10.0 ** (-k)
        params.append((1.0 - mc, mc, "near1"))
    for mc in (1e-20, 1e-50, 1e-300):
        params.append((1.0 - mc, mc, "near1_extreme"))
    for m in (0.0, 1e-12, 1e-6, 0.1, 0.25, 0.5, 0.75, 0.9):
        mc = 1.0 - m
        params.append((1.0 - mc, mc, "regular"))
    for m in (-1e-10, -1e-3, -0.1, -0.5, -1.0, -2.0, -3.7, -5.0):
        mc = 1.0 - m
        params.append((1.0 - mc, mc, "negative"))
    for m in (1.0 + 2.0**-30, 1.0000001, 1.5, 2.0, 3.0, 10.0, 100.0):
        mc = 1.0 - m
        assert mp.mpf(m) + mp.mpf(mc) == 1
        params.append((m, mc, "above1"))
    fracs = [1e-10, 0.05, 0.3, 0.5, 0.7, 0.95, 1.0, 1.2, 1.9, 2.0, 2.6, 3.3, 4.0, 7.7,
             33.3, 123.4, 1000.5, 3333.3, 9999.9]
    rows = {"u": [], "m": [], "mc": [], "region": [], "sn": [], "cn": [], "dn": [], "am": []}
    for m, mc, region in params:
        with mp.workdps(_dps_for(mc) + 10):
            K = float(quarter_period(m, mc))
        for f in fracs:
            for sgn in (1.0, -1.0):
                if f in (1.0, 2.0, 4.0):
                    u = sgn * f * K  # float(K) multiples: lands within an ulp of a zero
                else:
                    u = sgn * f * K * (1.0 + 0.02 * rng.random())
                ref = ellipj_ref(u, m, mc)
                rows["u"].append(u)
                rows["m"].append(m)
                rows["mc"].append(mc)
                rows["region"].append(region + ("_large_u" if f >= 100 else ""))
                for key, val in zip(("sn", "cn", "dn", "am"), ref):
                    rows[key].append(val)
    data["ellipj"] = rows

    # --- ellipk -----------------------------------------------------------
    mcs = [10.0 ** (-k) for k in range(1, 16)] + [1e-20, 1e-100, 1e-300, 0.25, 0.5, 0.75, 1.0,
                                                 1.5, 2.0, 6.0, 101.0, 1e6, 1e20]
    data["ellipk"] = {"mc": mcs, "m": [1.0 - mc for mc in mcs], "K": [ellipk_ref(mc) for mc in mcs]}

    # --- ellipf -----------------------------------------------------------
    rows = {"phi": [], "m": [], "mc": [], "F": []}
    phis = [1e-9, 0.3, 1.0, 1.5, 1.57, 1.5707963, math.pi / 2, 1.58, 2.5, 3.0, 3.2, 4.7, 10.0,
            -0.7, -2.0, 100.3, -1234.5, 31415.9]
    fparams = [(1.0 - 10.0 ** (-k), 10.0 ** (-k)) for k in (1, 3, 6, 9, 12, 15)]
    fparams += [(1.0 - mc, mc) for mc in (1.0, 0.9, 0.5, 0.1, 1.1, 1.5, 3.0, 6.0)]
    for m, mc in fparams:
        for phi in phis:
            rows["phi"].append(phi)
            rows["m"].append(m)
            rows["mc"].append(mc)
            rows["F"].append(ellipf_ref(phi, m, mc))
    for m in (1.0, 1.5, 2.0, 10.0):  # m >= 1 inside the real domain
        mc = 1.0 - m
        edge = math.asin(1.0 / math.sqrt(m))
        for frac in (0.1, 0.5, 0.9, 0.999):
            for sgn in (1.0, -1.0):
                phi = sgn * frac * edge
                rows["phi"].append(phi)
                rows["m"].append(m)
                rows["mc"].append(mc)
                rows["F"].append(ellipf_ref(phi, m, mc))
    data["ellipf"] = rows

    # --- Weierstrass ------------------------------------------------------
    lattices = [
        (4.0, 1.0), (4.0, -1.0), (1.0, 0.0), (10.0, 2.0), (0.5, -0.05),   # Δ > 0
        (3.0, 1.0), (3.0, -1.0), (12.0, 8.0), (12.0, -8.0),                # Δ = 0
        (3.0, 1.0 + 2.0**-40), (3.0, 1.0 - 2.0**-40),                       # Δ -> 0 -/+
        (3.0, -1.0 - 2.0**-40), (3.0, -1.0 + 2.0**-40),
        (-2.0, 1.0), (-2.0, -1.0), (0.0, 1.0), (0.0, -1.0), (1.0, 1.0),     # Δ < 0
        (-4.0, 0.0), (2.0, -3.0), (1e-3, 2e-5), (37.5, -12.25), (0.0, 0.0),
    ]
    rows = {"g2": [], "g3": [], "z": [], "wp": [], "wpp": [], "zfrac": []}
    lat_rows = {"g2": [], "g3": [], "omega": [], "e1": [], "e2": [], "e3": [], "dsign": []}
    # Fractions of ω; 2 ± 1e-6 and 4 + 1e-7 sit next to the poles 2ω, 4ω.
    zfracs = [1e-12, 1e-8, 1e-3, 0.01, 0.3, 0.7, 0.999, 1.0, 1.3, 1.9, 1.99, 2.0 - 1e-6,
              2.0 + 1e-6, 2.01, 3.1, 4.0 + 1e-7, 10.2, 100.7, 1000.3]
    for g2, g3 in lattices:
        e1, e2, e3, delta = wp_roots_ref(g2, g3)
        dsign = 0.0 if delta == 0 else (1.0 if delta > 0 else -1.0)
        finite_period = not (g2 == 0 and g3 == 0) and not (delta == 0 and g3 < 0)
        omega = half_period_ref(g2, g3) if finite_period else mp.inf
        lat_rows["g2"].append(g2)
        lat_rows["g3"].append(g3)
        lat_rows["omega"].append(float(omega) if finite_period else None)
        if delta < 0:
            lat_rows["e1"].append(float(mp.re(e1)))
            lat_rows["e2"].append(float(e2))
            lat_rows["e3"].append(float(mp.im(e1)))
        else:
            lat_rows["e1"].append(float(mp.re(e1)))
            lat_rows["e2"].append(float(mp.re(e2)))
            lat_rows["e3"].append(float(mp.re(e3)))
        lat_rows["dsign"].append(dsign)
        scale = float(omega) if finite_period else 1.0
        for zf in zfracs:
            for sgn in (1.0, -1.0):
                z = sgn * zf * scale
                p, pp = wp_mp(z, g2, g3)
                # Self-checks of the reference itself.
                resid = pp**2 - (4 * p**3 - mp.mpf(g2) * p - mp.mpf(g3))
                assert abs(resid) <= mp.mpf(10) ** (-25) * (abs(4 * p**3) + abs(g2 * p) + abs(g3) + 1)
                if zf <= 1e-3:
                    lau = wp_laurent(z, g2, g3)
                    assert abs(p - lau) <= mp.mpf(10) ** (-25) * abs(lau), (g2, g3, z)
                    assert pp * sgn < 0
                rows["g2"].append(g2)
                rows["g3"].append(g3)
                rows["z"].append(z)
                rows["zfrac"].append(sgn * zf)
                rows["wp"].append(float(p))
                rows["wpp"].append(float(pp))
        if finite_period:
            # Periodicity of the reference: ℘(z + 2ω) = ℘(z).
            z0 = 0.37 * float(omega)
            a = wp_mp(z0, g2, g3)[0]
            with mp.workdps(BASE_DPS):
                b = wp_mp(mp.mpf(z0) + 2 * omega, g2, g3)[0]
            assert abs(a - b) <= mp.mpf(10) ** (-25) * abs(a), (g2, g3)
    data["wp"] = rows
    data["lattice"] = lat_rows

    with open(OUT, "w") as fh:
        json.dump(data, fh, indent=0)
        fh.write("\n")
    print(f"wrote {OUT}: {len(data['ellipj']['u'])} ellipj, {len(data['ellipf']['phi'])} ellipf, "
          f"{len(data['wp']['z'])} wp points")


if __name__ == "__main__":
    build()
