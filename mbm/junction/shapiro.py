r"""Shapiro steps of the AC-driven junction: each step's edges, bisected.

Under the bias γ + A sin(Ωt + φ) the driven junction θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ)
(:mod:`mbm.junction.iv`) locks its rotation to the drive over ranges of γ: on the step p/q
the phase gains 2πp every q drive periods and the dc voltage is ⟨θ'⟩ = (p/q)Ω (a
periodic orbit of the stroboscopic map, or one of its period doublings, which keep the
voltage).  A step is the range of γ over which that locked motion exists, followed
adiabatically (each bias from the state the previous one settled to, as
:func:`mbm.iv_curve` sweeps): with hysteresis two steps can overlap, and one step can
come in pieces (the 3/2 step at β = 1, A = 0.5, Ω = 0.6: γ ≈ 1.198–1.204 and
1.231–1.263), each reported as a step.

:func:`shapiro_steps` measures ⟨θ'⟩ on a coarse grid over ``gamma_range``
(:func:`mbm.junction.iv.mean_velocity`, bias up) to find which steps exist.  A grid point
whose ⟨θ'⟩ is within :data:`GRID_MATCH` of a step's (p/q)Ω is tested by a *probe*
(below); each run of grid points on one step is then followed outward grid point by
grid point (past the ends of ``gamma_range`` too, at most ``points`` grid steps) while
the probe says it is on the step, and each edge is bisected between the last grid point
on the step and the first off it, as iv_curve bisects its switching and retrapping
currents: each probe starts from the settled state of the nearest bias known to be on
the step, until the bracket is at most ``current_tol`` wide.

The probe: from a state on the step, run :data:`PROBE_PERIODS` drive periods (in chunks
of :data:`PROBE_CHUNK_PERIODS`, stopping after the first chunk that slips) with :func:`mbm.solve`
and sample θ_k = θ(kT_d), T_d = 2π/Ω.  The deviation d_k = θ_k − θ_0 − 2πpk/q stays
bounded on the locked motion (periodic, period-doubled or chaotic within the step); a
phase slip changes it by ±2π for good.  The probe is on the step when the means of d_k
over the first and the last :data:`PROBE_MEAN_SAMPLES` samples of the run differ by less
than π (the means average out a locked orbit of up to that many drive periods).

What the probe cannot see: just outside a step's edge the motion is intermittent, long
laminar phases on the ghost of the vanished orbit between slips; the laminar time grows
like ε^{-1/2} at a distance ε from the edge (a saddle-node), and a probe shorter than it
reads "on the step".  The edge is so biased outward by the distance at which the laminar
time reaches the probe's length (:data:`PROBE_PERIODS`: measured below the tolerances
used, see there).
"""

import dataclasses
import fractions
import math
import numbers
import warnings

import numpy as np

from ..validate import (check_integer, check_positive, check_real, check_real_array, check_rule, check_rule_array,
                        keywords_named)

__all__ = ["shapiro_steps", "ShapiroSteps", "ShapiroStep", "ShapiroStepsSI", "ShapiroStepSI"]

# Drive periods a probe runs from a state on the step before it is said to stay on it.
# At β = 1, A = 0.5, Ω = 0.6 (current_tol 1e-6) the edges of the steps n = 0, 1, 2 were
# the same to the last bit with 4000 and 16000 periods, and 1000 periods moved two of
# them by 6e-7 (the laminar phases off an edge are then shorter than the probe beyond
# ~1e-6 of it): far below the default current_tol.
PROBE_PERIODS = 4000
# Chunks of the probe's run: a point off the step usually slips within the first (the
# laminar time far from the edge is a few periods), so most probes off a step stop early.
PROBE_CHUNK_PERIODS = 500
# Samples of d_k averaged at each end of a probe: 24 is a multiple of every orbit period
# 1, 2, 3, 4, 6, 8, 12 (q ≤ 4 and a period doubling or two), whose bounded swing of d_k
# the mean then removes (a period-doubled n = 1 orbit swings d_k by 4 rad at β = 1,
# Ω = 0.6, γ = 0.9, more than the π a slip test on single samples allows).
PROBE_MEAN_SAMPLES = 24
# A grid point whose ⟨θ'⟩ is within this of a step's (p/q)Ω (in units of Ω) is probed
# for that step: on a step it is (p/q)Ω to round-off once settled; a slowly settling
# point was 8e-5·Ω off on the n = 1 step (β = 1, Ω = 0.6, γ = 0.9, from the zero step).
GRID_MATCH = 1e-3
# The runs' tolerances (as mbm.junction.iv's runs: the probe needs a phase good to ≪ π over
# PROBE_PERIODS periods).
RUN_RTOL = 1e-11
RUN_ATOL = 1e-11


