/// @file online/centre.hpp
/// @brief The centre of several markers, frame by frame, without the future.
///
/// Offline (pipeline/points.py, robust_centre) a missing marker's offset from the centre is
/// interpolated towards the next frame where all markers are seen. Online the offset is carried
/// from the last frame where the marker was seen with all the others:
///
///   centre = mean over the visible markers j of (p_j - o_j),   o_j = p_j - mean(p) on full frames
///
/// A marker first seen late gets o_j = p_j - centre at that frame. When the set of visible markers
/// changes (a marker drops out or returns, or the offsets are refreshed after a partial stretch),
/// the two definitions of the centre differ by the offsets' drift. On such a frame the centre moves
/// by the mean displacement of the markers seen on both frames instead, and the difference becomes
/// a correction that decays with blend_tau_s: the centre never jumps.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "yoyogait/online/interval_cache.hpp"

namespace yoyogait::online {

/// The most points the online front-end follows.
inline constexpr std::size_t kMaxPoints = 16;

using Vec3 = std::array<double, 3>;

/// Causal marker centre; see the file comment. Everything per frame is noexcept and allocation-free.
class CausalCentre {
 public:
  /// What one frame gave.
  struct Result {
    Vec3 centre_m{};                  ///< the centre (valid only when ok)
    bool ok = false;                  ///< at least one marker with a known offset was visible
    std::uint8_t visible_points = 0;  ///< markers used on this frame
    bool set_changed = false;         ///< the set of visible markers changed: a correction starts blending
    double step_m = 0.0;              ///< how far this frame's set change moved the correction blended out [m]
  };

  struct Settings {
    double blend_tau_s = 0.3;  ///< a step of the centre when the set changes is blended out over this [s]
    double forget_s = 2.0;     ///< a marker unseen this long leaves the set (its offset would go stale) [s]
  };

  CausalCentre() noexcept = default;
  /// n_points: at most kMaxPoints.
  CausalCentre(std::size_t n_points, const Settings& s) noexcept
      : n_(n_points > kMaxPoints ? kMaxPoints : n_points),
        blend_tau_s_(s.blend_tau_s),
        forget_s_(s.forget_s),
        keeps_seen_(!(0.0 > s.forget_s)) {
    reset();
  }

  /// Forget every offset and the correction (a restart after a long gap).
  void reset() noexcept {
    known_.fill(false);
    unseen_s_.fill(0.0);
    prev_visible_.fill(false);
    offset_.fill(Vec3{});
    correction_ = Vec3{};
    have_prev_ = false;
    prev_full_ = false;
    steady_ = false;
    offsets_due_ = false;
  }

