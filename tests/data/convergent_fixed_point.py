"""Reference solutions of θ'' + βθ' + ω² sin θ = γ to ~1e-30, in fixed-point integer arithmetic.

Independent of mbm's kernels and of the benchmark (pure Python integers, mpmath's
fixed-point sine/cosine): a Taylor integrator of degree REF_DEGREE with step REF_STEP, every
quantity an integer scaled by 2^REF_BITS.  ``examples/convergence_study.py``
writes ``tests/data/convergent_reference.npz`` with it, and
``tests/approximants/test_convergent.py`` uses :func:`local_step` for true local errors.
:func:`check` compares it with itself at half the step and degree 24, and with
the exact Jacobi-elliptic solution (mpmath) on an undamped scene.

Scaled coefficients A_k = a_k h^k keep every number of order (h/R)^k ≤ 1 (R the
radius of convergence), so the fixed-point scale never under- or overflows:

    k S_k = Σ_{j=1}^{k} j A_j C_{k−j},   k C_k = −Σ_{j=1}^{k} j A_j S_{k−j},
    (k+1)(k+2) A_{k+2} = γh² δ_{k0} − βh (k+1) A_{k+1} − ω²h² S_k,
    θ(h) = Σ A_k,  θ'(h) = Σ k A_k / h.
"""

from fractions import Fraction

# 2^-128 ≈ 3e-39 per operation: 1.6e5 steps of ~1e3 operations stay below 1e-30.
REF_BITS = 128
# Step 1/16 (exact in binary) and degree 28: the running scene's radius ≈ 0.4 gives
# a truncation (0.16)^29 ≈ 1e-23 per step; every other scene's is far smaller.
REF_STEP = Fraction(1, 16)
REF_DEGREE = 28

_ONE = 1 << REF_BITS


def _fix(x):
    """A float or Fraction as a fixed-point integer (rounded)."""
    f = Fraction(x) * _ONE
    return round(f)


def _to_hi_lo(X):
    """Fixed-point integer -> (hi, lo) floats with hi + lo = X 2^-P to ~1e-32 relative."""
    f = Fraction(X, _ONE)
    hi = float(f)
    lo = float(f - Fraction(hi))
    return hi, lo


