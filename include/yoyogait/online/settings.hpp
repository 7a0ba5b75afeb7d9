/// @file online/settings.hpp
/// @brief The online front-end's parts configured from OnlineConfig, setting by setting (what
/// OnlineEstimator's constructor builds its parts from).
#pragma once

#include "yoyogait/online/heading.hpp"
#include "yoyogait/online/online_config.hpp"

namespace yoyogait::online {

/// The heading tracker's settings (heading_tau_s, heading_min_speed_mps).
inline HeadingTracker::Settings heading_settings(const OnlineConfig& c) noexcept {
  HeadingTracker::Settings s;
  s.tau_s = c.heading_tau_s;
  s.min_speed_mps = c.heading_min_speed_mps;
  return s;
}

}  // namespace yoyogait::online
