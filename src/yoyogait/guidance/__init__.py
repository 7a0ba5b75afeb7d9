"""Tethered guidance: a person guided along a path by an aerial robot, the estimate in its control law.

A consumer of estimates, like :mod:`yoyogait.evaluation`: it uses the online estimator and the
synthetic lab's walker, and nothing but the command line uses it.  Everything it simulates is
SYNTHETIC (docs/guidance.md).
"""

from __future__ import annotations

from .paths import BUILTIN_WALKS, GuidePath, builtin_walk, read_path
from .simulation import GuidanceConfig, GuidanceRun, cable_force, simulate
from .sources import SOURCE_NAMES, usable
from .walker import GuidedWalker, HumanModel

__all__ = [
    "BUILTIN_WALKS",
    "GuidePath",
    "builtin_walk",
    "read_path",
    "GuidanceConfig",
    "GuidanceRun",
    "cable_force",
    "simulate",
    "SOURCE_NAMES",
    "usable",
    "GuidedWalker",
    "HumanModel",
]
