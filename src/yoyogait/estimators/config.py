"""The estimator's configuration: :class:`EstimatorConfig` and the named presets.

Every field is declared once, in the tables of the C++ core (``include/yoyogait/config.hpp``):
type, name, default, unit, valid range and a one-line doc. :data:`SCHEMA` is those tables as the
native module gives them; the dataclasses here take their defaults and docs from it, and a test
holds their field names and types to it. The configuration nests by algorithm, as the C++ struct:

    EstimatorConfig(algorithm, sample_time_s, max_abs_velocity_mps,
                    paper_estimator=PaperConfig(...), gait_filter=GaitFilterConfig(...))

Files are TOML (``EstimatorConfig.from_file``, ``save``): the shared fields at the top, a table
per section. docs/configuration.md lists every field with its range (generated from
:data:`SCHEMA` by :func:`schema_markdown`).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from .. import _core, _reading
from .._files import atomic_file
from ..errors import InputError

__all__ = [
    "ALGORITHMS",
    "MAX_BANK_SIZE",
    "PRESETS",
    "SCHEMA",
    "SECTIONS",
    "EstimatorConfig",
    "FieldSchema",
    "ONLINE_SECTION",
    "OnlineConfig",
    "IMU_SECTION",
    "ImuConfig",
    "GaitFilterConfig",
    "PaperConfig",
    "effective_toml",
    "schema_markdown",
]

ALGORITHMS = ("paper", "gait_filter")
"""Values of :attr:`EstimatorConfig.algorithm`."""

MAX_BANK_SIZE = int(_core.MAX_BANK_SIZE)

SECTIONS = ("paper_estimator", "gait_filter")
"""The per-algorithm sections of :class:`EstimatorConfig`, as in the C++ struct and the TOML files."""

ONLINE_SECTION = "online"
"""The section of the online front-end (:class:`OnlineConfig`) in the schema and the TOML files."""

IMU_SECTION = "imu"
"""The section of the lower-back IMU front-end (:class:`ImuConfig`) in the schema and the TOML files."""


@dataclass(frozen=True)
class FieldSchema:
    """One field of the configuration, as the C++ tables declare it."""

    section: str  # "" for the shared fields, else one of SECTIONS or ONLINE_SECTION
    name: str
    type: str  # "float", "int", "bool", "float_list" or "str"
    default: Any
    unit: str
    doc: str
    min: float | None = None  # valid range (float_list: of each entry); None where there is none
    max: float | None = None
    min_inclusive: bool = True
    max_inclusive: bool = True
    choices: tuple = ()

    @property
    def path(self) -> str:
        """``section.name``, or ``name`` for a shared field: how errors and files name it."""
        return f"{self.section}.{self.name}" if self.section else self.name

    def range_text(self) -> str:
        """The valid range as an interval, e.g. ``[0.05, 20]`` or ``(0, 1e+100]``."""
        if self.choices:
            return ", ".join(repr(c) for c in self.choices)
        if self.type == "bool" or self.min is None or self.max is None:
            return "true, false" if self.type == "bool" else ""
        lo = "[" if self.min_inclusive else "("
        hi = "]" if self.max_inclusive else ")"
        return f"{lo}{_num(self.min)}, {_num(self.max)}{hi}"

    def in_range(self, value: float) -> bool:
        assert self.min is not None and self.max is not None
        above = value >= self.min if self.min_inclusive else value > self.min
        below = value <= self.max if self.max_inclusive else value < self.max
        return bool(above and below)

    def check(self, value: Any) -> Any:
        """``value`` as the native field takes it; InputError (a ValueError) naming the field otherwise."""
        name = self.path
        if self.type == "str":
            if value not in self.choices:
                raise InputError(f"{name} must be one of {', '.join(map(repr, self.choices))}, got {value!r}")
            return value
        if self.type == "bool":
            if not isinstance(value, (bool, np.bool_)):
                raise InputError(f"{name} must be true or false, got {value!r}")
            return bool(value)
        if self.type == "int":
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)):
                raise InputError(f"{name} must be an integer in {self.range_text()}, got {value!r}")
            if not self.in_range(int(value)):
                raise InputError(f"{name} = {value} is outside its valid range {self.range_text()}{self._unit()}")
            return int(value)
        if self.type == "float_list":
            if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or not 1 <= len(value) <= MAX_BANK_SIZE:
                raise InputError(f"{name} must hold 1 to {MAX_BANK_SIZE} frequencies, got {value!r}")
            return [self._float(f"{name}[{i}]", v) for i, v in enumerate(value)]
        return self._float(name, value)

    def _float(self, name: str, value: Any) -> float:
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise InputError(f"{name} must be a number in {self.range_text()}{self._unit()}, got {value!r}")
        if isinstance(value, (int, np.integer)) and abs(int(value)) > 2**1023:
            raise InputError(f"{name} = {value} is outside its valid range {self.range_text()}{self._unit()}")
        v = float(value)
        if not self.in_range(v):
            raise InputError(f"{name} = {v!r} is outside its valid range {self.range_text()}{self._unit()}")
        return v

    def _unit(self) -> str:
        return f" {self.unit}" if self.unit else ""


def _num(x: float) -> str:
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    return f"{x:.15g}"


def _schema() -> tuple[FieldSchema, ...]:
    out = []
    for d in _core.config_schema():
        d = dict(d)
        if "choices" in d:
            d["choices"] = tuple(d["choices"])
        out.append(FieldSchema(**d))
    return tuple(out)


SCHEMA: tuple[FieldSchema, ...] = _schema()
"""Every field of the configuration, from the C++ tables: shared, paper_estimator, gait_filter, then online."""

_BY_PATH = {f.path: f for f in SCHEMA}


def _field(section: str, name: str) -> Any:
    """A dataclass field whose default and doc come from the C++ table."""
    spec = _BY_PATH[f"{section}.{name}" if section else name]
    return field(default=spec.default, metadata={"schema": spec})


@dataclass
class PaperConfig:
    """The paper's estimator (Sec. III and IV-B), in the paper's units: its filter works per sample,
    so frequencies are in rad/sample and R_hat, r_hat are R/T, r/T (m/s). Fields, units, ranges:
    docs/configuration.md."""

    initial_R_hat_mps: float = _field("paper_estimator", "initial_R_hat_mps")
    initial_r_hat_mps: float = _field("paper_estimator", "initial_r_hat_mps")
    initial_omega_rad_per_sample: float = _field("paper_estimator", "initial_omega_rad_per_sample")
    q_oscillation_mps2: float = _field("paper_estimator", "q_oscillation_mps2")
    q_omega_rad2: float = _field("paper_estimator", "q_omega_rad2")
    q_bias_mps2: float = _field("paper_estimator", "q_bias_mps2")
    v_vx_mps2: float = _field("paper_estimator", "v_vx_mps2")
    v_vz_mps2: float = _field("paper_estimator", "v_vz_mps2")
    p0_oscillation_mps2: float = _field("paper_estimator", "p0_oscillation_mps2")
    p0_omega_rad2: float = _field("paper_estimator", "p0_omega_rad2")
    p0_bias_mps2: float = _field("paper_estimator", "p0_bias_mps2")
    smoothing_window_samples: int = _field("paper_estimator", "smoothing_window_samples")
    gate_omega_rad_per_sample: float = _field("paper_estimator", "gate_omega_rad_per_sample")
    gate_bias_mps: float = _field("paper_estimator", "gate_bias_mps")


@dataclass
class GaitFilterConfig:
    """The gait filter, the default estimator (docs/default_estimator.md), in SI units per second:
    noise densities are multiplied by the actual time step. Fields, units, ranges:
    docs/configuration.md."""

    f_min_hz: float = _field("gait_filter", "f_min_hz")
    f_max_hz: float = _field("gait_filter", "f_max_hz")
    bank_f_hz: tuple = _field("gait_filter", "bank_f_hz")
    bank_window_s: float = _field("gait_filter", "bank_window_s")
    bank_forget_s: float = _field("gait_filter", "bank_forget_s")
    bank_prior_f_hz: float = _field("gait_filter", "bank_prior_f_hz")
    bank_prior_bonus_nats: float = _field("gait_filter", "bank_prior_bonus_nats")
    bank_q_omega_rad2_per_s3: float = _field("gait_filter", "bank_q_omega_rad2_per_s3")
    p0_f_std_hz: float = _field("gait_filter", "p0_f_std_hz")
    p0_phasor_std_mps: float = _field("gait_filter", "p0_phasor_std_mps")
    p0_speed_std_mps: float = _field("gait_filter", "p0_speed_std_mps")
    p0_accel_std_mps2: float = _field("gait_filter", "p0_accel_std_mps2")
    p0_omega_rate_std_rad_s2: float = _field("gait_filter", "p0_omega_rate_std_rad_s2")
    spectral_init: bool = _field("gait_filter", "spectral_init")
    spectral_init_s: float = _field("gait_filter", "spectral_init_s")
    spectral_buffer_s: float = _field("gait_filter", "spectral_buffer_s")
    spectral_grid_step_hz: float = _field("gait_filter", "spectral_grid_step_hz")
    spectral_f_std_hz: float = _field("gait_filter", "spectral_f_std_hz")
    spectral_phasor_std_mps: float = _field("gait_filter", "spectral_phasor_std_mps")
    q_phasor_m2_per_s3: float = _field("gait_filter", "q_phasor_m2_per_s3")
    q_phase_rad2_per_s: float = _field("gait_filter", "q_phase_rad2_per_s")
    q_omega_rad2_per_s3: float = _field("gait_filter", "q_omega_rad2_per_s3")
    use_omega_rate: bool = _field("gait_filter", "use_omega_rate")
    q_omega_rate_lo_rad2_per_s5: float = _field("gait_filter", "q_omega_rate_lo_rad2_per_s5")
    q_omega_rate_hi_rad2_per_s5: float = _field("gait_filter", "q_omega_rate_hi_rad2_per_s5")
    omega_rate_ref_rad_s2: float = _field("gait_filter", "omega_rate_ref_rad_s2")
    omega_rate_lp_tau_s: float = _field("gait_filter", "omega_rate_lp_tau_s")
    omega_rate_tau_s: float = _field("gait_filter", "omega_rate_tau_s")
    q_speed_m2_per_s3: float = _field("gait_filter", "q_speed_m2_per_s3")
    q_accel_m2_per_s5: float = _field("gait_filter", "q_accel_m2_per_s5")
    accel_tau_s: float = _field("gait_filter", "accel_tau_s")
    use_harmonic: bool = _field("gait_filter", "use_harmonic")
    p0_harmonic_std_mps: float = _field("gait_filter", "p0_harmonic_std_mps")
    q_harmonic_m2_per_s3: float = _field("gait_filter", "q_harmonic_m2_per_s3")
    harmonic_min_amp_mps: float = _field("gait_filter", "harmonic_min_amp_mps")
    meas_vx_density_m2_per_s: float = _field("gait_filter", "meas_vx_density_m2_per_s")
    meas_vz_density_m2_per_s: float = _field("gait_filter", "meas_vz_density_m2_per_s")
    gate_sigma: float = _field("gait_filter", "gate_sigma")
    gate_max_consecutive_s: float = _field("gait_filter", "gate_max_consecutive_s")
    max_gap_s: float = _field("gait_filter", "max_gap_s")
    walk_tau_s: float = _field("gait_filter", "walk_tau_s")
    walk_speed_on_mps: float = _field("gait_filter", "walk_speed_on_mps")
    walk_speed_off_mps: float = _field("gait_filter", "walk_speed_off_mps")
    walk_vz_rms_on_mps: float = _field("gait_filter", "walk_vz_rms_on_mps")
    walk_vz_rms_off_mps: float = _field("gait_filter", "walk_vz_rms_off_mps")
    bound_watchdog_s: float = _field("gait_filter", "bound_watchdog_s")
    cadence_change_adapt: bool = _field("gait_filter", "cadence_change_adapt")
    cadence_change_tau_s: float = _field("gait_filter", "cadence_change_tau_s")
    cadence_change_phase_rad: float = _field("gait_filter", "cadence_change_phase_rad")
    cadence_change_sigma: float = _field("gait_filter", "cadence_change_sigma")
    cadence_change_noise_tau_s: float = _field("gait_filter", "cadence_change_noise_tau_s")
    cadence_change_horizon_s: float = _field("gait_filter", "cadence_change_horizon_s")
    cadence_change_max_std_hz: float = _field("gait_filter", "cadence_change_max_std_hz")
    cadence_change_min_amp_mps: float = _field("gait_filter", "cadence_change_min_amp_mps")
    std_scale_adapt: bool = _field("gait_filter", "std_scale_adapt")
    std_scale_tau_s: float = _field("gait_filter", "std_scale_tau_s")
    std_scale_min: float = _field("gait_filter", "std_scale_min")
    std_scale_max: float = _field("gait_filter", "std_scale_max")
    speed_std_floor_mps: float = _field("gait_filter", "speed_std_floor_mps")
    radii_tau_s: float = _field("gait_filter", "radii_tau_s")
    initial_R_m: float = _field("gait_filter", "initial_R_m")
    initial_r_m: float = _field("gait_filter", "initial_r_m")

    def __post_init__(self):
        if isinstance(self.bank_f_hz, list):
            self.bank_f_hz = tuple(self.bank_f_hz)


_SECTION_TYPES: dict[str, Any] = {"paper_estimator": PaperConfig, "gait_filter": GaitFilterConfig}


class _ConfigFile:
    """What both configurations do with files: TOML with every field, checked before it is written."""

    def to_dict(self) -> dict:
        raise NotImplementedError

    def to_native(self) -> Any:
        raise NotImplementedError

    def validate(self) -> None:
        """InputError (a ValueError) naming the first field that is not usable; None if all are."""
        self.to_native()

    def to_toml(self) -> str:
        """The configuration as TOML, every field (what :meth:`save` writes)."""
        self.validate()
        return tomli_w.dumps(self.to_dict())

    def save(self, path, *, force: bool = False) -> None:
        """Write the configuration as TOML (every field); an existing file only with ``force``."""
        text = self.to_toml()
        path = Path(path)
        if path.exists() and not force:
            raise InputError(f"{path} exists; use force=True to overwrite it")
        atomic_file(path, lambda p: Path(p).write_text(text, encoding="utf-8"))

    @classmethod
    def _from_file_values(cls, path: Path, values: dict):
        try:
            return cls.from_dict(values)  # type: ignore[attr-defined]
        except InputError as exc:
            raise InputError(_reading.one_line(f"{path}: {exc}")) from None


@dataclass
class EstimatorConfig(_ConfigFile):
    """Parameters of the estimator; mirrors ``yoyogait::EstimatorConfig``, section by section.

    ``EstimatorConfig()`` is the default estimator (``algorithm="gait_filter"``); :meth:`paper`
    is the paper's estimator exactly as published. Each algorithm reads its own section
    (``paper_estimator``, ``gait_filter``) and ignores the other's; ``sample_time_s`` and
    ``max_abs_velocity_mps`` are shared. Every field has a valid range (docs/configuration.md);
    a value outside it raises ``ValueError`` naming the field when an estimator is built from
    the configuration (or at :meth:`validate`, :meth:`from_dict`, :meth:`from_file`).
    """

    algorithm: str = _field("", "algorithm")
    sample_time_s: float = _field("", "sample_time_s")
    max_abs_velocity_mps: float = _field("", "max_abs_velocity_mps")
    paper_estimator: PaperConfig = field(default_factory=PaperConfig)
    gait_filter: GaitFilterConfig = field(default_factory=GaitFilterConfig)

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

    # ---------------------------------------------------------------- dictionaries and files

    def to_dict(self) -> dict:
        """Nested plain values: the shared fields, then one dict per section (bank_f_hz a list)."""
        out: dict[str, Any] = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name in SECTIONS:
                out[f.name] = {g.name: _plain(getattr(value, g.name)) for g in fields(value)}
            else:
                out[f.name] = _plain(value)
        return out

    @classmethod
    def from_dict(cls, values: Mapping) -> EstimatorConfig:
        """The default configuration with ``values`` (nested as :meth:`to_dict`; sections may be
        partial) applied, checked: InputError naming an unknown or invalid field."""
        return cls().with_values(values)

    def with_values(self, values: Mapping) -> EstimatorConfig:
        """A copy with ``values`` (nested as :meth:`to_dict`, partial) applied, checked."""
        if not isinstance(values, Mapping):
            raise InputError(f"an estimator configuration must be a table of fields, got {type(values).__name__}")
        top = {f.name for f in fields(self)}
        _reject_unknown(values, top, "")
        changes: dict[str, Any] = {}
        for key, value in values.items():
            if key in SECTIONS:
                if not isinstance(value, Mapping):
                    raise InputError(f"{key} must be a table of fields, got {value!r}")
                section = getattr(self, key)
                _reject_unknown(value, {g.name for g in fields(section)}, key)
                changes[key] = dataclasses.replace(section, **dict(value))
            else:
                changes[key] = value
        out = dataclasses.replace(self, **changes)
        out.validate()
        return out

    @classmethod
    def from_file(cls, path) -> EstimatorConfig:
        """A configuration from a TOML file (as :meth:`save` writes; fields left out keep their
        defaults; an ``[online]`` section, the online front-end's, is read by
        :meth:`OnlineConfig.from_file` and ignored here). InputError naming the file and the field
        for anything unusable."""
        path = Path(path)
        values = _read_toml(path)
        values.pop(ONLINE_SECTION, None)
        values.pop(IMU_SECTION, None)
        return cls._from_file_values(path, values)

    # ------------------------------------------------------------------------------- checking

    def to_native(self) -> _core.EstimatorConfig:
        """The C++ struct; raises InputError naming the field that is not usable (type, range, or
        a rule between fields)."""
        native = _core.EstimatorConfig()
        for f in fields(self):
            value: Any = getattr(self, f.name)
            if f.name in SECTIONS:
                if not isinstance(value, _SECTION_TYPES[f.name]):
                    raise InputError(f"{f.name} must be a {_SECTION_TYPES[f.name].__name__}, got {value!r}")
                target = getattr(native, f.name)
                for g in fields(value):
                    setattr(target, g.name, g.metadata["schema"].check(getattr(value, g.name)))
                setattr(native, f.name, target)
            else:
                setattr(native, f.name, f.metadata["schema"].check(value))
        problem = native.validate()
        if problem is not None:
            raise InputError(f"invalid estimator configuration: {problem}")
        return native


def _plain(value: Any) -> Any:
    if isinstance(value, tuple):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def _reject_unknown(values: Mapping, known: set, section: str) -> None:
    unknown = sorted(str(k) for k in set(values) - known)
    if not unknown:
        return
    hints = []
    for key in unknown:
        homes = [f.path for f in SCHEMA if f.name == key and f.section != section]
        hints.append(f"{key} (did you mean {' or '.join(homes)}?)" if homes else key)
    where = f" in [{section}]" if section else ""
    raise InputError(f"unknown estimator parameter(s){where}: {', '.join(hints)}")


def _read_toml(path: Path) -> dict:
    """A configuration file's TOML, read bounded (yoyogait._reading: a regular file within its limits)."""
    return _reading.read_toml(path, _reading.CONFIG_MAX_BYTES, "configuration file")


