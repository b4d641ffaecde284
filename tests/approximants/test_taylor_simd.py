"""The vector Taylor kernel (mbm.approximants.taylor_simd) against the recurrence in 50 digits.

At degree SIMD_ORDER the coefficients come from LLVM vector code emitted at compile
time, the module's sums in another order; every coefficient, undriven and driven,
must be within the rounding bound of a 50-digit recurrence that the loop form meets
as well, and the in-place path (the run's workspace) must give the bits of the
general one.
"""

import math

import mpmath
import numpy as np
import pytest

from mbm.approximants import taylor, taylor_simd
from mbm.approximants.taylor import (
    HEADER,
    N_EXTRA,
    driven_series_loop,
    drive_phase_sincos,
    series_loop,
    taylor_coefficients,
    taylor_coefficients_into,
    taylor_driven_coefficients,
    taylor_driven_coefficients_into,
    taylor_workspace,
)

N = taylor_simd.SIMD_ORDER
EPS = 2.220446049250313e-16

# Rounding bound per coefficient in units of eps·(k + 1)·A_k (A_k the recurrence on
# absolute values, so each operation's error is relative to what enters it): a few
# operations per order, compounded over k orders.
ROUNDING_UNITS = 2.0


def _scenes(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield dict(
            beta=rng.uniform(0.0, 2.0), gamma=rng.uniform(-3.0, 3.0), omega=rng.uniform(0.2, 4.0),
            theta0=rng.uniform(-20.0, 20.0), v0=rng.uniform(-8.0, 8.0), amp=rng.uniform(-2.0, 2.0),
            freq=rng.uniform(0.0, 3.0), phase=rng.uniform(-4.0, 4.0), t0=rng.uniform(0.0, 1e5),
        )


def _mp_series(s, n, driven):
    # The recurrence in 50-digit arithmetic, summed in the textbook order, and beside
    # it the same recurrence on absolute values (A_k).  The drive's series d_k =
    # A Ω^k/k! sin(ψ + kπ/2) takes ψ from the kernel's own (u, w) = (sin ψ, cos ψ)
    # (drive_phase_sincos, tested in test_drive): this checks the recurrence.
    mpmath.mp.dps = 50
    beta, gamma, w2 = mpmath.mpf(s["beta"]), mpmath.mpf(s["gamma"]), mpmath.mpf(s["omega"]) ** 2
    a = [mpmath.mpf(s["theta0"]), mpmath.mpf(s["v0"])]
    sn, cn = [mpmath.sin(a[0])], [mpmath.cos(a[0])]
    aa, sa, ca = [abs(a[0]), abs(a[1])], [abs(sn[0])], [abs(cn[0])]
    d = [mpmath.mpf(0)] * (n + N_EXTRA)
    if driven:
        u, w = drive_phase_sincos(s["freq"], s["phase"], s["t0"])
        uw = [mpmath.mpf(u), mpmath.mpf(w), -mpmath.mpf(u), -mpmath.mpf(w)]
        for k in range(n + N_EXTRA):
            d[k] = mpmath.mpf(s["amp"]) * mpmath.mpf(s["freq"]) ** k / mpmath.factorial(k) * uw[k % 4]
    a.append((gamma + d[0] - beta * a[1] - w2 * sn[0]) / 2)
    aa.append((abs(gamma) + abs(d[0]) + beta * aa[1] + w2 * sa[0]) / 2)
    for k in range(1, n + N_EXTRA - 1):
        sn.append(sum(j * a[j] * cn[k - j] for j in range(1, k + 1)) / k)
        cn.append(-sum(j * a[j] * sn[k - j] for j in range(1, k + 1)) / k)
        sa.append(sum(j * aa[j] * ca[k - j] for j in range(1, k + 1)) / k)
        ca.append(sum(j * aa[j] * sa[k - j] for j in range(1, k + 1)) / k)
        a.append((d[k] - beta * (k + 1) * a[k + 1] - w2 * sn[k]) / ((k + 1) * (k + 2)))
        aa.append((abs(d[k]) + beta * (k + 1) * aa[k + 1] + w2 * sa[k]) / ((k + 1) * (k + 2)))
    return a, aa


def _units(coef, ref, bound):
    return max(abs(coef[HEADER + k] - float(ref[k])) / (EPS * (k + 1) * float(bound[k]))
               for k in range(len(ref)))


def _loop(s, n, driven):
    a = np.empty(n + N_EXTRA + 1)
    scratch = np.empty(3 * (n + N_EXTRA + 1))
    if driven:
        u, w = drive_phase_sincos(s["freq"], s["phase"], s["t0"])
        driven_series_loop((s["beta"], s["gamma"], s["omega"]), (s["amp"], s["freq"], u, w), s["theta0"], s["v0"],
                           n, a, scratch)
    else:
        series_loop(s["beta"], s["gamma"], s["omega"], s["theta0"], s["v0"], n, a, scratch)
    return np.r_[np.zeros(HEADER), a]


def _kernel(s, n, driven):
    if driven:
        return taylor_driven_coefficients((s["beta"], s["gamma"], s["omega"], s["amp"], s["freq"], s["phase"]),
                                          s["t0"], s["theta0"], s["v0"], n)
    return taylor_coefficients(s["beta"], s["gamma"], s["omega"], s["theta0"], s["v0"], n)


@pytest.mark.parametrize("driven", [False, True])
def test_vector_kernel_within_the_rounding_bound_of_50_digits(driven):
    worst = worst_loop = 0.0
    for s in _scenes(20, 7 + driven):
        ref, bound = _mp_series(s, N, driven)
        worst = max(worst, _units(_kernel(s, N, driven), ref, bound))
        worst_loop = max(worst_loop, _units(_loop(s, N, driven), ref, bound))
    assert worst <= ROUNDING_UNITS, worst
    # The bound is one both forms meet (not one loose enough for either).
    assert worst_loop <= ROUNDING_UNITS, worst_loop


@pytest.mark.parametrize("n_order", [12, 16, 30])
def test_loop_form_within_the_same_bound(n_order):
    worst = 0.0
    for s in _scenes(10, 100 + n_order):
        ref, bound = _mp_series(s, n_order, False)
        worst = max(worst, _units(_kernel(s, n_order, False), ref, bound))
    assert worst <= ROUNDING_UNITS, worst


def test_degree_24_takes_the_vector_kernel():
    # Rounded apart from the loop form on generic states: the dispatch is observable.
    differs = 0
    for s in _scenes(50, 3):
        c = _kernel(s, N, False)
        a = _loop(s, N, False)
        scale = np.abs(a[HEADER:]).max()
        assert np.allclose(c[HEADER:], a[HEADER:], rtol=1e-9, atol=1e-12 * scale)
        differs += not np.array_equal(c[HEADER:], a[HEADER:])
    assert differs > 0


@pytest.mark.parametrize("driven", [False, True])
def test_workspace_in_place_gives_the_general_paths_bits(driven):
    coef, scratch = taylor_workspace(N)
    assert coef.size == HEADER + N + N_EXTRA + 1  # the in-place path's condition
    for s in _scenes(30, 11):
        big = np.full(coef.size + 5, 7.0)
        if driven:
            args = ((s["beta"], s["gamma"], s["omega"], s["amp"], s["freq"], s["phase"]), s["t0"], s["theta0"],
                    s["v0"], N)
            fast = taylor_driven_coefficients_into(*args, coef, scratch).copy()
            slow = taylor_driven_coefficients_into(*args, big, scratch)
        else:
            args = (s["beta"], s["gamma"], s["omega"], s["theta0"], s["v0"], N)
            fast = taylor_coefficients_into(*args, coef, scratch).copy()
            slow = taylor_coefficients_into(*args, big, scratch)
        assert np.array_equal(fast, slow)
        assert np.all(big[slow.size:] == 7.0)  # writes only its coefficients
        assert fast[0] == taylor.STATUS_OK and fast[1] == N


def test_in_place_path_refuses_a_bad_state_as_the_general_one():
    coef, scratch = taylor_workspace(N)
    out = taylor_coefficients_into(0.1, 0.2, 1.0, math.nan, 0.4, N, coef, scratch)
    assert out[0] == taylor.STATUS_BAD_STATE and np.isnan(out[HEADER:]).all()
    out = taylor_driven_coefficients_into((0.1, 0.2, 1.0, 0.5, 1.0, 0.0), math.inf, 0.3, 0.4, N, coef, scratch)
    assert out[0] == taylor.STATUS_BAD_STATE


def test_anchor_reproduced_exactly():
    for s in _scenes(20, 5):
        c = _kernel(s, N, False)
        assert c[HEADER] == s["theta0"] and c[HEADER + 1] == s["v0"]


def test_constants_agree_with_the_taylor_module():
    assert taylor_simd.HEADER == HEADER and taylor_simd.N_EXTRA == N_EXTRA
    assert taylor_simd.SIMD_ORDER == taylor.TAYLOR_DEFAULT_ORDER


def test_the_default_degree_kernels_are_the_general_ones_at_that_degree_and_refuse_others():
    # taylor24_coefficients_into (and its driven twin): what the default degree's loop
    # entries anchor with; a bad degree or a non-finite input is a status, as in general
    from mbm.approximants import taylor_series as ts
    from mbm.approximants.taylor_simd import SIMD_ORDER

    args = (0.1, 0.3, 1.0, 0.7, -0.2)
    drive = ((0.1, 0.3, 1.0, 0.4, 0.8, 0.3), 2.5, 0.7, -0.2)
    for fn24, fn, a in ((ts.taylor24_coefficients_into, ts.taylor_coefficients_into, args),
                        (ts.taylor24_driven_coefficients_into, ts.taylor_driven_coefficients_into, drive)):
        ws, wg = ts.taylor_workspace(SIMD_ORDER), ts.taylor_workspace(SIMD_ORDER)
        got = fn24(*a, SIMD_ORDER, *ws).copy()
        np.testing.assert_array_equal(got, fn(*a, SIMD_ORDER, *wg))
        assert got[0] == ts.STATUS_OK and got[1] == SIMD_ORDER
        bad = fn24(*a, 16, *ts.taylor_workspace(16))
        assert bad[0] == ts.STATUS_BAD_ORDER and bad.size == ts.HEADER
        nan = fn24(*a[:-2], math.nan, a[-1], SIMD_ORDER, *ts.taylor_workspace(SIMD_ORDER))
        assert nan[0] == ts.STATUS_BAD_STATE and np.isnan(nan[1:]).all()
