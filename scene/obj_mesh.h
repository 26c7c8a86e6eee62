// Triangle meshes from Wavefront OBJ files (tinyobjloader; polygons are triangulated, materials,
// normals and texture coordinates ignored), and their placement in ENU (scene/occluder_spec.h).
#pragma once

#include <string>

#include <Eigen/Core>

#include "scene/occluder_spec.h"
#include "scene/triangle_mesh.h"

namespace skypol::scene {

// The file's vertices and triangles as written. Throws std::invalid_argument with a message that
// says what is wrong (unreadable, no triangles, a coordinate that is not finite).
TriangleMesh load_obj(const std::string& path);

// mesh.triangles placed by mesh's position, yaw, scale and axes, shifted by -offset.
TriangleMesh place_mesh(const MeshSpec& mesh, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero());

}  // namespace skypol::scene
