"""Short guided walks shared by the guidance tests (a few seconds of simulation each)."""

from __future__ import annotations

import numpy as np
import pytest

from yoyogait.guidance import GuidePath


@pytest.fixture(scope="session")
def short_path() -> GuidePath:
    """A 5 m walk with a left turn after 3 m (SYNTHETIC)."""
    return GuidePath("short", np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 2.0]]), np.ones(3), np.zeros(3))
