#include "render/occluder_geometry.h"

#include "render/box_mesh.h"
#include "render/horizon_mesh.h"
#include "render/obj_mesh.h"

namespace skypol::render {

std::vector<TriangleMesh> occluder_meshes(const OccluderSpec& spec) {
  const Eigen::Vector3d eye(0, 0, spec.observer_height_m);
  std::vector<TriangleMesh> meshes;
  if (!spec.horizon.empty()) meshes.push_back(horizon_mesh(spec.horizon, kHorizonRadiusM));
  if (!spec.boxes.empty()) {
    TriangleMesh all;
    for (const BoxSpec& b : spec.boxes) {
      const TriangleMesh one = box_mesh(b, eye);
      const auto base = static_cast<std::uint32_t>(all.vertices.size());
      all.vertices.insert(all.vertices.end(), one.vertices.begin(), one.vertices.end());
      for (const auto& t : one.triangles) all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    meshes.push_back(std::move(all));
  }
  for (const MeshSpec& m : spec.meshes) meshes.push_back(place_mesh(m, eye));
  return meshes;
}

std::size_t triangle_count(const std::vector<TriangleMesh>& meshes) {
  std::size_t n = 0;
  for (const TriangleMesh& m : meshes) n += m.size();
  return n;
}

}  // namespace skypol::render
