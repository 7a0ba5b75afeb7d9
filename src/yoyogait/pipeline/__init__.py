"""The pipeline from a recording to the estimator's input, stage by stage.

* :mod:`.points`: which point to follow (the pelvis centre, a hand, the feet) and the up axis;
* :mod:`.velocities`: the paper's velocity pipeline (Sec. IV-A), forward and vertical velocity;
* :mod:`.events`: foot contacts, steps and walking segments (the reference on real data);
* :mod:`.spectral`: the DFT check of the Yoyo-model;
* :mod:`.signals`: the small signal helpers they share.
"""

from __future__ import annotations

from .events import GaitEvents, detect_gait_events
from .spectral import SpectralCheck, dft_check
from .velocities import GaitVelocities, gait_velocities

__all__ = ["GaitEvents", "GaitVelocities", "SpectralCheck", "detect_gait_events", "dft_check", "gait_velocities"]
