/// @file yoyogait.hpp
/// @brief Everything of the yoyogait core: the Yoyo-model, the EKF, the heuristics and the estimator.
#pragma once

#include "yoyogait/config.hpp"
#include "yoyogait/ekf.hpp"
#include "yoyogait/estimator.hpp"
#include "yoyogait/heuristics.hpp"
#include "yoyogait/state.hpp"
#include "yoyogait/yoyo_model.hpp"
