#include "render/occluder_geometry.h"

#include "scene/box_mesh.h"
#include "render/horizon_mesh.h"
#include "scene/obj_mesh.h"

namespace skypol::render {

std::vector<scene::TriangleMesh> occluder_meshes(const scene::OccluderSpec& spec) {
  const Eigen::Vector3d eye(0, 0, spec.observer_height_m);
  std::vector<scene::TriangleMesh> meshes;
  if (!spec.horizon.empty()) meshes.push_back(horizon_mesh(spec.horizon, kHorizonRadiusM));
  if (!spec.boxes.empty()) {
    scene::TriangleMesh all;
    for (const scene::BoxSpec& b : spec.boxes) {
      const scene::TriangleMesh one = scene::box_mesh(b, eye);
      const auto base = static_cast<std::uint32_t>(all.vertices.size());
      all.vertices.insert(all.vertices.end(), one.vertices.begin(), one.vertices.end());
      for (const auto& t : one.triangles) all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    meshes.push_back(std::move(all));
  }
  for (const scene::MeshSpec& m : spec.meshes) meshes.push_back(scene::place_mesh(m, eye));
  return meshes;
}

std::size_t triangle_count(const std::vector<scene::TriangleMesh>& meshes) {
  std::size_t n = 0;
  for (const scene::TriangleMesh& m : meshes) n += m.size();
  return n;
}

}  // namespace skypol::render
