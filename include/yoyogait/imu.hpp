/// @file imu.hpp
/// @brief The lower-back IMU front-end and ImuOnlineEstimator (docs/imu.md).
#pragma once

#include "yoyogait/imu/harmonic_check.hpp"
#include "yoyogait/imu/imu_config.hpp"
#include "yoyogait/imu/imu_estimate.hpp"
#include "yoyogait/imu/imu_estimator.hpp"
#include "yoyogait/imu/leaky_integrator.hpp"
#include "yoyogait/imu/mag_gate.hpp"
#include "yoyogait/imu/mahony.hpp"
#include "yoyogait/imu/pendulum.hpp"
#include "yoyogait/imu/sample_gaps.hpp"
#include "yoyogait/imu/speed_variance.hpp"
