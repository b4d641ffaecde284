"""The probing of plain callables: which member of the pendulum family a ``fun(t, y)`` is.

:func:`identify_model` finds β, γ, ω of  θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ)  and,
when ``fun`` depends on t, the drive A, Ω, φ; :func:`check_model` checks a given
``model=`` against ``fun``.  Both end in a verification of the model against ``fun`` at
many states and times across the whole span, its end included, to round-off.

The drive is found in three steps, on g(t) = fun(t, [0, 0])[1] = γ + A sin(Ωt + φ):

1. a coarse Ω from bursts of equally spaced samples (Prony: the differences d_k of
   a sinusoid plus a constant obey d_{k+1} + d_{k-1} = 2 cos(Ωh) d_k), the spacing h
   shrunk by :data:`PRONY_RATIO` until two spacings agree (no aliasing);
2. Gauss–Newton on (γ, A, φ, Ω) over windows growing by :data:`STAGE_GROWTH` from the
   burst to the whole span: each stage's Ω keeps the phase at the next stage's end
   well inside Newton's basin, and the last stage, sampled up to the span's end, fixes
   Ω to the round-off of the phase Ωt there;
3. the verification: at :data:`VERIFY_TIMES` fresh times (t_bound itself and times just
   before it among them), at θ = θ' = 0 and at other states (the time part must be
   additive), fun and the model agree within :data:`ROUNDOFF_ULPS` round-offs of the
   terms, the drive's argument Ωt + φ included.  So the phase at t_bound is that of
   ``fun`` to a few ulps of Ω·t_bound: an Ω off by k ulps moves it by k ulps of Ωt.
"""

import math

import numpy as np

from ..model import Pendulum

__all__ = ["identify_model", "check_model"]

EPS = float(np.finfo(float).eps)
_FLOAT64 = np.dtype(np.float64)
_FLOATS = (float, np.float64)
# Relative tolerance for accepting an autonomous callable as a member of the family:
# a member reproduces the fitted β, γ, ω² to round-off (a few ulps of the largest
# term), anything above this is a different equation.
PROBE_RTOL = 1e-10
# Probe states (θ, θ', t) used to check the fit after β, γ, ω² are identified;
# chosen off the identification states, with large |θ| and non-zero t so that a θ³
# term or a time dependence shows up.
PROBE_CHECK_STATES = (
    (0.7, -1.3, 0.37),
    (-2.1, 0.4, 3.1),
    (2.9, 2.2, -1.7),
    (11.3, -0.8, 12.9),
    (-0.3, 5.5, 100.25),
)
# Times at which g(t) = fun(t, [0, 0])[1] is compared with g(t0) to decide whether fun
# depends on t (spread over the span; an undriven fun gives the same bits at each).
DETECT_TIMES = 8
# Shortest window the drive is sought over, in small-oscillation periods 2π/ω: a short
# (or empty) span is widened to it, so that a drive of a few periods is seen whole.
MIN_WINDOW_PERIODS = 8.0
# Samples per Prony burst (7 differences, 5 recurrence equations: an overdetermined fit).
PRONY_SAMPLES = 8
# Ratio of successive burst spacings: irrational, so that an alias at one spacing is
# not one at the next (they would agree on a wrong Ω).
PRONY_RATIO = math.e
# Most spacings tried, from a window/8 down: 24 spans e^24 ≈ 3e10 of Ω·window.
PRONY_MAX_SCALES = 24
# Least phase Ωh between samples for a burst's Ω to count: below, cos(Ωh) is 1 to
# round-off and any curve (two frequencies, a drift) looks like a slow sinusoid.
PRONY_MIN_PHASE = 1e-3
# Two spacings agree on Ω to this relative difference: no alias at either.
PRONY_AGREE = 1e-6
# A burst whose differences miss the recurrence by more than this (relative to their
# size) is not a sinusoid at that spacing (round-off or another shape).
PRONY_RESIDUAL = 1e-5
# Growth of the fitted window per Gauss–Newton stage: a stage fixes Ω to ~1e-12 of a
# radian over its window, far inside Newton's basin over 64 windows.
STAGE_GROWTH = 64.0
# Samples per Gauss–Newton stage (four unknowns; the rest checks the shape).
STAGE_SAMPLES = 16
# Gauss–Newton iterations per stage at most (quadratic convergence: 3 or 4 suffice).
NEWTON_ITERATIONS = 8
# Fresh times of the final verification (t_bound and 4 times just before it included).
VERIFY_TIMES = 48
# Round-offs (units of eps times the size of the terms, the drive's argument Ωt + φ
# included) by which fun and the model may differ; above, they are different equations.
# Measured: 4 suffice for the client forms of benchmarks/driven_clients.py and drives
# over spans to 1e7 or starting at t = 1e6 (2 do not); 16 leaves room for a fun that
# rounds more (2*np.pi*(f*t), several divisions).
ROUNDOFF_ULPS = 16
# A parameter of model= differs from fun's when it moves the right-hand side by more
# than this, relative to its size (the drive's Ω over the span's length).
PARAM_RTOL = 1e-9


