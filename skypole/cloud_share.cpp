// The unpolarized share of the sky (cloud_share.h).
#include "skypole/cloud_share.h"

#include <cmath>
#include <numbers>

namespace skypol::skypole {

double unpolarized_share(const SkyImages& sky) {
  if (sky.frames() == 0 || sky.valid_count == 0) return 0.0;
  const auto suns = find_suns(sky, sky.dolp);
  const double cos40 = std::cos(40.0 * std::numbers::pi / 180.0);
  double total = 0;
  for (std::size_t f = 0; f < sky.frames(); ++f) {
    const std::vector<float>& img = sky.dolp[f];
    const float cut = 0.2f * valid_quantile(img, sky, 0.99);
    std::size_t low = 0, counted = 0;
    for (std::size_t i = 0; i < img.size(); ++i) {
      if (!sky.valid[i]) continue;
      if (suns[f]) {
        const double c = sky.ray_camera[i].cast<double>().dot(*suns[f]);
        if (std::abs(c) > cos40) continue;  // near the sun (c > 0) or the antisun (c < 0)
      }
      ++counted;
      low += img[i] < cut ? 1 : 0;
    }
    total += counted ? static_cast<double>(low) / static_cast<double>(counted) : 0.0;
  }
  return total / static_cast<double>(sky.frames());
}

}  // namespace skypol::skypole
