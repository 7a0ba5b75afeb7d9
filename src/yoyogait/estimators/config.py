"""The estimator's configuration: :class:`EstimatorConfig` and the named presets.

Mirrors the C++ ``yoyogait::EstimatorConfig`` field by field, with the unit in each name.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, fields

import numpy as np

from .. import _core
from ..errors import InputError

__all__ = ["EstimatorConfig", "PRESETS", "ALGORITHMS", "MAX_BANK_SIZE"]

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
    def paper(cls) -> EstimatorConfig:
        """The paper's estimator exactly as published (Sec. III and IV-B)."""
        return cls(algorithm="paper")

    @classmethod
    def default(cls) -> EstimatorConfig:
        """The default estimator, the gait filter (the same as ``EstimatorConfig()``)."""
        return cls()

    @classmethod
    def preset(cls, name: str) -> EstimatorConfig:
        """A named preset: one of :data:`PRESETS`."""
        try:
            return PRESETS[name]()
        except KeyError:
            raise InputError(f"unknown preset {name!r}; known: {', '.join(PRESETS)}") from None

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)

    @classmethod
    def from_dict(cls, values: dict) -> EstimatorConfig:
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(values) - known)
        if unknown:
            raise InputError(f"unknown estimator parameter(s): {', '.join(unknown)}")
        return cls(**values)

    def to_native(self) -> _core.EstimatorConfig:
        """The C++ struct; raises InputError naming the field that is not usable."""
        native = _core.EstimatorConfig()
        for f in fields(self):
            value = getattr(self, f.name)
            kind = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", "")
            if f.name == "algorithm":
                if value not in ALGORITHMS:
                    raise InputError(f"algorithm must be one of {', '.join(ALGORITHMS)}, got {value!r}")
            elif f.name == "bank_f_hz":
                if (
                    isinstance(value, (str, bytes))
                    or not hasattr(value, "__len__")
                    or not (1 <= len(value) <= MAX_BANK_SIZE)
                ):
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
