r"""Event points of the moving boundary method: where θ = d or θ' = 0.

The second paper (Salas, Martínez, Ocampo 2022, §3) re-anchors its analytic
approximant either on a fixed grid, (3.29)–(3.31), or at *event points*, (3.32):

    φ a numerical solution of the initial value problem on [0, T];
    τ₁ < τ₂ < … < τ_N the points of (0, T) where φ(τ) = d or φ'(τ) = 0;
    θ₀(t) = θ(y₀, ẏ₀)(t) on [0, τ₁],
    θ_n(t) = θ(φ(τ_n), φ'(τ_n))(t − τ_n) on (τ_n, τ_{n+1}],  n = 1, …, N,

with τ_{N+1} = T.  This module supplies the pieces, as pure functions:

:func:`event_function_d`
    the shift d of the zero-crossing surface θ = d for an approximant;
:func:`hybrid_event_points`
    the τ_n and φ(τ_n) of (3.32) from SUNDIALS CVODE (Adams) with its root finding
    ("hybrid" mode: numerical events, analytic windows);
:func:`next_event_analytic`
    the next event of an anchored formula found from the formula alone;
:func:`analytic_event_points`
    the event points of the "analytic" mode: each window anchored at the previous
    formula's event state, no numerical solution at all;
:func:`event_point_solution`
    the piecewise function (3.32) built from given event points;
:func:`successive`
    the successive approximant Θ_j of (3.31) on the fixed grid nτ.

Event kinds are reported as integer codes: :data:`KIND_CROSSING` (0, θ = d),
:data:`KIND_TURNING` (1, θ' = 0), :data:`KIND_BOTH` (2, both at the same instant,
e.g. a tangency of θ with d at a turning point) and :data:`KIND_NONE` (−1, no event).
"""

import math

import numpy as np
from scipy.optimize import brentq

from ..approximants.base import ApproximantDomainError, get_approximant
from ..model import Pendulum
from ..validate import check_span, check_state, check_tolerances
from ..frontends.reference import cvode_adams

__all__ = [
    "EVENT_KINDS",
    "KIND_BOTH",
    "KIND_CROSSING",
    "KIND_NONE",
    "KIND_TURNING",
    "PiecewiseApproximant",
    "analytic_event_points",
    "event_function_d",
    "event_point_solution",
    "hybrid_event_points",
    "next_event_analytic",
    "successive",
]

KIND_NONE = -1
KIND_CROSSING = 0
KIND_TURNING = 1
KIND_BOTH = 2
# Names accepted in ``kinds``, in the order of their codes.
EVENT_KINDS = ("crossing", "turning")

# Bracketing step of :func:`next_event_analytic` as a fraction of 2π/ω: the formulas
# oscillate with periods ≥ about 2π/ω (softening restoring forces only lengthen the
# period), so events of one kind are ≥ a quarter period ≈ 16 samples apart and two
# sign changes of one kind can never fall between neighbouring samples.
SAMPLES_PER_PERIOD = 64
# Absolute tolerance on the event time in the Brent refinement (~1e-14);
# the relative part is scipy's minimum 4 eps, so late events are limited by the
# spacing of doubles near t, not by the iteration.
ROOT_XTOL = 1e-14
ROOT_RTOL = 4.0 * np.finfo(float).eps
# An anchor with |θ₀ − d| ≤ ON_SURFACE_TOL·(1 + |d|) (or |θ̇₀| ≤ ON_SURFACE_TOL·ω)
# is *on* that event surface: its own event at t = 0 must not be re-detected.  Event
# states from CVODE or from a Brent-refined formula lie within ~1e-13 of the surface;
# 1e-9 is the accuracy the event states are specified to, far above that round-off.
ON_SURFACE_TOL = 1e-9
# Roots of the two kinds closer than this (relative to 1 + |t|) are one event of kind
# KIND_BOTH: both refinements are accurate to ~1e-14, so a gap below 1e-12 cannot be
# resolved and would only create a window of zero length.
SIMULTANEOUS_RTOL = 1e-12


# --------------------------------------------------------------------------- helpers


