// The sun's place for an observer, with ERFA (IAU SOFA).
//
// Chain (all ERFA, IAU 2006/2000A; the steps of eraApco13, spelled out so that TT can come from a
// given ΔT instead of the leap-second table):
//   eraDtf2d   UTC calendar fields → ERFA's two-part quasi-JD UTC (leap-second aware)
//   eraUtcut1  UT1 = UTC + ut1_minus_utc_s
//   TT         UT1 + ΔT when SunOptions::delta_t_s is given (SPA's way), else eraUtctai + eraTaitt
//              (TT = UTC + ΔAT + 32.184 s from ERFA's leap-second table)
//   eraApco    everything that depends on the site and the instant: the Earth's barycentric and
//              heliocentric position and velocity (eraEpv00), precession-nutation (eraPnm06a,
//              eraBpn2xy, eraS06), Earth rotation angle (eraEra00), TIO locator (eraSp00), the
//              observer's geocentric position (WGS84), refraction constants (eraRefco, only for
//              Refraction::erfa with pressure > 0; zero otherwise)
//   the sun    its direction from the observer is −astrom.eh (eh = Sun→observer unit vector, which
//              already includes the observer's offset from the geocentre, i.e. parallax); light time
//              is neglected (the Sun moves ~12 m/s about the barycentre: < 0.01″ in 8.3 min)
//   eraAb      aberration by the observer's barycentric velocity (annual + diurnal; eraApco puts
//              the diurnal part into v and sets diurab = 0)
//   eraRxp     bias-precession-nutation: BCRS direction → CIRS
//   eraAtioq   CIRS → observed azimuth, zenith distance, hour angle, declination (refracted by
//              ERFA's A·tan z + B·tan³ z for Refraction::erfa)
//   SPA        for Refraction::spa, SPA's eq. 42 lifts the airless elevation (sun.h); the
//              declination and hour angle are then those of the refracted direction (SI eq. 1
//              inverted, as sun_from_horizontal), so that they stay its equatorial coordinates.
//
// UT1−UTC defaults to 0 (|UT1−UTC| < 0.9 s, i.e. < 0.004° of hour angle) and is taken from
// SunOptions when a user has IERS Bulletin A values.
#include "sky/sun.h"

#include <erfa.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>

#include "sky/units.h"

namespace skypol::sky {
namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw std::invalid_argument(message);
}

void check_site(const Site& site) {
  require(std::isfinite(site.latitude_deg) && site.latitude_deg >= -90.0 && site.latitude_deg <= 90.0,
          "site latitude " + std::to_string(site.latitude_deg) +
              "° is outside [−90°, 90°] (geodetic latitude, north positive)");
  require(std::isfinite(site.longitude_deg),
          "site longitude must be a finite number of degrees (east positive)");
  require(std::isfinite(site.height_m) && site.height_m > -12000.0 && site.height_m < 100000.0,
          "site height " + std::to_string(site.height_m) +
              " m above the WGS84 ellipsoid is outside (−12 km, 100 km)");
}

void check_options(const SunOptions& o) {
  require(std::isfinite(o.pressure_hpa) && o.pressure_hpa >= 0.0,
          "pressure " + std::to_string(o.pressure_hpa) + " hPa must be ≥ 0 (0 = no refraction)");
  require(std::isfinite(o.temperature_c) && o.temperature_c > -150.0 && o.temperature_c < 200.0,
          "temperature " + std::to_string(o.temperature_c) + " °C is outside (−150, 200)");
  require(std::isfinite(o.relative_humidity) && o.relative_humidity >= 0.0 && o.relative_humidity <= 1.0,
          "relative humidity " + std::to_string(o.relative_humidity) + " must be in [0, 1]");
  require(std::isfinite(o.wavelength_um) && o.wavelength_um > 0.0,
          "wavelength " + std::to_string(o.wavelength_um) + " µm must be > 0");
  require(std::isfinite(o.ut1_minus_utc_s) && std::abs(o.ut1_minus_utc_s) < 1.0,
          "UT1−UTC " + std::to_string(o.ut1_minus_utc_s) + " s must be within ±1 s (IERS keeps it < 0.9 s)");
  require(!o.delta_t_s || (std::isfinite(*o.delta_t_s) && std::abs(*o.delta_t_s) <= 8000.0),
          "ΔT = TT − UT1 " + std::to_string(o.delta_t_s.value_or(0.0)) +
              " s must be within ±8000 s (SPA's range)");
  require(o.refraction == Refraction::spa || o.refraction == Refraction::erfa,
          "unknown refraction model (expected spa or erfa)");
}

