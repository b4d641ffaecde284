r"""Thermal escape of the junction: :func:`escape_times`, :func:`switching_currents`, Kramers.

The model: θ'' + βθ' + ω² sin θ = γ(t) + ξ(t), ⟨ξ(t)ξ(t')⟩ = 2βT δ(t − t'), T the
temperature in the equation's energy unit (the Hamiltonian θ'²/2 − ω² cos θ − γθ:
T = k_B T / E_J for ω = 1), integrated by the splitting of :mod:`mbm.noise.kernels`.
"""

import contextlib
import dataclasses
import math
import numbers

import numba
import numpy as np

from ..validate import check_integer, check_positive, check_real, check_rule
from .flow import make_params, substeps
from .kernels import escape_kernel, switching_kernel, thermal_start_kernel
from .rng import resolve_seed

__all__ = ["EscapeTimes", "SwitchingHistogram", "barrier_action", "bhl_rate", "escape_times",
           "kramers_rate", "switching_currents", "well"]

# Default step (units of 1/ω): agreement with a dt = 0.005 Heun run within 3 standard
# errors on 4,000 escapes at β = 1, γ = 0.7, T = 0.063 (benchmarks/noise.py).
DT_DEFAULT = 0.1
# The longest step accepted (units of 1/ω): past it the splitting's error is no longer
# small (its exact pieces keep it stable, not accurate).
DT_MAX = 1.0
# escape_times' default horizon, in Kramers mean times: a scene still in its well then
# (reported as inf) has probability e^-100 if Kramers holds, and e^-10 even if the
# true rate is ten times lower (weak damping).
KRAMERS_HORIZON = 100.0
# Steps one scene may take at most (a horizon past it is refused): ~1e9 steps are
# minutes of one core.
MAX_STEPS = 10**9
# switching_currents: the run ends at γ = GAMMA_END ω² (no well left past ω²: a scene
# still trapped there is reported as nan).
GAMMA_END = 1.5
# switching_currents: a switch is confirmed when θ reaches this (a further full slip
# past the first barrier's far side π: in the underdamped regime above retrapping,
# the running state).
THETA_DONE = 3.0 * math.pi
# Scenes per compiled call of escape_times and switching_currents: a Ctrl-C lands between
# calls (about a second each at the benchmark's scenes on 2 cores), enough scenes per
# call to keep every thread busy.
CHUNK_SCENES = 1024


def well(gamma, omega=1.0):
    """The well of U(θ) = −ω² cos θ − γθ holding θ = arcsin(γ/ω²) (abs(γ) < ω²).

    Returns
    -------
    dict
        ``theta_min``, ``theta_max`` (the barrier top on the downhill side,
        π − arcsin(γ/ω²) for γ ≥ 0), ``barrier`` ΔU = 2 sqrt(ω⁴ − γ²) −
        2abs(γ) arccos(abs(γ)/ω²), ``omega_well`` = ``omega_barrier`` = (ω⁴ − γ²)^{1/4}.
    """
    w2 = omega * omega
    x = gamma / w2
    g = abs(gamma)
    root = math.sqrt(w2 * w2 - gamma * gamma)
    th = math.asin(x)
    top = math.copysign(math.pi, gamma if gamma != 0 else 1.0) - th
    return {"theta_min": th, "theta_max": top, "omega_well": math.sqrt(root),
            "omega_barrier": math.sqrt(root), "barrier": 2.0 * root - 2.0 * g * math.acos(g / w2)}


def kramers_rate(beta, gamma, temperature, omega=1.0):
    r"""Kramers' escape rate (moderate to high damping) out of the well of :func:`well`.

    k = (ω_a / 2π) (sqrt(1 + α²) − α) e^{−ΔU/T}, α = β / (2 ω_b); valid for ΔU ≫ T
    and β S / T ≫ 1 with S the action of the barrier orbit (:func:`barrier_action`;
    the spatial-diffusion regime).  At weaker damping the energy supply, not the
    barrier crossing, limits the rate: :func:`bhl_rate`.  For γ = 0 the two
    barriers are both counted (k doubled).

    Parameters
    ----------
    beta : float
        Damping, > 0.
    gamma : float
        Bias, abs(γ) < ω².
    temperature : float
        T > 0 (as :func:`escape_times`).
    omega : float, optional
        Plasma frequency ω > 0.

    Returns
    -------
    float
        The rate k (escapes per unit time).
    """
    beta, gamma, temperature, omega, w = _rate_args(beta, gamma, temperature, omega)
    a = beta / (2.0 * w["omega_barrier"])
    k = w["omega_well"] / (2.0 * math.pi) * (math.sqrt(1.0 + a * a) - a)
    return k * math.exp(-w["barrier"] / temperature) * (2.0 if gamma == 0.0 else 1.0)


