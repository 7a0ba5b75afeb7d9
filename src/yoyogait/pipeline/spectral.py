"""The DFT check of the Yoyo-model (Sec. IV-A of the paper).

Over the walking part of a recording, find the dominant frequency of the
forward and of the vertical velocity oscillation, the step frequency (the
fundamental of the vertical one, see :func:`step_frequency`), and the phase
offset between forward and vertical at the step frequency.  The Yoyo-model (eq. 3-4),

    v_x = R w + r w cos(theta),   v_z = -r w sin(theta) = r w cos(theta + 90 deg),

has the forward oscillation a quarter cycle behind the vertical one:

    offset = phase(v_x) - phase(v_z) = -90 deg.

An offset near +90 deg means the opposite: the forward velocity is lowest
when the pelvis is highest (mid-stance), as in an inverted pendulum.

The spectrum is that of the mean- and trend-free signal under a Hann window
(few cycles in a short walk; the window keeps the start/stop transients
from leaking into the peak), zero-padded to ``resolution_hz`` so the peak is
read to better than the raw 1/T spacing.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError

__all__ = ["SpectralCheck", "dft_check", "dominant_frequency", "step_frequency", "spectrum", "MODEL_OFFSET_DEG"]

#: Phase of the forward minus the vertical velocity oscillation in the Yoyo-model.
MODEL_OFFSET_DEG = -90.0


@dataclass
class SpectralCheck:
    """Result of the DFT check over one stretch of walking."""

    step_frequency_hz: float  # fundamental of the vertical velocity (:func:`step_frequency`)
    vertical_frequency_hz: float  # strongest peak of the vertical velocity
    forward_frequency_hz: float  # strongest peak of the forward velocity
    phase_offset_deg: float  # phase(v_x) - phase(v_z) at the step frequency, in (-180, 180]
    forward_amplitude_mps: float  # of the oscillation at the step frequency
    vertical_amplitude_mps: float
    start_s: float
    end_s: float
    model_offset_deg: float = MODEL_OFFSET_DEG

    @property
    def duration_s(self) -> float:
        return self.end_s - self.start_s

    @property
    def offset_from_model_deg(self) -> float:
        """How far the measured offset is from the model's -90 deg, in (-180, 180]."""
        return _wrap(self.phase_offset_deg - self.model_offset_deg)

    @property
    def offset_sign(self) -> str:
        """ "negative" (as in the Yoyo-model) or "positive" (the opposite)."""
        return "negative" if self.phase_offset_deg < 0 else "positive"

    @property
    def matches_model(self) -> bool:
        """Measured offset within 45 deg of the model's."""
        return abs(self.offset_from_model_deg) <= 45.0

    @property
    def verdict(self) -> str:
        """ "consistent" (within 45 deg of the model), "opposite sign" (within 45 deg of +90) or "not consistent"."""
        if self.matches_model:
            return "consistent"
        return "opposite sign" if abs(self.offset_from_model_deg) >= 135.0 else "not consistent"

    def summary(self) -> str:
        """Two lines saying what the data show against the model."""
        lead = "lags" if self.phase_offset_deg < 0 else "leads"
        harmonic = (
            ""
            if abs(self.vertical_frequency_hz - self.step_frequency_hz) < 0.05
            else (f" (strongest vertical peak {self.vertical_frequency_hz:.2f} Hz is its harmonic)")
        )
        return (
            f"step frequency {self.step_frequency_hz:.2f} Hz{harmonic}; dominant forward "
            f"{self.forward_frequency_hz:.2f} Hz (over {self.duration_s:.1f} s of walking)\n"
            f"phase offset forward - vertical: {self.phase_offset_deg:+.0f} deg, {self.offset_sign} "
            f"(forward {lead} vertical); the Yoyo-model has {self.model_offset_deg:+.0f} deg: {self.verdict}"
        )


def spectrum(signal, rate_hz: float, resolution_hz: float = 0.005):
    """Frequencies and DFT magnitudes of the mean- and trend-free, Hann-windowed signal, zero-padded."""
    x = np.asarray(signal, dtype=float)
    if x.size < 4 or not np.all(np.isfinite(x)):
        raise InputError("the DFT needs at least 4 finite samples")
    n_fft = max(x.size, int(np.ceil(rate_hz / resolution_hz)))
    magnitude = np.abs(np.fft.rfft(_detrend(x) * np.hanning(x.size), n_fft))
    return np.fft.rfftfreq(n_fft, 1.0 / rate_hz), magnitude


