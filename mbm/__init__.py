"""mbm: the moving boundary method for the damped, torque-driven pendulum.

θ'' + β θ' + ω² sin θ = γ, integrated by re-anchored analytic approximants, as a
drop-in ``scipy.integrate.solve_ivp`` method (:class:`MBM`).
"""

from .approximants import (
    Anchored,
    Approximant,
    ApproximantDomainError,
    approximant_names,
    get_approximant,
)
from .approximants.belendez2007 import pendulum_flow, period
from .problem import Pendulum, identify_model
from .reference import reference
from . import choice
from .fast import solve, solve_batch
from .solver import MBM

__version__ = "0.1.0"

__all__ = [
    "MBM",
    "Anchored",
    "Approximant",
    "ApproximantDomainError",
    "Pendulum",
    "approximant_names",
    "get_approximant",
    "identify_model",
    "pendulum_flow",
    "period",
    "reference",
    "solve",
    "solve_batch",
]