@dataclasses.dataclass(frozen=True)
class ShapiroStep:
    """One Shapiro step: the range of bias γ where ⟨θ'⟩ = (p/q)Ω.

    A dataclass built by :func:`shapiro_steps`: each parameter is an attribute.

    Parameters
    ----------
    p, q : int
        The phase gains 2πp every q drive periods (q ≥ 1; q = 1 an integer step n = p).
    voltage : float
        ⟨θ'⟩ = pΩ/q on the step.
    lower, upper : float
        The step's edges: the midpoints of ``lower_bracket`` and ``upper_bracket`` (NaN
        where the step was followed ``points`` grid steps past an end of
        ``gamma_range`` and still went on).
    lower_bracket, upper_bracket : tuple of float
        ``(lo, hi)``, hi − lo ≤ ``current_tol``: the biases the bisection ended on, one
        on the step and one off it (``lower_bracket``: lo off, hi on; ``upper_bracket``:
        lo on, hi off); NaN for the side never found off the step.
    width : float
        ``upper − lower`` (NaN with an edge).
    sweep : {"up", "down", "both"}
        The bias sweep the step was found on ("both": found on each, with the same
        edges to within twice ``current_tol``).
    """

    p: int
    q: int
    voltage: float
    lower: float
    upper: float
    lower_bracket: tuple
    upper_bracket: tuple
    width: float
    sweep: str = "up"


