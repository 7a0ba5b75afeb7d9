/// @file gait_filter.hpp
/// @brief The default estimator, yoyogait::GaitFilter: see yoyogait/gait/gait_filter.hpp (this
/// path is kept for code that includes it).
#pragma once

#include "yoyogait/gait/gait_filter.hpp"
