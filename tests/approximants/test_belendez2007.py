"""Tests of the exact pendulum flow (third paper, Beléndez et al. 2007, Eqs. (23), (26),
(31)) generalized to any state (mbm.special.pendulum_flow), the period (26), and the
approximants of mbm.approximants.belendez2007: "belendez" and the harmonic approximation
(32)-(33).  The double-double K and sin/cos the flow relies on are tested in
tests/special/test_special.py.

References come from ``tests/data/belendez2007_mpmath.py`` (mpmath at 60 digits from
the exact binary inputs, cross-checked there against a Taylor integration of the ODE)
and are stored in ``tests/data/belendez2007_reference.npz``.
"""

import math

import mpmath as mp
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mbm.approximants import ApproximantDomainError, get_approximant
from mbm.model import Pendulum
from mbm.special.pendulum_flow import (
    REGIME_LIBRATION,
    REGIME_ROTATION,
    REGIME_SEPARATRIX,
    flow_setup_kernel,
    pendulum_flow,
    pendulum_flow_kernel,
    period,
    period_kernel,
)

from mbm.special.pendulum_flow_table import flow_table_point_kernel

import belendez2007_mpmath as refmod  # noqa: E402  tests/data, on pytest's pythonpath

# Accuracy target for t <= 100 against mpmath (θ and θ').
GOAL_ATOL = 1e-12
# Long horizon: phase error <= 1e-9 at t = 1e6 (θ error <= 1e-9 is stricter for |θ'| >= 1).
LONG_ATOL = 1e-9
# Energy E = θ'²/2 + 2ω² sin²(θ/2) along the flow, relative.
ENERGY_RTOL = 1e-13

_F = pendulum_flow_kernel


@pytest.fixture(scope="module")
def ref():
    with np.load(refmod.REFERENCE_FILE) as data:
        return dict(data)


def _flow(case, ts):
    out = np.array([_F(case[0], case[1], case[2], t) for t in ts])
    return out[:, 0], out[:, 1]


def _errors(ref, prefix, cases_key, t_key):
    out = []
    for i, case in enumerate(ref[cases_key]):
        th, v = _flow(case, ref[t_key])
        out.append((tuple(case), np.max(np.abs(th - ref[prefix + "_theta"][i])),
                    np.max(np.abs(v - ref[prefix + "_v"][i]))))
    return out


EPS = np.finfo(float).eps


def _energy(th, v, w):
    return 0.5 * v * v + 2.0 * w * w * np.sin(0.5 * th) ** 2


# --------------------------------------------------------------------------- goal 1


def test_goal_cases_against_mpmath(ref):
    """Libration θ₀ = 0.99π, rotation θ̇₀ = 2.5ω, θ̇₀ = 2ω(1 − 1e-6), ω ∈ {1, 3}, 0 < t <= 100."""
    for case, eth, ev in _errors(ref, "goal", "goal_cases", "goal_t"):
        assert eth <= GOAL_ATOL, (case, eth)
        assert ev <= GOAL_ATOL * max(1.0, case[2]), (case, ev)


def test_other_states_against_mpmath(ref):
    """Off-turning-point anchors, negative t, θ₀ ≈ 1000π, fl(π) at rest (mc = 3.7e-33), and
    librations next to the separatrix off their turning points (mc ≈ 1e-6, 1e-10)."""
    for case, eth, ev in _errors(ref, "extra", "extra_cases", "extra_t"):
        # θ₀ ≈ 3144: the output's own ulp is 4.5e-13.
        tol = GOAL_ATOL + 4 * np.spacing(abs(case[0]) + 50.0)
        assert eth <= tol, (case, eth)
        assert ev <= GOAL_ATOL * max(1.0, case[2]), (case, ev)


