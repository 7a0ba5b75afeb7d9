"""The gait estimator: Python face of the C++ core.

``GaitEstimator(config).step(vx, vz)`` is the streaming form (one estimate per
sample); ``run(vx, vz)`` is the batch form over arrays.  Both go through the
same native ``step``, so their results agree bit for bit, and ``run`` resumes
where the last call ended, so a signal run in chunks gives the same result as
one run.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field, fields

import numpy as np

from . import _core
from .errors import InputError

__all__ = ["EstimatorConfig", "GaitEstimator", "EstimateResult", "Status", "PRESETS"]

Status = _core.Status


@dataclass
class EstimatorConfig:
    """Parameters of the estimator; mirrors ``yoyogait::EstimatorConfig`` field by field.

    The filter works per sample, as in the paper: frequencies are in rad/sample
    and ``R_hat``, ``r_hat`` in the paper's unit R/T, r/T (m/s).
    Defaults are the paper's (Sec. IV-B); :meth:`paper` names them.
    """

    sample_time_s: float = 0.04
    """T, time between samples [s]."""
    initial_R_hat_mps: float = 2.0
    """R_hat(0) = R/T for the average person [m/s] (the paper's R0 = 2)."""
    initial_r_hat_mps: float = 0.2
    """r_hat(0) = r/T [m/s] (the paper's r0 = 0.2)."""
    initial_omega_rad_per_sample: float = 0.1
    """w(0) [rad/sample]."""
    q_oscillation_mps2: float = 1e-5
    """Q11 = Q22, process noise of x1, x2 [(m/s)^2]."""
    q_omega_rad2: float = 1e-3
    """Q33, process noise of the frequency [(rad/sample)^2]."""
    q_bias_mps2: float = 1e-3
    """Q44, process noise of the bias A0 [(m/s)^2]."""
    v_vx_mps2: float = 1e-2
    """V11, measurement noise of v_x [(m/s)^2]."""
    v_vz_mps2: float = 1e-2
    """V22, measurement noise of v_z [(m/s)^2]."""
    p0_oscillation_mps2: float = 1.0
    """P0 of x1, x2 [(m/s)^2]."""
    p0_omega_rad2: float = 1.0
    """P0 of x3 [(rad/sample)^2]."""
    p0_bias_mps2: float = 1.0
    """P0 of x4 [(m/s)^2]."""
    smoothing_window_samples: int = 10
    """n of eq. 11-12 [samples] (at most 256)."""
    gate_omega_rad_per_sample: float = 0.1
    """mu_w of eq. 11-12 [rad/sample]."""
    gate_bias_mps: float = 0.1
    """mu_A0 of eq. 11-12 [m/s]."""
    max_abs_velocity_mps: float = 1000.0
    """A sample with |v| above it is rejected like a non-finite one [m/s] (no walking reaches it)."""

    @classmethod
    def paper(cls) -> "EstimatorConfig":
        """The paper's estimator exactly as published (Sec. III and IV-B)."""
        return cls()

    @classmethod
    def preset(cls, name: str) -> "EstimatorConfig":
        """A named preset: one of :data:`PRESETS`."""
        try:
            return PRESETS[name]()
        except KeyError:
            raise InputError(f"unknown preset {name!r}; known: {', '.join(PRESETS)}") from None

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, values: dict) -> "EstimatorConfig":
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(values) - known)
        if unknown:
            raise InputError(f"unknown estimator parameter(s): {', '.join(unknown)}")
        return cls(**values)

    def to_native(self) -> "_core.EstimatorConfig":
        """The C++ struct; raises InputError naming the field that is not usable."""
        native = _core.EstimatorConfig()
        for f in fields(self):
            value = getattr(self, f.name)
            if f.type == "int" or f.type is int:
                if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
                    raise InputError(f"{f.name} must be a non-negative integer, got {value!r}")
            elif isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
                raise InputError(f"{f.name} must be a number, got {value!r}")
            setattr(native, f.name, value)
        problem = native.validate()
        if problem is not None:
            raise InputError(f"invalid estimator configuration: {problem}")
        return native


PRESETS = {"paper": EstimatorConfig.paper}


