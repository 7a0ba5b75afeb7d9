/// @file gait/gait_filter.hpp
/// @brief The default estimator: a dual-phasor EKF with a positive, bounded step frequency.
///
/// Equations and tuning: docs/default_estimator.md (sections cited as "sec."). In short:
///
///   x = [X1, X2, Z1, Z2, w, A0, dA0, dw]                          (sec. 2.1; gait/state.hpp)
///   v_x = A0 + X1 + h_x,   v_z = Z1 + h_z      (two sequential scalar updates; h: second harmonics)
///   R = diag(meas_vx_density, meas_vz_density) / dt          (the samples are means over dt; sec. 2.2)
///   Q = q_phasor dt I(X, Z) + q_phase dt g g^T + diag(q_omega, q_rate(dw_lp), q_speed, q_accel) dt,
///   g = [-X2, X1, -Z2, Z1, 0, 0, 0, 0]                                  (sec. 2.2; gait/member.hpp)
///
/// This class composes the parts, each in its own header and built from its settings
/// (gait/settings.hpp): the EKF kernels (gait/ekf.hpp), one EKF with its noise model, gate and
/// harmonics (gait/member.hpp, gait/harmonic.hpp), the start-up bank (gait/hypothesis_bank.hpp) and
/// its spectral initialisation and re-acquisition hint (gait/spectral_init.hpp, gait/lock_hint.hpp,
/// sec. 2.3), the walking detector (sec. 2.4),
/// the innovation gate and the dt-dependent factors (sec. 2.5), the bound watchdog, the radii and the
/// std scale (sec. 2.6), the cadence-change detector (sec. 2.8). step() makes no heap allocation and
/// cannot throw. The steady state (walking, one EKF, the same dt) runs no exp, log, bank or spectral code.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "yoyogait/config.hpp"
#include "yoyogait/estimate.hpp"
#include "yoyogait/forecast.hpp"
#include "yoyogait/gait/bound_watchdog.hpp"
#include "yoyogait/gait/cadence_change.hpp"
#include "yoyogait/gait/decay_factors.hpp"
#include "yoyogait/gait/ekf.hpp"
#include "yoyogait/gait/harmonic.hpp"
#include "yoyogait/gait/hypothesis_bank.hpp"
#include "yoyogait/gait/innovation_gate.hpp"
#include "yoyogait/gait/lock_hint.hpp"
#include "yoyogait/gait/member.hpp"
#include "yoyogait/gait/radii.hpp"
#include "yoyogait/gait/settings.hpp"
#include "yoyogait/gait/spectral_init.hpp"
#include "yoyogait/gait/state.hpp"
#include "yoyogait/gait/std_scale.hpp"
#include "yoyogait/gait/walking_detector.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait {

/// The gait filter (the default estimator): everything of default_estimator.py's DefaultEstimator.
/// Use it through yoyogait::Estimator; this class is public for tests and for embedding.
class GaitFilter {
 public:
  /// What a step did with its sample (mapped to yoyogait::Status by the Estimator). One per sample,
  /// by precedence: kNumerical, then kNonFinite, then kOutOfRange, then kOutlier, then kOk.
  enum class Outcome : std::uint8_t {
    kOk = 0,          ///< both channels used
    kNonFinite = 1,   ///< a channel (or dt) was NaN or infinite, or dt < 0: that channel (or the sample) not used
    kOutOfRange = 2,  ///< a channel was above max_abs_velocity_mps: not used
    kOutlier = 3,     ///< a channel failed the innovation gate: not used
    kNumerical = 4,   ///< the filter became non-finite and was restarted (not seen with in-range data)
  };

