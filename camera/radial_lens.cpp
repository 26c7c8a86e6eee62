// The five ideal radial mappings (Sun et al. 2019 eq. 7) with their closed-form inverses.
#include "camera/radial_lens.h"
#include "camera/detail/lens_checks.h"
#include "camera/lens_registry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "camera/detail/radial_util.h"
#include "sky/units.h"

namespace skypol::camera {
namespace {

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
  detail::check_intrinsics(k_);
  const MappingInfo& i = info(mapping_);
  const bool ok = std::isfinite(theta_max_) && theta_max_ > 0 &&
                  (i.limit_inclusive ? theta_max_ <= i.theta_limit : theta_max_ < i.theta_limit);
  if (!ok)
    throw std::invalid_argument(
        "field of view out of range for the " + std::string(i.name) + " mapping: half-angle " +
        std::to_string(deg_from_rad(theta_max_)) + "° (must be > 0 and " +
        (i.limit_inclusive ? "<= " : "< ") + std::to_string(deg_from_rad(i.theta_limit)) + "°)");
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
  return detail::project_radial(k_, theta_max_, dir_cam, [this](double t) { return radius(t); });
}

std::optional<Eigen::Vector3d> RadialLens::ray(const Eigen::Vector2d& pixel) const {
  const auto m = detail::normalized_within(k_, pixel, radius(theta_max_));
  if (!m) return std::nullopt;
  return detail::direction(std::min(angle(m->r), theta_max_), m->mx, m->my, m->r);
}

void RadialLens::ray_row(double y, double x0, std::size_t n, double* dx, double* dy, double* dz,
                         unsigned char* valid) const {
  // One loop per mapping, its closed-form inverse inlined (angle() per mapping, r ≥ 0 here).
  const double r_max = radius(theta_max_), tm = theta_max_;
  auto row = [&](auto theta_of) {
    detail::radial_ray_row(k_, r_max, [&](double r) { return std::min(theta_of(r), tm); }, y, x0, n, dx, dy, dz, valid);
  };
  switch (mapping_) {
    case Mapping::perspective: return row([](double r) { return std::atan(r); });
    case Mapping::stereographic: return row([](double r) { return 2 * std::atan(r / 2); });
    case Mapping::equidistant: return row([](double r) { return r; });
    case Mapping::equisolid: return row([](double r) { return 2 * std::asin(std::min(r / 2, 1.0)); });
    case Mapping::orthographic: return row([](double r) { return std::asin(std::min(r, 1.0)); });
  }
  Lens::ray_row(y, x0, n, dx, dy, dz, valid);
}

std::shared_ptr<const Lens> RadialLens::rescaled(double s) const {
  return std::make_shared<RadialLens>(mapping_, detail::rescale_intrinsics(k_, s), theta_max_);
}

// The five ideal mappings' entries (lens_registry.h): fx (or focal_mm with pitch_um), the principal
// point and fov_deg; the fisheye ones image a hemisphere unless told otherwise.
namespace {

LensModel radial_lens_model(const char* name, const char* description, bool hemisphere) {
  LensModel m;
  m.name = name;
  m.description = description;
  m.radial = true;
  m.hemisphere_default = hemisphere;
  m.make = [](const LensSpec& s) -> std::shared_ptr<const Lens> {
    return std::make_shared<RadialLens>(parse_mapping(s.model), detail::pinhole_intrinsics(s), detail::half_fov(s, true));
  };
  return m;
}

}  // namespace

LensModel perspective_lens_model() { return radial_lens_model("perspective", "r = f tan θ (the pinhole)", false); }
LensModel stereographic_lens_model() {
  return radial_lens_model("stereographic", "r = 2f tan(θ/2)", true);
}
LensModel equidistant_lens_model() { return radial_lens_model("equidistant", "r = f θ (the common fisheye)", true); }
LensModel equisolid_lens_model() { return radial_lens_model("equisolid", "r = 2f sin(θ/2) (equal area)", true); }
LensModel orthographic_lens_model() { return radial_lens_model("orthographic", "r = f sin θ", true); }

}  // namespace skypol::camera