// SPA's refraction (Reda & Andreas 2008, eq. 42 and its applicability rule in spa.c), degrees.
constexpr double kSpaSunRadiusDeg = 0.26667;
constexpr double kSpaAtmosRefractDeg = 0.5667;
double spa_refraction_deg(double e0_deg, double pressure_hpa, double temperature_c) {
  if (!(e0_deg >= -(kSpaSunRadiusDeg + kSpaAtmosRefractDeg))) return 0.0;
  return (pressure_hpa / 1010.0) * (283.0 / (273.0 + temperature_c)) * 1.02 /
         (60.0 * std::tan((e0_deg + 10.3 / (e0_deg + 5.11)) * kRadPerDeg));
}

// (−π, π]
double wrap_pm_pi(double a) {
  a = std::remainder(a, 2.0 * kPi);  // [−π, π]
  return a <= -kPi ? a + 2.0 * kPi : a;
}

// [0, 2π)
double wrap_2pi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  if (a < 0) a += 2.0 * kPi;
  return a >= 2.0 * kPi ? 0.0 : a;
}

}  // namespace

Refraction parse_refraction(std::string_view name) {
  if (name == "spa") return Refraction::spa;
  if (name == "erfa") return Refraction::erfa;
  throw std::invalid_argument("unknown refraction model \"" + std::string(name) +
                              "\" (expected one of spa, erfa)");
}

std::string_view refraction_name(Refraction r) { return r == Refraction::erfa ? "erfa" : "spa"; }

Sun sun_position(const Site& site, Instant t, const SunOptions& options) {
  check_site(site);
  check_options(options);
  require(std::isfinite(t.unix_seconds), "the instant is not a finite time");

  const CalendarUtc cal = to_calendar(t);
  double utc1 = 0, utc2 = 0;
  const int dtf = eraDtf2d("UTC", cal.year, cal.month, cal.day, cal.hour, cal.minute, cal.second, &utc1, &utc2);
  require(dtf >= 0, "ERFA cannot represent the instant " + format_iso8601(t) + " as UTC");

  // Status +1 is ERFA's "dubious year" (outside its leap-second table, e.g. decades ahead or
  // before 1960): the result is still the best available, so it is used; −1 is a date ERFA
  // cannot handle.
  const std::string rejected = "ERFA rejects the instant " + format_iso8601(t) + " (unacceptable date)";
  double ut11 = 0, ut12 = 0, tt1 = 0, tt2 = 0;
  require(eraUtcut1(utc1, utc2, options.ut1_minus_utc_s, &ut11, &ut12) >= 0, rejected);
  if (options.delta_t_s) {
    tt1 = ut11;
    tt2 = ut12 + *options.delta_t_s / 86400.0;
  } else {
    double tai1 = 0, tai2 = 0;
    require(eraUtctai(utc1, utc2, &tai1, &tai2) >= 0, rejected);
    eraTaitt(tai1, tai2, &tt1, &tt2);
  }

  // eraApco13's steps with our TT.
  double ehpv[2][3], ebpv[2][3];
  eraEpv00(tt1, tt2, ehpv, ebpv);
  double npb[3][3];
  eraPnm06a(tt1, tt2, npb);
  double x = 0, y = 0;
  eraBpn2xy(npb, &x, &y);
  const double s_cio = eraS06(tt1, tt2, x, y);
  const double theta = eraEra00(ut11, ut12);
  const double sp = eraSp00(tt1, tt2);
  const bool refract = options.pressure_hpa > 0.0;
  double refa = 0, refb = 0;
  if (refract && options.refraction == Refraction::erfa) {
    eraRefco(options.pressure_hpa, options.temperature_c, options.relative_humidity, options.wavelength_um,
             &refa, &refb);
  }
  eraASTROM astrom{};
  eraApco(tt1, tt2, ebpv, ehpv[0], x, y, s_cio, theta, site.longitude_deg * kRadPerDeg, site.latitude_deg * kRadPerDeg,
          site.height_m, 0.0, 0.0, sp, refa, refb, &astrom);

  double pnat[3] = {-astrom.eh[0], -astrom.eh[1], -astrom.eh[2]};
  double ppr[3];
  eraAb(pnat, astrom.v, astrom.em, astrom.bm1, ppr);
  double pcirs[3];
  eraRxp(astrom.bpn, ppr, pcirs);
  double ri = 0, di = 0;
  eraC2s(pcirs, &ri, &di);
  double aob = 0, zob = 0, hob = 0, dob = 0, rob = 0;
  eraAtioq(ri, di, &astrom, &aob, &zob, &hob, &dob, &rob);

  if (refract && options.refraction == Refraction::spa) {
    const double e0_deg = 90.0 - zob / kRadPerDeg;
    const double lift_deg = spa_refraction_deg(e0_deg, options.pressure_hpa, options.temperature_c);
    if (lift_deg != 0.0) return sun_from_horizontal(aob, (e0_deg + lift_deg) * kRadPerDeg, site.latitude_deg);
  }

  Sun sun;
  sun.azimuth = wrap_2pi(aob);
  sun.elevation = kPi / 2 - zob;
  sun.declination = dob;
  sun.hour_angle = wrap_pm_pi(hob);
  sun.direction = enu_direction(sun.azimuth, sun.elevation);
  return sun;
}