@dataclass
class OnlineConfig(_ConfigFile):
    """Settings of the online front-end (docs/online.md); mirrors ``yoyogait::OnlineConfig``: the
    gait estimator behind it and the fields of the C++ table ``YOYOGAIT_ONLINE_FIELDS``, whose
    defaults, units, ranges and docs :data:`SCHEMA` gives (section ``online``). In a TOML file the
    estimator's fields as :class:`EstimatorConfig` has them, and an ``[online]`` table.

    Every setting is in seconds, metres or a noise density, none in frames: the front-end
    behaves the same at any capture rate.
    """

    estimator: EstimatorConfig = field(default_factory=EstimatorConfig)
    """The gait estimator behind the front-end, fed every ``estimator.sample_time_s``."""
    antialias_hz: float = _field(ONLINE_SECTION, "antialias_hz")
    q_jerk_m2_per_s5: float = _field(ONLINE_SECTION, "q_jerk_m2_per_s5")
    meas_position_std_m: float = _field(ONLINE_SECTION, "meas_position_std_m")
    adapt_to_noise: bool = _field(ONLINE_SECTION, "adapt_to_noise")
    noise_tau_s: float = _field(ONLINE_SECTION, "noise_tau_s")
    noise_knee_m: float = _field(ONLINE_SECTION, "noise_knee_m")
    walk_noise_sigmas: float = _field(ONLINE_SECTION, "walk_noise_sigmas")
    outlier_gate_nis: float = _field(ONLINE_SECTION, "outlier_gate_nis")
    max_outlier_s: float = _field(ONLINE_SECTION, "max_outlier_s")
    initial_velocity_std_mps: float = _field(ONLINE_SECTION, "initial_velocity_std_mps")
    initial_accel_std_mps2: float = _field(ONLINE_SECTION, "initial_accel_std_mps2")
    settle_s: float = _field(ONLINE_SECTION, "settle_s")
    centre_blend_tau_s: float = _field(ONLINE_SECTION, "centre_blend_tau_s")
    centre_forget_s: float = _field(ONLINE_SECTION, "centre_forget_s")
    max_abs_position_m: float = _field(ONLINE_SECTION, "max_abs_position_m")
    max_gap_s: float = _field(ONLINE_SECTION, "max_gap_s")
    gait_bob_m: float = _field(ONLINE_SECTION, "gait_bob_m")
    gait_window_s: float = _field(ONLINE_SECTION, "gait_window_s")
    gait_max_bob_m: float = _field(ONLINE_SECTION, "gait_max_bob_m")
    gait_keep_bob_m: float = _field(ONLINE_SECTION, "gait_keep_bob_m")
    gait_in_place: bool = _field(ONLINE_SECTION, "gait_in_place")
    heading_tau_s: float = _field(ONLINE_SECTION, "heading_tau_s")
    heading_min_speed_mps: float = _field(ONLINE_SECTION, "heading_min_speed_mps")
    latency_f_hz: float = _field(ONLINE_SECTION, "latency_f_hz")
    max_time_jump_s: float = _field(ONLINE_SECTION, "max_time_jump_s")
    valid_after_s: float = _field(ONLINE_SECTION, "valid_after_s")
    min_rate_hz: float = _field(ONLINE_SECTION, "min_rate_hz")
    phase_std_tau_s: float = _field(ONLINE_SECTION, "phase_std_tau_s")
    max_plausible_speed_mps: float = _field(ONLINE_SECTION, "max_plausible_speed_mps")
    max_walking_speed_mps: float = _field(ONLINE_SECTION, "max_walking_speed_mps")
    max_input_noise_m: float = _field(ONLINE_SECTION, "max_input_noise_m")
    feet_max_input_noise_m: float = _field(ONLINE_SECTION, "feet_max_input_noise_m")
    max_mean_nis: float = _field(ONLINE_SECTION, "max_mean_nis")
    belt_tau_s: float = _field(ONLINE_SECTION, "belt_tau_s")
    treadmill_min_belt_mps: float = _field(ONLINE_SECTION, "treadmill_min_belt_mps")
    stance_band_m: float = _field(ONLINE_SECTION, "stance_band_m")
    treadmill_heading_rad: float = _field(ONLINE_SECTION, "treadmill_heading_rad")
    treadmill_max_pelvis_mps: float = _field(ONLINE_SECTION, "treadmill_max_pelvis_mps")

    def _own(self):
        return [f for f in fields(self) if f.name != "estimator"]

    def to_dict(self) -> dict:
        """The estimator's :meth:`EstimatorConfig.to_dict` with an ``online`` table of the front-end's fields."""
        return self.estimator.to_dict() | {ONLINE_SECTION: {f.name: _plain(getattr(self, f.name)) for f in self._own()}}

    @classmethod
    def from_dict(cls, values: Mapping) -> OnlineConfig:
        """The default with ``values`` (nested as :meth:`to_dict`, partial) applied, checked."""
        return cls().with_values(values)

    def with_values(self, values: Mapping) -> OnlineConfig:
        """A copy with ``values`` (the estimator's fields and an ``online`` table, partial) applied, checked."""
        if not isinstance(values, Mapping):
            raise InputError(f"a configuration must be a table of fields, got {type(values).__name__}")
        values = dict(values)
        values.pop(IMU_SECTION, None)
        online = values.pop(ONLINE_SECTION, {})
        if not isinstance(online, Mapping):
            raise InputError(f"{ONLINE_SECTION} must be a table of fields, got {online!r}")
        _reject_unknown(online, {f.name for f in self._own()}, ONLINE_SECTION)
        out = dataclasses.replace(self, estimator=self.estimator.with_values(values), **dict(online))
        out.validate()
        return out

    @classmethod
    def from_file(cls, path) -> OnlineConfig:
        """The estimator's fields and the ``[online]`` table of a TOML file (fields left out keep
        their defaults). InputError naming the file and the field for anything unusable."""
        path = Path(path)
        return cls._from_file_values(path, _read_toml(path))

    def to_native(self) -> _core.OnlineConfig:
        """The C++ struct; raises InputError saying what is not usable."""
        if not isinstance(self.estimator, EstimatorConfig):
            raise InputError(f"estimator must be an EstimatorConfig, got {type(self.estimator).__name__}")
        native = _core.OnlineConfig()
        native.estimator = self.estimator.to_native()
        for f in self._own():
            setattr(native, f.name, f.metadata["schema"].check(getattr(self, f.name)))
        problem = native.validate()
        if problem:
            raise InputError(f"invalid online configuration: {problem}")
        return native