class _Probe:
    """``fun`` called at a state (θ, θ') and time t, counting the calls; g(t) cached."""

    def __init__(self, fun):
        self.fun = fun
        self.nfev = 0
        self._g = {}

    def __call__(self, t, theta, v):
        return np.asarray(self.values(t, theta, v), dtype=float)

    def values(self, t, theta, v):
        """fun's two values at (t, θ, θ'): a list of two floats as fun gave it, else an array."""
        self.nfev += 1
        out = self.fun(t, np.array((theta, v)))
        if type(out) is list and len(out) == 2 and type(out[0]) in _FLOATS and type(out[1]) in _FLOATS:
            return out
        if type(out) is not np.ndarray or out.dtype is not _FLOAT64 or out.shape != (2,):
            out = np.asarray(out, dtype=float).reshape(-1)  # a list, another dtype or shape
            if out.shape != (2,):
                raise ValueError(f"fun must return 2 values for a pendulum state, got shape {out.shape}")
        return out

    def g(self, t):
        """The second component at θ = θ' = 0: γ + the time part."""
        t = float(t)
        if t not in self._g:
            self._g[t] = float(self.values(t, 0.0, 0.0)[1])
        return self._g[t]


NOT_FAMILY = (
    "fun is not of the pendulum family theta'' + beta*theta' + omega**2*sin(theta) = "
    "gamma + A*sin(Omega*t + phi) (first component theta', second gamma + A*sin(Omega*t + phi) "
    "- beta*theta' - omega**2*sin(theta)); MBM solves only that family"
)
NOT_ADDITIVE = (
    "; fun depends on t where theta or theta' is not 0, but not at theta = theta' = 0: its "
    "time dependence is not added to the torque (multiplicative?), and MBM integrates only "
    "the drive gamma + A*sin(Omega*t + phi) added to it."
)


def identify_model(fun, t0=0.0, t_bound=None):
    """Identify the pendulum-family member θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ) a
    right-hand side ``fun(t, y)`` is.

    The second component is linear in the basis (1, θ', sin θ) at each t, the first must
    be θ'.  Three probe states at ``t0`` identify γ(t0), β and ω².  When
    g(t) = fun(t, [0, 0])[1] does not change over the span, further states (with other t)
    check the autonomous fit; when it does, the drive γ + A sin(Ωt + φ) is fitted to
    g and the model is verified against ``fun`` across the span (module docstring).

    Parameters
    ----------
    fun : callable
        ``fun(t, y)`` returning an array_like of shape (2,).
    t0 : float, optional
        Start of the span (the probes' time origin).
    t_bound : float, optional
        End of the span (default ``t0``: the drive is then sought over
        ``MIN_WINDOW_PERIODS`` small-oscillation periods after ``t0``, as for any span
        shorter than that).

    Returns
    -------
    model : Pendulum
        The identified member (``fun`` itself when it already is a Pendulum), a drive
        with A > 0, Ω > 0 and φ in [−π, π].
    nfev : int
        Number of calls made to ``fun``.

    Raises
    ------
    ValueError
        If ``fun`` is not of the family with β ≥ 0, ω > 0, or depends on t otherwise
        than through γ + A sin(Ωt + φ); the message names what was found.
    """
    if isinstance(fun, Pendulum):
        return fun, 0
    t0 = float(t0)
    t_bound = t0 if t_bound is None else float(t_bound)
    p = _Probe(fun)
    g = p.g(t0)
    gb = float(p(t0, 0.0, 1.0)[1])
    gw = float(p(t0, 0.5 * math.pi, 0.0)[1])
    gamma, beta, w2 = g, g - gb, g - gw
    if not all(math.isfinite(x) for x in (gamma, beta, w2)):
        raise ValueError(NOT_FAMILY + " (non-finite values at probe states)")
    window = _window(t0, t_bound, w2)
    # off any regular grid, so that no drive period divides their spacing
    times = _stage_times(t0, window, DETECT_TIMES)
    times[-1] = t_bound if t_bound != t0 else times[-1]
    if all(abs(p.g(t) - g) <= 4 * EPS * abs(g) for t in times):
        _check_autonomous(p, t0, gamma, beta, w2)
        return _checked_pendulum(beta, gamma, w2), p.nfev
    if not (w2 > 0.0 and beta >= 0.0):
        _checked_pendulum(beta, gamma, w2)
    gamma, amp, freq, phase = _fit_drive(p, t0, window)
    model = _checked_pendulum(beta, gamma, w2, amp, freq, phase)
    bad = _first_mismatch(p, model, _verify_times(t0, t_bound, window))
    if bad is not None:
        raise ValueError(_mismatch_message(bad, model))
    return model, p.nfev


