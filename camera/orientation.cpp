// Orientation conventions are defined in orientation.h; this file only builds the matrices.
#include "camera/orientation.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sky/units.h"

namespace skypol::camera {
namespace {

Eigen::Matrix3d rot_x(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix();
}
Eigen::Matrix3d rot_z(double a) {
  return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// The starting camera: zenith-pointing, image-up North → columns x = West, y = South, z = Up.
Eigen::Matrix3d zenith_north_up() {
  Eigen::Matrix3d c0;
  c0.col(0) = Eigen::Vector3d(-1, 0, 0);
  c0.col(1) = Eigen::Vector3d(0, -1, 0);
  c0.col(2) = Eigen::Vector3d(0, 0, 1);
  return c0;
}

double azimuth_deg(double east, double north) {
  double a = std::atan2(east, north) / kRadPerDeg;
  if (a < 0) a += 360.0;
  if (a >= 360.0) a -= 360.0;  // -0.0 + 360 rounding
  return a;
}

}  // namespace

Eigen::Matrix3d world_from_heading_tilt_roll(double heading_deg, double tilt_deg, double roll_deg) {
  if (!std::isfinite(heading_deg)) throw std::invalid_argument("heading_deg must be finite");
  if (!std::isfinite(roll_deg)) throw std::invalid_argument("roll_deg must be finite");
  if (!std::isfinite(tilt_deg) || tilt_deg < 0 || tilt_deg > 180)
    throw std::invalid_argument("tilt_deg must be in [0, 180], got " + std::to_string(tilt_deg));
  return rot_z(-heading_deg * kRadPerDeg) * zenith_north_up() * rot_x(tilt_deg * kRadPerDeg) *
         rot_z(roll_deg * kRadPerDeg);
}

Eigen::Matrix3d world_from_quaternion(double w, double x, double y, double z) {
  if (!std::isfinite(w) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    throw std::invalid_argument("quaternion must be finite");
  Eigen::Quaterniond q(w, x, y, z);
  if (q.norm() < 1e-12) throw std::invalid_argument("quaternion must not be zero");
  return q.normalized().toRotationMatrix();
}

double heading_deg_of(const Eigen::Matrix3d& world_from_camera) {
  const Eigen::Vector3d axis = world_from_camera.col(2);
  if (std::hypot(axis.x(), axis.y()) > 1e-9) return azimuth_deg(axis.x(), axis.y());
  // Axis vertical: heading and roll are one rotation; report it all as heading (roll 0).
  // Zenith camera: image-up (−y) faces ψ. Nadir camera (tilted over by 180°): image-down (+y).
  const Eigen::Vector3d v = axis.z() > 0 ? Eigen::Vector3d(-world_from_camera.col(1))
                                         : Eigen::Vector3d(world_from_camera.col(1));
  return azimuth_deg(v.x(), v.y());
}

}  // namespace skypol::camera
