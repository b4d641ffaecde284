"""Random pendulum scenes in every regime, and mbm's error on them against the oracle.

The scenes of ``tests/test_oracle.py`` and of the measurements quoted in
``docs/oracle.md`` (run ``python tests/data/oracle_scenes.py --help``).  A scene is
drawn from issue 16's box: β ∈ [0, 3], γ ∈ [−2, 2], ω ∈ [0.2, 5], θ₀ ∈ [−π, π],
θ̇₀ ∈ [−3ω, 3ω], T ∈ [10, 300], with the regime (which of β, γ vanish) taken in turn
so that each has a quarter of the scenes: a continuous draw never makes β or γ
exactly 0, and the conservative regimes are where the controller is tested hardest.
"""

import argparse
import functools
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import oracle_heyoka  # noqa: E402

__all__ = ["REGIMES", "N_OUTPUT", "KAPPA_DELTA", "Scene", "random_scenes", "extra_scenes",
           "DrivenScene", "driven_scenes", "model", "oracle", "oracle_steps", "conditioning", "error", "solve"]

#: The four regimes, in the order the draw cycles through them.
REGIMES = ("free", "torqued", "damped", "damped-torqued")
#: Output times per scene (issue 12's error measure: max |θ − θ_ref| over 201 times).
N_OUTPUT = 201
#: Perturbation of θ₀, θ̇₀ for :func:`conditioning`: small enough that the response is
#: linear (κ·δ ≤ 1e-5 for κ ≤ 1e4), large enough that the long-double oracle resolves
#: it to 1e-8 relative.
KAPPA_DELTA = 1e-9


class Scene(tuple):
    """(beta, gamma, omega, theta0, v0, T, regime): a named tuple without the import."""

    __slots__ = ()
    names = ("beta", "gamma", "omega", "theta0", "v0", "T", "regime")

    def __getattr__(self, name):
        try:
            return self[self.names.index(name)]
        except ValueError:
            raise AttributeError(name) from None

    @property
    def t_eval(self):
        return np.linspace(0.0, self.T, N_OUTPUT)

    #: No AC drive (a :class:`DrivenScene` has one).
    drive = None

    def __repr__(self):
        return ("Scene(beta=%.17g, gamma=%.17g, omega=%.17g, theta0=%.17g, v0=%.17g, T=%.17g, %s)"
                % self)


class DrivenScene(Scene):
    """(beta, gamma, omega, amp, freq, phase, theta0, v0, T, regime): a scene with the AC
    drive A sin(Ωt + φ) added to its torque."""

    __slots__ = ()
    names = ("beta", "gamma", "omega", "amp", "freq", "phase", "theta0", "v0", "T", "regime")

    @property
    def drive(self):
        return (self.amp, self.freq, self.phase)

    def __repr__(self):
        return ("DrivenScene(beta=%.17g, gamma=%.17g, omega=%.17g, amp=%.17g, freq=%.17g, phase=%.17g, "
                "theta0=%.17g, v0=%.17g, T=%.17g, %s)" % self)


def random_scenes(n, seed):
    """``n`` scenes from issue 16's box, the regimes in turn, from ``numpy.random.default_rng(seed)``."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        regime = REGIMES[i % len(REGIMES)]
        beta = 0.0 if regime in ("free", "torqued") else float(rng.uniform(0.0, 3.0))
        gamma = 0.0 if regime in ("free", "damped") else float(rng.uniform(-2.0, 2.0))
        omega = float(rng.uniform(0.2, 5.0))
        theta0 = float(rng.uniform(-math.pi, math.pi))
        v0 = float(rng.uniform(-3.0, 3.0) * omega)
        T = float(rng.uniform(10.0, 300.0))
        out.append(Scene((beta, gamma, omega, theta0, v0, T, regime)))
    return out


def driven_scenes(n, seed):
    """``n`` driven scenes from ``numpy.random.default_rng(seed)``: β ∈ [0, 2], γ ∈ [−1.5, 1.5],
    ω ∈ [0.5, 2], A ∈ [0, 2], Ω ∈ [0.2, 3], φ ∈ [0, 2π), θ₀ ∈ [−π, π], θ̇₀ ∈ [−2ω, 2ω],
    T ∈ [10, 300]; every fourth undamped (β = 0, the hardest for the controller: no
    contraction)."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        beta = 0.0 if i % 4 == 0 else float(rng.uniform(0.0, 2.0))
        gamma = float(rng.uniform(-1.5, 1.5))
        omega = float(rng.uniform(0.5, 2.0))
        amp = float(rng.uniform(0.0, 2.0))
        freq = float(rng.uniform(0.2, 3.0))
        phase = float(rng.uniform(0.0, 2.0 * math.pi))
        theta0 = float(rng.uniform(-math.pi, math.pi))
        v0 = float(rng.uniform(-2.0, 2.0) * omega)
        T = float(rng.uniform(10.0, 300.0))
        out.append(DrivenScene((beta, gamma, omega, amp, freq, phase, theta0, v0, T,
                                "driven" if beta == 0.0 else "damped-driven")))
    return out