def _real(name, value, finite=True):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number, got {value!r}") from None
    if finite and not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v


def _check_model(model):
    if not isinstance(model, Pendulum):
        raise TypeError(f"model must be an mbm.Pendulum, got {type(model).__name__}")


def _kinds_and_d(kinds, d):
    """Validate ``kinds`` and ``d``: return (track_crossing, track_turning, d)."""
    if isinstance(kinds, str):
        kinds = (kinds,)
    try:
        kinds = tuple(kinds)
    except TypeError:
        raise ValueError(f"kinds must be a sequence drawn from {EVENT_KINDS}, got {kinds!r}") from None
    bad = [k for k in kinds if k not in EVENT_KINDS]
    if bad or not kinds:
        raise ValueError(f"kinds must be a non-empty sequence drawn from {EVENT_KINDS}, got {kinds!r}")
    crossing = "crossing" in kinds
    turning = "turning" in kinds
    if crossing:
        if d is None:
            # event_function_d returns None where there is no zero-crossing surface.
            crossing = False
        else:
            d = _real("d", d)
    if not (crossing or turning):
        raise ValueError(
            "kinds=('crossing',) with d=None leaves no event to track: there is no "
            "zero-crossing surface theta = d (see event_function_d)"
        )
    return crossing, turning, (d if crossing else None)


# ---------------------------------------------------------------------- d of θ = d


def event_function_d(model, approximant="salas-torque"):
    """The shift d of the zero-crossing event surface θ = d used by (3.32).

    Parameters
    ----------
    model : Pendulum
        The equation θ'' + βθ' + ω² sin θ = γ.
    approximant : str or Approximant, optional
        The approximant the windows use (default ``"salas-torque"``).

    Returns
    -------
    float or None
        For ``"salas-torque"``: the root of θ − 2θ³/13 = γ/ω² nearest arcsin(γ/ω²),
        the paper's d of (2.6) (``cubic_equilibrium``), about which its formula
        oscillates; None when |γ/ω²| exceeds the cubic's maximum (the approximant
        is then unusable anyway).  For every other approximant: the pendulum's
        stable equilibrium arcsin(γ/ω²) (:attr:`Pendulum.equilibrium`), or None
        when |γ| > ω² (no equilibrium: the pendulum runs over, and there are no
        zero-crossing events, only turning points if any).

    Raises
    ------
    TypeError
        If ``model`` is not a :class:`~mbm.Pendulum`.
    ValueError
        If ``approximant`` is not a registered approximant.
    """
    _check_model(model)
    ap = get_approximant(approximant)
    # The approximant knows its own centre (Approximant.event_center).
    return ap.event_center(model)


# ------------------------------------------------------------- hybrid: CVODE roots