def test_long_horizon(ref):
    """t ≈ 1e6: the argument is reduced with the exact half period 2K (double-double).

    Goal: phase error <= 1e-9.  Achieved: the error is at the output's rounding
    (measured <= 2.2e-14 in θ', ~0 in θ); a plain double reduction (u = ωt + u0 mod a
    double 4K) would already be off by ~u·ε ≈ 1e-10."""
    for case, eth, ev in _errors(ref, "long", "goal_cases", "long_t"):
        assert eth <= LONG_ATOL and ev <= LONG_ATOL, (case, eth, ev)
    for i, case in enumerate(ref["goal_cases"]):
        th, v = _flow(case, ref["long_t"])
        th_ref, v_ref = ref["long_theta"][i], ref["long_v"][i]
        assert np.all(np.abs(th - th_ref) <= 1e-13 + 2 * np.spacing(np.abs(th_ref))), case
        assert np.all(np.abs(v - v_ref) <= 1e-13 * max(1.0, case[2])), case


def test_horizon_free_single_window_solver_run(ref):
    """One MBM window of length 1e6 with the exact flow equals the reference; a run with
    many short windows accumulates only round-off."""
    from scipy.integrate import solve_ivp

    from mbm import MBM

    case = ref["goal_cases"][2]  # rotation θ̇₀ = 2.5, ω = 1
    model = Pendulum(omega=case[2])
    t_end = ref["long_t"][2]  # 1e6
    sol = solve_ivp(model, (0.0, t_end), case[:2], method=MBM, approximant="belendez",
                    model=model, tau=t_end)
    assert sol.success and sol.t.size == 2
    assert abs(sol.y[0, -1] - ref["long_theta"][2, 2]) <= 2 * np.spacing(sol.y[0, -1])
    assert abs(sol.y[1, -1] - ref["long_v"][2, 2]) <= 1e-13
    # 0.99π, ω = 1, 100 windows over 0 <= t <= 100.
    case = ref["goal_cases"][0]
    sol = solve_ivp(model, (0.0, 100.0), case[:2], method=MBM, approximant="belendez",
                    model=model, tau=1.0)
    assert sol.success
    err = max(abs(sol.y[0, -1] - ref["goal_theta"][0, -1]),
              abs(sol.y[1, -1] - ref["goal_v"][0, -1]))
    # Each re-anchored state carries one rounding of its energy; at 0.99π (mc = 2.4e-4)
    # the period's sensitivity dK/dm ≈ 1/(2mc) turns these into phase: measured 5.0e-12.
    assert err <= 1e-11


def test_anchor_reproduced():
    states = [(0.3, -0.2, 1.0), (3.1, 0.0415, 1.0), (0.0, 2.5, 3.0), (1e4, -3.0, 0.7),
              (0.0, 2.0, 1.0), (math.pi, 0.0, 1.0), (0.0, 0.0, 2.0), (-7.0, 1e-300, 1.0)]
    for th0, v0, w in states:
        assert _F(th0, v0, w, 0.0) == (th0, v0)
        assert _F(th0, v0, w, -0.0) == (th0, v0)
        for t in (1e-300, 1e-17, -1e-17):
            a, b = _F(th0, v0, w, t)
            assert abs(a - th0) <= 1e-12 + 4 * np.spacing(abs(th0)), (th0, v0, w, t, a)
            assert abs(b - v0) <= 1e-12, (th0, v0, w, t, b)


def test_extreme_times():
    """|t| up to 1e20: the two-pass reduction keeps θ' and the libration's θ exact (the
    rotation's θ is then only as good as its own ulp, 3e4 at 2.6e20)."""
    for th0, v0, w, t in [(0.1, 0.0, 1.0, 1e20), (0.3, 0.2, 2.0, -1e18),
                          (0.0, 3.0, 1.0, 1e20), (0.0, 2.000001, 1.0, 3e17)]:
        with mp.workdps(80):
            ref_th, ref_v = refmod.flow_mp(th0, v0, w, t, dps=80)
        th, v = _F(th0, v0, w, t)
        assert abs(th - float(ref_th)) <= 1e-12 + np.spacing(abs(th)), (th0, v0, w, t)
        assert abs(v - float(ref_v)) <= 1e-11, (th0, v0, w, t)


def test_invalid_input_gives_nan():
    for args in [(0.1, 0.0, 0.0, 1.0), (0.1, 0.0, -1.0, 1.0), (np.nan, 0.0, 1.0, 1.0),
                 (0.1, np.inf, 1.0, 1.0), (0.1, 0.0, 1.0, np.nan), (0.1, 0.0, np.inf, 1.0),
                 (2e15, 0.0, 1.0, 1.0), (0.1, 1e200, 1.0, 1.0), (0.1, 0.0, 1.0, 1e301)]:
        a, b = _F(*args)
        assert math.isnan(a) and math.isnan(b), args


