// A calibrated polarization camera: a lens, an orientation and the polarization transport through
// the lens. It answers the renderer's one question per pixel: which world direction does this
// pixel see, and which world direction does the sensor's 0° polarizer correspond to there?
#pragma once

#include <cstddef>
#include <memory>
#include <optional>

#include <Eigen/Core>

#include "camera/lens.h"

namespace skypol::camera {

// How the E-field crosses the lens (docs/conventions.md).
//  meridional: an ideal rotationally symmetric lens keeps the components along the meridional
//              and sagittal directions (default; exact for such a lens);
//  projected:  the world E-vector simply projected on the sensor plane (a common approximation;
//              AoLP differs far from the axis, DoLP never does).
enum class Transport { meridional, projected };

// A pixel's view of the world: d the unit direction it looks along (ENU) and e0 the unit world
// vector ⟂ d that the sensor's 0° polarizer (camera +x) corresponds to under meridional transport;
// Stokes vectors evaluated in the basis (e0, d × e0) are the sensor-frame Stokes vectors.
struct CameraRay {
  Eigen::Vector3d d;
  Eigen::Vector3d e0;
};

// Where Camera::ray_row writes: float planes, one value per pixel of the row.
struct RayRowOut {
  float *dx, *dy, *dz;  // CameraRay::d
  float *ux, *uy, *uz;  // CameraRay::e0
  float* valid;         // 1 where ray() answers, else 0 (and then d = +z, e0 = +x)
};

class Camera {
 public:
  Camera(std::shared_ptr<const Lens> lens, const Eigen::Matrix3d& world_from_camera,
         Transport transport = Transport::meridional);

  const Lens& lens() const { return *lens_; }
  const Eigen::Matrix3d& world_from_camera() const { return world_from_camera_; }
  Transport transport() const { return transport_; }
  int width() const { return lens_->intrinsics().width; }
  int height() const { return lens_->intrinsics().height; }

  // nullopt outside the image circle (or where the lens inverse fails).
  std::optional<CameraRay> ray(const Eigen::Vector2d& pixel) const;
  // ray() of the n pixels (x0 + i, y), i < n, cast to float: the renderer's per-stack planes.
  // ray()'s floats, at the cost of the arithmetic (Lens::ray_row, no per-pixel virtual call,
  // optional or heap); the same bits where the lens's ray_row gives ray()'s (Lens::ray_row).
  void ray_row(int y, int x0, std::size_t n, const RayRowOut& out) const;
  // Pixel of a world direction, nullopt if the lens cannot image it.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& dir_world) const;

  // The polarization angle (radians, from sensor +x towards +y) that light polarized at `angle`
  // in the ray's basis (e0, d × e0) shows on the sensor. Identity for meridional transport;
  // projected: wrapped to (−π/2, π/2]; where that E-vector lies along the optical axis (only at
  // θ = 90°) it has no sensor-plane angle and `angle` is returned unchanged.
  double sensor_angle(const CameraRay& ray, double angle) const;

 private:
  std::shared_ptr<const Lens> lens_;
  Eigen::Matrix3d world_from_camera_;
  Transport transport_;
};

// The meridional basis vector e0 in the camera frame for a unit camera-frame direction d:
// e0 = cos φ·m − sin φ·s with m = ∂d/∂θ (meridional), s = ẑ × d/|ẑ × d| (sagittal), φ = atan2(d_y, d_x).
// Equal to camera +x on the axis, continuous everywhere off the backward axis.
Eigen::Vector3d meridional_e0(const Eigen::Vector3d& d_cam);

}  // namespace skypol::camera
