"""mbm: the moving boundary method for the damped, torque-driven pendulum.

θ'' + β θ' + ω² sin θ = γ, integrated by re-anchored analytic approximants, as a
drop-in ``scipy.integrate.solve_ivp`` method (:class:`MBM`) and as a compiled
whole-run solver (:func:`solve`, :func:`solve_batch`).

:class:`MBM` and the :mod:`mbm.events.points` module import ``scipy.integrate`` (about
half a second); they are loaded on first use so that ``import mbm`` followed by
:func:`solve` stays fast.

At import, :mod:`mbm.compile.cache` drops numba's cached kernels if any of mbm's sources
changed since they were cached (``MBM_KEEP_CACHE=1`` skips this), and the first
compilation of a kernel in a process writes one line to stderr (``MBM_COMPILE_NOTICE=0``
silences it); while numba compiles mbm's kernels, :mod:`mbm.compile.gc` runs Python's
garbage collector less often (``MBM_COMPILE_GC=0`` leaves it alone).
"""

import importlib

from .compile import cache as _cache
from .compile import cache_lock as _cache_lock
from .compile import gc as _compile_gc

# Before any compiled module: a kernel must not load another's code from a cache two
# processes wrote at once, nor from a cache older than its callees,
# and a first compile should say so (MBM_KEEP_CACHE=1, MBM_COMPILE_NOTICE=0 turn these off)
# and not spend a tenth of its time in the garbage collector (MBM_COMPILE_GC=0).
_cache_lock.install()
_cache.check_sources()
_cache.install_compile_notice()
_compile_gc.install()

from . import choice  # noqa: F401  (mbm.choice: the "auto" rule, documented in the README)
from .approximants import (
    Anchored,
    Approximant,
    ApproximantDomainError,
    approximant_names,
    get_approximant,
)
from .special.pendulum_flow import pendulum_flow, period
from .frontends.solve import Integrator, solve, solve_njit
from .frontends.batch import solve_batch
from .events.compiled import Event, angle_event, section_event, velocity_event
from .events.njit import event_table, solve_njit_events, solve_njit_function_events
from .junction.iv import IVCurve, IVCurveSI, iv_curve
from .model import Pendulum
from .frontends.probe import identify_model
from .junction.shapiro import ShapiroStep, ShapiroStepSI, ShapiroSteps, ShapiroStepsSI, shapiro_steps
from .frontends.reference import reference

__version__ = "0.1.0"

__all__ = [
    "AccuracyWarning",
    "MBM",
    "MBMEventPoints",
    "Anchored",
    "Approximant",
    "ApproximantDomainError",
    "EscapeTimes",
    "Event",
    "IVCurve",
    "IVCurveSI",
    "IVFit",
    "Integrator",
    "Junction",
    "Pendulum",
    "ShapiroStep",
    "ShapiroSteps",
    "ShapiroStepsSI",
    "ShapiroStepSI",
    "RetrappingHistogram",
    "SwitchingHistogram",
    "angle_event",
    "approximant_names",
    "beta_from_retrapping",
    "bhl_rate",
    "escape_times",
    "event_table",
    "fit_iv",
    "get_approximant",
    "identify_model",
    "iv_curve",
    "kramers_rate",
    "pendulum_flow",
    "period",
    "reference",
    "retrapping_current",
    "retrapping_currents",
    "SENSITIVITY_NAMES",
    "section_event",
    "shapiro_steps",
    "solve",
    "solve_batch",
    "solve_njit",
    "solve_njit_events",
    "solve_njit_function_events",
    "successive",
    "sweep",
    "switching_currents",
    "switching_grid",
    "velocity_event",
]

# name -> (module, attribute or None for the module itself)
_LAZY = {
    "MBM": ("mbm.frontends.ivp", "MBM"),
    "MBMEventPoints": ("mbm.frontends.ivp", "MBMEventPoints"),
    "events": ("mbm.events.points", None),
    "scenes": ("mbm.scenes", None),
    "successive": ("mbm.events.points", "successive"),
    "solver": ("mbm.frontends.ivp", None),
    # xarray and dask are optional (pip install "mbm[dask]"): loaded on first use
    "sweep": ("mbm.junction.sweeps", "sweep"),
    # scipy.constants and scipy.optimize (~0.2 s and more): loaded on first use
    "Junction": ("mbm.junction.units", "Junction"),
    "IVFit": ("mbm.junction.fits", "IVFit"),
    "beta_from_retrapping": ("mbm.junction.fits", "beta_from_retrapping"),
    "fit_iv": ("mbm.junction.fits", "fit_iv"),
    "retrapping_current": ("mbm.junction.fits", "retrapping_current"),
    # thermal noise (issue 54): its kernels compile on first use, not at import
    "noise": ("mbm.noise", None),
    "EscapeTimes": ("mbm.noise.api", "EscapeTimes"),
    "SwitchingHistogram": ("mbm.noise.api", "SwitchingHistogram"),
    "escape_times": ("mbm.noise.api", "escape_times"),
    "kramers_rate": ("mbm.noise.api", "kramers_rate"),
    "bhl_rate": ("mbm.noise.api", "bhl_rate"),
    # xarray (optional) is imported when switching_grid runs
    "switching_grid": ("mbm.noise.grids", "switching_grid"),
    "switching_currents": ("mbm.noise.api", "switching_currents"),
    "RetrappingHistogram": ("mbm.noise.retrap", "RetrappingHistogram"),
    "retrapping_currents": ("mbm.noise.retrap", "retrapping_currents"),
    # error bars and sensitivities (issue 51)
    "AccuracyWarning": ("mbm.tangent.api", "AccuracyWarning"),
    "SENSITIVITY_NAMES": ("mbm.tangent.api", "SENSITIVITY_NAMES"),
}


def __getattr__(name):
    if name in _LAZY:
        mod_name, attr = _LAZY[name]
        mod = importlib.import_module(mod_name)
        value = mod if attr is None else getattr(mod, attr)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'mbm' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
