// The five ideal radial mappings (Sun et al. 2019 eq. 7) with their closed-form inverses.
#include "camera/radial_lens.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace skypol::camera {
namespace {

constexpr double kPi = std::numbers::pi;

struct MappingInfo {
  Mapping mapping;
  std::string_view name;
  double theta_limit;  // largest θmax the mapping can image
  bool limit_inclusive;
};

// perspective: tan θ is infinite at 90°; orthographic: sin θ turns over at 90° (90° itself is
// the edge of the image circle); stereographic: 2 tan(θ/2) is infinite at 180°.
constexpr std::array<MappingInfo, 5> kMappings = {{
    {Mapping::perspective, "perspective", kPi / 2, false},
    {Mapping::stereographic, "stereographic", kPi, false},
    {Mapping::equidistant, "equidistant", kPi, true},
    {Mapping::equisolid, "equisolid", kPi, true},
    {Mapping::orthographic, "orthographic", kPi / 2, true},
}};

const MappingInfo& info(Mapping m) {
  for (const auto& i : kMappings)
    if (i.mapping == m) return i;
  throw std::invalid_argument("unknown lens mapping");
}

void check_intrinsics(const Intrinsics& k) {
  if (!(std::isfinite(k.fx) && k.fx > 0)) throw std::invalid_argument("fx must be > 0");
  if (!(std::isfinite(k.fy) && k.fy > 0)) throw std::invalid_argument("fy must be > 0");
  if (!std::isfinite(k.cx)) throw std::invalid_argument("cx must be finite");
  if (!std::isfinite(k.cy)) throw std::invalid_argument("cy must be finite");
  if (k.width < 0) throw std::invalid_argument("width must be >= 0");
  if (k.height < 0) throw std::invalid_argument("height must be >= 0");
}

// Slack for directions exactly on the edge of the field of view after a round trip.
constexpr double kEdgeTol = 1e-12;

}  // namespace

Mapping parse_mapping(std::string_view name) {
  for (const auto& i : kMappings)
    if (i.name == name) return i.mapping;
  std::string legal;
  for (const auto& i : kMappings) legal += (legal.empty() ? "" : ", ") + std::string(i.name);
  throw std::invalid_argument("unknown lens mapping \"" + std::string(name) + "\" (expected one of " +
                              legal + ")");
}

std::string_view mapping_name(Mapping m) { return info(m).name; }

RadialLens::RadialLens(Mapping mapping, Intrinsics intrinsics, double max_field_angle)
    : mapping_(mapping), k_(intrinsics), theta_max_(max_field_angle) {
  check_intrinsics(k_);
  const MappingInfo& i = info(mapping_);
  const bool ok = std::isfinite(theta_max_) && theta_max_ > 0 &&
                  (i.limit_inclusive ? theta_max_ <= i.theta_limit : theta_max_ < i.theta_limit);
  if (!ok)
    throw std::invalid_argument(
        "field of view out of range for the " + std::string(i.name) + " mapping: half-angle " +
        std::to_string(theta_max_ * 180 / kPi) + "° (must be > 0 and " +
        (i.limit_inclusive ? "<= " : "< ") + std::to_string(i.theta_limit * 180 / kPi) + "°)");
}

std::string RadialLens::name() const { return std::string(mapping_name(mapping_)); }

double RadialLens::radius(double theta) const {
  switch (mapping_) {
    case Mapping::perspective: return std::tan(theta);
    case Mapping::stereographic: return 2 * std::tan(theta / 2);
    case Mapping::equidistant: return theta;
    case Mapping::equisolid: return 2 * std::sin(theta / 2);
    case Mapping::orthographic: return std::sin(theta);
  }
  return theta;
}

double RadialLens::angle(double radius) const {
  const double r = std::max(radius, 0.0);
  switch (mapping_) {
    case Mapping::perspective: return std::atan(r);
    case Mapping::stereographic: return 2 * std::atan(r / 2);
    case Mapping::equidistant: return r;
    case Mapping::equisolid: return 2 * std::asin(std::min(r / 2, 1.0));
    case Mapping::orthographic: return std::asin(std::min(r, 1.0));
  }
  return r;
}

std::optional<Eigen::Vector2d> RadialLens::project(const Eigen::Vector3d& dir_cam) const {
  if (!dir_cam.allFinite()) return std::nullopt;
  const double rho = std::hypot(dir_cam.x(), dir_cam.y());
  if (rho == 0 && dir_cam.z() <= 0) return std::nullopt;  // zero vector or straight back
  const double theta = std::atan2(rho, dir_cam.z());
  if (theta > theta_max_ + kEdgeTol) return std::nullopt;
  const double r = radius(std::min(theta, theta_max_));
  // cos φ, sin φ = x/ρ, y/ρ; on the axis r = 0 and φ does not matter.
  const double c = rho > 0 ? dir_cam.x() / rho : 1.0;
  const double s = rho > 0 ? dir_cam.y() / rho : 0.0;
  return Eigen::Vector2d(k_.cx + k_.fx * r * c, k_.cy + k_.fy * r * s);
}

std::optional<Eigen::Vector3d> RadialLens::ray(const Eigen::Vector2d& pixel) const {
  if (!pixel.allFinite()) return std::nullopt;
  const double mx = (pixel.x() - k_.cx) / k_.fx;
  const double my = (pixel.y() - k_.cy) / k_.fy;
  const double r = std::hypot(mx, my);
  const double r_max = radius(theta_max_);
  if (r > r_max * (1 + kEdgeTol)) return std::nullopt;
  if (r == 0) return Eigen::Vector3d(0, 0, 1);
  const double theta = std::min(angle(r), theta_max_);
  const double st = std::sin(theta);
  return Eigen::Vector3d(st * mx / r, st * my / r, std::cos(theta));
}

}  // namespace skypol::camera
