// Defaults shared by all lens models.
#include "camera/lens.h"

#include <stdexcept>

namespace skypol::camera {

std::shared_ptr<const Lens> Lens::rescaled(double /*s*/) const {
  throw std::logic_error("lens model \"" + name() + "\" cannot be rescaled (binning)");
}

}  // namespace skypol::camera
