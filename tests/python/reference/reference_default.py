"""Independent plain-numpy implementation of the default estimator (docs/default_estimator.md).

The tests compare the native core against it, as reference_ekf.py is for the paper.
Streaming: ``DefaultEstimator(cfg).step(vx, vz, dt_s)`` returns a dict; ``.predict(h_s)``.
:func:`config_from` maps a ``yoyogait.EstimatorConfig`` to the :class:`DefaultConfig` here.

Core: a dual-phasor EKF with one shared, strictly positive step frequency.

  state x = [X1, X2, Z1, Z2, w, A0, dA0, dw]
      X = (X1, X2)  phasor of the forward-velocity oscillation               (m/s)
      Z = (Z1, Z2)  phasor of the vertical-velocity oscillation              (m/s)
      w             step angular frequency, clamped to [w_min, w_max]        (rad/s)
      A0            forward-speed bias = R w (stride-averaged speed), >= 0   (m/s)
      dA0           its rate (Gauss-Markov, time constant accel_tau_s)       (m/s^2)
      dw            frequency rate (Gauss-Markov, time constant omega_rate_tau_s) (rad/s^2)

  transition over the actual dt (phi = w dt, a = exp(-dt/accel_tau_s), b = exp(-dt/omega_rate_tau_s)):
      X <- Rot(phi) X,  Z <- Rot(phi) Z,  w <- w + dt dw,  dw <- b dw,  A0 <- A0 + dt dA0,  dA0 <- a dA0
  measurement (two sequential scalar updates):
      vx = A0 + X1 + hx,   vz = Z1 + hz
      hx, hz: second harmonic of each channel, h = c cos(2 th) + s sin(2 th) with th the angle of
      that channel's own phasor; (c, s) from a cascaded 2-state Kalman filter per channel.

  The forward-vertical phase relation is the angle between X and Z: estimated, not imposed.
  A phasor observed through its first component cannot tell its direction of rotation, so
  w > 0 loses nothing: the paper's negative-frequency solution is the same signal with X2, Z2
  mirrored.

  Measurement noise: R = diag(r_vx_density, r_vz_density) / dt (a sample is the mean over dt).
  Process noise (continuous densities, times dt):
      q_phasor I on X and Z (independent drift: amplitude, phase relation),
      q_phase g g^T with g = [-X2, X1, -Z2, Z1, 0...] (common gait-phase jitter: rotates X and Z together),
      q_omega on w, q_rate on dw (trend-adaptive: q_lo + (q_hi - q_lo) min(1, (dw_lp/rate_ref)^2), dw_lp
      = dw low-passed over omega_rate_lp_tau_s),
      q_bias on A0, q_accel on dA0.

Around the core:
  * start-up / re-acquisition: a fixed bank of EKFs at several initial frequencies, scored by
    their innovation log-likelihood (exponential memory); after spec_init_s of walking a
    least-squares frequency grid search over a fixed ring buffer seeds the least likely member;
    after bank_window_s of walking the bank collapses to its best member.
  * walking / standing detector (low-passed speed and vertical RMS with hysteresis).  Standing:
    w, the phasors and R, r are frozen, only A0 (and its rate) keep tracking vx.  Walking
    resumes: the acquisition restarts, one member at the frozen frequency.
  * innovation gate (|nu| > gate_sigma sqrt(S) -> rejected-outlier), non-finite samples
    (rejected-nonfinite) are predicted over; actual dt everywhere; long gaps re-acquire.
  * watchdog: a frequency pinned at a bound for bound_watchdog_s restarts the acquisition.
  * changes of cadence: a persistent phase lag (least squares of the v_z innovations with the
    amplitude error) opens P_ww with its phase covariance (docs/default_estimator.md sec. 2.8).
  * uncertainty: std = sqrt(lambda P_ii), lambda = low-passed normalised innovation squared.

Per step in steady state: fixed 8-vector / 8x8 matrix arithmetic, 2 scalar updates, two 2-state
harmonic filters, one sin/cos pair.  No allocation (the Python lists/arrays here are fixed-size).
"""

import math

import numpy as np

# named state indices
IX1, IX2, IZ1, IZ2, IW, IA0, IDA, IDW = 0, 1, 2, 3, 4, 5, 6, 7
NX = 8

STATUS_OK = "ok"
STATUS_NONFINITE = "rejected-nonfinite"
STATUS_OUTLIER = "rejected-outlier"
STATUS_OUT_OF_RANGE = "rejected-out-of-range"

CH_VX, CH_VZ, CH_VX_STANDING = 0, 1, 2

TWO_PI = 2.0 * math.pi


