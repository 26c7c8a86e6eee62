// Lens descriptions from COLMAP and OpenCV calibrations, so their users recognise the numbers.
// COLMAP cameras.txt lines: "CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]" (colmap/sensor/models.h);
//   SIMPLE_RADIAL_FISHEYE: f, cx, cy, k               → kannala_brandt (k, 0, 0, 0)
//   RADIAL_FISHEYE:        f, cx, cy, k1, k2          → kannala_brandt (k1, k2, 0, 0)
//   OPENCV_FISHEYE: fx, fy, cx, cy, k1, k2, k3, k4 → kannala_brandt
//   THIN_PRISM_FISHEYE: fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1 → thin_prism_fisheye
//   PINHOLE:        fx, fy, cx, cy                 → perspective
//   SIMPLE_PINHOLE: f, cx, cy                      → perspective
// COLMAP puts pixel centres at +0.5, skypol (and OpenCV) at 0: cx, cy are shifted by −0.5.
// OpenCV cv::fisheye (K = [fx 0 cx; 0 fy cy], D = k1..k4) needs no shift: fill LensSpec directly.
#pragma once

#include <string_view>

#include "camera/lens_factory.h"

namespace skypol::camera {

// COLMAP stores no field of view: fov_deg is set to reach the farthest sensor corner (for
// kannala_brandt cut at the polynomial's turning point, clamp_fov_to_monotone = true). Override
// it with the lens' real field of view when you know it. Throws std::invalid_argument naming the
// problem (unsupported model with the supported ones, wrong parameter count, bad number).
LensSpec lens_spec_from_colmap(std::string_view cameras_txt_line);

}  // namespace skypol::camera