def hybrid_event_points(model, t_span, y0, d, kinds=("crossing", "turning"), rtol=1e-10, atol=1e-12):
    """Event points τ_n and states φ(τ_n) of (3.32) from CVODE's root finding.

    φ is SUNDIALS CVODE (variable-order Adams–Moulton, orders up to 12, analytic
    Jacobian) through scikit-sundae; the event functions θ − d and θ' are handed
    to CVODE's root finder (``eventsfn``, non-terminal, both directions), which
    locates each root to ~100 ulps of t on CVODE's own interpolant and returns the
    interpolated state there.

    Parameters
    ----------
    model : Pendulum
        The equation θ'' + βθ' + ω² sin θ = γ.
    t_span : pair of float
        ``(t0, tf)``, finite, ``t0 != tf``; ``tf < t0`` integrates backward.
    y0 : array_like, shape (2,)
        ``[θ(t0), θ'(t0)]``, finite.
    d : float or None
        The zero-crossing surface θ = d (see :func:`event_function_d`).  None means
        there is no such surface: crossing events are then not tracked.
    kinds : sequence of {"crossing", "turning"}, optional
        Which events to track (default both).
    rtol, atol : float, optional
        CVODE's tolerances (default 1e-10, 1e-12); positive; rtol below 100 eps is
        raised to it with a warning (scipy's rule).

    Returns
    -------
    t_events : ndarray, shape (k,)
        Event times in the order of integration (increasing forward, decreasing
        backward), an event exactly at ``t0`` excluded.
    y_events : ndarray, shape (k, 2)
        CVODE's state ``[θ, θ']`` at each event (not projected onto the surface).
    kind_codes : ndarray of int, shape (k,)
        :data:`KIND_CROSSING` (θ = d), :data:`KIND_TURNING` (θ' = 0) or
        :data:`KIND_BOTH` (CVODE found both roots at the same t).

    Raises
    ------
    TypeError
        If ``model`` is not a :class:`~mbm.Pendulum`.
    ValueError
        For a malformed ``t_span``, ``y0``, ``d``, ``kinds``, ``rtol`` or ``atol``.
    RuntimeError
        If CVODE fails before reaching ``tf``.

    Notes
    -----
    Cost is dominated by scikit-sundae's Python callbacks (~8 µs each, ~2–3 per
    step): an undamped pendulum over 0 ≤ t ≤ 1e4 (~6000 events) takes a few
    seconds at the default tolerances; a damped one settling to rest is ~10× faster.
    Once the motion has decayed to round-off (|θ − d|, |θ'| ~ 1e-16) CVODE may
    still report sign changes of the noise; they are genuine sign changes of φ.
    """
    _check_model(model)
    t0, tf = check_span(t_span, allow_empty=False)
    y0 = check_state("y0", y0)
    crossing, turning, d = _kinds_and_d(kinds, d)
    rtol, atol = check_tolerances(rtol, atol)

    # The event callback unpacks y with tolist(), as the model's (numpy scalars are slow).

    if crossing and turning:
        def events(t, y, g):
            th, v = y.tolist()
            g[0] = th - d
            g[1] = v
        columns = (KIND_CROSSING, KIND_TURNING)
    elif crossing:
        def events(t, y, g):
            g[0] = y[0] - d
        columns = (KIND_CROSSING,)
    else:
        def events(t, y, g):
            g[0] = y[1]
        columns = (KIND_TURNING,)
    # A fresh function object per call: scikit-sundae keeps its event log on it.
    events.terminal = [False] * len(columns)
    events.direction = [0] * len(columns)

    solver = cvode_adams(model, rtol, atol, eventsfn=events, num_events=len(columns))
    # Three output times select CVODE's CV_NORMAL mode (a two-point span would
    # record every internal step, which is not wanted); the stop time is tf.
    res = solver.solve(np.array([t0, 0.5 * (t0 + tf), tf]), y0)
    if not res.success:
        reached = float(res.t[-1]) if len(res.t) else t0
        raise RuntimeError(f"CVODE failed at t={reached!r} before reaching tf={tf!r}: {res.message}")
    if res.t_events is None:
        return np.empty(0), np.empty((0, 2)), np.empty(0, dtype=int)
    t_ev = np.asarray(res.t_events, dtype=float).reshape(-1)
    y_ev = np.asarray(res.y_events, dtype=float).reshape(-1, 2)
    hit = np.asarray(res.i_events).reshape(len(t_ev), -1) != 0
    if len(columns) == 2:
        codes = np.where(hit[:, 0] & hit[:, 1], KIND_BOTH, np.where(hit[:, 0], KIND_CROSSING, KIND_TURNING))
    else:
        codes = np.full(len(t_ev), columns[0])
    keep = t_ev != t0  # (3.32) uses the points of (0, T): the start is θ₀'s anchor
    return t_ev[keep], y_ev[keep], codes[keep].astype(int)


# ------------------------------------------------------- analytic: formula roots


def _check_search(t_max, direction, omega, coef):
    """:func:`next_event_analytic`'s search limit, direction, ω and coefficients, checked."""
    if direction not in (1, -1):
        raise ValueError(f"direction must be 1 or -1, got {direction!r}")
    t_max = _real("t_max", t_max)
    if not direction * t_max > 0.0:
        raise ValueError(f"t_max must be non-zero with the sign of direction={direction}, got {t_max!r}")
    omega = _real("omega", omega)
    if not omega > 0.0:
        raise ValueError(f"omega must be > 0, got {omega!r}")
    coef = np.asarray(coef, dtype=np.float64)
    if coef.ndim != 1 or coef.size == 0 or coef[0] != 0.0:
        raise ValueError(
            "coef must be the 1-D output of a successful anchor_kernel call (coef[0] == 0), "
            f"got {coef!r}"
        )
    return t_max, omega, coef