# --------------------------------------------------------------------------- the paper


@pytest.mark.parametrize("frac", [0.1, 0.5, 0.75, 0.99])
def test_eq31_turning_point(frac):
    """The kernel is Eq. (31): θ = 2 arcsin{sin(θ₀/2) sn[K(m) − ω₀t; m]}, m = sin²(θ₀/2)."""
    th0, w = frac * math.pi, 1.7
    with mp.workdps(40):
        m = mp.sin(mp.mpf(th0) / 2) ** 2
        K = mp.ellipk(m)
        for t in (0.3, 1.1, 2.9, 7.4):
            sn = mp.ellipfun("sn", K - mp.mpf(w) * t, m=m)
            exact = 2 * mp.asin(mp.sin(mp.mpf(th0) / 2) * sn)
            assert abs(_F(th0, 0.0, w, t)[0] - float(exact)) <= GOAL_ATOL


def test_eq23_time_to_angle():
    """Eq. (23): τ(z) = K(m) − F(arcsin z; m) is the time from θ₀ down to θ,
    z = sin(θ/2)/sin(θ₀/2)."""
    th0, w = 0.8 * math.pi, 2.0
    with mp.workdps(30):
        m = mp.sin(mp.mpf(th0) / 2) ** 2
        for z in (0.9, 0.5, 0.1, 0.0):
            tau = mp.ellipk(m) - mp.ellipf(mp.asin(z), m)
            th, _ = _F(th0, 0.0, w, float(tau / w))
            assert abs(math.sin(th / 2) - z * math.sin(th0 / 2)) <= 1e-14


# --------------------------------------------------------------------------- identities


_STATES = [
    (0.3, -0.2, 1.0), (1.234, -0.7, 1.0), (-2.9, 0.11, 2.0), (3.1, 0.0415, 1.0),
    (0.99 * math.pi, 0.0, 3.0), (0.0, 2.5, 1.0), (-20.0, 3.3, 1.5), (0.3, -2.0 * (1 + 1e-6), 1.0),
    (0.0, 2.0 * (1 - 1e-6), 1.0), (1e3, 7.0, 0.5), (0.0, 1e-8, 1.0), (math.pi, 0.0, 1.0),
]
_TIMES = np.array([-37.3, -5.1, -0.4, 0.01, 0.7, 3.3, 12.9, 61.0])


def test_energy_conserved():
    for th0, v0, w in _STATES:
        e0 = _energy(th0, v0, w)
        for t in _TIMES:
            th, v = _F(th0, v0, w, t)
            assert abs(_energy(th, v, w) - e0) <= ENERGY_RTOL * e0 + 1e-300, (th0, v0, w, t)


def test_derivatives_match_finite_differences():
    """θ' is the derivative of θ and θ'' = −ω² sin θ (4th-order central differences)."""
    h = 1e-3
    c = np.array([1.0, -8.0, 8.0, -1.0]) / (12.0 * h)
    for th0, v0, w in _STATES[:10]:
        for t in _TIMES:
            pts = [_F(th0, v0, w, t + s * h) for s in (-2, -1, 1, 2)]
            dth = sum(ci * p[0] for ci, p in zip(c, pts))
            dv = sum(ci * p[1] for ci, p in zip(c, pts))
            th, v = _F(th0, v0, w, t)
            assert abs(dth - v) <= 1e-9 * max(1.0, abs(th)), (th0, v0, w, t, dth - v)
            assert abs(dv + w * w * math.sin(th)) <= 1e-8, (th0, v0, w, t)


def _sensitivity(th0, v0, w, t):
    """Max change of φ_t under a 1-ulp change of either component of the state.

    Next to the separatrix the flow itself amplifies the rounding of an intermediate
    state (the period depends on the energy logarithmically), so identities that pass
    through a rounded state are checked relative to this measured conditioning."""
    base = _F(th0, v0, w, t)
    out = 0.0
    for dth, dv in [(np.spacing(th0) + 1e-300, 0.0), (0.0, np.spacing(v0) + 1e-300)]:
        for sgn in (1.0, -1.0):
            p = _F(th0 + sgn * dth, v0 + sgn * dv, w, t)
            out = max(out, abs(p[0] - base[0]), abs(p[1] - base[1]))
    return out