def dominant_frequency(
    signal, rate_hz: float, min_hz: float = 0.5, max_hz: float = 4.0, resolution_hz: float = 0.005
) -> float:
    """Frequency of the largest spectral peak of ``signal`` within ``min_hz``-``max_hz``."""
    freqs, magnitude = spectrum(signal, rate_hz, resolution_hz)
    band = _band(freqs, min_hz, max_hz)
    return float(freqs[band][np.argmax(magnitude[band])])


def step_frequency(
    signal,
    rate_hz: float,
    min_hz: float = 0.5,
    max_hz: float = 4.0,
    subharmonic_ratio: float = 0.5,
    resolution_hz: float = 0.005,
) -> float:
    """The fundamental of the step oscillation: the strongest peak, or half of it.

    In slow walking the pelvis rises twice per step (the vertical path turns
    M-shaped), so the strongest peak of the vertical velocity can be the
    second harmonic.  When the spectrum has a separate peak near half the
    strongest frequency that is at least ``subharmonic_ratio`` as tall, that
    one is the step frequency.  (A Hann window's side lobes are 3 % tall, so
    only a real oscillation passes the test.)  Strong left-right asymmetry
    would pass it too; then this returns the stride frequency.
    """
    freqs, magnitude = spectrum(signal, rate_hz, resolution_hz)
    band = _band(freqs, min_hz, max_hz)
    idx = np.flatnonzero(band)
    top = idx[np.argmax(magnitude[idx])]
    f_top = freqs[top]
    near_half = np.flatnonzero((freqs >= max(min_hz, 0.85 * f_top / 2)) & (freqs <= 1.15 * f_top / 2))
    peaks = [
        i
        for i in near_half
        if 0 < i < len(freqs) - 1 and magnitude[i] >= magnitude[i - 1] and magnitude[i] > magnitude[i + 1]
    ]
    if peaks:
        best = max(peaks, key=lambda i: magnitude[i])
        if magnitude[best] >= subharmonic_ratio * magnitude[top]:
            return float(freqs[best])
    return float(f_top)


def dft_check(velocities, *, min_hz: float = 0.5, max_hz: float = 4.0, min_duration_s: float = 1.5) -> SpectralCheck:
    """The DFT check over the longest stretch of walking of a :class:`~yoyogait.GaitVelocities`.

    InputError if that stretch is shorter than ``min_duration_s`` (a DFT of
    fewer than about three steps cannot tell the step frequency).
    """
    part = velocities.walking_part()
    n = part.stop - part.start
    rate = velocities.rate_hz
    if n / rate < min_duration_s:
        raise InputError(
            f"{velocities.source}: only {n / rate:.2f} s of walking in one stretch; "
            f"the DFT check needs {min_duration_s:g} s"
        )
    vx = velocities.vx[part]
    vz = velocities.vz[part]
    t = velocities.time_s[part]
    f_step = step_frequency(vz, rate, min_hz, max_hz)
    cx = _coefficient(vx, t, f_step)
    cz = _coefficient(vz, t, f_step)
    return SpectralCheck(
        step_frequency_hz=f_step,
        vertical_frequency_hz=dominant_frequency(vz, rate, min_hz, max_hz),
        forward_frequency_hz=dominant_frequency(vx, rate, min_hz, max_hz),
        phase_offset_deg=_wrap(np.degrees(np.angle(cx) - np.angle(cz))),
        forward_amplitude_mps=float(np.abs(cx)),
        vertical_amplitude_mps=float(np.abs(cz)),
        start_s=float(t[0]),
        end_s=float(t[-1]),
    )


def _band(freqs: np.ndarray, min_hz: float, max_hz: float) -> np.ndarray:
    band = (freqs >= min_hz) & (freqs <= max_hz)
    if not band.any():
        raise InputError(f"no frequency between {min_hz} and {max_hz} Hz at this rate")
    return band


def _detrend(x: np.ndarray) -> np.ndarray:
    """Without mean and linear trend (a start or stop inside the stretch is a trend, not a step)."""
    k = np.arange(x.size)
    return x - np.polyval(np.polyfit(k, x, 1), k)


def _coefficient(x: np.ndarray, t: np.ndarray, f_hz: float) -> complex:
    """Complex amplitude of ``x`` at ``f_hz`` (the DFT at one frequency), Hann-weighted.

    For x = A cos(2 pi f t + phi) its angle is phi and its magnitude about A.
    """
    w = np.hanning(x.size)
    return complex(2.0 * np.sum(w * _detrend(x) * np.exp(-2j * np.pi * f_hz * t)) / np.sum(w))


def _wrap(deg: float) -> float:
    """Angle in (-180, 180]."""
    wrapped = (float(deg) + 180.0) % 360.0 - 180.0
    return 180.0 if wrapped == -180.0 else wrapped
