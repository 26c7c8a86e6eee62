// The field checks that the lens models' entries share (camera/lens_registry.h): each throws
// std::invalid_argument with a message that starts with the field it names, so that the scene
// language reports it at that key.
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "camera/intrinsics.h"
#include "camera/lens_factory.h"

namespace skypol::camera::detail {

[[noreturn]] void lens_fail(const std::string& message);

// A value as the messages print it (no trailing zeros).
std::string lens_number(double x);

// *v, which must be finite and > 0 ("<field> must be > 0").
double positive(const std::optional<double>& v, const char* field);

// Scale and principal point for the models that take fx, fy, cx, cy (or focal_mm with pitch_um).
Intrinsics pinhole_intrinsics(const LensSpec& s);

// Half of fov_deg in radians; 0 when absent and not required.
double half_fov(const LensSpec& s, bool required);

// "coefficients: <model> needs n (<order>), got m" unless there are n.
void need_coefficients(const LensSpec& s, std::size_t n, const char* order);

}  // namespace skypol::camera::detail
