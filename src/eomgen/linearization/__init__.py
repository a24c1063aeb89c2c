"""Linearization about an operating point (`linearize`): ẋ ≈ ẋ0 + A (x − x0) + B (r − r0)."""
from .linearize import linearize
from .result import Linearization

__all__ = ["Linearization", "linearize"]
