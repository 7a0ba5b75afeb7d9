/// @file yoyogait.hpp
/// @brief Everything of the yoyogait core: the Yoyo-model, the paper's estimator (EKF, heuristics),
/// the default gait filter and the estimator that runs either.
#pragma once

#include "yoyogait/config.hpp"
#include "yoyogait/estimate.hpp"
#include "yoyogait/estimator.hpp"
#include "yoyogait/forecast.hpp"
#include "yoyogait/gait/gait_filter.hpp"
#include "yoyogait/math.hpp"
#include "yoyogait/paper/ekf.hpp"
#include "yoyogait/paper/heuristics.hpp"
#include "yoyogait/paper/paper_estimator.hpp"
#include "yoyogait/paper/state.hpp"
#include "yoyogait/yoyo_model.hpp"
