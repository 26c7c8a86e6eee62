// The sun's apparent position for an observer, from ERFA (the IAU SOFA routines Debian ships).
// Topocentric azimuth/elevation (with or without refraction), plus the declination and the hour
// angle that the SkyPole analysis is written in.
#pragma once

#include <optional>
#include <string_view>

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
// geometric, airless position), which is what skypol's sky models use by default. With pressure,
// the refraction model is one of two (docs/conventions.md, "Sun position"):
//   spa  (default) NREL SPA's (Reda & Andreas 2008, NREL/TP-560-34302, eq. 42):
//        Δe = (P/1010)(283/(273 + T))·1.02/(60·tan(e0 + 10.3/(e0 + 5.11))) degrees, e0 the
//        airless topocentric elevation in degrees, applied only while e0 ≥ −(0.26667° + 0.5667°)
//        (SPA's sun radius plus its atmos_refract; below that SPA refracts nothing). Humidity and
//        wavelength are not used. skypol then agrees with SPA's own outputs to < 0.0005° wherever
//        SPA refracts, the horizon included (tests/sky/sun_test.cpp).
//   erfa ERFA's eraRefco/eraAtioq, A·tan z + B·tan³ z from pressure, temperature, humidity and
//        wavelength: good to ~1″ above 15° elevation, degrades towards the horizon and is capped
//        below ~3° (finite, not accurate, for a sun at or under it). It refracts ~5 % less than
//        SPA's formula at 60° zenith (0.0013° at Auckland, 2010-06-15 00:30 UTC).
// Time scales: UT1 = UTC + ut1_minus_utc_s. TT = UT1 + delta_t_s when delta_t_s is given (SPA's
// ΔT input, to reproduce a published SPA case exactly); otherwise ERFA forms TT from UTC with its
// leap-second table (TT = UTC + ΔAT + 32.184 s), the better choice for the years it covers.
enum class Refraction { spa, erfa };

// "spa" | "erfa"; throws std::invalid_argument listing the legal names.
Refraction parse_refraction(std::string_view name);
std::string_view refraction_name(Refraction r);

struct SunOptions {
  double pressure_hpa = 0;
  double temperature_c = 15;
  double relative_humidity = 0.5;  // erfa refraction only
  double wavelength_um = 0.55;     // erfa refraction only
  double ut1_minus_utc_s = 0;  // |UT1−UTC| < 0.9 s; 0 unless a user supplies IERS values
  Refraction refraction = Refraction::spa;
  std::optional<double> delta_t_s;  // ΔT = TT − UT1 in seconds, |ΔT| ≤ 8000 (SPA's range)
};

// Radians inside (degrees only at the interfaces a person sees).
// declination and hour_angle are ERFA's *observed* (eraAtioq's dob, hob) place: the apparent (CIRS)
// equatorial coordinates seen from the site, i.e. topocentric (parallax ≤ 8.8″ and diurnal
// aberration included) and refracted only when SunOptions asked for refraction. They are exactly
// the equatorial coordinates of `direction` for this latitude, so SkyPole's SI eq. 1 and
// S·NCP = sin δ (SI eq. 4) hold to rounding. Polar motion is taken as zero.
struct Sun {
  double azimuth = 0;      // from North towards East, [0, 2π)
  double elevation = 0;    // above the horizon, refracted if SunOptions asked for it
  double declination = 0;  // apparent declination, topocentric (see above)
  double hour_angle = 0;   // local apparent hour angle, (−π, π], 0 at upper culmination, > 0 after it
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit vector in ENU towards the sun
};

// Throws std::invalid_argument for a latitude outside [−90°, 90°], a non-finite input, or options
// out of range (pressure < 0, humidity outside [0, 1], wavelength ≤ 0, |UT1−UTC| ≥ 1 s,
// |ΔT| > 8000 s).
// At a pole the azimuth follows ERFA's rule: "north" is the limit along the site's meridian.
Sun sun_position(const Site& site, Instant t, const SunOptions& options = {});

// A sun placed by hand (scenes that fix the sun instead of a time, hard cases such as a sun at
// the zenith): azimuth and elevation in radians, latitude in degrees. Declination and hour angle
// follow from SkyPole's SI eq. 1 inverted, so the Sun is as self-consistent as sun_position's.
// Throws std::invalid_argument for a latitude outside [−90°, 90°] or non-finite angles.
Sun sun_from_horizontal(double azimuth, double elevation, double latitude_deg);

// ENU unit vector from azimuth (from North towards East) and elevation, radians; and back.
Eigen::Vector3d enu_direction(double azimuth, double elevation);
double azimuth_of(const Eigen::Vector3d& enu);    // [0, 2π); 0 for the zenith (documented rule)
double elevation_of(const Eigen::Vector3d& enu);  // [−π/2, π/2]

// The north celestial pole in ENU for a site: (0, cos φ, sin φ); the south celestial pole is its
// negative (the visible one for southern latitudes). Latitude in degrees; throws outside ±90°.
Eigen::Vector3d north_celestial_pole(double latitude_deg);

}  // namespace skypol::sky
