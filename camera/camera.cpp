// Camera = lens + orientation + polarization transport (conventions in camera.h).
#include "camera/camera.h"

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace skypol::camera {

Eigen::Vector3d meridional_e0(const Eigen::Vector3d& d_cam) {
  const double n = d_cam.norm();
  if (!(n > 0) || !std::isfinite(n)) return Eigen::Vector3d::UnitX();
  const Eigen::Vector3d d = d_cam / n;
  // e0 = cos φ·m − sin φ·s = R(ẑ→d)·x̂, R the shortest rotation taking the axis to d:
  //   e0 = (1 − dx²/(1+dz), −dx·dy/(1+dz), −dx).
  // 1 + dz loses its digits near the backward axis; there use 1 + dz = (dx² + dy²)/(1 − dz).
  const double rho2 = d.x() * d.x() + d.y() * d.y();
  const double one_plus_dz = d.z() >= 0 ? 1 + d.z() : rho2 / (1 - d.z());
  if (!(one_plus_dz > 1e-300)) return Eigen::Vector3d(-1, 0, 0);  // θ = π, φ = 0 limit
  const Eigen::Vector3d e0(1 - d.x() * d.x() / one_plus_dz, -d.x() * d.y() / one_plus_dz, -d.x());
  return e0.normalized();  // unit already up to rounding; keep it exactly so
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
  return CameraRay{world_from_camera_ * *d_cam, world_from_camera_ * meridional_e0(*d_cam)};
}

void Camera::ray_row(int y, int x0, std::size_t n, const RayRowOut& out) const {
  // The lens's camera-frame directions in blocks that stay in L1, then the same expressions as
  // ray() (rotation, meridional_e0) per pixel.
  constexpr std::size_t kBlock = 256;
  double cx[kBlock], cy[kBlock], cz[kBlock];
  unsigned char ok[kBlock];
  const Eigen::Matrix3d& r = world_from_camera_;
  for (std::size_t b = 0; b < n; b += kBlock) {
    const std::size_t m = std::min(kBlock, n - b);
    lens_->ray_row(static_cast<double>(y), static_cast<double>(x0) + static_cast<double>(b), m, cx, cy, cz, ok);
    for (std::size_t i = 0; i < m; ++i) {
      const std::size_t k = b + i;
      if (!ok[i]) {
        out.dx[k] = 0, out.dy[k] = 0, out.dz[k] = 1;
        out.ux[k] = 1, out.uy[k] = 0, out.uz[k] = 0;
        out.valid[k] = 0;
        continue;
      }
      const Eigen::Vector3d d_cam(cx[i], cy[i], cz[i]);
      const Eigen::Vector3f d = (r * d_cam).cast<float>();
      const Eigen::Vector3f e0 = (r * meridional_e0(d_cam)).cast<float>();
      out.dx[k] = d.x(), out.dy[k] = d.y(), out.dz[k] = d.z();
      out.ux[k] = e0.x(), out.uy[k] = e0.y(), out.uz[k] = e0.z();
      out.valid[k] = 1;
    }
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
  constexpr double kHalfPi = std::numbers::pi / 2;
  if (a > kHalfPi) a -= std::numbers::pi;
  if (a <= -kHalfPi) a += std::numbers::pi;
  return a;
}

}  // namespace skypol::camera
