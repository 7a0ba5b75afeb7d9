"""Where the controller's human velocity comes from: one source per feedback, fed frame by frame.

Every source sees one motion-capture frame at a time (the handle's measured position at ``t_s``)
and returns the horizontal velocity (vx, vy) the controller uses; nothing it returns depends on a
later frame.  The sources compared (:data:`SOURCE_NAMES`):

* ``none``: no human velocity (the T-RO 2021 controller);
* ``raw``: the handle's velocity by backward difference of consecutive frames, as a motion-capture
  system gives it;
* ``lowpass-<f>hz``: that, through a causal 2nd-order Butterworth low-pass at ``f`` Hz
  (scipy.signal.butter, stepped one frame at a time);
* ``yoyogait``: :class:`yoyogait.estimators.online.OnlineEstimator` on the handle: its walking
  velocity without the oscillation (``speed_mps`` along ``heading_rad``: ``walk_a_mps``,
  ``walk_b_mps``);
* ``yoyogait-gated``: the same, zero while the estimate is not usable (:func:`usable`: the
  estimate's ``valid``);
* ``yoyogait-predicted``: the same, with the walking speed predicted ``latency_s`` ahead by the
  estimator's forecast (:meth:`OnlineEstimator.predict`), so that after the latency it describes the
  present;
* ``truth``: the true intended velocity of the handle (the walker's intent plus the hand offset
  turning with the body, no oscillation), undelayed: the bound; no real sensor has it.

:class:`Delayed` puts the sensing and actuation latency in front of every source but ``truth``: a
delay line of ``round(latency_s * rate_hz)`` frames.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from ..errors import InputError
from ..estimators.online import OnlineConfig, OnlineEstimator

__all__ = [
    "SOURCE_NAMES",
    "LOWPASS_CUTOFFS_HZ",
    "VelocitySource",
    "Delayed",
    "make_source",
    "usable",
    "check_sources",
]

LOWPASS_CUTOFFS_HZ = (0.5, 1.0, 2.0)
"""Cut-offs of the Butterworth low-passes compared [Hz]."""

SOURCE_NAMES: tuple[str, ...] = (
    "none",
    "raw",
    *(f"lowpass-{f:g}hz" for f in LOWPASS_CUTOFFS_HZ),
    "yoyogait",
    "yoyogait-gated",
    "yoyogait-predicted",
    "truth",
)
"""Every feedback source, in the order of the tables."""

HANDLE = "handle"
_PREDICT_SAMPLES = 4  # the step-averaged forecast: 4 horizons a quarter step apart cancel harmonics 1-3


def usable(estimate) -> bool:
    """Whether the controller may use an estimate's walking velocity (the gate of ``yoyogait-gated``):
    the online estimate's ``valid`` (docs/online.md, the validity output)."""
    return bool(estimate.valid)


class VelocitySource:
    """A feedback source: ``update(t_s, handle_m, intent_v)`` -> (vx, vy) [m/s].

    ``handle_m``: the handle's measured position (3) at ``t_s``; ``intent_v``: the walker's true
    intended velocity (only ``truth`` reads it).
    """

    name = "none"
    delayed = True

    def update(self, t_s: float, handle_m, intent_v) -> tuple[float, float]:
        return 0.0, 0.0


class _Raw(VelocitySource):
    name = "raw"

    def __init__(self):
        self._last: tuple[float, float, float] | None = None

    def update(self, t_s, handle_m, intent_v):
        x, y = float(handle_m[0]), float(handle_m[1])
        last = self._last
        self._last = (t_s, x, y)
        if last is None or not t_s > last[0]:
            return 0.0, 0.0
        dt = t_s - last[0]
        return (x - last[1]) / dt, (y - last[2]) / dt


class _LowPass(VelocitySource):
    """The raw velocity through a 2nd-order Butterworth, direct form II transposed, per axis."""

    def __init__(self, cutoff_hz: float, rate_hz: float):
        self.name = f"lowpass-{cutoff_hz:g}hz"
        self._raw = _Raw()
        from scipy import signal  # scipy.signal takes about a second to import: only where it is used

        b, a = signal.butter(2, cutoff_hz, fs=rate_hz)
        self._b = [float(v) for v in b]
        self._a = [float(v) for v in a]
        self._z = [[0.0, 0.0], [0.0, 0.0]]  # starts at rest, as the walker does

    def update(self, t_s, handle_m, intent_v):
        v = self._raw.update(t_s, handle_m, intent_v)
        b0, b1, b2 = self._b
        _, a1, a2 = self._a
        out = []
        for axis in range(2):
            z = self._z[axis]
            x = v[axis]
            y = b0 * x + z[0]
            z[0] = b1 * x - a1 * y + z[1]
            z[1] = b2 * x - a2 * y
            out.append(y)
        return out[0], out[1]


