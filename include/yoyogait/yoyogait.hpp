/// @file yoyogait.hpp
/// @brief Everything of the yoyogait core: the Yoyo-model, the paper's EKF and heuristics, the
/// default gait filter and the estimator that runs either.
#pragma once

#include "yoyogait/config.hpp"
#include "yoyogait/ekf.hpp"
#include "yoyogait/estimator.hpp"
#include "yoyogait/gait_filter.hpp"
#include "yoyogait/heuristics.hpp"
#include "yoyogait/state.hpp"
#include "yoyogait/yoyo_model.hpp"