def _first_root(g, found, direction):
    """The first event among the bracketed sign changes ``found`` of g, refined by brentq."""
    roots = []
    for code, i, a, b in found:
        lo, hi = (a, b) if a < b else (b, a)
        r = brentq(lambda s, i=i: g(s)[i], lo, hi, xtol=ROOT_XTOL, rtol=ROOT_RTOL)
        roots.append((r, code))
    roots.sort(key=lambda rc: direction * rc[0])
    t_ev, kind = roots[0]
    if len(roots) == 2 and abs(roots[1][0] - t_ev) <= SIMULTANEOUS_RTOL * (1.0 + abs(t_ev)):
        kind = KIND_BOTH
    return t_ev, kind


def next_event_analytic(eval_kernel, coef, d, kinds, t_max, direction, omega=1.0):
    """First event of an anchored formula after its anchor, from the formula alone.

    Finds the first t in (0, t_max] (``direction = +1``) or [t_max, 0)
    (``direction = −1``), t measured from the anchor, where θ(t) − d or θ'(t)
    of the anchored approximant changes sign.  The formula is sampled every
    (2π/ω)/:data:`SAMPLES_PER_PERIOD`; the first sign change is refined by Brent's
    method (:func:`scipy.optimize.brentq`) to :data:`ROOT_XTOL`.

    A kind whose function is on its surface at the anchor (|θ₀ − d| ≤
    ON_SURFACE_TOL·(1 + |d|), |θ̇₀| ≤ ON_SURFACE_TOL·ω) takes its reference sign from
    the first sample after t = 0, so that an anchor placed at an event of (3.32)
    does not re-detect that event: only sign changes strictly after the anchor
    count.  A root at which the function only touches zero is not an event.

    Parameters
    ----------
    eval_kernel : callable
        ``eval_kernel(coef, t) -> (theta, theta_dot)`` of an approximant.
    coef : ndarray
        The anchored coefficient vector (``anchor_kernel``'s output, status 0).
    d : float or None
        The zero-crossing surface θ = d; None: crossing events are not tracked.
    kinds : sequence of {"crossing", "turning"}
        Which events to look for.
    t_max : float
        Search limit, finite, with the sign of ``direction``.
    direction : {1, -1}
        Forward or backward in t.
    omega : float, optional
        The model's ω (default 1, the paper's scaling): sets the sampling step.
        Pass ``model.omega``: an ω too large only costs samples, one too small
        widens the step and may let two sign changes fall between samples.

    Returns
    -------
    t_event : float
        The event time (measured from the anchor), or ``inf`` when there is none
        (also when the formula stops being finite before the first sign change).
    kind : int
        :data:`KIND_CROSSING`, :data:`KIND_TURNING`, :data:`KIND_BOTH` (both roots
        within SIMULTANEOUS_RTOL), or :data:`KIND_NONE` with ``inf``.

    Raises
    ------
    ValueError
        For a malformed ``kinds``, ``d``, ``t_max``, ``direction``, ``omega``, or a
        ``coef`` whose status ``coef[0]`` is not 0.
    """
    crossing, turning, d = _kinds_and_d(kinds, d)
    t_max, omega, coef = _check_search(t_max, direction, omega, coef)

    track = []  # (kind code, index into (theta − d, theta'), surface tolerance)
    if crossing:
        track.append((KIND_CROSSING, 0, ON_SURFACE_TOL * (1.0 + abs(d))))
    if turning:
        track.append((KIND_TURNING, 1, ON_SURFACE_TOL * omega))
    dd = d if crossing else 0.0

    def g(t):
        th, v = eval_kernel(coef, t)
        return th - dd, v

    g0 = g(0.0)
    # last[k]: (t, value) of the last sample of kind k with a known non-zero sign;
    # None while the sign is still unknown (anchor on the surface, or exact zeros).
    last = {}
    for code, i, tol in track:
        last[code] = None if abs(g0[i]) <= tol or g0[i] == 0.0 else (0.0, g0[i])

    h = 2.0 * math.pi / omega / SAMPLES_PER_PERIOD
    n = max(1, math.ceil(abs(t_max) / h))
    for m in range(1, n + 1):
        t = t_max if m == n else direction * m * h
        gt = g(t)
        if not (math.isfinite(gt[0]) and math.isfinite(gt[1])):
            return math.inf, KIND_NONE
        found = []
        for code, i, _ in track:
            val = gt[i]
            ref = last[code]
            if ref is not None and ((val < 0.0 < ref[1]) or (ref[1] < 0.0 < val)):
                found.append((code, i, ref[0], t))
            elif ref is not None and val == 0.0 and m == n:
                found.append((code, i, ref[0], t))  # exactly on the surface at t_max
            if val != 0.0:
                last[code] = (t, val)
        if found:
            return _first_root(g, found, direction)
    return math.inf, KIND_NONE