class _Yoyogait(VelocitySource):
    def __init__(self, *, gated: bool = False, predict_s: float = 0.0):
        self.name = "yoyogait-gated" if gated else ("yoyogait-predicted" if predict_s > 0 else "yoyogait")
        # The handle is held: its rise and fall in place are no walking (gait_in_place false).
        self.estimator = OnlineEstimator([HANDLE], up_axis="z", config=OnlineConfig(gait_in_place=False))
        self.gated = gated
        self.predict_s = float(predict_s)
        self._frame = np.zeros((1, 3))

    def update(self, t_s, handle_m, intent_v):
        self._frame[0, :] = handle_m
        e = self.estimator.update(t_s, self._frame)
        if self.gated and not usable(e):
            return 0.0, 0.0
        if self.predict_s <= 0.0:
            return float(e.walk_a_mps), float(e.walk_b_mps)
        speed = self._predicted_speed(e)
        return speed * math.cos(e.heading_rad), speed * math.sin(e.heading_rad)

    def _predicted_speed(self, e) -> float:
        """The walking speed ``predict_s`` ahead: ``speed_mps`` plus the change, between horizons 0
        and ``predict_s``, of the forecast forward velocity averaged over one step (4 horizons a
        quarter step apart, which cancels the oscillation's harmonics 1 to 3)."""
        f = float(e.step_frequency_hz)
        if not (e.walking and f > 0.5):
            return float(e.speed_mps)
        quarter = 1.0 / (_PREDICT_SAMPLES * f)
        top = self.estimator.max_horizon_s
        now = ahead = 0.0
        for j in range(_PREDICT_SAMPLES):
            h = j * quarter
            if self.predict_s + h > top:
                return float(e.speed_mps)
            now += self.estimator.predict(h).vx_mps
            ahead += self.estimator.predict(self.predict_s + h).vx_mps
        return float(e.speed_mps) + (ahead - now) / _PREDICT_SAMPLES


class _Truth(VelocitySource):
    name = "truth"
    delayed = False

    def update(self, t_s, handle_m, intent_v):
        return float(intent_v[0]), float(intent_v[1])


class Delayed(VelocitySource):
    """``source`` seen ``frames`` frames late: a delay line (zeros until it has filled)."""

    def __init__(self, source: VelocitySource, frames: int):
        self.source = source
        self.name = source.name
        self.frames = int(frames)
        self._line: deque = deque([(0.0, 0.0)] * self.frames, maxlen=self.frames + 1)

    def update(self, t_s, handle_m, intent_v):
        self._line.append(self.source.update(t_s, handle_m, intent_v))
        return self._line.popleft()


def check_sources(names) -> tuple[str, ...]:
    """The names as a tuple, InputError naming the unknown ones."""
    names = tuple(names)
    unknown = [n for n in names if n not in SOURCE_NAMES]
    if unknown or not names:
        raise InputError(
            f"--source: unknown source {', '.join(unknown) or '(none given)'}; known: {', '.join(SOURCE_NAMES)}"
        )
    return tuple(dict.fromkeys(names))


def make_source(name: str, *, latency_s: float, rate_hz: float) -> VelocitySource:
    """The source called ``name`` behind a ``latency_s`` delay line (``truth``: no delay)."""
    check_sources([name])
    if name == "none":
        source: VelocitySource = VelocitySource()
    elif name == "raw":
        source = _Raw()
    elif name.startswith("lowpass-"):
        source = _LowPass(float(name[len("lowpass-") : -len("hz")]), rate_hz)
    elif name == "yoyogait":
        source = _Yoyogait()
    elif name == "yoyogait-gated":
        source = _Yoyogait(gated=True)
    elif name == "yoyogait-predicted":
        source = _Yoyogait(predict_s=latency_s)
    else:
        source = _Truth()
    frames = int(round(latency_s * rate_hz))
    if not source.delayed or frames == 0:
        return source
    return Delayed(source, frames)
