// A building box (scene/occluder_spec.h: base centre, size, yaw) as 12 triangles.
#pragma once

#include <Eigen/Core>

#include "scene/occluder_spec.h"
#include "scene/triangle_mesh.h"

namespace skypol::scene {

// Rotation about Up by yaw_deg from North towards East (clockwise seen from above, as an azimuth).
Eigen::Matrix3d yaw_rotation(double yaw_deg);

// The box's corners and faces in ENU, shifted by -offset (the renderer puts the eye at the origin).
TriangleMesh box_mesh(const BoxSpec& box, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero());

// Whether point p (ENU) lies inside the box or on its surface.
bool box_contains(const BoxSpec& box, const Eigen::Vector3d& p);

}  // namespace skypol::scene
