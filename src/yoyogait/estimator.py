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

import dataclasses
import math
from dataclasses import dataclass, field, fields

import numpy as np

from . import _core
from .errors import InputError

__all__ = ["EstimatorConfig", "GaitEstimator", "EstimateResult", "Status", "PRESETS", "ALGORITHMS"]

Status = _core.Status

ALGORITHMS = ("paper", "gait_filter")
"""Values of :attr:`EstimatorConfig.algorithm`."""

MAX_BANK_SIZE = 8


@dataclass
class EstimatorConfig:
    """Parameters of the estimator; mirrors ``yoyogait::EstimatorConfig`` field by field.

    ``EstimatorConfig()`` is the default estimator (``algorithm="gait_filter"``);
    :meth:`paper` is the paper's estimator exactly as published.  The paper's
    fields work per sample, as in the paper: frequencies in rad/sample and
    ``R_hat``, ``r_hat`` in the paper's unit R/T, r/T (m/s).  The gait filter's
    fields are in SI units per second (noise densities are multiplied by the
    actual time step).  Each algorithm ignores the other's fields;
    ``sample_time_s`` and ``max_abs_velocity_mps`` are shared.
    """

    algorithm: str = "gait_filter"
    """'gait_filter' (the default estimator) or 'paper'."""
    sample_time_s: float = 0.04
    """T, time between samples [s]; the gait filter's nominal time step."""

    # ----------------------------------------------------------- the paper
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
    """A sample (gait filter: a channel) with |v| above it is not used [m/s] (no walking reaches it)."""

    # --------------------------------------------------- the gait filter
    f_min_hz: float = 0.6
    """Lower bound of the step frequency [Hz] (0 is excluded)."""
    f_max_hz: float = 3.5
    """Upper bound of the step frequency [Hz]."""
    bank_f_hz: tuple = (0.9, 1.3, 1.8, 2.3, 2.8)
    """Start frequencies of the start-up bank of EKFs [Hz] (1 to 8)."""
    bank_window_s: float = 1.5
    """Walking time after which the bank collapses to its best member [s]."""
    bank_forget_s: float = 1.5
    """Memory of the members' innovation log-likelihood [s]."""
    bank_prior_f_hz: float = 1.8
    """Typical step frequency: its member starts with the log-prior bonus [Hz]."""
    bank_prior_bonus_nats: float = 2.0
    """Log-prior bonus [nats] (on re-acquisition: for the member at the last frequency)."""
    p0_f_std_hz: float = 0.25
    """Initial frequency std of each member [Hz]."""
    p0_phasor_std_mps: float = 0.3
    """Initial std of the phasors [m/s]."""
    p0_speed_std_mps: float = 0.3
    """Initial std of A0 [m/s]."""
    p0_accel_std_mps2: float = 0.5
    """Initial std of dA0 [m/s^2]."""
    p0_omega_rate_std_rad_s2: float = 0.05
    """Initial std of dw [rad/s^2]."""
    spectral_init: bool = True
    """Seed the least likely bank member by a least-squares frequency grid search."""
    spectral_init_s: float = 1.0
    """... after this much walking [s]."""
    spectral_buffer_samples: int = 40
    """... over this many buffered samples (at most 256)."""
    spectral_grid_step_hz: float = 0.025
    """Grid step of the search [Hz]."""
    spectral_f_std_hz: float = 0.08
    """Frequency std given to the seeded member [Hz]."""
    spectral_phasor_std_mps: float = 0.05
    """Phasor and A0 std given to the seeded member [m/s]."""
    q_phasor_m2_per_s3: float = 2e-3
    """Independent drift of each phasor entry [(m/s)^2/s]."""
    q_phase_rad2_per_s: float = 0.05
    """Common gait-phase jitter, rotating X and Z together [rad^2/s]."""
    q_omega_rad2_per_s3: float = 0.05
    """Random walk of w [(rad/s)^2/s]."""
    use_omega_rate: bool = True
    """Frequency-rate state dw (tracks cadence ramps)."""
    q_omega_rate_lo_rad2_per_s5: float = 0.01
    """Noise of dw while no trend is seen [(rad/s^2)^2/s]."""
    q_omega_rate_hi_rad2_per_s5: float = 2.0
    """Noise of dw once the low-passed rate reaches omega_rate_ref_rad_s2 [(rad/s^2)^2/s]."""
    omega_rate_ref_rad_s2: float = 0.2
    """Trend level of the low-passed rate [rad/s^2]."""
    omega_rate_lp_tau_s: float = 1.5
    """Low-pass of dw for the trend test (0: none) [s]."""
    omega_rate_tau_s: float = 3.0
    """Decay time of dw [s]."""
    q_speed_m2_per_s3: float = 1e-3
    """Random walk of A0 [(m/s)^2/s]."""
    q_accel_m2_per_s5: float = 1e-2
    """Random walk of dA0 [(m/s^2)^2/s]."""
    accel_tau_s: float = 1.0
    """Decay time of dA0 [s]."""
    use_harmonic: bool = True
    """Second harmonic of each channel by a cascaded 2-state Kalman filter."""
    p0_harmonic_std_mps: float = 0.1
    """Initial std of the harmonic coefficients [m/s]."""
    q_harmonic_m2_per_s3: float = 1e-3
    """Random walk of the harmonic coefficients [(m/s)^2/s]."""
    harmonic_min_amp_mps: float = 0.02
    """Below this fundamental amplitude the harmonic is not used [m/s]."""
    meas_vx_std_mps: float = 0.05
    """Measurement noise (std) of v_x [m/s]."""
    meas_vz_std_mps: float = 0.05
    """Measurement noise (std) of v_z [m/s]."""
    gate_sigma: float = 5.0
    """Innovation gate [sigma] (inf: off)."""
    gate_max_consecutive: int = 6
    """After this many consecutive rejections a sample is accepted and P inflated."""
    max_gap_s: float = 1.5
    """A longer time between samples restarts the acquisition [s]."""
    walk_tau_s: float = 0.3
    """Low-pass of the walking detector [s]."""
    walk_speed_on_mps: float = 0.2
    """Walking when the low-passed v_x exceeds it [m/s] ..."""
    walk_speed_off_mps: float = 0.15
    """Standing when the low-passed v_x is below it [m/s] ..."""
    walk_vz_rms_on_mps: float = 0.05
    """... or when the RMS of v_z exceeds it [m/s]."""
    walk_vz_rms_off_mps: float = 0.025
    """... and the RMS of v_z is below it [m/s]."""
    bound_watchdog_s: float = 1.0
    """w pinned at a bound this long while walking restarts the acquisition [s]."""
    std_scale_adapt: bool = True
    """Scale the reported standard deviations by the low-passed normalised innovation squared."""
    std_scale_tau_s: float = 10.0
    """Low-pass of that scale [s]."""
    std_scale_min: float = 0.05
    """Lower clip of the scale."""
    std_scale_max: float = 4.0
    """Upper clip of the scale."""
    speed_std_floor_mps: float = 0.025
    """Added in quadrature to the speed std [m/s]."""
    radii_tau_s: float = 2.0
    """Low-pass of R = A0 / w and r = |Z| / w while walking [s]."""
    initial_R_m: float = 0.12
    """R reported before the first walk [m]."""
    initial_r_m: float = 0.02
    """r reported before the first walk [m]."""

    def __post_init__(self):
        if isinstance(self.bank_f_hz, list):
            self.bank_f_hz = tuple(self.bank_f_hz)

    @classmethod
    def paper(cls) -> "EstimatorConfig":
        """The paper's estimator exactly as published (Sec. III and IV-B)."""
        return cls(algorithm="paper")

    @classmethod
    def default(cls) -> "EstimatorConfig":
        """The default estimator, the gait filter (the same as ``EstimatorConfig()``)."""
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
            kind = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", "")
            if f.name == "algorithm":
                if value not in ALGORITHMS:
                    raise InputError(f"algorithm must be one of {', '.join(ALGORITHMS)}, got {value!r}")
            elif f.name == "bank_f_hz":
                if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or not (
                        1 <= len(value) <= MAX_BANK_SIZE):
                    raise InputError(f"bank_f_hz must hold 1 to {MAX_BANK_SIZE} frequencies, got {value!r}")
                if any(isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) for v in value):
                    raise InputError(f"bank_f_hz must hold numbers, got {value!r}")
                value = [float(v) for v in value]
            elif kind == "bool":
                if not isinstance(value, (bool, np.bool_)):
                    raise InputError(f"{f.name} must be True or False, got {value!r}")
                value = bool(value)
            elif kind == "int":
                if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
                    raise InputError(f"{f.name} must be a non-negative integer, got {value!r}")
            elif isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
                raise InputError(f"{f.name} must be a number, got {value!r}")
            setattr(native, f.name, value)
        problem = native.validate()
        if problem is not None:
            raise InputError(f"invalid estimator configuration: {problem}")
        return native


