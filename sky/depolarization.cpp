#include "sky/depolarization.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace skypol::sky {

double max_dolp_from_turbidity(double turbidity) {
  if (!(std::isfinite(turbidity) && turbidity >= 1.0)) {
    throw std::invalid_argument("turbidity " + std::to_string(turbidity) +
                                " must be ≥ 1 (1 = a pure molecular atmosphere)");
  }
  return std::min(1.0, std::exp(-(turbidity - 0.6) / 4.0));
}

}  // namespace skypol::sky