def barrier_action(gamma, omega=1.0):
    r"""The action S = ∮ θ' dθ of the orbit at the barrier energy in the well of :func:`well`.

    The orbit at E_b = U(θ_max), U(θ) = −ω² cos θ − γθ, from the far turning point
    θ_1 (U(θ_1) = E_b) to the barrier top and back: S = 2 ∫ sqrt(2 (E_b − U)) dθ over
    (θ_1, θ_max).  β S is the energy the damping takes from it in one period.  S = 16ω
    at γ = 0 (the separatrix); S → 7.2 ΔU/ω_a as abs(γ) → ω² (the cubic well).

    Parameters
    ----------
    gamma : float
        Bias, abs(γ) < ω².
    omega : float, optional
        Plasma frequency ω > 0.

    Returns
    -------
    float
        S (in units of the energy over ω).
    """
    from scipy.integrate import quad
    from scipy.optimize import brentq

    omega = check_rule("omega", omega)
    g = abs(_check_gamma(gamma, omega))
    w2 = omega * omega
    if g == 0.0:
        return 16.0 * omega
    w = well(g, omega)
    top = w["theta_max"]

    def gap(th):  # E_b − U(θ), ≥ 0 on the orbit
        return w2 * (math.cos(th) - math.cos(top)) + g * (th - top)

    # θ_1 in (top − 2π, θ_min): U(top − 2π) = E_b + 2πγ lies above the barrier energy
    th1 = brentq(gap, top - 2.0 * math.pi, w["theta_min"], xtol=1e-15, rtol=4 * np.finfo(float).eps)
    val = quad(lambda th: math.sqrt(2.0 * max(gap(th), 0.0)), th1, top, epsabs=0.0, epsrel=1e-12,
               limit=200)[0]
    return 2.0 * val


def bhl_rate(beta, gamma, temperature, omega=1.0):
    r"""The escape rate out of the well of :func:`well` from weak to moderate damping (BHL).

    k = (ω_a / 2π) · 4 / (1 + sqrt(1 + 4T/(βS)))² · e^{−ΔU/T}, S the action of the
    barrier orbit (:func:`barrier_action`): the Büttiker–Harris–Landauer rate (M.
    Büttiker, E. P. Harris and R. Landauer, Phys. Rev. B 28, 1268 (1983)) in the
    interpolating form of Martinis, Devoret and Clarke (Phys. Rev. B 35, 4682 (1987),
    where 1.8 ΔU/Q = ω_a·S/(4Q) for the cubic well).  For βS ≪ T it is the
    energy-diffusion rate (ω_a/2π)(βS/T) e^{−ΔU/T}, below Kramers'
    (:func:`kramers_rate`, which holds for βS ≫ T); for βS ≫ T it tends to the
    transition-state rate (ω_a/2π) e^{−ΔU/T}.  Valid for ΔU ≫ T.  For γ = 0 both
    barriers are reached on the same orbit: one rate, not doubled.

    Parameters
    ----------
    beta : float
        Damping, > 0.
    gamma : float
        Bias, abs(γ) < ω².
    temperature : float
        T > 0 (as :func:`escape_times`).
    omega : float, optional
        Plasma frequency ω > 0.

    Returns
    -------
    float
        The rate k (escapes per unit time).
    """
    beta, gamma, temperature, omega, w = _rate_args(beta, gamma, temperature, omega)
    delta = beta * barrier_action(gamma, omega) / temperature
    a_t = 4.0 / (1.0 + math.sqrt(1.0 + 4.0 / delta)) ** 2
    return w["omega_well"] / (2.0 * math.pi) * a_t * math.exp(-w["barrier"] / temperature)