class DefaultConfig:
    """All tuning in one place; units in the names.  Defaults are the tuned values."""

    def __init__(self, **kw):
        self.nominal_dt_s = 0.04  # used when no dt is given
        self.f_min_hz = 0.4  # step-frequency bounds (w is clamped into them)
        self.f_max_hz = 3.5
        # --- start-up / re-acquisition bank
        self.bank_f_hz = (0.9, 1.3, 1.8, 2.3, 2.8)
        self.bank_window_s = 1.5  # walking time before the bank collapses to its best member
        self.bank_forget_s = 1.5  # memory of the members' log-likelihood
        self.bank_prior_f_hz = 1.8  # typical step frequency: its member gets a log-prior bonus
        self.bank_prior_bonus = 2.0  # (nats; the hint member gets it on re-acquisition)
        self.bank_q_omega_rad2_per_s3 = 0.05  # step-frequency random walk of the bank's members
        self.p0_f_std_hz = 0.25  # initial frequency std of each member
        self.p0_phasor_std_mps = 0.3
        self.p0_bias_std_mps = 0.3
        self.p0_accel_std_mps2 = 0.5
        self.p0_omega_rate_std_rad_s2 = 0.05
        # --- spectral initialisation (start-up work only)
        self.spec_init = True
        self.spec_init_s = 1.0  # walking time of buffered data used
        self.spec_buffer_s = 1.6  # ring-buffer span (s): spec_buffer_n samples of nominal_dt_s
        self.spec_grid_step_hz = 0.025
        self.spec_p_f_std_hz = 0.08  # frequency std given to the seeded member
        self.spec_p_phasor_std_mps = 0.05
        # --- process noise densities (per second)
        self.q_phasor_mps2_per_s = 2e-3  # independent drift of each phasor
        self.q_phase_rad2_per_s = 0.05  # common gait-phase jitter (rotates X and Z together)
        self.q_omega_rad2_per_s3 = 0.05  # step-frequency random walk
        self.use_omega_rate = True  # frequency-rate state (tracks cadence ramps)
        self.q_omega_rate_lo_rad2_per_s5 = 0.01  # rate noise while no trend is seen ...
        self.q_omega_rate_rad2_per_s5 = 2.0  # ... and once |dw| reaches omega_rate_ref
        self.omega_rate_ref_rad_s2 = 0.2
        self.omega_rate_lp_tau_s = 1.5  # the trend test uses dw low-passed over this time (no feedback loop)
        self.omega_rate_tau_s = 3.0  # the frequency rate decays (first-order Gauss-Markov)
        self.q_bias_mps2_per_s = 1e-3  # forward-speed bias random walk
        self.q_accel_mps4_per_s = 1e-2  # random walk of the bias rate
        self.accel_tau_s = 1.0  # the bias rate decays (no runaway extrapolation)
        # --- second harmonic (cascaded 2-state KF per channel, on the channel's own phase)
        self.use_harmonic = True
        self.p0_harm_std_mps = 0.1
        self.q_harm_mps2_per_s = 1e-3
        self.harm_min_amp_mps = 0.02  # below this fundamental amplitude the basis is undefined
        # --- measurement noise densities ((m/s)^2 s): noise + what the model does not explain; a
        # sample is the mean over its interval, R = density / dt (dt = 0: nominal_dt_s)
        self.r_vx_density_m2_per_s = 1e-4
        self.r_vz_density_m2_per_s = 1e-4
        # --- innovation gate
        self.gate_sigma = 5.0
        self.max_consecutive_rejects_s = 0.24  # then the sample is accepted and P inflated (in samples: below)
        self.max_gap_s = 1.5  # a longer gap between samples restarts the acquisition
        # --- walking / standing detector
        self.walk_tau_s = 0.3
        self.walk_speed_on_mps = 0.2
        self.walk_speed_off_mps = 0.15
        self.walk_vz_rms_on_mps = 0.05
        self.walk_vz_rms_off_mps = 0.025
        # --- watchdog
        self.bound_watchdog_s = 1.0  # w pinned near a bound this long while walking -> re-acquire
        # --- cadence changes: the phase lag of the model, least squares of the v_z innovations with the
        # amplitude error over cadence_tau_s; beyond max(phase, sigma x its RMS) P_ww is raised to
        # (excess / horizon)^2 (with its phase covariance)
        self.cadence_adapt = True
        self.cadence_tau_s = 0.1
        self.cadence_phase_rad = 0.05
        self.cadence_sigma = 3.0
        self.cadence_noise_tau_s = 2.0  # the RMS: of the lags within the limit; no detection before this long
        self.cadence_horizon_s = 0.4
        self.cadence_max_std_hz = 0.15  # the opened frequency std at most (no jump to a harmonic)
        self.cadence_min_amp_mps = 0.05  # a sample counts only while |Z| exceeds this
        # --- reported uncertainty: sqrt(lambda P), lambda = low-passed NIS, clipped
        self.std_scale_adapt = True
        self.std_scale_tau_s = 10.0
        self.std_scale_min = 0.05
        self.std_scale_max = 4.0
        self.speed_std_floor_mps = 0.025  # stride-to-stride speed variability the model does not carry
        # --- a channel above this is not used, like a non-finite one
        self.max_abs_velocity_mps = 1000.0
        # --- R, r (m): low-passed while walking, frozen while standing
        self.param_tau_s = 2.0
        self.R0_m = 0.12  # reported before the first walk
        self.r0_m = 0.02
        for k, v in kw.items():
            if not hasattr(self, k):
                raise KeyError(k)
            setattr(self, k, v)

    # Durations in samples of nominal_dt_s, rounded half away from zero (EstimatorConfig::samples_in).
    @staticmethod
    def _samples(duration_s, dt_s):
        n = duration_s / dt_s
        return int(math.floor(n + 0.5)) if n >= 0.5 else 0

    @property
    def spec_buffer_n(self):
        return self._samples(self.spec_buffer_s, self.nominal_dt_s)

    @property
    def max_consecutive_rejects(self):
        return self._samples(self.max_consecutive_rejects_s, self.nominal_dt_s)


def _solve_spd(A, b):
    """Solve A x = b for a small symmetric positive-definite A (Cholesky, fixed size)."""
    n = len(b)
    L = [[0.0] * n for _ in range(n)]
    for i in range(n):
        for j in range(i + 1):
            s = A[i][j]
            for k in range(j):
                s -= L[i][k] * L[j][k]
            if i == j:
                L[i][i] = math.sqrt(s) if s > 1e-300 else 1e-150
            else:
                L[i][j] = s / L[j][j]
    y = [0.0] * n
    for i in range(n):
        s = b[i]
        for k in range(i):
            s -= L[i][k] * y[k]
        y[i] = s / L[i][i]
    x = [0.0] * n
    for i in range(n - 1, -1, -1):
        s = y[i]
        for k in range(i + 1, n):
            s -= L[k][i] * x[k]
        x[i] = s / L[i][i]
    return x


