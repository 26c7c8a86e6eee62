// Triangles as plain arrays: what the occluder builders (horizon, boxes, OBJ files) produce and
// what the Embree scene is made of. Single precision, as Embree stores it.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace skypol::scene {

struct TriangleMesh {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;  // indices into vertices

  std::size_t size() const { return triangles.size(); }
};

}  // namespace skypol::scene
