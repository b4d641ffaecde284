"""Analytic approximants, one module per source paper (named after its first author).

Every paper module is imported here, explicitly, so that its ``@register`` decorators
have run once ``mbm.approximants`` is loaded.
"""

from .base import (
    Anchored,
    Approximant,
    ApproximantDomainError,
    approximant_names,
    get_approximant,
    register,
)
from . import salas2022  # noqa: F401,E402  second paper: Salas, Martínez, Ocampo (2022)
from . import belendez2007  # noqa: F401,E402  third paper: Beléndez et al. (2007)
from . import salas2021  # noqa: F401,E402  first paper: Salas (2021), Johannessen (2014)
from . import taylor  # noqa: F401,E402  convergent: anchored Taylor series of the true equation
from . import splitting  # noqa: F401,E402  convergent: exact elliptic + drift flow compositions

__all__ = [
    "Anchored",
    "Approximant",
    "ApproximantDomainError",
    "approximant_names",
    "get_approximant",
    "register",
]
