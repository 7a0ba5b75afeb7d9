"""``python -m yoyogait.ros2 [--ros-args -p name:=value ...]``: the node (as ``yoyogait ros2``)."""

from __future__ import annotations

import sys

from .node import main

if __name__ == "__main__":
    sys.exit(main())
