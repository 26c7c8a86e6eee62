// Scoring and the small conversions of estimate.h.
#include "skypole/estimate.h"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

#include <Eigen/Geometry>

#include "sky/units.h"
#include "skypole/enum_names.h"

namespace skypol::skypole {
namespace {
}

constexpr EnumNames<Hemisphere, 3> kHemisphereNames{
    {{Hemisphere::automatic, "automatic"}, {Hemisphere::north, "north"}, {Hemisphere::south, "south"}}};

Hemisphere parse_hemisphere(std::string_view name) {
  return enum_from_name(kHemisphereNames, name, "hemisphere");
}
std::string_view hemisphere_name(Hemisphere h) { return enum_name(kHemisphereNames, h); }

constexpr EnumNames<PolarizerModel, 3> kPolarizerModelNames{{{PolarizerModel::from_stack, "stack"},
                                                              {PolarizerModel::always, "always"},
                                                              {PolarizerModel::never, "never"}}};

PolarizerModel parse_polarizer_model(std::string_view name) {
  return enum_from_name(kPolarizerModelNames, name, "--polarizer-model");
}

PolarizerFit polarizer_fit(const stack::Frame& frame, PolarizerModel model) {
  const bool modelled = model == PolarizerModel::always || (model == PolarizerModel::from_stack &&
                                                            frame.polarizer_angles == stack::PolarizerAngles::nominal);
  return modelled ? PolarizerFit::modelled : PolarizerFit::plain;
}

double wrap180(double deg) {
  double a = std::fmod(deg, 360.0);
  if (a > 180.0) a -= 360.0;
  if (a <= -180.0) a += 360.0;
  return a;
}

std::string format_heading(double deg, int decimals) {
  const double unit = std::pow(10.0, decimals);
  double r = wrap360(std::round(wrap360(deg) * unit) / unit);
  if (r == 0) r = 0;  // no "-0.000"
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, r);
  return buf;
}

double wrap360(double deg) {
  double a = std::fmod(deg, 360.0);
  if (a < 0) a += 360.0;
  if (a >= 360.0) a -= 360.0;
  return a;
}

Score score(const PoleEstimate& estimate, const scene::Truth& truth) {
  if (!estimate.valid)
    throw std::invalid_argument("cannot score an invalid " + estimate.method +
                                " estimate: " + estimate.why_invalid);
  Score s;
  const Eigen::Vector3d true_ncp =
      (truth.pole_is_north ? truth.pole_enu : Eigen::Vector3d(-truth.pole_enu)).normalized();
  const Eigen::Vector3d est_ncp =
      (truth.world_from_camera *
       (estimate.is_north ? estimate.pole_camera : Eigen::Vector3d(-estimate.pole_camera)))
          .normalized();
  s.angular_error_deg = std::atan2(true_ncp.cross(est_ncp).norm(), true_ncp.dot(est_ncp)) / kRadPerDeg;
  s.latitude_error_deg = estimate.latitude_deg - truth.site.latitude_deg;
  // The true bearing exists unless the NCP is at the zenith or nadir (a geographic pole).
  const bool truth_defined = std::hypot(true_ncp.x(), true_ncp.y()) > 1e-9;
  if (truth_defined && estimate.heading_deg)
    s.bearing_error_deg = wrap180(*estimate.heading_deg - truth.heading_deg);
  return s;
}

}  // namespace skypol::skypole
