"""Analytic approximants, one module per source paper (named after its first author)."""

from .base import (
    Anchored,
    Approximant,
    ApproximantDomainError,
    approximant_names,
    get_approximant,
    register,
)

__all__ = [
    "Anchored",
    "Approximant",
    "ApproximantDomainError",
    "approximant_names",
    "get_approximant",
    "register",
]