def extra_scenes():
    """Issue 16's named cases: its β = 0 example, and the fast T = 1 scenes."""
    return [
        Scene((0.0, -0.680, 2.832, -2.035, 2.661, 208.0, "torqued")),
        Scene((0.0, 1e6, 1.0, 0.0, 0.0, 1.0, "torqued")),
        Scene((0.1, 1e6, 1.0, 0.5, 0.0, 1.0, "damped-torqued")),
        Scene((0.0, 0.0, 1e3, 1.0, 0.0, 1.0, "free")),
        Scene((0.0, 0.3, 1e3, 1.0, 0.0, 1.0, "torqued")),
        Scene((0.1, 0.3, 1e3, 2.0, 500.0, 1.0, "damped-torqued")),
    ]


def oracle(scene):
    """The oracle's θ (long double) at the scene's output times."""
    return oracle_heyoka.reference(scene.beta, scene.gamma, scene.omega,
                                   (scene.theta0, scene.v0), scene.t_eval, drive=scene.drive)[0]


def oracle_steps(scene):
    """The oracle's θ (long double) at the scene's output times, and its step count."""
    y, steps = oracle_heyoka.reference(scene.beta, scene.gamma, scene.omega,
                                       (scene.theta0, scene.v0), scene.t_eval, return_steps=True,
                                       drive=scene.drive)
    return y[0], steps


# The round-off allowance of the proportionality checks (tests/test_oracle.py states
# why and what it was measured against): 10·eps·κ·√n, n windows, κ the outputs'
# sensitivity to the initial state (conditioning below).
ROUNDOFF_ALLOWANCE = 10.0
EPS = float(np.finfo(float).eps)
EPS_ORACLE = float(np.finfo(np.longdouble).eps)


@functools.lru_cache(maxsize=None)
def oracle_with_floor(scene):
    """(θ_ref in long double, κ, the oracle's own floor in the error measure), cached."""
    ref, steps = oracle_steps(scene)
    kappa = conditioning(scene, ref)
    return ref, kappa, ROUNDOFF_ALLOWANCE * EPS_ORACLE * kappa * math.sqrt(steps)


@functools.lru_cache(maxsize=None)
def solved(scene, tol):
    """:func:`solve` at rtol = atol = tol, asserted successful, cached."""
    r = solve(scene, tol)
    assert r.success, (scene, tol, r.message)
    return r


def assert_proportional(scene, tols, bound):
    """The error at each tolerance within ``bound``·tol plus the round-off allowance."""
    ref, kappa, _ = oracle_with_floor(scene)
    for tol in tols:
        r = solved(scene, tol)
        err = error(r.y[0], ref)
        floor = ROUNDOFF_ALLOWANCE * EPS * kappa * math.sqrt(r.n_windows)
        assert err <= bound * tol + floor, (scene, tol, err / tol, floor / tol)


def assert_monotone(scene):
    """The error at 1e-12 no larger than at 1e-8 (up to the oracle's own floor)."""
    ref, _, oracle_floor = oracle_with_floor(scene)
    e8 = error(solved(scene, 1e-8).y[0], ref)
    e12 = error(solved(scene, 1e-12).y[0], ref)
    assert e12 <= e8 + oracle_floor, (scene, e12, e8, oracle_floor)