def _window(t0, t_bound, w2):
    """The signed span the drive is sought over: the span, at least MIN_WINDOW_PERIODS."""
    direction = 1.0 if t_bound >= t0 else -1.0
    natural = MIN_WINDOW_PERIODS * 2 * math.pi / math.sqrt(w2) if w2 > 0.0 else MIN_WINDOW_PERIODS
    return direction * max(abs(t_bound - t0), natural)


def _check_autonomous(p, t0, gamma, beta, w2):
    """The autonomous fit checked at PROBE_CHECK_STATES (as before drives were probed)."""
    for theta, v, t in PROBE_CHECK_STATES:
        out = p(t0 + t, theta, v)
        expect = gamma - beta * v - w2 * math.sin(theta)
        scale = abs(gamma) + abs(beta * v) + abs(w2) + 1e-300
        if not (abs(out[0] - v) <= PROBE_RTOL * (abs(v) + 1.0)) or not (
            abs(out[1] - expect) <= PROBE_RTOL * scale
        ):
            where = f" (mismatch at theta={theta}, theta'={v}, t={t0 + t}: fun gives {out.tolist()}, " \
                    f"the fit [{v}, {expect!r}])"
            # The same state at another time: a different value means fun depends on t.
            other = p(t0 + t + 1.0 / 3.0 + 2.0**-0.5, theta, v)
            if np.any(np.abs(other - out) > PROBE_RTOL * (np.abs(out) + scale)):
                raise ValueError(NOT_FAMILY + where + NOT_ADDITIVE)
            raise ValueError(NOT_FAMILY + where)


def _checked_pendulum(beta, gamma, w2, amp=0.0, freq=0.0, phase=0.0):
    if w2 <= 0.0:
        raise ValueError(f"fun is of the pendulum form but with omega**2 = {w2!r}; omega**2 must be > 0")
    if beta < 0.0:
        raise ValueError(f"fun is of the pendulum form but with beta = {beta!r}; beta must be >= 0")
    return Pendulum(beta=beta, gamma=gamma, omega=math.sqrt(w2), drive_amplitude=amp,
                    drive_frequency=freq, drive_phase=phase)


