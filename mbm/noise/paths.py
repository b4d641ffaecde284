"""``mbm.solve(..., temperature=T)``: one Langevin path of a :class:`mbm.Pendulum` scene.

The scene's θ'' + βθ' + ω² sin θ = γ + A sin(Ωt + φ) with the noise ξ, ⟨ξ(t)ξ(t')⟩ =
2βT δ(t − t'), integrated at a fixed step by the splitting O(h/2) D(h) O(h/2)
(:func:`mbm.noise.kernels.path_kernel`); outputs on the step grid.  A path runs in
compiled calls of at most :data:`CHUNK_STEPS` scene-steps, the state carried between
them; step k draws pair k of its stream, so the bits do not depend on the cuts.
"""

import math

import numpy as np

from ..result import SolveResult
from ..validate import as_t_eval, check_positive, check_real_array, check_rule_array
from .api import DT_DEFAULT, DT_MAX, MAX_STEPS
from .flow import make_params, substeps
from .kernels import batch_path_kernel, path_kernel
from .rng import resolve_seed

__all__ = ["solve_langevin", "solve_langevin_batch"]

# A t_eval time is on the step grid when within this many steps of a grid point.
GRID_SLACK = 1e-6
# The method's name in the result (``approximant``).
METHOD = "langevin-odo"
# Scene-steps per compiled call (a batch of N scenes runs CHUNK_STEPS // N steps a call):
# a Ctrl-C lands between calls, ~0.05 s apart, and a call's overhead (µs) stays negligible.
CHUNK_STEPS = 2**16


def _check_dt(dt, w_eff):
    # The step: default DT_DEFAULT / ω_eff, else in (0, DT_MAX / ω_eff].
    dt = DT_DEFAULT / w_eff if dt is None else check_positive("dt", dt)
    if dt * w_eff > DT_MAX:
        raise ValueError(f"dt must be in (0, {DT_MAX}/max(omega, drive_frequency)] = "
                         f"(0, {DT_MAX / w_eff!r}], got {dt!r}")
    return dt


def _marks(t_eval, t0, t1, dt):
    # Step counts of the outputs: every step without t_eval, else t_eval's (on the grid).
    n_steps = int(round((t1 - t0) / dt))
    if abs(t0 + n_steps * dt - t1) > GRID_SLACK * dt:
        raise ValueError(f"t_span must be a whole number of steps dt = {dt!r} with a temperature, "
                         f"got a span of {t1 - t0!r} ({(t1 - t0) / dt!r} steps)")
    if n_steps > MAX_STEPS:
        raise ValueError(f"the span must be at most {MAX_STEPS} steps dt, got {n_steps}")
    if t_eval is None:
        return np.arange(n_steps + 1, dtype=np.int64)
    t = as_t_eval(t_eval)
    k = np.round((t - t0) / dt)
    if t.size and (np.any(np.abs(t0 + k * dt - t) > GRID_SLACK * dt) or np.any(k < 0) or np.any(k > n_steps)
                   or np.any(np.diff(k) < 0)):
        raise ValueError(f"t_eval must be sorted times t0 + k*dt within t_span (dt = {dt!r}) with a temperature")
    return k.astype(np.int64)


def _in_chunks(run, marks, per_call):
    # run(k0, k1, j0) for consecutive step ranges [k0, k1] of at most per_call steps up
    # to the last mark; j0 indexes the first mark not yet written (marks at k0 were
    # written by the call before, which ended there).
    end = int(marks[-1]) if marks.size else 0
    k0 = 0
    j0 = 0
    while True:
        k1 = min(k0 + per_call, end)
        run(k0, k1, j0)
        if k1 >= end:
            return
        j0 = int(np.searchsorted(marks, k1, side="right"))
        k0 = k1


