// The sun for many times, as a dict of NumPy arrays (shared by skypol.sun_position and
// Scene.sun_positions).
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "sky/sun.h"

namespace skypol::python {

using Seconds = pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast>;

// Keys azimuth_deg, elevation_deg, declination_deg, hour_angle_deg (1-D) and direction (N×3, ENU).
pybind11::dict sun_table(const sky::Site& site, const sky::SunOptions& options,
                         const Seconds& unix_seconds);
pybind11::dict sun_options_to_dict(const sky::SunOptions& options);

}  // namespace skypol::python
