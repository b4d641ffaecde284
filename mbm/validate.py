"""Argument checks shared by every entry point: one rule for each argument.

:class:`mbm.MBM`, :func:`mbm.solve`, :func:`mbm.solve_batch`, :func:`mbm.reference`
and the event-point functions validate through these, so a span, a state or a
tolerance is accepted or refused in the same way everywhere.  Each failure is a
``ValueError`` (``TypeError`` for a value of the wrong kind) naming the argument and
the allowed range.  A leaf module: it imports nothing of mbm.
"""

import functools
import inspect
import math
import numbers
import warnings

import numba
import numpy as np

__all__ = [
    "RTOL_FLOOR",
    "WINDOW_MARGIN",
    "ANGLE_PER_WINDOW",
    "DEFAULT_MAX_WINDOWS",
    "PARAMETER_RULES",
    "check_real",
    "check_positive",
    "check_rule",
    "check_real_array",
    "check_rule_array",
    "check_drive",
    "check_span",
    "check_state",
    "check_tolerances",
    "check_t_eval",
    "as_t_eval",
    "t_eval_problem",
    "t_eval_error",
    "check_max_windows",
    "check_window_budget",
    "warn_extraneous",
]

# scipy's rule for rtol (OdeSolver.validate_tol): below 100 machine epsilons the
# round-off of a window's end state is as large as the tolerance, so the tolerance is
# raised to this floor with a warning.  One policy for every entry point.
RTOL_FLOOR = 100 * np.finfo(float).eps

# Windows a run may take before it stops with a failure status: 10⁷ windows are
# 2–10 s of compute (0.3–1 µs a Taylor window), far past any run of the benchmark
# (≤ 10⁵), so only a runaway (e.g. a backward run of a damped scene, which grows like
# e^{β|t|}) reaches it.
DEFAULT_MAX_WINDOWS = 10**7

# The rule of each model parameter beyond "finite" (one wording for every entry
# point): (test, words).
PARAMETER_RULES = {
    "beta": (">=0", ">= 0 (damping)"),
    "omega": (">0", "> 0"),
    "drive_frequency": (">=0", ">= 0 (an angular frequency Omega)"),
}
_RULES = {">=0": lambda v: v >= 0.0, ">0": lambda v: v > 0.0}

# What check_real refuses outright (float() would read a string, a bool, or drop the
# imaginary part of a numpy complex).
_NOT_REAL = (str, bytes, bool, np.bool_, complex, np.complexfloating)

# check_window_budget: a run is refused before it starts only when a lower bound of
# its windows exceeds max_windows this many times (the bound is loose, the run would
# fail at max_windows anyway: no legitimate run is refused).
WINDOW_MARGIN = 100.0
# ... where a window advances θ by at most this many radians: measured ≤ 20 (Taylor)
# and ≤ 260 (split2) on the runaway scenes γ = 1e4–1e6 at rtol 1e-1–1e-6, growing
# like γ^0.06; 1e4 leaves a factor 40 over the largest.
ANGLE_PER_WINDOW = 1.0e4

# The native float64 dtype (an identity test is the cheap one; an equal dtype that is
# another object takes the conversion, which then copies nothing).
_FLOAT64 = np.dtype(np.float64)

def _float(name, value, what="a real number"):
    """``value`` as a float (any real number, not checked for finiteness), or a
    TypeError naming ``name``: str, bytes, bool, complex and arrays of more than one
    element are refused (``float()`` would read a string or drop an imaginary part)."""
    if type(value) is float:
        return value
    if isinstance(value, _NOT_REAL) or (
            isinstance(value, np.ndarray) and (value.ndim != 0 or value.dtype.kind not in "iuf")):
        raise TypeError(f"{name} must be {what}, got {value!r}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be {what}, got {value!r}") from None


