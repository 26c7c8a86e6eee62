// The two sets of sky points whose Rayleigh DoLP is the same at two times (SkyPole SI eqs. 2–10),
// as the SI writes them: altitude θ as a function of azimuth α (from North towards East) for an
// observer at latitude φ, the sun at hour angles ω1, ω2 and a declination δ held constant.
//   Set 1, radial invariance (S1·P = S2·P, SI eq. 7):
//     tan θ = (cos α sin φ tan m − sin α) / (cos φ tan m),  m = (ω1 + ω2)/2;
//   Set 2, plane invariance (S1·P = −S2·P, SI eq. 10):
//     tan θ = (sin α cos δ [sin ω1 + sin ω2] + cos α (−2 sin δ cos φ + cos δ sin φ [cos ω1 + cos ω2]))
//             / (cos δ cos φ [cos ω1 + cos ω2] + 2 sin δ sin φ).
// Both are great circles; every Set 1 passes through the celestial pole (α = 0, θ = φ), which is
// what SkyPole finds. Hour angles as sky::Sun::hour_angle (0 at upper culmination, > 0 after it).
// Radians throughout. Where a denominator vanishes the circle passes through the zenith and θ is
// ±π/2 for every α on its side (atan2 keeps this finite: no NaN, never a division by zero).
#pragma once

namespace skypol::skypole {

double radial_invariance_altitude(double azimuth, double latitude, double omega1, double omega2);
double plane_invariance_altitude(double azimuth, double latitude, double declination,
                                 double omega1, double omega2);

}  // namespace skypol::skypole
