// Bindings of the lower-back IMU estimator (include/yoyogait/imu/), added to yoyogait._core.
#pragma once

#include <nanobind/nanobind.h>

void bind_imu(nanobind::module_& m);
