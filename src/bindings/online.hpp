// Bindings of the online estimator (include/yoyogait/online/), added to yoyogait._core.
#pragma once

#include <nanobind/nanobind.h>

void bind_online(nanobind::module_& m);
