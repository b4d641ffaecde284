"""Reference locks of driven scenes that mbm's switch rule leaves integrating (item S8).

Writes ``tests/data/lock_watch_reference.json``, read by ``tests/regimes/test_lock_watch.py``.
Independent of mbm: heyoka's Taylor integrator in double precision at tol 1e-15 (the
lock is a property of the attractor, not of one trajectory's last digits, so long
double is not needed; a chaotic trajectory is not reproducible by any integrator).

How it was made (``python tests/data/lock_watch_heyoka.py``; about a minute): each
scene θ'' + βθ' + sin θ = γ + A sin(Ωt) from rest is sampled at the stroboscopic times
kT_d, T_d = 2π/Ω, for PERIODS drive periods.  Over the later half, the samples' winding
rate (turns per drive period, from the two ends) is rounded to the nearest p/q with
q ≤ 12, and the deviations d_k = θ_k − θ_first − 2πkp/q give the lock's ``swing``
(their range; bounded: locked, for the whole later half).  ``period`` is the smallest m
≤ 24 drive periods over which the last RING samples repeat (θ gaining 2πmp/q, θ' the
same) to 1e-8, 0 where none does.  ``lyapunov`` is the largest Lyapunov exponent
(per unit time) from the mid-run state: a displacement of DISPLACEMENT renormalised after
each drive period, over LYAP_PERIODS periods (Benettin's method): positive on a chaotic
orbit, negative on a periodic one (the two exponents sum to −β).
"""

import fractions
import json
import math
import pathlib

import numpy as np

TOL = 1e-15
PERIODS = 20000
RING = 200
LYAP_PERIODS = 2000
DISPLACEMENT = 1e-9
#: name: (β, γ, A, Ω); ω = 1, φ = 0, from (θ, θ') = (0, 0) at t = 0.
SCENES = {
    "slow period one": (0.1791, 0.3014, 2.5938, 1.1541),
    "period six": (0.5015, 0.9636, 0.9397, 1.2613),
    "period eight": (0.4381, 1.3830, 2.6896, 1.2074),
    "period three": (0.4159, 0.8718, 0.7081, 1.2080),
    "chaotic within a step": (0.4905, 0.1659, 1.1984, 0.7083),
    "chaotic, not locked": (0.2, 0.2, 1.0, 1.0),
}


def _integrator(hy, beta, gamma, amp, freq):
    th, v = hy.make_vars("th", "v")
    sys = [(th, v), (v, gamma + amp * hy.sin(freq * hy.time) - beta * v - hy.sin(th))]
    return hy.taylor_adaptive(sys, [0.0, 0.0], tol=TOL)


def _lyapunov(ta, theta, v, t, period):
    # Benettin: a 1e-10 displacement renormalised after every drive period; the mean log
    # growth per unit time over LYAP_PERIODS periods.
    base = np.array([theta, v])
    other = base + np.array([0.0, DISPLACEMENT])
    total = 0.0
    for i in range(LYAP_PERIODS):
        ends = []
        for y in (base, other):
            ta.time = t + i * period
            ta.state[:] = y
            ta.propagate_until(t + (i + 1) * period)
            ends.append(ta.state.copy())
        sep = float(np.hypot(*(ends[1] - ends[0])))
        total += math.log(sep / DISPLACEMENT)
        base = ends[0]
        other = base + (ends[1] - ends[0]) * (DISPLACEMENT / sep)
    return total / (LYAP_PERIODS * period)


def reference(beta, gamma, amp, freq):
    """The lock of one scene (see the module docstring)."""
    import heyoka as hy

    ta = _integrator(hy, beta, gamma, amp, freq)
    period = 2.0 * math.pi / freq
    grid = np.arange(PERIODS + 1) * period
    out = ta.propagate_grid(grid)[5]
    theta, v = out[:, 0], out[:, 1]
    half = theta[PERIODS // 2:]
    k = np.arange(half.size)
    turns = (half[-1] - half[0]) / (2.0 * math.pi * (half.size - 1))
    rate = fractions.Fraction(turns).limit_denominator(12)
    d = half - half[0] - 2.0 * math.pi * float(rate) * k
    m_found = 0
    for m in range(1, 25):
        gain = 2.0 * math.pi * float(rate) * m
        dt = theta[-RING:][m:] - theta[-RING:][:-m] - gain
        dv = v[-RING:][m:] - v[-RING:][:-m]
        if max(np.abs(dt).max(), np.abs(dv).max()) < 1e-8:
            m_found = m
            break
    lyapunov = _lyapunov(ta, theta[PERIODS // 2], v[PERIODS // 2], float(grid[PERIODS // 2]), period)
    return {"beta": beta, "gamma": gamma, "amp": amp, "freq": freq, "p": rate.numerator, "q": rate.denominator,
            "turns": turns, "swing": float(np.ptp(d)), "period": m_found, "lyapunov": lyapunov}


def main():
    refs = {name: reference(*s) for name, s in SCENES.items()}
    path = pathlib.Path(__file__).with_name("lock_watch_reference.json")
    path.write_text(json.dumps(refs, indent=1) + "\n")
    for name, r in refs.items():
        print(f"{name:24s} p/q {r['p']}/{r['q']} swing {r['swing']:.3g} period {r['period']} "
              f"lyapunov {r['lyapunov']:.3g}")


if __name__ == "__main__":
    main()