def test_flow_composition_and_time_reversal():
    """φ_s ∘ φ_t = φ_{s+t}; φ_{−t} ∘ φ_t = id; θ(−t; θ₀, θ̇₀) = θ(t; θ₀, −θ̇₀)."""
    for th0, v0, w in _STATES[:8]:
        for t, s in [(0.7, 2.1), (-3.3, 12.9), (41.0, -17.5)]:
            a = _F(th0, v0, w, t)
            b = _F(a[0], a[1], w, s)
            c = _F(th0, v0, w, t + s)
            # a is rounded: allow 4 ulps of it, propagated by the flow.
            tol = 1e-12 * max(1.0, abs(c[0]), w) + 4 * _sensitivity(a[0], a[1], w, s)
            assert abs(b[0] - c[0]) <= tol, (th0, v0, w, t, s, b[0] - c[0], tol)
            assert abs(b[1] - c[1]) <= tol, (th0, v0, w, t, s, b[1] - c[1], tol)
            back = _F(a[0], a[1], w, -t)
            tol = 1e-12 * max(1.0, abs(th0), w) + 4 * _sensitivity(a[0], a[1], w, -t)
            assert abs(back[0] - th0) <= tol, (th0, v0, w, t)
            assert abs(back[1] - v0) <= tol, (th0, v0, w, t)
            # Time reversal involves no intermediate state: round-off only.
            r = _F(th0, -v0, w, -t)
            assert abs(r[0] - a[0]) <= 1e-13 * max(1.0, abs(a[0])) and abs(r[1] + a[1]) <= 1e-13
    # Reflection symmetry θ → −θ.
    for th0, v0, w in _STATES[:8]:
        a, b = _F(th0, v0, w, 5.5), _F(-th0, -v0, w, 5.5)
        assert abs(a[0] + b[0]) <= 1e-13 * max(1.0, abs(a[0])) and abs(a[1] + b[1]) <= 1e-13


@settings(max_examples=60, deadline=None)
@given(
    th0=st.floats(-30.0, 30.0),
    v0=st.floats(-8.0, 8.0),
    w=st.floats(0.2, 4.0),
    t=st.floats(-20.0, 20.0),
    s=st.floats(-20.0, 20.0),
)
def test_flow_properties_random(th0, v0, w, t, s):
    """Energy and composition for random states away from the separatrix (|mc| >= 1e-3;
    nearer, the flow itself amplifies the rounding of the intermediate state)."""
    mc = flow_setup_kernel(th0, v0, w)[6]
    if abs(mc) < 1e-3:
        return
    a = _F(th0, v0, w, t)
    e0 = _energy(th0, v0, w)
    # The energy formula itself is ill-conditioned at small amplitude away from θ = 0:
    # a rounding of θ by eps·|θ| moves 2ω² sin²(θ/2) by ω²|sin θ|·eps·|θ| (hypothesis
    # found θ₀ = 2π + 9.6e-6, E = 1.6e-10, where this term is 1e-21 ≫ 1e-13·E).
    cond = 4 * EPS * w * w * (abs(np.sin(th0)) * abs(th0) + abs(np.sin(a[0])) * abs(a[0]))
    assert abs(_energy(a[0], a[1], w) - e0) <= ENERGY_RTOL * e0 + cond + 1e-300
    b = _F(a[0], a[1], w, s)
    c = _F(th0, v0, w, t + s)
    assert abs(b[0] - c[0]) <= 1e-10 * max(1.0, abs(c[0]))
    assert abs(b[1] - c[1]) <= 1e-10 * max(1.0, w)


