"""Identification: base parameters and their grouping."""
from .grouping import Grouping, group

__all__ = ["Grouping", "group"]
