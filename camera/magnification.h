// How much a lens stretches the sky: radial and tangential magnification (Sun et al. 2019,
// eq. 22: β_r = P'Q'/PQ along the meridian, β_t = P'S'/PS along the parallel of constant θ),
// in pixels per radian of arc on the unit sphere, for any Lens (central differences of project()).
// For the ideal mappings they are eqs. 23–28: equidistant β_r = f, β_t = f·θ/sin θ; equisolid
// f·cos(θ/2), f/cos(θ/2); stereographic both f/cos²(θ/2).
#pragma once

#include <optional>

#include "camera/lens.h"

namespace skypol::camera {

struct Magnification {
  double radial_px = 0;      // pixels per radian along the meridian
  double tangential_px = 0;  // pixels per radian of arc across it (sin θ·dφ)
};

// At angle θ off the axis (radians) and azimuth φ about it; nullopt beyond the field of view.
// On the axis the tangential value is the radial one (the limit).
std::optional<Magnification> magnification(const Lens& lens, double theta, double phi);

}  // namespace skypol::camera