def conditioning(scene, ref):
    """κ: the largest response max_i |Δθ(t_i)| / δ to a change δ of θ₀ or of θ̇₀ (the oracle's).

    A perturbation e of the state at any time grows to at most about κ·e at the outputs
    (the largest is usually the earliest), so κ·ε·√n bounds the round-off floor of n
    windows that each round the state to a relative ε (a random walk): what a tolerance
    cannot buy below.  Two extra oracle runs.
    """
    k = 0.0
    for d0, d1 in ((KAPPA_DELTA, 0.0), (0.0, KAPPA_DELTA)):
        r = oracle_heyoka.reference(scene.beta, scene.gamma, scene.omega,
                                    (scene.theta0 + d0, scene.v0 + d1), scene.t_eval,
                                    drive=scene.drive)[0]
        k = max(k, float(np.max(np.abs(r - ref))) / KAPPA_DELTA)
    return k


def solve(scene, tol, **kw):
    """``mbm.solve`` of the scene at rtol = atol = ``tol`` (outputs at its t_eval)."""
    import mbm

    return mbm.solve(model(scene), (0.0, scene.T), (scene.theta0, scene.v0), rtol=tol, atol=tol,
                     t_eval=scene.t_eval, **kw)


def model(scene):
    """The scene's ``mbm.Pendulum`` (with its drive, if any)."""
    import mbm

    return mbm.Pendulum(scene.beta, scene.gamma, scene.omega, *(scene.drive or ()))


def error(theta, ref):
    """The error measure: max over the outputs of |θ − θ_ref| / max(1, |θ_ref|).

    With rtol = atol = tol that is the absolute error while |θ| ≤ 1 and the relative
    error beyond (a running or torqued pendulum winds to |θ| ~ 10⁴, where ulp(θ) alone
    is 2e-12); in units of tol it is within a factor 2 of scipy's scale
    atol + rtol·|θ_ref|, and the stricter of the two.  Differenced in long double.
    """
    ref = np.asarray(ref, dtype=np.longdouble)
    d = np.abs(np.asarray(theta, dtype=np.longdouble) - ref)
    return float(np.max(d / np.maximum(1.0, np.abs(ref))))


def _main(argv=None):
    ap = argparse.ArgumentParser(description="mbm's error/tol on random scenes against the oracle")
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--seed", type=int, default=16)
    ap.add_argument("--tols", default="1e-4,1e-8,1e-12")
    ap.add_argument("--out", help="write the per-scene table to this .npz")
    args = ap.parse_args(argv)
    tols = [float(x) for x in args.tols.split(",")]
    scenes = random_scenes(args.n, args.seed) + extra_scenes()
    rows = []
    for sc in scenes:
        ref = oracle(sc)
        row = []
        for tol in tols:
            t0 = time.perf_counter()
            r = solve(sc, tol)
            dt = time.perf_counter() - t0
            e = error(r.y[0], ref)
            row.append((e / tol, r.n_windows, dt, r.status, e))
        rows.append(row)
    a = np.array(rows)  # (scene, tol, 5): error/tol, windows, seconds, status, error
    regimes = np.array([sc.regime for sc in scenes])
    for k, tol in enumerate(tols):
        for reg in REGIMES + ("all",):
            m = np.ones(len(scenes), bool) if reg == "all" else regimes == reg
            e = a[m, k, 0]
            print(f"tol {tol:.0e} {reg:15s} n={m.sum():4d} median {np.median(e):9.3g} "
                  f"p99 {np.percentile(e, 99):9.3g} max {e.max():9.3g}  "
                  f"windows {a[m, k, 1].sum():9.0f}  time {a[m, k, 2].sum():7.3f} s")
    if 1e-12 in tols and 1e-8 in tols:
        e12, e8 = a[:, tols.index(1e-12), 4], a[:, tols.index(1e-8), 4]
        print("non-monotone (error at 1e-12 > error at 1e-8):", int((e12 > e8).sum()))
    worst = np.argsort(-a[:, :, 0].max(axis=1))[:8]
    for i in worst:
        print(scenes[i], a[i, :, 0])
    if args.out:
        np.savez(args.out, table=a, tols=tols, scenes=np.array([tuple(s)[:6] for s in scenes]),
                 regimes=regimes)


if __name__ == "__main__":
    _main()