  /// Estimates after a step (sec. 2.6).
  struct Output {
    GaitState x{};                      ///< state of the active EKF
    double step_frequency_std_hz = 0;   ///< sqrt(lambda P_ww) / 2 pi [Hz]
    double speed_std_mps = 0;           ///< sqrt(lambda P_A0A0 + floor^2) [m/s]
    double amp_x_mps = 0;               ///< |X| [m/s]
    double vx_hat_mps = 0;              ///< model reconstruction A0 + X1 (standing: A0) [m/s]
    double vz_hat_mps = 0;              ///< model reconstruction Z1 (standing: 0) [m/s]
    double vx_hat_h2_mps = 0;           ///< ... with the second harmonic [m/s]
    double vz_hat_h2_mps = 0;           ///< ... with the second harmonic [m/s]
    double R_m = 0;                     ///< R = A0 / w, low-passed while walking [m]
    double r_m = 0;                     ///< r = |Z| / w, low-passed while walking [m]
    double std_scale = 1;               ///< lambda [1]
    bool walking = false;               ///< the detector says walking
    bool acquiring = false;             ///< the bank is running (start-up / re-acquisition)
    bool radii_updated = false;         ///< R, r were updated at this step
  };

  /// (v_x, v_z) predicted ahead [m/s].
  struct Prediction {
    double vx_mps = 0.0, vz_mps = 0.0;
  };

  GaitFilter() noexcept : GaitFilter(EstimatorConfig{}) {}

  /// config must pass EstimatorConfig::validate() (the Estimator checks it); the gait filter reads
  /// its section, config.gait_filter, and the shared fields.
  explicit GaitFilter(const EstimatorConfig& config) noexcept : GaitFilter(config, gait::filter_settings(config)) {}

  /// Back to the state before the first sample.
  void reset() noexcept {
    started_ = false;
    acquiring_ = true;
    detector_.reset();
    radii_.reset();
    hint_.reset();
    gate_.reset();
    watchdog_.reset();
    scale_.reset();
    t_now_s_ = 0.0;
    spectral_.reset();
    radii_updated_ = false;
    updated_ = false;
    out_hx_ = out_hz_ = 0.0;
    factors_.reset();
    // Defined outputs (w > 0) even before the first finite sample.
    start_acquisition(0.0, 0.0);
    collapse();
    acquiring_ = true;
  }

  /// One sample at the nominal time step (sample_time_s) since the previous one.
  Outcome step(double vx_mps, double vz_mps) noexcept { return advance(vx_mps, vz_mps, nominal_dt_); }

  /// One sample dt_s [s] after the previous one. A non-finite or negative dt_s: the sample is not
  /// used (kNonFinite). dt_s of the first sample is not used.
  Outcome step(double vx_mps, double vz_mps, double dt_s) noexcept {
    if (!(std::isfinite(dt_s) && dt_s >= 0.0)) {
      updated_ = false;
      return Outcome::kNonFinite;
    }
    return advance(vx_mps, vz_mps, dt_s);
  }

  /// The innovations and NIS of the last step (see yoyogait::Innovation): those of the EKF that
  /// is active after it; all NaN when the step updated nothing.
  Innovation innovation() const noexcept {
    Innovation out;
    if (!updated_) return out;
    const gait::Innovations& in = active().innovations;
    out.innovation_vx_mps = in.vx_mps;
    out.innovation_vz_mps = in.vz_mps;
    const bool x = !std::isnan(in.vx_mps), z = !std::isnan(in.vz_mps);
    if (x || z)
      out.nis = (x ? in.vx_mps * in.vx_mps / in.var_vx_mps2 : 0.0) + (z ? in.vz_mps * in.vz_mps / in.var_vz_mps2 : 0.0);
    return out;
  }

