"""The batch front end of the compiled path: many scenes in parallel (``numba.prange``).

:func:`solve_batch` checks and broadcasts the scenes' arrays, plans each scene's
windows as :func:`mbm.frontends.solve.solve` would, runs them in :func:`mbm.core.lanes.run_batch` and
gathers the per-scene result; each scene's answer equals :func:`mbm.frontends.solve.solve` for it.
"""

import collections
import threading
import warnings

import numba
import numpy as np

from ..compile import warm as _warm
from ..events import compiled as compiled_events
from ..core import lanes, record
from ..validate import (
    DEFAULT_MAX_WINDOWS,
    ANGLE_PER_WINDOW,
    WINDOW_MARGIN,
    check_drive,
    check_max_windows,
    check_positive,
    check_real_array,
    check_rule_array,
    check_span,
    check_t_eval,
    check_tolerances,
    check_window_budget,
)
from ..approximants import Approximant, get_approximant
from ..choice import auto_name
from .solve import Integrator, _plan, _resolve, _tangent_request, compiled
from ..tangent import AccuracyWarning
from ..result import SolveResult
from ..regimes.summary import run_summary
from ..model import Pendulum
from ..status import STATUS_EVENT, STATUS_OK
from ..regimes import (
    REGIME_LIBRATION,
    REGIME_LOCKED,
    REGIME_NAMES,
    REGIME_NONE,
    REGIME_PHASE_LOCKED,
    REGIME_RUNNING,
)

__all__ = ["solve_batch"]

# Stride of solve_batch's scene order, as a fraction of the batch: the golden ratio's
# (Weyl sequence i·φ mod 1), so every contiguous block of the order samples the whole
# batch evenly.  Sweeps list scenes by parameter and cost varies ~100x along them
# (settling vs running); numba splits a prange into contiguous blocks, and in sweep
# order one thread got all the running scenes (2 threads: 1.16x; in this order 1.95x).
ORDER_STRIDE = 0.6180339887498949
# How often the thread waiting for a batch wakes to let Ctrl-C in (seconds).
BATCH_POLL = 0.05


def _is_zero(x):
    # A scalar 0 (the default): solve_batch's undriven call does no drive work at all.
    return np.ndim(x) == 0 and isinstance(x, (int, float, np.integer, np.floating)) and x == 0


def _balanced_order(n):
    """A permutation of range(n) whose contiguous blocks each sample the whole range."""
    return np.argsort((np.arange(n) * ORDER_STRIDE) % 1.0, kind="stable")


def _check_params(beta, gamma, omega, amp=None, freq=None, phase=None):
    # The rules of Pendulum, over arrays (mbm.validate); the first bad scene is named.
    names = ("beta", "gamma", "omega") + (() if amp is None else ("drive_amplitude", "drive_frequency",
                                                                  "drive_phase"))
    for name, arr in zip(names, (beta, gamma, omega, amp, freq, phase)):
        check_rule_array(name, arr)
    if amp is not None:
        check_drive(amp, freq)


def _run_interruptibly(job):
    # job(cancel) holds no GIL: run it in a thread and wait in short joins, so that a
    # KeyboardInterrupt reaches this (main) thread, which sets the cancel flag; every
    # scene then stops at its next window.  Returns job's result.
    cancel = np.zeros(1, dtype=np.int64)
    failure, result = [], []
    # numba's thread count is per calling thread (numba.set_num_threads): carry the
    # caller's into the worker thread.
    n_threads = numba.get_num_threads()

    def target():
        try:
            numba.set_num_threads(n_threads)
            result.append(job(cancel))
        except BaseException as exc:  # pragma: no cover - re-raised below
            failure.append(exc)

    worker = threading.Thread(target=target, name="mbm-solve-batch", daemon=True)
    worker.start()
    try:
        while worker.is_alive():
            worker.join(BATCH_POLL)
    except KeyboardInterrupt:
        cancel[0] = 1
        worker.join()
        raise
    if failure:
        raise failure[0]
    return result[0]


def _run_batch_interruptibly(p, te, out, order):
    # The batch without events (lanes and loop), interruptible; from a cold cache, a
    # helper process compiles the lanes beside them.
    eligible = lanes.eligible_rows(p)
    if eligible.any():
        _warm.prefetch("batch", lanes._run_lanes)
    _run_interruptibly(lambda cancel: lanes.run_batch(p, te, out, order, cancel, eligible=eligible))


