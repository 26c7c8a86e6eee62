// A lens model: the map between directions in the camera frame and pixels, both ways.
// Camera frame: x = image right (columns), y = image down (rows), z = optical axis (out of the
// lens, into the scene). Pixel (u, v)'s centre is at continuous coordinate (u, v) (OpenCV).
// Every model in camera/ has this shape (COLMAP's habit): the parameter order is written once
// beside the model, with the paper or library it matches.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace skypol::camera {

// Pinhole-style intrinsics in pixels, shared by the radial models.
struct Intrinsics {
  double fx = 1, fy = 1;  // focal length in pixels (f_mm / pitch_mm)
  double cx = 0, cy = 0;  // principal point, pixel-centre convention of OpenCV
  int width = 0, height = 0;
};

class Lens {
 public:
  virtual ~Lens() = default;
  virtual std::string name() const = 0;
  virtual const Intrinsics& intrinsics() const = 0;

  // Pixel of a camera-frame direction (any length > 0), or nullopt beyond the usable field of
  // view. The pixel may fall outside the sensor; callers check bounds.
  virtual std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& dir_cam) const = 0;

  // Unit camera-frame direction of a pixel, or nullopt outside the image circle or where the
  // inverse does not converge. Never NaN.
  virtual std::optional<Eigen::Vector3d> ray(const Eigen::Vector2d& pixel) const = 0;

  // ray() of the n pixels (x0 + i, y), i < n, in one call: d{x,y,z}[i] the unit direction and
  // valid[i] = 1, or valid[i] = 0 and d = (0, 0, 1) where ray() gives nullopt. Validity is
  // exactly ray()'s; the directions are ray()'s bits for the closed forms and within 1e-12 rad of
  // them for the tabulated inverses of Kannala–Brandt, thin prism and Mei (camera/detail/ray_table.h;
  // tests/camera/ray_row_test). A model overrides it to drop the per-pixel virtual call, optional
  // and iteration. The base version calls ray() per pixel, so a new model works unchanged.
  virtual void ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                       unsigned char* valid) const;

  // The largest angle off the optical axis the lens images (radians; > π/2 for a 185° fisheye).
  virtual double max_field_angle() const = 0;

  // The same lens seen through a resampled pixel grid u' = s·(u + ½) − ½, v' likewise, on a
  // sensor of floor(s·width) × floor(s·height) pixels: s = 1/b for b×b binning, s < 1 for a
  // downscale. Every model in camera/ implements it; the base version throws std::logic_error.
  virtual std::shared_ptr<const Lens> rescaled(double s) const;

  // The model's parameters by name, in its documented order (for file headers and logs; angles
  // in degrees). Base version: fx, fy, cx, cy, width, height, fov_deg.
  virtual std::vector<std::pair<std::string, double>> parameters() const;
};

}  // namespace skypol::camera