class _Ekf:
    """One dual-phasor EKF (fixed size)."""

    def __init__(self):
        self.x = np.zeros(NX)
        self.P = np.zeros((NX, NX))
        self.loglik = 0.0
        self.dw_lp = 0.0
        self.innov = {}  # channel (0: vx, 1: vz) -> (nu, S) of the last update, for the diagnostics

    def reset(self, cfg, f_hz, A0):
        self.x[:] = 0.0
        self.x[IW] = TWO_PI * f_hz
        self.x[IA0] = A0
        self.P[:, :] = 0.0
        sp = cfg.p0_phasor_std_mps**2
        self.P[IX1, IX1] = self.P[IX2, IX2] = self.P[IZ1, IZ1] = self.P[IZ2, IZ2] = sp
        self.P[IW, IW] = (TWO_PI * cfg.p0_f_std_hz) ** 2
        self.P[IA0, IA0] = cfg.p0_bias_std_mps**2
        self.P[IDA, IDA] = cfg.p0_accel_std_mps2**2
        self.P[IDW, IDW] = cfg.p0_omega_rate_std_rad_s2**2 if cfg.use_omega_rate else 0.0
        self.loglik = 0.0
        self.dw_lp = 0.0
        self.innov = {}

    def copy_from(self, o):
        self.x[:] = o.x
        self.P[:, :] = o.P
        self.loglik = o.loglik
        self.dw_lp = o.dw_lp
        self.innov = dict(o.innov)

    def predict(self, cfg, dt, oscillate=True, q_omega=None):
        """q_omega: the frequency random walk (the bank's members: bank_q_omega_rad2_per_s3)."""
        x, P = self.x, self.P
        da = math.exp(-dt / cfg.accel_tau_s)
        qb = cfg.q_bias_mps2_per_s * dt
        qa = cfg.q_accel_mps4_per_s * dt
        if not oscillate:
            # standing: oscillator frozen; only the bias and its rate evolve
            # P <- F P F^T with F = I + dt e_A0 e_dA^T + (da - 1) e_dA e_dA^T
            x[IA0] += dt * x[IDA]
            x[IDA] *= da
            for j in range(NX):
                P[IA0, j] += dt * P[IDA, j]
                P[IDA, j] *= da
            for i in range(NX):
                P[i, IA0] += dt * P[i, IDA]
                P[i, IDA] *= da
            P[IA0, IA0] += qb
            P[IDA, IDA] += qa
            return
        phi = x[IW] * dt
        c, s = math.cos(phi), math.sin(phi)
        X1 = c * x[IX1] - s * x[IX2]
        X2 = s * x[IX1] + c * x[IX2]
        Z1 = c * x[IZ1] - s * x[IZ2]
        Z2 = s * x[IZ1] + c * x[IZ2]
        x[IX1], x[IX2], x[IZ1], x[IZ2] = X1, X2, Z1, Z2
        db = math.exp(-dt / cfg.omega_rate_tau_s)
        x[IW] += dt * x[IDW]
        x[IDW] *= db
        x[IA0] += dt * x[IDA]
        x[IDA] *= da
        # Jacobian: two 2x2 rotations, d(rotated phasor)/dw = dt * J * phasor, two Gauss-Markov rates.
        F = np.eye(NX)
        F[IX1, IX1] = c
        F[IX1, IX2] = -s
        F[IX2, IX1] = s
        F[IX2, IX2] = c
        F[IZ1, IZ1] = c
        F[IZ1, IZ2] = -s
        F[IZ2, IZ1] = s
        F[IZ2, IZ2] = c
        F[IX1, IW] = -dt * X2
        F[IX2, IW] = dt * X1
        F[IZ1, IW] = -dt * Z2
        F[IZ2, IW] = dt * Z1
        F[IW, IDW] = dt
        F[IDW, IDW] = db
        F[IA0, IDA] = dt
        F[IDA, IDA] = da
        P[:, :] = F @ P @ F.T
        # independent phasor drift
        qp = cfg.q_phasor_mps2_per_s * dt
        P[IX1, IX1] += qp
        P[IX2, IX2] += qp
        P[IZ1, IZ1] += qp
        P[IZ2, IZ2] += qp
        # common gait-phase jitter: q_phase * g g^T, g = d(state)/d(phase) = [-X2, X1, -Z2, Z1, 0, ...]
        qt = cfg.q_phase_rad2_per_s * dt
        g = (-X2, X1, -Z2, Z1)
        for i in range(4):
            for j in range(4):
                P[i, j] += qt * g[i] * g[j]
        P[IW, IW] += (cfg.q_omega_rad2_per_s3 if q_omega is None else q_omega) * dt
        if cfg.use_omega_rate:
            if cfg.omega_rate_lp_tau_s > 0.0:
                self.dw_lp += (1.0 - math.exp(-dt / cfg.omega_rate_lp_tau_s)) * (x[IDW] - self.dw_lp)
            else:
                self.dw_lp = x[IDW]
            rr = self.dw_lp / cfg.omega_rate_ref_rad_s2
            rr = min(rr * rr, 1.0)
            qlo = cfg.q_omega_rate_lo_rad2_per_s5
            P[IDW, IDW] += (qlo + (cfg.q_omega_rate_rad2_per_s5 - qlo) * rr) * dt
        P[IA0, IA0] += qb
        P[IDA, IDA] += qa

    # --- the covariance guard (docs/default_estimator.md, sec. 2.7), written independently

    def bound_variances(self, cfg):
        """Popoviciu: phasors within +-v_max, A0 within [0, v_max], w within [w_min, w_max]; a row and
        column beyond its bound are scaled to it (correlations kept); not finite: the initial P."""
        P = self.P
        if not np.all(np.isfinite(P)):
            self.reset_covariance(cfg)
            return
        v2 = cfg.max_abs_velocity_mps**2
        half_w = 0.5 * TWO_PI * (cfg.f_max_hz - cfg.f_min_hz)
        bound = np.array([v2, v2, v2, v2, half_w**2, 0.25 * v2, np.inf, np.inf])
        d = np.where(np.diag(P) > bound, np.sqrt(bound / np.diag(P)), 1.0)
        if np.any(d != 1.0):
            P[:, :] = P * np.outer(d, d)

    def guard(self, cfg):
        """After the updates: variances within their bounds, and P positive semi-definite with exact
        zeros only (Cholesky of the rows that are not all zero), else the nearest matrix with
        eigenvalues >= 1e-12 of the largest."""
        self.bound_variances(cfg)
        P = self.P
        live = np.any(P != 0.0, axis=1)
        try:
            np.linalg.cholesky(P[np.ix_(live, live)])
            if np.all(np.isfinite(P)):
                return
        except np.linalg.LinAlgError:
            pass
        if not np.all(np.isfinite(P)):
            self.reset_covariance(cfg)
            return
        lam, vec = np.linalg.eigh(P)
        if not lam[-1] > 0:
            self.reset_covariance(cfg)
            return
        lam = np.maximum(lam, 1e-12 * lam[-1])
        out = (vec * lam) @ vec.T
        P[:, :] = 0.5 * (out + out.T)

    def reset_covariance(self, cfg):
        P = self.P
        P[:, :] = 0.0
        sp = cfg.p0_phasor_std_mps**2
        P[IX1, IX1] = P[IX2, IX2] = P[IZ1, IZ1] = P[IZ2, IZ2] = sp
        P[IW, IW] = (TWO_PI * cfg.p0_f_std_hz) ** 2
        P[IA0, IA0] = cfg.p0_bias_std_mps**2
        P[IDA, IDA] = cfg.p0_accel_std_mps2**2
        P[IDW, IDW] = cfg.p0_omega_rate_std_rad_s2**2 if cfg.use_omega_rate else 0.0

    def innovation(self, ch, y, r):
        """(nu, S) of a scalar measurement: CH_VX: vx = A0 + X1, CH_VZ: vz = Z1, CH_VX_STANDING: vx = A0."""
        x, P = self.x, self.P
        if ch == CH_VX:
            return y - (x[IA0] + x[IX1]), P[IX1, IX1] + 2.0 * P[IX1, IA0] + P[IA0, IA0] + r
        if ch == CH_VZ:
            return y - x[IZ1], P[IZ1, IZ1] + r
        return y - x[IA0], P[IA0, IA0] + r

    def update(self, ch, nu, S):
        P = self.P
        if ch == CH_VX:
            PHt = P[:, IX1] + P[:, IA0]
        elif ch == CH_VZ:
            PHt = P[:, IZ1].copy()
        else:
            PHt = P[:, IA0].copy()
        K = PHt / S
        self.x += K * nu
        P -= np.outer(K, PHt)
        P[:, :] = 0.5 * (P + P.T)
        self.loglik += -0.5 * (nu * nu / S + math.log(S))

    def clamp(self, cfg):
        """Projection onto the physical set: w in [w_min, w_max], speed A0 >= 0."""
        x = self.x
        if x[IA0] < 0.0:
            x[IA0] = 0.0
            if x[IDA] < 0.0:
                x[IDA] = 0.0
        wmin, wmax = TWO_PI * cfg.f_min_hz, TWO_PI * cfg.f_max_hz
        if x[IW] < wmin:
            x[IW] = wmin
            if x[IDW] < 0.0:
                x[IDW] = 0.0
        elif x[IW] > wmax:
            x[IW] = wmax
            if x[IDW] > 0.0:
                x[IDW] = 0.0