  /// The estimates after the last step (sec. 2.6).
  Output output() const noexcept {
    using namespace gait;
    const Ekf& f = active();
    const GaitState& x = f.x;
    const bool walking = detector_.walking();
    Output o;
    o.x = x;
    if (walking) {
      o.vx_hat_mps = x[kA0] + x[kX1];  // model reconstruction: R w + phase-shifted oscillation
      o.vz_hat_mps = x[kZ1];
      // The second harmonics at the posterior phasors (computed at the end of the step).
      o.vx_hat_h2_mps = o.vx_hat_mps + out_hx_;
      o.vz_hat_h2_mps = o.vz_hat_mps + out_hz_;
    } else {
      o.vx_hat_mps = o.vx_hat_h2_mps = x[kA0];
      o.vz_hat_mps = o.vz_hat_h2_mps = 0.0;
    }
    o.amp_x_mps = std::sqrt(x[kX1] * x[kX1] + x[kX2] * x[kX2]);
    // |Z|, the X-Z phase relation and the rates: Estimate derives them from x on demand.
    const double lam = scale_.value();
    o.step_frequency_std_hz = std::sqrt(detail::py_max(lam * f.P[kW][kW], 0.0)) * kInvTwoPi;
    o.speed_std_mps = std::sqrt(detail::py_max(lam * f.P[kA0][kA0], 0.0) + speed_floor2_);
    o.R_m = radii_.R_m();
    o.r_m = radii_.r_m();
    o.std_scale = lam;
    o.walking = walking;
    o.acquiring = acquiring_;
    o.radii_updated = radii_updated_;
    return o;
  }

  /// (v_x, v_z) h_s [s] after the last sample: phasors turned by w h + dw h^2 / 2, A0 held, second
  /// harmonics added unless harmonics is false or the bank is running. Standing: (A0, 0).
  Prediction predict(double h_s, bool harmonics = true) const noexcept;  // gait/forecast.hpp

  /// The model's forecast h_s >= 0 ahead (yoyogait::Forecast, rates included; with_std: the covariance
  /// too). Defined and described in gait/forecast.hpp. decay: the caller's cache of the exp factors.
  /// phase_var_scale: a factor on the phase's variance over h_s (the square of the stds' inflation
  /// where the innovations exceed their covariance: the model holds less than P says).
  Forecast forecast(double h_s, bool with_std, double phase_var_scale = 1.0) const noexcept;
  Forecast forecast(double h_s, bool with_std, gait::HorizonDecay& decay, double phase_var_scale = 1.0) const noexcept;
  /// The most covariance steps forecast takes (beyond 64 sample times, longer steps).
  static constexpr double kMaxForecastSteps = 64.0;

  const EstimatorConfig& config() const noexcept { return cfg_; }
  /// State of the active EKF (the best bank member while acquiring).
  const GaitState& state() const noexcept { return active().x; }
  /// Covariance of the active EKF, both triangles filled.
  GaitMatrix covariance() const noexcept {
    GaitMatrix P = active().P;
    for (std::size_t i = 0; i < gait::kDim; ++i)
      for (std::size_t j = 0; j < i; ++j) P[i][j] = P[j][i];
    return P;
  }
  /// One element of the active EKF's covariance, without copying it.
  double covariance(std::size_t i, std::size_t j) const noexcept {
    return i <= j ? active().P[i][j] : active().P[j][i];
  }
  bool walking() const noexcept { return detector_.walking(); }
  bool acquiring() const noexcept { return acquiring_; }
  /// Variances added to the measurement noise of v_x and v_z from the next step on [(m/s)^2]
  /// (gait/decay_factors.hpp; 0 unless set: the online front-end's noisy input); the walking
  /// detector does not count the v_z part in RMS(v_z).
  /// noise_sigmas: the detector's thresholds are raised by this many standard deviations of what
  /// that noise gives its low-passes (gait/walking_detector.hpp; 0: not raised). floor_vz: the v_z
  /// variance of the input's noise floor on every sample, only kept out of RMS(v_z).
  void set_extra_measurement_variance(double vx_m2_per_s2, double vz_m2_per_s2, double noise_sigmas = 0.0,
                                      double floor_vz_m2_per_s2 = 0.0) noexcept {
    factors_.set_extra_variance(vx_m2_per_s2, vz_m2_per_s2);
    detector_.set_noise(vx_m2_per_s2, vz_m2_per_s2, noise_sigmas, floor_vz_m2_per_s2);
  }
  double std_scale() const noexcept { return scale_.value(); }
  /// Sec. 2.3: a failed lock (a frequency pinned at a bound, the watchdog; or one its user finds
  /// below the steps): the acquisition restarts. Nothing while acquiring or standing.
  void reacquire() noexcept {
    if (acquiring_ || !detector_.walking()) return;
    hint_.fail();
    start_acquisition(main_.x[gait::kA0], 0.0);
  }
  /// The step frequency f_hz with variance var_hz2 [Hz^2] from another evidence (the feet's steps):
  /// an observation of w in the one EKF. Nothing while acquiring or standing.
  void observe_frequency(double f_hz, double var_hz2) noexcept {
    if (acquiring_ || !detector_.walking() || !(var_hz2 > 0.0)) return;
    model_.observe_w(main_, kTwoPi * f_hz, kTwoPi * kTwoPi * var_hz2);
  }
  /// A cadence that another evidence shows (the feet's steps, online/foot_cadence.hpp), against the
  /// lock or before the bank has chosen: the one EKF restarts at f_hz, its phasors and their
  /// covariance as a bank member's start, the speed kept; the bank stops (the evidence has chosen).
  /// Nothing while standing, or for an f_hz outside the frequency range.
  void relock(double f_hz) noexcept {
    if (!detector_.walking() || !(f_hz >= cfg_.gait_filter.f_min_hz && f_hz <= cfg_.gait_filter.f_max_hz)) return;
    start_acquisition(active().x[gait::kA0], f_hz);
    collapse();
    hint_.choose(kTwoPi * f_hz);
  }