def check_real(name, value):
    """``value`` as a finite float, or an error naming ``name``.

    The policy of every entry point for a real argument: a TypeError ("``name`` must
    be a real number") for a str, bytes, bool, complex or a sequence; a ValueError
    ("``name`` must be finite") for nan and ±inf.  Python and numpy integers and
    floats (and 0-d real arrays) are accepted.
    """
    if type(value) is float and value - value == 0.0:
        return value  # the common call: a finite float
    v = _float(name, value)
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {v!r}")
    return v


def check_positive(name, value, allow_inf=False, why=None):
    """``value`` as a float > 0 (finite unless ``allow_inf``), or an error naming ``name``.

    Wording: "``name`` must be > 0, got ..." (with ``why``: "``name`` must be > 0 (why),
    got ..."; ValueError; nan and, unless ``allow_inf``, inf: "``name`` must be
    finite"), and :func:`check_real`'s TypeError.
    """
    if type(value) is float and value > 0.0 and (allow_inf or value != math.inf):
        return value  # the common call, accepted as below without the conversions
    v = _float(name, value)
    if math.isnan(v) or (math.isinf(v) and not allow_inf):
        raise ValueError(f"{name} must be finite, got {v!r}")
    if not v > 0.0:
        raise ValueError(f"{name} must be > 0{'' if why is None else f' ({why})'}, got {v!r}")
    return v