@dataclasses.dataclass(frozen=True)
class ShapiroSteps:
    """The Shapiro steps of a driven junction over a bias range, and the grid that found them.

    A dataclass built by :func:`shapiro_steps`: each parameter is an attribute.

    Parameters
    ----------
    steps : tuple of ShapiroStep
        The steps found, by voltage (then lower edge, then sweep).
    gamma : ndarray
        The coarse grid over ``gamma_range``, increasing.
    mean_velocity : ndarray
        ⟨θ'⟩ on the grid on the way up (each point from the previous one's state,
        :func:`mbm.junction.iv.mean_velocity`); NaN where the bias was swept down only.
    beta, omega, amplitude, frequency, phase, current_tol : float
        The junction, the drive A sin(Ωt + φ) and the bisection width.
    mean_velocity_down : ndarray or None
        ⟨θ'⟩ on the grid on the way down (in the grid's increasing order), None where
        the bias was swept up only.
    sweep : {"up", "down", "both"}
        The sweeps run.
    """

    steps: tuple
    gamma: np.ndarray
    mean_velocity: np.ndarray
    beta: float
    omega: float
    amplitude: float
    frequency: float
    phase: float
    current_tol: float
    mean_velocity_down: np.ndarray = None
    sweep: str = "up"

    def step(self, p, q=1):
        """The step p/q (the first one found, by lower edge), or None.

        Parameters
        ----------
        p, q : int
            The step's order p/q (q = 1: the integer step n = p).

        Returns
        -------
        ShapiroStep or None
        """
        return _first_step(self.steps, p, q)

    def in_units(self, junction):
        """The steps in amperes and volts, for the junction they were computed on.

        Each step's voltage is (p/q) h f / 2e, f the drive frequency in hertz
        (:meth:`mbm.Junction.shapiro_voltage`).

        Parameters
        ----------
        junction : mbm.Junction
            The junction: its β must be the steps' ``beta`` (``beta / omega`` where
            ``omega`` ≠ 1: :func:`mbm.junction.units.result_scales`).

        Returns
        -------
        ShapiroStepsSI

        Raises
        ------
        TypeError
            If ``junction`` is not an :class:`mbm.Junction`.
        ValueError
            If the steps were computed at another β than the junction's.
        """
        from .units import result_scales

        amps, volts = result_scales(junction, self.beta, self.omega)

        def current(pair):
            return tuple(float(g) * amps for g in pair)

        steps = tuple(ShapiroStepSI(p=s.p, q=s.q, voltage=float(s.voltage) * volts, lower=float(s.lower) * amps,
                                    upper=float(s.upper) * amps, lower_bracket=current(s.lower_bracket),
                                    upper_bracket=current(s.upper_bracket), width=float(s.width) * amps,
                                    sweep=s.sweep)
                      for s in self.steps)
        down = self.mean_velocity_down
        return ShapiroStepsSI(steps=steps, current=self.gamma * amps, voltage=self.mean_velocity * volts,
                              voltage_down=None if down is None else down * volts,
                              drive_current=float(self.amplitude) * amps,
                              drive_frequency_hz=junction.frequency(self.frequency / self.omega), junction=junction)

    def table(self):
        """The steps as a text table: order, voltage, edges with their brackets, width.

        Returns
        -------
        str
        """
        rows = [f"{'step':>6} {'voltage':>10} {'lower edge':>12} {'upper edge':>12} {'width':>11}"
                f"   lower bracket / upper bracket"]
        for s in self.steps:
            order = f"{s.p}" if s.q == 1 else f"{s.p}/{s.q}"
            rows.append(f"{order:>6} {s.voltage:10.6g} {s.lower:12.7f} {s.upper:12.7f} {s.width:11.7f}"
                        f"   [{s.lower_bracket[0]:.8g}, {s.lower_bracket[1]:.8g}] / "
                        f"[{s.upper_bracket[0]:.8g}, {s.upper_bracket[1]:.8g}]")
        return "\n".join(rows)

    def plot(self, ax=None):
        """Draw ⟨θ'⟩/Ω on the grid against γ (each sweep run), each step's bisected range shaded.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (default a new figure).

        Returns
        -------
        matplotlib.axes.Axes
        """
        if ax is None:
            import matplotlib.pyplot as plt

            ax = plt.subplots(figsize=(7, 5))[1]
        if self.sweep != "down":
            ax.plot(self.gamma, self.mean_velocity / self.frequency, "k.-", ms=3, lw=0.8, label="grid, bias up")
        if self.mean_velocity_down is not None:
            ax.plot(self.gamma, self.mean_velocity_down / self.frequency, "b.--", ms=3, lw=0.8,
                    label="grid, bias down")
        for s in self.steps:
            lo = s.lower if math.isfinite(s.lower) else self.gamma[0]
            hi = s.upper if math.isfinite(s.upper) else self.gamma[-1]
            ax.plot([lo, hi], [s.p / s.q] * 2, lw=4, alpha=0.5,
                    label=f"step {s.p}" + ("" if s.q == 1 else f"/{s.q}") + f": width {s.width:.4g}")
        ax.set_xlabel(r"bias $\gamma$")
        ax.set_ylabel(r"$\langle\theta'\rangle / \Omega$")
        ax.set_title(rf"Shapiro steps: $\beta$ = {self.beta:g}, $A$ = {self.amplitude:g}, $\Omega$ = {self.frequency:g}")
        ax.legend(fontsize=8, loc="upper left")
        return ax

    def to_csv(self, path):
        """Write one row per step: p, q, voltage, edges, brackets, width (the junction in a header).

        Parameters
        ----------
        path : str or path-like
            The file to write.
        """
        with open(path, "w") as f:
            f.write(f"# beta={self.beta!r}, omega={self.omega!r}, amplitude={self.amplitude!r}, "
                    f"frequency={self.frequency!r}, phase={self.phase!r}, current_tol={self.current_tol!r}\n")
            f.write("p,q,voltage,lower,upper,lower_lo,lower_hi,upper_lo,upper_hi,width\n")
            for s in self.steps:
                values = (s.voltage, s.lower, s.upper, *s.lower_bracket, *s.upper_bracket, s.width)
                f.write(f"{s.p},{s.q}," + ",".join(repr(float(v)) for v in values) + "\n")