  /// One frame. positions: n x 3 metres; visible[j] false where marker j is missing. dt_s: time
  /// since the previous frame with a visible marker (decays the correction; <= 0 on the first).
  Result update(const Vec3* positions, const bool* visible, double dt_s) noexcept {
    if (dt_s > 0.0 && steady(visible)) return update_steady(positions, dt_s);
    if (offsets_due_) refresh_offsets();
    steady_ = false;  // until this frame ends as one that a steady frame may follow
    Result r;
    if (dt_s > 0.0) {
      for (std::size_t j = 0; j < n_; ++j) {
        unseen_s_[j] = visible[j] ? 0.0 : unseen_s_[j] + dt_s;
        if (known_[j] && unseen_s_[j] > forget_s_) known_[j] = false;
      }
    }
    std::size_t n_vis = 0, n_known_vis = 0, n_known = 0;
    bool all_known_visible = true;
    for (std::size_t j = 0; j < n_; ++j) {
      n_vis += visible[j];
      n_known += known_[j];
      if (known_[j]) {
        if (visible[j])
          ++n_known_vis;
        else
          all_known_visible = false;
      }
    }
    if (n_vis == 0) return r;

    // Markers seen for the first time take their offset from the centre of the known visible ones,
    // or, when none of those is visible, from the last centre (the first frame: their mean).
    bool set_changed = false;
    if (n_known_vis < n_vis) {
      Vec3 c{};
      if (n_known_vis > 0) {
        for (std::size_t j = 0; j < n_; ++j)
          if (visible[j] && known_[j])
            for (int a = 0; a < 3; ++a) c[a] += positions[j][a] - offset_[j][a];
        for (int a = 0; a < 3; ++a) c[a] /= static_cast<double>(n_known_vis);
      } else if (have_prev_) {
        c = last_m_;
      } else {
        for (std::size_t j = 0; j < n_; ++j)
          if (visible[j])
            for (int a = 0; a < 3; ++a) c[a] += positions[j][a];
        for (int a = 0; a < 3; ++a) c[a] /= static_cast<double>(n_vis);
      }
      for (std::size_t j = 0; j < n_; ++j) {
        if (visible[j] && !known_[j]) {
          for (int a = 0; a < 3; ++a) offset_[j][a] = positions[j][a] - c[a];
          known_[j] = true;
        }
      }
      set_changed = true;
      all_known_visible = true;
      for (std::size_t j = 0; j < n_; ++j)
        if (known_[j] && !visible[j]) all_known_visible = false;
    }

    // Full frame (every known marker visible): the centre is their mean, the offsets are refreshed.
    Vec3 centre{};
    if (all_known_visible) {
      std::size_t m = 0;
      for (std::size_t j = 0; j < n_; ++j)
        if (known_[j]) {
          for (int a = 0; a < 3; ++a) centre[a] += positions[j][a];
          ++m;
        }
      for (int a = 0; a < 3; ++a) centre[a] /= static_cast<double>(m);
      for (std::size_t j = 0; j < n_; ++j)
        if (known_[j])
          for (int a = 0; a < 3; ++a) offset_[j][a] = positions[j][a] - centre[a];
    } else {
      std::size_t m = 0;
      for (std::size_t j = 0; j < n_; ++j)
        if (visible[j] && known_[j]) {
          for (int a = 0; a < 3; ++a) centre[a] += positions[j][a] - offset_[j][a];
          ++m;
        }
      for (int a = 0; a < 3; ++a) centre[a] /= static_cast<double>(m);
    }
    for (std::size_t j = 0; j < n_; ++j)
      if (visible[j] != prev_visible_[j]) set_changed = true;
    if (all_known_visible != prev_full_) set_changed = true;

    // Decay the correction, then absorb this frame's step into it.
    if (dt_s > 0.0) decay_correction(dt_s);
    r.set_changed = set_changed && have_prev_;
    if (set_changed && have_prev_) {
      // How far the markers seen on this frame and the previous one moved: what the centre moves
      // on a frame where the set changes (only then: prev_pos_ is still the previous frame's).
      Vec3 moved{};
      std::size_t n_both = 0;
      for (std::size_t j = 0; j < n_; ++j) {
        if (visible[j] && prev_visible_[j]) {
          for (int a = 0; a < 3; ++a) moved[a] += positions[j][a] - prev_pos_[j][a];
          ++n_both;
        }
      }
      // Continue from the last centre by the common markers' displacement (none: hold it).
      double step2 = 0.0;
      for (int a = 0; a < 3; ++a) {
        const double target = last_m_[a] + (n_both > 0 ? moved[a] / static_cast<double>(n_both) : 0.0);
        const double fresh = centre[a] - target;
        step2 += (fresh - correction_[a]) * (fresh - correction_[a]);
        correction_[a] = fresh;
      }
      r.step_m = std::sqrt(step2);
    }
    for (int a = 0; a < 3; ++a) r.centre_m[a] = centre[a] - correction_[a];
    r.ok = true;
    last_m_ = r.centre_m;
    r.visible_points = static_cast<std::uint8_t>(n_vis);
    for (std::size_t j = 0; j < n_; ++j) {
      prev_visible_[j] = visible[j];
      if (visible[j]) prev_pos_[j] = positions[j];
    }
    prev_full_ = all_known_visible;
    have_prev_ = true;
    // Every marker known and seen, none unseen for any time: the next frame may be steady.
    bool unseen = false;
    for (std::size_t j = 0; j < n_; ++j) unseen |= unseen_s_[j] != 0.0;
    steady_ = all_known_visible && n_vis == n_ && !unseen && keeps_seen_;
    return r;
  }