 private:
  using Ekf = gait::Ekf;

  GaitFilter(const EstimatorConfig& config, const gait::FilterSettings& s) noexcept
      : cfg_(config),
        model_(s.model),
        bank_model_(s.bank_model),
        factors_(s.time_constants, s.measurement_noise),
        detector_(s.walking),
        gate_(s.gate),
        scale_(s.std_scale),
        radii_(s.radii),
        watchdog_(s.watchdog),
        cadence_(s.cadence_change),
        nominal_dt_(s.nominal_dt_s),
        speed_floor2_(s.speed_std_floor2),
        bank_(s.bank),
        spectral_(s.spectral) {
    reset();
  }

  // (A0 + X1, Z1) with the phasors turned by angle_rad, plus the second harmonics where they apply
  // (harmonics asked, enabled, and the bank not running): what predict and forecast share.
  // coherence: E[cos(phase error)] of the turn, on the fundamental; the harmonic, at twice the
  // phase, gets its fourth power (a Gaussian phase error of variance s2: exp(-s2 / 2), exp(-2 s2)).
  Prediction turned(double angle_rad, double A0, bool harmonics, double coherence = 1.0) const noexcept;

  // gait/forecast.hpp
  Forecast forecast_at(double h_s, bool with_std, double ea, double eb, double phase_var_scale = 1.0) const noexcept;
  const Ekf& active() const noexcept { return acquiring_ ? bank_.best() : main_; }
  Ekf& active() noexcept { return acquiring_ ? bank_.best() : main_; }
  const gait::Harmonic* active_harmonics() const noexcept {
    return acquiring_ ? bank_.best_harmonics() : main_h_.data();
  }
  gait::Harmonic* active_harmonics() noexcept { return acquiring_ ? bank_.best_harmonics() : main_h_.data(); }
  bool harmonics_on() const noexcept { return model_.use_harmonic && !acquiring_; }

  /// Sec. 2.3: the bank restarts (around f_hint_hz, if positive: the evidence's, or the last chosen
  /// lock's, hint_.f_hz()), with a fresh spectral buffer and watchdog.
  void start_acquisition(double A0, double f_hint_hz) noexcept {
    bank_.start(model_, A0, f_hint_hz > 0.0, f_hint_hz);
    acquiring_ = true;
    hint_.acquiring();
    spectral_.reset();
    watchdog_.reset();
    cadence_.reset();
  }