@dataclasses.dataclass(frozen=True)
class EscapeTimes:
    """First-slip times out of the starting well (:func:`escape_times`).

    A frozen dataclass built by :func:`escape_times`: each parameter is an attribute.

    Parameters
    ----------
    times : ndarray (n,)
        Each scene's escape time; inf for a scene still in its well at ``t_max``.
    mean, stderr : float
        Mean and standard error of the finite times (nan if none).
    rate : float
        Escapes per unit time: escaped count / total time spent in the well (the
        maximum-likelihood rate of an exponential law, censored scenes counted).
    seed : int
        The run's seed (reproduces it).
    dt, t_max : float
        The step and the horizon.
    """

    times: np.ndarray
    mean: float
    stderr: float
    rate: float
    seed: int
    dt: float
    t_max: float


@dataclasses.dataclass(frozen=True)
class SwitchingHistogram:
    """Switching biases under a linear ramp γ = γ0 + r t (:func:`switching_currents`).

    A frozen dataclass built by :func:`switching_currents`: each parameter is an attribute.

    Parameters
    ----------
    currents : ndarray (n,)
        Each scene's switching bias γ_sw (the equation's units; I_sw/I_c = γ_sw/ω²);
        nan for a scene that had not switched by γ = 1.5 ω².
    mean, width : float
        Mean and standard deviation (ddof = 1) of the finite currents.
    skewness : float
        m3 / m2^{3/2} (≈ −1 for thermal activation; a Gumbel law has −1.14).
    kurtosis : float
        m4 / m2², not the excess (≈ 5 for thermal activation; a Gumbel law has 5.4,
        a normal law 3).
    seed : int
        The run's seed (reproduces it).
    dt, ramp_rate : float
        The step and the ramp r.
    """

    currents: np.ndarray
    mean: float
    width: float
    skewness: float
    kurtosis: float
    seed: int
    dt: float
    ramp_rate: float


def _check_gamma(gamma, omega, name="gamma"):
    g = check_real(name, gamma)
    if not abs(g) < omega * omega:
        raise ValueError(f"{name} must satisfy |{name}| < omega**2 = {omega * omega!r} "
                         f"(a well to escape from), got {g!r}")
    return g


def _rate_args(beta, gamma, temperature, omega):
    # A rate formula's arguments checked, and the well they describe.
    beta = check_positive("beta", beta)
    temperature = check_positive("temperature", temperature)
    omega = check_rule("omega", omega)
    gamma = _check_gamma(gamma, omega)
    return beta, gamma, temperature, omega, well(gamma, omega)


def ramp_args(beta, temperature, ramp_rate, omega, n, dt):
    """A ramped histogram's arguments checked (:func:`switching_currents`,
    :func:`mbm.retrapping_currents`): (β, T, r, ω, n, dt)."""
    beta = check_positive("beta", beta)
    temperature = check_positive("temperature", temperature)
    ramp_rate = check_positive("ramp_rate", ramp_rate)
    omega = check_rule("omega", omega)
    return beta, temperature, ramp_rate, omega, _check_count(n), _check_dt(dt, omega)


def _check_count(n):
    return check_integer("n", n, 1)


def _check_dt(dt, omega):
    dt = check_positive("dt", dt)
    if dt * omega > DT_MAX:
        raise ValueError(f"dt must be in (0, {DT_MAX}/omega] = (0, {DT_MAX / omega!r}], got {dt!r}")
    return dt


@contextlib.contextmanager
def _threads(threads):
    # numba's thread count for the duration of a run (None: as it is).
    if threads is None:
        yield
        return
    if isinstance(threads, (bool, np.bool_)) or not isinstance(threads, numbers.Integral):
        raise TypeError(f"threads must be None or an integer >= 1, got {threads!r}")
    top = numba.config.NUMBA_NUM_THREADS
    if not 1 <= threads <= top:
        raise ValueError(f"threads must be in [1, {top}], got {threads!r}")
    before = numba.get_num_threads()
    numba.set_num_threads(int(threads))
    try:
        yield
    finally:
        numba.set_num_threads(before)


