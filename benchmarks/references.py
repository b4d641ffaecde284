r"""The references the benchmark's errors are measured against.

:func:`scene_reference` gives θ_ref at a scene's output times, its source, and an
independent check:

* β = γ = 0 (P6): the exact elliptic flow :func:`mbm.pendulum_flow`;
* otherwise, with mpmath: :func:`fixed_point_reference`, a degree-28 Taylor
  integrator in 128-bit fixed point (mpmath's fixed-point sine and cosine,
  ~1e-20), because CVODE at rtol = atol = 1e-13 is itself off by 2e-8 on P5 and
  4e-8 on P6;
* ``method="heyoka-ld"``, or without mpmath: :func:`heyoka_ld_reference`, heyoka's
  Taylor integrator in 80-bit long double at tol 1e-19 (seconds where the fixed
  point takes minutes: P4 costs ~90 s in fixed point);
* without either: CVODE at :data:`REF_TOL`, checked against the numba DOP853 of
  :mod:`benchmarks.peers`; targets within :data:`REF_MARGIN` of that difference are
  flagged in the report.

Each reference is checked against CVODE at 1e-13 (:func:`mbm.reference`) and the
difference reported.  References are cached as ``.npz`` files in
:func:`default_cache_dir` (not in the repository).
"""

import hashlib
import math
import os
from fractions import Fraction
from pathlib import Path

import numpy as np

import mbm

from . import peers
from .scenes import N_OUTPUT

__all__ = [
    "REF_TOL",
    "REF_MARGIN",
    "REFERENCE_METHODS",
    "default_cache_dir",
    "fixed_point_reference",
    "heyoka_ld_available",
    "heyoka_ld_reference",
    "scene_reference",
    "reference_uncertainty",
]

# CVODE tolerance (rtol = atol) of the check of each reference, and of the
# reference itself when neither mpmath nor heyoka is there.  Measured against the
# fixed-point reference it is off by 2e-11 (P2), 7e-11 (P4), 4e-9 (P5 at t <= 200:
# rtol·|θ| with |θ| ~ 1e3) and 4e-8 (P6, next to the separatrix).
REF_TOL = 1e-13

# Fixed-point Taylor reference (mpmath's fixed-point sin/cos, Python integers):
# 2^-128 per operation keeps 2e5 steps of ~1e3 operations below 1e-30; degree 28
# with steps <= 1/16 gives a truncation (h/R)^29 <= 1e-23 per step even on the
# running scene, whose Taylor radius R ~ 0.4 is the smallest.
REF_BITS = 128
REF_DEGREE = 28
REF_MAX_STEP = 1.0 / 16.0

# heyoka's tolerance in 80-bit long double (machine epsilon 1.08e-19): at the
# precision's end, so its error is the round-off of ~1e4 steps in 64-bit mantissas.
HEYOKA_LD_TOL = 1e-19

# Tolerance of the independent check of a CVODE reference (numba DOP853, used
# only when the other references are missing); its difference from the reference
# bounds the larger of the two errors.
REF_CHECK_TOL = 1e-13

# With a CVODE reference, a target below REF_MARGIN x the reference discrepancy is
# flagged: errors there are measured against a reference no better than the target.
REF_MARGIN = 10.0

# A fixed-point, heyoka or exact reference that differs from its CVODE check by more
# than this is a bug, not a tolerance effect (CVODE at 1e-13 is within 1e-7 everywhere).
REF_SANITY = 1e-6

# Bump when the reference computation changes, to invalidate cached references.
REFERENCE_VERSION = 2

# Names scene_reference accepts for its method (β = γ = 0 is always the exact flow).
REFERENCE_METHODS = ("auto", "fixed-point", "heyoka-ld", "cvode")


def default_cache_dir():
    """Where references are cached: ``$MBM_BENCH_CACHE``, else ``$XDG_CACHE_HOME/mbm-bench``
    (``~/.cache/mbm-bench``)."""
    env = os.environ.get("MBM_BENCH_CACHE")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "mbm-bench"


def _reference_key(scene, method):
    payload = repr((REFERENCE_VERSION, method, tuple(scene.params()), N_OUTPUT, REF_TOL,
                    REF_CHECK_TOL, REF_BITS, REF_DEGREE, REF_MAX_STEP, HEYOKA_LD_TOL))
    return hashlib.sha1(payload.encode()).hexdigest()[:16]


