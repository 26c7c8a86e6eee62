// Intrinsics from physical numbers, binning, and the image circle / usable field of view.
// Pixel centres follow OpenCV (pixel (0, 0)'s centre at (0, 0)). From MATLAB's calibration
// toolboxes (1-based centres) subtract 1 from cx, cy; from COLMAP (centre at 0.5) subtract 0.5.
#pragma once

#include <memory>

#include <Eigen/Core>

#include "camera/lens.h"

namespace skypol::camera {

// fx = fy = focal_mm / pitch; principal point at the sensor centre ((w − 1)/2, (h − 1)/2).
// Throws std::invalid_argument naming focal_mm, pitch_um, width or height when ≤ 0.
Intrinsics intrinsics_from_mm(double focal_mm, double pitch_um, int width, int height);

// The same lens read out with b×b binning (u' = (u + ½)/b − ½: fx/b, cx' = (cx + 0.5)/b − 0.5,
// width/b rounded down). Throws std::invalid_argument for b < 1.
std::shared_ptr<const Lens> binned(const Lens& lens, int b);

// What the lens draws on the sensor.
struct ImageCircle {
  Eigen::Vector2d centre;     // pixel of the optical axis
  double radius_px = 0;       // largest distance of the θmax circle from the centre
  double max_fov_deg = 0;     // 2·θmax: the lens' full field of view
  double full_circle_fov_deg = 0;  // largest 2θ whose whole circle lands on the sensor
  bool fits_on_sensor = false;     // the whole θmax circle lands on the sensor
};
ImageCircle image_circle(const Lens& lens);

}  // namespace skypol::camera