def _scene_arrays(params, driven_call):
    """The parameter arrays broadcast to (N,), N ≥ 1, and checked by Pendulum's rules."""
    beta, gamma, omega, drive_amplitude, drive_frequency, drive_phase = params
    params = (beta, gamma, omega) + ((drive_amplitude, drive_frequency, drive_phase) if driven_call else ())
    which = "beta, gamma, omega" + (", drive_amplitude, drive_frequency, drive_phase" if driven_call else "")
    try:
        arrays = np.broadcast_arrays(*(np.atleast_1d(check_real_array(name, a))
                                       for name, a in zip(which.split(", "), params)))
    except ValueError:
        raise ValueError(
            f"{which} must broadcast to one shape (N,), got shapes "
            + ", ".join(str(np.shape(a)) for a in params)
        ) from None
    beta, gamma, omega = arrays[:3]
    if beta.ndim != 1:
        raise ValueError(f"{which} must broadcast to shape (N,), got shape {beta.shape}")
    n = beta.size
    if n == 0:
        raise ValueError(f"{which} must hold at least one scene (got empty arrays)")
    amp = freq = phase = None
    if driven_call:
        amp, freq, phase = arrays[3:]
    _check_params(beta, gamma, omega, amp, freq, phase)
    return beta, gamma, omega, amp, freq, phase


def _scene_states(y0, n):
    """The initial states as an (N, 2) array of finite numbers."""
    y0 = check_real_array("y0", y0)
    if y0.shape == (2,):
        y0 = np.broadcast_to(y0, (n, 2))
    if y0.shape != (n, 2):
        raise ValueError(f"y0 must have shape (2,) or ({n}, 2), got {y0.shape}")
    if not np.all(np.isfinite(y0)):
        raise ValueError(f"y0 must be finite, got y0[{int(np.flatnonzero(~np.isfinite(y0).all(axis=1))[0])}]")
    return y0


def _check_budgets(beta, gamma, omega, amp, y0, t0, t1, tau_checked, *, max_step, max_windows):
    """check_window_budget on the scenes its cheap test does not clear (vectorized here)."""
    span = t1 - t0
    longest = min(np.inf if tau_checked is None else tau_checked, max_step)
    limit = WINDOW_MARGIN * max_windows
    maybe = (np.abs(gamma) > omega**2) & (
        (np.abs(y0[:, 1]) + (np.abs(gamma) + omega**2) * abs(span)) * abs(span) >= limit * ANGLE_PER_WINDOW
    ) | (abs(span) >= limit * longest)
    if amp is not None:
        maybe &= amp == 0.0
    for i in np.flatnonzero(maybe) if span > 0.0 else ():
        try:
            check_window_budget(float(beta[i]), float(gamma[i]), float(omega[i]), 0.0, t0, t1, float(y0[i, 1]),
                                tau_checked, max_step=max_step, max_windows=max_windows)
        except ValueError as exc:
            raise ValueError(f"scene {i}: {exc}") from None


def _plan_scenes(approximant, beta, gamma, omega, amp, freq, phase, *, driven_call, tau, max_step, t0, t1):
    """Per scene: the drive (3, N), the plan (kind, karg, controller, error_order), h_abs, names."""
    n = beta.size
    undamped = (beta == 0.0) & (gamma == 0.0)
    drive = np.zeros((3, n))
    if driven_call:
        drive[0], drive[1], drive[2] = amp, freq, phase
        driven = amp != 0.0
        undamped &= ~driven
    # Per scene: kind, karg, controller, error_order (int64) and h_abs.
    plan = np.zeros((4, n), dtype=np.int64)
    h = np.zeros(n)
    names = np.empty(n, dtype=object)
    # "auto" resolves to at most two approximants (damped or not); a named one to one.
    for flag in (False, True):
        rows = np.flatnonzero(undamped == flag)
        if rows.size == 0:
            continue
        ap, kind, karg = _resolve(approximant, flag) if isinstance(approximant, str) else compiled(
            get_approximant(approximant))
        if driven_call and not ap.drive_capable and np.any(driven[rows]):
            i = int(rows[np.flatnonzero(driven[rows])[0]])
            ap.check_drive(Pendulum(beta[i], gamma[i], omega[i], amp[i], freq[i], phase[i]))
        if type(ap).check_model is not Approximant.check_model:
            # The approximant restricts the model: check each distinct model once.
            for b, g, w in {(beta[i], gamma[i], omega[i]) for i in rows}:
                ap.check_model(Pendulum(b, g, w))
        controller, h_abs, error_order = _plan(ap, tau, max_step, t0, t1)
        plan[0, rows], plan[1, rows], plan[2, rows], plan[3, rows] = kind, karg, controller, error_order
        h[rows] = h_abs
        names[rows] = ap.name
    return drive, plan, h, names


