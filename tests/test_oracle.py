"""The standing oracle suite: random scenes in every regime against heyoka in long double.

Issue 16's targets, asserted on scenes drawn at random (a fixed seed, so every run is
the same; more under ``-m slow``) from its box β ∈ [0, 3], γ ∈ [−2, 2], ω ∈ [0.2, 5],
θ₀ ∈ [−π, π], θ̇₀ ∈ [−3ω, 3ω], T ∈ [10, 300], the four regimes (β, γ zero or not) in
turn, plus its named cases (the β = 0 example and the fast T = 1 scenes):

* proportionality: the error at rtol = atol = tol (max over 201 outputs of
  |θ − θ_ref| / max(1, |θ_ref|), :func:`oracle_scenes.error`) stays within
  :data:`PROPORTIONALITY_BOUND` × tol, at tol = 1e-4, 1e-8, 1e-12;
* monotonicity: the error at 1e-12 is no larger than at 1e-8, but for the oracle's
  own floor;
* one answer: ``mbm.solve``, ``solve_ivp(method=mbm.MBM, windows_per_step=None)`` and
  ``mbm.solve_batch`` agree bit for bit.

The oracle (``tests/data/oracle_heyoka.py``): heyoka's adaptive Taylor integrator in
80-bit long double at tol 1e-19, checked here against the exact undamped flow.  The
scenes and the error measure: ``tests/data/oracle_scenes.py`` (also the measuring
script behind docs/oracle.md).
"""


import numpy as np
import pytest
from scipy.integrate import solve_ivp

import mbm

import oracle_heyoka  # noqa: E402  tests/data, on pytest's pythonpath
import oracle_scenes  # noqa: E402

pytestmark = pytest.mark.skipif(
    not oracle_heyoka.available(),
    reason="the oracle needs heyoka (the test extra) and an 80-bit long double (x86-64)")

# The scenes: SEED fixes the draw; N_DEFAULT in the default run (a quarter per regime,
# ~8 s here with a warm numba cache), N_SLOW more under -m slow (a different seed, so the
# slow run sees scenes the default one does not).
SEED = 16
N_DEFAULT = 60
SEED_SLOW = 2016
N_SLOW = 1000
TOLS = (1e-4, 1e-8, 1e-12)

# Issue 16's target: the global error within 100× the tolerance on every
# well-conditioned scene.  Measured on 2012 random scenes of this draw (seeds 7 and
# 2016, docs/oracle.md): at most 6.8×, 47×, 46× at 1e-4, 1e-8, 1e-12, but for one
# rotation wound to |θ| ≈ 400 at the round-off floor below (119× at 1e-12; 12.5× since
# the runs hold θ as a winding count and an angle in (−π, π], mbm.core.window "Winding");
# before the a-priori Taylor windows 3.7e4×, 1.4e5×, 1e5×.  A target, not a fit.
PROPORTIONALITY_BOUND = 100.0
# Round-off: each window rounds the state to double (relative eps), and the dynamics
# amplify a perturbation by up to κ (oracle_scenes.conditioning); over n windows that
# is about eps·κ·√n if the roundings were a fair random walk, which no tolerance can
# undercut.  They are not quite (θ grows steadily along a rotation): the worst 1e-12
# errors measured are 0.3-6.8× eps·κ·√n (docs/oracle.md), so the allowance is 10× it.
# It matters only where round-off alone approaches the bound: at 1e-12, rotations
# wound to |θ| ~ 10²-10³ (measured when each window rounded θ to an ulp of |θ|; the
# winding count now keeps that rounding at ulp(π), and the allowance is kept).
ROUNDOFF_ALLOWANCE = oracle_scenes.ROUNDOFF_ALLOWANCE  # 10: applied by oracle_scenes.assert_proportional
# Checked against the exact flow: on the undamped scenes below, heyoka in long double
# at 1e-19 and mbm.pendulum_flow differ by at most 1.1e-14 in the error measure (just
# inside the separatrix over 200 time units, where the flow itself is that sensitive;
# ≤ 4e-15 elsewhere); the bound leaves 9×.
ORACLE_EXACT_BOUND = 1e-13

DEFAULT_SCENES = oracle_scenes.random_scenes(N_DEFAULT, SEED) + oracle_scenes.extra_scenes()
SLOW_SCENES = oracle_scenes.random_scenes(N_SLOW, SEED_SLOW)


def _ids(scenes):
    return [f"{i}-{s.regime}" for i, s in enumerate(scenes)]


def _check_proportional(scene):
    oracle_scenes.assert_proportional(scene, TOLS, PROPORTIONALITY_BOUND)


def _check_monotone(scene):
    oracle_scenes.assert_monotone(scene)


