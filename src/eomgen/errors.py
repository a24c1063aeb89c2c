"""Errors raised for bad input: each message names the offending body, joint, frame or field."""
from __future__ import annotations

import difflib
from collections.abc import Iterable


class ModelError(ValueError):
    """A system description that cannot be a valid multibody model."""


class UnknownName(ModelError, KeyError):
    """A name that is not among the known ones (a `KeyError` too, for lookups in a mapping)."""

    __str__ = ModelError.__str__  # the message, not KeyError's repr of it


def unknown(kind: str, name, known: Iterable) -> UnknownName:
    """The error for `name` not among `known`: the known names listed, the closest suggested (difflib)."""
    known = sorted(map(str, known))
    close = difflib.get_close_matches(str(name), known, n=3, cutoff=0.6)
    hint = f"; did you mean {' or '.join(map(repr, close))}?" if close else ""
    return UnknownName(f"unknown {kind} {name!r}{hint} (the {kind}s are {known})")


class ByName(dict):
    """Results by name ({joint: ...}); a missing name is an `UnknownName` naming the known ones."""

    def __init__(self, kind: str, items) -> None:
        super().__init__(items)
        self.kind = kind

    def __missing__(self, name):
        raise unknown(self.kind, name, self)
