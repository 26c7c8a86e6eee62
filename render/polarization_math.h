// Derived polarization quantities over whole images, with the rules for undefined values that
// docs/conventions.md states: DoLP = 0 where S0 ≤ 0; AoLP = 0 where S1 = S2 = 0; AoLP ∈ (−π/2, π/2].
#pragma once

#include <span>
#include <vector>

#include "camera/camera.h"
#include "sky/sky_model.h"

namespace skypol::render {

std::vector<float> dolp_image(std::span<const float> s0, std::span<const float> s1, std::span<const float> s2);
std::vector<float> aolp_image(std::span<const float> s1, std::span<const float> s2);

// The Stokes vector of a sample re-expressed for projected transport (camera/camera.h): same S0
// and degree of polarization, angle mapped by Camera::sensor_angle.
sky::StokesF to_projected(const camera::Camera& camera, const sky::ViewRay& ray, const sky::StokesF& s);

}  // namespace skypol::render