def test_winding_shift_invariance():
    """θ₀ → θ₀ + 2πN shifts the whole trajectory by 2πN."""
    for th0, v0, w in [(0.4, 0.3, 1.0), (-1.0, 3.0, 1.0), (2.0, -0.5, 2.0)]:
        for N in (1, -7, 1000):
            shift = 2 * np.pi * N
            for t in (0.5, -13.0, 80.0):
                a = _F(th0, v0, w, t)
                b = _F(th0 + shift, v0, w, t)
                # θ₀ + shift is θ₀ + 2πN only to the rounding of the sum, which the flow
                # propagates like any change of θ₀ (4 ulps of it, see _sensitivity).
                tol = 1e-13 + 4 * np.spacing(abs(shift) + 10.0) * (
                    1.0 + _sensitivity(th0, v0, w, t) / np.spacing(abs(th0)))
                assert abs((b[0] - shift) - a[0]) <= tol, (th0, v0, N, t)
                assert abs(b[1] - a[1]) <= tol, (th0, v0, N, t)


def test_rotation_winds_without_jumps():
    """θ is continuous and monotone in a rotation (backwards too), growing ~ 2π per period."""
    th0, v0, w = 0.5, -2.9, 1.3
    assert flow_setup_kernel(th0, v0, w)[0] == REGIME_ROTATION
    T = period_kernel(th0, v0, w)
    ts = np.linspace(-5 * T, 5 * T, 4001)
    th, v = _flow((th0, v0, w), ts)
    assert np.all(v < 0) and np.all(np.diff(th) < 0)
    # Exactly 2π per period.
    for n in (1, 3, -4):
        a = _F(th0, v0, w, n * T)
        assert abs(a[0] - (th0 - 2 * np.pi * n)) <= 1e-12 and abs(a[1] - v0) <= 1e-12


# --------------------------------------------------------------------------- separatrix


def test_separatrix_reference(ref):
    """θ̇₀ = 2ω(1 ± 10^-e), e = 1..12, and exactly 2ω: each against mpmath."""
    for case, eth, ev in _errors(ref, "sep", "sep_cases", "sep_t"):
        assert eth <= GOAL_ATOL and ev <= GOAL_ATOL, (case, eth, ev)


def test_separatrix_continuity_and_ordering(ref):
    """Trajectories through θ = 0 with θ̇₀ = 2(1 ∓ 10^-e) bracket the separatrix
    θ = 4 arctan(e^t) − π and converge to it linearly in 10^-e."""
    ts = np.array([0.5, 1.0, 2.0, 4.0, 6.0])
    sep = np.array([_F(0.0, 2.0, 1.0, t)[0] for t in ts])
    assert np.max(np.abs(sep - (4 * np.arctan(np.exp(ts)) - np.pi))) <= 1e-15
    assert flow_setup_kernel(0.0, 2.0, 1.0)[0] == REGIME_SEPARATRIX
    ratios = []
    for e in range(1, 13):
        d = 10.0 ** -e
        lib = np.array([_F(0.0, 2.0 * (1 - d), 1.0, t)[0] for t in ts])
        rot = np.array([_F(0.0, 2.0 * (1 + d), 1.0, t)[0] for t in ts])
        assert flow_setup_kernel(0.0, 2.0 * (1 - d), 1.0)[0] == REGIME_LIBRATION
        assert flow_setup_kernel(0.0, 2.0 * (1 + d), 1.0)[0] == REGIME_ROTATION
        assert np.all(lib < sep) and np.all(sep < rot), e
        if e >= 3:  # linear regime: deviation ∝ 10^-e at fixed t
            ratios.append(max(np.max(sep - lib), np.max(rot - sep)) / d)
    ratios = np.array(ratios)
    # Measured: the ratio is ~ 3.5e2 (dominated by t = 6, where e^t ≈ 400), constant to
    # a few percent from e = 3 to 12.
    assert np.all(ratios < 1e3) and np.max(ratios) / np.min(ratios) < 1.1, ratios