class _Harmonic:
    """Second harmonic of one channel: h = c0 cos(2 th) + c1 sin(2 th), th = angle of the channel's
    fundamental phasor; (c0, c1) by a 2-state Kalman filter (random walk)."""

    def __init__(self):
        self.c = [0.0, 0.0]
        self.P = [[0.0, 0.0], [0.0, 0.0]]

    def reset(self, cfg):
        self.c[0] = self.c[1] = 0.0
        self.P[0][0] = self.P[1][1] = cfg.p0_harm_std_mps**2
        self.P[0][1] = self.P[1][0] = 0.0

    def copy_from(self, o):
        self.c[0], self.c[1] = o.c[0], o.c[1]
        for i in range(2):
            for j in range(2):
                self.P[i][j] = o.P[i][j]

    @staticmethod
    def basis(p1, p2, cfg):
        """(cos 2th, sin 2th) of the phasor (p1, p2) by the double-angle formulas; (0, 0) if too small."""
        a2 = p1 * p1 + p2 * p2
        if a2 < cfg.harm_min_amp_mps**2:
            return 0.0, 0.0
        return (p1 * p1 - p2 * p2) / a2, 2.0 * p1 * p2 / a2

    def value(self, u, v):
        return self.c[0] * u + self.c[1] * v

    def predict(self, cfg, dt):
        q = cfg.q_harm_mps2_per_s * dt
        self.P[0][0] += q
        self.P[1][1] += q

    def update(self, u, v, e, r):
        if u == 0.0 and v == 0.0:
            return
        P = self.P
        ph0 = P[0][0] * u + P[0][1] * v
        ph1 = P[1][0] * u + P[1][1] * v
        S = u * ph0 + v * ph1 + r
        k0, k1 = ph0 / S, ph1 / S
        self.c[0] += k0 * e
        self.c[1] += k1 * e
        P[0][0] -= k0 * ph0
        P[0][1] -= k0 * ph1
        P[1][0] -= k1 * ph0
        P[1][1] -= k1 * ph1


