// sun_azimuth: north and latitude from the sun's azimuths and the clock alone — a celestial fix
// that a multiply scattering sky does not bias.
//
// Why azimuths. In a horizontally uniform atmosphere over a uniform ground the polarized sky is
// mirror-symmetric about the sun's vertical plane at every order of scattering, whatever the
// aerosol, so the sun that sun_from_aolp finds (the direction most nearly ⟂ the E-vectors, a
// symmetric quadratic form of a symmetric field: its eigenvectors lie in the symmetry plane or ⟂
// to it) lies in that plane: its azimuth is unbiased. Its elevation is not: multiple scattering
// turns the E-vectors near the neutral points and the horizon, which moves the fitted sun along
// its vertical, alike in every frame and sector, where no jackknife sees it. So this method reads
// only the level-frame azimuths a_t of the suns.
//
// Why the clock is enough. The sun's geocentric direction at the frames' UTC times needs no site
// (ERFA, sky::sun_position); an observer at latitude φ and longitude λ sees it from its place on
// the Earth, i.e. in ENU the geocentric direction less the observer's offset from the centre (the
// sun's parallax, ≤ 8.8″, so that the fit holds to 10⁻⁴°),
// and at level-frame azimuth A_t(φ, λ) − ψ, ψ the camera's heading (estimate.h). The fit finds
// (φ, λ, ψ) minimising Σ [cos e_t · wrap(a_t − A_t + ψ)]²: the azimuth residual times the cosine of
// the sun's measured elevation is its angle across the vertical plane, the size of the sun fit's
// error whatever the elevation (a sun near the zenith has an ill-defined azimuth and counts
// little). It starts from the best point of a grid over (φ, λ) (ψ in closed form at each: the
// circular mean of A_t − a_t) and refines by Levenberg–Marquardt. The pole is then the site's
// celestial pole placed with that heading; which pole is north follows from the model (the sun
// turns westward), so no hemisphere rule is needed. Refraction moves the sun only in elevation, so
// the fit needs no pressure or temperature either.
//
// What it cannot see: over a short window the azimuths lie nearly on a line in time, which fixes
// only two combinations of the three unknowns: the frame jackknife then spreads and the stated cone
// is wide, or the fit declines (uncertainty.h). A second minimum of the fit whose cost is within the
// noise of the first (the window does not decide between two sites) is a decline, never a guess.
// Cloud, clipping or a tilted camera make the sampled sky unequal on the two sides of the sun's
// vertical; the sector jackknife measures what that costs.
// residual_deg: the RMS of the weighted azimuth residuals at the fit. latitude_deg of the estimate
// is φ; the fitted longitude is in the note.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "sky/time.h"
#include "skypole/estimate.h"
#include "skypole/stack_sky.h"

namespace skypol::skypole {

struct SunAzimuthParams {
  InputOptions input;
  double min_dolp = 0.05;  // sun_from_aolp's
  // A second minimum of the fit whose cost is below (1 + this) × the best one's is an ambiguity.
  double ambiguity_margin = 1.0;
};

// The fix itself, from level-frame suns (unit vectors, above the horizon) at UTC times.
struct AzimuthFix {
  bool ok = false;
  std::string why;        // when !ok
  double latitude_deg = 0;
  double longitude_deg = 0;
  double heading_deg = 0;  // world azimuth = level azimuth + heading
  double rms_rad = 0;      // RMS of cos e · azimuth residual
  double elevation_rms_deg = 0;  // RMS of the measured suns' elevations less the fitted site's
};
AzimuthFix fix_from_sun_azimuths(const std::vector<Eigen::Vector3d>& suns_level,
                                 const std::vector<sky::Instant>& times, double ambiguity_margin = 1.0);

// Needs the "AoLP.<band>" channel, at least 3 frames and their times.
PoleEstimate estimate_sun_azimuth(const SkyView& view, const SunAzimuthParams& params = {});
PoleEstimate estimate_sun_azimuth(const stack::Stack& stack, const SunAzimuthParams& params = {});

}  // namespace skypol::skypole
