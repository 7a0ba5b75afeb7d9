"""Errors that carry a message meant for the user.

The CLI prints these as one line and exits non-zero; the library raises them
so that a caller can tell bad input from a bug.
"""


class YoyogaitError(Exception):
    """Base class of every error yoyogait raises on purpose."""


class InputError(YoyogaitError, ValueError):
    """A file, array or argument that yoyogait cannot use (says what is wrong)."""


class OutputError(YoyogaitError, OSError):
    """An output that could not be written (says which, and why; never a temporary name)."""