def test_oracle_matches_the_exact_undamped_flow():
    # β = γ = 0: the exact flow (Jacobi elliptic functions in double-double) is the
    # judge of the oracle; libration, near the separatrix, rotation, at several ω.
    for omega, y0, T in ((1.0, (1.0, 0.0), 200.0), (1.0, (0.0, 1.999), 200.0),
                         (1.0, (0.3, 2.5), 200.0), (2.832, (-2.035, 2.661), 208.0),
                         (4.5, (-2.0, -12.0), 50.0)):
        t = np.linspace(0.0, T, 201)
        ref = oracle_heyoka.reference(0.0, 0.0, omega, y0, t)
        exact = mbm.pendulum_flow(mbm.Pendulum(0.0, 0.0, omega), y0, t)
        scale = np.maximum(1.0, np.abs(exact))
        assert np.max(np.abs(ref.astype(float) - exact) / scale) <= ORACLE_EXACT_BOUND, (omega, y0)


def test_oracle_runs_backward():
    t = np.linspace(0.0, -30.0, 61)
    y0 = (1.0, 0.3)
    back = oracle_heyoka.reference(0.0, 0.0, 1.0, y0, t).astype(float)
    exact = mbm.pendulum_flow(mbm.Pendulum(0.0, 0.0), y0, t)
    assert np.max(np.abs(back - exact)) <= ORACLE_EXACT_BOUND


def test_scene_draw_is_fixed_and_covers_every_regime():
    again = oracle_scenes.random_scenes(N_DEFAULT, SEED)
    assert again == DEFAULT_SCENES[:N_DEFAULT]
    regimes = [s.regime for s in DEFAULT_SCENES[:N_DEFAULT]]
    assert all(regimes.count(r) == N_DEFAULT // 4 for r in oracle_scenes.REGIMES)
    for s in DEFAULT_SCENES[:N_DEFAULT]:
        assert (s.beta == 0.0) == (s.regime in ("free", "torqued"))
        assert (s.gamma == 0.0) == (s.regime in ("free", "damped"))
        assert 0.2 <= s.omega <= 5.0 and 10.0 <= s.T <= 300.0 and abs(s.v0) <= 3.0 * s.omega


@pytest.mark.parametrize("scene", DEFAULT_SCENES, ids=_ids(DEFAULT_SCENES))
def test_error_proportional_to_tolerance(scene):
    _check_proportional(scene)


@pytest.mark.parametrize("scene", DEFAULT_SCENES, ids=_ids(DEFAULT_SCENES))
def test_error_monotone_in_tolerance(scene):
    _check_monotone(scene)


@pytest.mark.parametrize("tol", TOLS)
@pytest.mark.parametrize("scene", DEFAULT_SCENES, ids=_ids(DEFAULT_SCENES))
def test_paths_agree_bit_for_bit(scene, tol):
    fast = oracle_scenes.solved(scene, tol)
    model = mbm.Pendulum(scene.beta, scene.gamma, scene.omega)
    ivp = solve_ivp(model, (0.0, scene.T), (scene.theta0, scene.v0), method=mbm.MBM,
                    rtol=tol, atol=tol, t_eval=scene.t_eval, windows_per_step=None)
    assert ivp.success, ivp.message
    np.testing.assert_array_equal(ivp.y, fast.y)


@pytest.mark.parametrize("tol", TOLS)
@pytest.mark.parametrize("which", ["random", "named"])
def test_batch_agrees_bit_for_bit(tol, which):
    # A whole draw in one batch (prange over scenes, the regimes mixed) on a common
    # span: each row equals mbm.solve of its scene.  The named T = 1 scenes on their
    # own span (γ = 1e6 winds to θ ~ 1e8 by t = 30: max_windows).
    scenes, T = (DEFAULT_SCENES[:N_DEFAULT], 30.0) if which == "random" else (
        DEFAULT_SCENES[N_DEFAULT:], 1.0)
    t = np.linspace(0.0, T, oracle_scenes.N_OUTPUT)
    beta, gamma, omega = (np.array([getattr(s, k) for s in scenes]) for k in ("beta", "gamma", "omega"))
    y0 = np.array([(s.theta0, s.v0) for s in scenes])
    batch = mbm.solve_batch(beta, gamma, omega, y0, (0.0, T), t, rtol=tol, atol=tol)
    assert np.all(batch.success), batch.status
    for i, s in enumerate(scenes):
        one = mbm.solve(mbm.Pendulum(s.beta, s.gamma, s.omega), (0.0, T), y0[i], rtol=tol,
                        atol=tol, t_eval=t)
        np.testing.assert_array_equal(batch.y[i], one.y, err_msg=repr(s))
        assert batch.n_windows[i] == one.n_windows


@pytest.mark.slow
@pytest.mark.parametrize("scene", SLOW_SCENES, ids=_ids(SLOW_SCENES))
def test_error_proportional_to_tolerance_slow(scene):
    _check_proportional(scene)


@pytest.mark.slow
@pytest.mark.parametrize("scene", SLOW_SCENES, ids=_ids(SLOW_SCENES))
def test_error_monotone_in_tolerance_slow(scene):
    _check_monotone(scene)