def _chunked(run, seed, n):
    """``run((seed, first), m)`` over the n scenes CHUNK_SCENES at a time, the results
    joined: scene i draws the stream of scene i whatever the chunks, and a
    KeyboardInterrupt lands between two compiled calls."""
    out = np.empty(n)
    for first in range(0, n, CHUNK_SCENES):
        m = min(CHUNK_SCENES, n - first)
        out[first:first + m] = run((np.uint64(seed), np.int64(first)), m)
    return out


def _steps(t_max, dt, name="t_max"):
    steps = int(math.ceil(t_max / dt))
    if steps > MAX_STEPS:
        raise ValueError(f"{name} / dt must be <= {MAX_STEPS} steps, got {steps}")
    return steps


def _thermal_starts(p, stream, m, gamma, omega):
    # The Boltzmann starts of scenes first .. first + m − 1 in the well of θ0 = arcsin(γ/ω²),
    # between its two barrier tops −π − θ0 and π − θ0, where U is lowest at θ0.
    th0 = math.asin(gamma / (omega * omega))
    u_min = -omega * omega * math.cos(th0) - gamma * th0
    return thermal_start_kernel(p, stream, m, -math.pi - th0, u_min)


def escape_times(beta, gamma, temperature, n, *, omega=1.0, seed=None, dt=DT_DEFAULT,
                 t_max=None, threads=None, start="bottom"):
    r"""First-slip times of ``n`` thermal junctions out of their starting well.

    Each scene starts at the well bottom θ0 = arcsin(γ/ω²) with θ' = 0 (or from the
    Boltzmann law in the well, ``start="thermal"``) and runs
    θ'' + βθ' + ω² sin θ = γ + ξ(t), ⟨ξ(t)ξ(t')⟩ = 2βT δ(t − t'), until θ reaches the
    next well's bottom θ0 ± 2π: one completed phase slip, ΔU + 2πabs(γ) below the barrier
    top on the downhill side, so that a crossing counted is not undone (the time from
    the barrier top down there is O(1/ω), against the e^{ΔU/T} of the wait).

    Parameters
    ----------
    beta : float
        Damping, > 0 (the noise strength is 2βT).
    gamma : float
        Bias, abs(γ) < ω² (a well to escape from).
    temperature : float
        T > 0 in the unit of the energy θ'²/2 − ω² cos θ − γθ.
    n : int
        Number of independent scenes, ≥ 1.
    omega : float, optional
        Plasma frequency ω > 0.
    seed : int, optional
        In [0, 2^64 − 1]; None draws one (kept in the result).  Scene i uses the
        counter-based stream (seed, i): the same seed gives the same bits on any
        thread count.
    dt : float, optional
        Step of the splitting O(h/2) D(h) O(h/2), in (0, 1/ω].
    t_max : float, optional
        Horizon; default 100 Kramers mean times (:data:`KRAMERS_HORIZON`).
    threads : int, optional
        numba threads for this call (default: numba's current count).
    start : {"bottom", "thermal"}, optional
        "bottom": θ0, θ' = 0.  "thermal": θ' ~ N(0, T) and θ from e^{−U(θ)/T} between
        the well's two barrier tops (−π − θ0, π − θ0), drawn by rejection from scene
        i's own stream at counters from 2^40 on, apart from the steps' (the scene's
        energy is not capped: a start above the barrier, probability ~e^{−ΔU/T}, escapes
        at once).

    Returns
    -------
    EscapeTimes
    """
    beta = check_positive("beta", beta)
    omega = check_rule("omega", omega)
    gamma = _check_gamma(gamma, omega)
    temperature = check_positive("temperature", temperature)
    n = _check_count(n)
    dt = _check_dt(dt, omega)
    if not (isinstance(start, str) and start in ("bottom", "thermal")):
        raise ValueError(f"start must be 'bottom' or 'thermal', got {start!r}")
    seed = resolve_seed(seed)
    if t_max is None:
        t_max = min(KRAMERS_HORIZON / kramers_rate(beta, gamma, temperature, omega), MAX_STEPS * dt)
    t_max = check_positive("t_max", t_max)
    steps = _steps(t_max, dt)
    th0 = math.asin(gamma / (omega * omega))
    p = make_params(beta, omega, gamma, 0.0, 0.0, 0.0, 0.0, temperature)
    bounds = np.array([th0 - 2.0 * math.pi, th0 + 2.0 * math.pi])
    with _threads(threads):
        plan = substeps(dt, omega, abs(gamma), 0.0)

        def run(stream, m):
            starts = (_thermal_starts(p, stream, m, gamma, omega) if start == "thermal"
                      else np.tile(np.array([th0, 0.0]), (m, 1)))
            return escape_kernel(p, stream, m, starts, dt, plan, steps, bounds)

        times = _chunked(run, seed, n)
    done = times[np.isfinite(times)]
    mean = float(done.mean()) if done.size else math.nan
    se = float(done.std(ddof=1) / math.sqrt(done.size)) if done.size > 1 else math.nan
    total = float(done.sum()) + (n - done.size) * steps * dt
    return EscapeTimes(times, mean, se, done.size / total, seed, dt, steps * dt)