  std::size_t size() const noexcept { return n_; }

 private:
  /// Every marker known and seen on this frame and on the last, a full frame with no marker unseen
  /// for any time (steady_): the case of almost every frame, in which update() changes no set, starts
  /// no correction and forgets nothing.
  bool steady(const bool* visible) const noexcept {
    if (!steady_) return false;
    bool all = true;
    for (std::size_t j = 0; j < n_; ++j) all &= visible[j];
    return all;
  }

  /// update() in the steady case (dt_s > 0), without its searches: the same operations in the same
  /// order on the same values, so the same bits. The offsets (positions - centre), read only once the
  /// set changes, are formed then from the positions kept (refresh_offsets).
  Result update_steady(const Vec3* positions, double dt_s) noexcept {
    Result r;
    Vec3 centre{};
    for (std::size_t j = 0; j < n_; ++j) {
      for (int a = 0; a < 3; ++a) centre[a] += positions[j][a];
      prev_pos_[j] = positions[j];
    }
    for (int a = 0; a < 3; ++a) centre[a] /= static_cast<double>(n_);
    offsets_centre_m_ = centre;
    offsets_due_ = true;
    decay_correction(dt_s);
    for (int a = 0; a < 3; ++a) r.centre_m[a] = centre[a] - correction_[a];
    r.ok = true;
    last_m_ = r.centre_m;
    r.visible_points = static_cast<std::uint8_t>(n_);
    return r;
  }

  /// The offsets of the last steady frame: its positions (prev_pos_) less its centre.
  void refresh_offsets() noexcept {
    for (std::size_t j = 0; j < n_; ++j)
      for (int a = 0; a < 3; ++a) offset_[j][a] = prev_pos_[j][a] - offsets_centre_m_[a];
    offsets_due_ = false;
  }

  /// The correction decays over dt_s (> 0) by exp(-dt_s / blend_tau_s), computed when dt_s changes.
  void decay_correction(double dt_s) noexcept {
    if (correction_[0] != 0.0 || correction_[1] != 0.0 || correction_[2] != 0.0) {
      const double decay = decay_.at(dt_s, [this](double dt) { return std::exp(-dt / blend_tau_s_); });
      for (int a = 0; a < 3; ++a) correction_[a] *= decay;
    }
  }

  std::size_t n_ = 0;
  double blend_tau_s_ = 0.3;
  double forget_s_ = 2.0;
  bool keeps_seen_ = true;  ///< a marker seen on this frame stays known (forget_s >= 0): the steady case's premise
  std::array<double, kMaxPoints> unseen_s_{};
  std::array<bool, kMaxPoints> known_{};
  std::array<bool, kMaxPoints> prev_visible_{};
  std::array<Vec3, kMaxPoints> offset_{};
  Vec3 correction_{};
  std::array<Vec3, kMaxPoints> prev_pos_{};
  Vec3 last_m_{};  // the last centre returned
  IntervalCache<double> decay_;  ///< the correction's decay at the last intervals
  bool have_prev_ = false;
  bool prev_full_ = false;
  bool steady_ = false;       ///< the next frame is steady if it sees every marker (steady())
  bool offsets_due_ = false;  ///< offset_ is prev_pos_ - offsets_centre_m_, not yet formed
  Vec3 offsets_centre_m_{};   ///< the centre of the last steady frame
};

}  // namespace yoyogait::online
