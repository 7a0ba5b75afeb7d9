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


class about_file:  # noqa: N801 (used as a context manager, like contextlib's)
    """Context manager: an InputError raised inside that does not name ``path`` gets it in front,
    so that every message about a file says which file."""

    def __init__(self, path):
        self.path = str(path)

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if isinstance(exc, InputError) and self.path not in str(exc):
            raise InputError(f"{self.path}: {exc}") from None
        return False