def _moments(x):
    # (mean, std ddof=1, skewness m3/m2^1.5, kurtosis m4/m2^2) of the finite values.
    x = x[np.isfinite(x)]
    if x.size < 2:
        return (float(x.mean()) if x.size else math.nan), math.nan, math.nan, math.nan
    d = x - x.mean()
    m2, m3, m4 = (d**2).mean(), (d**3).mean(), (d**4).mean()
    return float(x.mean()), float(x.std(ddof=1)), float(m3 / m2**1.5), float(m4 / m2**2)


def switching_currents(beta, temperature, ramp_rate, n, *, omega=1.0, seed=None,
                       dt=DT_DEFAULT, gamma_start=0.0, threads=None):
    r"""Switching biases of ``n`` thermal junctions under the ramp γ(t) = γ0 + r t.

    Each scene starts at the well bottom θ = arcsin(γ0/ω²), θ' = 0, and runs
    θ'' + βθ' + ω² sin θ = γ0 + r t + ξ(t) (γ0 = ``gamma_start``, 0 by default).  Its
    switching bias is γ at the end of the step where θ last went past the top of its first well's barrier (π/2 < θ and
    ω² sin θ < γ(t), i.e. θ > π − arcsin(γ/ω²)), read when θ reaches 3π: one further
    full slip, the running state in the underdamped regime above retrapping.  A
    backward slip (θ ≤ −π) is wrapped by 2π.

    Parameters
    ----------
    beta : float
        Damping, > 0.
    temperature : float
        T > 0 (as :func:`escape_times`).
    ramp_rate : float
        r > 0, bias per unit time.
    n : int
        Number of scenes, ≥ 1.
    omega, seed, dt : optional
        As :func:`escape_times`.
    gamma_start : float, optional
        γ0, the bias at t = 0, in [0, ω²) (a start where escape is negligible saves
        the ramp's uneventful part; the scene thermalises within ~2/β).
    threads : int, optional
        As :func:`escape_times`.

    Returns
    -------
    SwitchingHistogram
        ``kurtosis`` is m4/m2² (not the excess).
    """
    beta, temperature, ramp_rate, omega, n, dt = ramp_args(beta, temperature, ramp_rate, omega, n, dt)
    g0 = _check_gamma(check_rule("gamma_start", gamma_start, (">=0", ">= 0")), omega, "gamma_start")
    seed = resolve_seed(seed)
    g_end = GAMMA_END * omega * omega
    slowest = (g_end - g0) / (MAX_STEPS * dt)
    if ramp_rate < slowest:
        raise ValueError(f"ramp_rate must be >= {slowest!r} with dt = {dt!r} (the ramp to "
                         f"1.5 omega**2 in at most {MAX_STEPS} steps), got {ramp_rate!r}")
    steps = _steps((g_end - g0) / ramp_rate, dt)
    p = make_params(beta, omega, g0, ramp_rate, 0.0, 0.0, 0.0, temperature)
    with _threads(threads):
        plan = substeps(dt, omega, g_end, 0.0)
        t = _chunked(lambda stream, m: switching_kernel(p, stream, m, math.asin(g0 / (omega * omega)), dt, plan,
                                                        steps, THETA_DONE), seed, n)
    currents = np.where(np.isfinite(t), g0 + ramp_rate * t, np.nan)
    return SwitchingHistogram(currents, *_moments(currents), seed, dt, ramp_rate)
