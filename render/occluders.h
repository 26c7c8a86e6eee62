// What blocks the sky: buildings, a horizon profile, meshes. The renderer asks one question of it:
// does the ray from the observer (ENU origin) along each direction hit anything? The Embree
// implementation lives behind this interface so that nothing else includes embree3/rtcore.h, and
// a scene without occluders never creates one (DESIGN.md: pay for what the scene asks for).
#pragma once

#include <cstdint>
#include <span>

#include <Eigen/Core>

namespace skypol::render {

class Occluders {
 public:
  virtual ~Occluders() = default;
  // out[i] = 1 if the ray from the origin along dirs[i] (unit, ENU) hits geometry, else 0.
  virtual void occluded(std::span<const Eigen::Vector3f> dirs, std::span<std::uint8_t> out) const = 0;
};

}  // namespace skypol::render
