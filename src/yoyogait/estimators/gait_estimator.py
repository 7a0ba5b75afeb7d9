"""The gait estimator: Python face of the C++ core.

``GaitEstimator(config).step(vx, vz)`` is the streaming form (one estimate per
sample); ``run(vx, vz)`` is the batch form over arrays.  Both go through the
same native ``step``, so their results agree bit for bit, and ``run`` resumes
where the last call ended, so a signal run in chunks gives the same result as
one run.

Two algorithms: the default gait filter (``EstimatorConfig()``, preset
``"default"``; docs/default_estimator.md) and the paper's estimator exactly as
published (``EstimatorConfig.paper()``, preset ``"paper"``;
docs/paper_estimator.md).
"""

from __future__ import annotations

import math

import numpy as np

from .. import _core
from ..errors import InputError
from .config import EstimatorConfig
from .results import EstimateResult

__all__ = ["GaitEstimator", "Status"]

Status = _core.Status
"""What a step did with its sample (``Status.UPDATED``, ``REJECTED_NON_FINITE``, ...)."""


def _as_signal(name: str, values) -> np.ndarray:
    arr = np.asarray(values, dtype=np.float64)
    if arr.ndim != 1:
        raise InputError(f"{name} must be one-dimensional, got shape {arr.shape}")
    return np.ascontiguousarray(arr)


class GaitEstimator:
    """Online estimator of step frequency, forward speed and the Yoyo-model parameters.

    >>> est = GaitEstimator()                  # the default estimator; GaitEstimator(EstimatorConfig.paper())
    >>> e = est.step(1.2, 0.05)                # one sample: a native Estimate
    >>> e = est.step(1.2, 0.05, dt_s=0.041)    # ... taken 0.041 s after the previous one
    >>> result = est.run(vx, vz, time_s=t)     # many samples: an EstimateResult of arrays
    """

    def __init__(self, config: EstimatorConfig | None = None):
        self.config = config if config is not None else EstimatorConfig()
        if not isinstance(self.config, EstimatorConfig):
            raise InputError(f"config must be an EstimatorConfig, got {type(self.config).__name__}")
        self._impl = _core.Estimator(self.config.to_native())
        self._last_time_s: float | None = None

    def step(self, vx: float, vz: float, dt_s: float | None = None, *, diagnostics: bool = False):
        """Process one sample of forward and vertical velocity [m/s]; returns the estimate after it.

        ``dt_s``: time since the previous sample [s] (None: ``sample_time_s``).  The default
        estimator propagates over it; the paper's works per sample and does not use it.
        A NaN or infinite sample (default: channel) is not used and is flagged in ``status``.
        ``diagnostics``: the estimate also carries ``innovation_vx_mps``, ``innovation_vz_mps``
        and ``nis`` (see :class:`EstimateResult`).
        """
        self._last_time_s = None
        step = self._impl.step_diagnosed if diagnostics else self._impl.step
        if dt_s is None:
            return step(vx, vz)
        return step(vx, vz, dt_s)

    def run(
        self, vx, vz, *, predict_ahead_s=(), time_s=None, diagnostics: bool = False, covariance: bool = False
    ) -> EstimateResult:
        """Process arrays of samples, continuing from the current state.

        ``predict_ahead_s``: horizons [s] for which to also predict the velocities at each sample.
        ``time_s``: timestamps of the samples [s]; the default estimator then propagates over
        their differences (irregular sampling, gaps), continuing from the last timestamp of the
        previous ``run``.  Without it every sample is ``sample_time_s`` after the previous one.
        The paper's estimator works per sample and does not use them.
        ``diagnostics``: also the innovations and the NIS of every sample (``innovation_vx_mps``,
        ``innovation_vz_mps``, ``nis``); without, they are not computed.
        ``covariance``: also return the filter's covariance after every sample (for checks).

        The arrays are views of one table written row by row (one row per sample), so most are
        strided; ``np.ascontiguousarray`` gives a compact copy.  The table's memory is handed to
        the next ``run`` once every view of it is gone (one block of up to 64 MiB is kept), so
        runs over many recordings reuse warm memory.
        """
        vx = _as_signal("vx", vx)
        vz = _as_signal("vz", vz)
        if vx.shape != vz.shape:
            raise InputError(f"vx and vz must have the same length, got {vx.size} and {vz.size}")
        horizons_s = tuple(float(h) for h in np.atleast_1d(np.asarray(predict_ahead_s, dtype=float)))
        if any(not math.isfinite(h) or h < 0 for h in horizons_s):
            raise InputError("predict_ahead_s must hold finite horizons >= 0")
        dt = None
        paper = self.config.algorithm == "paper"
        if time_s is not None:
            time_s = _as_signal("time_s", time_s)
            if time_s.shape != vx.shape:
                raise InputError(f"time_s must have the length of vx, got {time_s.size} and {vx.size}")
            if time_s.size and not paper:  # the paper's filter works per sample and does not use dt
                dt = np.empty_like(time_s)
                with np.errstate(invalid="ignore"):  # inf - inf: a NaN step, flagged by the filter
                    dt[1:] = time_s[1:] - time_s[:-1]
                dt[0] = (time_s[0] - self._last_time_s) if self._last_time_s is not None else self.config.sample_time_s
        horizons = np.asarray(horizons_s, dtype=np.float64)
        out = self._impl.run(vx, vz, horizons, dt, bool(diagnostics), bool(covariance))
        if "covariance" in out:
            k = 4 if paper else 8
            out["covariance"] = out["covariance"].reshape(vx.size, k, k)
        if "gait_state" not in out:
            # The paper: its gait-filter outputs carry nothing new, so they are not written per
            # sample (see yoyogait::Estimate): the reconstruction is the same array, the constant
            # flags are read-only views, and the 8-state is left to the per-step Estimate.
            n = vx.size
            out.update(
                vx_hat_h2_mps=out["vx_hat_mps"],
                vz_hat_h2_mps=out["vz_hat_mps"],
                std_scale=np.broadcast_to(np.float64(1.0), (n,)),
                walking=np.broadcast_to(np.True_, (n,)),
                acquiring=np.broadcast_to(np.False_, (n,)),
            )
        if vx.size:
            self._last_time_s = float(time_s[-1]) if time_s is not None else None
        return EstimateResult(
            sample_time_s=self.config.sample_time_s,
            predict_ahead_s=horizons_s,
            time_s=time_s,
            **out,
        )

    def reset(self) -> None:
        """Back to the state before the first sample."""
        self._impl.reset()
        self._last_time_s = None

    def predict(self, horizon_s: float) -> tuple[float, float]:
        """(vx, vz) predicted ``horizon_s`` after the last sample."""
        vx, vz = self._impl.predict_ahead(float(horizon_s))
        return vx, vz

    @property
    def state(self) -> np.ndarray:
        """Paper: x of eq. 5 after the last sample, [A1 cos, A1 sin, w (rad/sample), A0 (m/s)].
        Default: the same form, [X1, X2, w T, A0]."""
        return np.array(self._impl.state)

    @property
    def gait_state(self) -> np.ndarray:
        """Default: [X1, X2, Z1, Z2, w, A0, dA0, dw] of the active filter (paper: zeros)."""
        return np.array(self._impl.gait_state)

    @property
    def covariance(self) -> np.ndarray:
        """The filter's covariance after the last sample: paper 4 x 4 (eq. 5), default 8 x 8."""
        return self._impl.covariance

    @property
    def sample_count(self) -> int:
        return self._impl.sample_count
