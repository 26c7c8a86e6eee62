// `skypol sun`: the sun's position for a site and instant, to check a scene's sun without rendering.
#include <cstdio>
#include <numbers>
#include <string>

#include "cli/commands.h"
#include "sky/sun.h"
#include "sky/units.h"

namespace skypol::cli {

void add_sun(CLI::App& app) {
  struct Args {
    sky::Site site;
    sky::SunOptions options;
    std::string time;
    std::string refraction = "spa";
  };
  auto a = std::make_shared<Args>();
  CLI::App* sun = app.add_subcommand("sun", "Print the sun's azimuth, elevation, declination and hour angle");
  sun->add_option("--lat", a->site.latitude_deg, "Latitude, degrees north")->required();
  sun->add_option("--lon", a->site.longitude_deg, "Longitude, degrees east")->required();
  sun->add_option("--height", a->site.height_m, "Height above the ellipsoid, metres");
  sun->add_option("-t,--time", a->time, "ISO 8601 instant with zone, e.g. 2022-09-23T12:00:00+02:00")->required();
  sun->add_option("--pressure", a->options.pressure_hpa, "Pressure in hPa for refraction (0: none)");
  sun->add_option("--temperature", a->options.temperature_c, "Temperature in °C for refraction");
  sun->add_option("--humidity", a->options.relative_humidity,
                  "Relative humidity in [0, 1] for refraction (erfa model only), default 0.5");
  sun->add_option("--wavelength", a->options.wavelength_um,
                  "Wavelength in µm for refraction (erfa model only), default 0.55");
  sun->add_option("--refraction", a->refraction,
                  "Refraction model when --pressure > 0: spa (NREL SPA's formula, default) or erfa");
  sun->add_option("--dut1", a->options.ut1_minus_utc_s, "UT1−UTC in seconds (IERS), default 0");
  sun->add_option("--delta-t", a->options.delta_t_s,
                  "ΔT = TT − UT1 in seconds, as SPA takes it (default: TT from ERFA's leap seconds)");
  sun->callback([a] {
    a->options.refraction = sky::parse_refraction(a->refraction);
    const sky::Instant t = sky::parse_iso8601(a->time);
    const sky::Sun s = sky::sun_position(a->site, t, a->options);
    std::printf("time          %s\n", sky::format_iso8601(t).c_str());
    std::printf("site          %.6f N  %.6f E  %.1f m\n", a->site.latitude_deg, a->site.longitude_deg, a->site.height_m);
    std::printf("azimuth       %.6f deg (from North towards East)\n", s.azimuth * kDegPerRad);
    const std::string refracted = a->options.pressure_hpa > 0
                                      ? " (refracted, " + std::string(sky::refraction_name(a->options.refraction)) + ")"
                                      : " (no refraction)";
    std::printf("elevation     %.6f deg%s\n", s.elevation * kDegPerRad, refracted.c_str());
    std::printf("zenith angle  %.6f deg\n", 90 - s.elevation * kDegPerRad);
    std::printf("declination   %.6f deg\n", s.declination * kDegPerRad);
    std::printf("hour angle    %.6f deg\n", s.hour_angle * kDegPerRad);
    std::printf("direction ENU (%.9f, %.9f, %.9f)\n", s.direction.x(), s.direction.y(), s.direction.z());
  });
}

}  // namespace skypol::cli