@dataclasses.dataclass(frozen=True)
class ShapiroStepSI:
    """One Shapiro step in amperes and volts (:meth:`ShapiroSteps.in_units`).

    Parameters
    ----------
    p, q : int
        The step's order p/q, as :class:`ShapiroStep`.
    voltage : float
        The step's voltage (p/q) h f / 2e (V), f the drive frequency.
    lower, upper : float
        The step's edges in bias current (A; NaN as :class:`ShapiroStep`).
    lower_bracket, upper_bracket : tuple of float
        The edges' bisection brackets (A).
    width : float
        ``upper − lower`` (A).
    sweep : {"up", "down", "both"}
        The bias sweep the step was found on.
    """

    p: int
    q: int
    voltage: float
    lower: float
    upper: float
    lower_bracket: tuple
    upper_bracket: tuple
    width: float
    sweep: str


@dataclasses.dataclass(frozen=True)
class ShapiroStepsSI:
    """Shapiro steps in amperes and volts: what :meth:`ShapiroSteps.in_units` returns.

    Parameters
    ----------
    steps : tuple of ShapiroStepSI
        The steps, in the order of :attr:`ShapiroSteps.steps`.
    current : ndarray
        The grid's bias currents (A).
    voltage : ndarray
        The dc voltage on the grid on the way up (V; NaN where swept down only).
    voltage_down : ndarray or None
        The dc voltage on the grid on the way down (V), None where swept up only.
    drive_current, drive_frequency_hz : float
        The drive's amplitude I_ac (A) and frequency f (Hz).
    junction : mbm.Junction
        The junction converted with.
    """

    steps: tuple
    current: np.ndarray
    voltage: np.ndarray
    voltage_down: np.ndarray
    drive_current: float
    drive_frequency_hz: float
    junction: object

    def step(self, p, q=1):
        """The step p/q (the first one found, by lower edge), or None, as :meth:`ShapiroSteps.step`.

        Parameters
        ----------
        p, q : int
            The step's order p/q (q = 1: the integer step n = p).

        Returns
        -------
        ShapiroStepSI or None
        """
        return _first_step(self.steps, p, q)


def _first_step(steps, p, q):
    # The first of ``steps`` of order p/q, or None.
    return next((s for s in steps if (s.p, s.q) == (p, q)), None)


def _check_orders(orders):
    # None, or (p, q) pairs from ints, Fractions and (p, q) tuples (q >= 1, reduced).
    if orders is None:
        return None
    if isinstance(orders, (str, bytes)) or not hasattr(orders, "__iter__"):
        raise TypeError(f"orders must be a sequence of integers, fractions.Fraction or (p, q) pairs, got {orders!r}")
    out = []
    for o in orders:
        if isinstance(o, tuple) and len(o) == 2:
            p, q = o
        elif isinstance(o, numbers.Rational):
            p, q = o.numerator, o.denominator
        else:
            p = q = None
        if not all(isinstance(x, numbers.Integral) and not isinstance(x, (bool, np.bool_)) for x in (p, q)):
            raise TypeError(f"orders must hold integers, fractions.Fraction or (p, q) pairs of integers, got {o!r}")
        if q < 1:
            raise ValueError(f"orders: q must be >= 1, got {o!r}")
        f = fractions.Fraction(int(p), int(q))
        out.append((f.numerator, f.denominator))
    if not out:
        raise ValueError("orders must hold at least one step")
    return sorted(set(out), key=lambda pq: pq[0] / pq[1])