PRESETS = {"paper": EstimatorConfig.paper, "default": EstimatorConfig.default}
"""Named configurations: the paper's estimator and the default (the gait filter)."""


@dataclass
class EstimateResult:
    """Estimates over a signal, one row per sample (the estimate after that sample).

    Arrays in physical units: ``vx_hat``, ``vz_hat`` (the model's reconstruction,
    m/s), ``R_m``, ``r_m`` (m), ``step_frequency_hz`` (paper: signed, as the
    filter has it; default: > 0), ``omega_rad_s``, ``speed_mps`` (the forward
    speed without the oscillation), ``A0_mps``, ``A1_mps``, their standard
    deviations, the state (N, 4) in the paper's form of eq. 5 (default:
    [X1, X2, w T, A0]) and the paper's ``R_hat_mps``, ``r_hat_mps``.  ``status``
    holds a :class:`Status` code per sample.  When predictions were asked for,
    ``vx_pred``/``vz_pred`` (N, H) hold the velocities predicted at each sample
    for ``predict_ahead_s[j]`` later.

    From the native estimators also (None for results built elsewhere):
    ``vx_hat_h2``, ``vz_hat_h2`` (with the second harmonics), ``std_scale``,
    ``walking``, ``acquiring`` and, for the default, ``gait_state`` (N, 8) =
    [X1, X2, Z1, Z2, w, A0, dA0, dw].  For the paper these carry nothing new
    and are not written per sample: ``vx_hat_h2`` is ``vx_hat``, the flags and
    ``std_scale`` are constant read-only views (True, False, 1) and
    ``gait_state`` is None (``GaitEstimator.step`` gives it in the gait form).
    ``covariance`` (N, k, k): the filter's covariance after each sample (k = 4 for the
    paper, 8 for the default), when ``run(..., covariance=True)`` asked for it, else None.
    Derived when read, for every result with a state: ``amp_z_mps``,
    ``phase_x_rel_z_rad``, ``signed_amp_x_mps``, ``omega_rate_rad_s2``,
    ``accel_mps2`` (see the C++ ``yoyogait::Estimate``).
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
    gait_state: np.ndarray | None = None
    vx_hat_h2: np.ndarray | None = None
    vz_hat_h2: np.ndarray | None = None
    std_scale: np.ndarray | None = None
    walking: np.ndarray | None = None
    acquiring: np.ndarray | None = None
    covariance: np.ndarray | None = None

    def __len__(self) -> int:
        return int(self.vx_hat.shape[0])

    # Derived from the state when read, as yoyogait::Estimate does: from gait_state, or, for
    # results without it (the paper's run, the baselines), from the paper-form state (eq. 5:
    # Z is X turned by +90 degrees, no rates).

    def _g(self) -> np.ndarray:
        if self.gait_state is not None:
            return self.gait_state
        s = self.state
        zero = np.zeros(s.shape[0])
        return np.column_stack([s[:, 0], s[:, 1], -s[:, 1], s[:, 0], s[:, 2] / self.sample_time_s, s[:, 3], zero,
                                zero])

    @property
    def amp_z_mps(self) -> np.ndarray:
        """Amplitude of the vertical oscillation |Z| [m/s] (paper: A1)."""
        g = self._g()
        return np.hypot(g[:, 2], g[:, 3])

    @property
    def phase_x_rel_z_rad(self) -> np.ndarray:
        """Phase of the forward oscillation relative to the vertical one, [-pi, pi], in the direction
        of the gait phase: the Yoyo model has -pi/2, real walking about +pi/2; 0 where |X| or |Z| is
        at most 1e-9 m/s (no oscillation, no relation)."""
        g = self._g()
        a = np.arctan2(g[:, 1] * g[:, 2] - g[:, 0] * g[:, 3], g[:, 0] * g[:, 2] + g[:, 1] * g[:, 3])
        defined = (g[:, 0] ** 2 + g[:, 1] ** 2 > 1e-18) & (np.hypot(g[:, 2], g[:, 3]) > 1e-9)
        return np.where(defined, np.where(g[:, 4] >= 0.0, a, -a), 0.0)

    @property
    def signed_amp_x_mps(self) -> np.ndarray:
        """Forward amplitude signed by the relation (> 0 Yoyo, < 0 real walking) [m/s]."""
        g = self._g()
        az = np.hypot(g[:, 2], g[:, 3])
        with np.errstate(invalid="ignore", divide="ignore"):
            p = np.where(az > 1e-9, (g[:, 0] * g[:, 3] - g[:, 1] * g[:, 2]) / az, 0.0)
        return np.where(g[:, 4] >= 0.0, p, -p)

    @property
    def omega_rate_rad_s2(self) -> np.ndarray:
        """Rate of the step angular frequency dw [rad/s^2] (paper: 0)."""
        return self._g()[:, 7]

    @property
    def accel_mps2(self) -> np.ndarray:
        """Rate of the forward-speed bias dA0 [m/s^2] (paper: 0)."""
        return self._g()[:, 6]

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
        self._last_time_s = None

    def step(self, vx: float, vz: float, dt_s: float | None = None):
        """Process one sample of forward and vertical velocity [m/s]; returns the estimate after it.

        ``dt_s``: time since the previous sample [s] (None: ``sample_time_s``).  The default
        estimator propagates over it; the paper's works per sample and does not use it.
        A NaN or infinite sample (default: channel) is not used and is flagged in ``status``.
        """
        self._last_time_s = None
        if dt_s is None:
            return self._impl.step(vx, vz)
        return self._impl.step(vx, vz, dt_s)

    def run(self, vx, vz, *, predict_ahead_s=(), time_s=None, covariance=False) -> EstimateResult:
        """Process arrays of samples, continuing from the current state.

        ``predict_ahead_s``: horizons [s] for which to also predict the velocities at each sample.
        ``time_s``: timestamps of the samples [s]; the default estimator then propagates over
        their differences (irregular sampling, gaps), continuing from the last timestamp of the
        previous ``run``.  Without it every sample is ``sample_time_s`` after the previous one.
        The paper's estimator works per sample and does not use them.
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
                dt[1:] = time_s[1:] - time_s[:-1]
                dt[0] = (time_s[0] - self._last_time_s) if self._last_time_s is not None \
                    else self.config.sample_time_s
        horizons = np.asarray(horizons_s, dtype=np.float64) / self.config.sample_time_s
        out = self._impl.run(vx, vz, horizons, dt, bool(covariance))
        if "covariance" in out:
            k = 4 if paper else 8
            out["covariance"] = out["covariance"].reshape(vx.size, k, k)
        if "gait_state" not in out:
            # The paper: its gait-filter outputs carry nothing new, so they are not written per
            # sample (see yoyogait::Estimate): the reconstruction is the same array, the constant
            # flags are read-only views, and the 8-state is left to the per-step Estimate.
            n = vx.size
            out.update(vx_hat_h2=out["vx_hat"], vz_hat_h2=out["vz_hat"],
                       std_scale=np.broadcast_to(np.float64(1.0), (n,)),
                       walking=np.broadcast_to(np.True_, (n,)), acquiring=np.broadcast_to(np.False_, (n,)))
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
        vx, vz = self._impl.predict_ahead(horizon_s / self.config.sample_time_s)
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
