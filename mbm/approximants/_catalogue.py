"""Imports every paper module so that its approximants are registered."""

from . import salas2022  # noqa: F401  second paper: Salas, Martínez, Ocampo (2022)
from . import belendez2007  # noqa: F401  third paper: Beléndez et al. (2007)
from . import salas2021  # noqa: F401  first paper: Salas (2021), Johannessen (2014)
from . import taylor  # noqa: F401  convergent: anchored Taylor series of the true equation
from . import splitting  # noqa: F401  convergent: exact elliptic + drift flow compositions