def _check_range(gamma_range):
    g = check_rule_array("gamma_range", check_real_array("gamma_range", gamma_range), rule=None)
    if g.shape != (2,):
        raise ValueError(f"gamma_range must be a pair (lo, hi), got {gamma_range!r}")
    if not g[0] < g[1]:
        raise ValueError(f"gamma_range must be increasing (lo < hi), got {gamma_range!r}")
    return float(g[0]), float(g[1])


def _check_points(points):
    return check_integer("points", points, 3)


def _probe(model, y, p, q):
    """Whether the motion from ``y`` (at a drive phase φ) stays on the step p/q for
    :data:`PROBE_PERIODS` drive periods (module docstring), and the state it ends in."""
    from ..frontends.solve import solve

    period_d = 2.0 * math.pi / model.drive_frequency
    m, n_mean = PROBE_CHUNK_PERIODS, PROBE_MEAN_SAMPLES
    samples = np.arange(m + 1) * period_d
    rate = 2.0 * math.pi * p / q
    y = np.array(y, dtype=float)
    theta0, offset, head = y[0], 0.0, None
    for chunk in range(PROBE_PERIODS // m):
        r = solve(model, (0.0, m * period_d), y, t_eval=samples, rtol=RUN_RTOL, atol=RUN_ATOL)
        if not r.success:
            raise RuntimeError(f"gamma={model.gamma!r}: {r.message}")
        d = r.y[0] + offset - theta0 - rate * (chunk * m + np.arange(m + 1))
        if head is None:
            head = float(np.mean(d[:n_mean]))
        if abs(float(np.mean(d[-n_mean:])) - head) >= math.pi:
            return False, None
        y = r.y[:, -1].copy()
        reduced = math.remainder(y[0], 2.0 * math.pi)
        offset += y[0] - reduced
        y[0] = reduced
    return True, y


def _candidate(v, omega_d, orders):
    # The step (p, q) whose voltage (p/q)Ω is within GRID_MATCH·Ω of v, or None.
    if orders is None:
        n = round(v / omega_d)
        best = (n, 1)
    else:
        best = min(orders, key=lambda pq: abs(v - omega_d * pq[0] / pq[1]))
    return best if abs(v - omega_d * best[0] / best[1]) <= GRID_MATCH * omega_d else None


def _edge(at, g, y, step, pq, tol, max_steps):
    """From bias g on the step (state y) toward ``step``: follow the step grid step by
    grid step (at most ``max_steps``), then bisect the edge to ``tol``; the final
    (g_on, g_off) (g_off NaN when the step went on)."""
    for _ in range(max_steps):
        on, y_next = _probe(at(g + step), y, *pq)
        if not on:
            break
        g, y = g + step, y_next
    else:
        return g, math.nan
    g_off = g + step
    while abs(g_off - g) > tol:
        mid = 0.5 * (g + g_off)
        on, y_mid = _probe(at(mid), y, *pq)
        if on:
            g, y = mid, y_mid
        else:
            g_off = mid
    return g, g_off


def _grid(at, gammas, omega_d, orders, y0=None):
    # ⟨θ'⟩ on the grid (in its order, adiabatic: each point from the previous one's
    # state, the first from y0 or rest) and the step (p, q) each point is on (None off
    # the steps), with the state it settled to.
    from .iv import mean_velocity

    y = np.zeros(2) if y0 is None else np.array(y0, dtype=float)
    velocities, on, states = [], [], []
    for g in gammas:
        model = at(g)
        _, v, _, y = mean_velocity(model, y)
        velocities.append(v)
        pq = _candidate(v, omega_d, orders)
        if pq is not None:
            stays, y_end = _probe(model, y, *pq)
            if stays:
                y = y_end
            else:
                pq = None
        on.append(pq)
        states.append(y.copy())
    return np.array(velocities), on, states


@keywords_named
def shapiro_steps(beta, gamma_range, *, amplitude, frequency, omega=1.0, phase=0.0, orders=None,
                  current_tol=1e-4, points=41, sweep="up"):
    """The Shapiro steps of the driven junction over ``gamma_range``, their edges bisected.

    The junction θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ); a step p/q is the range of γ
    where the phase is locked to the drive with ⟨θ'⟩ = (p/q)Ω (module docstring: found
    on a coarse grid, followed adiabatically and bisected).

    Parameters
    ----------
    beta : float
        Damping β > 0.
    gamma_range : (float, float)
        The bias range (lo < hi) the coarse grid covers; a step that reaches an end is
        followed beyond it (at most ``points`` grid steps).
    amplitude : float
        Drive amplitude A > 0.
    frequency : float
        Drive angular frequency Ω > 0.
    omega : float, optional
        ω > 0 (1 in the junction's reduced units).
    phase : float, optional
        Drive phase φ.
    orders : sequence, optional
        The steps looked for: integers n, :class:`fractions.Fraction` p/q or (p, q)
        pairs (q ≥ 1).  Default: every integer step n found on the grid.
    current_tol : float, optional
        Width to which each edge is bisected (default 1e-4).
    points : int, optional
        Points of the coarse grid (≥ 3, default 41): a step narrower than its spacing
        may fall between two points and be missed.
    sweep : {"up", "down", "both"}, optional
        The bias followed up from ``gamma_range[0]``, down from ``gamma_range[1]`` (each
        from rest at its first bias), or both ("both": the down sweep from the state the
        up sweep ended in, as a measured I–V loop).  A junction with hysteresis may sit
        on a step on one sweep direction only; a step found on both with the same edges
        is listed once (:attr:`ShapiroStep.sweep`).

    Returns
    -------
    ShapiroSteps

    Raises
    ------
    ValueError
        For β ≤ 0, A ≤ 0, Ω ≤ 0, ω ≤ 0, ``current_tol`` ≤ 0, a non-finite argument,
        ``gamma_range`` not an increasing pair, ``points`` < 3, an order with q < 1, or
        ``sweep`` not "up", "down" or "both".

    Warns
    -----
    RuntimeWarning
        Where a step asked for in ``orders`` was not found.
    TypeError
        For an argument that is not a real number (``points``: an integer; ``orders``:
        integers, fractions or (p, q) pairs of integers).

    Examples
    --------
    >>> s = mbm.shapiro_steps(1.0, (0.0, 1.6), amplitude=0.5, frequency=0.6)  # doctest: +SKIP
    >>> s.step(1).lower, s.step(1).upper  # doctest: +SKIP
    """
    from ..model import Pendulum

    beta = check_positive("beta", beta, why="damping: an I–V curve needs a damped junction")
    lo, hi = _check_range(gamma_range)
    amplitude = check_positive("amplitude", amplitude)
    frequency = check_positive("frequency", frequency)
    omega = check_rule("omega", omega)
    phase = check_real("phase", phase)
    current_tol = check_positive("current_tol", current_tol)
    orders = _check_orders(orders)
    points = _check_points(points)
    sweep = _check_sweep(sweep)

    def at(g):
        return Pendulum(beta, g, omega, amplitude, frequency, phase)

    gammas = np.linspace(lo, hi, points)
    velocities, down, steps, y_top = np.full(points, np.nan), None, [], None
    if sweep in ("up", "both"):
        velocities, on, states = _grid(at, gammas, frequency, orders)
        steps += _steps_on(at, gammas, (on, states), frequency, current_tol, "up")
        y_top = states[-1]
    if sweep in ("down", "both"):
        v_down, on, states = _grid(at, gammas[::-1], frequency, orders, y_top)
        steps += _steps_on(at, gammas[::-1], (on, states), frequency, current_tol, "down")
        down = v_down[::-1].copy()
    steps = _merged(steps, current_tol)
    steps.sort(key=lambda st: (st.p / st.q, st.lower, st.sweep))
    _warn_missing(orders, steps, (lo, hi, points), sweep)
    return ShapiroSteps(steps=tuple(steps), gamma=gammas, mean_velocity=velocities, beta=beta, omega=omega,
                        amplitude=amplitude, frequency=frequency, phase=phase, current_tol=current_tol,
                        mean_velocity_down=down, sweep=sweep)


def _check_sweep(sweep):
    if sweep not in ("up", "down", "both"):
        raise ValueError(f"sweep must be 'up', 'down' or 'both', got {sweep!r}")
    return sweep


def _steps_on(at, gammas, grid, frequency, current_tol, sweep):
    """The steps on one sweep's grid ``gammas`` (in the sweep's order; ``grid`` its points'
    steps and states, :func:`_grid`): each run of points on a step followed back and
    ahead past its last point and the edges bisected (drive frequency ``frequency``)."""
    on, states = grid
    points = gammas.size
    dg = gammas[1] - gammas[0]  # signed: negative on the way down
    steps, covered = [], np.zeros(points, dtype=bool)
    for i in range(points):
        if on[i] is None or covered[i]:
            continue
        j = i
        while j + 1 < points and on[j + 1] == on[i]:
            j += 1
        back = _edge(at, gammas[i], states[i], -dg, on[i], current_tol, points)
        ahead = _edge(at, gammas[j], states[j], dg, on[i], current_tol, points)
        lower, upper = (_bracket(back, -dg), _bracket(ahead, dg)) if dg > 0 else (_bracket(ahead, dg),
                                                                                  _bracket(back, -dg))
        # Later points of the sweep on this step up to its far edge belong to it (a run past a gap).
        far = ahead[1] if math.isfinite(ahead[1]) else math.copysign(math.inf, dg)
        covered |= np.array([pq == on[i] for pq in on]) & (np.sign(dg) * (gammas - far) <= 0.0)
        steps.append(_step(on[i], frequency, lower, upper, sweep))
    return steps


def _bracket(edge, step):
    # An edge's bracket (lo, hi) from _edge's (g_on, g_off) found moving by ``step``.
    g_on, g_off = edge
    return (g_off, g_on) if step < 0 else (g_on, g_off)


def _same_edge(a, b, tol):
    return (math.isnan(a) and math.isnan(b)) or abs(a - b) <= 2.0 * tol


def _merged(steps, tol):
    """``steps`` with a step found on both sweeps with the same edges (to 2 ``tol``) once,
    its sweep "both"."""
    out = []
    for st in steps:
        twin = next((k for k, o in enumerate(out) if (o.p, o.q) == (st.p, st.q) and o.sweep != st.sweep
                     and _same_edge(o.lower, st.lower, tol) and _same_edge(o.upper, st.upper, tol)), None)
        if twin is None:
            out.append(st)
        else:
            out[twin] = dataclasses.replace(out[twin], sweep="both")
    return out


def _warn_missing(orders, steps, grid, sweep):
    # A step asked for by name and not found: say so, and why it may be missing.
    if orders is None:
        return
    lo, hi, points = grid
    found = {(st.p, st.q) for st in steps}
    missing = [f"{p}" if q == 1 else f"{p}/{q}" for p, q in orders if (p, q) not in found]
    if missing:
        where = "on either sweep" if sweep == "both" else f"on the {sweep} sweep (try sweep='both')"
        warnings.warn(f"shapiro_steps: step(s) {', '.join(missing)} not found {where} over gamma in "
                      f"[{lo:g}, {hi:g}]: a step narrower than the grid spacing {(hi - lo) / (points - 1):.3g} "
                      f"(points={points}) falls between points, and with hysteresis a step may be reached "
                      f"on one sweep direction only", RuntimeWarning, stacklevel=3)


def _step(pq, frequency, lower, upper, sweep):
    # A ShapiroStep from its brackets: each edge the midpoint of its bracket.
    lo_edge, hi_edge = 0.5 * (lower[0] + lower[1]), 0.5 * (upper[0] + upper[1])
    return ShapiroStep(p=pq[0], q=pq[1], voltage=frequency * pq[0] / pq[1], lower=float(lo_edge),
                       upper=float(hi_edge), lower_bracket=tuple(map(float, lower)),
                       upper_bracket=tuple(map(float, upper)), width=float(hi_edge - lo_edge), sweep=sweep)
