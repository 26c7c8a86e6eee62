// Defaults shared by all lens models.
#include "camera/lens.h"

#include <numbers>
#include <stdexcept>

#include "sky/units.h"

namespace skypol::camera {

std::shared_ptr<const Lens> Lens::rescaled(double /*s*/) const {
  throw std::logic_error("lens model \"" + name() + "\" cannot be rescaled (binning)");
}

void Lens::ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                   unsigned char* valid) const {
  for (std::size_t i = 0; i < n; ++i) {
    const std::optional<Eigen::Vector3d> d = ray(Eigen::Vector2d(x0 + static_cast<double>(i), y));
    valid[i] = d ? 1 : 0;
    const Eigen::Vector3d v = d ? *d : Eigen::Vector3d::UnitZ();
    dx[i] = v.x(), dy[i] = v.y(), dz[i] = v.z();
  }
}

std::vector<std::pair<std::string, double>> Lens::parameters() const {
  const Intrinsics& k = intrinsics();
  return {{"fx", k.fx},
          {"fy", k.fy},
          {"cx", k.cx},
          {"cy", k.cy},
          {"width", k.width},
          {"height", k.height},
          {"fov_deg", deg_from_rad(2 * max_field_angle())}};
}

}  // namespace skypol::camera
