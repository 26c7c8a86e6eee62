// Closed-form radial and tangential magnification of the five ideal radial mappings (Sun et al.
// 2019 eqs. 22–28, where they are written for equidistant, equisolid and stereographic; the same
// derivation, β_r = f·dr/dθ and β_t = f·r(θ)/sin θ, for perspective and orthographic). The oracle
// against which camera/magnification.h's numerical derivatives of any Lens are checked.
#pragma once

#include <cmath>

#include "camera/magnification.h"
#include "camera/radial_lens.h"

namespace skypol::camera {

// At field angle θ (radians, 0 ≤ θ within the mapping's domain) for focal length f in pixels.
// On the axis β_t is the limit, equal to β_r (= f for every mapping).
inline Magnification ideal_magnification(Mapping mapping, double theta, double f_px) {
  const double c = std::cos(theta), h = std::cos(theta / 2);
  const double s = std::sin(theta);
  const bool axis = std::abs(theta) < 1e-12;
  Magnification m;
  switch (mapping) {
    case Mapping::perspective:  // r = tan θ
      m.radial_px = f_px / (c * c);
      m.tangential_px = f_px / c;
      break;
    case Mapping::stereographic:  // r = 2 tan(θ/2): eqs. 27–28
      m.radial_px = f_px / (h * h);
      m.tangential_px = f_px / (h * h);
      break;
    case Mapping::equidistant:  // r = θ: eqs. 23–24
      m.radial_px = f_px;
      m.tangential_px = axis ? f_px : f_px * theta / s;
      break;
    case Mapping::equisolid:  // r = 2 sin(θ/2): eqs. 25–26
      m.radial_px = f_px * h;
      m.tangential_px = f_px / h;
      break;
    case Mapping::orthographic:  // r = sin θ ("vertical projection")
      m.radial_px = f_px * c;
      m.tangential_px = f_px;
      break;
  }
  return m;
}

}  // namespace skypol::camera