def analytic_event_points(model, t_span, y0, d, kinds=("crossing", "turning"), approximant="salas-torque"):
    """Event points of (3.32) with φ replaced by the approximant's own continuation.

    θ₀ is anchored at ``y0``; its first event τ₁ (:func:`next_event_analytic`) gives
    the anchor θ₀(τ₁) of θ₁, whose first event gives τ₂, and so on to ``tf``: the
    "analytic" mode of the event-point method, with no numerical solution.

    Parameters
    ----------
    model : Pendulum
    t_span : pair of float
        ``(t0, tf)``, finite, ``t0 != tf``; ``tf < t0`` goes backward.
    y0 : array_like, shape (2,)
        ``[θ(t0), θ'(t0)]``.
    d : float or None
        The surface θ = d (:func:`event_function_d`); None: no crossing events.
    kinds : sequence of {"crossing", "turning"}, optional
    approximant : str or Approximant, optional
        Default ``"salas-torque"``.

    Returns
    -------
    t_events, y_events, kind_codes
        As :func:`hybrid_event_points`; ``y_events[n]`` is θ_{n−1}(τ_n), the
        formula's state at its event, which anchors θ_n.

    Raises
    ------
    ValueError
        For malformed arguments.
    ApproximantDomainError
        If an event state is outside the approximant's domain.
    """
    _check_model(model)
    ap = get_approximant(approximant)
    ap.check_model(model)
    try:
        t0, tf = (float(v) for v in t_span)
    except (TypeError, ValueError):
        raise ValueError(f"t_span must be a pair of real numbers (t0, tf), got {t_span!r}") from None
    if not (math.isfinite(t0) and math.isfinite(tf)) or t0 == tf:
        raise ValueError(f"t_span must be finite with t0 != tf, got {t_span!r}")
    y = check_state("y0", y0)
    _kinds_and_d(kinds, d)  # validate here, before the loop
    sign = 1 if tf > t0 else -1
    t = t0
    ts, ys, ks = [], [], []
    coef = _anchor(ap, model, y[0], y[1], f"t={t0!r}")
    while sign * (tf - t) > 0.0:
        dt, kind = next_event_analytic(ap.eval_kernel, coef, d, kinds, tf - t, sign, model.omega)
        if kind == KIND_NONE:
            break
        th, v = ap.eval_kernel(coef, dt)
        t = t + dt
        ts.append(t)
        ys.append((th, v))
        ks.append(kind)
        coef = _anchor(ap, model, th, v, f"the event t={t!r}")
    return np.array(ts, dtype=float), np.array(ys, dtype=float).reshape(-1, 2), np.array(ks, dtype=int)


# ------------------------------------------------------------ piecewise formulas


