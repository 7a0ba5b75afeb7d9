/// @file gait/hypothesis_bank.hpp
/// @brief The start-up bank (sec. 2.3): EKFs at several start frequencies, ranked by their
/// innovation log-likelihood with exponential memory and a log-prior.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>

#include "yoyogait/config.hpp"
#include "yoyogait/gait/member.hpp"
#include "yoyogait/gait/spectral_init.hpp"
#include "yoyogait/math.hpp"

namespace yoyogait::gait {

/// The bank's members, their harmonics and the acquisition's walking time.
class HypothesisBank {
 public:
  struct Settings {
    std::array<double, kMaxBankSize> f_hz{};  ///< start frequencies of the members [Hz]
    std::size_t size = 0;                     ///< members in use (1..kMaxBankSize)
    double prior_f_hz = 1.8;                  ///< typical frequency: its member gets the prior [Hz]
    double prior_bonus_nats = 2.0;            ///< the log-prior bonus [nats]
    double seed_f_var = 0.0;                  ///< (2 pi spectral_f_std_hz)^2: w variance of a seeded member
    double seed_phasor_var = 0.0;             ///< spectral_phasor_std_mps^2: phasor and A0 variance of it
  };

  HypothesisBank() noexcept = default;
  explicit HypothesisBank(const Settings& s) noexcept : s_(s) {}

  /// Every member restarts at its frequency with speed A0; the member nearest to the hint
  /// (re-acquisition: the last chosen lock's frequency) or to the typical frequency gets the log-prior, and the hint.
  void start(const MemberModel& model, double A0, bool has_hint, double f_hint_hz) noexcept {
    for (std::size_t i = 0; i < s_.size; ++i) {
      model.reset(members_[i], s_.f_hz[i], A0);
      model.reset(harmonics_[i].data());
    }
    const double f_pri = has_hint ? f_hint_hz : s_.prior_f_hz;
    std::size_t j = 0;
    for (std::size_t i = 1; i < s_.size; ++i)
      if (std::fabs(s_.f_hz[i] - f_pri) < std::fabs(s_.f_hz[j] - f_pri)) j = i;
    if (has_hint) model.reset(members_[j], f_hint_hz, A0);
    members_[j].loglik = s_.prior_bonus_nats;
    best_ = j;
    walk_time_s_ = 0.0;
  }

  /// One step of every member: predictions, then updates. Returns true when a channel was rejected.
  bool step(const MemberModel& model, double vx, double vz, bool use_x, bool use_z, bool oscillate, double dt,
            const DecayFactors::Values& fc, const InnovationGate& gate, StdScale& scale) noexcept {
    bool rejected = false;
    for (std::size_t i = 0; i < s_.size; ++i) model.predict(members_[i], harmonics_[i].data(), dt, fc, oscillate);
    for (std::size_t i = 0; i < s_.size; ++i)
      rejected |= model.update<true>(members_[i], harmonics_[i].data(), vx, vz, use_x, use_z, oscillate, gate,
                                     scale, fc);
    return rejected;
  }

  /// The log-likelihoods' exponential memory over one step.
  void forget(double factor) noexcept {
    for (std::size_t i = 0; i < s_.size; ++i) members_[i].loglik *= factor;
  }
  void add_walk_time(double dt_s) noexcept { walk_time_s_ += dt_s; }
  double walk_time_s() const noexcept { return walk_time_s_; }

  /// The most likely member becomes the best (the first of equals).
  void select_best() noexcept {
    best_ = 0;
    for (std::size_t i = 1; i < s_.size; ++i)
      if (members_[i].loglik > members_[best_].loglik) best_ = i;
  }

  /// The spectral fit seeds the least likely member (phasors at the last sample: X = (Xc, -Xs),
  /// Z = (Zc, -Zs)), which takes the likelihood of the most likely one.
  void seed(const MemberModel& model, const SpectralInit::Fit& fit) noexcept {
    using F = SpectralInit::Fit;
    const double* sol = fit.sol;
    std::size_t j = 0, jb = 0;
    for (std::size_t i = 1; i < s_.size; ++i) {
      if (members_[i].loglik < members_[j].loglik) j = i;
      if (members_[i].loglik > members_[jb].loglik) jb = i;
    }
    Ekf& m = members_[j];
    model.reset(m, fit.f_hz, detail::py_max(sol[F::kA], 0.0));
    m.x[kDA0] = sol[F::kB];
    m.x[kX1] = sol[F::kXc];
    m.x[kX2] = -sol[F::kXs];
    m.x[kZ1] = sol[F::kZc];
    m.x[kZ2] = -sol[F::kZs];
    const double sp = s_.seed_phasor_var;
    m.P[kX1][kX1] = m.P[kX2][kX2] = m.P[kZ1][kZ1] = m.P[kZ2][kZ2] = sp;
    m.P[kA0][kA0] = sp;
    m.P[kW][kW] = s_.seed_f_var;
    m.loglik = members_[jb].loglik;  // (after the reset: 0 where j is jb)
    model.reset(harmonics_[j].data());
  }

  const Ekf& best() const noexcept { return members_[best_]; }
  Ekf& best() noexcept { return members_[best_]; }
  const Harmonic* best_harmonics() const noexcept { return harmonics_[best_].data(); }
  Harmonic* best_harmonics() noexcept { return harmonics_[best_].data(); }
  const std::array<Harmonic, 2>& best_harmonic_pair() const noexcept { return harmonics_[best_]; }

 private:
  Settings s_;
  std::array<Ekf, kMaxBankSize> members_{};
  std::array<std::array<Harmonic, 2>, kMaxBankSize> harmonics_{};
  std::size_t best_ = 0;
  double walk_time_s_ = 0.0;
};

}  // namespace yoyogait::gait
