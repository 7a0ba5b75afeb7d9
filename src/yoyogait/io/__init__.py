"""Readers of motion-capture files into :class:`Recording`."""

from .recording import Recording

__all__ = ["Recording"]