def _batch_result(p, te, out, wrap, names):
    """The SolveResult of a finished batch: outputs, status and regime summaries per scene."""
    n = names.size
    f = record.flat(p)
    status = f["status"].astype(np.int64)
    winding = None
    if wrap:
        # A failed scene's outputs past its failure stay NaN; its count there is 0.
        winding = np.where(np.isnan(out[:, 2]), 0.0, out[:, 2]).astype(np.int64)
        out = np.ascontiguousarray(out[:, :2])
    # Phase-locked scenes: period q·2π/Ω and pΩ/q, as regimes.strobe_summary (the same
    # operations, so the same bits).
    locked_to_drive = f["regime"] == REGIME_PHASE_LOCKED
    str_q = np.where(locked_to_drive, f["str_q"], 1.0)
    res = SolveResult(
        t=te, y=out, status=status, success=(status == STATUS_OK) | (status == STATUS_EVENT), winding=winding,
        n_windows=f["n_windows"].astype(np.int64), approximant=names.astype(str),
        regime=np.array([REGIME_NAMES[int(k)] for k in f["regime"]], dtype=object),
        t_regime=f["t_regime"].astype(np.float64),
        period=np.where((f["regime"] == REGIME_RUNNING) | (f["regime"] == REGIME_LIBRATION), f["cyc_T"],
                        np.divide(str_q * 2.0 * np.pi, f["drive_freq"], out=np.full(n, np.nan),
                                  where=locked_to_drive)),
        mean_velocity=np.where(
            (f["regime"] == REGIME_LOCKED) | (f["regime"] == REGIME_LIBRATION), 0.0,
            np.where(locked_to_drive, f["str_p"] * f["drive_freq"] / str_q,
                     np.divide(f["cyc_sign"] * 2.0 * np.pi, f["cyc_T"], out=np.full(n, np.nan),
                               where=f["regime"] == REGIME_RUNNING))),
    )
    # Driven scenes that never switched: the lock watch's reading (regimes.summary, S8).
    words = p.view(np.float64).reshape(n, -1)
    for i in np.flatnonzero((f["regime"] == REGIME_NONE) & (f["drive_amp"] != 0.0)):
        res.regime[i], res.period[i], res.mean_velocity[i] = run_summary(words[i])
    return res


def _batch_tangent(res, scenes, tangent, options, span):
    """Add ``error_estimate`` and ``sensitivities`` to a finished batch's result: each scene
    run again by its own :class:`Integrator` with the tangent pass (the same windows and
    outputs, bit for bit), the warnings gathered into one."""
    params, y0 = scenes
    t0, t1, wrap = span
    n, m = y0.shape[0], res["t"].size
    err = np.full((n, 2, m), np.nan)
    sens = np.full((n, len(tangent.names), 2, m), np.nan)
    loud = []
    for i in range(n):
        b, g, w, a, f, ph = (float(x) for x in params[i])
        ig = Integrator(Pendulum(b, g, w, drive_amplitude=a, drive_frequency=f, drive_phase=ph),
                        approximant=str(res["approximant"][i]), **options)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", AccuracyWarning)
            r = ig._solve(t0, t1, float(y0[i, 0]), float(y0[i, 1]), res["t"], wrap, tangent)
        if any(issubclass(c.category, AccuracyWarning) for c in caught):
            loud.append(i)
        k = r["t"].size
        if tangent.error_estimate:
            err[i, :, :k] = r["error_estimate"]
        if tangent.names:
            sens[i, :, :, :k] = r["sensitivities"]
    if tangent.error_estimate:
        res["error_estimate"] = err
    if tangent.names:
        res["sensitivities"] = sens
        res["sensitivity_names"] = tangent.names
    if loud:
        warnings.warn(f"solve_batch: the error estimate exceeds 10 times the tolerance in {len(loud)} of {n} "
                      f"scenes (the first: scene {loud[0]}); a tighter rtol/atol reduces it", AccuracyWarning,
                      stacklevel=3)


# solve_batch's options common to every scene (_run_options).
_RunOptions = collections.namedtuple("_RunOptions", ("t0", "t1", "t_eval", "rtol", "atol", "max_step", "max_windows"))


def _langevin_batch(params, y0, times, noise, refused):
    # solve_batch with a temperature: mbm.noise.paths, loaded on first use.
    from ..noise.paths import solve_langevin_batch

    for name, value in refused.items():
        if value is not None and value is not False:
            raise ValueError(f"{name} is not supported with a temperature > 0 (Langevin paths)")
    (t0, t1), (temperature, seed, dt) = check_span(times[0]), noise
    return solve_langevin_batch(params, y0, t0, t1, temperature=temperature, seed=seed, dt=dt, t_eval=times[1])


