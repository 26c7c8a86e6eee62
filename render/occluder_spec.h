// What a scene's [occluders] section asks for, as checked plain values (docs/scenes.md). Empty
// when the scene names no occluders: then no Embree device or BVH is ever created.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace skypol::render {

struct OccluderSpec {
  // Filled by the occluder loader (render/scene_occluders.cpp).
  bool empty() const { return true; }
};

}  // namespace skypol::render