def effective_toml(preset: str | None = None, path=None) -> str:
    """The effective configuration as TOML: the estimator of ``preset`` (default: the default) or of
    the file ``path`` applied to the defaults, then the ``[online]`` table (the file's, checked, else
    the defaults), then the ``[imu]`` table likewise. Both are printed for either algorithm: the offline
    commands ignore them."""
    if path is not None:
        path = Path(path)
        estimator = EstimatorConfig.from_file(path)
        online_values = _read_toml(path).get(ONLINE_SECTION, {})
        imu_values = _read_toml(path).get(IMU_SECTION, {})
    else:
        estimator = EstimatorConfig.preset(preset or "default")
        online_values = imu_values = {}
    try:  # the online and imu tables checked on their own (with the default estimator behind them)
        online = OnlineConfig().with_values({ONLINE_SECTION: online_values})
        imu = ImuConfig().with_values({IMU_SECTION: imu_values})
    except InputError as exc:
        raise InputError(f"{path}: {exc}" if path is not None else str(exc)) from None
    tables = {ONLINE_SECTION: online.to_dict()[ONLINE_SECTION], IMU_SECTION: imu.to_dict()[IMU_SECTION]}
    return estimator.to_toml() + "\n" + tomli_w.dumps(tables)


PRESETS = {"paper": EstimatorConfig.paper, "default": EstimatorConfig.default}
"""Named configurations: the paper's estimator and the default (the gait filter)."""


