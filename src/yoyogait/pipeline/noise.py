"""The velocity noise that a recording's own samples show: their part above the gait's band.

Walking velocity has its power at the step frequency and its first harmonics (below 5-6 Hz at
any cadence up to 2.5 steps/s); what a marker system adds above that is noise. The offline
estimator's measurement noise is raised to it where it exceeds the configured one
(:func:`yoyogait.estimators.registry.noise_adapted`), so that a markerless capture's centimetres
of jitter are weighed as noise and not followed as gait; a laboratory capture stays below the
configured noise and nothing changes.
"""

from __future__ import annotations

import numpy as np

__all__ = ["NOISE_CUTOFF_HZ", "velocity_noise_var"]

NOISE_CUTOFF_HZ = 6.0
"""Above this the walking velocity holds no gait (the second harmonic of 2.5 steps/s is 5 Hz)."""

_MIN_RUN = 16  # samples: shorter runs of finite samples are left out (filtfilt needs 9)


def velocity_noise_var(v, rate_hz: float, cutoff_hz: float = NOISE_CUTOFF_HZ) -> float:
    """The noise variance of the velocity samples ``v`` [(m/s)^2]: the mean square of their part
    above ``cutoff_hz`` (``v`` less a zero-phase second-order Butterworth low-pass of it), over the
    runs of finite samples, times nyquist / (nyquist - cutoff_hz) for the noise below the cutoff
    (a flat noise spectrum). 0 when there are too few samples or the rate leaves too little band
    above the cutoff (cutoff at 0.8 of the Nyquist frequency or more)."""
    v = np.asarray(v, dtype=float)
    nyquist = 0.5 * float(rate_hz)
    if not (cutoff_hz > 0 and nyquist > 0 and cutoff_hz < 0.8 * nyquist):
        return 0.0
    from scipy import signal  # scipy.signal takes about a second to import: only where it is used

    b, a = signal.butter(2, cutoff_hz / nyquist)
    finite = np.isfinite(v)
    # Runs of finite samples: their starts and ends.
    edges = np.flatnonzero(np.diff(np.concatenate(([0], finite.astype(np.int8), [0]))))
    squares, n = 0.0, 0
    for start, end in zip(edges[::2], edges[1::2]):
        if end - start < _MIN_RUN:
            continue
        run = v[start:end]
        residual = run - signal.filtfilt(b, a, run)
        squares += float(np.sum(residual * residual))
        n += end - start
    if n == 0:
        return 0.0
    return squares / n * nyquist / (nyquist - cutoff_hz)
