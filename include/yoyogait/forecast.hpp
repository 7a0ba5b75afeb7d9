/// @file forecast.hpp
/// @brief Forecast: the estimator's model some time ahead of its last sample, rates included, with
/// standard deviations (Estimator::forecast; docs/online.md sec. 5). Filled by both algorithms.
#pragma once

namespace yoyogait {

/// The model h [s] after the last sample. Where the two algorithms differ, "gait:" is the default
/// gait filter (GaitFilter::forecast) and "paper:" the paper's (Estimator::forecast).
struct Forecast {
  double vx_mps = 0.0;  ///< gait: A0(h) + X1(h) (+ second harmonic), standing A0(h); paper: predict_ahead(h) [m/s]
  double vz_mps = 0.0;  ///< gait: Z1(h) (+ second harmonic), standing 0; paper: predict_ahead(h) [m/s]
  /// gait: sqrt(lambda (tr(P_XX) / 2 + P_A0A0)) propagated to h; paper: NaN; 0 unless asked [m/s]
  double vx_std_mps = 0.0;
  double vz_std_mps = 0.0;         ///< gait: sqrt(lambda tr(P_ZZ) / 2) propagated to h; as vx_std_mps [m/s]
  double phase_advance_rad = 0.0;  ///< the phasors' turn over h: the integral of w (paper: w h) [rad]
  double omega_rad_s = 0.0;        ///< step angular frequency at h, w(h) [rad/s]
  double omega_rate_rad_s2 = 0.0;  ///< its rate at h, dw(h) (paper: 0) [rad/s^2]
  double speed_mps = 0.0;          ///< forward speed without the oscillation at h, A0(h) [m/s]
};

}  // namespace yoyogait