def schema_markdown() -> str:
    """docs/configuration.md: every field of :data:`SCHEMA` with its default, unit, range and doc."""
    titles = {
        "": "Shared by both algorithms",
        "paper_estimator": '`[paper_estimator]`: the paper\'s estimator (`algorithm = "paper"`)',
        "gait_filter": '`[gait_filter]`: the gait filter, the default estimator (`algorithm = "gait_filter"`)',
        ONLINE_SECTION: "`[online]`: the online front-end (`OnlineConfig`; `--online`, `live`, `evaluate --online`)",
        IMU_SECTION: "`[imu]`: the lower-back IMU front-end (`ImuConfig`; IMU files, docs/imu.md)",
    }
    lines = [
        "# Configuration",
        "",
        "<!-- Generated from the C++ tables (include/yoyogait/config.hpp) by",
        "     python -c 'import sys, yoyogait.estimators.config as c; sys.stdout.write(c.schema_markdown())' \\",
        "     > docs/configuration.md",
        "     and checked by tests/python/estimators/test_config.py. -->",
        "",
        "Every field of `EstimatorConfig` (Python `yoyogait.EstimatorConfig`, C++ `yoyogait::EstimatorConfig`),",
        "declared once in `include/yoyogait/config.hpp`. A value outside its valid range is an error naming",
        "the field (Python `ValueError`, C++ `std::invalid_argument`) when an estimator is built. Rules",
        "between fields: `f_max_hz > f_min_hz`; `bank_f_hz` increasing, within [`f_min_hz`, `f_max_hz`];",
        "at most 10000 spectral grid frequencies in [`f_min_hz`, `f_max_hz`]; `q_omega_rate_hi_rad2_per_s5 >=",
        "q_omega_rate_lo_rad2_per_s5`; `walk_speed_off_mps <= walk_speed_on_mps`;",
        "`walk_vz_rms_off_mps <= walk_vz_rms_on_mps`; `std_scale_max >= std_scale_min`. The ranges are",
        "wide (every value in them gives finite estimates), not advice: `default_estimator.md` and",
        "`paper_estimator.md` say which values are sensible and why the defaults are what they are.",
        "",
        "A configuration file is TOML: the shared fields at the top, then one table per section; fields",
        "left out keep their defaults (`EstimatorConfig.from_file`, `save`; `--config FILE` on the",
        "command line):",
        "",
        "```toml",
        'algorithm = "gait_filter"',
        "sample_time_s = 0.04",
        "",
        "[gait_filter]",
        "gate_sigma = 4.0",
        "bank_f_hz = [1.0, 1.5, 2.0]",
        "",
        "[online]",
        "meas_position_std_m = 0.002",
        "```",
        "",
        "The `[online]` table is the online front-end's (`OnlineConfig`: `estimate --online`, `live`,",
        "`evaluate --online`); the offline commands ignore it, so one file serves both. `yoyogait config`",
        "prints the effective configuration of a preset or a file as TOML.",
    ]
    for section in ("", *SECTIONS, ONLINE_SECTION, IMU_SECTION):
        lines += ["", f"## {titles[section]}", "", "| field | type | default | unit | valid range | what it is |"]
        lines.append("|---|---|---|---|---|---|")
        for f in SCHEMA:
            if f.section != section:
                continue
            default = _default_text(f.default)
            doc = f.doc.replace("|", "\\|")
            lines.append(f"| `{f.name}` | {f.type} | {default} | {f.unit or '-'} | {f.range_text() or '-'} | {doc} |")
    return "\n".join(lines) + "\n"