def _step(X, V, h, cst, degree):
    """One Taylor step of length h (Fraction) from fixed-point (X, V).

    ``cst`` = (βh, γh², ω²h², h) scaled by 2^REF_BITS (:func:`_constants`); the
    recurrence is the one in this module's docstring, in plain integer arithmetic
    with mpmath's fixed-point sine and cosine (no code of the kernels it checks).
    The benchmark's reference (``benchmarks/references.py``) has its own copy;
    ``tests/bench/test_bench.py`` checks that the two give the same integers.
    """
    from mpmath.libmp import from_man_exp, mpf_cos_sin, to_fixed

    P = REF_BITS
    bh, gh2, wh2, H = cst
    A = [0] * (degree + 1)
    JA = [0] * (degree + 1)  # j A_j
    A[0] = X
    A[1] = JA[1] = (V * H) >> P
    c0, s0 = mpf_cos_sin(from_man_exp(X, -P), P + 16)
    S = [to_fixed(s0, P)]
    C = [to_fixed(c0, P)]
    A[2] = (gh2 - ((bh * A[1] + wh2 * S[0]) >> P)) // 2
    JA[2] = 2 * A[2]
    for k in range(1, degree - 1):
        ss = 0
        cc = 0
        for j in range(1, k + 1):
            ss += JA[j] * C[k - j]
            cc += JA[j] * S[k - j]
        S.append((ss >> P) // k)
        C.append(-((cc >> P) // k))
        A[k + 2] = (-((bh * (k + 1) * A[k + 1] + wh2 * S[k]) >> P)) // ((k + 1) * (k + 2))
        JA[k + 2] = (k + 2) * A[k + 2]
    return sum(A), (sum(JA) << P) // H


def _constants(beta, gamma, omega, h):
    b, g, w = Fraction(beta), Fraction(gamma), Fraction(omega)
    return (_fix(b * h), _fix(g * h * h), _fix(w * w * h * h), _fix(h))


def fixed_point_reference(beta, gamma, omega, y0, t_end, step=REF_STEP, degree=REF_DEGREE,
                          sample_every=1):
    """States at t = 0, s, 2s, ..., t_end (s = ``sample_every``) as double-double pairs.

    Parameters
    ----------
    beta, gamma, omega : float
        Model.
    y0 : (float, float)
        Initial state at t = 0 (taken as exact binary values).
    t_end : int
        Horizon, a multiple of ``sample_every``.
    step : Fraction
        Taylor step; must divide ``sample_every``.
    degree : int
        Taylor degree.
    sample_every : int or Fraction
        Sampling interval.

    Returns
    -------
    list of (theta_hi, theta_lo, v_hi, v_lo)
    """
    h = Fraction(step)
    per = Fraction(sample_every) / h
    assert per.denominator == 1
    per = int(per)
    nsamp = int(Fraction(t_end) / Fraction(sample_every))
    cst = _constants(beta, gamma, omega, h)
    X, V = _fix(y0[0]), _fix(y0[1])
    out = [_to_hi_lo(X) + _to_hi_lo(V)]
    for _ in range(nsamp):
        for _ in range(per):
            X, V = _step(X, V, h, cst, degree)
        out.append(_to_hi_lo(X) + _to_hi_lo(V))
    return out


def local_step(beta, gamma, omega, theta0, v0, h, degree=40):
    """The state at time h from (θ₀, θ̇₀) (taken as exact binary values).

    Substeps of at most REF_STEP; returns ((theta_hi, theta_lo), (v_hi, v_lo)).
    """
    hf = Fraction(h)
    n = max(1, -(-abs(hf) // REF_STEP))
    hs = hf / n
    cst = _constants(beta, gamma, omega, hs)
    X, V = _fix(theta0), _fix(v0)
    for _ in range(int(n)):
        X, V = _step(X, V, hs, cst, degree)
    return _to_hi_lo(X), _to_hi_lo(V)


def check():
    """Self-consistency and an exact-solution check; returns the three discrepancies.

    * a running pendulum (β = 0.1, γ = 1.2) to t = 20 at the default step and
      degree, against step 1/32 and degree 24;
    * θ'' + sin θ = 0 from (0, 1.999) to t = 50 against 2 arcsin(k sn(t | k²)),
      k = 0.9995, by mpmath at 40 digits (θ and θ').
    """
    from mpmath import asin, ellipfun, mp, mpf

    a = fixed_point_reference(0.1, 1.2, 1.0, (0.0, 0.0), 20)
    b = fixed_point_reference(0.1, 1.2, 1.0, (0.0, 0.0), 20, step=Fraction(1, 32), degree=24)
    d_self = max(abs((x[0] - y[0]) + (x[1] - y[1])) for x, y in zip(a, b))
    c = fixed_point_reference(0.0, 0.0, 1.0, (0.0, 1.999), 50)
    with mp.workdps(40):
        k = mpf(1.999) / 2
        d_th = d_v = 0.0
        for t in (1, 17, 50):
            sn = ellipfun("sn", mpf(t), m=k * k)
            cn = ellipfun("cn", mpf(t), m=k * k)
            d_th = max(d_th, abs(float(2 * asin(k * sn) - mpf(c[t][0]) - mpf(c[t][1]))))
            d_v = max(d_v, abs(float(2 * k * cn - mpf(c[t][2]) - mpf(c[t][3]))))
    return d_self, d_th, d_v


if __name__ == "__main__":
    print("half step / degree 24: %.1e;  exact elliptic: theta %.1e, theta' %.1e" % check())
