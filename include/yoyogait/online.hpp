/// @file online.hpp
/// @brief The online front-end and OnlineEstimator (docs/online.md).
#pragma once

#include "yoyogait/online/belt.hpp"
#include "yoyogait/online/centre.hpp"
#include "yoyogait/online/decimator.hpp"
#include "yoyogait/online/differentiator.hpp"
#include "yoyogait/online/frame.hpp"
#include "yoyogait/online/gait_phase.hpp"
#include "yoyogait/online/heading.hpp"
#include "yoyogait/online/latency.hpp"
#include "yoyogait/online/lowpass.hpp"
#include "yoyogait/online/online_config.hpp"
#include "yoyogait/online/online_estimate.hpp"
#include "yoyogait/online/online_estimator.hpp"
#include "yoyogait/online/settings.hpp"
#include "yoyogait/online/velocity_noise.hpp"