def _default_text(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_num(v) for v in value) + "]"
    if isinstance(value, float):
        return _num(value)
    return str(value)


@dataclass
class ImuConfig(_ConfigFile):
    """Settings of the lower-back IMU front-end (docs/imu.md); mirrors ``yoyogait::ImuConfig``: the
    gait estimator behind it and the fields of the C++ table ``YOYOGAIT_IMU_FIELDS`` (section
    ``imu`` of :data:`SCHEMA`). In a TOML file the estimator's fields as :class:`EstimatorConfig`
    has them, and an ``[imu]`` table; ``[online]`` is ignored here, as ``[imu]`` is by the others.
    """

    estimator: EstimatorConfig = field(default_factory=EstimatorConfig)
    """The gait estimator behind the front-end, fed every ``estimator.sample_time_s``."""
    mahony_kp_per_s: float = _field(IMU_SECTION, "mahony_kp_per_s")
    mahony_ki_per_s2: float = _field(IMU_SECTION, "mahony_ki_per_s2")
    max_gyro_bias_rad_s: float = _field(IMU_SECTION, "max_gyro_bias_rad_s")
    highpass_tau_s: float = _field(IMU_SECTION, "highpass_tau_s")
    forward_axis: int = _field(IMU_SECTION, "forward_axis")
    forward_negative: bool = _field(IMU_SECTION, "forward_negative")
    sensor_height_m: float = _field(IMU_SECTION, "sensor_height_m")
    step_length_factor: float = _field(IMU_SECTION, "step_length_factor")
    excursion_tau_s: float = _field(IMU_SECTION, "excursion_tau_s")
    speed_rel_std: float = _field(IMU_SECTION, "speed_rel_std")
    max_walk_ratio_m_per_spm: float = _field(IMU_SECTION, "max_walk_ratio_m_per_spm")
    turn_f_std_hz_per_rad_s: float = _field(IMU_SECTION, "turn_f_std_hz_per_rad_s")
    lock_f_rel_std: float = _field(IMU_SECTION, "lock_f_rel_std")
    min_periodicity: float = _field(IMU_SECTION, "min_periodicity")
    periodicity_steps: float = _field(IMU_SECTION, "periodicity_steps")
    min_vz_rms_mps: float = _field(IMU_SECTION, "min_vz_rms_mps")
    phase_std_tau_s: float = _field(IMU_SECTION, "phase_std_tau_s")
    phase_onset_tau_s: float = _field(IMU_SECTION, "phase_onset_tau_s")
    settle_s: float = _field(IMU_SECTION, "settle_s")
    max_gap_s: float = _field(IMU_SECTION, "max_gap_s")
    acc_saturation_mps2: float = _field(IMU_SECTION, "acc_saturation_mps2")
    gyr_saturation_rad_s: float = _field(IMU_SECTION, "gyr_saturation_rad_s")
    saturation_hold_s: float = _field(IMU_SECTION, "saturation_hold_s")
    gravity_tau_s: float = _field(IMU_SECTION, "gravity_tau_s")
    gravity_tolerance: float = _field(IMU_SECTION, "gravity_tolerance")
    max_speed_mps: float = _field(IMU_SECTION, "max_speed_mps")
    mag_kp_per_s: float = _field(IMU_SECTION, "mag_kp_per_s")
    mag_norm_tolerance: float = _field(IMU_SECTION, "mag_norm_tolerance")
    latency_f_hz: float = _field(IMU_SECTION, "latency_f_hz")

    def _own(self):
        return [f for f in fields(self) if f.name != "estimator"]

    def to_dict(self) -> dict:
        """The estimator's :meth:`EstimatorConfig.to_dict` with an ``imu`` table of the front-end's fields."""
        return self.estimator.to_dict() | {IMU_SECTION: {f.name: _plain(getattr(self, f.name)) for f in self._own()}}

    @classmethod
    def from_dict(cls, values: Mapping) -> ImuConfig:
        """The default with ``values`` (nested as :meth:`to_dict`, partial) applied, checked."""
        return cls().with_values(values)

    def with_values(self, values: Mapping) -> ImuConfig:
        """A copy with ``values`` (the estimator's fields and an ``imu`` table, partial) applied, checked."""
        if not isinstance(values, Mapping):
            raise InputError(f"a configuration must be a table of fields, got {type(values).__name__}")
        values = dict(values)
        values.pop(ONLINE_SECTION, None)
        imu = values.pop(IMU_SECTION, {})
        if not isinstance(imu, Mapping):
            raise InputError(f"{IMU_SECTION} must be a table of fields, got {imu!r}")
        _reject_unknown(imu, {f.name for f in self._own()}, IMU_SECTION)
        out = dataclasses.replace(self, estimator=self.estimator.with_values(values), **dict(imu))
        out.validate()
        return out

    @classmethod
    def from_file(cls, path) -> ImuConfig:
        """The estimator's fields and the ``[imu]`` table of a TOML file (fields left out keep their
        defaults). InputError naming the file and the field for anything unusable."""
        path = Path(path)
        return cls._from_file_values(path, _read_toml(path))

    def to_native(self) -> _core.ImuConfig:
        """The C++ struct; raises InputError saying what is not usable."""
        if not isinstance(self.estimator, EstimatorConfig):
            raise InputError(f"estimator must be an EstimatorConfig, got {type(self.estimator).__name__}")
        native = _core.ImuConfig()
        native.estimator = self.estimator.to_native()
        for f in self._own():
            setattr(native, f.name, f.metadata["schema"].check(getattr(self, f.name)))
        problem = native.validate()
        if problem:
            raise InputError(f"invalid imu configuration: {problem}")
        return native