def test_inverted_rest_and_bottom_rest():
    assert flow_setup_kernel(0.0, 0.0, 1.0)[0] == REGIME_LIBRATION
    for t in (1.0, -50.0, 1e9):
        assert _F(0.0, 0.0, 1.0, t) == (0.0, 0.0)
        # fl(6π) is 2.1e-15 off 6π: a tiny libration of that amplitude about 6π.
        a = _F(6 * math.pi, 0.0, 1.0, t)
        assert abs(a[0] - 6 * math.pi) <= 5e-15 and abs(a[1]) <= 5e-15
    # fl(π) is below π by 1.2e-16: a genuine libration with mc = 3.7e-33, period ~ 155/ω.
    res = flow_setup_kernel(math.pi, 0.0, 1.0)
    assert res[0] == REGIME_LIBRATION and 0 < res[6] < 1e-32
    assert abs(period_kernel(math.pi, 0.0, 1.0) - 154.87260221755525) <= 1e-12


# --------------------------------------------------------------------------- period (26)


def test_period_against_mpmath(ref):
    for case, T in zip(ref["period_cases"], ref["period"]):
        got = period(Pendulum(omega=case[2]), case[:2])
        assert abs(got - T) <= 4e-16 * T, (case, got, T)


@pytest.mark.parametrize("deg", [1.0, 45.0, 90.0, 135.0, 170.0, 179.9])
def test_period_eq26(deg):
    """T = 4K(m)/ω₀ = (2/π) T₀ K(m), m = sin²(θ₀/2) (Eqs. (10), (26), (27))."""
    th0, w = math.radians(deg), 2.5
    with mp.workdps(30):
        T = 4 * mp.ellipk(mp.sin(mp.mpf(th0) / 2) ** 2) / w
    got = period(Pendulum(omega=w), [th0, 0.0])
    assert abs(got - float(T)) <= 2e-16 * float(T)
    # The flow returns to the anchor after one period.
    a = _F(th0, 0.0, w, got)
    assert abs(a[0] - th0) <= 1e-12 and abs(a[1]) <= 1e-12


def test_period_limits_and_regimes():
    assert period(Pendulum(omega=3.0), [0.0, 0.0]) == 2 * math.pi / 3.0
    assert abs(period(Pendulum(omega=3.0), [1e-8, 0.0]) - 2 * math.pi / 3.0) <= 1e-15
    assert period(Pendulum(), [0.0, 2.0]) == math.inf
    assert period(Pendulum(omega=2.0), [0.0, -4.0]) == math.inf
    # fl(4π) is not 4π: next to, not on, the separatrix (a rotation, huge period).
    assert 30.0 < period(Pendulum(omega=2.0), [-4 * math.pi, -4.0]) < math.inf
    # Rotation: the time for θ to advance by 2π, 2K(1/m)/(√m ω).
    w, v0 = 1.5, 7.0
    m = (v0 / (2 * w)) ** 2
    with mp.workdps(30):
        T = float(2 * mp.ellipk(1 / mp.mpf(m)) / (mp.sqrt(m) * w))
    assert abs(period(Pendulum(omega=w), (0.0, v0)) - T) <= 4e-16 * T
    # The log divergence at the separatrix: θ̇₀ = 2(1 ∓ d) gives |mc| ≈ 2d and
    # K ≈ ½ ln(16/|mc|), so T_libration ≈ 2 ln(8/d) and T_rotation ≈ ln(8/d) (one turn
    # of a rotation is half an oscillation of the neighbouring libration).
    for e in (4, 8, 12):
        d = 10.0 ** -e
        Tl = period(Pendulum(), [0.0, 2 * (1 - d)])
        Tr = period(Pendulum(), [0.0, 2 * (1 + d)])
        assert abs(Tl - 2 * math.log(8 / d)) < 1e-2 and abs(Tr - math.log(8 / d)) < 1e-2


def test_pendulum_flow_wrapper():
    model = Pendulum(omega=1.5)
    t = np.array([[0.0, 1.0], [-2.5, 40.0]])
    y = pendulum_flow(model, [0.7, -1.9], t)
    assert y.shape == (2, 2, 2)
    for idx in np.ndindex(t.shape):
        assert (y[0][idx], y[1][idx]) == _F(0.7, -1.9, 1.5, t[idx])
    assert np.array_equal(pendulum_flow(model, (0.7, -1.9), 0.0), [0.7, -1.9])
    with pytest.raises(ValueError, match="model"):
        pendulum_flow(Pendulum(beta=0.1), [0.1, 0.0], 1.0)
    with pytest.raises(ValueError, match="y0"):
        pendulum_flow(model, [2e15, 0.0], 1.0)