Sun sun_from_horizontal(double azimuth, double elevation, double latitude_deg) {
  require(std::isfinite(azimuth) && std::isfinite(elevation), "sun azimuth and elevation must be finite");
  const Eigen::Vector3d ncp = north_celestial_pole(latitude_deg);  // checks the latitude
  Sun sun;
  sun.azimuth = wrap_2pi(azimuth);
  sun.elevation = std::clamp(elevation, -kPi / 2, kPi / 2);
  sun.direction = enu_direction(sun.azimuth, sun.elevation);
  // SI eq. 1: E = −cos δ sin ω, and cos δ cos ω = Z cos φ − N sin φ; sin δ = S·NCP.
  const double phi = latitude_deg * kRadPerDeg;
  const Eigen::Vector3d& s = sun.direction;
  const double cos_dec_cos_ha = s.z() * std::cos(phi) - s.y() * std::sin(phi);
  sun.declination = std::atan2(s.dot(ncp), std::hypot(s.x(), cos_dec_cos_ha));
  sun.hour_angle = (s.x() == 0.0 && cos_dec_cos_ha == 0.0) ? 0.0 : wrap_pm_pi(std::atan2(-s.x(), cos_dec_cos_ha));
  return sun;
}

Eigen::Vector3d enu_direction(double azimuth, double elevation) {
  const double ce = std::cos(elevation);
  return {ce * std::sin(azimuth), ce * std::cos(azimuth), std::sin(elevation)};
}

double azimuth_of(const Eigen::Vector3d& enu) {
  if (enu.x() == 0.0 && enu.y() == 0.0) return 0.0;  // the zenith/nadir: documented rule
  return wrap_2pi(std::atan2(enu.x(), enu.y()));
}

double elevation_of(const Eigen::Vector3d& enu) {
  // atan2 rather than asin: exact at the zenith and tolerant of a vector that is not quite unit.
  return std::atan2(enu.z(), std::hypot(enu.x(), enu.y()));
}

Eigen::Vector3d north_celestial_pole(double latitude_deg) {
  require(std::isfinite(latitude_deg) && latitude_deg >= -90.0 && latitude_deg <= 90.0,
          "latitude " + std::to_string(latitude_deg) + "° is outside [−90°, 90°]");
  const double phi = latitude_deg * kRadPerDeg;
  return {0.0, std::cos(phi), std::sin(phi)};
}

}  // namespace skypol::sky
