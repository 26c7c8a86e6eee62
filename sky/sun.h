// The sun's apparent position for an observer, from ERFA (the IAU SOFA routines Debian ships).
// Topocentric azimuth/elevation (with or without refraction), plus the declination and the hour
// angle that the SkyPole analysis is written in.
#pragma once

#include <Eigen/Core>

#include "sky/time.h"

namespace skypol::sky {

// An observer on the WGS84 ellipsoid. Degrees and metres: this is a person-facing value.
struct Site {
  double latitude_deg = 0;   // geodetic, north positive, [−90, 90]
  double longitude_deg = 0;  // east positive
  double height_m = 0;       // above the ellipsoid
};

// Refraction and the Earth-orientation inputs. pressure_hpa = 0 means no refraction (the
// geometric, airless position), which is what skypol's sky models use by default.
struct SunOptions {
  double pressure_hpa = 0;
  double temperature_c = 15;
  double relative_humidity = 0.5;
  double wavelength_um = 0.55;
  double ut1_minus_utc_s = 0;  // |UT1−UTC| < 0.9 s; 0 unless a user supplies IERS values
};

// Radians inside (degrees only at the interfaces a person sees).
struct Sun {
  double azimuth = 0;      // from North towards East, [0, 2π)
  double elevation = 0;    // above the horizon, refracted if SunOptions asked for it
  double declination = 0;  // apparent (CIRS) declination
  double hour_angle = 0;   // local apparent hour angle, (−π, π], 0 at upper culmination
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit vector in ENU towards the sun
};

// Throws std::invalid_argument for a latitude outside [−90°, 90°] or a non-finite input.
Sun sun_position(const Site& site, Instant t, const SunOptions& options = {});

// ENU unit vector from azimuth (from North towards East) and elevation, radians; and back.
Eigen::Vector3d enu_direction(double azimuth, double elevation);
double azimuth_of(const Eigen::Vector3d& enu);    // [0, 2π); 0 for the zenith (documented rule)
double elevation_of(const Eigen::Vector3d& enu);  // [−π/2, π/2]

// The north celestial pole in ENU for a site (the south pole for southern latitudes is its
// negative). Latitude in degrees.
Eigen::Vector3d north_celestial_pole(double latitude_deg);

}  // namespace skypol::sky
