// The estimator tests' shared fixtures (see fixtures.h).
#include "fixtures.h"

#include <algorithm>
#include <cmath>
#include <iostream>

#include <catch2/catch.hpp>
#include <Eigen/Geometry>

#include "sky/units.h"
#include "skypole/evaluate.h"
#include "skypole/uncertainty.h"

namespace skypol::testing {

SyntheticSpec paper_spec(double heading_deg) {
  SyntheticSpec spec;
  spec.times = paper_times();
  spec.heading_deg = heading_deg;
  return spec;
}

SyntheticSpec sydney_spec(double heading_deg) {
  SyntheticSpec spec;
  spec.latitude_deg = -33.87;
  spec.longitude_deg = 151.21;
  spec.times = times_every("2022-09-22T22:00:00Z", "2022-09-23T06:00:00Z", 30);
  spec.heading_deg = heading_deg;
  return spec;
}

skypole::Score require_scored(const std::string& label, const skypole::PoleEstimate& e,
                              const stack::Stack& stack, const std::string& extra) {
  INFO(label << ": " << e.why_invalid);
  REQUIRE(e.valid);
  const skypole::Score s = skypole::score(e, stack.frames.front().truth);
  std::cout << label << ": bearing err " << (s.bearing_error_deg ? *s.bearing_error_deg : std::nan(""))
            << "°, latitude err " << s.latitude_error_deg << "°, angular err " << s.angular_error_deg
            << "°, residual " << e.residual_deg << "°" << extra << ", " << e.seconds << " s\n";
  return s;
}

std::vector<std::uint8_t> keep_all_but(std::size_t frames, std::size_t every, std::size_t at) {
  std::vector<std::uint8_t> keep(frames, 1);
  for (std::size_t i = 0; i < frames; ++i) keep[i] = i % every != at;
  return keep;
}

void check_refit_is_rerun(const skypole::PoleEstimate& cached, const skypole::PoleEstimate& fresh,
                          double max_angle_rad, double residual_margin_deg) {
  INFO(cached.why_invalid << " / " << fresh.why_invalid);
  REQUIRE(cached.valid);
  REQUIRE(fresh.valid);
  CHECK(cached.is_north == fresh.is_north);
  CHECK(std::acos(std::min(1.0, cached.pole_camera.dot(fresh.pole_camera))) < max_angle_rad);
  CHECK(cached.residual_deg == Approx(fresh.residual_deg).margin(residual_margin_deg));
}

skypole::InputOptions uncalibrated_unmasked() {
  skypole::InputOptions in;
  in.calibrated = false;
  in.sky_mask = false;
  return in;
}

VeilPaint rayleigh_of_moved_sun(const stack::Stack& clear) {
  return [&clear](std::size_t f, const Eigen::Vector3d& ray, float& dolp, float&) {
    const scene::Truth& t = clear.frames[f].truth;
    const double az = t.sun.azimuth, el = t.sun.elevation;
    const Eigen::Vector3d sun(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
    const Eigen::Vector3d moved = Eigen::AngleAxisd(10 * kRadPerDeg, Eigen::Vector3d::UnitX()) * sun;
    const double c = (t.world_from_camera.transpose() * moved).dot(ray);
    dolp = static_cast<float>(0.7 * (1 - c * c) / (1 + c * c));
  };
}

JackknifeReading jackknife_reading(const skypole::PoleEstimate& e, const stack::Stack& stack) {
  return {skypole::score(e, stack.frames.front().truth).angular_error_deg,
          skypole::sigma_deg_of(e.jackknife_frames_rad2), skypole::sigma_deg_of(e.jackknife_sectors_rad2)};
}

ClearAndVeiled read_clear_and_veiled(const std::string& method, const stack::Stack& clear,
                                     const stack::Stack& veiled, const skypole::InputOptions& input) {
  ClearAndVeiled r{skypole::run_method(clear, method, input), skypole::run_method(veiled, method, input), {}, {}};
  INFO(r.clear.why_invalid << " / " << r.veiled.why_invalid);
  REQUIRE(r.clear.valid);
  REQUIRE(r.veiled.valid);
  r.c = jackknife_reading(r.clear, clear);
  r.v = jackknife_reading(r.veiled, veiled);
  std::cout << method << " sector jackknife: clear error " << r.c.error_deg << "°, σ frames " << r.c.frames_deg
            << "°, σ sectors " << r.c.sectors_deg << "°; veiled error " << r.v.error_deg << "°, σ frames "
            << r.v.frames_deg << "°, σ sectors " << r.v.sectors_deg << "°\n";
  return r;
}

void check_clear_day_small(const ClearAndVeiled& r) {
  CHECK(r.c.error_deg < 0.05);
  CHECK(r.c.frames_deg < 0.05);
  CHECK(r.c.sectors_deg < 0.05);
}

void check_sectors_hold_the_veil(const ClearAndVeiled& r) {
  CHECK(r.v.sectors_deg > r.v.error_deg / 2);
  CHECK(r.veiled.sigma_deg >= r.v.sectors_deg * (1 - 1e-9));
  CHECK(r.v.error_deg < 5 * r.veiled.sigma_deg);
  CHECK(r.v.error_deg > 5 * std::hypot(r.v.frames_deg, 0.05));
}

skypole::PoleEstimate pole_at(double azimuth_deg, double altitude_deg) {
  skypole::PoleEstimate e;
  e.valid = true;
  e.is_north = true;
  e.altitude_deg = altitude_deg;
  e.azimuth_rel_deg = azimuth_deg;
  const double a = azimuth_deg * kRadPerDeg, h = altitude_deg * kRadPerDeg;
  e.pole_level = Eigen::Vector3d(std::cos(h) * std::sin(a), std::cos(h) * std::cos(a), std::sin(h));
  e.pole_camera = e.pole_level;
  return e;
}

}  // namespace skypol::testing