  /// The bank's best member becomes the one EKF.
  void collapse() noexcept {
    main_ = bank_.best();
    main_h_ = bank_.best_harmonic_pair();
    acquiring_ = false;
  }

  /// Walking stops: freeze the oscillator, drop the oscillation, decouple the bias. The bank
  /// collapses first if it was running; otherwise the one EKF goes on (the bank holds stale members).
  void stop_walking() noexcept {
    using namespace gait;
    if (acquiring_) collapse();
    Ekf& m = main_;
    m.x[kX1] = m.x[kX2] = m.x[kZ1] = m.x[kZ2] = m.x[kDW] = 0.0;
    for (std::size_t i = 0; i < kDim; ++i) {
      if (i == kA0 || i == kDA0) continue;
      (i < kA0 ? m.P[i][kA0] : m.P[kA0][i]) = 0.0;
      (i < kDA0 ? m.P[i][kDA0] : m.P[kDA0][i]) = 0.0;
    }
  }

  /// While walking: R = A0 / w, r = |Z| / w and the output's harmonic bases (1 / |X|^2, 1 / |Z|^2
  /// at the posterior phasors) from one division.
  void walking_outputs(const Ekf& act, double radii_gain) noexcept {
    using namespace gait;
    const GaitState& x = act.x;
    const double ax2 = x[kX1] * x[kX1] + x[kX2] * x[kX2], az2 = x[kZ1] * x[kZ1] + x[kZ2] * x[kZ2];
    const bool hx = harmonics_on() && !(ax2 < model_.harm_min2), hz = harmonics_on() && !(az2 < model_.harm_min2);
    const double dx = hx ? ax2 : 1.0, dz = hz ? az2 : 1.0, w = x[kW];
    const double dxz = dx * dz;
    const double inv = 1.0 / (w * dxz);
    const double inv_w = dxz * inv;
    out_hx_ = hx ? active_harmonics()[kVx].value((x[kX1] * x[kX1] - x[kX2] * x[kX2]) * (w * dz * inv),
                                              2.0 * x[kX1] * x[kX2] * (w * dz * inv))
                 : 0.0;
    out_hz_ = hz ? active_harmonics()[kVz].value((x[kZ1] * x[kZ1] - x[kZ2] * x[kZ2]) * (w * dx * inv),
                                              2.0 * x[kZ1] * x[kZ2] * (w * dx * inv))
                 : 0.0;
    hint_.follow(w);
    radii_.update(x[kA0] * inv_w, std::sqrt(az2) * inv_w, radii_gain);
    radii_updated_ = true;
  }

  // ------------------------------------------------------------------------------------ one step

  /// One sample dt [s] after the previous one, in the order of sec. 2: the channels screened, the
  /// first sample or a long gap handled, the walking detector, the EKF step (the bank's while
  /// acquiring), the gate's release, the acquisition, the watchdog, the outputs, the finiteness check.
  Outcome advance(double vx, double vz, double dt) noexcept {
    using namespace gait;
    // The channels used: finite and within max_abs_velocity_mps (a channel out of range is dropped
    // like a non-finite one: a corrupt 1e200 would overflow P).
    const bool fin_x = std::isfinite(vx), fin_z = std::isfinite(vz);
    const bool use_x = fin_x && std::fabs(vx) <= cfg_.max_abs_velocity_mps;
    const bool use_z = fin_z && std::fabs(vz) <= cfg_.max_abs_velocity_mps;
    Outcome outcome = !(fin_x && fin_z) ? Outcome::kNonFinite : (use_x && use_z) ? Outcome::kOk : Outcome::kOutOfRange;
    if (!started_ && !use_x) {
      updated_ = false;
      return outcome;
    }
    if (!started_) dt = start_filter(vx, vz, use_z);
    t_now_s_ += dt;
    const double dt_walk = dt;  // the detector runs over the gap too
    if (dt > cfg_.gait_filter.max_gap_s) dt = bridge_gap();
    const DecayFactors::Values& fc = factors_.at(dt);
    const bool walking = detect_walking(vx, vz, use_x, use_z, dt_walk, dt, fc);
    const bool rejected = filter_step(vx, vz, use_x, use_z, walking, dt, fc);
    updated_ = true;
    // A non-finite or out-of-range channel says more about the sample than the gate.
    if (rejected && outcome == Outcome::kOk) outcome = Outcome::kOutlier;
    if (gate_.after_step(rejected)) release_gate();
    if (acquiring_) acquire(vx, vz, use_x && use_z, walking, dt, fc);
    if (walking && !acquiring_ && watchdog_.update(main_.x[kW], dt)) reacquire();  // a failed lock
    radii_updated_ = false;
    Ekf& act = active();
    if (walking) walking_outputs(act, fc.radii_gain);
    if (!finite(act)) {
      recover();
      outcome = Outcome::kNumerical;
    }
    return outcome;
  }

