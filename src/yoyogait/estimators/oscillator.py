"""Adaptive frequency oscillator: the usual gait-phase estimator of exoskeletons, as a baseline.

In the style of Righetti et al. (2006) and Ronsse et al. (2011). A pool of
phase oscillators learns the vertical velocity F = v_z of the pelvis:

    F_hat     = a0 + sum_i a_i cos(phi_i)                      i = 1..n harmonics
    e         = F - F_hat,   e_n = e / s                       (s: running RMS of F - a0)
    dphi_i/dt = i w - nu_phi e_n sin(phi_i)
    dw/dt     = -nu_w e_n sin(phi_1)
    da_0/dt   = eta e,   da_i/dt = eta e cos(phi_i)

The forward velocity is fitted on the same phase by least mean squares,
v_x_hat = b0 + sum_i (b_i cos(i phi_1) + c_i sin(i phi_1)), with b0 a low-pass
of v_x (the speed).  Euler integration over the actual time step; w is kept in
[f_min, f_max].  Normalising the error by s makes the gains independent of
the size of the oscillation.  The default gains were chosen on the same real
recordings the estimator is evaluated on, so that the comparison is fair.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._sample_time import SAMPLE_TIME_S
from ..errors import InputError
from .results import PREDICTION_HORIZONS_S, EstimateResult, result_from_fit

__all__ = ["OscillatorConfig", "AdaptiveOscillator", "OscillatorBaseline", "run_oscillator"]

TWO_PI = 2.0 * math.pi


@dataclass
class OscillatorConfig:
    """Gains and bounds of the adaptive oscillator."""

    n_harmonics: int = 2
    initial_step_frequency_hz: float = 1.8
    nu_phi_per_s: float = 6.0  # phase coupling gain
    nu_w_rad_per_s2: float = 6.0  # frequency adaptation gain
    eta_per_s: float = 1.0  # learning rate of the v_z Fourier amplitudes
    eta_x_per_s: float = 4.0  # learning rate of the v_x Fourier coefficients
    mean_tau_s: float = 0.5  # time constant of the speed b0
    rms_tau_s: float = 1.0  # time constant of the error normalisation
    min_rms_mps: float = 0.02  # floor of the normalisation
    f_min_hz: float = 0.3
    f_max_hz: float = 4.0
    sample_time_s: float = SAMPLE_TIME_S  # used where no time step is given

    def __post_init__(self):
        if not (isinstance(self.n_harmonics, int) and self.n_harmonics >= 1):
            raise InputError("n_harmonics must be an integer >= 1")
        if not (0 < self.f_min_hz < self.f_max_hz):
            raise InputError("need 0 < f_min_hz < f_max_hz")
        if not (self.sample_time_s > 0 and self.mean_tau_s > 0 and self.rms_tau_s > 0):
            raise InputError("sample_time_s, mean_tau_s and rms_tau_s must be > 0")


class AdaptiveOscillator:
    """Streaming adaptive oscillator: ``step(vx, vz, dt_s)`` per sample (see the module doc)."""

    def __init__(self, config: OscillatorConfig | None = None):
        self.config = config or OscillatorConfig()
        self.reset()

    def reset(self) -> None:
        n = self.config.n_harmonics
        self.omega_rad_s = TWO_PI * self.config.initial_step_frequency_hz
        self.phi = np.zeros(n + 1)  # phi[i] for harmonic i (phi[0] unused)
        self.a = np.zeros(n + 1)  # v_z: a0 and cosine amplitudes
        self.b = np.zeros(n + 1)  # v_x: b0 and cosine coefficients
        self.c = np.zeros(n + 1)  # v_x: sine coefficients
        self.rms2 = 0.0
        self.started = False
        self._k = np.arange(n + 1)

    def _vz_hat(self, phi) -> float:
        return float(self.a[0] + np.dot(self.a[1:], np.cos(phi[1:])))

    def _vx_hat(self, p1: float) -> float:
        k = self._k[1:]
        return float(self.b[0] + np.dot(self.b[1:], np.cos(k * p1)) + np.dot(self.c[1:], np.sin(k * p1)))

    def step(self, vx: float, vz: float, dt_s: float | None = None) -> tuple[float, float]:
        """One sample; returns the reconstruction (vx_hat_mps, vz_hat_mps) after it."""
        cfg = self.config
        dt = dt_s if (dt_s is not None and dt_s > 0 and math.isfinite(dt_s)) else cfg.sample_time_s
        if not self.started:
            if not (math.isfinite(vx) and math.isfinite(vz)):
                return self._vx_hat(self.phi[1]), self._vz_hat(self.phi)
            # Start on the first good sample: speed from it, everything else from zero.
            self.started = True
            self.b[0] = vx
            self.rms2 = 0.1**2
            dt = 0.0
        k = self._k[1:]
        self.phi[1:] += k * self.omega_rad_s * dt
        if math.isfinite(vz):
            e = vz - self._vz_hat(self.phi)
            alpha = 1.0 - math.exp(-dt / cfg.rms_tau_s) if dt > 0 else 0.0
            self.rms2 += alpha * ((vz - self.a[0]) ** 2 - self.rms2)
            en = e / math.sqrt(max(self.rms2, cfg.min_rms_mps**2))
            dw = -cfg.nu_w_rad_per_s2 * en * math.sin(self.phi[1])
            self.phi[1:] += -cfg.nu_phi_per_s * en * np.sin(self.phi[1:]) * dt
            self.omega_rad_s = min(max(self.omega_rad_s + dw * dt, TWO_PI * cfg.f_min_hz), TWO_PI * cfg.f_max_hz)
            self.a[0] += cfg.eta_per_s * e * dt
            self.a[1:] += cfg.eta_per_s * e * np.cos(self.phi[1:]) * dt
        if math.isfinite(vx):
            p1 = self.phi[1]
            ex = vx - self._vx_hat(p1)
            self.b[0] += (1.0 - math.exp(-dt / cfg.mean_tau_s) if dt > 0 else 0.0) * ex
            self.b[1:] += cfg.eta_x_per_s * ex * np.cos(k * p1) * dt
            self.c[1:] += cfg.eta_x_per_s * ex * np.sin(k * p1) * dt
        self.phi[1:] = np.fmod(self.phi[1:], TWO_PI * k)
        return self._vx_hat(self.phi[1]), self._vz_hat(self.phi)

    def predict(self, horizon_s: float) -> tuple[float, float]:
        """(vx, vz) ``horizon_s`` ahead: the phases advanced at the current frequency."""
        phi = self.phi + self._k * self.omega_rad_s * horizon_s
        return self._vx_hat(phi[1]), self._vz_hat(phi)


def oscillate(time_s, vx, vz, config: OscillatorConfig | None = None, predict_ahead_s=()) -> dict[str, np.ndarray]:
    """The oscillator over a signal, sample by sample: per sample the reconstruction
    (``vx_hat_mps``, ``vz_hat_mps``), ``omega_rad_s``, the speed ``b0_mps``, the fundamentals
    ``x1_mps``, ``z1_mps``, the phase ``gait_phase`` (phi_1 mod 2 pi, in cycles), ``started``
    (the first finite sample has been seen) and the predictions ``vx_pred``, ``vz_pred``
    (samples x horizons). The one loop of the baseline: :func:`run_oscillator` and the online
    evaluation both read it."""
    cfg = config or OscillatorConfig()
    t = np.asarray(time_s, dtype=float)
    vx = np.asarray(vx, dtype=float)
    vz = np.asarray(vz, dtype=float)
    if not (t.shape == vx.shape == vz.shape and t.ndim == 1):
        raise InputError("time_s, vx and vz must be one-dimensional and of the same length")
    n = t.size
    osc = AdaptiveOscillator(cfg)
    horizons = tuple(float(h) for h in predict_ahead_s)
    keys = ("vx_hat_mps", "vz_hat_mps", "omega_rad_s", "b0_mps", "x1_mps", "z1_mps", "gait_phase")
    out = {k: np.empty(n) for k in keys}
    out["started"] = np.zeros(n, dtype=bool)
    out["vx_pred"], out["vz_pred"] = np.empty((n, len(horizons))), np.empty((n, len(horizons)))
    prev = None
    for i in range(n):
        dt = None if prev is None else t[i] - prev
        prev = t[i]
        out["vx_hat_mps"][i], out["vz_hat_mps"][i] = osc.step(vx[i], vz[i], dt)
        out["omega_rad_s"][i], out["b0_mps"][i] = osc.omega_rad_s, osc.b[0]
        out["x1_mps"][i] = osc.b[1] * math.cos(osc.phi[1]) + osc.c[1] * math.sin(osc.phi[1])  # v_x fundamental
        out["z1_mps"][i] = osc.a[1] * math.cos(osc.phi[1])  # v_z fundamental
        out["gait_phase"][i] = (osc.phi[1] % TWO_PI) / TWO_PI
        out["started"][i] = osc.started
        for j, h in enumerate(horizons):
            out["vx_pred"][i, j], out["vz_pred"][i, j] = osc.predict(h)
    return out


def run_oscillator(
    time_s, vx, vz, *, config: OscillatorConfig | None = None, predict_ahead_s=PREDICTION_HORIZONS_S
) -> EstimateResult:
    """Run the oscillator over a signal; returns an :class:`~yoyogait.estimators.results.EstimateResult`."""
    cfg = config or OscillatorConfig()
    t = np.asarray(time_s, dtype=float)
    o = oscillate(t, vx, vz, cfg, predict_ahead_s)
    n = t.size
    T = float(np.median(np.diff(t))) if n > 1 else cfg.sample_time_s
    horizons = tuple(float(h) for h in predict_ahead_s)
    # In the paper's state, v_z = -x2.
    return result_from_fit(
        o["omega_rad_s"], o["b0_mps"], o["x1_mps"], -o["z1_mps"], o["vx_hat_mps"], o["vz_hat_mps"], T,
        o["vx_pred"], o["vz_pred"], horizons, t,
    )  # fmt: skip


@dataclass(frozen=True)
class OscillatorBaseline:
    """The adaptive-oscillator baseline's parameters; :meth:`run` computes (parameters apart from results)."""

    config: OscillatorConfig = field(default_factory=OscillatorConfig)

    def run(self, time_s, vx, vz, *, predict_ahead_s=PREDICTION_HORIZONS_S) -> EstimateResult:
        """Estimates at every sample (see :func:`run_oscillator`)."""
        return run_oscillator(time_s, vx, vz, config=self.config, predict_ahead_s=predict_ahead_s)
