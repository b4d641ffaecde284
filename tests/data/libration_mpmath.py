"""The period of a conservative libration by mpmath, for tests/regimes/test_libration.py.

θ'' + ω² sin θ = γ (β = 0, |γ| < ω²): H = θ'²/2 − ω² cos θ − γθ is constant and a
state trapped in a well librates between the turning points θ₋ < θ₊ (V(θ±) = H),
with period T = 2∫ dθ / sqrt(2(H − V(θ))).  Here the turning points are found by
bisection and Newton inside the well's brackets and the integral, after θ = m + r sin ψ
(which removes the endpoint singularities), by mpmath's tanh-sinh quadrature, at
DPS digits: independent of mbm's double-double midpoint rule (mbm.regimes, C2).

Run as a script it prints the periods of a few scenes.
"""

import mpmath as mp

__all__ = ["DPS", "period_mp"]

# Working digits: the double-double period carries ~30; 60 leave the reference's own
# error (turning points, quadrature) far below it.
DPS = 60


def _root(f, df, inside, outside):
    # f > 0 at ``inside``, < 0 at ``outside``: bisection to a few digits, Newton to DPS.
    a, b = mp.mpf(inside), mp.mpf(outside)
    for _ in range(60):
        mid = (a + b) / 2
        if f(mid) > 0:
            a = mid
        else:
            b = mid
    x = (a + b) / 2
    for _ in range(12):
        x = x - f(x) / df(x)
    return x


def period_mp(gamma, omega, theta, v, dps=DPS):
    """The period of the libration through (θ, θ'), or None if the state is not trapped.

    Parameters
    ----------
    gamma, omega : float
        Torque and ω (|γ| < ω²).
    theta, v : float
        The state (taken exactly as the doubles given).
    dps : int, optional
        mpmath digits.

    Returns
    -------
    mpmath.mpf or None
    """
    with mp.workdps(dps):
        g, w2 = mp.mpf(gamma), mp.mpf(omega) ** 2
        th, vv = mp.mpf(theta), mp.mpf(v)
        d = mp.asin(g / w2)

        def V(x):
            return -w2 * mp.cos(x) - g * x

        H = vv**2 / 2 + V(th)
        k = mp.floor((th + d + mp.pi) / (2 * mp.pi))
        c = d + 2 * k * mp.pi
        right, left = c - 2 * d + mp.pi, c - 2 * d - mp.pi  # the saddles of the well
        if not (left < th < right) or H >= min(V(left), V(right)):
            return None

        def f(x):
            return H - V(x)

        def df(x):
            return g - w2 * mp.sin(x)

        xp = _root(f, df, c, right)
        xm = _root(f, df, c, left)
        m, r = (xp + xm) / 2, (xp - xm) / 2

        def integrand(psi):
            return r * mp.cos(psi) / mp.sqrt(2 * f(m + r * mp.sin(psi)))

        return 2 * mp.re(mp.quad(integrand, [-mp.pi / 2, 0, mp.pi / 2]))


if __name__ == "__main__":
    for scene in [(0.4, 1.0, 0.9, 0.0), (0.0, 1.0, 1.0, 0.0), (-0.3, 2.0, 0.1, 1.5)]:
        print(scene, mp.nstr(period_mp(*scene), 40))