class PiecewiseApproximant:
    """A piecewise analytic approximant: formula n on the window (b_n, b_{n+1}].

    The value at a window boundary b_n (n ≥ 1) is that of the *left* window's
    formula, the convention of (3.30)–(3.32) (θ_n on (τ_n, τ_{n+1}]); the first
    window includes its start b_0, and the last formula is continued to infinity
    (in the direction of ``sign``).

    Attributes
    ----------
    approximant : Approximant
    boundaries : ndarray, shape (N + 1,)
        b_0 < b_1 < … < b_N (or decreasing when ``sign == -1``): b_0 the start,
        formula n holds on (b_n, b_{n+1}], the last one on (b_N, ∞).
    coefs : list of ndarray
        The N + 1 anchored coefficient vectors; formula n is evaluated at t − b_n.
    sign : int
        +1 (forward in t) or −1 (backward).
    """

    def __init__(self, approximant, boundaries, coefs, sign=1):
        self.approximant = approximant
        self.boundaries = np.asarray(boundaries, dtype=float)
        self.coefs = list(coefs)
        self.sign = sign

    def __call__(self, t):
        """θ(t), θ'(t) at absolute times ``t`` (scalar or array).

        Raises
        ------
        ValueError
            If a time lies before the start b_0 (in the direction of ``sign``).
        """
        t_arr = np.asarray(t, dtype=np.float64)
        flat = np.ascontiguousarray(t_arr.reshape(-1))
        s = self.sign
        if np.any(~np.isfinite(flat)) or np.any(s * (flat - self.boundaries[0]) < 0.0):
            raise ValueError(
                f"t must be finite and {'>=' if s > 0 else '<='} the start {self.boundaries[0]!r}, got {t!r}"
            )
        # Window n holds (b_n, b_{n+1}]: side="left" on s·b sends t = b_{n+1} to n.
        idx = np.searchsorted(s * self.boundaries, s * flat, side="left") - 1
        idx = np.clip(idx, 0, len(self.coefs) - 1)
        th = np.empty_like(flat)
        v = np.empty_like(flat)
        ek = self.approximant.eval_array_kernel
        for n in np.unique(idx):
            sel = np.flatnonzero(idx == n)
            # t − b_n formed as the solver forms it, so the boundaries agree bitwise.
            local = np.ascontiguousarray(flat[sel] - self.boundaries[n])
            a = np.empty_like(local)
            b = np.empty_like(local)
            ek(self.coefs[n], local, a, b)
            th[sel] = a
            v[sel] = b
        if t_arr.ndim == 0:
            return float(th[0]), float(v[0])
        return th.reshape(t_arr.shape), v.reshape(t_arr.shape)

    def __len__(self):
        return len(self.coefs)

    def __repr__(self):
        return (
            f"<PiecewiseApproximant {self.approximant.name!r}: {len(self.coefs)} formulas from "
            f"t={self.boundaries[0]!r}>"
        )


def _anchor(ap, model, theta0, v0, where):
    coef = ap.anchor_kernel(model.beta, model.gamma, model.omega, float(theta0), float(v0))
    if coef[0] != 0:
        msg = ap.status_messages.get(int(coef[0]), f"status {int(coef[0])}")
        raise ApproximantDomainError(f"approximant {ap.name!r} cannot be anchored at {where}: {msg}")
    return coef


