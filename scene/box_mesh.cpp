#include "scene/box_mesh.h"

#include <cmath>
#include <numbers>

#include "sky/units.h"

namespace skypol::scene {

Eigen::Matrix3d yaw_rotation(double yaw_deg) {
  const double t = rad_from_deg(yaw_deg), c = std::cos(t), s = std::sin(t);
  Eigen::Matrix3d r;
  // East (1,0,0) goes to (c, −s, 0) and North (0,1,0) to (s, c, 0): clockwise seen from above.
  r << c, s, 0, -s, c, 0, 0, 0, 1;
  return r;
}

TriangleMesh box_mesh(const BoxSpec& box, const Eigen::Vector3d& offset) {
  const Eigen::Matrix3d r = yaw_rotation(box.yaw_deg);
  TriangleMesh mesh;
  // Corner k has bit 0 = +x, bit 1 = +y, bit 2 = top.
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d local((k & 1 ? 0.5 : -0.5) * box.size_m.x(), (k & 2 ? 0.5 : -0.5) * box.size_m.y(),
                                k & 4 ? box.size_m.z() : 0.0);
    mesh.vertices.push_back((box.position_m + r * local - offset).cast<float>());
  }
  // Two triangles per face, wound counter-clockwise seen from outside.
  mesh.triangles = {{0, 2, 1}, {1, 2, 3},   // bottom (z = 0)
                    {4, 5, 6}, {5, 7, 6},   // top
                    {0, 1, 4}, {1, 5, 4},   // −y
                    {2, 6, 3}, {3, 6, 7},   // +y
                    {0, 4, 2}, {2, 4, 6},   // −x
                    {1, 3, 5}, {3, 7, 5}};  // +x
  return mesh;
}

bool box_contains(const BoxSpec& box, const Eigen::Vector3d& p) {
  const Eigen::Vector3d local = yaw_rotation(box.yaw_deg).transpose() * (p - box.position_m);
  return std::abs(local.x()) <= 0.5 * box.size_m.x() && std::abs(local.y()) <= 0.5 * box.size_m.y() &&
         local.z() >= 0 && local.z() <= box.size_m.z();
}

}  // namespace skypol::scene
