// Calibration files of other tools → LensSpec, so that a user's calibration drops into a scene as
// it is. Each format keeps its tool's names and parameter order; docs/scenes.md has an example
// of each, docs/conventions.md the pixel-centre rule of each.
//   colmap    cameras.txt: SIMPLE_RADIAL_FISHEYE, RADIAL_FISHEYE, OPENCV_FISHEYE → kannala_brandt,
//             THIN_PRISM_FISHEYE → thin_prism_fisheye, PINHOLE, SIMPLE_PINHOLE → perspective;
//             camera = the CAMERA_ID; cx, cy − 0.5 (COLMAP's pixel centres are at +0.5)
//   opencv    FileStorage YAML or JSON: K + D (cv::fisheye → kannala_brandt) or K + D + xi
//             (cv::omnidir → mei), image_width/image_height or image_size
//   kalibr    camchain YAML: camera_model ds / eucm / omni(+radtan) / pinhole(+equidistant);
//             camera = "cam0", "cam1", ...
//   basalt    calibration.json: camera_type ds / eucm / kb4 / pinhole; camera = index (0, 1, ...)
//   ocamcalib calib_results.txt (centre 0-based row, column: see ocam_lens.h)
// No format stores a field of view: fov_deg is set to what the sensor's farthest corner sees,
// cut where the model stops being one-to-one; a scene's fov_deg overrides it.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "camera/lens_factory.h"

namespace skypol::camera {

struct Calibration {
  std::string format;  // colmap | opencv | kalibr | basalt | ocamcalib
  std::string text;    // the file's contents
  std::string name;    // the file's name, for messages
  std::string camera;  // which camera of a multi-camera file ("" = the only one)
};

const std::vector<std::string_view>& calibration_formats();

// Throws std::invalid_argument "NAME:LINE: message" (the line of the calibration file where the
// problem is): unknown model with the supported ones, wrong parameter count, malformed number,
// missing key, camera not found (listing the ones there are), a selector given to a single-camera
// format.
LensSpec lens_spec_from_calibration(const Calibration& c);

// Sets spec.fov_deg to the angle of the sensor's farthest corner (pixel edges), cut at the
// largest field of view the model accepts. Leaves fov_deg unset if no field of view is accepted.
void fit_fov_to_sensor(LensSpec& spec);

// Sets spec.fov_deg to what a lens whose image circle has `radius_px` pixels' radius about the
// principal point images: twice the smallest angle off the axis of a pixel on that circle (so that
// no pixel beyond the circle is read; where fx ≠ fy, a little of the circle is left out too), cut
// at the largest field of view the model accepts. Throws std::invalid_argument for a radius ≤ 0.
void fit_fov_to_image_circle(LensSpec& spec, double radius_px);

}  // namespace skypol::camera