  /// The first sample with a usable v_x: the detector's low-passes and the bank start at it (its
  /// best member is also the one EKF: defined from the start). Returns its time step, 0 (dt unused).
  double start_filter(double vx, double vz, bool use_z) noexcept {
    started_ = true;
    detector_.start(vx, vz, use_z);
    start_acquisition(vx, 0.0);
    collapse();
    acquiring_ = true;
    return 0.0;
  }

  /// A gap longer than max_gap_s: the acquisition restarts around the last chosen lock's frequency, with the
  /// speed kept. Returns the time step of the fresh members, 0 (not propagated over the gap).
  double bridge_gap() noexcept {
    start_acquisition(active().x[gait::kA0], hint_.f_hz());
    return 0.0;
  }

  /// Sec. 2.4: the walking detector over dt_walk (the sample's own interval, also over a gap);
  /// walking (re)starting re-opens the acquisition (bias from this sample, one member at the last
  /// chosen lock's frequency), stopping freezes the oscillator. Returns whether walking.
  bool detect_walking(double vx, double vz, bool use_x, bool use_z, double dt_walk, double dt,
                      const gait::DecayFactors::Values& fc) noexcept {
    const bool was_walking = detector_.walking();
    detector_.update(vx, vz, use_x, use_z, dt_walk == dt ? fc.walk_gain : detector_.gain(dt_walk));
    const bool walking = detector_.walking();
    if (walking && !was_walking)
      start_acquisition(use_x ? vx : active().x[gait::kA0], hint_.f_hz());
    if (was_walking && !walking) stop_walking();
    return walking;
  }

  /// Sec. 2.1-2.2, 2.5, 2.8: prediction and updates of every bank member while acquiring, else of
  /// the one EKF, followed while walking by the cadence-change hook. Returns whether the gate
  /// rejected a channel. (Inlined: the steady state's step is most of advance.)
  YOYOGAIT_ALWAYS_INLINE bool filter_step(double vx, double vz, bool use_x, bool use_z, bool walking, double dt,
                                          const gait::DecayFactors::Values& fc) noexcept {
    if (acquiring_) return bank_.step(bank_model_, vx, vz, use_x, use_z, walking, dt, fc, gate_, scale_);
    model_.predict(main_, main_h_.data(), dt, fc, walking);
    const gait::PriorPhasors prior = gait::CadenceChangeDetector::prior(main_.x);
    const bool rejected =
        model_.update<false>(main_, main_h_.data(), vx, vz, use_x, use_z, walking, gate_, scale_, fc);
    if (walking) cadence_.after_update(model_, main_, prior, fc, rejected);  // sec. 2.8: cadence changes
    return rejected;
  }

  /// Sec. 2.5: a persistent disagreement was accepted: inflate P so that the filter follows again
  /// (up to the variance bounds, sec. 2.7; a non-negative diagonal increment keeps P positive definite).
  void release_gate() noexcept {
    using namespace gait;
    model_.inflate(main_, kX1, model_.p0_phasor);
    model_.inflate(main_, kX2, model_.p0_phasor);
    model_.inflate(main_, kZ1, model_.p0_phasor);
    model_.inflate(main_, kZ2, model_.p0_phasor);
    model_.inflate(main_, kA0, model_.p0_speed);
  }

