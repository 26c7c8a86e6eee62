#include "render/horizon_mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sky/units.h"

namespace skypol::render {
namespace {

constexpr double kMaxStepDeg = 0.5;
constexpr double kToleranceDeg = 1e-4;

Eigen::Vector3f enu(double azimuth_deg, double elevation_deg, double radius) {
  const double az = rad_from_deg(azimuth_deg), el = rad_from_deg(elevation_deg);
  return (radius * Eigen::Vector3d(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el)))
      .cast<float>();
}

double elevation_deg_of(const Eigen::Vector3d& v) { return deg_from_rad(std::atan2(v.z(), std::hypot(v.x(), v.y()))); }
double azimuth_deg_of(const Eigen::Vector3d& v) { return deg_from_rad(std::atan2(v.x(), v.y())); }

}  // namespace

double horizon_elevation_deg(const std::vector<scene::HorizonPoint>& profile, double azimuth_deg) {
  if (profile.size() == 1) return profile.front().elevation_deg;
  double az = std::fmod(azimuth_deg, 360.0);
  if (az < 0) az += 360;
  // The segment [a, b) that holds az; the last one wraps to the first point + 360°.
  auto next = std::upper_bound(profile.begin(), profile.end(), az,
                               [](double v, const scene::HorizonPoint& p) { return v < p.azimuth_deg; });
  const scene::HorizonPoint& b0 = next == profile.end() ? profile.front() : *next;
  const scene::HorizonPoint& a = next == profile.begin() ? profile.back() : *(next - 1);
  double a_az = a.azimuth_deg, b_az = b0.azimuth_deg;
  if (b_az <= a_az) b_az += 360;         // the wrapping segment
  if (az < a_az) az += 360;              // az before the first point: on the wrapping segment
  const double t = (az - a_az) / (b_az - a_az);
  return a.elevation_deg + t * (b0.elevation_deg - a.elevation_deg);
}

namespace {

// The largest distance, in elevation, between the rule and the chords of [a, b] cut into `steps`,
// probed at each chord's quarter, middle and three-quarter points.
double chord_error_deg(const std::vector<scene::HorizonPoint>& profile, double a, double b, int steps) {
  double worst = 0;
  for (int s = 0; s < steps; ++s) {
    const double a0 = a + (b - a) * s / steps, a1 = a + (b - a) * (s + 1) / steps;
    const Eigen::Vector3d p0 = enu(a0, horizon_elevation_deg(profile, a0), 1).cast<double>();
    const Eigen::Vector3d p1 = enu(a1, horizon_elevation_deg(profile, a1), 1).cast<double>();
    for (double t : {0.25, 0.5, 0.75}) {
      const Eigen::Vector3d q = p0 + t * (p1 - p0);
      worst = std::max(worst, std::abs(elevation_deg_of(q) - horizon_elevation_deg(profile, azimuth_deg_of(q))));
    }
  }
  return worst;
}

}  // namespace

scene::TriangleMesh horizon_mesh(const std::vector<scene::HorizonPoint>& profile, double radius_m) {
  // Sample azimuths: every profile point, and enough between them that no step exceeds 0.5° and
  // the straight edge between two samples stays within kToleranceDeg of the rule (a steep slope
  // needs finer steps: the chord is a great circle, the rule is linear in azimuth).
  std::vector<double> azimuths;
  const std::size_t n = profile.size();
  const double start = profile.front().azimuth_deg;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = profile[i].azimuth_deg;
    const double b = n == 1 ? a + 360 : (i + 1 < n ? profile[i + 1].azimuth_deg : start + 360);
    int steps = std::max(1, static_cast<int>(std::ceil((b - a) / kMaxStepDeg - 1e-9)));
    while (steps < (1 << 20) && chord_error_deg(profile, a, b, steps) > kToleranceDeg) steps *= 2;
    for (int s = 0; s < steps; ++s) azimuths.push_back(a + (b - a) * s / steps);
  }
  double lowest = 0;
  for (const scene::HorizonPoint& p : profile) lowest = std::min(lowest, p.elevation_deg);
  const double floor_deg = std::max(lowest - 1, -89.5);

  // Vertices: profile samples 0..m−1, ring below them m..2m−1, the floor's centre 2m.
  scene::TriangleMesh mesh;
  const auto m = static_cast<std::uint32_t>(azimuths.size());
  for (double az : azimuths) mesh.vertices.push_back(enu(az, horizon_elevation_deg(profile, az), radius_m));
  for (double az : azimuths) mesh.vertices.push_back(enu(az, floor_deg, radius_m));
  mesh.vertices.emplace_back(0.0f, 0.0f, static_cast<float>(radius_m * std::sin(rad_from_deg(floor_deg))));
  for (std::uint32_t i = 0; i < m; ++i) {
    const std::uint32_t j = (i + 1) % m;
    mesh.triangles.push_back({i, j, m + i});          // wall
    mesh.triangles.push_back({j, m + j, m + i});
    mesh.triangles.push_back({m + i, m + j, 2 * m});  // floor
  }
  return mesh;
}

}  // namespace skypol::render