def test_period_validation():
    with pytest.raises(ValueError, match="model"):
        period(Pendulum(beta=0.1), [0.1, 0.0])
    with pytest.raises(ValueError, match="model"):
        period(Pendulum(gamma=0.1), [0.1, 0.0])
    with pytest.raises(TypeError, match="Pendulum"):
        period(lambda t, y: y, [0.1, 0.0])
    for bad in ([0.1], [0.1, 0.2, 0.3], [[0.1, 0.0]], [np.nan, 0.0], [0.0, np.inf]):
        with pytest.raises(ValueError, match="y0"):
            period(Pendulum(), bad)
    # what is not a real number is a TypeError (mbm.validate's one policy)
    with pytest.raises(TypeError, match="y0 must be array_like of 2 real numbers"):
        period(Pendulum(), ["a", "b"])


# --------------------------------------------------------------------------- approximants


def test_flow_names_reexported_from_the_paper_module():
    # mbm.approximants.belendez2007 keeps the names it had before the flow moved to
    # mbm.special.pendulum_flow; the top-level faces are the same objects.
    import mbm
    import mbm.approximants.belendez2007 as B
    import mbm.special.pendulum_flow as PF

    for name in ("pendulum_flow", "period", "pendulum_flow_kernel", "flow_setup_kernel",
                 "flow_eval_kernel", "period_kernel", "REGIME_LIBRATION", "REGIME_ROTATION",
                 "REGIME_SEPARATRIX", "REGIME_REST"):
        assert getattr(B, name) is getattr(PF, name), name
    assert mbm.pendulum_flow is PF.pendulum_flow and mbm.period is PF.period
    assert get_approximant("belendez").param_names() == PF.FLOW_PARAM_NAMES


def test_belendez_approximant():
    ap = get_approximant("belendez")
    assert ap.anchors == "any"
    model = Pendulum(omega=2.0)
    an = ap.anchor(model, 1.2, -0.4)
    for key in ("k", "m", "mc", "K", "period", "u0", "regime"):
        assert key in an.params
    assert an.params["regime"] == REGIME_LIBRATION
    assert abs(an.params["m"] + an.params["mc"] - 1.0) <= 1e-15
    assert an.params["period"] == period(model, [1.2, -0.4])
    t = np.linspace(-3.0, 30.0, 37)
    th, v = an(t)
    # The approximant reads the flow's table (its per-time kernel, the same bits as a
    # table): within a few ulps of the flow kernel (tests/special/test_pendulum_flow_table.py).
    flow = flow_setup_kernel(1.2, -0.4, 2.0)
    for i, ti in enumerate(t):
        assert (th[i], v[i]) == flow_table_point_kernel(flow, ti)
        ref = _F(1.2, -0.4, 2.0, ti)
        assert abs(th[i] - ref[0]) <= 8 * np.spacing(2.0) and abs(v[i] - ref[1]) <= 16 * np.spacing(4.0)
    assert an(0.0) == (1.2, -0.4)
    rot = ap.anchor(model, 0.0, 9.0)
    assert rot.params["regime"] == REGIME_ROTATION and rot.params["k"] > 1.0
    for m in (Pendulum(beta=0.1), Pendulum(gamma=0.2)):
        with pytest.raises(ApproximantDomainError):
            ap.anchor(m, 0.1, 0.0)
    # The kernel checks β, γ itself too (the solver may call it directly).
    assert ap.anchor_kernel(0.1, 0.0, 1.0, 0.1, 0.0)[0] != 0
    assert ap.anchor_kernel(0.0, 0.2, 1.0, 0.1, 0.0)[0] != 0


