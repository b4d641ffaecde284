"""An independent oracle for the damped, torqued pendulum: heyoka in long double.

θ'' + βθ' + ω² sin θ = γ, y = [θ, θ'], integrated by heyoka's adaptive Taylor method
(``taylor_adaptive``, LLVM-compiled; Biscani & Izzo 2021) in ``numpy.longdouble``
(the 80-bit x87 format of x86-64: 64-bit mantissa, eps = 1.08e-19) at tol = 1e-19.
It shares no code with mbm: its own coefficient recurrences, its own order and step
rules.  Checked against mbm's exact undamped flow (``mbm.pendulum_flow``, Jacobi
elliptic functions in double-double) by ``tests/test_oracle.py``.

β, γ and ω² are runtime parameters (``ta.pars``), so one integrator, compiled once
per process (a few seconds for long double), serves every scene.  A driven scene
(torque γ + A sin(Ωt + φ), ``drive=(A, Ω, φ)``) has its own integrator, with the drive
``A·hy.sin(Ω·hy.time + φ)`` in heyoka's expression system and A, Ω, φ as runtime
parameters too (compiled on its first use), so the undriven oracle is untouched.
"""

import numpy as np

__all__ = ["ORACLE_TOL", "available", "reference"]

# heyoka's tolerance in long double: its eps (1.08e-19), rounded; the order it picks
# from it (ceil(−ln tol / 2) + 1 = 23) keeps each step's truncation at round-off.
ORACLE_TOL = 1e-19

_CACHE = {}


def available():
    """Whether heyoka imports and ``numpy.longdouble`` is wider than a double."""
    try:
        import heyoka  # noqa: F401
    except ImportError:
        return False
    return np.finfo(np.longdouble).eps < 1e-18


def _integrator():
    ta = _CACHE.get("ta")
    if ta is None:
        import heyoka as hy

        x, v = hy.make_vars("x", "v")
        # par[0] = β, par[1] = γ, par[2] = ω².
        sys = [(x, v), (v, hy.par[1] - hy.par[0] * v - hy.par[2] * hy.sin(x))]
        ld = np.longdouble
        ta = hy.taylor_adaptive(sys, np.zeros(2, dtype=ld), tol=ld(ORACLE_TOL),
                                pars=np.zeros(3, dtype=ld), fp_type=ld)
        _CACHE["ta"] = ta
    return ta


def _driven_integrator():
    ta = _CACHE.get("ta_drive")
    if ta is None:
        import heyoka as hy

        x, v = hy.make_vars("x", "v")
        # par[0] = β, par[1] = γ, par[2] = ω², par[3] = A, par[4] = Ω, par[5] = φ.
        torque = hy.par[1] + hy.par[3] * hy.sin(hy.par[4] * hy.time + hy.par[5])
        sys = [(x, v), (v, torque - hy.par[0] * v - hy.par[2] * hy.sin(x))]
        ld = np.longdouble
        ta = hy.taylor_adaptive(sys, np.zeros(2, dtype=ld), tol=ld(ORACLE_TOL),
                                pars=np.zeros(6, dtype=ld), fp_type=ld)
        _CACHE["ta_drive"] = ta
    return ta


def reference(beta, gamma, omega, y0, t_eval, return_steps=False, drive=None):
    """θ, θ' at ``t_eval`` from ``y0`` at ``t_eval[0]``, by heyoka in long double.

    Parameters
    ----------
    beta, gamma, omega : float
        Model parameters.
    y0 : array_like, shape (2,)
        [θ, θ'] at ``t_eval[0]``.
    t_eval : array_like, shape (m,)
        Output times, monotone (either direction); the first is the start time.
    return_steps : bool, optional
        Also return the number of steps heyoka took (its round-off accumulates over
        them).
    drive : (float, float, float), optional
        The AC drive (A, Ω, φ) added to the torque: γ + A sin(Ωt + φ), t the time of
        ``t_eval`` (default None: no drive).

    Returns
    -------
    ndarray of numpy.longdouble, shape (2, m)
        [θ(t_eval), θ'(t_eval)] (long double: round to float64 only after
        differencing against a float64 solution, to keep the oracle's digits).
    steps : int
        Only with ``return_steps``.

    Raises
    ------
    RuntimeError
        If heyoka does not reach the last output time.
    """
    import heyoka as hy

    ld = np.longdouble
    ta = _integrator() if drive is None else _driven_integrator()
    t = np.asarray(t_eval, dtype=ld)
    ta.time = t[0]
    ta.state[0] = ld(y0[0])
    ta.state[1] = ld(y0[1])
    ta.pars[0] = ld(beta)
    ta.pars[1] = ld(gamma)
    ta.pars[2] = ld(omega) * ld(omega)
    if drive is not None:
        ta.pars[3] = ld(drive[0])
        ta.pars[4] = ld(drive[1])
        ta.pars[5] = ld(drive[2])
    outcome, _min_h, _max_h, steps, *_, out = ta.propagate_grid(t)
    if outcome != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"heyoka propagate_grid stopped: {outcome}")
    y = np.ascontiguousarray(np.asarray(out).T)
    return (y, int(steps)) if return_steps else y