class DefaultEstimator:
    """Streaming estimator: out = est.step(vx_mps, vz_mps, dt_s); est.predict(h_s) -> (vx, vz)."""

    def __init__(self, cfg=None):
        self.cfg = cfg or DefaultConfig()
        c = self.cfg
        self.nbank = len(c.bank_f_hz)
        self.bank = [_Ekf() for _ in range(self.nbank)]
        self.bank_h = [[_Harmonic(), _Harmonic()] for _ in range(self.nbank)]
        self.main = _Ekf()
        self.main_h = [_Harmonic(), _Harmonic()]
        self.started = False
        self.acquiring = True
        self.acq_walk_time_s = 0.0
        self.best = 0
        self.walking = False
        self.ema_vx = 0.0
        self.ema_vz2 = 0.0
        self.R_m = c.R0_m
        self.r_m = c.r0_m
        self.have_params = False
        self.last_w = TWO_PI * 1.8
        self.n_rejects = 0
        self.t_at_bound = 0.0
        self.lag_sums = np.zeros(5)  # low-passed Z1^2, Z1 Z2, Z2^2, Z1 nu_z, Z2 nu_z (prior Z)
        self.lag_noise2 = 0.0  # mean square of the lag while within the limit (from the floor at each acquisition)
        self.lag_learn_s = 0.0  # walking time of the one EKF since the acquisition
        self.lag_beyond_s = 0.0  # how long the lag has been beyond the limit
        self.lam = 1.0
        self.t_now = 0.0
        self.updated = False  # the last step ran the updates (diagnostics)
        # fixed ring buffer for the spectral initialisation
        nb = c.spec_buffer_n
        self.buf_t = [0.0] * nb
        self.buf_x = [0.0] * nb
        self.buf_z = [0.0] * nb
        self.buf_n = 0
        self.buf_head = 0
        self.spec_done = False
        # defined outputs (w > 0) even before the first finite sample
        self._start_acquisition(0.0)
        self._collapse()
        self.acquiring = True

    # ------------------------------------------------------------------ internals
    def _active(self):
        return self.bank[self.best] if self.acquiring else self.main

    def _active_h(self):
        return self.bank_h[self.best] if self.acquiring else self.main_h

    def _harm_basis(self, f, ch):
        # the bank compares fundamentals only: a harmonic model would let a half-frequency member
        # explain the step oscillation with its harmonic (sub-harmonic lock)
        if not self.cfg.use_harmonic or self.acquiring:
            return 0.0, 0.0
        if ch == CH_VX:
            return _Harmonic.basis(f.x[IX1], f.x[IX2], self.cfg)
        return _Harmonic.basis(f.x[IZ1], f.x[IZ2], self.cfg)

    def _start_acquisition(self, A0, f_hint_hz=None):
        c = self.cfg
        for i in range(self.nbank):
            self.bank[i].reset(c, c.bank_f_hz[i], A0)
            self.bank_h[i][0].reset(c)
            self.bank_h[i][1].reset(c)
        # log-prior: the member nearest to the hint (re-acquisition) or to the typical step frequency
        # starts ahead; the hint member starts exactly at the hint
        f_pri = f_hint_hz if f_hint_hz is not None else c.bank_prior_f_hz
        j = min(range(self.nbank), key=lambda i: abs(c.bank_f_hz[i] - f_pri))
        if f_hint_hz is not None:
            self.bank[j].reset(c, f_hint_hz, A0)
        self.bank[j].loglik = c.bank_prior_bonus
        self.best = j
        self.acquiring = True
        self.acq_walk_time_s = 0.0
        self.buf_n = 0
        self.buf_head = 0
        self.spec_done = False
        self.t_at_bound = 0.0
        self.lag_sums[:] = 0.0
        self.lag_noise2 = c.cadence_phase_rad**2
        self.lag_learn_s = self.lag_beyond_s = 0.0

    def _cadence_change(self, before, dt):
        """The phase lag d of the model: nu_z = rho Z1 - d Z2 (rho the relative amplitude error; prior
        Z), least squares over cadence_tau_s (low-passed sums). Beyond max(phase, sigma x RMS) (the RMS
        of the lags within that limit, learnt for cadence_noise_tau_s after each acquisition before any
        test) P gets add v v^T, v = e_w + tau (-X2, X1, -Z2, Z1) (what a frequency error over the last
        tau would have built), add = min((|d| - limit) / horizon, 2 pi max_std)^2 - P_ww, reduced so
        that no variance takes more than half the room below its bound."""
        c, m = self.cfg, self.main
        # evidence: a sample with both channels and a vertical oscillation; another changes nothing
        if CH_VX not in m.innov or CH_VZ not in m.innov:
            return
        nu = m.innov[CH_VZ][0]
        z1, z2 = before[2], before[3]
        if z1 * z1 + z2 * z2 <= c.cadence_min_amp_mps**2:
            return
        if dt > 0.0:
            a = 1.0 - math.exp(-dt / c.cadence_tau_s)
            self.lag_sums += a * (np.array([z1 * z1, z1 * z2, z2 * z2, z1 * nu, z2 * nu]) - self.lag_sums)
        s11, s12, s22, s1n, s2n = self.lag_sums
        det = s11 * s22 - s12 * s12
        learning = self.lag_learn_s < c.cadence_noise_tau_s
        self.lag_learn_s += dt
        if not det > 1e-3 * s11 * s22:  # too little phase diversity to tell phase from amplitude
            return
        lag = (s12 * s1n - s11 * s2n) / det
        limit = max(c.cadence_phase_rad, c.cadence_sigma * math.sqrt(self.lag_noise2))
        if learning or abs(lag) <= limit:
            if dt > 0.0:
                b = 1.0 - math.exp(-dt / c.cadence_noise_tau_s)
                self.lag_noise2 += b * (lag * lag - self.lag_noise2)
            self.lag_beyond_s = 0.0
            return
        self.lag_beyond_s += dt
        if self.lag_beyond_s < c.cadence_tau_s:  # the lag must persist for tau: one corrupt sample is not enough
            return
        excess = min((abs(lag) - limit) / c.cadence_horizon_s, TWO_PI * c.cadence_max_std_hz)
        add = max(excess * excess - m.P[IW, IW], 0.0)
        if add <= 0.0:
            return
        after = m.x
        v = np.zeros(NX)
        v[IX1], v[IX2], v[IZ1], v[IZ2] = -after[IX2], after[IX1], -after[IZ2], after[IZ1]
        v *= c.cadence_tau_s
        v[IW] = 1.0
        # no variance takes more than half the room left below its bound (the covariance guard's, sec. 2.7)
        vmax2 = c.max_abs_velocity_mps**2
        half = 0.5 * TWO_PI * (c.f_max_hz - c.f_min_hz)
        bounds = (vmax2, vmax2, vmax2, vmax2, half * half)
        for i in range(5):
            if v[i] * v[i] > 0.0:
                add = min(add, 0.5 * (bounds[i] - m.P[i, i]) / (v[i] * v[i]))
        if add > 0.0:
            m.P += add * np.outer(v, v)

    def _collapse(self):
        self.main.copy_from(self.bank[self.best])
        self.main_h[0].copy_from(self.bank_h[self.best][0])
        self.main_h[1].copy_from(self.bank_h[self.best][1])
        self.acquiring = False

    def _buffer_push(self, t, vx, vz):
        nb = self.cfg.spec_buffer_n
        self.buf_t[self.buf_head] = t
        self.buf_x[self.buf_head] = vx
        self.buf_z[self.buf_head] = vz
        self.buf_head = (self.buf_head + 1) % nb
        if self.buf_n < nb:
            self.buf_n += 1

    def _ls_cost(self, w, n, i0, t_last, rx, rz, sol):
        """Weighted residual of two linear least-squares fits at angular frequency w:
        vx(tau) = a + b tau + Xc cos(w tau) + Xs sin(w tau), vz(tau) = c + Zc cos(w tau) + Zs sin(w tau)."""
        nb = self.cfg.spec_buffer_n
        A = [[0.0] * 4 for _ in range(4)]  # normal matrix on [1, tau, cos, sin]
        bx = [0.0] * 4
        bz = [0.0] * 3
        yy_x = yy_z = 0.0
        for q in range(n):
            i = (i0 + q) % nb
            tau = self.buf_t[i] - t_last
            cs, sn = math.cos(w * tau), math.sin(w * tau)
            phi = (1.0, tau, cs, sn)
            for a in range(4):
                for b in range(a, 4):
                    A[a][b] += phi[a] * phi[b]
                bx[a] += phi[a] * self.buf_x[i]
            bz[0] += self.buf_z[i]
            bz[1] += cs * self.buf_z[i]
            bz[2] += sn * self.buf_z[i]
            yy_x += self.buf_x[i] * self.buf_x[i]
            yy_z += self.buf_z[i] * self.buf_z[i]
        for a in range(4):
            for b in range(a):
                A[a][b] = A[b][a]
        ridge = 1e-9
        ax = _solve_spd([[A[a][b] + (ridge if a == b else 0.0) for b in range(4)] for a in range(4)], bx)
        az = _solve_spd(
            [
                [A[0][0] + ridge, A[0][2], A[0][3]],
                [A[2][0], A[2][2] + ridge, A[2][3]],
                [A[3][0], A[3][2], A[3][3] + ridge],
            ],
            bz,
        )
        rss_x = yy_x - (bx[0] * ax[0] + bx[1] * ax[1] + bx[2] * ax[2] + bx[3] * ax[3])
        rss_z = yy_z - (bz[0] * az[0] + bz[1] * az[1] + bz[2] * az[2])
        if sol is not None:
            sol[0], sol[1], sol[2], sol[3] = ax[0], ax[1], ax[2], ax[3]
            sol[4], sol[5], sol[6] = az[0], az[1], az[2]
        return rss_x / rx + rss_z / rz

    def _spectral_seed(self):
        """Grid search of the least-squares cost over [f_min, f_max] on the buffered window,
        parabolic refinement, then the fit seeds the least likely bank member (phasors at the last
        sample: X = (Xc, -Xs), Z = (Zc, -Zs)).  Start-up work only: fixed-size loops, no allocation."""
        c = self.cfg
        n = self.buf_n
        if n < 10:
            return
        nb = c.spec_buffer_n
        t_last = self.buf_t[(self.buf_head - 1) % nb]
        i0 = (self.buf_head - n) % nb
        rx, rz = c.r_vx_density_m2_per_s / c.nominal_dt_s, c.r_vz_density_m2_per_s / c.nominal_dt_s
        nf = int((c.f_max_hz - c.f_min_hz) / c.spec_grid_step_hz) + 1
        costs = [0.0] * nf  # fixed size in C++
        best_k = 0
        for k in range(nf):
            costs[k] = self._ls_cost(TWO_PI * (c.f_min_hz + k * c.spec_grid_step_hz), n, i0, t_last, rx, rz, None)
            if costs[k] < costs[best_k]:
                best_k = k
        f_best = c.f_min_hz + best_k * c.spec_grid_step_hz
        if 0 < best_k < nf - 1:
            y0, y1, y2 = costs[best_k - 1], costs[best_k], costs[best_k + 1]
            den = y0 - 2.0 * y1 + y2
            if den > 0.0:
                f_best += max(-0.5, min(0.5, 0.5 * (y0 - y2) / den)) * c.spec_grid_step_hz
        sol = [0.0] * 7
        self._ls_cost(TWO_PI * f_best, n, i0, t_last, rx, rz, sol)
        j = min(range(self.nbank), key=lambda i: self.bank[i].loglik)
        jb = max(range(self.nbank), key=lambda i: self.bank[i].loglik)
        m = self.bank[j]
        m.reset(c, f_best, max(sol[0], 0.0))
        m.x[IDA] = sol[1]
        m.x[IX1], m.x[IX2] = sol[2], -sol[3]
        m.x[IZ1], m.x[IZ2] = sol[5], -sol[6]
        sp = c.spec_p_phasor_std_mps**2
        m.P[IX1, IX1] = m.P[IX2, IX2] = m.P[IZ1, IZ1] = m.P[IZ2, IZ2] = sp
        m.P[IA0, IA0] = sp
        m.P[IW, IW] = (TWO_PI * c.spec_p_f_std_hz) ** 2
        m.loglik = self.bank[jb].loglik
        self.bank_h[j][0].reset(c)
        self.bank_h[j][1].reset(c)

    def _update_walking(self, vx, vz, fin_x, fin_z, dt):
        c = self.cfg
        a = 1.0 - math.exp(-dt / c.walk_tau_s) if dt > 0.0 else 0.0
        if fin_x:
            self.ema_vx += a * (vx - self.ema_vx)
        if fin_z:
            self.ema_vz2 += a * (vz * vz - self.ema_vz2)
        vz_rms = math.sqrt(max(self.ema_vz2, 0.0))
        if self.walking:
            if self.ema_vx < c.walk_speed_off_mps and vz_rms < c.walk_vz_rms_off_mps:
                self.walking = False
        elif self.ema_vx > c.walk_speed_on_mps or vz_rms > c.walk_vz_rms_on_mps:
            self.walking = True

    # ------------------------------------------------------------------ API
    def step(self, vx, vz, dt_s=None):
        """One sample: forward speed vx (m/s, >= 0), vertical velocity vz (m/s), dt_s = time since the
        previous sample (s; None -> nominal).  Returns a dict of estimates and a status."""
        c = self.cfg
        fin_x = vx is not None and math.isfinite(vx)
        fin_z = vz is not None and math.isfinite(vz)
        # usable channels; one status per sample: non-finite beats out-of-range beats outlier
        use_x = fin_x and abs(vx) <= c.max_abs_velocity_mps
        use_z = fin_z and abs(vz) <= c.max_abs_velocity_mps
        status = STATUS_NONFINITE if not (fin_x and fin_z) else STATUS_OK if (use_x and use_z) else STATUS_OUT_OF_RANGE
        if dt_s is None:
            dt = c.nominal_dt_s
        elif not math.isfinite(dt_s) or dt_s < 0.0:
            self.updated = False
            return self._output(STATUS_NONFINITE)  # unusable timestamp: sample ignored
        else:
            dt = dt_s
        if not self.started:
            if not use_x:
                self.updated = False
                return self._output(status)
            self.started = True
            self.ema_vx = vx
            self.ema_vz2 = vz * vz if use_z else 0.0
            self._start_acquisition(vx)
            self._collapse()  # main filter defined from the start
            self.acquiring = True
            dt = 0.0
        self.t_now += dt
        dt_walk = dt
        if dt > c.max_gap_s:
            # long gap: keep the speed, restart the acquisition around the last frequency; the fresh
            # members are not propagated over the gap
            self._start_acquisition(self._active().x[IA0], self.last_w / TWO_PI if self.have_params else None)
            dt = 0.0
        was_walking = self.walking
        self._update_walking(vx, vz, use_x, use_z, dt_walk)
        if self.walking and not was_walking:
            # walking (re)starts: re-open the acquisition (frequency covariance re-opened, bias
            # from this sample, one member at the frozen frequency)
            self._start_acquisition(
                vx if use_x else self._active().x[IA0], self.last_w / TWO_PI if self.have_params else None
            )
        if was_walking and not self.walking:
            # stop: freeze the oscillator, drop the oscillation, decouple the bias (the bank collapses
            # first if it was running; otherwise the main filter goes on: the bank holds stale members)
            if self.acquiring:
                self._collapse()
            m = self.main
            for i in (IX1, IX2, IZ1, IZ2, IDW):
                m.x[i] = 0.0
            for i in range(NX):
                if i != IA0 and i != IDA:
                    m.P[i, IA0] = m.P[IA0, i] = m.P[i, IDA] = m.P[IDA, i] = 0.0

        osc = self.walking
        filters = self.bank if self.acquiring else [self.main]
        filters_h = self.bank_h if self.acquiring else [self.main_h]
        q_omega = c.bank_q_omega_rad2_per_s3 if self.acquiring else c.q_omega_rad2_per_s3
        for f in filters:
            f.predict(c, dt, oscillate=osc, q_omega=q_omega)
        track_cadence = osc and not self.acquiring and c.cadence_adapt
        if track_cadence:
            phasors_before = self.main.x[:4].copy()
        if osc:
            for fh in filters_h:
                fh[0].predict(c, dt)
                fh[1].predict(c, dt)

        dt_r = dt if dt > 0.0 else c.nominal_dt_s
        rx, rz = c.r_vx_density_m2_per_s / dt_r, c.r_vz_density_m2_per_s / dt_r
        chans = []
        if osc:
            if use_x:
                chans.append((CH_VX, vx, rx))
            if use_z:
                chans.append((CH_VZ, vz, rz))
        elif use_x:
            chans.append((CH_VX_STANDING, vx, rx))
        gate2 = c.gate_sigma * c.gate_sigma
        a_l = 0.5 * (1.0 - math.exp(-dt / c.std_scale_tau_s)) if dt > 0.0 else 0.0
        rejected = False
        self.updated = True
        for f, fh in zip(filters, filters_h):
            f.innov = {}
            for ch, y, r in chans:
                # the channel's second harmonic (from the predicted phasor) is cancelled first
                u = v = 0.0
                if ch != CH_VX_STANDING:
                    u, v = self._harm_basis(f, ch)
                yh = fh[ch].value(u, v) if ch != CH_VX_STANDING else 0.0
                nu, S = f.innovation(ch, y - yh, r)
                f.innov[CH_VZ if ch == CH_VZ else CH_VX] = (nu, S)
                if (not self.acquiring) and nu * nu > gate2 * S and self.n_rejects < c.max_consecutive_rejects:
                    rejected = True
                    continue
                f.update(ch, nu, S)
                if c.std_scale_adapt and ch != CH_VX_STANDING and not self.acquiring:
                    lam = self.lam + a_l * (nu * nu / S - self.lam)
                    self.lam = min(max(lam, c.std_scale_min), c.std_scale_max)
                if u != 0.0 or v != 0.0:
                    # harmonic coefficients learn from the residual left by the updated fundamental
                    e, _ = f.innovation(ch, y - yh, r)
                    fh[ch].update(u, v, e, r)
            f.clamp(c)
            f.guard(c)
        if track_cadence and not rejected:
            self._cadence_change(phasors_before, dt)
        if rejected:
            self.n_rejects += 1
            if status == STATUS_OK:
                status = STATUS_OUTLIER
        else:
            if self.n_rejects >= c.max_consecutive_rejects:
                # persistent disagreement was accepted: inflate P so the filter follows again (up to
                # the variance bounds of the covariance guard)
                m = self.main
                v2 = c.max_abs_velocity_mps**2
                for i in (IX1, IX2, IZ1, IZ2):
                    m.P[i, i] += max(min(c.p0_phasor_std_mps**2, v2 - m.P[i, i]), 0.0)
                m.P[IA0, IA0] += max(min(c.p0_bias_std_mps**2, 0.25 * v2 - m.P[IA0, IA0]), 0.0)
            self.n_rejects = 0

        if self.acquiring:
            lam = math.exp(-dt / c.bank_forget_s)
            for f in self.bank:
                f.loglik *= lam
            if self.walking:
                self.acq_walk_time_s += dt
                if use_x and use_z:
                    self._buffer_push(self.t_now, vx, vz)
                if c.spec_init and not self.spec_done and self.acq_walk_time_s >= c.spec_init_s:
                    self.spec_done = True
                    self._spectral_seed()
            self.best = max(range(self.nbank), key=lambda i: self.bank[i].loglik)
            if self.acq_walk_time_s >= c.bank_window_s:
                self._collapse()

        act = self._active()
        if self.walking and not self.acquiring:
            # watchdog: a frequency pinned at a bound is a failed lock -> re-acquire
            wmin, wmax = TWO_PI * c.f_min_hz, TWO_PI * c.f_max_hz
            if act.x[IW] <= 1.05 * wmin or act.x[IW] >= 0.95 * wmax:
                self.t_at_bound += dt
            elif 1.15 * wmin < act.x[IW] < 0.85 * wmax:
                self.t_at_bound = self.t_at_bound - dt if self.t_at_bound > dt else 0.0
            if self.t_at_bound > c.bound_watchdog_s:
                self._start_acquisition(act.x[IA0])
                act = self._active()
        if self.walking:
            self.last_w = act.x[IW]
            Rn = act.x[IA0] / act.x[IW]
            rn = math.hypot(act.x[IZ1], act.x[IZ2]) / act.x[IW]
            if not self.have_params:
                self.R_m, self.r_m = Rn, rn
                self.have_params = True
            else:
                b = 1.0 - math.exp(-dt / c.param_tau_s)
                self.R_m += b * (Rn - self.R_m)
                self.r_m += b * (rn - self.r_m)
        return self._output(status)

    def _output(self, status):
        f = self._active()
        fh = self._active_h()
        x, P = f.x, f.P
        w = x[IW]
        if self.walking:
            vx_hat_mps = x[IA0] + x[IX1]  # model reconstruction: R w + phase-shifted oscillation
            vz_hat_mps = x[IZ1]
            ux, vx2 = self._harm_basis(f, CH_VX)
            uz, vz2 = self._harm_basis(f, CH_VZ)
            vx_h2 = vx_hat_mps + fh[0].value(ux, vx2)
            vz_h2 = vz_hat_mps + fh[1].value(uz, vz2)
        else:
            vx_hat_mps = vx_h2 = x[IA0]
            vz_hat_mps = vz_h2 = 0.0
        ax = math.hypot(x[IX1], x[IX2])
        az = math.hypot(x[IZ1], x[IZ2])
        # phase of the forward oscillation relative to the vertical one, (-pi, pi]: the Yoyo model
        # (eq. 3-4) has -pi/2 in this convention, real walking about +pi/2
        rel = math.atan2(x[IX2] * x[IZ1] - x[IX1] * x[IZ2], x[IX1] * x[IZ1] + x[IX2] * x[IZ2])
        # signed forward amplitude: projection of X on the Yoyo direction (Z rotated by -pi/2);
        # positive = Yoyo relation, negative = the opposite (real walking)
        signed = (x[IX1] * x[IZ2] - x[IX2] * x[IZ1]) / az if az > 1e-9 else 0.0
        lam = self.lam
        innov = f.innov if self.updated else {}
        nan = float("nan")
        nis = sum(nu * nu / S for nu, S in innov.values()) if innov else nan
        return dict(
            innovation_vx_mps=innov.get(CH_VX, (nan, nan))[0],
            innovation_vz_mps=innov.get(CH_VZ, (nan, nan))[0],
            nis=nis,
            status=status,
            walking=self.walking,
            acquiring=self.acquiring,
            omega_rad_s=w,
            step_frequency_hz=w / TWO_PI,
            step_frequency_std_hz=math.sqrt(max(lam * P[IW, IW], 0.0)) / TWO_PI,
            omega_rate_rad_s2=x[IDW],
            A0=x[IA0],
            speed_mps=x[IA0],
            speed_std_mps=math.sqrt(max(lam * P[IA0, IA0], 0.0) + self.cfg.speed_std_floor_mps**2),
            accel_mps2=x[IDA],
            amp_x_mps=ax,
            amp_z_mps=az,
            phase_x_rel_z_rad=rel,
            signed_amp_x_mps=signed,
            vx_hat_mps=vx_hat_mps,
            vz_hat_mps=vz_hat_mps,
            vx_hat_h2_mps=vx_h2,
            vz_hat_h2_mps=vz_h2,
            R_m=self.R_m,
            r_m=self.r_m,
            std_scale=lam,
        )

    def predict(self, h_s, harmonics=True):
        """(vx, vz) h_s seconds ahead: phasors rotated by w h + dw h^2 / 2, bias held (extrapolating it
        with its rate was measured to be slightly worse at 0.2 s), second harmonics included unless
        harmonics=False.  Standing: (A0, 0)."""
        c = self.cfg
        f = self._active()
        x = f.x
        A0 = x[IA0]
        if not self.walking:
            return A0, 0.0
        phi = x[IW] * h_s + 0.5 * x[IDW] * h_s * h_s
        cs, sn = math.cos(phi), math.sin(phi)
        X1, X2 = cs * x[IX1] - sn * x[IX2], sn * x[IX1] + cs * x[IX2]
        Z1, Z2 = cs * x[IZ1] - sn * x[IZ2], sn * x[IZ1] + cs * x[IZ2]
        vx, vz = A0 + X1, Z1
        if harmonics and c.use_harmonic and not self.acquiring:
            fh = self._active_h()
            ux, vx2 = _Harmonic.basis(X1, X2, c)
            uz, vz2 = _Harmonic.basis(Z1, Z2, c)
            vx += fh[0].value(ux, vx2)
            vz += fh[1].value(uz, vz2)
        return vx, vz


