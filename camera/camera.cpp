// Camera = lens + orientation + polarization transport (conventions in camera.h).
#include "camera/camera.h"

#include "camera/detail/ray_kernels.h"
#include "sky/units.h"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace skypol::camera {
namespace {

detail::Rotation rows(const Eigen::Matrix3d& m) {
  return {m(0, 0), m(0, 1), m(0, 2), m(1, 0), m(1, 1), m(1, 2), m(2, 0), m(2, 1), m(2, 2)};
}

}  // namespace

Eigen::Vector3d meridional_e0(const Eigen::Vector3d& d_cam) {
  // e0 = cos φ·m − sin φ·s = R(ẑ→d)·x̂, R the shortest rotation taking the axis to d (the
  // arithmetic, shared with ray_row's loops, is in detail/ray_kernels.h).
  Eigen::Vector3d e0;
  detail::meridional_e0(d_cam.x(), d_cam.y(), d_cam.z(), e0.x(), e0.y(), e0.z());
  return e0;
}

Camera::Camera(std::shared_ptr<const Lens> lens, const Eigen::Matrix3d& world_from_camera,
               Transport transport)
    : lens_(std::move(lens)), world_from_camera_(world_from_camera), transport_(transport) {
  if (!lens_) throw std::invalid_argument("camera needs a lens");
  const Eigen::Matrix3d& r = world_from_camera_;
  if (!r.allFinite() || (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-9 ||
      std::abs(r.determinant() - 1) > 1e-9)
    throw std::invalid_argument("world_from_camera must be a rotation (orthonormal, det +1)");
}

std::optional<CameraRay> Camera::ray(const Eigen::Vector2d& pixel) const {
  const auto d_cam = lens_->ray(pixel);
  if (!d_cam) return std::nullopt;
  // detail::rotate rather than Eigen's product: ray_row's loops round the same way (ray_kernels.h).
  const detail::Rotation r = rows(world_from_camera_);
  const Eigen::Vector3d e0 = meridional_e0(*d_cam);
  CameraRay out;
  detail::rotate(r, d_cam->x(), d_cam->y(), d_cam->z(), out.d.x(), out.d.y(), out.d.z());
  detail::rotate(r, e0.x(), e0.y(), e0.z(), out.e0.x(), out.e0.y(), out.e0.z());
  return out;
}

void Camera::ray_row(int y, int x0, std::size_t n, const RayRowOut& out) const {
  // The lens's camera-frame directions in blocks that stay in L1, then rotation and meridional_e0
  // in one vector loop (detail::world_rays): ray()'s arithmetic, so ray()'s bits.
  constexpr std::size_t kBlock = 256;
  double cx[kBlock], cy[kBlock], cz[kBlock];
  unsigned char ok[kBlock];
  const detail::Rotation r = rows(world_from_camera_);
  for (std::size_t b = 0; b < n; b += kBlock) {
    const std::size_t m = std::min(kBlock, n - b);
    lens_->ray_row(static_cast<double>(y), static_cast<double>(x0) + static_cast<double>(b), m, cx, cy, cz, ok);
    std::size_t lo, hi;
    detail::valid_span(m, [&](std::size_t i) { return ok[i] != 0; }, lo, hi);
    detail::world_rays(r, m, lo, hi, cx, cy, cz, ok, out.dx + b, out.dy + b, out.dz + b, out.ux + b, out.uy + b, out.uz + b,
                       out.valid + b);
  }
}

std::optional<Eigen::Vector2d> Camera::project(const Eigen::Vector3d& dir_world) const {
  return lens_->project(world_from_camera_.transpose() * dir_world);
}

double Camera::sensor_angle(const CameraRay& ray, double angle) const {
  if (transport_ == Transport::meridional) return angle;
  // Projected: the world E-vector at `angle` in (e0, d × e0), seen in the camera frame with its
  // component along the optical axis dropped.
  const Eigen::Vector3d e1 = ray.d.cross(ray.e0);
  const Eigen::Vector3d e_cam =
      world_from_camera_.transpose() * (std::cos(angle) * ray.e0 + std::sin(angle) * e1);
  // E along the optical axis (possible only at θ = 90°) projects to nothing: no defined angle;
  // fall back to the meridional one (documented rule; that light gives no modulation anyway).
  if (std::hypot(e_cam.x(), e_cam.y()) < 1e-12) return angle;
  double a = std::atan2(e_cam.y(), e_cam.x());
  if (a > kPi / 2) a -= kPi;
  if (a <= -kPi / 2) a += kPi;
  return a;
}

}  // namespace skypol::camera
