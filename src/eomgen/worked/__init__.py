"""Worked solutions step by step, in textbook form, rendered as LaTeX, Markdown and in Jupyter."""

from .build import solution
from .document import Solution
from .steps import Step

__all__ = ["Solution", "Step", "solution"]
