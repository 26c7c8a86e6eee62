// What blocks the sky: buildings, a horizon profile, meshes. The renderer asks one question of it:
// does the ray from the observer's eye along each direction hit anything? The Embree
// implementation (render/occluders_embree.h) lives behind this interface so that nothing else
// includes embree3/rtcore.h, and a scene without occluders never creates one (a scene pays only for
// what it asks for).
#pragma once

#include <cstdint>
#include <span>

#include <Eigen/Core>

namespace skypol::render {

class Occluders {
 public:
  virtual ~Occluders() = default;
  // out[i] = 1 if the ray from the eye along dirs[i] (unit, ENU) hits geometry, else 0.
  // out.size() == dirs.size(). Safe to call from many threads at once.
  virtual void occluded(std::span<const Eigen::Vector3f> dirs, std::span<std::uint8_t> out) const = 0;

  // Whether occluded pixels show a shaded surface (scene::OccludedPixels::shaded) instead of nothing.
  virtual bool shaded() const { return false; }
  // out[i] = S0 of the surface the ray along dirs[i] meets first (scene/occluder_spec.h's shaded
  // rule), 0 where it meets none. Only called when shaded().
  virtual void surface_s0(std::span<const Eigen::Vector3f> dirs, std::span<float> out) const {
    for (float& v : out) v = 0;
    static_cast<void>(dirs);
  }
};

}  // namespace skypol::render