def _fp_step(X, V, cst, degree):
    """One degree-``degree`` Taylor step of θ'' = γ − βθ' − ω² sin θ in fixed point.

    X, V are θ, θ' scaled by 2^REF_BITS; ``cst`` = (βh, γh², ω²h², h) scaled the
    same way.  Scaled coefficients A_k = a_k h^k (all of size (h/R)^k, so nothing
    over- or underflows) follow from s = sin θ, c = cos θ, s' = cθ', c' = −sθ':

        k S_k = Σ_{j=1}^{k} j A_j C_{k−j},   k C_k = −Σ_{j=1}^{k} j A_j S_{k−j},
        (k+1)(k+2) A_{k+2} = γh² δ_{k0} − βh (k+1) A_{k+1} − ω²h² S_k,

    and θ(h) = Σ A_k, θ'(h) = Σ k A_k / h.  (``tests/data/convergent_fixed_point.py``
    carries its own copy for the tests' reference file; the two are checked against
    each other in ``tests/bench/test_bench.py``.)
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


def fixed_point_reference(scene):
    """θ at the scene's output times to ~1e-20: a Taylor integrator in 128-bit fixed point.

    Degree :data:`REF_DEGREE`, steps of at most :data:`REF_MAX_STEP` dividing the
    output spacing exactly (rational arithmetic), the scene's float parameters and
    initial state taken as exact binary numbers.  Needs mpmath (its fixed-point
    sine and cosine).  Costs ~0.5 ms per step: ~1 s for P1-P3, ~10 s for P5,
    ~90 s for P4 (cached by :func:`scene_reference`).

    Parameters
    ----------
    scene : benchmarks.scenes.BenchScene

    Returns
    -------
    ndarray, shape (N_OUTPUT,)
    """
    one = 1 << REF_BITS

    def fix(x):
        return round(Fraction(x) * one)

    dt_out = Fraction(scene.t_end) / (N_OUTPUT - 1)
    n_sub = math.ceil(dt_out / Fraction(REF_MAX_STEP))
    h = dt_out / n_sub
    b, g, w = Fraction(scene.beta), Fraction(scene.gamma), Fraction(scene.omega)
    cst = (fix(b * h), fix(g * h * h), fix(w * w * h * h), fix(h))
    X, V = fix(scene.theta0), fix(scene.v0)
    out = np.empty(N_OUTPUT)
    out[0] = float(Fraction(X, one))
    for i in range(1, N_OUTPUT):
        for _ in range(n_sub):
            X, V = _fp_step(X, V, cst, REF_DEGREE)
        out[i] = float(Fraction(X, one))
    return out


def heyoka_ld_available():
    """Whether heyoka is installed and ``numpy.longdouble`` is wider than a double."""
    return peers.heyoka_module() is not None and np.finfo(np.longdouble).eps < 1e-18


_HEYOKA_LD = {}


def heyoka_ld_reference(scene, t_eval=None):
    """θ at ``t_eval`` (default the scene's) by heyoka in long double at tol 1e-19.

    The 80-bit x87 format of x86-64 (64-bit mantissa): ~1e-19 per step, so a
    reference good to well below the benchmark's tightest target (1e-9) in
    milliseconds, where :func:`fixed_point_reference` takes seconds to minutes.

    Parameters
    ----------
    scene : benchmarks.scenes.BenchScene
    t_eval : ndarray, optional

    Returns
    -------
    ndarray of float64

    Raises
    ------
    RuntimeError
        If heyoka is not installed or long double is no wider than double here.
    """
    if not heyoka_ld_available():
        raise RuntimeError("heyoka in long double needs heyoka and an 80-bit long double "
                           "(x86-64)")
    if "peer" not in _HEYOKA_LD:
        _HEYOKA_LD["peer"] = peers.HeyokaPeer(np.longdouble)
    out = _HEYOKA_LD["peer"].propagate(scene, HEYOKA_LD_TOL, t_eval)
    return np.asarray(out[:, 0], dtype=float)


def _have_mpmath():
    try:
        import mpmath  # noqa: F401
    except ImportError:
        return False
    return True


def scene_reference(scene, cache_dir=None, method="auto"):
    """θ_ref at the scene's output times, its source, and an independent check.

    Parameters
    ----------
    scene : benchmarks.scenes.BenchScene
    cache_dir : path-like, None or False
        Cache directory (default :func:`default_cache_dir`); ``False`` disables
        the cache.
    method : {"auto", "fixed-point", "heyoka-ld", "cvode"}
        The reference where β or γ is non-zero (β = γ = 0 is always the exact
        flow).  ``"auto"``: the fixed point with mpmath, else heyoka in long double,
        else CVODE.

    Returns
    -------
    dict
        ``theta`` (ndarray (201,)), ``method``, ``check_method`` (str), ``check``
        (max |θ_ref − θ_check|, i.e. mostly the check's own error for an exact,
        fixed-point or heyoka reference), ``uncertainty`` (the reference's own error
        scale: 0 for exact, fixed-point and heyoka references, ``check`` for CVODE).

    Raises
    ------
    ValueError
        For an unknown ``method``.
    RuntimeError
        If CVODE fails, the requested reference is unavailable, or an exact,
        fixed-point or heyoka reference and its check differ by more than
        :data:`REF_SANITY`.
    """
    if method not in REFERENCE_METHODS:
        raise ValueError(f"unknown reference method {method!r}; choose from {REFERENCE_METHODS}")
    if cache_dir is None:
        cache_dir = default_cache_dir()
    path = None
    if cache_dir is not False:
        path = Path(cache_dir) / f"ref_{scene.name}_{_reference_key(scene, method)}.npz"
        if path.exists():
            with np.load(path) as z:
                return {
                    "theta": z["theta"],
                    "method": str(z["method"]),
                    "check_method": str(z["check_method"]),
                    "check": float(z["check"]),
                    "uncertainty": float(z["uncertainty"]),
                }
    model, t = scene.model, scene.t_eval
    cvode = mbm.reference(model, scene.t_span, scene.y0, t_eval=t, rtol=REF_TOL, atol=REF_TOL)
    if not cvode.success:
        raise RuntimeError(f"CVODE failed on {scene.name}: {cvode.message}")
    cvode_name = f"CVODE Adams rtol=atol={REF_TOL:g}"
    fell_back = False
    if method == "auto":
        method = ("fixed-point" if _have_mpmath()
                  else "heyoka-ld" if heyoka_ld_available() else "cvode")
        fell_back = method == "cvode"
    check, check_method, unc = cvode.y[0], cvode_name, 0.0
    if scene.beta == 0.0 and scene.gamma == 0.0:
        theta = np.asarray(mbm.pendulum_flow(model, scene.y0, t))[0]
        name = "exact (mbm.pendulum_flow)"
    elif method == "fixed-point":
        if not _have_mpmath():
            raise RuntimeError("the fixed-point reference needs mpmath (pip install mpmath)")
        theta = fixed_point_reference(scene)
        name = f"Taylor degree {REF_DEGREE}, {REF_BITS}-bit fixed point (mpmath)"
    elif method == "heyoka-ld":
        theta = heyoka_ld_reference(scene)
        name = f"heyoka long double, tol {HEYOKA_LD_TOL:g}"
    else:
        theta = cvode.y[0]
        name = cvode_name + (" (mpmath and heyoka missing)" if fell_back else "")
        peers.compile_numba_peers()
        check = peers.dop853_run(scene.beta, scene.gamma, scene.omega ** 2, scene.theta0,
                                 scene.v0, t, REF_CHECK_TOL, REF_CHECK_TOL, peers.MAX_STEPS)[0]
        check_method = f"numba DOP853 rtol=atol={REF_CHECK_TOL:g}"
        unc = None
    diff = float(np.max(np.abs(np.asarray(check) - theta)))
    if unc is None:
        unc = diff
    elif not diff <= REF_SANITY:
        raise RuntimeError(f"reference of {scene.name} ({name}) and its check ({check_method}) "
                           f"differ by {diff:.2e}")
    out = {"theta": np.asarray(theta, dtype=float), "method": name,
           "check_method": check_method, "check": diff, "uncertainty": unc}
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(path.stem + ".tmp.npz")
        np.savez(tmp, **out)
        os.replace(tmp, path)
    return out


def reference_uncertainty(ref):
    """The error scale below which a scene's errors are not resolved (0: exact or ~1e-20)."""
    return ref["uncertainty"]