def _run_options(t_span, t_eval, rtol, atol, max_step, max_windows, wrap):
    # solve_batch's options common to every scene, checked.
    if t_eval is None:
        raise ValueError("t_eval is required for solve_batch (common output times)")
    t0, t1 = check_span(t_span)
    te = check_t_eval(t_eval, t0, t1)
    rtol, atol = check_tolerances(rtol, atol)
    max_step = check_positive("max_step", max_step, allow_inf=True)
    max_windows = check_max_windows(max_windows)
    if wrap is not False and wrap is not True:
        raise ValueError(f"wrap must be True or False, got {wrap!r}")
    return _RunOptions(t0, t1, te, rtol, atol, max_step, max_windows)


def _run_events(p, te, out, order, ev, cap, items, drive, *, fresh):
    # The scenes run with their events: the stored events and the counts.
    if any(compiled_events.is_event_function(e) for e in items):
        return compiled_events.run_batch_functions(p, te, out, order, ev, cap, items, drive)
    return _run_interruptibly(
        lambda cancel: compiled_events.run_batch_events(p, te, out, order, ev, cap, cancel, fresh))


def solve_batch(beta, gamma, omega, y0, t_span, t_eval, *, rtol=1e-6, atol=1e-9,
                approximant="auto", tau=None, max_step=np.inf, max_windows=DEFAULT_MAX_WINDOWS,
                drive_amplitude=0.0, drive_frequency=0.0, drive_phase=0.0, wrap=False, events=None,
                max_events=None, temperature=None, seed=None, dt=None, error_estimate=False, sensitivities=None):
    """Solve N scenes at once, in parallel over scenes (groups of scenes on numba's threads).

    Parameters
    ----------
    beta, gamma, omega : array_like
        Model parameters, broadcast to a common shape (N,), N ≥ 1.
    y0 : array_like, shape (2,) or (N, 2)
        Initial states.
    t_span, t_eval : (float, float), array_like (m,)
        Common time span and output times.
    rtol, atol, approximant, tau, max_step, max_windows
        As in :func:`mbm.solve` (one value for all scenes; "auto" chooses per scene).
    drive_amplitude, drive_frequency, drive_phase : array_like, optional
        The AC drive A sin(Ωt + φ) of each scene (default 0: none), broadcast with
        ``beta``, ``gamma``, ``omega`` (see :class:`mbm.Pendulum`).
    wrap : bool, optional
        As in :func:`mbm.solve`.
    events : Event, numba.njit function, or sequence of them, optional
        As in :func:`mbm.solve`, in every scene (bit for bit, however grouped); a
        terminal event stops its scene only.  Every scene must use a Taylor approximant,
        and be driven for a section event (:doc:`/guide/events`).
    max_events : int, optional
        Events of each kind stored per scene, K (default: the most any scene has).
    temperature, seed, dt : array_like, int, float, optional
        T > 0 (or one per scene): Langevin paths, scene i on the random stream
        (seed, i) (:doc:`/guide/noise`).  None or 0: as above.
    error_estimate, sensitivities : bool, sequence of str, optional
        As in :func:`mbm.solve`, per scene: ``error_estimate`` (N, 2, m), ``sensitivities``
        (N, len(names), 2, m), bit for bit :func:`mbm.solve`'s (each scene runs again with
        the pass); one :class:`mbm.AccuracyWarning` counts the scenes past 10× the tolerance.

    Returns
    -------
    SolveResult
        ``t`` (m,), ``y`` (N, 2, m), ``status`` (N,) per scene (0 ok, else the code of
        what stopped it, :doc:`/guide/statuses`), ``success`` (N,) bool, ``n_windows``
        (N,) steps taken, ``approximant`` (N,) names, ``regime``,
        ``t_regime``, ``period``, ``mean_velocity`` (N,) as in :func:`mbm.solve`, ``winding``
        (N, m) int64 with ``wrap=True`` (else None).  Each scene's answer equals
        :func:`mbm.solve` for that scene (a trapped scene's end apart).  A scene failing at
        run time (status ≠ 0) keeps its outputs so far, NaN after; the others are unaffected.
        With ``events``: ``t_events`` (N, n_events, K), ``y_events`` (N, n_events, K, 2)
        (NaN past each scene's stored count), ``winding_events`` (N, n_events, K) int64
        (0 past it) and ``n_events`` (N, n_events), every occurrence counted; status 6
        (``EVENT``) ends a scene at a terminal event (NaN after it), status 7
        (``CROWDED``) asks for a smaller ``max_step``; a damped scene trapped out of its
        events' reach ends early, ``"locked"`` (:doc:`/guide/events`).

    Raises
    ------
    ValueError
        Invalid arguments (named; for parameter arrays the first bad scene),
        ``max_events`` < 1 or without ``events``, events on a scene without a Taylor
        approximant, an approximant outside some scene's domain, a scene certain to
        take 100 times ``max_windows`` steps.
    TypeError
        Not real numbers (a str, bool, complex), an event neither mbm's nor ``numba.njit``,
        a non-int ``max_events``.
    KeyboardInterrupt
        Honoured while the batch runs (every scene stops at its next step).
    """
    driven_call = not (_is_zero(drive_amplitude) and _is_zero(drive_frequency) and _is_zero(drive_phase))
    beta, gamma, omega, amp, freq, phase = _scene_arrays(
        (beta, gamma, omega, drive_amplitude, drive_frequency, drive_phase), driven_call)
    y0 = _scene_states(y0, beta.size)
    tangent = _tangent_request(error_estimate, sensitivities, events)
    if temperature is not None and np.any(check_real_array("temperature", temperature) != 0.0):
        return _langevin_batch((beta, gamma, omega, amp, freq, phase), y0, (t_span, t_eval), (temperature, seed, dt),
                               {"tau": tau, "wrap": wrap, "events": events, "error_estimate": error_estimate,
                                "sensitivities": sensitivities})
    opts = _run_options(t_span, t_eval, rtol, atol, max_step, max_windows, wrap)
    if events is not None and isinstance(approximant, str) and approximant == "auto":
        approximant = auto_name(False)  # events are located on Taylor windows (mbm.solve)
    tau_checked = None if tau is None else check_positive("tau", tau)
    _check_budgets(beta, gamma, omega, amp, y0, opts.t0, opts.t1, tau_checked, max_step=opts.max_step,
                   max_windows=opts.max_windows)
    return _run_scenes((beta, gamma, omega, amp, freq, phase), y0, opts, approximant=approximant, tau=tau,
                       events=(events, max_events), wrap=wrap, tangent=tangent, driven_call=driven_call)


