// Sun et al. 2019 (Sensors 19:4844, §2.3 and §3) in simulation: the Rayleigh sky as a zenith
// fisheye of each ideal radial mapping (camera/radial_lens.h, their eq. 7) images it, all on one
// square pixel grid with the field-of-view edge on the same image circle; their DoP and AoP, the
// per-pixel differences between two mappings, and the paper's similarity ε (the share of pixels
// whose AoP differs by less than 5°).
//
// AoP is the paper's: the angle of the E-vector from the local meridian, α of their eq. 3, which is
// −AoLP in skypol's meridian basis (tests/sky/fisheye_forms_test.cpp checks eqs. 12–21 that way);
// degrees in (−90, 90]. At a pixel the two conventions differ by the pixel's image angle only, which
// every radial mapping shares, so differences and ε are the same in either.
// Orientation: heading 0, so image top = North and image right = West (the sky seen from below);
// the paper draws the map view (x = East to the right): flip the columns to compare pictures.
#pragma once

#include <cstdint>
#include <vector>

#include "camera/radial_lens.h"
#include "sky/sky_model.h"
#include "sky/sun.h"

namespace skypol::studies {

struct ModeImage {
  camera::Mapping mapping = camera::Mapping::equidistant;
  int size = 0;                        // size × size pixels, row-major
  double fov_deg = 0;                  // full field of view on the image circle
  std::vector<float> dop;              // DoLP (0 outside)
  std::vector<float> aop_deg;          // the paper's AoP (0 outside)
  std::vector<float> theta_deg;        // zenith angle the pixel sees (0 outside)
  std::vector<float> azimuth_deg;      // its azimuth, from North towards East (0 outside)
  std::vector<std::uint8_t> inside;    // 1 = within the field of view
};

// Image circle radius size/2 pixels (principal point at the grid centre), f = (size/2) / r(θmax)
// with θmax = fov/2. Throws std::invalid_argument for a field of view the mapping cannot image.
ModeImage render_mode(camera::Mapping mapping, int size, double fov_deg, const sky::SkyModel& sky,
                      const sky::Sun& sun);

// a − b per pixel, 0 where either image is outside: DoP, and AoP wrapped to (−90, 90].
std::vector<float> dop_difference(const ModeImage& a, const ModeImage& b);
std::vector<float> aop_difference_deg(const ModeImage& a, const ModeImage& b);

// Which pixels count. `a` is the camera whose field of view is meant (as the paper crops its
// measured equidistant image): pixels inside both images whose zenith angle in `a` is at most
// max_theta_deg; with anti_sun_half, only those whose azimuth is more than 90° from the sun's.
struct Region {
  double max_theta_deg = 90;
  bool anti_sun_half = false;
};

struct Similarity {
  double epsilon = 0;   // similar / pixels, in [0, 1]; 0 when no pixel counts
  long pixels = 0;
  long similar = 0;     // |ΔAoP| < threshold
};

// Throws std::invalid_argument when the images' sizes differ.
Similarity similarity(const ModeImage& a, const ModeImage& b, const sky::Sun& sun,
                      const Region& region, double threshold_deg = 5.0);

}  // namespace skypol::studies
