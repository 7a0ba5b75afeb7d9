"""What the estimators return: :class:`EstimateResult`, one row per sample.

The native estimators (:class:`~yoyogait.estimators.GaitEstimator`) and the
baselines (:mod:`~yoyogait.estimators.oscillator`,
:mod:`~yoyogait.estimators.sliding_dft`) all give this type, so the evaluation
scores them alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import _table
from .._sample_time import SAMPLE_TIME_S
from ..errors import InputError

__all__ = ["EstimateResult", "PREDICTION_HORIZONS_S", "result_from_fit"]

PREDICTION_HORIZONS_S = (SAMPLE_TIME_S, 0.2)
"""Horizons the evaluation predicts at [s]: one sample (the estimator's sample_time_s, 0.04 s), and 0.2 s."""

TWO_PI = 2.0 * math.pi


@dataclass
class EstimateResult:
    """Estimates over a signal, one row per sample (the estimate after that sample).

    Arrays in physical units: ``vx_hat_mps``, ``vz_hat_mps`` (the model's reconstruction,
    m/s), ``R_m``, ``r_m`` (m), ``step_frequency_hz`` (paper: signed, as the
    filter has it; default: > 0), ``omega_rad_s``, ``speed_mps`` (the forward
    speed without the oscillation), ``A0_mps``, ``A1_mps``, their standard
    deviations, the state (N, 4) in the paper's form of eq. 5 (default:
    [X1, X2, w T, A0]) and the paper's ``R_hat_mps``, ``r_hat_mps``.  ``status``
    holds a :class:`Status` code per sample.  When predictions were asked for,
    ``vx_pred``/``vz_pred`` (N, H) hold the velocities predicted at each sample
    for ``predict_ahead_s[j]`` later.

    From the native estimators also (None for results built elsewhere):
    ``vx_hat_h2_mps``, ``vz_hat_h2_mps`` (with the second harmonics), ``std_scale``,
    ``walking``, ``acquiring`` and, for the default, ``gait_state`` (N, 8) =
    [X1, X2, Z1, Z2, w, A0, dA0, dw].  For the paper these carry nothing new
    and are not written per sample: ``vx_hat_h2_mps`` is ``vx_hat_mps``, the flags and
    ``std_scale`` are constant read-only views (True, False, 1) and
    ``gait_state`` is None (``GaitEstimator.step`` gives it in the gait form).
    ``covariance`` (N, k, k): the filter's covariance after each sample (k = 4 for the
    paper, 8 for the default), when ``run(..., covariance=True)`` asked for it, else None.
    Derived when read, for every result with a state: ``amp_z_mps``,
    ``phase_x_rel_z_rad``, ``signed_amp_x_mps``, ``omega_rate_rad_s2``,
    ``accel_mps2`` (see the C++ ``yoyogait::Estimate``).

    Diagnostics, only from ``GaitEstimator.run(..., diagnostics=True)`` (None otherwise), as
    FilterPy exposes them: ``innovation_vx_mps``, ``innovation_vz_mps`` (measurement minus
    predicted measurement of each channel; the default's v_z innovation is taken after its v_x
    update, as its sequential updates use it) and ``nis``, the normalised innovation squared
    (about 2, the number of channels, on average when the noise model fits the data); NaN for a
    channel a sample did not use (see the C++ ``yoyogait::Innovation``).
    """

    state: np.ndarray
    vx_hat_mps: np.ndarray
    vz_hat_mps: np.ndarray
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
    vx_hat_h2_mps: np.ndarray | None = None
    vz_hat_h2_mps: np.ndarray | None = None
    std_scale: np.ndarray | None = None
    walking: np.ndarray | None = None
    acquiring: np.ndarray | None = None
    innovation_vx_mps: np.ndarray | None = None
    innovation_vz_mps: np.ndarray | None = None
    nis: np.ndarray | None = None
    covariance: np.ndarray | None = None

    def __len__(self) -> int:
        return int(self.vx_hat_mps.shape[0])

    def __repr__(self) -> str:
        n = len(self)
        if n == 0:
            return f"EstimateResult(0 samples, T={self.sample_time_s:g} s)"
        duration_s = (
            float(self.time_s[-1] - self.time_s[0]) if self.time_s is not None else (n - 1) * self.sample_time_s
        )
        walking = np.asarray(self.walking, dtype=bool) if self.walking is not None else np.ones(n, dtype=bool)
        where = "while walking" if walking.any() and not walking.all() else "median"
        rows = walking if walking.any() else np.ones(n, dtype=bool)

        def median(values) -> float:
            v = np.asarray(values, dtype=float)[rows]
            v = v[np.isfinite(v)]
            return float(np.median(v)) if v.size else float("nan")

        not_used = int(np.count_nonzero(np.asarray(self.status) != 0))
        return (
            f"EstimateResult({n} samples, {duration_s:.2f} s, T={self.sample_time_s:g} s; {where}: "
            f"step frequency {median(self.step_frequency_hz):.3g} Hz, speed {median(self.speed_mps):.3g} m/s, "
            f"R {median(self.R_m):.3g} m, r {median(self.r_m):.3g} m; "
            f"{not_used} samples not used"
            + (f"; predictions at {self.predict_ahead_s} s" if self.predict_ahead_s else "")
            + ")"
        )

    def to_columns(self, velocities=None) -> dict[str, np.ndarray]:
        """The estimates as named columns, units in every name, one row per sample (what
        :meth:`to_csv` writes).

        With ``velocities`` (the :class:`~yoyogait.pipeline.velocities.GaitVelocities` the result was
        computed from) the measured ``vx_mps``, ``vz_mps`` and the data's ``walking`` (from foot
        contacts or speed) come first.  ``estimator_walking`` is the estimator's own detector: where
        it is 0 the default estimator holds its last walking values.  ``status`` is the
        :class:`~yoyogait.Status` code of the sample (0: used).
        """
        n = len(self)
        if velocities is not None and len(velocities.time_s) != n:
            raise InputError(f"velocities have {len(velocities.time_s)} samples, the result {n}")
        if velocities is not None:
            time_s = velocities.time_s
        elif self.time_s is not None:
            time_s = self.time_s
        else:
            time_s = np.arange(n) * self.sample_time_s
        cols: dict[str, np.ndarray] = {"time_s": np.asarray(time_s, dtype=float)}
        if velocities is not None:
            cols.update(vx_mps=velocities.vx, vz_mps=velocities.vz, walking=np.asarray(velocities.walking, bool))
        state = np.asarray(self.state)
        cols.update(
            vx_hat_mps=self.vx_hat_mps,
            vz_hat_mps=self.vz_hat_mps,
            step_frequency_hz=self.step_frequency_hz,
            step_frequency_std_hz=self.step_frequency_std_hz,
            speed_mps=self.speed_mps,
            speed_std_mps=self.speed_std_mps,
            R_m=self.R_m,
            r_m=self.r_m,
            A0_mps=self.A0_mps,
            A1_mps=self.A1_mps,
            x1_mps=state[:, 0],
            x2_mps=state[:, 1],
            x3_rad_per_sample=state[:, 2],
            x4_mps=state[:, 3],
        )
        walking = self.walking if self.walking is not None else np.ones(n, dtype=bool)
        cols["estimator_walking"] = np.asarray(walking, dtype=bool)
        cols["status"] = np.asarray(self.status).astype(np.int64)
        return {k: np.ascontiguousarray(v) for k, v in cols.items()}

    def to_dataframe(self, velocities=None):
        """:meth:`to_columns` as a pandas DataFrame (needs the extra ``yoyogait[pandas]``)."""
        return _table.to_dataframe(self.to_columns(velocities))

    def to_csv(self, path, velocities=None):
        """Write :meth:`to_columns` as CSV to ``path`` (through a temporary file); returns the path."""
        return _table.write_csv(path, self.to_columns(velocities))

    # Derived from the state when read, as yoyogait::Estimate does: from gait_state, or, for
    # results without it (the paper's run, the baselines), from the paper-form state (eq. 5:
    # Z is X turned by +90 degrees, no rates).

    def _g(self) -> np.ndarray:
        if self.gait_state is not None:
            return self.gait_state
        s = self.state
        zero = np.zeros(s.shape[0])
        return np.column_stack([s[:, 0], s[:, 1], -s[:, 1], s[:, 0], s[:, 2] / self.sample_time_s, s[:, 3], zero, zero])

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

        Aligned by real time: the prediction made at sample i is for ``time_s[i] + horizon_s``; at
        sample k it is the prediction whose time is ``time_s[k]`` (to 1e-9 s), else the linear
        interpolation between the two predictions whose times bracket it (irregular sampling,
        gaps). Without ``time_s`` (or with times that do not increase) the samples are taken
        ``sample_time_s`` apart. NaN where no prediction reaches (the first samples).
        """
        for j, h in enumerate(self.predict_ahead_s):  # noqa: B007 (j is used after the loop)
            if math.isclose(h, horizon_s, rel_tol=1e-9, abs_tol=1e-12):
                break
        else:
            raise InputError(f"no prediction {horizon_s} s ahead was computed; have {self.predict_ahead_s}")
        assert self.vx_pred is not None and self.vz_pred is not None  # set with predict_ahead_s
        n = len(self)
        t = None if self.time_s is None else np.asarray(self.time_s, dtype=float)
        if t is None or t.size != n or not np.all(np.diff(t) > 0):
            t = np.arange(n) * self.sample_time_s
        target = t + float(h)
        out = []
        for pred in (self.vx_pred[:, j], self.vz_pred[:, j]):
            aligned = np.interp(t, target, pred, left=np.nan, right=np.nan) if n else np.empty(0)
            # A prediction made for a sample's own time is taken as it is (no interpolation weights).
            for i in (np.searchsorted(target, t) - 1, np.searchsorted(target, t)):
                i = np.clip(i, 0, max(n - 1, 0))
                exact = np.abs(target[i] - t) <= 1e-9 if n else np.zeros(0, dtype=bool)
                aligned[exact] = pred[i[exact]]
            out.append(aligned)
        return out[0], out[1]


def result_from_fit(omega_rad_s, a0, cos_part, sin_part, vx_hat_mps, vz_hat_mps, T, vx_pred, vz_pred, horizons, time_s):
    """An EstimateResult from per-sample fit values (state in the paper's form, eq. 5), for the baselines."""
    n = omega_rad_s.size
    w = omega_rad_s * T
    a1 = np.hypot(cos_part, sin_part)
    with np.errstate(invalid="ignore", divide="ignore"):
        R_m = np.where(omega_rad_s > 0, a0 / omega_rad_s, np.nan)
        r_m = np.where(omega_rad_s > 0, a1 / omega_rad_s, np.nan)
    nan = np.full(n, np.nan)
    return EstimateResult(
        state=np.column_stack([cos_part, sin_part, w, a0]),
        vx_hat_mps=vx_hat_mps,
        vz_hat_mps=vz_hat_mps,
        R_hat_mps=R_m / T,
        r_hat_mps=r_m / T,
        R_m=R_m,
        r_m=r_m,
        omega_rad_s=omega_rad_s,
        step_frequency_hz=omega_rad_s / TWO_PI,
        step_frequency_std_hz=nan,
        speed_mps=a0,
        speed_std_mps=nan,
        A0_mps=a0,
        A1_mps=a1,
        status=np.zeros(n, dtype=np.uint8),
        parameters_updated=np.ones(n, dtype=bool),
        sample_time_s=T,
        predict_ahead_s=tuple(horizons),
        vx_pred=vx_pred,
        vz_pred=vz_pred,
        time_s=time_s,
    )
