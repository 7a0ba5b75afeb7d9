"""The one recording type every reader produces."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

AXES = ("x", "y", "z")


@dataclass
class Recording:
    """Motion-capture points over time, in metres.

    ``positions_m`` is frames x points x 3 in the file's frame, NaN where a
    point is missing (never zero).  ``time_s`` holds the timestamp of every
    frame; ``rate_hz`` is the nominal rate when the file has one.
    ``up_axis`` is ``"x"``, ``"y"`` or ``"z"`` when the file says it, else None.
    """

    positions_m: np.ndarray
    point_names: list[str]
    time_s: np.ndarray
    rate_hz: float | None = None
    up_axis: str | None = None
    source: str = ""
    metadata: dict = field(default_factory=dict)

    @property
    def n_frames(self) -> int:
        return int(self.positions_m.shape[0])

    @property
    def duration_s(self) -> float:
        return float(self.time_s[-1] - self.time_s[0]) if self.n_frames > 1 else 0.0

    def point(self, name: str) -> np.ndarray:
        """Trajectory (frames x 3) of the point called ``name``."""
        from ..errors import InputError

        try:
            return self.positions_m[:, self.point_names.index(name), :]
        except ValueError:
            raise InputError(
                f"no point {name!r} in {self.source or 'the recording'}; "
                f"available: {', '.join(self.point_names)}"
            ) from None
