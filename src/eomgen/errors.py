"""Errors raised for bad input: each message names the offending body, joint, frame or field."""


class ModelError(ValueError):
    """A system description that cannot be a valid multibody model."""