@dataclass
class EstimateResult:
    """Estimates over a signal, one row per sample (the estimate after that sample).

    Arrays in physical units: ``vx_hat``, ``vz_hat`` (eq. 13-14, m/s), ``R_m``,
    ``r_m`` (m), ``step_frequency_hz`` (signed, as the filter has it),
    ``omega_rad_s``, ``speed_mps`` (R omega, the forward speed without the
    oscillation), ``A0_mps``, ``A1_mps``, their standard deviations, the state
    (N, 4) of eq. 5 and the paper's ``R_hat_mps``, ``r_hat_mps``.  ``status``
    holds a :class:`Status` code per sample.  When predictions were asked for,
    ``vx_pred``/``vz_pred`` (N, H) hold the velocities predicted at each sample
    for ``predict_ahead_s[j]`` later.
    """

    state: np.ndarray
    vx_hat: np.ndarray
    vz_hat: np.ndarray
    R_hat_mps: np.ndarray
    r_hat_mps: np.ndarray
    R_m: np.ndarray
    r_m: np.ndarray
    omega_rad_s: np.ndarray
    step_frequency_hz: np.ndarray
    step_frequency_std_hz: np.ndarray
    speed_mps: np.ndarray
    speed_std_mps: np.ndarray
    A0_mps: np.ndarray
    A1_mps: np.ndarray
    status: np.ndarray
    parameters_updated: np.ndarray
    sample_time_s: float
    predict_ahead_s: tuple = ()
    vx_pred: np.ndarray | None = None
    vz_pred: np.ndarray | None = None
    time_s: np.ndarray | None = field(default=None)

    def __len__(self) -> int:
        return int(self.vx_hat.shape[0])

    @property
    def omega_rad_per_sample(self) -> np.ndarray:
        """x3 of eq. 5."""
        return self.state[:, 2]

    def aligned_prediction(self, horizon_s: float) -> tuple[np.ndarray, np.ndarray]:
        """(vx, vz) predicted ``horizon_s`` before each sample, aligned to the sample they predict.

        NaN where no prediction reaches (the first samples).
        """
        for j, h in enumerate(self.predict_ahead_s):
            if math.isclose(h, horizon_s, rel_tol=1e-9, abs_tol=1e-12):
                break
        else:
            raise InputError(f"no prediction {horizon_s} s ahead was computed; have {self.predict_ahead_s}")
        shift = int(round(horizon_s / self.sample_time_s))
        out_vx = np.full(len(self), np.nan)
        out_vz = np.full(len(self), np.nan)
        if shift < len(self):
            out_vx[shift:] = self.vx_pred[: len(self) - shift, j]
            out_vz[shift:] = self.vz_pred[: len(self) - shift, j]
        return out_vx, out_vz


def _as_signal(name: str, values) -> np.ndarray:
    arr = np.asarray(values, dtype=np.float64)
    if arr.ndim != 1:
        raise InputError(f"{name} must be one-dimensional, got shape {arr.shape}")
    return np.ascontiguousarray(arr)


class GaitEstimator:
    """Online estimator of step frequency, forward speed and the Yoyo-model parameters.

    >>> est = GaitEstimator(EstimatorConfig.paper())
    >>> e = est.step(1.2, 0.05)        # one sample: a native Estimate
    >>> result = est.run(vx, vz)       # many samples: an EstimateResult of arrays
    """

    def __init__(self, config: EstimatorConfig | None = None):
        self.config = config if config is not None else EstimatorConfig()
        if not isinstance(self.config, EstimatorConfig):
            raise InputError(f"config must be an EstimatorConfig, got {type(self.config).__name__}")
        self._impl = _core.Estimator(self.config.to_native())

    def step(self, vx: float, vz: float):
        """Process one sample of forward and vertical velocity [m/s]; returns the estimate after it.

        A NaN or infinite sample is not used (prediction only) and is flagged in ``status``.
        """
        return self._impl.step(vx, vz)

    def run(self, vx, vz, *, predict_ahead_s=(), time_s=None) -> EstimateResult:
        """Process arrays of samples, continuing from the current state.

        ``predict_ahead_s``: horizons [s] for which to also predict the velocities at each sample.
        """
        vx = _as_signal("vx", vx)
        vz = _as_signal("vz", vz)
        if vx.shape != vz.shape:
            raise InputError(f"vx and vz must have the same length, got {vx.size} and {vz.size}")
        horizons_s = tuple(float(h) for h in np.atleast_1d(np.asarray(predict_ahead_s, dtype=float)))
        if any(not math.isfinite(h) or h < 0 for h in horizons_s):
            raise InputError("predict_ahead_s must hold finite horizons >= 0")
        if time_s is not None:
            time_s = _as_signal("time_s", time_s)
            if time_s.shape != vx.shape:
                raise InputError(f"time_s must have the length of vx, got {time_s.size} and {vx.size}")
        horizons = np.asarray(horizons_s, dtype=np.float64) / self.config.sample_time_s
        out = self._impl.run(vx, vz, horizons)
        return EstimateResult(
            sample_time_s=self.config.sample_time_s,
            predict_ahead_s=horizons_s,
            time_s=time_s,
            **out,
        )

    def reset(self) -> None:
        """Back to the state before the first sample."""
        self._impl.reset()

    def predict(self, horizon_s: float) -> tuple[float, float]:
        """(vx, vz) predicted ``horizon_s`` after the last sample."""
        vx, vz = self._impl.predict_ahead(horizon_s / self.config.sample_time_s)
        return vx, vz

    @property
    def state(self) -> np.ndarray:
        """x of eq. 5 after the last sample: [A1 cos, A1 sin, w (rad/sample), A0 (m/s)]."""
        return np.array(self._impl.state)

    @property
    def covariance(self) -> np.ndarray:
        """P after the last sample (4 x 4)."""
        return self._impl.covariance

    @property
    def sample_count(self) -> int:
        return self._impl.sample_count