# Names of the native yoyogait.EstimatorConfig for the fields of DefaultConfig.
_NATIVE_NAMES = {
    "nominal_dt_s": "sample_time_s",
    "f_min_hz": "f_min_hz",
    "f_max_hz": "f_max_hz",
    "bank_f_hz": "bank_f_hz",
    "bank_window_s": "bank_window_s",
    "bank_forget_s": "bank_forget_s",
    "bank_prior_f_hz": "bank_prior_f_hz",
    "bank_prior_bonus": "bank_prior_bonus_nats",
    "bank_q_omega_rad2_per_s3": "bank_q_omega_rad2_per_s3",
    "p0_f_std_hz": "p0_f_std_hz",
    "p0_phasor_std_mps": "p0_phasor_std_mps",
    "p0_bias_std_mps": "p0_speed_std_mps",
    "p0_accel_std_mps2": "p0_accel_std_mps2",
    "p0_omega_rate_std_rad_s2": "p0_omega_rate_std_rad_s2",
    "spec_init": "spectral_init",
    "spec_init_s": "spectral_init_s",
    "spec_buffer_s": "spectral_buffer_s",
    "spec_grid_step_hz": "spectral_grid_step_hz",
    "spec_p_f_std_hz": "spectral_f_std_hz",
    "spec_p_phasor_std_mps": "spectral_phasor_std_mps",
    "q_phasor_mps2_per_s": "q_phasor_m2_per_s3",
    "q_phase_rad2_per_s": "q_phase_rad2_per_s",
    "q_omega_rad2_per_s3": "q_omega_rad2_per_s3",
    "use_omega_rate": "use_omega_rate",
    "q_omega_rate_lo_rad2_per_s5": "q_omega_rate_lo_rad2_per_s5",
    "q_omega_rate_rad2_per_s5": "q_omega_rate_hi_rad2_per_s5",
    "omega_rate_ref_rad_s2": "omega_rate_ref_rad_s2",
    "omega_rate_lp_tau_s": "omega_rate_lp_tau_s",
    "omega_rate_tau_s": "omega_rate_tau_s",
    "q_bias_mps2_per_s": "q_speed_m2_per_s3",
    "q_accel_mps4_per_s": "q_accel_m2_per_s5",
    "accel_tau_s": "accel_tau_s",
    "use_harmonic": "use_harmonic",
    "p0_harm_std_mps": "p0_harmonic_std_mps",
    "q_harm_mps2_per_s": "q_harmonic_m2_per_s3",
    "harm_min_amp_mps": "harmonic_min_amp_mps",
    "r_vx_density_m2_per_s": "meas_vx_density_m2_per_s",
    "r_vz_density_m2_per_s": "meas_vz_density_m2_per_s",
    "gate_sigma": "gate_sigma",
    "max_consecutive_rejects_s": "gate_max_consecutive_s",
    "max_gap_s": "max_gap_s",
    "walk_tau_s": "walk_tau_s",
    "walk_speed_on_mps": "walk_speed_on_mps",
    "walk_speed_off_mps": "walk_speed_off_mps",
    "walk_vz_rms_on_mps": "walk_vz_rms_on_mps",
    "walk_vz_rms_off_mps": "walk_vz_rms_off_mps",
    "bound_watchdog_s": "bound_watchdog_s",
    "cadence_adapt": "cadence_change_adapt",
    "cadence_tau_s": "cadence_change_tau_s",
    "cadence_phase_rad": "cadence_change_phase_rad",
    "cadence_sigma": "cadence_change_sigma",
    "cadence_noise_tau_s": "cadence_change_noise_tau_s",
    "cadence_horizon_s": "cadence_change_horizon_s",
    "cadence_max_std_hz": "cadence_change_max_std_hz",
    "cadence_min_amp_mps": "cadence_change_min_amp_mps",
    "std_scale_adapt": "std_scale_adapt",
    "std_scale_tau_s": "std_scale_tau_s",
    "std_scale_min": "std_scale_min",
    "std_scale_max": "std_scale_max",
    "speed_std_floor_mps": "speed_std_floor_mps",
    "max_abs_velocity_mps": "max_abs_velocity_mps",
    "param_tau_s": "radii_tau_s",
    "R0_m": "initial_R_m",
    "r0_m": "initial_r_m",
}