def test_harmonic_turning_point_is_eq32_33():
    """At θ̇₀ = 0: θ = θ₀ cos(ω t), ω = π ω₀ / (2K(sin²(θ₀/2))) (Eqs. (32), (33))."""
    ap = get_approximant("harmonic")
    for th0, w0 in [(0.25 * math.pi, 1.0), (0.75 * math.pi, 3.0), (-2.0, 0.5)]:
        an = ap.anchor(Pendulum(omega=w0), th0, 0.0)
        with mp.workdps(30):
            om = float(mp.pi * w0 / (2 * mp.ellipk(mp.sin(mp.mpf(th0) / 2) ** 2)))
        assert abs(an.params["omega_h"] - om) <= 2e-16 * om
        assert abs(an.params["period"] - period(Pendulum(omega=w0), [th0, 0.0])) <= 1e-14
        t = np.linspace(-4.0, 40.0, 23)
        th, v = an(t)
        assert np.max(np.abs(th - th0 * np.cos(om * t))) <= 1e-13
        assert np.max(np.abs(v + th0 * om * np.sin(om * t))) <= 1e-13


def test_harmonic_general_anchor():
    ap = get_approximant("harmonic")
    assert ap.anchors == "any"
    model = Pendulum(omega=1.5)
    for th0, v0 in [(0.4, 0.9), (-1.0, -0.3), (2 * math.pi * 5 + 0.2, 1.0)]:
        an = ap.anchor(model, th0, v0)
        assert an(0.0) == (th0, v0)
        a, b = an(1e-12)
        assert abs(a - th0) <= 1e-11 and abs(b - v0) <= 1e-11
        # Same frequency as the exact motion: the fit returns to the anchor after T.
        T = period(model, [th0, v0])
        a, b = an(T)
        assert abs(a - th0) <= 1e-12 * max(1.0, abs(th0)) and abs(b - v0) <= 1e-12
        # The amplitude differs from the energy amplitude by the anharmonicity only.
        assert abs(an.params["A"] - an.params["A_energy"]) <= 0.05 * an.params["A_energy"]
    with pytest.raises(ApproximantDomainError, match="oscillation"):
        ap.anchor(model, 0.0, 3.5)  # rotation
    with pytest.raises(ApproximantDomainError, match="oscillation"):
        ap.anchor(model, 0.0, 3.0)  # separatrix
    with pytest.raises(ApproximantDomainError):
        ap.anchor(Pendulum(beta=0.2, omega=1.5), 0.1, 0.0)


def _harmonic_max_error(amplitude, n=2001):
    """max over a quarter period of |θ_exact − θ_harmonic| (ω₀ = 1), refined by golden section."""
    exact = get_approximant("belendez").anchor(Pendulum(), amplitude, 0.0)
    harm = get_approximant("harmonic").anchor(Pendulum(), amplitude, 0.0)
    T = exact.params["period"]

    def err(t):
        return np.abs(exact(t)[0] - harm(t)[0])

    t = np.linspace(0.0, T / 4, n)
    e = err(t)
    i = int(np.argmax(e))
    lo, hi = t[max(i - 1, 0)], t[min(i + 1, n - 1)]
    g = (math.sqrt(5) - 1) / 2
    for _ in range(50):
        c, d = hi - g * (hi - lo), lo + g * (hi - lo)
        if err(c) > err(d):
            hi = d
        else:
            lo = c
    return max(e[i], float(err(0.5 * (lo + hi))))


def test_harmonic_claim_135_degrees(ref):
    """The paper: "for amplitudes lower than 135° the motion is practically harmonic".

    Quantified (ω₀ = 1, turning-point anchor, max over a period of |(31) − (32)|):
    18°: 2.5e-4 rad (0.08 % of the amplitude), 45°: 4.0e-3 (0.5 %), 90°: 0.0366 (2.3 %),
    135°: 0.163 rad = 9.3° (6.9 %), 162°: 0.400 (14 %), 178.2°: 0.982 (32 %).
    """
    amps, pinned = ref["harmonic_amplitudes"], ref["harmonic_max_error"]
    for a, e_ref in zip(amps, pinned):
        e = _harmonic_max_error(a)
        assert abs(e - e_ref) <= 1e-9 * max(1.0, e_ref) + 1e-12, (a, e, e_ref)
    i135 = int(np.argmin(np.abs(amps - 0.75 * np.pi)))
    assert 0.162 < pinned[i135] < 0.163
    assert 0.069 < pinned[i135] / amps[i135] < 0.070
    # The error grows monotonically with the amplitude.
    assert np.all(np.diff(pinned) > 0)