  /// Sec. 2.3, while the bank runs: the likelihoods' memory, the walking time, the spectral buffer
  /// and its fit (which seeds a member; both_used: both channels of the sample are used), the
  /// best member, and the collapse to one EKF once the bank has walked bank_window_s.
  void acquire(double vx, double vz, bool both_used, bool walking, double dt,
               const gait::DecayFactors::Values& fc) noexcept {
    bank_.forget(fc.forget);
    if (walking) {
      bank_.add_walk_time(dt);
      if (both_used) spectral_.push(t_now_s_, vx, vz);
      gait::SpectralInit::Fit fit;
      if (spectral_.due(bank_.walk_time_s()) && spectral_.fit(fit)) bank_.seed(model_, fit);
    }
    bank_.select_best();
    if (bank_.walk_time_s() < cfg_.gait_filter.bank_window_s) return;
    collapse();  // the bank has chosen: its lock's frequency is the hint from now on
    hint_.choose(main_.x[gait::kW]);
  }

  /// Whether the active EKF act and the outputs are finite. Never false with in-range samples; it
  /// keeps the state finite whatever comes in: a finite state and diagonal mean a finite covariance
  /// (|P_ij| <= sqrt(P_ii P_jj)).
  bool finite(const Ekf& act) const noexcept {
    using namespace gait;
    const GaitState& xa = act.x;
    const GaitMatrix& Pa = act.P;
    const double check = ((xa[kX1] + xa[kX2]) + (xa[kZ1] + xa[kZ2])) + ((xa[kW] + xa[kA0]) + (xa[kDA0] + xa[kDW])) +
                         ((Pa[kX1][kX1] + Pa[kX2][kX2]) + (Pa[kZ1][kZ1] + Pa[kZ2][kZ2])) +
                         ((Pa[kW][kW] + Pa[kA0][kA0]) + (Pa[kDA0][kDA0] + Pa[kDW][kDW])) +
                         (radii_.R_m() + radii_.r_m() + scale_.value());
    return std::isfinite(check);
  }

  /// After a non-finite result: restart from the last finite speed and frequency.
  void recover() noexcept {
    const double A0 = detector_.recover();
    radii_.recover();
    scale_.reset();
    gate_.reset();
    out_hx_ = out_hz_ = 0.0;
    start_acquisition(A0, hint_.f_hz());
    collapse();
    acquiring_ = true;
  }

  EstimatorConfig cfg_;
  gait::MemberModel model_;
  gait::MemberModel bank_model_;  ///< model_ with the bank's q_omega (bank_q_omega_rad2_per_s3): its steps
  // The one EKF of the steady state and its harmonics.
  Ekf main_;
  std::array<gait::Harmonic, 2> main_h_{};
  gait::DecayFactors factors_;
  gait::WalkingDetector detector_;
  gait::InnovationGate gate_;
  gait::StdScale scale_;
  gait::RadiiSmoother radii_;
  gait::BoundWatchdog watchdog_;
  gait::CadenceChangeDetector cadence_;
  double nominal_dt_ = 0.04, speed_floor2_ = 0.0;
  gait::LockHint hint_;                 ///< the re-acquisition hint (gait/lock_hint.hpp)
  double out_hx_ = 0.0, out_hz_ = 0.0;  ///< second harmonics at the posterior phasors, for output()
  double t_now_s_ = 0.0;
  bool started_ = false, acquiring_ = true, radii_updated_ = false;
  bool updated_ = false;  ///< the last step ran the updates (its innovations are in the active EKF)
  // Start-up: the bank and the spectral ring buffer.
  gait::HypothesisBank bank_;
  gait::SpectralInit spectral_;
};

}  // namespace yoyogait

// The forecast's definition: the model h_s ahead, with its covariance (docs/online.md sec. 5).
#include "yoyogait/gait/forecast.hpp"
