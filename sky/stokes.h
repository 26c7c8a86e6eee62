// Stokes vectors and the one rotation between reference frames.
// A Stokes vector means nothing without its basis (see docs/conventions.md): skypol always states
// it as a pair of unit vectors (e0, e90) transverse to the viewing direction d, with e90 = d × e0.
// The polarizer angle is measured from e0 towards e90, i.e. "seen from the sensor, looking back
// along the propagation direction" (Mitsuba 3's convention). In the sensor frame e0 is camera +x.
#pragma once

namespace skypol::sky {

struct Stokes {
  double s0 = 0;  // radiance, relative units
  double s1 = 0;  // I(0°) − I(90°)
  double s2 = 0;  // I(45°) − I(135°)
  double s3 = 0;  // circular; 0 for single scattering

  // √(S1²+S2²)/S0, and 0 where S0 = 0 (documented rule: no light carries no polarization).
  double dolp() const;
  // ½·atan2(S2, S1) in (−π/2, π/2], radians; 0 where S1 = S2 = 0 (documented rule).
  double aolp() const;
};

// The same light described in a basis turned by `angle` (radians) from e0 towards e90:
// S1' = S1 cos 2a + S2 sin 2a, S2' = −S1 sin 2a + S2 cos 2a (Collett, ch. 5). The only frame
// rotation in skypol.
Stokes rotate_reference(const Stokes& s, double angle);

// Linearly polarized light of radiance s0, degree `dolp` and angle `aolp` (radians) in the basis.
Stokes from_polarization(double s0, double dolp, double aolp);

}  // namespace skypol::sky
