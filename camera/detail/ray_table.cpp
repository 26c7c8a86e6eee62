#include "camera/detail/ray_table.h"

#include <numbers>

namespace skypol::camera::detail {

const SinCosTable& sincos_table() {
  static const SinCosTable t = [] {
    SinCosTable s{};
    for (int i = 0; i <= SinCosTable::kNodes; ++i) {
      s.theta[i] = i * (std::numbers::pi / SinCosTable::kNodes);
      s.s[i] = std::sin(s.theta[i]);
      s.c[i] = std::cos(s.theta[i]);
    }
    return s;
  }();
  return t;
}

}  // namespace skypol::camera::detail