def _not_drive(p, what):
    """The refusal of a time dependence that is no single sinusoid, with samples of it."""
    ts = sorted(p._g)[:: max(1, len(p._g) // 6)][:6]
    samples = ", ".join(f"g({t!r}) = {p._g[t]!r}" for t in ts)
    return ValueError(
        "fun's time dependence is not gamma + A*sin(Omega*t + phi) (the one MBM integrates): "
        f"{what}; g(t) = fun(t, [0, 0])[1] sampled: {samples}."
    )


def _prony(s, h):
    """Ω from equally spaced samples ``s`` (spacing h) of γ + A sin(Ωt + φ), or None."""
    d = np.diff(np.asarray(s))
    mid, side = d[1:-1], d[2:] + d[:-2]
    den = 2.0 * float(mid @ mid)
    if den == 0.0:
        return None
    c = float(mid @ side) / den
    if np.max(np.abs(side - 2.0 * c * mid)) > PRONY_RESIDUAL * np.max(np.abs(d)):
        return None
    if abs(c) > 1.0 + PRONY_RESIDUAL:
        return None
    return math.acos(min(1.0, max(-1.0, c))) / h


def _coarse_frequency(p, t0, window):
    """Ω from bursts of shrinking spacing, the first two spacings that agree; the burst's span."""
    h = window / PRONY_SAMPLES
    previous = None
    for j in range(PRONY_MAX_SCALES):
        est = _prony([p.g(t0 + k * h) for k in range(PRONY_SAMPLES)], abs(h))
        if j == 1 and est is not None and previous is not None and max(est, previous) * abs(window) < 1e-3:
            raise _not_drive(p, f"it changes without oscillating over the span (Omega found "
                                f"{est!r}: a ramp or a slow drift?)")
        if (est is not None and previous is not None and abs(est - previous) <= PRONY_AGREE * est
                and est * abs(h) >= PRONY_MIN_PHASE):
            return est, (PRONY_SAMPLES - 1) * h
        previous = est
        h /= PRONY_RATIO
    raise _not_drive(p, "no single frequency fits bursts of samples at any spacing from "
                        f"{abs(window) / PRONY_SAMPLES!r} down to {abs(h) * PRONY_RATIO!r}")


def _linear_fit(ts, gs, freq):
    """γ, A, φ of γ + A sin(Ωt + φ) fitted to samples at a fixed Ω (linear least squares)."""
    m = np.column_stack((np.ones_like(ts), np.sin(freq * ts), np.cos(freq * ts)))
    (gamma, a, b), *_ = np.linalg.lstsq(m, gs, rcond=None)
    return float(gamma), math.hypot(a, b), math.atan2(b, a)


def _newton(ts, gs, t_ref, params):
    """Gauss–Newton on (γ, A, φ, Ω) over samples (ts, gs), each weighted by the inverse
    of its round-off (which grows with |Ωt|); φ's step taken at t_ref for conditioning
    (δφ + δΩ·t_ref is what the samples fix best)."""
    gamma, amp, phase, freq = params
    for _ in range(NEWTON_ITERATIONS):
        arg = freq * ts + phase
        s, c = np.sin(arg), np.cos(arg)
        weight = 1.0 / (1.0 + np.abs(freq * ts))
        r = (gs - (gamma + amp * s)) * weight
        jac = np.column_stack((np.ones_like(ts), s, amp * c, amp * (ts - t_ref) * c)) * weight[:, None]
        norms = np.sqrt(np.sum(jac * jac, axis=0))
        norms[norms == 0.0] = 1.0
        jac /= norms
        # The normal equations: the normalised columns (1, sin, cos, (t − t_ref)·cos) are
        # near orthogonal over the stage's periods, so squaring their condition costs no
        # digits of the step, and a 4×4 solve costs a fraction of an SVD.
        try:
            step = np.linalg.solve(jac.T @ jac, jac.T @ r)
        except np.linalg.LinAlgError:  # a vanished column (A = 0): the least-squares step
            step = np.linalg.lstsq(jac, r, rcond=None)[0]
        dg, da, dpsi, dw = (step / norms).tolist()
        gamma, amp, freq = gamma + dg, amp + da, freq + dw
        phase = phase + (dpsi - dw * t_ref)
        # Done when the steps are round-off of what they move: Ω·t over the stage and
        # the phase Ωt_ref + φ at t_ref.
        if (abs(dw) * abs(ts - t_ref).max() <= 4 * EPS * (1.0 + abs(freq * ts).max())
                and abs(dpsi) <= 4 * EPS * (1.0 + abs(phase) + abs(freq * t_ref))):
            break
    return gamma, amp, phase, freq


def _stage_times(t0, length, n):
    """n times over (t0, t0 + length], its end included, off any regular grid."""
    k = np.arange(n, dtype=float)
    u = (k + 0.5 + 0.45 * np.sin(2.4 * k + 1.0)) / n
    u[-1] = 1.0
    return t0 + length * u


def _fit_drive(p, t0, window):
    """γ, A, Ω, φ of g(t) (A ≥ 0, φ in [−π, π]), fitted over windows growing to ``window``."""
    freq, length = _coarse_frequency(p, t0, window)
    ts = t0 + np.linspace(0.0, length, PRONY_SAMPLES)
    gamma, amp, phase = _linear_fit(ts, np.array([p.g(t) for t in ts]), freq)
    while True:
        length = window if abs(length) * STAGE_GROWTH >= abs(window) else length * STAGE_GROWTH
        ts = _stage_times(t0, length, STAGE_SAMPLES)
        ts = np.concatenate((ts, np.array(list(p._g), dtype=float)))
        gs = np.array([p.g(t) for t in ts])
        gamma, amp, phase, freq = _newton(ts, gs, t0 + 0.5 * length, (gamma, amp, phase, freq))
        model = gamma + amp * np.sin(freq * ts + phase)
        allowed = _roundoff(gamma, amp, freq, phase, ts)
        worst = int(np.argmax(np.abs(gs - model) / allowed))
        if not abs(gs[worst] - model[worst]) <= allowed[worst]:
            raise _not_drive(p, (
                f"at t={float(ts[worst])!r}, fun gives theta''={float(gs[worst])!r} at theta = theta' = 0, "
                f"the best sinusoid over [{t0!r}, {float(t0 + length)!r}] (gamma={gamma!r}, A={amp!r}, "
                f"Omega={freq!r}, phi={phase!r}) gives {float(model[worst])!r} (they differ by "
                f"{float(abs(gs[worst] - model[worst]))!r}, round-off allows {float(allowed[worst])!r})"))
        if length == window:
            break
    if amp < 0.0:
        amp, phase = -amp, phase + math.pi
    if freq <= 0.0 or amp == 0.0:
        raise _not_drive(p, f"the best sinusoid has A={amp!r}, Omega={freq!r}")
    return gamma, amp, freq, math.remainder(phase, 2 * math.pi)


def _roundoff(gamma, amp, freq, phase, ts, extra=0.0):
    """What round-off allows between fun and the model at times ``ts`` (array)."""
    return ROUNDOFF_ULPS * EPS * (abs(gamma) + abs(amp) * (1.0 + np.abs(freq * ts) + abs(phase)) + extra) + 1e-300


def _verify_times(t0, t_bound, window):
    """Fresh times over the span (and the window), t_bound and times just before it included."""
    span = t_bound - t0
    near = [t_bound - span * 1e-3 * k for k in (1, 2, 5, 10)] if span != 0.0 else []
    rest = VERIFY_TIMES - len(near) - 2
    k = np.arange(rest, dtype=float)
    u = np.sort(np.abs(np.sin(1.7 * k + 0.3)))
    wide = (abs(window) > abs(span))
    return [t0, t_bound] + near + (t0 + (window if wide else span) * u).tolist()


def _first_mismatch(p, model, times):
    """The first (t, θ, θ', fun's value, model's value, allowed) where fun and model
    differ beyond round-off, or None: at θ = θ' = 0 at each of ``times``, then at each
    PROBE_CHECK_STATES state at its first, middle and last time (the t part additive)."""
    n = len(times)
    at = [(t, 0.0, 0.0) for t in times]
    at += [(times[j], theta, v) for theta, v, _ in PROBE_CHECK_STATES for j in (0, 1, n // 2)]
    got = np.array([p.values(t, theta, v) for t, theta, v in at], dtype=float)
    t, theta, v = (np.array(c) for c in zip(*at))
    beta, gamma, omega = model.params
    amp, freq, phase = model.drive
    w2 = omega**2
    expect = (gamma + amp * np.sin(freq * t + phase)) - beta * v - w2 * np.sin(theta)
    allowed = _roundoff(gamma, amp, freq, phase, t, np.abs(beta * v) + w2 * np.abs(np.sin(theta)) + np.abs(v))
    ok = (np.abs(got[:, 0] - v) <= ROUNDOFF_ULPS * EPS * np.abs(v)) & (np.abs(got[:, 1] - expect) <= allowed)
    if ok.all():
        return None
    i = int(np.argmin(ok))
    return (float(t[i]), float(theta[i]), float(v[i]), got[i].tolist(), [float(v[i]), float(expect[i])],
            float(allowed[i]))


def _mismatch_message(bad, model):
    """The refusal of an identified model that ``fun`` does not follow somewhere."""
    t, theta, v, got, expect, allowed = bad
    if theta == 0.0 and v == 0.0:
        return ("fun's time dependence is not gamma + A*sin(Omega*t + phi) (the one MBM integrates): "
                f"at t={t!r}, fun gives theta''={got[1]!r} at theta = theta' = 0, the best sinusoid "
                f"(gamma={model.gamma!r}, A={model.drive_amplitude!r}, Omega={model.drive_frequency!r}, "
                f"phi={model.drive_phase!r}) gives {expect[1]!r} (they differ by {abs(got[1] - expect[1])!r}, "
                f"round-off allows {allowed!r}).")
    if not abs(got[0] - v) <= ROUNDOFF_ULPS * EPS * abs(v):
        return NOT_FAMILY + (f" (at theta={theta}, theta'={v}, t={t!r}, fun's first component is "
                             f"{got[0]!r}, not theta').")
    return (NOT_FAMILY + f" (mismatch at theta={theta}, theta'={v}, t={t!r}: fun gives {got}, the "
            f"model identified at theta = theta' = 0, {model!r}, gives {expect}, round-off allows "
            f"{allowed!r}); fun's time dependence is not added to the torque (multiplicative?), and "
            "MBM integrates only the drive gamma + A*sin(Omega*t + phi) added to it.")


def check_model(fun, model, t0=0.0, t_bound=None):
    """Check a given ``model`` against ``fun``: the same equation to round-off, or a
    ValueError naming the parameters that differ.

    ``fun`` is compared with ``model`` at the states and times of the verification of
    :func:`identify_model` (θ = θ' = 0 across the span, its end included, and other
    states); where they differ beyond round-off, ``fun`` is identified and its
    parameters compared with the model's.

    Parameters
    ----------
    fun : callable
        ``fun(t, y)`` returning an array_like of shape (2,).
    model : Pendulum
        The model given with it.
    t0, t_bound : float, optional
        The span, as in :func:`identify_model`.

    Returns
    -------
    nfev : int
        Number of calls made to ``fun``.

    Raises
    ------
    ValueError
        If ``fun`` and ``model`` differ beyond round-off: the message names the
        parameters (beta, gamma, omega, drive_amplitude, drive_frequency, drive_phase;
        a sin/cos slip shows as drive_phase differing by pi/2), or says that ``fun`` is
        not of the family at all.
    """
    if fun is model or (isinstance(fun, Pendulum) and fun == model):
        return 0
    t0 = float(t0)
    t_bound = t0 if t_bound is None else float(t_bound)
    p = _Probe(fun)
    window = _window(t0, t_bound, model.omega**2)
    bad = _first_mismatch(p, model, _verify_times(t0, t_bound, window))
    if bad is None:
        return p.nfev
    t, theta, v, got, expect, _ = bad
    where = f"at t={t!r}, theta={theta!r}, theta'={v!r}, fun gives {got}, model={model!r} gives {expect}"
    try:
        found, _ = identify_model(fun, t0, t_bound)
    except ValueError as err:
        raise ValueError(f"fun and model= are different equations: {where}; and fun itself: {err}") from None
    raise ValueError(f"fun and model= are different equations: {_differences(found, model, t_bound - t0)} "
                     f"(fun identified by probing as {found!r}; {where})")


def _canonical_drive(model):
    """(A, Ω, φ) with A ≥ 0, φ in [−π, π]; (0, 0, 0) without a drive."""
    amp, freq, phase = model.drive
    if amp == 0.0:
        return 0.0, 0.0, 0.0
    if amp < 0.0:
        amp, phase = -amp, phase + math.pi
    return amp, freq, math.remainder(phase, 2 * math.pi)


def _differences(found, model, span):
    """The parameters of ``found`` (fun's) that differ from ``model``'s, named with both values."""
    fa, ff, fp = _canonical_drive(found)
    ma, mf, mp = _canonical_drive(model)
    size = (abs(found.gamma) + abs(model.gamma) + fa + ma + found.beta + model.beta
            + found.omega**2 + model.omega**2)
    amp = max(fa, ma)
    dphase = abs(math.remainder(fp - mp, 2 * math.pi)) if fa and ma else 0.0
    effects = {
        "beta": abs(found.beta - model.beta),
        "gamma": abs(found.gamma - model.gamma),
        "omega": abs(found.omega**2 - model.omega**2),
        "drive_amplitude": abs(fa - ma),
        "drive_frequency": amp * abs(ff - mf) * (abs(span) + 1.0) if fa and ma else 0.0,
        "drive_phase": amp * dphase,
    }
    named = [k for k, e in effects.items() if e > PARAM_RTOL * size]
    if not named:
        named = [max(effects, key=effects.get)]
    values = {"beta": (found.beta, model.beta), "gamma": (found.gamma, model.gamma),
              "omega": (found.omega, model.omega), "drive_amplitude": (fa, ma),
              "drive_frequency": (ff, mf), "drive_phase": (fp, mp)}
    parts = [f"{k} differs (fun {values[k][0]!r}, model {values[k][1]!r})" for k in named]
    if "drive_phase" in named:
        slip = dphase / (0.5 * math.pi)
        if abs(slip - round(slip)) < 1e-6 and round(slip) in (1, 2):
            parts[-1] += (" by pi/2: sin written for cos, or cos for sin?" if round(slip) == 1
                          else " by pi: the drive's sign?")
    return "; ".join(parts)