def event_point_solution(model, t0, y0, t_events, y_events, approximant="salas-torque"):
    """The event-point approximant (3.32) from given event times and states.

    θ₀ is anchored at ``(t0, y0)`` and holds on [t0, τ₁]; θ_n is anchored at the
    given state φ(τ_n) and holds on (τ_n, τ_{n+1}]; the last one, θ_N, is continued
    beyond τ_N (the paper stops it at T).

    Parameters
    ----------
    model : Pendulum
    t0 : float
        Start time.
    y0 : array_like, shape (2,)
        Initial state, θ₀'s anchor.
    t_events : array_like, shape (N,)
        τ₁, …, τ_N, strictly monotonic away from ``t0`` (increasing forward,
        decreasing backward), e.g. from :func:`hybrid_event_points`.
    y_events : array_like, shape (N, 2)
        The anchor states φ(τ_n) (for the analytic mode, θ_{n−1}(τ_n)).
    approximant : str or Approximant, optional
        Default ``"salas-torque"``.

    Returns
    -------
    PiecewiseApproximant
        Callable ``(t) -> (theta, theta_dot)`` at absolute times.

    Raises
    ------
    ValueError
        For malformed times or states.
    ApproximantDomainError
        If an anchor state is outside the approximant's domain.
    """
    _check_model(model)
    ap = get_approximant(approximant)
    ap.check_model(model)
    t0 = _real("t0", t0)
    y0 = check_state("y0", y0)
    te = np.asarray(t_events, dtype=float).reshape(-1)
    ye = np.asarray(y_events, dtype=float).reshape(-1, 2) if te.size else np.empty((0, 2))
    if ye.shape != (te.size, 2):
        raise ValueError(f"y_events must have shape ({te.size}, 2) to match t_events, got {np.shape(y_events)}")
    if not (np.all(np.isfinite(te)) and np.all(np.isfinite(ye))):
        raise ValueError("t_events and y_events must be finite")
    sign = 1
    if te.size:
        sign = 1 if te[0] > t0 else -1
        if np.any(sign * np.diff(np.concatenate(([t0], te))) <= 0.0):
            raise ValueError("t_events must be strictly monotonic away from t0")
    coefs = [_anchor(ap, model, y0[0], y0[1], f"t={t0!r}")]
    for tn, yn in zip(te, ye):
        coefs.append(_anchor(ap, model, yn[0], yn[1], f"the event t={tn!r}"))
    return PiecewiseApproximant(ap, np.concatenate(([t0], te)), coefs, sign)


def successive(model, y0, tau, j, approximant="salas-torque"):
    """The successive approximant Θ_j of the moving boundary method, (3.31).

    Θ_j(t) = θ₀(t) on [0, τ], θ_n(t) on (nτ, (n+1)τ] for 1 ≤ n < j, and θ_j(t) on
    (jτ, ∞): the first j windows of (3.29)–(3.30), then the j-th anchored formula
    continued indefinitely.  The anchors follow (3.29): θ_n is anchored at
    (θ_{n−1}(nτ), θ'_{n−1}(nτ)), the approximant's own continuation.

    The boundaries nτ are accumulated as b_n = b_{n−1} + τ and each anchor is
    θ_{n−1} evaluated at b_n − b_{n−1}, exactly as :class:`mbm.MBM` forms its windows,
    so Θ_j agrees bitwise with MBM's dense output on [0, jτ].

    Parameters
    ----------
    model : Pendulum
    y0 : array_like, shape (2,)
        ``[θ(0), θ'(0)]``.
    tau : float
        Window length τ > 0, finite.
    j : int
        Number of re-anchorings, j ≥ 0 ((3.31) has j ≥ 1; j = 0 is the single
        approximant θ₀ on [0, ∞)).
    approximant : str or Approximant, optional
        Default ``"salas-torque"``.

    Returns
    -------
    PiecewiseApproximant
        Callable ``(t) -> (theta, theta_dot)``, vectorized, for t ≥ 0.

    Raises
    ------
    ValueError
        For a malformed ``y0``, ``tau`` or ``j``.
    ApproximantDomainError
        If an anchor leaves the approximant's domain, or a formula is not finite
        at the end of its window.
    """
    _check_model(model)
    ap = get_approximant(approximant)
    ap.check_model(model)
    y0 = check_state("y0", y0)
    tau = _real("tau", tau)
    if not tau > 0.0:
        raise ValueError(f"tau must be > 0, got {tau!r}")
    if isinstance(j, bool) or not isinstance(j, (int, np.integer)) or j < 0:
        raise ValueError(f"j must be an integer >= 0, got {j!r}")
    j = int(j)
    b = [0.0]
    coefs = [_anchor(ap, model, y0[0], y0[1], "t=0")]
    for n in range(1, j + 1):
        b.append(b[-1] + tau)
        th, v = ap.eval_kernel(coefs[-1], b[-1] - b[-2])
        if not (math.isfinite(th) and math.isfinite(v)):
            raise ApproximantDomainError(
                f"approximant {ap.name!r} is not finite at the end of window {n - 1} (t={b[-1]!r})"
            )
        coefs.append(_anchor(ap, model, th, v, f"t={b[-1]!r} (window {n})"))
    return PiecewiseApproximant(ap, b, coefs, 1)
