"""The straight-line Taylor recurrences (mbm.approximants.taylor_unrolled) against the loop form.

They are generated code: the committed module must be what the generator writes, and
each function must give the loop kernel's bits (the same sums in the same order), so
that no path of a run depends on which form computed its coefficients.
"""

import mpmath
import numpy as np
import pytest

from mbm.approximants import _unrolled_gen, taylor, taylor_unrolled
from mbm.approximants.taylor import (
    HEADER,
    N_EXTRA,
    driven_series_loop,
    drive_phase_sincos,
    series_loop,
    taylor_coefficients,
    taylor_driven_coefficients,
    taylor_workspace,
)


def _scenes(n, seed):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        yield dict(
            beta=rng.uniform(0.0, 2.0), gamma=rng.uniform(-3.0, 3.0), omega=rng.uniform(0.2, 4.0),
            theta0=rng.uniform(-20.0, 20.0), v0=rng.uniform(-8.0, 8.0), amp=rng.uniform(-2.0, 2.0),
            freq=rng.uniform(0.0, 3.0), phase=rng.uniform(-4.0, 4.0), t0=rng.uniform(0.0, 1e5),
        )


def test_committed_module_is_the_generators_output():
    assert _unrolled_gen.TARGET.read_text() == _unrolled_gen.source()
    assert taylor_unrolled.UNROLLED_ORDERS == _unrolled_gen.UNROLLED_ORDERS
    assert _unrolled_gen.N_EXTRA == N_EXTRA


def test_generator_check_mode_reports_a_stale_module(tmp_path, monkeypatch, capsys):
    stale = tmp_path / "taylor_unrolled.py"
    stale.write_text(_unrolled_gen.source() + "# edited by hand\n")
    monkeypatch.setattr(_unrolled_gen, "TARGET", stale)
    assert _unrolled_gen.main(["--check"]) == 1
    stale.write_text(_unrolled_gen.source())
    assert _unrolled_gen.main(["--check"]) == 0
    assert "up to date" in capsys.readouterr().out


def test_every_unrolled_degree_is_wired_into_the_kernels():
    # taylor_coefficients_into dispatches on the degree; a degree generated but not
    # wired would silently take the loop (same bits, none of the speed).
    src = open(taylor.__file__).read()
    for n in taylor_unrolled.UNROLLED_ORDERS:
        assert f"taylor{n}_series(" in src and f"taylor{n}_driven_series(" in src


@pytest.mark.parametrize("n_order", taylor_unrolled.UNROLLED_ORDERS)
def test_unrolled_gives_the_loops_bits(n_order):
    nt = n_order + N_EXTRA
    a = np.empty(nt + 1)
    scratch = np.empty(3 * (nt + 1))
    for s in _scenes(300, n_order):
        coef = taylor_coefficients(s["beta"], s["gamma"], s["omega"], s["theta0"], s["v0"], n_order)
        series_loop(s["beta"], s["gamma"], s["omega"], s["theta0"], s["v0"], n_order, a, scratch)
        assert np.array_equal(coef[HEADER:], a)
        assert np.array_equal(np.signbit(coef[HEADER:]), np.signbit(a))
        coef = taylor_driven_coefficients(s["beta"], s["gamma"], s["omega"], s["amp"], s["freq"], s["phase"],
                                          s["t0"], s["theta0"], s["v0"], n_order)
        u, w = drive_phase_sincos(s["freq"], s["phase"], s["t0"])
        driven_series_loop(s["beta"], s["gamma"], s["omega"], s["amp"], s["freq"], u, w, s["theta0"],
                           s["v0"], n_order, a, scratch)
        assert np.array_equal(coef[HEADER:], a)


def test_unrolled_kernel_writes_only_its_coefficients():
    n = taylor_unrolled.UNROLLED_ORDERS[0]
    coef, scratch = taylor_workspace(n)
    big = np.full(coef.size + 5, 7.0)
    out = taylor.taylor_coefficients_into(0.1, 0.2, 1.0, 0.3, 0.4, n, big, scratch)
    assert out.size == HEADER + n + N_EXTRA + 1
    assert np.all(big[out.size:] == 7.0)


def _mp_series(beta, gamma, omega, theta0, v0, n):
    # The recurrence in 50-digit arithmetic, summed in the textbook order (an independent
    # check of every coefficient, not of the bits), and beside it the same recurrence
    # on absolute values: A_k bounds what rounding can reach in a_k (each operation's
    # error is relative to the magnitudes that enter it).
    mpmath.mp.dps = 50
    beta, gamma, w2 = mpmath.mpf(beta), mpmath.mpf(gamma), mpmath.mpf(omega) ** 2
    a = [mpmath.mpf(theta0), mpmath.mpf(v0)]
    s, c = [mpmath.sin(a[0])], [mpmath.cos(a[0])]
    aa, sa, ca = [abs(a[0]), abs(a[1])], [abs(s[0])], [abs(c[0])]
    a.append((gamma - beta * a[1] - w2 * s[0]) / 2)
    aa.append((abs(gamma) + beta * aa[1] + w2 * sa[0]) / 2)
    for k in range(1, n + N_EXTRA - 1):
        s.append(sum(j * a[j] * c[k - j] for j in range(1, k + 1)) / k)
        c.append(-sum(j * a[j] * s[k - j] for j in range(1, k + 1)) / k)
        sa.append(sum(j * aa[j] * ca[k - j] for j in range(1, k + 1)) / k)
        ca.append(sum(j * aa[j] * sa[k - j] for j in range(1, k + 1)) / k)
        a.append((-beta * (k + 1) * a[k + 1] - w2 * s[k]) / ((k + 1) * (k + 2)))
        aa.append((beta * (k + 1) * aa[k + 1] + w2 * sa[k]) / ((k + 1) * (k + 2)))
    return a, aa


# Rounding bound per coefficient in units of eps·A_k (A_k the absolute-value
# recurrence): a few operations per order, compounded over k orders.
ROUNDING_UNITS = 2.0


@pytest.mark.parametrize("n_order", sorted(set(taylor_unrolled.UNROLLED_ORDERS) | {12, 16, 30}))
def test_coefficients_match_the_recurrence_in_50_digits(n_order):
    worst = 0.0
    for s in _scenes(20, 100 + n_order):
        coef = taylor_coefficients(s["beta"], s["gamma"], s["omega"], s["theta0"], s["v0"], n_order)
        ref, bound = _mp_series(s["beta"], s["gamma"], s["omega"], s["theta0"], s["v0"], n_order)
        for k in range(len(ref)):
            err = abs(coef[HEADER + k] - float(ref[k]))
            units = err / (2.220446049250313e-16 * (k + 1) * float(bound[k]))
            worst = max(worst, units)
    assert worst <= ROUNDING_UNITS, worst