def solve_langevin(model, t0, t1, theta0, v0, *, temperature, seed=None, dt=None, t_eval=None):
    """One path of ``model`` with thermal noise at ``temperature``: a SolveResult.

    Parameters
    ----------
    model : Pendulum
        β > 0 (the noise strength is 2βT), γ, ω, and the drive.
    t0, t1 : float
        The span, t1 > t0, a whole number of steps.
    theta0, v0 : float
        The start.
    temperature : float
        T > 0.
    seed : int, optional
        The stream's seed (scene 0 of it); None draws one.
    dt : float, optional
        The step, in (0, 1/ω_eff]; default 0.1/ω_eff with ω_eff = max(ω, Ω).
    t_eval : array_like, optional
        Output times on the step grid; default every step.

    Returns
    -------
    SolveResult
        ``t``, ``y`` (2, m), ``success``, ``status`` 0, ``message``, ``n_steps``,
        ``seed``, ``temperature``, ``dt``, ``approximant`` "langevin-odo".
    """
    temperature = check_positive("temperature", temperature)
    if not model.beta > 0.0:
        raise ValueError(f"model.beta must be > 0 with a temperature (noise 2*beta*T), got {model.beta!r}")
    if not t1 > t0:
        raise ValueError(f"t_span must run forward (t_bound > t0) with a temperature, got ({t0!r}, {t1!r})")
    dt = _check_dt(dt, max(model.omega, model.drive_frequency))
    marks = _marks(t_eval, t0, t1, dt)
    seed = resolve_seed(seed)
    amp = model.drive_amplitude
    p = make_params(model.beta, model.omega, model.gamma, 0.0, amp, model.drive_frequency,
                    model.drive_phase + model.drive_frequency * t0, temperature)
    plan = substeps(dt, model.omega, abs(model.gamma) + abs(amp), model.drive_frequency)
    state = np.array([theta0, v0], dtype=float)
    y = np.empty((marks.size, 2))
    _in_chunks(lambda k0, k1, j0: path_kernel(p, (np.uint64(seed), 0), state, (k0, k1, dt), plan, marks[j0:], y[j0:]),
               marks, CHUNK_STEPS)
    return SolveResult(t=t0 + marks * dt, y=np.ascontiguousarray(y.T), success=True, status=0,
                       message="Langevin path completed (fixed step)", n_steps=int(marks[-1]) if marks.size else 0,
                       approximant=METHOD, seed=seed, temperature=temperature, dt=dt,
                       regime=None, t_regime=math.nan, period=math.nan, mean_velocity=math.nan)


def solve_langevin_batch(params, y0, t0, t1, *, temperature, seed=None, dt=None, t_eval=None):
    """:func:`solve_langevin` for N scenes in parallel: scene i on the stream (seed, i).

    Parameters
    ----------
    params : tuple of ndarray
        (β, γ, ω, A, Ω, φ), each (N,) (A, Ω, φ None: no drive), checked by the caller
        (β > 0 is checked here).
    y0 : ndarray (N, 2)
        The starts.
    t0, t1 : float
        The common span (forward, whole steps).
    temperature : float or array_like
        T > 0, one or one per scene (broadcast to (N,)).
    seed, dt, t_eval
        As :func:`solve_langevin` (dt from the largest max(ω, Ω) of the scenes).

    Returns
    -------
    SolveResult
        ``t`` (m,), ``y`` (N, 2, m), ``status`` (N,) zeros, ``success`` (N,),
        ``n_steps``, ``seed``, ``temperature`` (N,), ``dt``, ``approximant``.  Scene 0
        is :func:`solve_langevin`'s path for the same seed.
    """
    beta, gamma, omega, amp, freq, phase = params
    n = beta.size
    amp, freq, phase = (np.zeros(n) if a is None else a for a in (amp, freq, phase))
    temps = np.broadcast_to(check_rule_array("temperature", check_real_array("temperature", temperature),
                                             (">0", "> 0")), (n,)).astype(float)
    check_rule_array("beta", beta, (">0", "> 0 with a temperature (noise 2*beta*T)"))
    if not t1 > t0:
        raise ValueError(f"t_span must run forward (t_bound > t0) with a temperature, got ({t0!r}, {t1!r})")
    dt = _check_dt(dt, float(np.max(np.maximum(omega, freq))))
    marks = _marks(t_eval, t0, t1, dt)
    seed = resolve_seed(seed)
    table = np.stack([make_params(beta[i], omega[i], gamma[i], 0.0, amp[i], freq[i],
                                  phase[i] + freq[i] * t0, temps[i]) for i in range(n)])
    plans = np.array([substeps(dt, omega[i], abs(gamma[i]) + abs(amp[i]), freq[i]) for i in range(n)],
                     dtype=np.int64)
    states = np.array(y0, dtype=float, order="C")
    y = np.empty((n, marks.size, 2))
    _in_chunks(lambda k0, k1, j0: batch_path_kernel(table, np.uint64(seed), states, (k0, k1, dt), plans,
                                                    marks[j0:], y[:, j0:]), marks, max(1, CHUNK_STEPS // n))
    return SolveResult(t=t0 + marks * dt, y=np.ascontiguousarray(y.transpose(0, 2, 1)),
                       status=np.zeros(n, dtype=np.int64), success=np.ones(n, dtype=bool),
                       message="Langevin paths completed (fixed step)",
                       n_steps=int(marks[-1]) if marks.size else 0, approximant=METHOD, seed=seed,
                       temperature=temps, dt=dt)
