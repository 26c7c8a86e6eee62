// Defaults shared by all lens models.
#include "camera/lens.h"

#include <numbers>
#include <stdexcept>

namespace skypol::camera {

std::shared_ptr<const Lens> Lens::rescaled(double /*s*/) const {
  throw std::logic_error("lens model \"" + name() + "\" cannot be rescaled (binning)");
}

std::vector<std::pair<std::string, double>> Lens::parameters() const {
  const Intrinsics& k = intrinsics();
  return {{"fx", k.fx},
          {"fy", k.fy},
          {"cx", k.cx},
          {"cy", k.cy},
          {"width", k.width},
          {"height", k.height},
          {"fov_deg", 2 * max_field_angle() * 180 / std::numbers::pi}};
}

}  // namespace skypol::camera