def keywords_named(fn):
    """``fn`` whose calls with too many positional arguments raise a TypeError that names
    the parameters it takes by keyword (Python's own message names none of them)."""
    sig = inspect.signature(fn)
    params = sig.parameters.values()
    positional = [p.name for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    keywords = [p.name for p in params if p.kind == p.KEYWORD_ONLY]

    @functools.wraps(fn)
    def call(*args, **kwargs):
        if len(args) > len(positional):
            takes = ", ".join(positional) if positional else "none"
            extra = ", ".join(f"{k}=..." for k in keywords[:len(args) - len(positional)])
            raise TypeError(f"{fn.__name__}() takes {len(positional)} positional argument(s) ({takes}) but "
                            f"{len(args)} were given; pass the others by keyword ({extra}, ...): the "
                            f"keywords are {', '.join(keywords)}")
        return fn(*args, **kwargs)

    return call


def check_rule(name, value, rule=None):
    """``value`` as a finite float obeying the rule of parameter ``name``
    (:data:`PARAMETER_RULES`; ``rule`` overrides it), or an error naming ``name``."""
    v = check_real(name, value)
    rule = PARAMETER_RULES.get(name) if rule is None else rule
    if rule is not None and not _RULES[rule[0]](v):
        raise ValueError(f"{name} must be {rule[1]}, got {v!r}")
    return v


def check_real_array(name, value):
    """``value`` as a float ndarray of any shape: real numbers only (TypeError naming
    ``name`` for strings, booleans, complex or other objects); not checked for
    finiteness (:func:`check_rule_array`)."""
    arr = np.asarray(value)
    kind = arr.dtype.kind
    if kind == "O" and all(isinstance(x, numbers.Real) and not isinstance(x, (bool, np.bool_))
                           for x in arr.reshape(-1)):
        kind = "f"
    if kind not in "iuf":
        raise TypeError(f"{name} must be a real number or an array of real numbers, got {value!r}")
    return arr.astype(float)


def check_rule_array(name, arr, rule=None):
    """Check a float array (:func:`check_real_array`) element-wise: finite and, for a
    parameter of :data:`PARAMETER_RULES` (or ``rule``), its rule; the first bad
    element is named, as ``name[i]`` (``name`` for a 0-d array)."""
    rule = PARAMETER_RULES.get(name) if rule is None else rule
    flat = np.asarray(arr, dtype=float).reshape(-1)
    for words, ok in (("finite", np.isfinite), (None if rule is None else rule[1],
                                                 None if rule is None else _RULES[rule[0]])):
        if words is None:
            continue
        bad = np.flatnonzero(~ok(flat))
        if bad.size:
            i = int(bad[0])
            where = f"{name}[{i}] = " if np.ndim(arr) else ""
            raise ValueError(f"{name} must be {words}, got {where}{float(flat[i])!r}")
    return arr


def check_drive(amplitude, frequency, index=None):
    """A drive A sin(Ωt + φ) with A ≠ 0 needs Ω > 0: the ValueError otherwise (arrays:
    the first such scene is named)."""
    amp, freq = np.asarray(amplitude, dtype=float), np.asarray(frequency, dtype=float)
    bad = (amp != 0.0) & ~(freq > 0.0)
    if np.any(bad):
        if np.ndim(bad):
            i = int(np.flatnonzero(np.broadcast_to(bad, np.broadcast(amp, freq).shape).reshape(-1))[0])
            f = float(np.broadcast_to(freq, bad.shape).reshape(-1)[i])
            got = f"drive_frequency[{i}] = {f!r}"
        else:
            got = repr(float(freq))
        raise ValueError(f"drive_frequency must be > 0 with a drive (drive_amplitude != 0), got {got}")


def check_span(t_span, allow_empty=True):
    """``(t0, t_bound)`` as finite floats; ``allow_empty=False`` refuses t0 == t_bound."""
    try:
        if len(t_span) != 2:
            raise ValueError
        first, last = t_span[0], t_span[1]
    except (TypeError, ValueError, IndexError, KeyError):
        raise ValueError(_pair_message(t_span)) from None
    try:
        t0, t1 = _float("t_span", first), _float("t_span", last)
    except TypeError:
        raise TypeError(_pair_message(t_span)) from None
    if not (math.isfinite(t0) and math.isfinite(t1)):
        raise ValueError(f"t_span must be finite, got {t_span!r}")
    if not allow_empty and t0 == t1:
        raise ValueError(f"t_span must have t0 != t_bound, got {t_span!r}")
    return t0, t1


def _pair_message(t_span):
    # check_span's message, formatted only when it is raised (a repr costs every call).
    return f"t_span must be a pair of real numbers (t0, t_bound), got {t_span!r}"


def check_state(name, y0):
    """``y0`` as a finite float array of shape (2,), or an error naming ``name``
    (TypeError for what is not real numbers, ValueError for a wrong shape or a non-finite value)."""
    try:
        y = check_real_array(name, y0)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be array_like of 2 real numbers [theta, theta'], got {y0!r}") from None
    if y.shape != (2,):
        raise ValueError(f"{name} must have shape (2,) ([theta, theta']), got shape {y.shape}")
    if not np.all(np.isfinite(y)):
        raise ValueError(f"{name} must be finite, got {y0!r}")
    return y


def check_tolerances(rtol, atol, stacklevel=3):
    """``(rtol, atol)`` as floats: positive and finite; rtol below :data:`RTOL_FLOOR`
    is raised to it with a warning (scipy's rule)."""
    if type(rtol) is float and type(atol) is float and RTOL_FLOOR <= rtol < math.inf and 0.0 < atol < math.inf:
        return rtol, atol  # the common call, accepted as below without the conversions
    rtol = check_positive("rtol", rtol)
    atol = check_positive("atol", atol)
    if rtol < RTOL_FLOOR:
        warnings.warn(
            f"rtol={rtol!r} is below 100 machine epsilons; using rtol={RTOL_FLOOR:.3g}",
            stacklevel=stacklevel,
        )
        rtol = RTOL_FLOOR
    return rtol, atol


@numba.njit(cache=True)
def t_eval_problem(t_eval, t0, t1, strict):
    """0 if ``t_eval`` passes :func:`check_t_eval`, else what is wrong: 1 non-finite,
    2 outside t_span, 3 not sorted in the direction of integration (``strict``:
    strictly).  Compiled in one pass (also called from :mod:`mbm.frontends.solve`'s compiled
    entry, so a short run pays no separate dispatch for it)."""
    lo, hi = min(t0, t1), max(t0, t1)
    direction = 1.0 if t1 >= t0 else -1.0
    for i in range(t_eval.size):
        x = t_eval[i]
        if not math.isfinite(x):
            return 1
        if x < lo or x > hi:
            return 2
        if i > 0:
            d = direction * (x - t_eval[i - 1])
            if d < 0.0 or (strict and d == 0.0):
                return 3
    return 0


def as_t_eval(t_eval):
    """``t_eval`` as a C-contiguous, aligned, writeable 1-D float64 array (the array
    itself when it is one; TypeError for what is not real numbers), otherwise unchecked:
    :func:`check_t_eval` without its check, for
    callers that run :func:`t_eval_problem` in compiled code of their own (a read-only
    or unaligned array is copied: compiled code would otherwise be specialized again
    for it, minutes of compiling)."""
    te = t_eval
    # flags.carray: C-contiguous, aligned and writeable (what compiled code is typed for).
    if not (type(te) is np.ndarray and te.ndim == 1 and te.dtype is _FLOAT64 and te.flags.carray):
        te = np.ascontiguousarray(check_real_array("t_eval", t_eval)).reshape(-1)
        if not te.flags.carray:
            te = te.copy()
    return te


def t_eval_error(problem, t0, t1, strict=False):
    """The ValueError of a :func:`t_eval_problem` code (1, 2 or 3)."""
    if problem == 1:
        return ValueError("t_eval must be finite")
    if problem == 2:
        return ValueError(f"t_eval must lie within t_span {(t0, t1)!r}")
    return ValueError(
        f"t_eval must be {'strictly monotonic' if strict else 'sorted'} in the direction of "
        f"integration ({'increasing' if t1 >= t0 else 'decreasing'})"
    )


def check_t_eval(t_eval, t0, t1, strict=False):
    """``t_eval`` as a contiguous float array within the span, sorted in the direction
    of integration (``strict``: strictly), or a ValueError."""
    te = as_t_eval(t_eval)
    problem = t_eval_problem(te, t0, t1, strict)
    if problem != 0:
        raise t_eval_error(problem, t0, t1, strict)
    return te


def check_integer(name, value, least):
    """``value`` as an int ≥ ``least``: a TypeError ("``name`` must be an integer") for a
    bool or a non-integer, a ValueError ("``name`` must be >= least") below it."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {value!r}")
    if value < least:
        raise ValueError(f"{name} must be >= {least}, got {value!r}")
    return int(value)


def check_max_windows(max_windows):
    """``max_windows`` as an int ≥ 1, or a ValueError."""
    if type(max_windows) is int and max_windows >= 1:
        return max_windows
    if isinstance(max_windows, (bool, np.bool_)) or not isinstance(max_windows, (int, np.integer)):
        raise ValueError(f"max_windows must be an integer >= 1, got {max_windows!r}")
    if max_windows < 1:
        raise ValueError(f"max_windows must be an integer >= 1, got {max_windows!r}")
    return int(max_windows)


def _transient_angle(beta, gamma, omega, v0, span):
    """A lower bound of the angle a forward, undriven run covers while no regime of
    :mod:`mbm.regimes` can take over, and the time it takes (0, 0 when no bound).

    Only |γ| > ω² has one: no equilibrium (no locked regime, no libration), and the
    velocity obeys s·v' ≥ F − β s·v, s = sign γ, F = |γ| − ω² (comparison with the
    linear equation: v ≥ v_low).  At β = 0 nothing else can happen over the span;
    for β > 0 only while the fastest solution (F + 2ω² in place of F) is below half
    the cycle's least velocity F/β: the return map's steps then are ≥ F·T_c/2, so the
    cycle watch cannot see a converged cycle.
    """
    w2 = omega * omega
    f = abs(gamma) - w2
    if not f > 0.0 or not span > 0.0:
        return 0.0, 0.0
    u0 = math.copysign(1.0, gamma) * v0
    if beta == 0.0:
        t = span
        # ∫ max(0, u0 + f t) dt over [0, t]
        if u0 >= 0.0:
            return u0 * t + 0.5 * f * t * t, t
        t_pos = -u0 / f
        return (0.5 * f * (t - t_pos) ** 2 if t > t_pos else 0.0), t
    fast = (f + 2.0 * w2) / beta
    half = 0.5 * f / beta
    if u0 >= half:
        return 0.0, 0.0
    # the fastest solution fast + (u0 − fast) e^{−βt} reaches `half` at t_half
    t = min(span, math.log((fast - u0) / (fast - half)) / beta)
    a = f / beta
    c = u0 - a
    # ∫ max(0, a + c e^{−βs}) ds over [0, t]: v_low increases from u0 (< a) to its end
    t_pos = 0.0 if u0 >= 0.0 else math.log(c / -a) / beta
    if t <= t_pos:
        return 0.0, t
    angle = a * (t - t_pos) + (c / beta) * (math.exp(-beta * t_pos) - math.exp(-beta * t))
    return max(angle, 0.0), t


def check_window_budget(beta, gamma, omega, drive_amplitude, t0, t1, v0, tau, *, max_step, max_windows,
                        exact=False):
    """Refuse a run whose windows would exceed ``max_windows`` by a wide margin, before it runs.

    A lower bound of the windows (:func:`_transient_angle`: the angle covered at most
    :data:`ANGLE_PER_WINDOW` radians a window, and the time in windows of at most
    ``tau`` or ``max_step``) above :data:`WINDOW_MARGIN` · ``max_windows`` is a
    ValueError naming the parameter that causes it.  Backward and driven runs and
    exact flows are not predicted (no bound: they run, and stop at ``max_windows``
    with its status).
    """
    if drive_amplitude != 0.0 or not t1 > t0 or exact:
        return
    span = t1 - t0
    limit = WINDOW_MARGIN * max_windows
    w2 = omega * omega
    # the cheap test first: the most the run can cover, |θ'| ≤ |v0| + (|γ| + ω²)·t
    longest = min(math.inf if tau is None else tau, max_step)
    if (abs(v0) + (abs(gamma) + w2) * span) * span < limit * ANGLE_PER_WINDOW and span < limit * longest:
        return
    angle, t = _transient_angle(beta, gamma, omega, v0, span)
    by_angle, by_time = angle / ANGLE_PER_WINDOW, t / longest
    if tau is not None:
        by_angle = 0.0  # fixed windows: their count is the time's
    n = max(by_angle, by_time)
    if n <= limit:
        return
    if by_angle >= by_time:
        cause = (f"gamma={gamma!r} (with beta={beta!r}, omega={omega!r}"
                 + (f", theta'0={v0!r}" if v0 != 0.0 else "") + ")")
        why = f"θ runs through more than {angle:.3g} rad, at most {ANGLE_PER_WINDOW:g} rad a window"
        fix = "lower |gamma|, shorten t_span or raise max_windows"
    else:
        name = "tau" if tau is not None and tau <= max_step else "max_step"
        cause = f"{name}={longest!r} over t_span {(t0, t1)!r} with gamma={gamma!r}"
        why = f"{t:.3g} time units before any regime can take over"
        fix = f"raise {name}, shorten t_span or raise max_windows"
    raise ValueError(
        f"{cause} would take more than {n:.3g} windows, {n / max_windows:.3g} times "
        f"max_windows={max_windows} ({why}): the run would stop at max_windows; {fix}"
    )


def warn_extraneous(extraneous, stacklevel=3):
    """Warn that options in ``extraneous`` have no effect (scipy's ``warn_extraneous``)."""
    if extraneous:
        warnings.warn(
            "The following arguments have no effect for the MBM solver: "
            + ", ".join(f"`{x}`" for x in extraneous),
            stacklevel=stacklevel,
        )
