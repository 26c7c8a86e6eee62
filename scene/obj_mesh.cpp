#include "scene/obj_mesh.h"

#include <cmath>
#include <stdexcept>

#include <tiny_obj_loader.h>

#include "scene/box_mesh.h"

namespace skypol::scene {

TriangleMesh load_obj(const std::string& path) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config)) {
    std::string why = reader.Error();
    while (!why.empty() && (why.back() == '\n' || why.back() == '\r')) why.pop_back();
    throw std::invalid_argument("cannot read OBJ file " + path + (why.empty() ? "" : ": " + why));
  }
  TriangleMesh mesh;
  const std::vector<tinyobj::real_t>& v = reader.GetAttrib().vertices;
  for (std::size_t i = 0; i + 2 < v.size(); i += 3) {
    const Eigen::Vector3f p(static_cast<float>(v[i]), static_cast<float>(v[i + 1]), static_cast<float>(v[i + 2]));
    if (!p.allFinite()) {
      throw std::invalid_argument("OBJ file " + path + ": vertex " + std::to_string(i / 3 + 1) + " is not finite");
    }
    mesh.vertices.push_back(p);
  }
  const auto count = static_cast<long long>(mesh.vertices.size());
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const std::vector<tinyobj::index_t>& idx = shape.mesh.indices;
    std::size_t at = 0;
    for (const unsigned char corners : shape.mesh.num_face_vertices) {
      if (corners == 3) {
        std::array<std::uint32_t, 3> t{};
        for (std::size_t c = 0; c < 3; ++c) {
          const long long k = idx[at + c].vertex_index;
          if (k < 0 || k >= count) {
            throw std::invalid_argument("OBJ file " + path + ": a face in '" + shape.name +
                                        "' refers to a vertex that does not exist");
          }
          t[c] = static_cast<std::uint32_t>(k);
        }
        mesh.triangles.push_back(t);
      }
      at += corners;  // lines and points (if any) are skipped
    }
  }
  if (mesh.triangles.empty()) throw std::invalid_argument("OBJ file " + path + " has no faces");
  return mesh;
}

TriangleMesh place_mesh(const MeshSpec& spec, const Eigen::Vector3d& offset) {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  // y-up files: x East, y Up, z South.
  if (spec.y_up) axes << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  const Eigen::Matrix3d m = yaw_rotation(spec.yaw_deg) * spec.scale * axes;
  TriangleMesh out;
  out.triangles = spec.triangles.triangles;
  out.vertices.reserve(spec.triangles.vertices.size());
  for (const Eigen::Vector3f& v : spec.triangles.vertices) {
    out.vertices.push_back((spec.position_m + m * v.cast<double>() - offset).cast<float>());
  }
  return out;
}

}  // namespace skypol::scene
