// Synthetic stacks for the estimator tests, rendered here pixel by pixel with camera::Camera::ray
// and sky::RayleighSky or Berry's sky (no EXR round trip): an equidistant 185° fisheye, DoLP/AoLP/mask channels
// and the truth the renderer would write.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "stack/frame.h"
#include "sky/time.h"

namespace skypol::testing {

struct SyntheticSpec {
  double latitude_deg = 43.28699;  // the paper's roof in Marseille
  double longitude_deg = 5.40336;
  std::vector<sky::Instant> times;
  double heading_deg = 0;
  double tilt_deg = 0;
  double roll_deg = 0;
  int size = 256;             // square image, image circle touching the borders
  double fov_deg = 185;
  double max_dolp = 1.0;      // Rayleigh Pmax
  std::string sky_model = "rayleigh";  // or "berry" (neutral points 20° from the sun and antisun)
  double noise = 0;           // σ of Gaussian noise on each polarizer intensity, in units of S0/2
  std::uint32_t seed = 1;
  bool with_aolp = true;
  std::string band = "Y";
};

// Times from `start` to `end` inclusive every `step_min` minutes (ISO 8601 with zone).
std::vector<sky::Instant> times_every(const std::string& start, const std::string& end,
                                      double step_min);

// The paper's day: 2022-09-23 every 30 min 08:00–16:00 UTC (17 frames).
std::vector<sky::Instant> paper_times();

// The paper's day seen by a `size`-pixel camera turned to `heading_deg`, under a Rayleigh sky of
// Pmax 0.7 with polarizer noise `noise`: the clear day most estimator tests start from.
SyntheticSpec paper_day(int size, double heading_deg, double noise = 0);

stack::Stack make_stack(const SyntheticSpec& spec);

// What no clear sky shows, confined to one part of the sky in every frame: inside the disc of
// `radius_deg` about the camera direction `centre` (unit), `paint(frame, ray, dolp, aolp)` rewrites
// each pixel's DoLP and AoLP (radians) of `band`; `ray` is the pixel's unit direction, camera frame.
using VeilPaint = std::function<void(std::size_t frame, const Eigen::Vector3d& ray, float& dolp, float& aolp)>;
void veil_disc(stack::Stack& stack, const Eigen::Vector3d& centre, double radius_deg, const VeilPaint& paint,
               const std::string& band = "Y");

// The true celestial pole of the stack's first frame, as a unit direction in the camera frame.
Eigen::Vector3d true_pole_camera(const stack::Stack& stack);

// A cloud parked on `centre` (unit, camera frame): DoLP non-finite within `radius_deg` of it in
// every frame, so no method reads that sky (veil_disc painting NaN).
void mask_disc(stack::Stack& stack, const Eigen::Vector3d& centre, double radius_deg, const std::string& band = "Y");

}  // namespace skypol::testing