def config_from(native_cfg) -> DefaultConfig:
    """The DefaultConfig with the values of a yoyogait.EstimatorConfig (or its native struct)."""
    section = native_cfg.gait_filter
    values = {
        ours: getattr(section, theirs) if hasattr(section, theirs) else getattr(native_cfg, theirs)
        for ours, theirs in _NATIVE_NAMES.items()
    }
    values["bank_f_hz"] = tuple(values["bank_f_hz"])
    return DefaultConfig(**values)


def run_reference(vx, vz, dt=None, cfg=None, predict_ahead_s=()):
    """Run DefaultEstimator over arrays; dt[i] is the time since sample i-1 (None: nominal; dt[0]
    is not used). Returns a dict of arrays named as yoyogait.EstimateResult."""
    est = DefaultEstimator(cfg)
    n = len(vx)
    keys = (
        "step_frequency_hz",
        "step_frequency_std_hz",
        "omega_rate_rad_s2",
        "speed_mps",
        "speed_std_mps",
        "accel_mps2",
        "amp_x_mps",
        "amp_z_mps",
        "phase_x_rel_z_rad",
        "signed_amp_x_mps",
        "vx_hat_mps",
        "vz_hat_mps",
        "vx_hat_h2_mps",
        "vz_hat_h2_mps",
        "R_m",
        "r_m",
        "std_scale",
        "innovation_vx_mps",
        "innovation_vz_mps",
        "nis",
    )
    out = {k: np.empty(n) for k in keys}
    out["gait_state"] = np.empty((n, NX))
    out["walking"] = np.empty(n, bool)
    out["acquiring"] = np.empty(n, bool)
    out["status"] = []
    out["vx_pred"] = np.empty((n, len(predict_ahead_s)))
    out["vz_pred"] = np.empty((n, len(predict_ahead_s)))
    for k in range(n):
        o = est.step(float(vx[k]), float(vz[k]), None if (dt is None or k == 0) else float(dt[k]))
        for key in keys:
            out[key][k] = o[key]
        out["gait_state"][k] = est._active().x
        out["walking"][k] = o["walking"]
        out["acquiring"][k] = o["acquiring"]
        out["status"].append(o["status"])
        for j, h in enumerate(predict_ahead_s):
            out["vx_pred"][k, j], out["vz_pred"][k, j] = est.predict(h)
    return out
