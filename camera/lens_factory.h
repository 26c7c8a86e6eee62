// Builds any lens model from a plain description, so the scene loader needs no model-specific
// code. Every check happens here and in the model's entry (lens_registry.h; pbrt's Create habit):
// the models' constructors only see checked values, and an error names the offending field.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "camera/lens.h"

namespace skypol::camera {

struct LensSpec {
  // A registered model (lens_list.h): perspective | stereographic | equidistant | equisolid |
  // orthographic | kannala_brandt | double_sphere | ocam | tabulated | thin_prism_fisheye | mei | eucm
  std::string model;
  int width = 0, height = 0;  // sensor pixels; required except for ocam (from the file)
  // Scale: fx [fy defaults to fx] in pixels, or focal_mm with pitch_um (not both).
  // tabulated: pitch_um converts the table's mm to pixels; focal_mm and fx are not used.
  std::optional<double> fx, fy, focal_mm, pitch_um;
  std::optional<double> cx, cy;   // principal point, OpenCV centres; default ((w−1)/2, (h−1)/2)
  std::optional<double> fov_deg;  // full field of view 2θmax; required except ocam/tabulated
  std::optional<double> skew;     // mei: K(0,1) of cv::omnidir, pixels (default 0)
  // kannala_brandt: k1 k2 k3 k4; double_sphere: xi alpha; thin_prism_fisheye: k1 k2 p1 p2 k3 k4
  // sx1 sy1 (COLMAP's order); mei: xi k1 k2 p1 p2; eucm: alpha beta
  std::vector<double> coefficients;
  std::vector<std::pair<double, double>> table;  // tabulated: (field angle deg, height mm)
  std::string ocamcalib_path;                    // ocam: calib_results.txt
  std::string ocamcalib_text;  // ocam: that file's contents; when set, the file is not opened
  bool clamp_fov_to_monotone = false;  // kannala_brandt: cut the FOV at a turning point
  int binning = 1;                     // b×b binning applied after building (≥ 1)
};

// Throws std::invalid_argument naming the field: "focal_mm must be > 0", "principal point off
// the sensor (cx = 3000, width = 2448)", "distortion curve not monotone over the declared field
// of view (turns over at 87.3°)", an unknown model with the legal names, a field the model
// does not use ("coefficients: not used by model equidistant").
std::shared_ptr<const Lens> make_lens(const LensSpec& spec);

// The legal values of LensSpec::model: the registered models' names (lens_registry.h), in order.
const std::vector<std::string_view>& lens_model_names();

}  // namespace skypol::camera