def _run_scenes(params, y0, opts, *, approximant, tau, events, wrap, tangent, driven_call):
    # solve_batch's run of its checked scenes (``params`` the six arrays, ``opts`` the
    # _RunOptions, ``events`` = (events, max_events)): plan, run in lanes, result.
    beta, gamma, omega, amp, freq, phase = params
    t0, t1, te, rtol, atol, max_step, max_windows = opts
    events, max_events = events
    tau_checked = None if tau is None else float(tau)
    drive, plan, h, names = _plan_scenes(approximant, beta, gamma, omega, amp, freq, phase, driven_call=driven_call,
                                         tau=tau, max_step=max_step, t0=t0, t1=t1)
    ev, cap, items = compiled_events.batch_table(events, max_events, plan[0], drive[0], drive[1], names)
    model = np.stack([beta, gamma, omega, drive[0], drive[1], drive[2]]).astype(np.float64)
    y0 = np.ascontiguousarray(y0, dtype=np.float64)

    def fresh(rows):
        # The records of the scenes ``rows`` at their start.
        q = np.empty(rows.size, dtype=record.RUN)
        record.init_runs(q, np.ascontiguousarray(model[:, rows]), np.ascontiguousarray(y0[rows]),
                         np.ascontiguousarray(plan[:, rows]), np.ascontiguousarray(h[rows]),
                         (float(t0), float(t1), float(max_step), float(rtol), float(atol), int(max_windows)))
        return q

    p = fresh(np.arange(beta.size))
    out = np.full((beta.size, 3 if wrap else 2, te.size), np.nan)
    order = _balanced_order(beta.size)
    if ev is None:
        _run_batch_interruptibly(p, te, out, order)
        res = _batch_result(p, te, out, wrap, names)
        if tangent is not None:  # each scene again by its Integrator, with the pass
            _batch_tangent(res, (np.stack([beta, gamma, omega, amp, freq, phase], axis=1), y0), tangent,
                           dict(rtol=rtol, atol=atol, tau=tau_checked, max_step=max_step, max_windows=max_windows),
                           (float(t0), float(t1), wrap))
        return res
    found = _run_events(p, te, out, order, ev, cap, items, drive, fresh=fresh)
    res = _batch_result(p, te, out, wrap, names)
    res["t_events"], res["y_events"], res["winding_events"], res["n_events"] = compiled_events.batch_event_arrays(
        items, cap, *found)
    return res
