"""pylsl, imported on first use, with one clear line when it is absent."""

from __future__ import annotations

from typing import Any

from ..errors import YoyogaitError

INSTALL_HINT = (
    "live streaming over LSL needs pylsl: pip install 'yoyogait[live]' (ROS 2 topics in, without LSL: "
    "yoyogait ros2, docs/ros2.md)"
)


def pylsl() -> Any:
    """The pylsl module; YoyogaitError naming the ``live`` extra when it cannot be loaded."""
    try:
        import pylsl as module
    except (ImportError, OSError, RuntimeError) as exc:  # absent, or its bundled liblsl does not load
        raise YoyogaitError(f"{INSTALL_HINT} ({exc})") from None
    return module


def child_text(element: Any, name: str) -> str:
    """Text of the child ``name`` of an LSL XML element, "" when absent."""
    child = element.child(name)
    return "" if child.empty() else child.child_value().strip()


def children(element: Any, name: str) -> list[Any]:
    """Every child ``name`` of an LSL XML element, in order."""
    found = []
    child = element.child(name)
    while not child.empty():
        found.append(child)
        child = child.next_sibling(name)
    return found
